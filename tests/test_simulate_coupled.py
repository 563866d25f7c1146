"""The wear loop with thermal coupling, a friction law, and the Winkler interface model."""
import subprocess
import sys

import numpy as np
import pytest

from brakewear.errors import WearError
from brakewear.interfaces import FoundationInterface, WinklerInterface
from brakewear.laws.base import FrictionLaw, WearLaw
from brakewear.model import BrakeModel
from brakewear.thermal import ThermalModel
from brakewear.wear import Numerics, Run, wear_history

PAD, ROTOR = WearLaw(5e-15), WearLaw(5e-16)
HOT_PAD = WearLaw(5e-15, activation_energy=5e4, T_threshold=320.0)
ARGS = (1e6, 55.0, 40.0)


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=8e-3)


def test_thermal_energy_balance_every_step_and_hotter_wear(model):
    cold = list(
        wear_history(
            Run(model, *ARGS, HOT_PAD, ROTOR, mu=0.4, numerics=Numerics(steps=3, scheme="implicit"))
        )
    )
    th = ThermalModel(model, contact_conductance=1e5)
    hot = list(
        wear_history(
            Run(
                model,
                *ARGS,
                HOT_PAD,
                ROTOR,
                mu=0.4,
                thermal=th,
                numerics=Numerics(steps=3, scheme="implicit"),
            )
        )
    )
    for s in hot:
        assert s.heat_balance_error <= 1e-8
        # worn volume = Archard integral with k(T), still to round-off
        assert abs(s.pad_volume - s.pad_archard) <= 1e-10 * s.pad_archard
    T = [s.pad_temperature_max for s in hot]
    assert T[0] > th.T_ambient and np.all(np.diff(T) > 0)          # a steady drag heats up
    assert np.isnan(cold[-1].pad_temperature_max)
    # above the threshold the pad wears faster
    assert hot[-1].pad_volume > 1.5 * cold[-1].pad_volume


def test_thermal_resume_repeats_the_run(model, tmp_path):
    ck = tmp_path / "t.npz"

    def run(**kw):
        return list(
            wear_history(
                Run(
                    model,
                    *ARGS,
                    PAD,
                    ROTOR,
                    mu=0.4,
                    thermal=ThermalModel(model, contact_conductance=1e5),
                    numerics=Numerics(steps=4, scheme="implicit"),
                ),
                checkpoint=ck,
                every=1,
                **kw,
            )
        )

    full = run()
    for s in wear_history(
        Run(
            model,
            *ARGS,
            PAD,
            ROTOR,
            mu=0.4,
            thermal=ThermalModel(model, contact_conductance=1e5),
            numerics=Numerics(steps=4, scheme="implicit"),
        ),
        checkpoint=ck,
        every=1,
    ):
        if s.step == 3:     # stopped while step 3 is handled: the checkpoint holds step 2
            break
    rest = run(resume=True)
    assert [s.step for s in rest] == [3, 4]
    assert np.abs(rest[-1].pad_wear - full[-1].pad_wear).max() <= 1e-12 * full[-1].pad_wear.max()
    assert rest[-1].pad_temperature_max == pytest.approx(full[-1].pad_temperature_max, rel=1e-12)


def test_friction_law_follows_temperature(model):
    law = FrictionLaw(0.4, slope=-5e-4, T_ref=293.15, mu_min=0.2)
    steps = list(
        wear_history(
            Run(
                model,
                *ARGS,
                PAD,
                ROTOR,
                mu=law,
                thermal=ThermalModel(model, contact_conductance=1e5),
                numerics=Numerics(steps=3, scheme="implicit"),
            )
        )
    )
    mus = [s.mu for s in steps]
    assert mus[0] == pytest.approx(0.4) and mus[-1] < mus[0] and min(mus) >= 0.2


def test_friction_law_needs_thermal(model):
    with pytest.raises(WearError, match="thermal"):
        next(
            wear_history(
                Run(
                    model,
                    *ARGS,
                    PAD,
                    mu=FrictionLaw(0.4, slope=-5e-4),
                    numerics=Numerics(scheme="explicit"),
                )
            )
        )


