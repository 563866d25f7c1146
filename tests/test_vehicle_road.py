"""The vehicle's road load and regenerative blending (brakewear.duty.vehicle) and a
drive cycle replayed through them (brakewear.duty.cycle): closed forms, brute-force
integrals of the same forces, the stop's equation of motion, energy closure."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from brakewear import DutyError, Numerics, WearLaw
from brakewear.duty import (
    KMH,
    Stop,
    Vehicle,
    packaged_cycle,
    read_speed_trace,
    replay_cycle,
    run_schedule,
    study_car,
)
from brakewear.duty.vehicle import G
from brakewear.wear import Run

ROAD = dict(mass=1800.0, rolling_resistance=0.01, drag_area=0.6, air_density=1.2,
            drivetrain_drag=30.0, inertia_factor=1.03)
BLEND = dict(regen_share=1.0, regen_torque_limit=2500.0, regen_power_limit=60e3,
             regen_decel_limit=2.0, regen_cutoff_speed=5 * KMH, regen_full_speed=12 * KMH)


def _brute(car, v0, v1, a, n=400_001):
    """The stop's energies by the trapezoid rule on the time axis (v = v0 - a t)."""
    t = np.linspace(0.0, (v0 - v1) / a, n)
    v = v0 - a * t
    road, regen, fric = car.road_force(v), car.regen_force(a, v), car.friction_force(a, v)
    return {k: np.trapezoid(f * v, t) for k, f in (("road_J", road), ("regenerated_J", regen),
                                               ("friction_J", fric))}


def test_road_load_of_a_stop_is_its_closed_form():
    """Rolling resistance and drivetrain drag are constant, drag quadratic in v:
    over a stop at a, road work = (c0 (v0^2 - v1^2)/2 + c2 (v0^4 - v1^4)/4) / a."""
    car = Vehicle(**ROAD)
    v0, v1, a = 100 * KMH, 20 * KMH, 1.2
    c0, c2 = 0.01 * 1800 * G + 30.0, 0.5 * 1.2 * 0.6
    e = car.stop_energy(v0, v1, a)
    assert e["road_J"] == pytest.approx((c0 * (v0**2 - v1**2) / 2 + c2 * (v0**4 - v1**4) / 4) / a,
                                        rel=1e-13)
    assert e["kinetic_J"] == pytest.approx(0.5 * 1.03 * 1800 * (v0**2 - v1**2), rel=1e-14)
    assert e["friction_J"] == pytest.approx(e["kinetic_J"] - e["road_J"], rel=1e-13)
    assert e["propulsion_J"] == 0.0
    assert e["face_J"] == pytest.approx(e["friction_J"] * 0.7 / 2 / 2, rel=1e-14)
    # the torque held is the stop's work over its angle; without road load it is m a R share/n
    assert car.stop_torque(v0, v1, a) * e["rotor_angle"] == pytest.approx(e["brake_J"], rel=1e-14)
    bare = Vehicle(mass=1800.0)
    assert bare.stop_torque(v0, v1, a) == pytest.approx(bare.brake_torque(a), rel=1e-14)


@pytest.mark.parametrize("a", [0.3, 1.0, 2.5, 6.0])
def test_blended_stop_closes_and_equals_the_brute_force_integral(a):
    """Fade-out, torque, power and deceleration limits: the quadrature against a
    400 001-point trapezoid of the same forces, and kinetic + propulsion = road +
    regenerated + friction."""
    car = Vehicle(**ROAD, **BLEND)
    e = car.stop_energy(130 * KMH, 0.0, a)
    closure = e["road_J"] + e["regenerated_J"] + e["friction_J"] - e["propulsion_J"]
    assert closure == pytest.approx(e["kinetic_J"], rel=1e-10)
    brute = _brute(car, 130 * KMH, 0.0, a)
    for k, v in brute.items():
        assert e[k] == pytest.approx(v, rel=2e-6, abs=1e-6 * e["kinetic_J"]), k


