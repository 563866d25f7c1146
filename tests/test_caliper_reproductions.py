"""Draws whose outboard pad rocks on the edge of its fingers' footprint, run as
new-pad routines on the floating caliper (8 mm, heat on, the fingers' radius
and footprint at their medians): the caliper's nested active sets cycled or did
not settle on them, and the torque iteration met a jump of the effective radius.
Each runs through its stops with a line pressure for every stop.  The draws are
pinned in tests/data/caliper_rocking_draws.json (inputs in SI units, as
:func:`brakewear.cleaning.priors.draw` gives them).

In routine 740, at its 19th stop, the pad's pressure jumps as it rocks onto its
other edge: the change (0.19) does not shrink as the wear step is halved down
to 2 ms, and the step control takes the jump in its shortest step
(:meth:`brakewear.wear.control.StepControl.spans_jump`) instead of raising
StepSizeError."""
import json
import logging
from pathlib import Path

import pytest

DRAWS = json.loads((Path(__file__).parent / "data" / "caliper_rocking_draws.json").read_text())

#: routine -> stops run
CASES = {"92": 2, "94": 12, "98": 12, "828": 20, "740": 20}


def _run(index: str) -> dict:
    from brakewear.cleaning.car import packaged_car
    from brakewear.cleaning.priors import cleaning_inputs, medians
    from brakewear.cleaning.sample import RoutineSettings
    from brakewear.cleaning.sweep import routine_task, run_task

    case = DRAWS[index]
    draw = dict(medians(cleaning_inputs("new")), **case["draw"])
    task = routine_task(draw, case["speed_kmh"], case["decel"], case["interval"],
                        CASES[index], RoutineSettings(size=8e-3, start="new", run_to_end=True),
                        packaged_car("study"))
    return run_task(task)


@pytest.mark.parametrize("index", ["92"] + [pytest.param(i, marks=pytest.mark.slow)
                                           for i in ("94", "98", "828", "740")])
def test_the_routine_runs_through_its_rocking_stops(index, caplog):
    with caplog.at_level(logging.WARNING, logger="brakewear.wear.stepper"):
        r = _run(index)
    if index == "740":
        assert any("a jump of the contact state" in m for m in caplog.messages)
    assert "error" not in r, r.get("error")
    assert len(r["rows"]) == CASES[index]
    assert all(row["line_pressure_MPa"] > 0 for row in r["rows"])
