"""Messages of bad scenes: the table of docs/scenes.md is what the reader says now, each
case is refused before anything is meshed or written, and bounds are checked against
each other and the start state (in the file's keys and units)."""
from __future__ import annotations

import pytest

from brakewear.cli import main
from brakewear.duty import Drag, Dwell, Stop, Vehicle, check_schedule, read_schedule_csv
from brakewear.errors import DutyError, InputError, SceneError, ThermalError
from brakewear.geometry import load_geometry
from brakewear.scene import Scene, ThermalSpec, WearSpec, load_scene
from studyload import load_study
from test_scenefile import _dump

STUDY = load_study("scene_messages")


def test_the_message_table_in_the_docs_is_what_the_reader_says():
    """docs/scenes.md's table of messages is the one studies/scene_messages.py makes from
    the reader now (renew it with ``python studies/scene_messages.py --write``)."""
    assert STUDY.documented() == STUDY.main(), (
        "the message table of docs/scenes.md differs from what the reader says; run "
        "python studies/scene_messages.py --write and read the difference")


@pytest.mark.parametrize("case,base,edits", STUDY.CASES, ids=[c[0] for c in STUDY.CASES])
def test_each_case_is_refused_before_meshing_or_writing(case, base, edits, tmp_path,
                                                        no_meshing, capsys):
    """The command line refuses each case of the table with exit code 2 and its message,
    before anything is meshed (a spy on the meshers) and before the output folder is
    made."""
    for name, text in STUDY.FILES.items():
        (tmp_path / name).write_text(text)
    path = tmp_path / STUDY.SOURCE
    path.write_text(_dump(STUDY._edited(base, edits)))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.replace(str(tmp_path) + "/", "")
    assert STUDY.message(base, edits, tmp_path) in err, err
    assert not out.exists(), "nothing may be written before the input is valid"


def test_the_known_messages_speak_the_files_keys_and_units():
    """A stop's end speed, a dwell speed, a tyre radius under mm and a T_max below the
    ambient are named as the file writes them, in its units (km/h, mm, C), with the
    scene file's name; a gap map that does not cover the pad names the scene file."""
    msgs = dict(STUDY.rows())
    for case, words in (
            ("`[schedule]` `speed_to = 60.0`", "schedule.speed_to: 60.0 km/h is not allowed; "
                                               "it must be below schedule.speed_from = 50.0 "
                                               "km/h"),
            ("`[vehicle]` `tyre_radius = 0.32`", "vehicle.tyre_radius: 0.32 mm is not allowed; "
                                                 "it must be >= 100 mm"),
            ("`[schedule]` `dwell_speed = -10.0`", "schedule.dwell_speed: -10.0 km/h is not "
                                                   "allowed; it must be >= 0 km/h"),
            ("`T_max = 10.0`", "thermal.T_max: 10.0 C is not allowed; it must be above "
                               "environment.ambient = 20.0 C"),
            ("`gap_file", "interface.gap_file: 'gap.csv': the map covers")):
        found = [m for c, m in msgs.items() if case in c]
        assert len(found) == 1 and found[0].startswith(f"{STUDY.SOURCE}: ") \
            and words in found[0], (case, found)


# --------------------------------------------------------------- cross-checks --

def _scene(**kw) -> Scene:
    return Scene(geometry=load_geometry("default"), **kw)


def test_thermal_bounds_are_checked_against_the_start():
    """T_max must lie above the ambient and the starting temperature (a face would start
    beyond its plausibility bound); a Python scene speaks SI; the ThermalModel of a
    Python run refuses the same."""
    with pytest.raises(SceneError, match=r"thermal\.T_max: 283\.15 K is not allowed; it must "
                                         r"be above environment\.ambient = 293\.15 K"):
        _scene(thermal=ThermalSpec(enabled=True, T_max=283.15))
    with pytest.raises(SceneError, match=r"thermal\.T_max: 400\.0 K .* above "
                                         r"thermal\.T_initial = 450\.0 K"):
        _scene(thermal=ThermalSpec(enabled=True, T_initial=450.0, T_max=400.0))
    with pytest.raises(SceneError, match=r"thermal\.T_initial: 1200\.0 K .* below "
                                         r"thermal\.T_max = 1173\.15 K \(the default"):
        _scene(thermal=ThermalSpec(enabled=True, T_initial=1200.0))
    # a bound just above the start, and any bound of a scene without heat, pass
    _scene(thermal=ThermalSpec(enabled=True, T_max=293.16))
    _scene(thermal=ThermalSpec(enabled=False, T_max=283.15))


def test_thermal_model_refuses_a_bound_below_its_start():
    from brakewear.model import BrakeModel
    from brakewear.thermal import ThermalModel
    m = BrakeModel("default", size=12e-3, rotor="rigid")
    with pytest.raises(ThermalError, match=r"T_max: 283\.15 K is not allowed; it must be "
                                           r"above T_ambient = 293\.15 K"):
        ThermalModel(m, T_max=283.15)
    with pytest.raises(ThermalError, match=r"above T_initial = 500\.0 K"):
        ThermalModel(m, T_initial=500.0, T_max=450.0)


