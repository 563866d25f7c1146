"""Duty: the vehicle's torque and energy, stops against drags, schedules and
their inputs (brakewear.duty, brakewear.wear.speed)."""
import numpy as np
import pytest

from brakewear import DutyError, FEInterface, Numerics, WearLaw
from brakewear.duty import (
    Drag,
    Dwell,
    Stop,
    Vehicle,
    brake_torque,
    read_schedule_csv,
    repeated_stops,
    run_schedule,
    schedule_from_table,
)
from brakewear.model import BrakeModel
from brakewear.wear import ConstantSpeed, LinearSpeed, Run, wear_history

K_PAD, K_ROT = 5e-13, 5e-14
CAR = Vehicle(mass=1800.0, front_share=0.7, tyre_radius=0.32, brakes_per_axle=2)


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=12e-3, rotor="rigid")


# ------------------------------------------------------------------ vehicle --
@pytest.mark.parametrize("regen", [dict(), dict(regen_share=0.6),
                                   dict(regen_share=0.8, regen_torque_limit=900.0)])
def test_torque_and_deceleration_are_inverse_and_energy_adds_up(regen):
    car = Vehicle(mass=1800.0, **regen)
    for a in (0.5, 1.5, 4.0):
        assert car.deceleration(car.brake_torque(a)) == pytest.approx(a, rel=1e-12)
        e = car.stop_energy(50 / 3.6, 10 / 3.6, a)
        assert e["kinetic_J"] == pytest.approx(0.5 * 1800.0 * ((50 / 3.6) ** 2 - (10 / 3.6) ** 2),
                                               rel=1e-14)
        # the modelled brake's axle in its share, the other axle, the motor: all of it
        axle = e["brake_J"] * car.brakes_per_axle / car.axle_share
        assert axle + e["regenerated_J"] == pytest.approx(e["kinetic_J"], rel=1e-12)
        assert e["face_J"] == pytest.approx(0.5 * e["brake_J"], rel=1e-15)
    if "regen_torque_limit" in regen:     # the motor saturates at 900 N m / 0.32 m
        assert car.regen_force(4.0) == pytest.approx(900.0 / 0.32, rel=1e-14)


@pytest.mark.parametrize("kw, match", [
    (dict(mass=-5.0), r"vehicle\.mass: -5\.0 kg is not allowed; it must be >= 50 kg"),
    (dict(mass=1800.0, regen_share=1.5), r"vehicle\.regen_share: 1\.5 .*it must be <= 1"),
    (dict(mass=1800.0, tyre_radius=3.2), r"vehicle\.tyre_radius: 3\.2 m is not allowed"),
    (dict(mass=1800.0, axle="middle"), r"vehicle\.axle: 'middle' is not allowed"),
    (dict(mass=1800.0, front_share=1.0, axle="rear"), r"takes no braking force"),
])
def test_bad_vehicle_is_refused_by_key(kw, match):
    with pytest.raises(DutyError, match=match):
        Vehicle(**kw)


def test_deceleration_beyond_the_tyres_is_refused_before_solving():
    with pytest.raises(DutyError, match=r"deceleration = 12\.0 m/s\^2 .*tyre_mu g = 9\.81"):
        CAR.check_deceleration(12.0)
    with pytest.raises(DutyError, match="a stop needs a vehicle"):
        next(
            run_schedule(
                Run(None, pad_law=WearLaw(K_PAD), mu=0.4, schedule=[Stop(10.0, decel=1.0)])
            )
        )


