"""Routines of the caliper robustness study (studies/caliper_robustness.py, seed 37,
8 mm, heat on) whose outboard pad rocks on the edge of its fingers' footprint:
the rows' active-set iteration cycles or does not settle there, and the
torque iteration meets a jump of the effective radius.  Each routine runs to
the first stop past the one where its solves failed without the complementarity
fallback (92: stop 2; 94 and 98: stop 12), with the fallback used and a
line pressure for every stop.  Routine 92 (seconds) runs by default, the
others (15-25 s each) with the slow tests.  Routine 740 is a known failure
(strict xfail): in one of its stops a bore row and a finger row tip against
each other, and the best states the methods meet leave 9-53 nm of
penetration, far beyond the active-set tolerance (1e-10 of the model's size,
0.04 nm): ComplementarityError."""
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "studies"))

#: routine -> stops run (the failing stop and none after)
CASES = {92: 2, 94: 12, 98: 12, 740: 20}


@pytest.fixture(scope="module")
def routines():
    import caliper_robustness as cb
    return cb.tasks(1000, 0.25, 37, size=8.0)


@pytest.mark.parametrize("index", [92] + [pytest.param(i, marks=pytest.mark.slow)
                                         for i in CASES if i not in (92, 740)] + [
    pytest.param(740, marks=[pytest.mark.slow, pytest.mark.xfail(
        strict=True, raises=AssertionError,
        reason="a bore row and a finger row tip against each other: no state meets the "
               "active-set tolerances (penetration 9-53 nm against 0.04 nm); "
               "ComplementarityError")])])
def test_the_routine_runs_through_its_rocking_stop(routines, index, monkeypatch):
    import cleaning_routine as cr

    from brakewear.caliper.joint import JointSets

    used = []
    damped = JointSets._damped

    def counted(self, *args, **kwargs):
        used.append(1)
        return damped(self, *args, **kwargs)
    monkeypatch.setattr(JointSets, "_damped", counted)
    task = {k: v for k, v in routines[index].items() if k != "tail"}
    task["stops"] = CASES[index]
    r = cr.run_sample(task)
    assert "error" not in r, r.get("error")
    assert used                                   # the state the active sets did not settle
    assert len(r["rows"]) == CASES[index]
    assert all(row["line_pressure_MPa"] > 0 for row in r["rows"])