def test_a_constant_friction_law_per_node_is_the_number(model):
    """mu per node (one value at every pad node) gives the history of the number
    bit for bit: the same friction operator, pressures and wear."""

    def run(mu):
        return list(
            wear_history(
                Run(model, *ARGS, PAD, ROTOR, mu=mu, numerics=Numerics(steps=2, scheme="implicit"))
            )
        )

    a, b = run(0.4), run(FrictionLaw(0.4))
    for x, y in zip(a, b):
        assert np.array_equal(x.pressure_end, y.pressure_end)
        assert np.array_equal(x.pad_wear, y.pad_wear) and np.array_equal(x.rotor_wear,
                                                                         y.rotor_wear)
        assert y.mu == pytest.approx(0.4, rel=1e-14)


def test_loop_without_thermal_never_imports_it():
    code = ("import sys; from brakewear import BrakeModel; from brakewear import "
            "wear_history; from brakewear import Run, WearLaw, Numerics; "
            "m = BrakeModel(size=1.2e-2); "
            "list(wear_history(Run(m, 1e6, 55.0, 10.0, WearLaw(5e-15), "
            "numerics=Numerics(scheme='explicit', steps=1)))); "
            "assert 'brakewear.thermal' not in sys.modules, 'thermal imported'")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_winkler_interface_in_the_loop_conserves_and_balances(model):
    w = WinklerInterface.from_model(model)
    itf = FoundationInterface(model, w, 1e6)
    for scheme in ("explicit", "implicit"):
        steps = list(
            wear_history(
                Run(
                    model,
                    1e6,
                    55.0,
                    600.0,
                    PAD,
                    ROTOR,
                    interface=itf,
                    numerics=Numerics(steps=6, scheme=scheme),
                )
            )
        )
        s = steps[-1]
        F = 1e6 * model.geometry.piston.hydraulic_area
        assert (s.pressure * itf.area).sum() == pytest.approx(F, rel=1e-8)
        assert abs(s.pad_volume - s.pad_archard) <= 1e-10 * s.pad_archard
        assert abs(s.rotor_volume - s.rotor_archard) <= 1e-10 * s.rotor_archard


def test_thermal_with_the_geometry_update(model):
    """With the geometry update the temperatures ride on the moved nodes and the
    heat balances to 1e-8 in every step; at a few um of wear (0.1 % of the 3.5 mm
    element) the history is the gap-offset one to O(wear / h)."""
    runs = {}
    for update in ("gap", "geometry"):
        th = ThermalModel(model)
        runs[update] = (
            th,
            list(
                wear_history(
                    Run(
                        model,
                        *ARGS,
                        PAD,
                        ROTOR,
                        mu=0.4,
                        thermal=th,
                        numerics=Numerics(steps=4, update=update),
                    )
                )
            ),
        )
    (th_gap, gap), (th_geo, geo) = runs["gap"], runs["geometry"]
    assert th_gap.model is model and th_geo.model is not model     # moved with the faces
    for s in geo:
        assert s.heat_balance_error <= 1e-8
        assert abs(s.pad_volume - s.pad_archard) <= 1e-10 * s.pad_archard
    a, b = gap[-1], geo[-1]
    assert np.abs(a.pad_wear - b.pad_wear).max() <= 0.03 * a.pad_wear.max()
    rise = a.pad_temperature_max - th_gap.T_ambient
    assert abs(b.pad_temperature_max - a.pad_temperature_max) <= 0.01 * rise
    # the moved pad face carries the temperatures of the reference one, node by node
    z0 = model.meshes["pad"].p[2, th_gap.pad_nodes]
    z1 = th_geo.model.meshes["pad"].p[2, th_geo.pad_nodes]
    assert (
        np.abs((z1 - z0) - b.pad_wear).max() <= 1e-9 * b.pad_wear.max() + 1e-12 * np.abs(z0).max()
    )