def test_a_bad_schedule_is_refused_whole_before_any_solve(model, monkeypatch):
    """run_schedule checks every application when called: a third stop beyond the
    tyres' grip is refused, naming its index and value, before the interface is
    built or anything solved (a spy on the model's contact system sees no call)."""
    import brakewear.wear.run as runs

    built = []
    monkeypatch.setattr(type(model), "contact_system",
                        lambda self, *a, **k: built.append(a) or pytest.fail("assembled"))
    monkeypatch.setattr(runs, "build_interface",
                        lambda *a, **k: built.append(a) or pytest.fail("interface built"))
    laws = (WearLaw(K_PAD), WearLaw(K_ROT), 0.4)
    ok = Stop(50 / 3.6, decel=1.5)
    sched = [ok, Dwell(60.0), ok, Dwell(60.0), Stop(50 / 3.6, decel=12.0)]
    with pytest.raises(DutyError, match=r"^application 4: deceleration = 12\.0 m/s\^2 is not "
                                        r"allowed; need 0 < deceleration <= tyre_mu g = 9\.81"):
        run_schedule(
            Run(model, pad_law=laws[0], rotor_law=laws[1], mu=0.4, schedule=sched, vehicle=CAR)
        )
    # a line pressure whose least deceleration (all of it at the pad's inner radius)
    # is beyond the grip; a dwell from a stop's start that ends before the stop does
    r_in, A = model.geometry.pad.inner_radius, model.geometry.clamp_area
    p_bad = 1.05 * CAR.brake_torque(9.80665) / (2 * 0.4 * A * r_in)
    drag = Drag(1e6, 5.0, omega=40.0)
    for sched, car, match in (
            ([ok, Dwell(60.0), Stop(50 / 3.6, line_pressure=p_bad)], CAR,
             r"^application 2: line_pressure = .* MPa is not allowed; .*at least 10\.3 m/s\^2"),
            ([drag, ok, Dwell(5.0, from_start=True)], CAR,
             r"^application 2: dwell\.duration = 5\.0 s is not allowed; .*outlast its 9\.259 s"),
            ([drag, drag, Drag(1e6, 5.0, speed=10.0)], None,
             r"^application 2: a drag at a vehicle speed needs a vehicle")):
        with pytest.raises(DutyError, match=match):
            run_schedule(
                Run(model, pad_law=laws[0], rotor_law=laws[1], mu=0.4, schedule=sched, vehicle=car)
            )
    regen = Vehicle(mass=1800.0, regen_share=1.0)
    with pytest.raises(DutyError, match=r"^application 0: .*the motor takes all the braking"):
        run_schedule(
            Run(model, pad_law=laws[0], rotor_law=laws[1], mu=0.4, schedule=[ok], vehicle=regen)
        )
    with pytest.raises(DutyError, match=r"^initial_gap: 3 value\(s\)"):
        run_schedule(
            Run(
                model,
                pad_law=laws[0],
                rotor_law=laws[1],
                mu=0.4,
                schedule=[ok],
                vehicle=CAR,
                initial_gap=np.zeros(3),
            )
        )
    assert built == []


# ------------------------------------------------------------------ speed --
def test_linear_speed_angle_and_inverse():
    s = LinearSpeed(45.0, 0.0, 5.0)
    assert s.angle(5.0) == pytest.approx(112.5, rel=1e-15)
    for th in (0.0, 10.0, 112.5):
        assert s.angle(s.time_at_angle(th)) == pytest.approx(th, rel=1e-13, abs=1e-12)
    assert s.mean(1.0, 2.0) * 2.0 == pytest.approx(s.angle(3.0) - s.angle(1.0), rel=1e-14)
    with pytest.raises(Exception, match="omega0 = omega1 = 0"):
        LinearSpeed(0.0, 0.0, 1.0)


def test_a_stop_wears_as_a_drag_of_equal_sliding_distance(model):
    """Isothermal Archard wear depends on the rotor angle only: a stop (speed
    falling to 0) and a drag over the same angle, with steps equal in angle,
    wear the same to round-off (solver tolerance 1e-12)."""
    num = Numerics(scheme="implicit", steps=6, tol=1e-12)
    stop = LinearSpeed(45.0, 0.0, 5.0)
    theta = stop.angle(5.0)
    runs = []
    for speed, duration in ((stop, 5.0), (ConstantSpeed(60.0), theta / 60.0)):
        *_, last = wear_history(
            Run(model, 2e6, speed, duration, WearLaw(K_PAD), WearLaw(K_ROT), 0.4, numerics=num)
        )
        runs.append(last)
    a, b = runs
    assert a.sliding_distance == pytest.approx(b.sliding_distance, rel=1e-13)
    for f in ("pad_wear", "rotor_wear"):
        x, y = getattr(a, f), getattr(b, f)
        assert np.abs(x - y).max() <= 1e-10 * np.abs(y).max(), f
    assert a.pad_archard == pytest.approx(b.pad_archard, rel=1e-10)


