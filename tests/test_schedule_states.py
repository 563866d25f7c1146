"""Schedule states (brakewear.duty.states): what a schedule carries besides the wear,
asked by the one schedule runner before and after each application and told of each
wear step; the rust layer and the pads' touch as registered states."""
from typing import ClassVar

import numpy as np
import pytest

from brakewear import DutyError, Numerics, WearLaw
from brakewear.duty import (
    Dwell,
    Stop,
    Vehicle,
    brake_torque,
    check_states,
    register_state,
    run_schedule,
    state_kinds,
)
from brakewear.model import BrakeModel
from brakewear.wear import Run

K_PAD, K_ROT = 5e-13, 5e-14
CAR = Vehicle(mass=1800.0, front_share=0.7, tyre_radius=0.32, brakes_per_axle=2)


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=12e-3, rotor="rigid")


@register_state
class Doubler:
    """A test state: the second braked application runs with twice the friction and a
    uniform extra gap; it counts the steps and the pauses it is told of."""

    name: ClassVar[str] = "doubler"

    def __init__(self, gap: float = 0.0):
        self.gap, self.braked, self.steps, self.pauses, self.seen = gap, 0, 0, 0, []

    def before(self, app, context):
        self.seen.append(np.asarray(context["offset"]).copy())
        if not app.braked:
            return None
        self.braked += 1
        if self.braked == 2:
            return {"mu_factor": 2.0, "gap": np.full(context["offset"].size, self.gap)}
        return None

    def step(self, pad_wear, rotor_wear):
        self.steps += 1
        self.last_wear = pad_wear.copy()

    def after(self, record):
        if not record.braked:
            self.pauses += 1
        return {"braked": record.braked, "n": self.braked}


def _run(model, states, **kw):
    sched = [Stop(50 / 3.6, decel=1.5), Dwell(30.0), Stop(50 / 3.6, decel=1.5), Dwell(30.0),
             Stop(30 / 3.6, decel=1.0)]
    return list(run_schedule(Run(model, pad_law=WearLaw(K_PAD), rotor_law=WearLaw(K_ROT),
                                 mu=0.4, schedule=sched, vehicle=CAR,
                                 numerics=Numerics(scheme="implicit", steps=2, tol=1e-12),
                                 states=states, **kw)))


def test_a_state_sets_the_friction_of_an_application_and_is_told_of_each_step(model):
    d = Doubler()
    recs = _run(model, (d,))
    plain = _run(model, ())
    stops = [r for r in recs if r.braked]
    assert [r.mu for r in stops] == [pytest.approx(0.4), pytest.approx(0.8), pytest.approx(0.4)]
    # the torque is the vehicle's: twice the friction needs about half the line pressure
    # (the field, and its radius, move a little with the load), and the torque equation
    # holds with the friction it ran with
    ref = [r for r in plain if r.braked]
    assert stops[1].line_pressure == pytest.approx(0.5 * ref[1].line_pressure, rel=0.02)
    assert stops[0].line_pressure == pytest.approx(ref[0].line_pressure, rel=1e-12)
    area = model.geometry.clamp_area
    for r in stops[:2]:
        assert brake_torque(r.line_pressure, r.mu, area, r.r_eff) == pytest.approx(
            CAR.stop_torque(50 / 3.6, 0.0, 1.5), rel=1e-8)
    assert d.steps == sum(r.steps for r in stops) and d.pauses == 2
    assert recs[1].states["doubler"] == {"braked": False, "n": 1}
    # the wear it is told of is the schedule's, cumulative
    assert np.allclose(d.last_wear, recs[-1].pad_wear, rtol=1e-12, atol=0)


def test_a_states_gap_holds_for_its_application_only(model):
    d = Doubler(gap=3e-6)
    _run(model, (d,))
    plain = Doubler()
    _run(model, (plain,))
    # what a state sees before an application is the offset without any state's gap: the
    # second stop's extra 3 um is not carried into the pause after it or the stop after
    # that (only the wear differs, by far less than the gap)
    assert len(d.seen) == 5
    for a, b in zip(d.seen[3:], plain.seen[3:]):
        assert np.abs(a - b).max() < 0.05 * 3e-6


def test_a_state_that_is_not_registered_is_refused_before_anything_runs(model):
    class Stranger:
        name = "stranger"

        def before(self, app, context):
            return None

        def step(self, pad_wear, rotor_wear):
            pass

        def after(self, record):
            return None

    with pytest.raises(DutyError, match=r"states\[0\] = Stranger is not a registered schedule "
                                        r"state; registered kinds: .*doubler"):
        run_schedule(Run(model, pad_law=WearLaw(K_PAD), mu=0.4,
                         schedule=[Stop(50 / 3.6, decel=1.5)], vehicle=CAR,
                         states=(Stranger(),)))
    with pytest.raises(DutyError, match="a second state of kind 'doubler'"):
        check_states((Doubler(), Doubler()))
    with pytest.raises(DutyError, match="Half is not a schedule state: it has no before"):
        register_state(type("Half", (), {"name": "half", "step": None, "after": None}))


def test_a_bad_change_names_the_state(model):
    @register_state
    class Bad(Doubler):
        name: ClassVar[str] = "bad"

        def before(self, app, context):
            return {"mu_factor": -1.0}

    with pytest.raises(DutyError, match="state 'bad': mu_factor = -1.0; need a finite value > 0"):
        _run(model, (Bad(),))


def test_the_cleaning_states_are_registered():
    assert {"rust", "rotor_heat", "touch"} <= set(state_kinds())
