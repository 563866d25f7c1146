"""Convection that follows the rotor's speed, and cooling in the dwells of a duty."""
import numpy as np
import pytest

from brakewear.duty import Dwell
from brakewear.errors import DutyError, ThermalError
from brakewear.model import BrakeModel
from brakewear.thermal import K_AIR, NU_AIR, SpeedConvection, ThermalModel
from brakewear.wear import Run


def test_speed_convection_law():
    law = SpeedConvection(100.0, 50.0, 0.8, 10.0)
    assert law.h(0.0) == 10.0 and law.h(50.0) == pytest.approx(100.0, rel=1e-15)
    assert law.h(100.0) == pytest.approx(10.0 + 90.0 * 2 ** 0.8, rel=1e-14)
    solid = SpeedConvection.solid(h_static=0.0)
    # von Karman's laminar rotating disc: h = 0.33 k_air sqrt(omega / nu_air)
    for w in (10.0, 55.0, 120.0):
        assert solid.h(w) == pytest.approx(0.33 * K_AIR * np.sqrt(w / NU_AIR), rel=1e-12)
    # the scale is rounded to an eighth of an octave: at most 2^(1/16) - 1 = 4.4 % off
    for w in np.linspace(1.0, 150.0, 37):
        s = law.scale(w)
        assert abs(np.log2(s) * 8 - np.round(np.log2(s) * 8)) < 1e-9
        assert abs(s * law.h_ref / law.h(w) - 1.0) <= 2 ** (1 / 16) - 1 + 1e-12
    assert SpeedConvection(100.0, 50.0).scale(0.0) == 0.0


@pytest.mark.parametrize("kw, match", [
    (dict(h_ref=0.0, omega_ref=50.0), "h_ref"),
    (dict(h_ref=100.0, omega_ref=-1.0), "omega_ref"),
    (dict(h_ref=100.0, omega_ref=50.0, exponent=3.0), "exponent"),
    (dict(h_ref=100.0, omega_ref=50.0, h_static=200.0), "h_static"),
])
def test_bad_speed_convection_is_refused(kw, match):
    with pytest.raises(ThermalError, match=match):
        SpeedConvection(**kw)


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=1.2e-2)


def _cooled(model, omega, law):
    th = ThermalModel(model, h_conv={"pad": 40.0, "rotor": law},
                      T_initial=473.15, contact_conductance=0.0)
    th.set_speed(omega)
    q = np.zeros(th.pad_nodes.size)
    for _ in range(3):
        th.step(q, 4.0)
        b = th.heat_balance()
        assert b["relative_error"] < 1e-8 or b["friction_power_W"] == 0.0
        rotor = b["bodies"]["rotor"]
        assert abs(rotor["stored_W"] + rotor["convected_W"]) <= 1e-8 * abs(rotor["stored_W"])
    return th, rotor["convected_W"]


def test_a_spinning_rotor_cools_faster_and_its_balance_holds(model):
    law = SpeedConvection.vented()
    th0, still = _cooled(model, 0.0, law)
    th1, spinning = _cooled(model, 55.0, law)
    assert th1.heat["rotor"].h_scale == 1.0 and th0.heat["rotor"].h_scale == pytest.approx(
        0.1, rel=2 ** (1 / 16) - 1
    )
    assert spinning > 5 * still > 0
    assert th1.face_temperature("rotor").mean() < th0.face_temperature("rotor").mean()
    # the pad's constant coefficient does not follow the speed
    assert th1.heat["pad"].h_scale == th0.heat["pad"].h_scale == 1.0


def test_a_number_and_a_constant_law_cool_alike(model):
    """h_conv = 40 and a SpeedConvection that is 40 at the speed give the same field."""
    law = SpeedConvection(40.0, 55.0, 0.8, 0.0)
    a, _ = _cooled(model, 55.0, law)
    b, _ = _cooled(model, 55.0, 40.0)
    assert np.abs(a.T["rotor"] - b.T["rotor"]).max() <= 1e-12 * a.T["rotor"].max()


def test_dwell_speed_checks():
    with pytest.raises(DutyError, match="at most one of speed"):
        Dwell(10.0, speed=20.0, omega=60.0)
    with pytest.raises(DutyError, match="dwell.speed"):
        Dwell(10.0, speed=-1.0)


def test_radiation_coefficient_is_the_exact_secant():
    from brakewear.thermal import SIGMA, radiation_coefficient
    for T in (373.15, 873.15):
        h = radiation_coefficient(0.6, T, 293.15)
        assert h * (T - 293.15) == pytest.approx(0.6 * SIGMA * (T ** 4 - 293.15 ** 4), rel=1e-13)


