"""The pad-support study on a coarse mesh: friction moves the centre of pressure toward
the leading end by the statics of the bracket's lever, and the bearing end takes the drag."""
import json

import pytest

from studyload import load_study

study = load_study("pad_support")


@pytest.fixture(scope="module")
def res(tmp_path_factory):
    out = tmp_path_factory.mktemp("support")
    return study.main(size=10.0, out=out), out


def test_the_centre_of_pressure_moves_by_the_brackets_lever(res):
    # statics about the pad's radial centre line: the drag mu N on the friction face and
    # the bracket's in-plane force at height `lever` make a couple that the pressure
    # balances, so the centre moves by -lever mu <cos> (toward the leading end)
    r, _ = res
    for kind, by_mu in r["runs"].items():
        v = by_mu["mu=0.4"]
        assert v["shift_mm"] < 0, kind
        assert v["shift_mm"] == pytest.approx(v["statics_shift_mm"], rel=0.05), (kind, v)


def test_the_bearing_end_takes_the_drag_and_sets_the_lever(res):
    r, _ = res
    s = r["settings"]
    tf, tb = s["lining_thickness_mm"], s["backplate_thickness_mm"]
    push, pull, bil = (r["runs"][k]["mu=0.4"] for k in ("push", "pull", "bilateral"))
    # the bearing end carries the drag (its share of mu F: the drag's mean cosine to the
    # centre line, less the anti-rattle spring's part); the other end nothing
    assert push["trailing_share"] > 0.95 and abs(push["leading_share"]) < 1e-3
    assert pull["leading_share"] > 0.95 and abs(pull["trailing_share"]) < 1e-3
    assert 0.3 < bil["leading_share"] < 0.7
    # push: the pad tilts toward its leading end and its trailing end face rocks on the
    # stop's lower edge (the backplate's bottom); pull: the hook holds the leading end
    # higher up; the bilateral support holds the whole face
    assert tf <= push["lever_mm"] < tf + 0.25 * tb
    assert push["lever_mm"] < bil["lever_mm"] < pull["lever_mm"] < tf + tb
    assert pull["shift_mm"] < bil["shift_mm"] < push["shift_mm"] < 0
    # both pads balance their clamp force
    for kind in ("bilateral", "push", "pull"):
        v = r["runs"][kind]["mu=0"]
        assert v["normal_force_N"] == pytest.approx(v["clamp_force_N"], rel=1e-8)


def test_the_study_writes_its_numbers_and_figure(res):
    r, out = res
    saved = json.loads((out / "pad_support.json").read_text())
    assert saved["runs"]["push"]["mu=0.4"]["cop_mm"] == pytest.approx(
        r["runs"]["push"]["mu=0.4"]["cop_mm"])
    assert (out / "pad_support.png").stat().st_size > 10_000
