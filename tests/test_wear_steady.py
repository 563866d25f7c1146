"""Uniform-wear steady state (docs/references.md, Wear): a stiff-backed pad runs in to p r = const.

A pad whose backplate is 1000 times stiffer than steel, on a rigid rotor,
starts flat (first contact, no wear) and wears under constant line pressure
and speed.  Archard wear with ``v = omega r`` is uniform once ``p r`` is the
same everywhere, so the pressure must approach ``p = F / (theta (ro - ri) r)``
and the torque ``mu F (ro + ri) / 2``.  Only ``k`` times the sliding distance
sets the worn shape, so a large ``k`` with a short duration is the same run
as a realistic ``k`` over hours of drag.
"""
from dataclasses import replace

import numpy as np
import pytest

from brakewear.analytic import uniform_wear_torque
from brakewear.geometry import load_geometry
from brakewear.interfaces import FEInterface
from brakewear.laws.base import WearLaw
from brakewear.model import BrakeModel
from brakewear.wear import Numerics, Run, wear_history

P_LINE, OMEGA, MU = 1e6, 55.0, 0.4
K_PAD = 5e-13          # 100 x a resin pad's k: the same worn shape in 1/100 of the time
DURATION = 6.0         # s: 38 m of sliding at the mean radius (explicit: under 2 % by ~4.3 s)


def stiff_backing_model(size: float = 8e-3) -> BrakeModel:
    """The default brake with a backplate 1000 x stiffer than steel, rigid rotor."""
    g = load_geometry("default")
    bp = g.pad.backplate_material
    stiff = replace(bp, elastic=replace(bp.elastic, E=1000.0 * bp.elastic.E))
    return BrakeModel(replace(g, pad=replace(g.pad, backplate_material=stiff)), size=size,
                      rotor="rigid")


_RUNS: dict = {}


def end_state(model, scheme):
    if scheme in _RUNS:
        return _RUNS[scheme]
    itf = FEInterface(model, P_LINE, MU)
    last = None
    for last in wear_history(  # noqa: B007  (the last step)
        Run(
            model,
            P_LINE,
            OMEGA,
            DURATION,
            WearLaw(K_PAD),
            None,
            MU,
            interface=itf,
            numerics=Numerics(scheme=scheme),
        )
    ):
        pass
    # the pressure at the end of the last step (records hold the start-of-step pressure)
    sol = itf.solve(last.pad_wear, last.active)
    p, act = sol.pressure, sol.active
    _RUNS[scheme] = itf, last, p, act
    return _RUNS[scheme]


@pytest.fixture(scope="module")
def model():
    return stiff_backing_model()


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_runs_in_to_uniform_wear(model, scheme):
    itf, last, p, act = end_state(model, scheme)
    g = model.geometry.pad
    A, r = itf.area, itf.r
    assert act.all(), f"{scheme}: contact fraction {A[act].sum() / A.sum():.3f} < 1"
    pr = p * r
    spread = (pr.max() - pr.min()) / pr.mean()
    assert spread < 0.02, f"{scheme}: p r spread {spread:.4f} after {last.step} steps"
    F = float((p * A).sum())
    T = MU * float((p * A * r).sum())
    ref = uniform_wear_torque(F, MU, g.inner_radius, g.outer_radius)
    assert T / ref == pytest.approx(1.0, abs=5e-3), f"{scheme}: torque / mu F (ro+ri)/2 = {T / ref}"
    # the start is far from it: the flat pad's p r varies by more than 100 %
    first = next(
        wear_history(
            Run(
                model,
                P_LINE,
                OMEGA,
                DURATION,
                WearLaw(K_PAD),
                None,
                MU,
                interface=itf,
                numerics=Numerics(scheme="explicit", steps=1000),
            )
        )
    )
    pr0 = (first.pressure * r)[first.active]
    assert (pr0.max() - pr0.min()) / pr0.mean() > 1.0


def test_steady_pressure_is_the_uniform_wear_law(model):
    from brakewear.analytic import uniform_wear_pressure

    itf, last, p, act = end_state(model, "implicit")
    g = model.geometry.pad
    F = float((p * itf.area).sum())
    ref = uniform_wear_pressure(itf.r, F, g.arc_angle, g.inner_radius, g.outer_radius)
    err = np.abs(p - ref).max() / ref.max()
    # the lumped nodal areas at the pad's edges make F/(theta (ro-ri)) differ slightly
    assert err < 0.03, f"max |p - p_uniform_wear| / max p = {err:.4f}"