# ------------------------------------------------------------------ schedule --
def test_stop_pressure_matches_the_torque_equation_and_energy_balances(model):
    """Without wear (k = 1e-30) the pressure field does not move within a stop: the friction
    work the model dissipates is the vehicle's demand on the face to 1e-8."""
    (rec,) = run_schedule(
        Run(
            model,
            pad_law=WearLaw(1e-30),
            mu=0.4,
            schedule=[Stop(50 / 3.6, decel=1.5)],
            vehicle=CAR,
            numerics=Numerics(steps=3, tol=1e-12),
        )
    )
    A = model.geometry.piston.hydraulic_area
    assert brake_torque(rec.line_pressure, 0.4, A, rec.r_eff) == pytest.approx(
        CAR.brake_torque(1.5), rel=1e-9)
    assert rec.duration == pytest.approx((50 / 3.6) / 1.5, rel=1e-14)
    assert rec.rotor_angle == pytest.approx((50 / 3.6) ** 2 / (2 * 1.5 * 0.32), rel=1e-12)
    assert rec.target_face_J == pytest.approx(
        0.5 * CAR.stop_energy(50 / 3.6, 0.0, 1.5)["brake_J"], rel=1e-14)
    assert abs(rec.torque_drift) < 1e-8, rec.torque_drift
    # the pad's effective radius lies on the pad
    g = model.geometry.pad
    assert g.inner_radius < rec.r_eff < g.outer_radius


def test_two_pistons_per_side_clamp_with_their_joint_area():
    """A fixed caliper with two 40 mm pistons per side clamps with twice one
    piston's force: the torque equation uses the pistons' joint area
    (``geometry.clamp_area``), so the model's friction work is the vehicle's
    demand to 1e-8 (no wear) as with one piston."""
    from dataclasses import replace

    from brakewear.geometry import CaliperGeometry, load_geometry
    g = load_geometry("default")
    p1 = replace(g.piston, diameter=0.040, rim_inner_diameter=0.036, bore_diameter=0.040,
                 radius=0.119, angle=np.radians(-12.0))
    fixed = replace(g, caliper=CaliperGeometry("fixed"), piston=p1,
                    extra_pistons=(replace(p1, angle=np.radians(12.0)),))
    m = BrakeModel(fixed, size=12e-3, rotor="rigid")
    (rec,) = run_schedule(
        Run(
            m,
            pad_law=WearLaw(1e-30),
            mu=0.4,
            schedule=[Stop(50 / 3.6, decel=1.5)],
            vehicle=CAR,
            numerics=Numerics(steps=2, tol=1e-12),
        )
    )
    assert fixed.clamp_area == pytest.approx(2 * p1.hydraulic_area, rel=1e-15)
    assert brake_torque(rec.line_pressure, 0.4, fixed.clamp_area, rec.r_eff) == pytest.approx(
        CAR.brake_torque(1.5), rel=1e-9)
    assert abs(rec.torque_drift) < 1e-8, rec.torque_drift


def test_the_full_model_dissipates_the_demand_on_each_face():
    """Both pads modelled (equal pistons both sides): each face carries the clamp
    force, the torque equation holds with the effective radius of both faces'
    pressure, and the friction work per face is the vehicle's demand per face
    to 1e-8 (no wear), as in the half model, at the half model's line pressure
    (the meshes are mirror images: 1e-9)."""
    from dataclasses import replace

    from brakewear.geometry import load_geometry
    g = load_geometry("default")
    rim = replace(g, piston=replace(g.piston, rim_inner_diameter=0.030))
    recs = {}
    for layout in ("half", "full"):
        m = BrakeModel(rim, size=8e-3, layout=layout)
        (recs[layout],) = run_schedule(
            Run(
                m,
                pad_law=WearLaw(1e-30),
                mu=0.4,
                schedule=[Stop(50 / 3.6, decel=1.5)],
                vehicle=CAR,
                numerics=Numerics(steps=2, tol=1e-12),
            )
        )
        assert abs(recs[layout].torque_drift) < 1e-8, (layout, recs[layout].torque_drift)
    assert recs["full"].line_pressure == pytest.approx(recs["half"].line_pressure, rel=1e-9)


