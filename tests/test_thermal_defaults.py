"""The default heat partition on the default drag: temperatures in the range the
energy allows, and the fixed partition of old refused by the plausibility bound."""
import pytest

from brakewear.laws.base import WearLaw
from brakewear.model import BrakeModel
from brakewear.thermal import H_CONTACT_DEFAULT, ThermalModel
from brakewear.wear import Numerics, Run, wear_history


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=1.2e-2)


def test_defaults_resolve_by_the_rotor():
    elastic = ThermalModel(BrakeModel("default", size=1.2e-2))
    assert elastic.contact_conductance == H_CONTACT_DEFAULT == 1e5
    assert elastic.settings["partition"] == "effusivity"
    rigid = ThermalModel(BrakeModel("default", size=1.2e-2, rotor="rigid"))
    assert rigid.contact_conductance == 0.0 and rigid.settings["partition"] == "effusivity_area"
    # the area-weighted share: the rotor's flux averaged over a revolution
    assert rigid.partition < 0.2 * elastic.partition


def test_default_drag_faces_lie_between_the_bulk_rise_and_the_fade_range(model):
    """90 s at 1 MPa, 55 rad/s, mu 0.4 (6 kW per face): the stored heat is the
    friction work (no convection shortcut), so the faces are at least as hot as the
    bodies' mean, E / sum(m c); with the contact conductance pad and rotor faces
    agree within a tenth of the rise and stay below 500 C, just beyond the roughly
    300-450 C over which the phenolic binder of resin-bonded pads decomposes
    (docs/references.md, Wear)."""
    th = ThermalModel(model)
    steps = list(
        wear_history(
            Run(
                model,
                1e6,
                55.0,
                90.0,
                WearLaw(5e-15),
                WearLaw(5e-16),
                mu=0.4,
                thermal=th,
                numerics=Numerics(steps=15),
            )
        )
    )
    T0 = th.T_ambient
    stored = sum(float((th.heat[b].M @ (th.T[b] - T0)).sum()) for b in th.bodies)
    mc = sum(float(th.heat[b].M.sum()) for b in th.bodies)
    bulk = stored / mc
    pad, rotor = steps[-1].pad_temperature_max - T0, steps[-1].rotor_temperature_max - T0
    assert bulk < rotor and bulk < pad
    assert abs(pad - rotor) < 0.1 * rotor
    assert max(pad, rotor) + T0 < 773.15, (pad, rotor)
    assert all(s.heat_balance_error < 1e-8 for s in steps)


def test_the_fixed_partition_trips_the_bound_naming_the_key(model):
    from brakewear.errors import TemperatureLimitError
    th = ThermalModel(model, partition="effusivity", contact_conductance=0.0)
    with pytest.raises(TemperatureLimitError,
                       match=r"contact_conductance 0 .* give thermal.contact_conductance > 0"):
        for _ in wear_history(
            Run(
                model,
                1e6,
                55.0,
                90.0,
                WearLaw(5e-15),
                WearLaw(5e-16),
                mu=0.4,
                thermal=th,
                numerics=Numerics(steps=15),
            )
        ):
            pass


def test_a_rigid_rotor_drag_localises_and_is_refused_with_its_figures():
    """With a rigid rotor only the pad expands: its hot spot takes the contact (105 pad
    nodes to 4 within 24 s at 8 mm) and the face passes 900 C even with the
    area-weighted share; the error names the localisation and the elastic rotor."""
    from brakewear.errors import TemperatureLimitError
    m = BrakeModel("default", size=8e-3, rotor="rigid")
    with pytest.raises(TemperatureLimitError,
                       match=r"now \d of \d+ pad nodes.*thermoelastic localisation.*"
                             r"components.rotor = 'elastic'"):
        for _ in wear_history(
            Run(
                m,
                1e6,
                55.0,
                30.0,
                WearLaw(5e-15),
                None,
                mu=0.4,
                thermal=ThermalModel(m),
                numerics=Numerics(steps=10),
            )
        ):
            pass


def test_the_packaged_thermal_scene_is_the_default_drag_with_heat_on():
    """`brakewear run thermal`: the default scene's brake, mesh, load and laws, the
    first 90 s of its drag in 30 equal steps, heating on with the default partition
    and the plausibility bound of 900 C."""
    import dataclasses

    from brakewear.scene import load_scene
    hot, cold = load_scene("thermal"), load_scene("default")
    assert hot.thermal.enabled and not cold.thermal.enabled
    assert hot.thermal.contact_conductance == H_CONTACT_DEFAULT
    assert hot.thermal.T_max == pytest.approx(900.0 + 273.15)
    assert hot.duration == pytest.approx(90.0) and hot.numerics.steps == 30
    same = ("geometry", "line_pressure", "omega", "ambient", "rotor", "piston", "layout",
            "mesh_size", "order", "resolution", "interface", "pad_wear", "rotor_wear")
    assert {f: getattr(hot, f) for f in same} == {f: getattr(cold, f) for f in same}
    assert dataclasses.replace(hot.numerics, steps=cold.numerics.steps) == cold.numerics