def test_the_blending_as_the_controller_does_it():
    car = Vehicle(**ROAD, **BLEND)
    a = 1.0
    need = car.braking_demand(a, 50 * KMH)
    assert car.regen_force(a, 50 * KMH) == pytest.approx(need, rel=1e-14)   # all regenerated
    assert car.regen_force(a, 4 * KMH) == 0.0                             # below the cutoff
    mid = 8.5 * KMH                                                       # half faded out
    assert car.regen_force(a, mid) == pytest.approx(0.5 * car.braking_demand(a, mid), rel=1e-12)
    assert car.regen_force(2.0, 120 * KMH) == pytest.approx(60e3 / (120 * KMH), rel=1e-14)  # power
    assert car.regen_force(5.0, 30 * KMH) == pytest.approx(1800.0 * 2.0, rel=1e-14)  # decel cap
    # friction share against deceleration: nothing up to the cap, then the rest
    share = [car.friction_force(x, 30 * KMH) / car.braking_demand(x, 30 * KMH)
             for x in (1.0, 2.5, 5.0)]
    assert share[0] == 0.0 and 0 < share[1] < share[2] < 1
    # a cleaning routine: friction-only stops, or a friction share
    assert car.with_friction_share(1.0).regen_force(a, 50 * KMH) == 0.0
    part = car.with_friction_share(0.4)
    assert part.friction_force(a, 50 * KMH) == pytest.approx(0.4 * need, rel=1e-13)
    # road load alone slows the car at a crawl: the motor must drive, the brakes give nothing
    slow = car.stop_energy(130 * KMH, 100 * KMH, 0.2)
    assert slow["propulsion_J"] > 0 and car.friction_force(0.2, 130 * KMH) == 0.0


@pytest.mark.parametrize("blend", [{}, BLEND])
def test_deceleration_inverts_the_torque_at_every_speed(blend):
    car = Vehicle(**ROAD, **blend)
    for v in (3 * KMH, 8 * KMH, 40 * KMH, 120 * KMH):
        for a in (0.8, 3.0, 6.0):
            T = car.brake_torque(a, v)
            if T > 0:
                assert car.deceleration(T, v) == pytest.approx(a, rel=1e-12)


@pytest.mark.parametrize("blend", [{}, BLEND])
def test_a_stop_under_a_torque_integrates_its_equation_of_motion(blend):
    """Constant brake torque: lambda m dv/dt = -(F_f + F_regen + F_road); distance,
    time and energies against solve_ivp of that equation."""
    car = Vehicle(**ROAD, **blend)
    T, v0 = 600.0, 110 * KMH
    e = car.stop_energy(v0, 0.0, torque=T)
    stop = lambda t, y: y[0] - 1e-9  # noqa: E731
    stop.terminal = True
    sol = solve_ivp(lambda t, y: [-car.deceleration(T, max(y[0], 0.0)), max(y[0], 0.0),
                                  car.road_force(max(y[0], 0.0)) * max(y[0], 0.0)],
                    (0, 200), [v0, 0.0, 0.0], rtol=1e-11, atol=1e-10, events=stop,
                    max_step=0.05)
    assert e["duration"] == pytest.approx(sol.t[-1], rel=1e-6)
    assert e["distance"] == pytest.approx(sol.y[1, -1], rel=1e-7)
    assert e["road_J"] == pytest.approx(sol.y[2, -1], rel=1e-7)
    assert e["brake_J"] == pytest.approx(T / car.tyre_radius * e["distance"], rel=1e-14)
    assert e["kinetic_J"] == pytest.approx(e["road_J"] + e["regenerated_J"] + e["friction_J"],
                                           rel=1e-12)
    assert e["rotor_angle"] == pytest.approx(e["distance"] / car.tyre_radius, rel=1e-14)
    # a linear speed profile at the returned deceleration has the stop's distance
    assert v0 ** 2 / (2 * e["decel"]) == pytest.approx(e["distance"], rel=1e-13)


@pytest.mark.parametrize("kw, match", [
    (dict(regen_cutoff_speed=5.0, regen_full_speed=2.0), r"regen_cutoff_speed"),
    (dict(rolling_resistance=0.2), r"vehicle\.rolling_resistance: 0\.2 is not allowed"),
    (dict(drag_area=-1.0), r"vehicle\.drag_area: -1\.0 m\^2 is not allowed"),
    (dict(inertia_factor=0.9), r"vehicle\.inertia_factor"),
    (dict(regen_power_limit=-5.0), r"vehicle\.regen_power_limit: -5\.0 W"),
])
def test_bad_road_load_or_blending_is_refused_by_key(kw, match):
    with pytest.raises(DutyError, match=match):
        Vehicle(mass=1800.0, **kw)