def test_wear_limits_stay_within_the_layer_and_the_face():
    g = load_geometry("default")
    t_f, half = g.pad.friction_thickness, 0.5 * g.rotor.thickness
    _scene(pad_wear=WearSpec(limit=t_f), rotor_wear=WearSpec(limit=half))
    with pytest.raises(SceneError, match=r"wear\.pad\.limit: .* at most "
                                         r"pad\.friction_thickness .*backplate would wear"):
        _scene(pad_wear=WearSpec(limit=1.01 * t_f))
    with pytest.raises(SceneError, match=r"wear\.rotor\.limit: .* at most half of "
                                         r"rotor\.thickness"):
        _scene(rotor_wear=WearSpec(limit=1.01 * half))


CAR = Vehicle(mass=1800.0)


def test_a_stop_interval_shorter_than_any_stop_is_refused_before_the_run():
    """A dwell from a stop's start (a table's interval under a line pressure) must outlast
    the shortest the stop can be: its pressure field at the pad's outer radius, the
    largest torque it can give; the bound is the stop's time at that deceleration."""
    g = load_geometry("default")
    stop = Stop(50 / 3.6, line_pressure=3e6)
    from brakewear.duty.vehicle import brake_torque
    a_max = CAR.deceleration(brake_torque(3e6, 0.4, g.clamp_area, g.pad.outer_radius))
    shortest = stop.v0 / a_max
    check_schedule([stop, Dwell(1.001 * shortest, from_start=True)], CAR, mu=0.4, geometry=g)
    with pytest.raises(DutyError, match=r"^application 1: an interval of .* s \(start to "
                                        r"start\) is not allowed; .*lasts at least "
                                        + f"{shortest:.4g}"):
        check_schedule([stop, Dwell(0.999 * shortest, from_start=True)], CAR, mu=0.4,
                       geometry=g)


def test_schedule_line_pressures_are_plausible():
    with pytest.raises(DutyError, match=r"application 0: line_pressure: 200\.0 MPa is "
                                        r"implausible"):
        check_schedule([Drag(200e6, 5.0, omega=40.0)])


def test_a_drive_cycle_names_its_rows(tmp_path):
    """Each application of a drive cycle names its rows (a merged dwell all of them); a
    row beyond 360 km/h or 100 MPa is refused in the file's units."""
    f = tmp_path / "cycle.csv"
    f.write_text("time_s,speed_kmh,line_pressure_MPa\n0,50,2\n10,0,0\n20,0,0\n30,0,0\n"
                 "40,40,0\n50,40,1\n60,40,0\n70,40,0\n")
    apps = read_schedule_csv(f)
    assert [type(a).__name__ for a in apps] == ["Stop", "Dwell", "Drag", "Dwell"]
    assert [a.source for a in apps] == [f"{f}, rows {a}-{b}" for a, b in
                                        ((2, 3), (3, 7), (7, 8), (8, 9))]
    assert apps[1].duration == 40.0
    for bad, words in (("0,400,2", "speed_kmh = '400' is not allowed; need a value from 0 "
                                   "to 360 km/h"),
                       ("0,50,200", "line_pressure_MPa = '200' is not allowed; need a value "
                                    "from 0 to 100 (MPa)")):
        f.write_text(f"time_s,speed_kmh,line_pressure_MPa\n{bad}\n10,0,0\n")
        with pytest.raises(DutyError, match=r"cycle\.csv, row 2: " + words.replace("(", r"\(")
                           .replace(")", r"\)")):
            read_schedule_csv(f)


def test_a_map_that_refuses_look_ups_covers_the_start(tmp_path):
    """A friction map with map_outside = 'error' must cover the sliding speeds of the pad
    face at the scene's omega (and, thermal, the starting temperature); 'clamp' passes."""
    from brakewear.scene import InterfaceSpec
    f = tmp_path / "mu.csv"
    f.write_text("p_MPa,v_km_h,T_C,mu\n" + "".join(
        f"{p},{v},{T},0.4\n" for p in (0.5, 2) for v in (5, 50) for T in (0, 300)))
    g = load_geometry("default")
    fast = 30.0 / g.pad.inner_radius          # 30 m/s at the inner radius: beyond 50 km/h
    slow = 10.0 / 3.6 / g.pad.inner_radius    # 10 to 14.5 km/h over the face
    error = InterfaceSpec(mu_map=str(f), map_outside="error")
    with pytest.raises(SceneError, match=r"interface\.mu_map: .*environment\.omega = .* "
                                         r"rad/s: v = .* km/h is outside the map's range 5 "
                                         r"to 50 km/h"):
        _scene(omega=fast, thermal=ThermalSpec(enabled=True), interface=error)
    with pytest.raises(SceneError, match=r"the starting temperature thermal\.T_initial = "
                                         r"673\.15 K: T = 400 C is outside the map's range 0 "
                                         r"to 300 C"):
        _scene(omega=slow, thermal=ThermalSpec(enabled=True, T_initial=673.15),
               interface=error)
    _scene(omega=slow, thermal=ThermalSpec(enabled=True), interface=error)
    _scene(omega=fast, thermal=ThermalSpec(enabled=True),
           interface=InterfaceSpec(mu_map=str(f), map_outside="clamp"))