def test_chained_applications_equal_one_history(model):
    """Three drags under one line pressure with dwells between, run as a schedule
    (each a history started from the wear before it), wear as one history over
    their total time with the same steps: in gap-offset mode the wear enters
    only the gap.  (A stop wears as a drag of its angle: the test above.)"""
    num = Numerics(scheme="implicit", steps=4, tol=1e-12)
    sched = [Drag(2e6, 2.5, omega=40.0), Dwell(30.0)] * 2 + [Drag(2e6, 2.5, omega=40.0)]
    recs = list(
        run_schedule(
            Run(
                model,
                pad_law=WearLaw(K_PAD),
                rotor_law=WearLaw(K_ROT),
                mu=0.4,
                schedule=sched,
                numerics=num,
            )
        )
    )
    assert [r.kind for r in recs] == ["drag", "dwell"] * 2 + ["drag"]
    *_, one = wear_history(
        Run(
            model,
            2e6,
            40.0,
            7.5,
            WearLaw(K_PAD),
            WearLaw(K_ROT),
            0.4,
            numerics=Numerics(scheme="implicit", steps=12, tol=1e-12),
        )
    )
    last = recs[-1]
    assert np.abs(last.pad_wear - one.pad_wear).max() <= 1e-9 * one.pad_wear.max()
    assert np.abs(last.rotor_wear - one.rotor_wear).max() <= 1e-9 * one.rotor_wear.max()
    drags = [r for r in recs if r.kind == "drag"]
    assert sum(r.pad_volume_m3 for r in drags) == pytest.approx(one.pad_volume, rel=1e-9)
    assert recs[2].t_start == pytest.approx(32.5, rel=1e-15)
    # a drag's demand is its own torque over its angle at the start; wear (k = 100 x a
    # resin pad's) moves the effective radius inwards by ~0.1 % within each drag
    drift = [r.torque_drift for r in drags]
    assert all(-5e-3 < d < 0 for d in drift), drift


def test_chained_stops_equal_one_schedule_run(model):
    """Three stops (with the dwells between them) run as one schedule wear as the
    same stops run one call at a time, each call started from the worn state of
    the calls before: its gap is the initial gap plus the pad's wear plus the
    rotor's carried onto the pad (``W``), which is all the state gap-offset
    wear has.  Wear, end pressures and line pressures agree to 1e-9 (the
    contact solves' tolerance is 1e-12; the active set is only a first guess)."""
    num = Numerics(scheme="implicit", steps=4, tol=1e-12)
    laws = (WearLaw(K_PAD), WearLaw(K_ROT), 0.4)
    sched = repeated_stops(3, 50 / 3.6, decel=1.5, interval=60.0)
    one = [
        r
        for r in run_schedule(
            Run(
                model,
                pad_law=laws[0],
                rotor_law=laws[1],
                mu=0.4,
                schedule=sched,
                vehicle=CAR,
                numerics=num,
            )
        )
        if r.kind == "stop"
    ]
    itf = FEInterface(model, 1e6, 0.4, num.tol)
    pad, rotor, chained = np.zeros(itf.area.size), np.zeros(itf.rotor_area.size), []
    for k in range(3):
        part = sched[2 * k:2 * k + 2]  # a stop and the dwell after it
        recs = list(
            run_schedule(
                Run(
                    model,
                    pad_law=laws[0],
                    rotor_law=laws[1],
                    mu=0.4,
                    schedule=part,
                    vehicle=CAR,
                    numerics=num,
                    interface=itf,
                    initial_gap=pad + itf.W @ rotor,
                )
            )
        )
        stop = recs[0]
        pad, rotor = pad + recs[-1].pad_wear, rotor + recs[-1].rotor_wear
        chained.append((stop, pad.copy(), rotor.copy()))
    assert len(one) == 3
    for a, (b, pad_b, rotor_b) in zip(one, chained):
        assert b.line_pressure == pytest.approx(a.line_pressure, rel=1e-9)
        for x, y in ((pad_b, a.pad_wear), (rotor_b, a.rotor_wear), (b.pressure, a.pressure)):
            assert np.abs(x - y).max() <= 1e-9 * np.abs(y).max()
        assert b.pad_volume_m3 == pytest.approx(a.pad_volume_m3, rel=1e-9)
        assert b.friction_face_J == pytest.approx(a.friction_face_J, rel=1e-9)
    # the state matters: the wear moves the pressure inward, so the last stop needs a
    # higher line pressure for the same torque (0.8 % here)
    assert one[-1].line_pressure > 1.002 * one[0].line_pressure


