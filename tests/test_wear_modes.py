"""Geometry update against gap offset on a coarse mesh: they agree early, and the
pad wears to half its friction layer with no inverted element."""
import importlib.util
from pathlib import Path

import pytest

spec = importlib.util.spec_from_file_location(
    "wear_modes", Path(__file__).parents[1] / "studies" / "wear_modes.py")
study = importlib.util.module_from_spec(spec)
spec.loader.exec_module(study)


@pytest.mark.slow
def test_modes_agree_early_and_geometry_reaches_half_the_layer(tmp_path):
    res = study.main(size_mm=12.0, out=tmp_path, fractions=(0.01, 0.5), figures=False)
    early, half = res["rows"]
    tf = res["settings"]["friction_thickness_m"]
    for row in (early, half):
        for mode in ("gap", "geometry"):
            depth = row[f"mean_depth_{mode}_m"]
            assert depth == pytest.approx(row["fraction"] * tf, rel=0.01), (mode, depth)
        # both carry the clamp force
        assert row["force_geometry_N"] == pytest.approx(row["force_gap_N"], rel=1e-6)
    # at 1 % of the layer the worn depth is far below the elements: the modes agree
    assert early["pressure_diff"] < 0.02, early["pressure_diff"]
    assert early["wear_diff"] < 0.01, early["wear_diff"]
    # half the friction layer worn away: no inverted or degenerate pad element
    assert half["pad_inverted_geometry"] == 0
    assert half["pad_min_quality_geometry"] > 0.2, half["pad_min_quality_geometry"]
    assert half["pressure_diff"] < 0.1, half["pressure_diff"]
    assert (tmp_path / "data" / "wear_modes.json").exists()
