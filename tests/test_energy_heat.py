"""Energy bookkeeping of a schedule with heat on: one friction work (the heat put into
the bodies), and the vehicle's demand met to the torque drift, which is exactly the
angle-mean move of the effective radius within the application (docs/duty.md)."""
import numpy as np
import pytest

from brakewear import Numerics, WearLaw
from brakewear.duty import Drag, Dwell, Stop, Vehicle, run_schedule
from brakewear.duty.vehicle import effective_radius
from brakewear.model import BrakeModel
from brakewear.thermal.model import ThermalModel
from brakewear.wear import Run

CAR = Vehicle(mass=1800.0, front_share=0.7, tyre_radius=0.32, brakes_per_axle=2)
SCHEDULE = [Stop(100 / 3.6, 0.0, decel=3.0), Dwell(20.0), Drag(2e6, 20.0, speed=50 / 3.6),
            Stop(80 / 3.6, 10 / 3.6, line_pressure=3e6), Stop(60 / 3.6, decel=1.5)]


@pytest.mark.parametrize("scheme", ["implicit", "explicit"])
def test_heat_equals_friction_work_and_the_demand_is_met_to_the_r_eff_drift(scheme):
    m = BrakeModel("default", size=12e-3, rotor="elastic")
    thermal = ThermalModel(m)
    steps = {}

    def on_step(rec, s, *_):
        steps.setdefault(rec.index, []).append(s.pressure)

    recs = [
        r
        for r in run_schedule(
            Run(
                m,
                pad_law=WearLaw(5e-14),
                rotor_law=WearLaw(5e-15),
                mu=0.4,
                schedule=SCHEDULE,
                vehicle=CAR,
                numerics=Numerics(scheme=scheme, steps=4),
                thermal=thermal,
            ),
            on_step=on_step,
        )
        if r.kind != "dwell"
    ]
    itf_area, itf_r = (lambda i: (i.area, i.r))(_interface(m))
    hot = 0.0
    for rec in recs:
        heat = rec.heat["heat_pad_J"] + rec.heat["heat_rotor_J"]
        # one friction work: the heat put into pad and rotor over the application
        assert heat == pytest.approx(rec.friction_face_J, rel=1e-9), rec.index
        # the demand, met to the move of r_eff: friction work = torque(r_eff mean) x angle
        ratio = rec.r_eff_mean / rec.r_eff
        assert 1.0 + rec.torque_drift == pytest.approx(ratio, rel=1e-7), rec.index
        # ... which lies within the steps' own r_eff (the one the first step starts at
        # is the torque equation's, solved with the same thermal load)
        r_k = np.array([effective_radius(p, itf_area, itf_r) for p in steps[rec.index]])
        assert r_k[0] == pytest.approx(rec.r_eff, rel=1e-7)     # two solves to tol 1e-9
        assert r_k.min() * (1 - 1e-12) <= rec.r_eff_mean <= r_k.max() * (1 + 1e-12)
        # the bound docs/duty.md states for a thermal schedule
        assert abs(rec.torque_drift) < 0.02, (rec.index, rec.torque_drift)
        hot = max(hot, rec.heat["rotor_T_max_peak_C"])
    assert hot > 100.0          # the bodies did heat: the thermal load moved the pressure


def _interface(model):
    from brakewear.interfaces import FEInterface
    return FEInterface(model, 1e6, 0.4)