# ------------------------------------------------------------------ inputs --
def test_schedule_table_in_scene_units():
    sched = schedule_from_table({"stops": 3, "speed_from": 50.0, "deceleration": 1.5,
                                 "interval": 120.0}, "s.toml")
    assert [type(a).__name__ for a in sched] == ["Stop", "Dwell", "Stop", "Dwell", "Stop"]
    assert sched[0].v0 == pytest.approx(50 / 3.6, rel=1e-15)
    assert sched[1].duration == pytest.approx(120.0 - (50 / 3.6) / 1.5, rel=1e-14)
    with pytest.raises(DutyError, match=r"s\.toml: schedule\.speed: unknown key"):
        schedule_from_table({"stops": 3, "speed": 50.0}, "s.toml")
    with pytest.raises(DutyError, match=r"s\.toml: schedule\.interval: 5\.0 s is not allowed; "
                                        r"it must be above the stop's duration"):
        schedule_from_table({"stops": 3, "speed_from": 50.0, "deceleration": 1.5,
                             "interval": 5.0}, "s.toml")
    with pytest.raises(DutyError, match="exactly one of decel"):
        repeated_stops(2, 10.0)


def test_drive_cycle_csv(tmp_path):
    f = tmp_path / "cycle.csv"
    f.write_text("time_s,speed_kmh,line_pressure_MPa\n0,50,2\n8,10,0\n20,10,1\n30,10,0\n"
                 "40,30,0\n50,30,\n")
    apps = read_schedule_csv(f)
    assert [type(a).__name__ for a in apps] == ["Stop", "Dwell", "Drag", "Dwell"]
    assert apps[0] == Stop(50 / 3.6, 10 / 3.6, line_pressure=2e6)
    assert apps[1].duration == 12.0 and apps[3].duration == 20.0
    assert apps[2] == Drag(1e6, 10.0, speed=10 / 3.6)


@pytest.mark.parametrize("text, match", [
    ("time_s,speed_kmh,line_pressure_MPa\n0,50,2\n8,10,0\n5,0,0\n",
     r"row 4: time_s = 5 does not increase"),
    ("time_s,line_pressure_MPa\n0,2\n8,0\n", r"missing column\(s\) speed_kmh or speed_m_s"),
    ("time_s,speed_kmh,line_pressure_MPa\n0,50,-2\n8,10,0\n",
     r"row 2: line_pressure_MPa = '-2' is not allowed"),
    ("time_s,speed_kmh,line_pressure_MPa\n0,fast,2\n8,10,0\n", r"row 2: not a number"),
])
def test_bad_drive_cycle_names_the_row(tmp_path, text, match):
    f = tmp_path / "cycle.csv"
    f.write_text(text)
    with pytest.raises(DutyError, match=match):
        read_schedule_csv(f)


@pytest.mark.parametrize("error", ["ActiveSetError", "ConvergenceError"])
def test_an_implicit_step_whose_contact_set_cycles_is_retried_shorter(model, error):
    """An implicit step whose active set does not settle, or whose linear solve does
    not converge (a pad free to tilt, held by the weak springs of a long step), is
    retried with half the step; with fixed steps the error is raised."""
    import brakewear
    from brakewear import FEInterface

    Error = getattr(brakewear, error)
    itf = FEInterface(model, 2e6, 0.4)
    solve, failures = itf.solve, []

    def flaky(offset, active, **kw):
        if kw.get("compliance") is not None and not failures:
            failures.append(kw["compliance"].max())
            raise Error("pad-rotor: scripted failure")
        return solve(offset, active, **kw)

    itf.solve = flaky
    first, *_ = wear_history(
        Run(
            model,
            2e6,
            40.0,
            1.0,
            WearLaw(K_PAD),
            None,
            0.4,
            interface=itf,
            numerics=Numerics(scheme="implicit"),
        )
    )
    assert first.rejected == 1 and len(failures) == 1
    failures.clear()
    with pytest.raises(Error, match="scripted"):
        next(
            wear_history(
                Run(
                    model,
                    2e6,
                    40.0,
                    1.0,
                    WearLaw(K_PAD),
                    None,
                    0.4,
                    interface=itf,
                    numerics=Numerics(scheme="implicit", steps=4),
                )
            )
        )
