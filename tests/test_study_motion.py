"""The geometry-update study on a coarse mesh: partial and full reassembly
move the same elements, the pad's quality falls gradually with wear and no
element inverts before the friction layer is worn through."""
import json

import pytest

from studyload import load_study

study = load_study("motion_quality")


def test_motion_study_runs_and_its_numbers_hold(tmp_path):
    size = 10e-3
    res = study.main(sizes=(size,), repeats=1, out=tmp_path, quality_size=size,
                     fractions=(0.0, 0.5, 0.9))
    (row,) = res["cost"]
    # the taper moves every pad friction node: the band's elements move, the backplate's not
    assert 0 < row["pad_moved_elements"] < row["pad_elements"]
    assert 0 < row["rotor_moved_elements"] < row["rotor_elements"]
    for mode in ("partial", "full"):
        assert 0 < row[f"{mode}_reassembly_s"] <= row[f"{mode}_apply_s"]
    for taper in (False, True):
        q = [r["min_quality"] for r in res["quality"] if r["taper"] is taper]
        # unworn: the initial quality; then falling with wear, never inverted
        assert q[0] > 0.1
        assert q[0] >= q[1] >= q[2] > 0.0, (taper, q)
    uniform = {r["fraction"]: r["min_quality"] for r in res["quality"] if not r["taper"]}
    # uniform wear compresses the band evenly: quality scales with the band's height
    assert uniform[0.9] < 0.5 * uniform[0.0]
    assert (
        json.loads((tmp_path / "data" / "motion_cost.json").read_text())[0]["dofs"] == row["dofs"]
    )
    lines = (tmp_path / "data" / "motion_quality.csv").read_text().splitlines()
    assert len(lines) == 1 + 6
    assert (tmp_path / "figures" / "motion_pad_section.png").stat().st_size > 10_000
    tapered = {r["fraction"]: r["min_quality"] for r in res["quality"] if r["taper"]}
    # the figure draws the pad tapered to half the layer: the quality curve's point
    assert res["figure"]["min_quality"] == pytest.approx(tapered[0.5], rel=1e-12)
