"""The brake contact study on a coarse mesh: friction moves the pressure to the leading edge."""
import importlib.util
import json
from pathlib import Path

import pytest

spec = importlib.util.spec_from_file_location(
    "brake_contact", Path(__file__).parents[1] / "studies" / "brake_contact.py")
study = importlib.util.module_from_spec(spec)
spec.loader.exec_module(study)


@pytest.mark.parametrize("rotor", ["rigid", "elastic"])
def test_friction_shifts_centre_of_pressure_to_leading_edge(rotor, tmp_path):
    res = study.main(1.0, 0.4, size_mm=6.0, rotor=rotor, out=tmp_path, figures=(rotor == "rigid"))
    F = res["clamp_force_N"]
    for k in ("frictionless", "friction"):
        assert abs(res[f"{k}_normal_force_N"] - F) / F < 1e-8, res
    assert res["friction_friction_force_N"] == pytest.approx(0.4 * F, rel=1e-8)
    assert res["cop_shift_toward_leading_edge"], res["cop_shift_deg"]
    assert abs(res["cop_shift_deg"]) > 0.5, res["cop_shift_deg"]
    assert 0.2 < res["frictionless_contact_fraction"] <= 1.0
    assert json.loads((tmp_path / "brake_contact.json").read_text())["mu"] == 0.4
    if rotor == "rigid":
        assert (tmp_path / "brake_contact_friction.png").stat().st_size > 10_000