def test_a_radiating_rotor_sheds_the_stefan_boltzmann_power(model):
    """A rotor at a uniform 600 C with no convection: the first short step loses
    eps sigma (T^4 - T_a^4) A (to the 2^(1/16) rounding of the coefficient), the heat
    balance holds, and the loss falls as the rotor cools."""
    from brakewear.thermal import SIGMA
    th = ThermalModel(model, h_conv={"pad": 0.0, "rotor": 0.0}, emissivity={"rotor": 0.6},
                      T_initial=873.15, contact_conductance=0.0)
    heat = th.heat["rotor"]
    area = float(heat.H1.sum()) / th.h_assembled["rotor"]
    q = np.zeros(th.pad_nodes.size)
    th.step(q, 0.01)
    b = th.heat_balance()["bodies"]["rotor"]
    expected = 0.6 * SIGMA * (873.15 ** 4 - 293.15 ** 4) * area
    assert b["convected_W"] == pytest.approx(expected, rel=2 ** (1 / 16) - 1 + 1e-3)
    assert abs(b["stored_W"] + b["convected_W"]) <= 1e-8 * b["convected_W"]
    for _ in range(5):
        th.step(q, 60.0)
    later = th.heat_balance()["bodies"]["rotor"]["convected_W"]
    assert 0 < later < 0.9 * b["convected_W"]
    assert th.heat["pad"].h_scale == 1.0        # the pad neither convects nor radiates


def test_bad_emissivity_is_refused(model):
    with pytest.raises(ThermalError, match="emissivity = 1.5"):
        ThermalModel(model, emissivity=1.5)
    with pytest.raises(ThermalError, match="emissivity: body 'hat'"):
        ThermalModel(model, emissivity={"hat": 0.5})


def test_scene_convection_and_dwell_speed(tmp_path):
    """thermal.convection = 'vented' gives the rotor a SpeedConvection and keeps the
    pad's h_conv; a [schedule] with dwell_speed drives the dwells at that speed."""
    from brakewear.duty.schedule import KMH, schedule_from_table
    from brakewear.errors import SceneError
    from brakewear.scene import ThermalSpec
    t = ThermalSpec(enabled=True, convection="vented", h_conv=25.0, emissivity=0.5)
    law = t.convection_law()
    assert law["pad"] == 25.0 and law["rotor"] == SpeedConvection.vented()
    with pytest.raises(SceneError, match="thermal.h_conv.rotor"):
        ThermalSpec(convection="solid", h_conv={"rotor": 30.0})
    with pytest.raises(SceneError, match="thermal.convection"):
        ThermalSpec(convection="forced")
    with pytest.raises(SceneError, match="thermal.emissivity"):
        ThermalSpec(emissivity=2.0)
    apps = schedule_from_table({"stops": 3, "speed_from": 80.0, "deceleration": 3.0,
                                "interval": 60.0, "dwell_speed": 80.0})
    dwells = [a for a in apps if isinstance(a, Dwell)]
    assert len(dwells) == 2 and all(d.speed == pytest.approx(80.0 * KMH) for d in dwells)


def test_a_dwell_driven_at_speed_cools_the_vented_rotor_more(model):
    """The same stop, then 60 s of dwell at rest or driven at 80 km/h: with a vented
    rotor's speed-dependent convection the driven dwell ends cooler."""
    from brakewear import Numerics, WearLaw
    from brakewear.duty import Stop, Vehicle, run_schedule
    car = Vehicle(mass=1800.0, front_share=0.7, tyre_radius=0.32, brakes_per_axle=2)
    end = {}
    for label, dwell in (("rest", Dwell(60.0)), ("driven", Dwell(60.0, speed=80 / 3.6))):
        th = ThermalModel(model, h_conv={"pad": 40.0, "rotor": SpeedConvection.vented()})
        list(
            run_schedule(
                Run(
                    model,
                    pad_law=WearLaw(5e-15),
                    rotor_law=WearLaw(5e-16),
                    mu=0.4,
                    schedule=[Stop(80 / 3.6, decel=3.0), dwell],
                    vehicle=car,
                    thermal=th,
                    numerics=Numerics(steps=3),
                )
            )
        )
        end[label] = float(th.face_temperature("rotor").mean())
    rise = end["rest"] - 293.15
    assert rise > 10.0
    assert end["driven"] < end["rest"] - 0.05 * rise, end