def test_resume_differences_are_shown_in_the_files_units(tmp_path):
    """A checkpoint's changed inputs are named by the scene file's keys and shown in its
    units when the file gave them (a Python run: the internal names, in SI)."""
    from brakewear.checks import user_units
    from brakewear.errors import WearError
    from brakewear.wear.state import WearState, check_fingerprint
    ck = tmp_path / "checkpoint.npz"
    WearState.fresh(2, 1).save(ck, {"line_pressure": repr(1e6), "omega": repr(55.0)})
    new = {"line_pressure": repr(1.2e6), "omega": repr(55.0)}
    with pytest.raises(WearError, match=r"line_pressure: 1e\+06 Pa -> 1\.2e\+06 Pa"):
        check_fingerprint(ck, new)
    with user_units({"environment.line_pressure": ("bar", 1e5, 0.0, 12.0)}):
        with pytest.raises(WearError, match=r"environment\.line_pressure: 10 bar -> 12 bar"):
            check_fingerprint(ck, new)


def test_input_errors_of_a_scene_run_name_the_scene_file(tmp_path, monkeypatch):
    """An input error raised while a scene runs (a gap map checked on the pad's nodes)
    names the scene file; a Python scene's does not get a made-up name."""
    import brakewear.output.runs as output
    from brakewear.checks import file_messages
    with pytest.raises(InputError, match=r"^s\.toml: a: b"):
        with file_messages("s.toml", {}):
            raise SceneError("a: b")
    with pytest.raises(InputError, match=r"^a: b"):
        with file_messages("<python>", {}):
            raise SceneError("a: b")
    scene = load_scene("default")
    assert scene.user_units["environment.line_pressure"][:2] == ("MPa", 1e6)

    def boom(*a, **k):
        raise SceneError("interface.gap_file: 3 pad node(s) lie outside the map")
    monkeypatch.setattr(output, "_run_scene", boom)
    with pytest.raises(SceneError, match=r"^brakewear scene 'default': interface\.gap_file"):
        output.run_scene(scene, tmp_path / "o")


def test_a_drive_cycle_that_never_brakes_is_refused(tmp_path, caplog):
    """Braking while the speed rises is taken as no braking, with a warning naming the
    rows; a cycle with no braked interval at all is refused."""
    f = tmp_path / "cycle.csv"
    f.write_text("time_s,speed_kmh,line_pressure_MPa\n0,0,2\n10,50,0\n20,50,0\n")
    with caplog.at_level("WARNING", logger="brakewear.duty.schedule"):
        with pytest.raises(DutyError, match=r"cycle\.csv: no interval brakes"):
            read_schedule_csv(f)
    assert "rows 2-3: line_pressure_MPa = 2 while the speed rises" in caplog.text


def test_thermal_keys_without_heat_are_named(caplog):
    with caplog.at_level("WARNING", logger="brakewear.scene.bounds"):
        _scene(thermal=ThermalSpec(enabled=False))
        assert caplog.text == ""
        _scene(thermal=ThermalSpec(enabled=False, T_max=600.0))
    assert "thermal.T_max is given but thermal.enabled = false" in caplog.text


def test_a_condensed_interface_beyond_the_memory_budget_is_refused_before_meshing(no_meshing):
    """The condensation's dense compliances (16 n^2 bytes for n pad contact nodes, plus the
    factor) are estimated from the geometry like the model's size: the default scene's
    2280 contact nodes need about 2.5 GB, refused under a 2 GB budget, run under 3 GB."""
    from dataclasses import replace

    from brakewear import Numerics
    from brakewear.scene import InterfaceSpec
    s = load_scene("default")
    condensed = InterfaceSpec(model="condensed", mu=0.4)
    with pytest.raises(SceneError, match=r"interface\.model: 'condensed' condenses about 2280 "
                                         r"pad contact nodes .* about 2\.5 GB, beyond the "
                                         r"memory budget you set \(2\.0 GB\)"):
        replace(s, interface=condensed, numerics=Numerics(memory_budget=2.0))
    replace(s, interface=condensed, numerics=Numerics(memory_budget=3.0))


def test_a_different_scene_is_named_in_the_files_units():
    """The first difference between a folder's scene.json (SI) and the scene resumed into it
    is shown under the file's key, in its unit."""
    from brakewear.checks import user_units
    from brakewear.scene.spec import first_difference
    old, new = {"duration": 600.0, "omega": 55.0}, {"duration": 1200.0, "omega": 55.0}
    assert first_difference(old, new) == "environment.duration: 600.0 then, 1200.0 now"
    with user_units({"environment.duration": ("min", 60.0, 0.0, 20.0)}):
        assert first_difference(old, new) == ("environment.duration: 10.0 min then, "
                                               "20.0 min now")
