"""Step convergence of the wear loop on a coarse mesh: both schemes are first order."""
import importlib.util
import json
from pathlib import Path

import pytest

spec = importlib.util.spec_from_file_location(
    "wear_steps", Path(__file__).parents[1] / "studies" / "wear_steps.py")
study = importlib.util.module_from_spec(spec)
spec.loader.exec_module(study)


@pytest.mark.slow
def test_fixed_steps_converge_at_first_order(tmp_path):
    res = study.main(size_mm=10.0, out=tmp_path, quick=True, figures=False)
    # the short horizon keeps the coarsest explicit step below the stability limit
    assert res["explicit"]["rows"][0]["dt_s"] < 2.0 * res["settings"]["explicit_monotone_bound_s"]
    for key in ("explicit", "implicit", "implicit_long"):
        s = res[key]
        assert s["rate"] >= 0.8, f"{key}: observed rate {s['rate']:.3f}"
        finest = s["rows"][-1]["error"]
        assert finest < 0.01, f"{key}: finest error {finest:.3e}"
        # the reference's own error is far below the finest run's
        assert s["reference_error_estimate"] < 0.2 * finest
    data = json.loads((tmp_path / "data" / "wear_steps.json").read_text())
    assert len(data["control"]) == 6
    assert all(r["contact_solves"] > r["steps"] for r in data["control"])