def test_speed_dependent_forces_need_the_speed():
    with pytest.raises(DutyError, match="give the speed v"):
        Vehicle(**ROAD).brake_torque(1.0)
    with pytest.raises(DutyError, match="exactly one of decel"):
        Vehicle(**ROAD).stop_energy(10.0, 0.0)


def test_nedc_is_the_regulations_cycle():
    """Four ECE-15 cycles (1.013 km each) and the EUDC (6.955 km), 1180 s."""
    tr = packaged_cycle("nedc")
    assert tr.time[-1] == 1180.0
    assert tr.distance == pytest.approx(4 * 1013 + 6955, rel=2e-3)
    eudc = tr.time >= 780.0
    part = type(tr)(tr.time[eudc], tr.speed[eudc])
    assert part.distance == pytest.approx(6955.0, rel=5e-4)
    assert tr.speed.max() == pytest.approx(120 * KMH, rel=1e-14)


def test_replayed_cycle_closes_and_blending_spares_the_rotor():
    tr = packaged_cycle("nedc")
    car = study_car()
    blended, friction_only = replay_cycle(tr, car), replay_cycle(tr, car.with_friction_share(1))
    for r in (blended, friction_only):
        assert r["kinetic_J"] + r["propulsion_J"] == pytest.approx(
            r["road_J"] + r["regenerated_J"] + r["friction_J"], rel=1e-10)
    assert friction_only["regenerated_J"] == 0.0
    # the same decelerations: the kinetic energy and the road's share do not depend on it
    assert blended["kinetic_J"] == pytest.approx(friction_only["kinetic_J"], rel=1e-14)
    # NEDC's decelerations stay below the blending's 2 m/s^2: friction only where the
    # motor fades out (below 12 km/h) -- and every braking event ends there
    assert blended["friction_J"] < 0.05 * friction_only["friction_J"]
    assert all(ev["to_kmh"] < 12.0 + 1e-9 for ev in blended["events"])


def test_a_bad_speed_trace_names_the_row(tmp_path):
    f = tmp_path / "c.csv"
    f.write_text("time_s,speed_kmh\n0,0\n5,20\n5,30\n")
    with pytest.raises(DutyError, match=r"c\.csv, row 4: time_s = 5 is not after"):
        read_speed_trace(f)
    f.write_text("time_s,speed_kmh\n0,0\n5,400\n")
    with pytest.raises(DutyError, match=r"row 3: speed_kmh = 400 is not allowed"):
        read_speed_trace(f)
    f.write_text("t,v\n0,0\n")
    with pytest.raises(DutyError, match="need the columns time_s"):
        read_speed_trace(f)


def test_schedule_energy_closes_with_road_load_and_regeneration():
    """Per stop of a run: the demand on the faces, the road load and the motor's part
    make up the kinetic energy; the model's friction work is the demand within the
    torque drift (a stop that wears nothing: 1e-8)."""
    from brakewear.model import BrakeModel

    car = study_car(regen_share=0.5)
    model = BrakeModel("default", size=12e-3, rotor="rigid")
    sched = [Stop(80 * KMH, 30 * KMH, decel=1.5), Stop(60 * KMH, 10 * KMH, line_pressure=1.2e6)]
    for rec in run_schedule(
        Run(
            model,
            pad_law=WearLaw(1e-20),
            mu=0.4,
            schedule=sched,
            vehicle=car,
            numerics=Numerics(scheme="implicit", steps=3),
        )
    ):
        friction = rec.target_face_J * 2 * car.brakes_per_axle / car.axle_share
        assert rec.road_net_J + rec.regenerated_J + friction == pytest.approx(rec.kinetic_J,
                                                                              rel=1e-10)
        # the record's road_J is Vehicle.stop_energy's (the whole road load)
        e = car.stop_energy(rec.v0, rec.v1, rec.decel) if sched[rec.index].decel else None
        assert e is None or (rec.road_J == e["road_J"] and rec.propulsion_J == e["propulsion_J"])
        assert rec.road_net_J == rec.road_J - rec.propulsion_J
        assert abs(rec.torque_drift) < 1e-8
        assert rec.road_J > 0 and rec.regenerated_J > 0
