"""Scene files: the default scene, the same scene built in Python, and every class of
bad input caught -- with the key named -- before anything is meshed."""
import copy
import json
import math
import sys

import numpy as np
import pytest

from brakewear.errors import GeometryError, SceneError
from brakewear.geometry import geometry_file
from brakewear.mesh import pad_mesh, piston_mesh, rotor_mesh
from brakewear.output.runs import run_scene
from brakewear.scene import (
    SURFACES,
    InterfaceSpec,
    OutputSpec,
    Scene,
    ThermalSpec,
    WearSpec,
    available_scenes,
    load_scene,
    scene_file,
    scene_from_dict,
)
from brakewear.wear import Numerics

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def _default_dict() -> dict:
    return tomllib.loads(scene_file("default").read_text())


def _dump(d: dict) -> str:
    """A minimal TOML writer for the scene tables (strings, numbers, booleans, lists)."""
    def val(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return f'"{v}"'
        if isinstance(v, list):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return repr(v)

    lines = []

    def table(name, t):
        scalars = {k: v for k, v in t.items() if not isinstance(v, dict)}
        subs = {k: v for k, v in t.items() if isinstance(v, dict)}
        if scalars or not subs:
            lines.append(f"[{name}]")
            lines.extend(f"{k} = {val(v)}" for k, v in scalars.items())
        for k, v in subs.items():
            table(f"{name}.{k}", v)

    for name, t in d.items():
        table(name, t)
    return "\n".join(lines) + "\n"


def test_default_scene_loads_in_si():
    assert "default" in available_scenes()
    s = load_scene("default")
    assert s.line_pressure == 1e6 and s.omega == 55.0 and s.duration == 3600.0
    assert s.ambient == pytest.approx(293.15)
    assert s.interface.mu == 0.4 and s.interface.model == "auto"
    assert s.numerics.scheme == "implicit" and s.numerics.update == "gap"
    mesh = _default_dict()["mesh"]           # the file's [mesh] (mm), chosen in docs/performance.md
    assert s.mesh_size == pytest.approx(mesh.pop("size") * 1e-3)
    assert s.resolution == pytest.approx({k: v * 1e-3 if k.endswith("_size") else v
                                          for k, v in mesh.items()})
    pad, rot = s.wear_laws()
    assert pad.k == 5e-15 and rot.k == 5e-16   # "material": pad_resin and grey cast iron
    assert s.thermal.enabled is False


def test_python_built_scene_equals_the_file():
    # the example of docs/scenes.md
    py = Scene(
        geometry="default",
        rotor="elastic", piston="traction",
        mesh_size=1.5e-3,                    # m: the pad, and the rotor unless given
        resolution={"rotor_size": 4.5 * 1e-3, "friction_layers": 4,   # m, as 4.5 mm reads
                    "backplate_layers": 8, "rotor_layers": 3},
        line_pressure=1e6, omega=55.0, duration=3600.0, ambient=293.15,
        interface=InterfaceSpec(model="auto", surfaces=("pad.friction", "rotor.friction"), mu=0.4),
        pad_wear=WearSpec(k=None, a=1.0, b=1.0),
        rotor_wear=WearSpec(k=None),
        thermal=ThermalSpec(enabled=False),
        numerics=Numerics(scheme="implicit", update="gap", steps=60),
        output=OutputSpec(vtu_every=50, checkpoint_every=5, figures=True),
        name="default",
    )
    assert py == load_scene("default")
    assert py != Scene(geometry="default", duration=3600.0, mesh_size=1.5e-3,
                       interface=InterfaceSpec(mu=0.3))


def test_same_scene_in_other_units():
    d = _default_dict()
    d["units"].update(pressure="bar", time="min", angular_speed="rpm", temperature="K",
                      length="m")
    d["environment"].update(line_pressure=10.0, duration=60.0,
                            omega=55.0 * 60 / (2 * math.pi), ambient=293.15)
    d["mesh"].update(size=d["mesh"]["size"] * 1e-3, rotor_size=d["mesh"]["rotor_size"] * 1e-3)
    s, ref = scene_from_dict(d), load_scene("default")
    assert s.resolution == pytest.approx(ref.resolution)
    assert s.line_pressure == pytest.approx(ref.line_pressure)
    assert s.duration == pytest.approx(ref.duration)
    assert s.omega == pytest.approx(ref.omega)
    assert s.mesh_size == pytest.approx(ref.mesh_size)


def test_surfaces_are_the_meshes_facet_names():
    from brakewear.geometry import load_geometry
    g = load_geometry("default")
    for body, mesher in (("rotor", rotor_mesh), ("piston", piston_mesh)):
        assert set(SURFACES[body]) == set(mesher(g, size=0.02).boundaries), body
    # the pad names its chamfer and slot faces only where it has them
    every = set(pad_mesh(load_geometry("floating"), size=0.02).boundaries)
    assert set(SURFACES["pad"]) == every
    assert set(pad_mesh(g, size=0.02).boundaries) == every - {"leading_chamfer",
                                                              "trailing_chamfer", "slot"}


def _edit(fn):
    d = _default_dict()
    fn(d)
    return d


BAD = {
    # class of error: (edit of the default scene, key named, words in the message)
    "unknown key": (lambda d: d["environment"].update(speed=55.0), "environment.speed",
                    "allowed keys: line_pressure, omega, duration, ambient"),
    "unknown table": (lambda d: d.update(enviroment={}), "enviroment", "allowed tables"),
    "wrong type": (lambda d: d["environment"].update(line_pressure="1"),
                   "environment.line_pressure", "expected a number"),
    "wrong type bool": (lambda d: d["output"].update(figures=1), "output.figures",
                        "expected true or false"),
    "wrong type int": (lambda d: d["numerics"].update(steps=2.5), "numerics.steps",
                       "whole number"),
    "wrong unit": (lambda d: d["units"].update(pressure="psi"), "units.pressure",
                   "allowed units: 'Pa', 'kPa', 'MPa', 'bar'"),
    "missing unit": (lambda d: d["units"].pop("time"), "units.time", "missing required"),
    "missing body": (lambda d: d["components"].pop("pad"), "components.pad",
                     "missing required body"),
    "missing table": (lambda d: d.pop("environment"), "environment", "missing required table"),
    "missing pad wear": (lambda d: d["wear"].pop("pad"), "wear.pad", "missing required table"),
    "missing surface": (lambda d: d["interface"].update(surfaces=["pad.frction", "rotor.friction"]),
                        "interface.surfaces", "the pad has no surface 'frction'"),
    "surface of no body": (lambda d: d["interface"].update(surfaces=["caliper.friction",
                                                                     "rotor.friction"]),
                           "interface.surfaces", "names no body"),
    "surface of an absent body": (lambda d: d["interface"].update(
        surfaces=["piston.piston_face", "pad.back"]), "interface.surfaces",
        "the piston is not a body"),
    "unsupported pair": (lambda d: d["interface"].update(surfaces=["pad.back", "rotor.friction"]),
                         "interface.surfaces", "sliding interface is pad.friction"),
    "negative mu": (lambda d: d["interface"].update(mu=-0.1), "interface.mu", ">= 0"),
    "zero duration": (lambda d: d["environment"].update(duration=0.0), "environment.duration",
                      "> 0 s"),
    "coarse mesh": (lambda d: d["mesh"].update(size=30.0), "mesh.size",
                    "30.0 mm is not allowed; allowed range (0, 21.5 mm]"),
    "bad choice": (lambda d: d["numerics"].update(scheme="rk4"), "numerics.scheme",
                   "'explicit', 'implicit'"),
    "dp_tol": (lambda d: d["numerics"].update(dp_tol=0.0), "numerics.dp_tol", "> 0"),
    "wear_tol": (lambda d: d["numerics"].update(wear_tol=-0.001), "numerics.wear_tol", "> 0"),
    "partition": (lambda d: d["thermal"].update(partition=1.5), "thermal.partition", "<= 1"),
    "implicit needs a=1": (lambda d: d["wear"]["pad"].update(a=2.0), "wear.pad.a",
                           "scheme = 'explicit'"),
    "k as text": (lambda d: d["wear"]["pad"].update(k="5e-15"), "wear.pad.k", "\"material\""),
    "winkler with geometry update": (lambda d: (d["interface"].update(model="winkler"),
                                                d["numerics"].update(update="geometry")),
                                     "numerics.update", "interface.model = 'fe'"),
    "condensed with geometry update": (lambda d: (d["interface"].update(model="condensed"),
                                                  d["numerics"].update(update="geometry")),
                                       "numerics.update", "interface.model = 'fe'"),
    "unknown interface model": (lambda d: d["interface"].update(model="mortar"),
                                "interface.model", "'fe', 'winkler', 'condensed'"),
    "two geometries": (lambda d: d.update(geometry={}), "scene.geometry", "given twice"),
    "T_max below 0 K": (lambda d: d["thermal"].update(T_max=-300.0), "thermal.T_max",
                        "-300.0 C is not allowed; it must be > -273.15 C"),
    "coning too large": (lambda d: d["interface"].update(coning=-2.5), "interface.coning",
                         "-2.5 mm is not allowed; it must be >= -1 mm"),
    "coning as text": (lambda d: d["interface"].update(pad_taper="30 um"),
                       "interface.pad_taper", "expected a number"),
    "coning per face on the half model": (
        lambda d: d["interface"].update(coning={"inboard": 0.03, "outboard": -0.03}),
        "interface.coning", "a table per face needs both faces: components.layout = 'full'"),
    "coning of an unknown face": (
        lambda d: (d["components"].update(layout="full"),
                   d["interface"].update(coning={"inboard": 0.03, "rim": 0.0})),
        "interface.coning", "unknown key(s) 'rim'; a table per face needs exactly the keys "
                            "inboard, outboard"),
    "coning of one face too large": (
        lambda d: (d["components"].update(layout="full"),
                   d["interface"].update(coning={"inboard": 0.03, "outboard": -2.5})),
        "interface.coning.outboard", "-2.5 mm is not allowed; it must be >= -1 mm"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_bad_scene_names_file_and_key_before_meshing(case, tmp_path, no_meshing):
    edit, key, words = BAD[case]
    path = tmp_path / "bad.toml"
    path.write_text(_dump(_edit(edit)))
    with pytest.raises(SceneError) as e:
        load_scene(path)
    msg = str(e.value)
    assert msg.startswith(f"{path}: {key}:"), msg
    assert words in msg, msg


def test_inline_geometry_errors_name_the_table_and_field(no_meshing):
    d = _default_dict()
    d["scene"].pop("geometry")
    g = tomllib.loads(geometry_file("default").read_text())
    d["geometry"] = copy.deepcopy(g)
    assert scene_from_dict(d).geometry == load_scene("default").geometry
    d["geometry"]["pad"]["inner_radius"] = 50.0
    with pytest.raises(GeometryError, match=r"\[geometry\]: pad.inner_radius: 50 mm"):
        scene_from_dict(d, source="s.toml")


def test_geometry_path_is_relative_to_the_scene_file(tmp_path):
    (tmp_path / "brakes").mkdir()
    (tmp_path / "brakes" / "mine.toml").write_text(geometry_file("default").read_text()
                                                   .replace("size = 2.5", "size = 4.0"))
    d = _default_dict()
    d["scene"]["geometry"] = "brakes/mine.toml"
    (tmp_path / "s.toml").write_text(_dump(d))
    assert load_scene(tmp_path / "s.toml").geometry.mesh.size == pytest.approx(4e-3)
    d["scene"]["geometry"] = "brakes/missing.toml"
    (tmp_path / "s.toml").write_text(_dump(d))
    with pytest.raises(GeometryError, match="missing.toml: cannot read"):
        load_scene(tmp_path / "s.toml")


def test_python_built_bad_values_name_the_key():
    with pytest.raises(SceneError, match=r"interface.mu: -1"):
        InterfaceSpec(mu=-1)
    with pytest.raises(SceneError, match=r"environment.line_pressure: -5"):
        Scene(line_pressure=-5.0)
    with pytest.raises(SceneError, match=r"numerics.update: 'mesh' is not allowed"):
        Numerics(update="mesh")
    with pytest.raises(SceneError, match=r"thermal.h_conv.disc: unknown body"):
        ThermalSpec(h_conv={"disc": 10.0})


def test_unknown_scene_name_lists_the_packaged_ones():
    with pytest.raises(SceneError, match="unknown scene name 'nope'; packaged scenes: .*default"):
        load_scene("nope")


def test_combinations_the_loop_refuses_are_refused_before_meshing(no_meshing, tmp_path):
    s = load_scene("default")
    with pytest.raises(SceneError, match="numerics.update: 'geometry' moves the FE meshes"):
        Scene(geometry=s.geometry, interface=InterfaceSpec(model="winkler"),
              numerics=Numerics(update="geometry"))


def test_thermal_with_the_foundation_interface_is_refused_before_meshing(no_meshing,
                                                                        tmp_path, capsys):
    """The foundation (Winkler) interface takes no thermal-strain load: a scene asking
    for both is refused naming both keys, from Python and from the command line (exit
    2, nothing meshed or written)."""
    from brakewear.cli import main
    s = load_scene("default")
    with pytest.raises(SceneError) as e:
        Scene(geometry=s.geometry, interface=InterfaceSpec(model="winkler"),
              thermal=ThermalSpec(enabled=True))
    msg = str(e.value)
    assert msg.startswith("thermal.enabled: true needs interface.model = 'fe' or "
                          "'condensed'"), msg
    assert "thermal-strain load" in msg
    path = tmp_path / "hot_winkler.toml"
    path.write_text(_dump(_edit(lambda d: (d["interface"].update(model="winkler"),
                                           d["thermal"].update(enabled=True)))))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert f"{path}: thermal.enabled: true needs interface.model = 'fe'" in err, err
    assert not out.exists()


def test_thermal_and_winkler_scenes_run(tmp_path):
    s = load_scene("default")
    small = dict(geometry=s.geometry, mesh_size=1.2e-2, duration=20.0,
                 numerics=Numerics(steps=2, scheme="implicit"))
    small["output"] = OutputSpec(figures=False)
    a = run_scene(
        Scene(**small, thermal=ThermalSpec(enabled=True, contact_conductance=1e5)), tmp_path / "t"
    )
    assert a["steps"] == 2 and a["final"]["pressure_max_Pa"] > 0
    b = run_scene(Scene(**small, interface=InterfaceSpec(model="winkler")), tmp_path / "w")
    assert b["steps"] == 2
    # the condensed interface: the FE run's answer, thermal load included
    fe = run_scene(Scene(**small, thermal=ThermalSpec(enabled=True, contact_conductance=1e5),
                         interface=InterfaceSpec(mu=0.4)), tmp_path / "fe")
    c = run_scene(Scene(**small, thermal=ThermalSpec(enabled=True, contact_conductance=1e5),
                        interface=InterfaceSpec(model="condensed", mu=0.4)), tmp_path / "c")
    assert c["scene"]["interface"] == "condensed"
    assert c["final"]["pressure_max_Pa"] == pytest.approx(fe["final"]["pressure_max_Pa"],
                                                          rel=1e-6)


def test_wear_tol_is_a_length_passed_to_the_loop(tmp_path, monkeypatch):
    """numerics.wear_tol is in the file's length unit (mm in the default scene) and
    reaches wear_history in metres; absent, the loop gets None (dp_tol control)."""
    d = _default_dict()
    d["numerics"]["wear_tol"] = 0.002                       # mm
    s = scene_from_dict(d)
    assert s.numerics.wear_tol == pytest.approx(2e-6)
    assert load_scene("default").numerics.wear_tol is None
    import brakewear.output.runs as history
    seen = {}

    def fake_run_wear(run, *args, **kw):
        seen.update(run=run, **kw)
        raise RuntimeError("stop")
    monkeypatch.setattr(history, "run_wear", fake_run_wear)
    small = Scene(geometry=s.geometry, mesh_size=1.2e-2, duration=20.0,
                  numerics=Numerics(wear_tol=2e-6), output=OutputSpec(figures=False))
    with pytest.raises(RuntimeError, match="stop"):
        run_scene(small, tmp_path / "w")
    assert seen["run"].numerics.wear_tol == 2e-6


def test_coning_and_taper_give_the_loops_initial_gap(tmp_path, monkeypatch):
    """interface.coning and interface.pad_taper are signed lengths in the file's unit;
    they add into one gap, linear in radius across the pad, that reaches the wear
    loop as its initial_gap (zero at the touching edge)."""
    from brakewear.cleaning.corrosion import coning_gap
    d = _default_dict()
    d["interface"].update(coning=0.030, pad_taper=-0.010)          # mm
    s = scene_from_dict(d)
    assert (s.interface.coning, s.interface.pad_taper) == pytest.approx((30e-6, -10e-6))
    assert load_scene("default").initial_gap(np.zeros((3, 1))) is None
    pad = s.geometry.pad
    r = np.linspace(pad.inner_radius, pad.outer_radius, 5)
    x = np.vstack([r, np.zeros(5), np.zeros(5)])
    assert s.initial_gap(x) == pytest.approx(np.linspace(0.0, 20e-6, 5), abs=1e-18)
    # a coned rotor's outboard face (z = -thickness) opens the other way; the pad
    # taper opens the same way on both pads
    x_out = x.copy()
    x_out[2] = -s.geometry.rotor.thickness
    assert s.initial_gap(np.hstack([x, x_out]))[5:] == pytest.approx(
        np.linspace(40e-6, 0.0, 5), rel=1e-12)
    d["components"].update(layout="full")
    d["interface"].update(coning={"inboard": 0.030, "outboard": 0.010})
    full = scene_from_dict(d)
    assert full.interface.face_coning() == pytest.approx({"inboard": 30e-6, "outboard": 10e-6})
    gap = full.initial_gap(np.hstack([x, x_out]))
    assert gap[:5] == pytest.approx(np.linspace(0.0, 20e-6, 5), rel=1e-12)
    assert np.abs(gap[5:]).max() <= 1e-12 * 30e-6        # 10 um coning less 10 um taper
    import brakewear.output.runs as history
    seen = {}

    def fake_run_wear(run, *args, **kw):
        seen.update(run=run, **kw)
        raise RuntimeError("stop")
    monkeypatch.setattr(history, "run_wear", fake_run_wear)
    small = Scene(geometry=s.geometry, mesh_size=1.2e-2, duration=20.0, interface=s.interface,
                  output=OutputSpec(figures=False))
    with pytest.raises(RuntimeError, match="stop"):
        run_scene(small, tmp_path / "w")
    itf, gap = seen["run"].interface, seen["run"].initial_gap
    assert gap == pytest.approx(
        coning_gap(itf.r, pad.inner_radius, pad.outer_radius, 20e-6), abs=1e-18)
    assert gap.max() == pytest.approx(20e-6 * (itf.r.max() - pad.inner_radius)
                                                      / (pad.outer_radius - pad.inner_radius))


def test_a_face_beyond_T_max_ends_the_run_with_its_figures(tmp_path):
    """thermal.T_max (in the file's temperature unit) bounds the face temperatures:
    a run whose pad face passes it fails with TemperatureLimitError naming the face,
    the step and the bound.  With the default bound (900 C) a heat partition without
    contact conductance (the pad face keeps its share of the heat) is refused with
    a message naming the key to change, and the default (a contact conductance of
    1e5 W/m^2 K with the meshed rotor) runs."""
    from brakewear.errors import TemperatureLimitError
    d = _default_dict()
    d["thermal"].update(enabled=True, T_max=25.0)              # C in the default scene
    assert scene_from_dict(d).thermal.T_max == pytest.approx(298.15)
    s = load_scene("default")
    small = dict(geometry=s.geometry, mesh_size=1.2e-2, duration=20.0,
                 numerics=Numerics(steps=2), output=OutputSpec(figures=False),
                 interface=InterfaceSpec(mu=0.4))
    with pytest.raises(TemperatureLimitError, match=r"step 1 \(t = 10 s\): the pad face "
                                                    r"reached \d+ C, beyond the plausibility "
                                                    r"bound T_max = 25 C") as e:
        run_scene(Scene(**small, thermal=ThermalSpec(enabled=True, T_max=298.15)),
                  tmp_path / "hot")
    assert e.value.temperature > e.value.T_max == pytest.approx(298.15)
    assert e.value.exit_code == 3
    with pytest.raises(TemperatureLimitError, match=r"the pad face reached \d+ C, beyond .* "
                                                    r"T_max = 900 C .*contact_conductance 0.*"
                                                    r"give thermal.contact_conductance > 0"):
        run_scene(Scene(**small, thermal=ThermalSpec(enabled=True, partition="effusivity",
                                                     contact_conductance=0.0)),
                  tmp_path / "fixed")
    ok = run_scene(Scene(**small, thermal=ThermalSpec(enabled=True)), tmp_path / "ok")
    assert ok["steps"] == 2
    # the temperatures are in the history, the summary and both VTU series
    import csv

    import meshio
    rows = list(csv.DictReader(open(tmp_path / "ok" / "history.csv")))
    hot = [float(r["pad_T_max_C"]) for r in rows]
    assert 20.0 < hot[0] < hot[1] < 900.0
    assert all(float(r["heat_balance_error"]) < 1e-8 for r in rows)
    for r in rows:      # the history's heat figures: means below maxima, heat in and out
        assert float(r["pad_T_mean_C"]) <= float(r["pad_T_max_C"])
        assert float(r["rotor_T_mean_C"]) <= float(r["rotor_T_max_C"])
        assert float(r["heat_pad_W"]) > 0 and float(r["heat_rotor_W"]) > 0
        assert float(r["convected_rotor_W"]) > 0
        # net heat: the contact exchange leaves one body and enters the other, so the
        # two sum to the friction power of the step (torque x speed, 55 rad/s)
        assert float(r["heat_pad_W"]) + float(r["heat_rotor_W"]) == pytest.approx(
            float(r["torque_Nm"]) * 55.0, rel=1e-9)
    th = ok["thermal"]
    assert th["settings"]["contact_conductance"] == 1e5
    assert th["final"]["pad_T_max_C"] == pytest.approx(hot[1], rel=1e-12)
    assert th["final"]["heat_balance"]["relative_error"] < 1e-8
    for body in ("pad", "rotor"):
        last = sorted((tmp_path / "ok").glob(f"{body}*.vtu"))[-1]
        T = meshio.read(last).point_data["temperature_C"]
        # the consistent capacity matrix undershoots the ambient slightly ahead of a
        # heat front on a coarse mesh (0.7 % of the rise here; "lumped" does not)
        assert T.max() > 20.0 and T.min() >= 20.0 - 0.02 * (T.max() - 20.0)


# --- a scene whose run is a schedule of a vehicle's stops ------------------------------

def _stops_scene(tmp_path, **edits):
    d = _default_dict()
    for k in ("line_pressure", "omega", "duration"):
        d["environment"].pop(k)
    d["components"]["rotor"] = "rigid"
    d["mesh"]["size"] = 12.0                                            # mm
    d["vehicle"] = {"mass": 1800.0, "front_share": 0.7, "tyre_radius": 320.0}   # mm
    d["schedule"] = {"stops": 2, "speed_from": 50.0, "deceleration": 1.5, "interval": 60.0}
    for table, values in edits.items():
        if values is None:
            d.pop(table)
        else:
            d.setdefault(table, {}).update(values)
    path = tmp_path / "stops.toml"
    path.write_text(_dump(d))
    return path


def test_a_schedule_scene_runs_the_vehicles_stops(tmp_path):
    """[vehicle] and [schedule] in a scene: `brakewear run` runs the stops (stop, dwell,
    stop), writes one row per application and the pad after each stop; every stop
    asks 0.5 m v^2 x 0.7 / 2 brakes / 2 faces of each face, and the model's friction
    work matches it to the torque drift of a held line pressure (< 3 %)."""
    import csv

    from brakewear.cli import main
    path = _stops_scene(tmp_path)
    s = load_scene(path)
    assert s.vehicle.tyre_radius == pytest.approx(0.32) and len(s.schedule) == 3
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    rows = list(csv.DictReader(open(out / "applications.csv")))
    assert [r["kind"] for r in rows] == ["stop", "dwell", "stop"]
    demand = 0.5 * 1800.0 * (50 / 3.6) ** 2 * 0.7 / 2 / 2
    for r in (rows[0], rows[2]):
        assert float(r["target_face_J"]) == pytest.approx(demand, rel=1e-12)
        assert float(r["friction_face_J"]) == pytest.approx(demand, rel=0.03)
    assert float(rows[2]["t_start"]) == pytest.approx(60.0)
    summ = json.loads((out / "summary.json").read_text())
    assert summ["braked_applications"] == 2
    assert summ["energy"]["demanded_per_face_J"] == pytest.approx(2 * demand, rel=1e-12)
    assert len(list(out.glob("pad_*.vtu"))) == 2
    assert json.loads((out / "scene.json").read_text())["schedule"][0]["kind"] == "stop"
    with pytest.raises(SceneError, match=r"--resume: a scene with a \[schedule\]"):
        run_scene(s, out, resume=True)
    # the same stops on the condensed interface: the same applications
    (tmp_path / "c").mkdir()
    cpath = _stops_scene(tmp_path / "c", interface={"model": "condensed"})
    assert main(["run", str(cpath), "--out", str(tmp_path / "c" / "run"), "--quiet"]) == 0
    crows = list(csv.DictReader(open(tmp_path / "c" / "run" / "applications.csv")))
    assert [r["kind"] for r in crows] == ["stop", "dwell", "stop"]
    for a, b in zip((rows[0], rows[2]), (crows[0], crows[2])):
        for key in ("line_pressure", "friction_face_J", "pad_volume_m3"):
            assert float(b[key]) == pytest.approx(float(a[key]), rel=1e-6), key


def test_a_thermal_schedule_writes_temperatures_per_application(tmp_path):
    """A thermal schedule (stop, dwell, stop; elastic rotor) writes what a thermal drag
    writes: temperature_C in the pad and rotor VTUs after every application (the dwell
    too, without contact), per application the face temperatures at its end and their
    peaks, the net heat into each body (summing to the friction work of a stop, to zero
    in a dwell), the convected heat and the balance error, and the summary's thermal
    settings and final state."""
    import csv

    import meshio

    from brakewear.cli import main
    path = _stops_scene(tmp_path, components={"rotor": "elastic"}, thermal={"enabled": True},
                        numerics={"steps": 3}, schedule={"interval": 40.0})
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    rows = list(csv.DictReader(open(out / "applications.csv")))
    assert [r["kind"] for r in rows] == ["stop", "dwell", "stop"]
    # the energy, pressure, wear and temperature per application, as a figure
    assert json.loads((out / "summary.json").read_text())["files"]["figure"].endswith(
        "applications.png") and (out / "applications.png").stat().st_size > 0
    f = [{k: float(v) for k, v in r.items()
          if "_T_" in k or k.startswith(("heat_", "convected_"))} for r in rows]
    for r in f:
        for b in ("pad", "rotor"):
            for which in ("max", "mean"):
                assert r[f"{b}_T_{which}_peak_C"] >= r[f"{b}_T_{which}_C"]
            assert r[f"{b}_T_max_C"] >= r[f"{b}_T_mean_C"] > 20.0     # ambient 20 C
            assert r[f"convected_{b}_J"] > 0
        assert r["heat_balance_error"] < 1e-8
    stop1, dwell, stop2 = f
    # a stop: friction heat into the bodies (at each step's start pressure; the friction
    # work takes its end pressure, within the held line pressure's drift, < 3 %)
    for r, row in ((stop1, rows[0]), (stop2, rows[2])):
        assert r["heat_pad_J"] > 0 and r["heat_rotor_J"] > 0
        assert r["heat_pad_J"] + r["heat_rotor_J"] == pytest.approx(
            float(row["friction_face_J"]), rel=0.03)
    # the dwell: no friction, the pad and rotor only exchange heat and cool
    assert abs(dwell["heat_pad_J"] + dwell["heat_rotor_J"]) <= 1e-9 * abs(dwell["heat_rotor_J"])
    assert dwell["pad_T_max_C"] < dwell["pad_T_max_peak_C"] <= stop1["pad_T_max_C"]
    assert stop2["pad_T_max_C"] > stop1["pad_T_max_C"] > dwell["pad_T_max_C"]
    assert float(rows[0]["pad_temperature_max"]) - 273.15 == pytest.approx(
        stop1["pad_T_max_C"], rel=1e-12)
    # VTU series: one frame per application, temperatures on both bodies
    for b, fields in (("pad", {"pressure", "pad_wear", "active", "temperature_C"}),
                      ("rotor", {"rotor_wear", "temperature_C"})):
        frames = sorted(out.glob(f"{b}_*.vtu"))
        assert len(frames) == 3
        for frame, r in zip(frames, f):
            m = meshio.read(frame)
            assert set(m.point_data) == fields
            T = m.point_data["temperature_C"]
            # the face is part of the body; the rise above ambient sets the tolerance
            assert T.max() >= r[f"{b}_T_max_C"] - 1e-12 * (r[f"{b}_T_max_C"] - 20.0)
    assert meshio.read(out / "pad_00002.vtu").point_data["pressure"].max() == 0.0
    summ = json.loads((out / "summary.json").read_text())
    th = summ["thermal"]
    assert th["settings"]["contact_conductance"] == 1e5 and summ["files"]["rotor"] == "rotor.pvd"
    assert th["final"]["pad_T_max_C"] == pytest.approx(stop2["pad_T_max_C"], rel=1e-12)
    assert th["final"]["rotor_T_max_C"] == pytest.approx(stop2["rotor_T_max_C"], rel=1e-12)
    assert th["final"]["heat_balance"]["relative_error"] < 1e-8


@pytest.mark.parametrize("edits,key,words", [
    ({"vehicle": None}, "vehicle", "the [schedule]'s stops need a [vehicle]"),
    ({"environment": {"duration": 10.0}}, "environment.duration", "set by the [schedule]"),
    ({"schedule": {"deceleration": 15.0}}, "schedule.deceleration = 15.0 m/s^2",
     "what the tyres can give"),
    ({"vehicle": {"mass": -5.0}}, "vehicle.mass", "it must be >= 50 kg"),
    ({"schedule": {"speed_form": 50.0}}, "schedule.speed_form", "unknown key"),
    ({"numerics": {"update": "geometry"}}, "numerics.update", "gap-offset"),
])
def test_bad_schedule_scenes_name_the_key_before_meshing(tmp_path, no_meshing, edits, key,
                                                         words):
    from brakewear.errors import InputError
    path = _stops_scene(tmp_path, **edits)
    with pytest.raises(InputError) as e:
        load_scene(path)
    msg = str(e.value)
    assert str(path) in msg and key in msg and words in msg, msg


def test_a_gap_map_from_a_csv_is_interpolated_onto_the_pad(tmp_path):
    """interface.gap_file (relative to the scene file): a map linear in radius gives
    the coning's gap; a map that does not cover the pad, or a bad row, is refused
    naming the key, the file and the row."""
    from brakewear.cleaning.corrosion import coning_gap, map_gap, read_gap_map
    from brakewear.errors import InputError
    pad = load_scene("default").geometry.pad
    r_in, r_out = pad.inner_radius * 1e3, pad.outer_radius * 1e3
    lines = ["r_mm,theta_deg,gap_um"]
    for r in np.linspace(r_in - 1, r_out + 1, 7):
        for th in (-40.0, 0.0, 40.0):
            lines.append(f"{r},{th},{30.0 * (r - r_in) / (r_out - r_in)}")
    (tmp_path / "gap.csv").write_text("\n".join(lines) + "\n")
    d = _default_dict()
    d["interface"]["gap_file"] = "gap.csv"
    path = tmp_path / "s.toml"
    path.write_text(_dump(d))
    s = load_scene(path)
    assert s.interface.gap_file == str(tmp_path / "gap.csv")
    rng = np.random.default_rng(0)
    rr = rng.uniform(pad.inner_radius, pad.outer_radius, 40)
    th = rng.uniform(-0.4, 0.4, 40)
    x = np.vstack([rr * np.cos(th), rr * np.sin(th), np.zeros(40)])
    ref = coning_gap(rr, pad.inner_radius, pad.outer_radius, 30e-6)
    assert s.initial_gap(x) == pytest.approx(ref - ref.min(), abs=1e-12)
    # the pad sticks out of a map that stops at 0 deg
    pts = read_gap_map(tmp_path / "gap.csv")
    with pytest.raises(InputError, match="outside the map, e.g. r = .* mm, theta = "):
        map_gap(pts[pts[:, 1] <= 0.0], x)
    (tmp_path / "bad.csv").write_text("r_mm,theta_deg,gap_um\n100,0,1\n110,x,2\n")
    d["interface"]["gap_file"] = "bad.csv"
    path.write_text(_dump(d))
    with pytest.raises(SceneError, match=r"interface.gap_file: .*bad.csv, row 3: not a number"):
        load_scene(path)
