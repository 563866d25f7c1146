"""Smoke run of studies/fidelity.py (the fidelity ladder) on tiny settings."""
import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

_path = Path(__file__).parents[1] / "studies" / "fidelity.py"
_spec = importlib.util.spec_from_file_location("fidelity", _path)
fid = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fid)


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("fid")
    return fid.main(size=1.5e-2, steps=2, out=out), out


def test_levels_and_differences(result):
    res, _ = result
    lv = {r["name"]: r for r in res["levels"]}
    assert list(lv) == ["rigid rotor", "elastic rotor", "piston body", "thermal"]
    for r in res["levels"]:
        assert r["run_s"] > 0
        assert all(np.isfinite(v) for v in r["difference_vs_top"].values())
    assert all(v == 0.0 for v in lv["thermal"]["difference_vs_top"].values())
    assert lv["rigid rotor"]["difference_vs_previous"] is None
    # what each level adds is in the model
    assert lv["rigid rotor"]["dofs"] < lv["elastic rotor"]["dofs"] < lv["piston body"]["dofs"]
    assert lv["thermal"]["pad_temperature_max_K"] > 300.0
    assert lv["elastic rotor"]["cost_ratio_vs_elastic"] == 1.0


def test_files_written(result):
    res, out = result
    data = json.loads((out / "data" / "fidelity.json").read_text())
    assert [r["name"] for r in data["levels"]] == [n for n, _ in fid.LEVELS]
    prof = data["profiles"]["thermal"]
    assert len(prof["row_r_m"]) == len(prof["pad_wear_m"]) >= 2
    assert (out / "figures" / "fidelity.png").stat().st_size > 10_000
    assert "| thermal |" in fid.table(res)
