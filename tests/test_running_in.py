"""The running-in study on a tiny mesh and a short drag: volumes conserved, the
pressure moves toward p r = const, the files are written."""
import importlib.util
import json
from pathlib import Path

import pytest

spec = importlib.util.spec_from_file_location(
    "running_in", Path(__file__).parents[1] / "studies" / "running_in.py")
study = importlib.util.module_from_spec(spec)
spec.loader.exec_module(study)


def test_running_in_tiny(tmp_path):
    res = study.main(size_mm=10.0, duration=300.0, out=tmp_path, stages=(0.0, 1.0),
                     figures=False, dp_tol=0.2)
    # Archard volumes of both surfaces to round-off; the pad loses about k_pad/k_rotor = 10 x
    # (not exactly: the pad wears with the end-of-step pressure, the rotor with the start's)
    assert abs(res["pad_volume_m3"] - res["pad_archard_m3"]) <= 1e-10 * res["pad_archard_m3"]
    assert abs(res["rotor_volume_m3"] - res["rotor_archard_m3"]) <= 1e-10 * res["rotor_archard_m3"]
    assert res["pad_volume_m3"] / res["rotor_volume_m3"] == pytest.approx(10.0, rel=0.01)
    first, last = res["stages"][0], res["stages"][-1]
    assert first["time_s"] == 0.0 and last["time_s"] == pytest.approx(300.0)
    # running in: the contact spreads and p r evens out
    assert last["contact_fraction"] >= first["contact_fraction"]
    assert last["pr_spread"] < 0.8 * first["pr_spread"], (first["pr_spread"], last["pr_spread"])
    # the clamp force is carried throughout
    F = res["settings"]["clamp_force_N"]
    assert F == pytest.approx(1e6 * 3.141592653589793 * 0.057 ** 2 / 4, rel=1e-6)
    data = json.loads((tmp_path / "data" / "running_in.json").read_text())
    assert data["steps"] == res["steps"] >= 2
    assert (tmp_path / "data" / "running_in.csv").read_text().count("\n") == res["steps"] + 1
