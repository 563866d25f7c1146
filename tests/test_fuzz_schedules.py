"""Random but valid schedules thrown at run_schedule on a coarse brake (hypothesis,
derandomised: the same examples on every run).  Each one finishes, within the loop
budgets (few fixed steps, or automatic steps under a small ``max_steps``), with its
energy closed (the friction work is the demand times r_eff_mean / r_eff, and
positive), or raises a named brakewear error.  A hang is caught by an alarm far
above any example's run time: the test then fails naming the schedule."""
import math
import signal
from contextlib import contextmanager

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from brakewear import Numerics, WearLaw  # noqa: E402
from brakewear.duty import Drag, Dwell, Stop, Vehicle, run_schedule  # noqa: E402
from brakewear.errors import BrakewearError  # noqa: E402
from brakewear.interfaces import FEInterface  # noqa: E402
from brakewear.model import BrakeModel  # noqa: E402
from brakewear.wear import Run  # noqa: E402

#: examples per run (the issue's floor is 200)
EXAMPLES = 220
#: seconds after which an example counts as hung (a run takes well under one)
HANG_S = 120

CAR = Vehicle(mass=1800.0, front_share=0.7, tyre_radius=0.32, brakes_per_axle=2)
_BRAKES: dict = {}


def _brake(rotor: str):
    """One coarse model and its interface per rotor kind, shared by the examples."""
    if rotor not in _BRAKES:
        m = BrakeModel("default", size=12e-3 if rotor == "elastic" else 10e-3, rotor=rotor)
        _BRAKES[rotor] = (m, FEInterface(m, 1e6, 0.4, 1e-9))
    return _BRAKES[rotor]


@contextmanager
def _alarm(seconds: int, what):
    def hung(*_):
        raise AssertionError(f"no result after {seconds} s: {what}")
    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


kmh = st.floats(5.0, 130.0).map(lambda v: v / 3.6)
pressure = st.floats(0.2e6, 6e6)


@st.composite
def stops(draw):
    v0 = draw(kmh)
    v1 = draw(st.one_of(st.just(0.0), st.floats(0.0, 0.9).map(lambda f: f * v0)))
    if draw(st.booleans()):
        return Stop(v0, v1, decel=draw(st.floats(0.3, 7.0)))
    return Stop(v0, v1, line_pressure=draw(pressure))


drags = st.builds(Drag, pressure, st.floats(0.5, 60.0), speed=kmh)
dwells = st.builds(Dwell, st.floats(0.5, 200.0),
                   speed=st.one_of(st.none(), st.floats(0.0, 30.0)))
applications = st.lists(st.one_of(stops(), stops(), drags, dwells), min_size=1, max_size=4)


@pytest.mark.slow
@settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(schedule=applications, rotor=st.sampled_from(["rigid", "rigid", "elastic"]),
       scheme=st.sampled_from(["implicit", "explicit"]),
       steps=st.one_of(st.none(), st.integers(1, 6)),
       mu=st.floats(0.25, 0.55), k_pad=st.floats(-15.0, -12.5))
def test_random_schedules_finish_with_energy_closure_or_a_named_error(schedule, rotor, scheme,
                                                                      steps, mu, k_pad):
    model, itf = _brake(rotor)
    num = Numerics(scheme=scheme, steps=steps, max_steps=30)
    what = f"{schedule}, rotor {rotor}, {num}, mu {mu}, k_pad 1e{k_pad:.2f}"
    laws = (WearLaw(10.0 ** k_pad), WearLaw(10.0 ** (k_pad - 1.0)))
    records = []
    try:
        with _alarm(HANG_S, what):
            for rec in run_schedule(
                Run(
                    model,
                    pad_law=laws[0],
                    rotor_law=laws[1],
                    mu=mu,
                    schedule=schedule,
                    vehicle=CAR,
                    numerics=num,
                    interface=itf,
                )
            ):
                records.append(rec)
    except BrakewearError as exc:       # a named error, with its message
        assert type(exc).__name__.endswith("Error") and str(exc), what
        event(f"raised {type(exc).__name__}")
        return
    event("finished")
    assert len(records) == len(schedule), what
    for rec in records:
        if rec.kind == "dwell":
            continue
        assert rec.steps >= 1 and (steps is None or rec.steps == steps), what
        assert math.isfinite(rec.friction_face_J) and rec.friction_face_J > 0, what
        assert rec.target_face_J > 0, what
        # closure: the friction work is the demand times the angle-mean move of r_eff
        assert 1.0 + rec.torque_drift == pytest.approx(rec.r_eff_mean / rec.r_eff,
                                                       rel=1e-6), what
        assert abs(rec.torque_drift) < DRIFT_BOUND, (rec.torque_drift, what)
        assert np.all(np.isfinite(rec.pad_wear)) and rec.pad_wear.min() >= 0, what


#: the largest |torque_drift| of an isothermal application (docs/duty.md: the
#: pressure field moves with the wear only)
DRIFT_BOUND = 0.05
