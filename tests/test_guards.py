"""Guard rails: model size, wear limits, meshes in and out, messages in the user's units."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from brakewear.cli import main
from brakewear.errors import GeometryError, MeshFileError, SceneError, WornThroughError
from brakewear.geometry import load_geometry
from brakewear.geometry.parts import MESH_BODY_KEYS
from brakewear.mesh import read_mesh, write_mesh
from brakewear.mesh.brake import pad_mesh
from brakewear.mesh.estimate import MEMORY_ENV, check_model_size, estimate_model
from brakewear.scene import load_scene, scene_file
from brakewear.static import solve_tied
from brakewear.wear import Run

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).parents[1]


def _scene_text(**edits) -> str:
    """The default scene file, without its per-body mesh keys (so that ``mesh.size``
    sets the whole mesh), with ``key = value`` lines replaced or added per table.

    ``edits``: ``{"mesh": {"size": "0.01"}}`` style, values as TOML text.
    """
    lines = [line for line in scene_file("default").read_text().splitlines()
             if line.split("=")[0].strip() not in MESH_BODY_KEYS]
    out, table = [], None
    pending = {t: dict(kv) for t, kv in edits.items()}
    for line in lines:
        s = line.strip()
        if s.startswith("[") and s.endswith("]"):
            if table in pending:
                out += [f"{k} = {v}" for k, v in pending.pop(table).items()]
            table = s[1:-1]
        elif table in pending and "=" in s and not s.startswith("#"):
            key = s.split("=")[0].strip()
            if key in pending[table]:
                out.append(f"{key} = {pending[table].pop(key)}")
                continue
        out.append(line)
    if table in pending:
        out += [f"{k} = {v}" for k, v in pending.pop(table).items()]
    for t, kv in pending.items():
        out += [f"[{t}]"] + [f"{k} = {v}" for k, v in kv.items()]
    return "\n".join(out) + "\n"


def _write_scene(tmp_path, name="s.toml", **edits) -> Path:
    p = tmp_path / name
    p.write_text(_scene_text(**edits))
    return p


# ---------------------------------------------------------------- model size --

@pytest.mark.parametrize("size_mm, piston", [(12.0, "traction"), (6.0, "body"), (4.0, "traction")])
def test_size_estimate_matches_real_meshes(size_mm, piston):
    from brakewear.model import BrakeModel
    geom = load_geometry("default")
    est = estimate_model(geom, size_mm * 1e-3, piston=piston)
    model = BrakeModel(geom, piston=piston, size=size_mm * 1e-3)
    ratio = est.dofs / model.dofs
    assert 1 / 1.5 < ratio < 1.5, f"estimate {est.dofs} vs {model.dofs} DOFs"
    for b in model.bodies:
        n = model.meshes[b].nelements
        assert 1 / 1.5 < est.elements[b] / n < 1.5, f"{b}: {est.elements[b]} vs {n} elements"


def test_absurd_size_is_refused_at_once_and_nothing_is_written(tmp_path):
    scene = _write_scene(tmp_path, mesh={"size": "0.01"})
    out = tmp_path / "out"
    t0 = time.perf_counter()
    assert main(["run", str(scene), "--out", str(out), "--quiet"]) == 2
    assert time.perf_counter() - t0 < 1.0
    assert not out.exists(), "nothing may be written before the input is valid"
    with pytest.raises(SceneError) as e:
        load_scene(scene)
    msg = str(e.value)
    for words in (str(scene), "mesh.size: 0.01 mm", "DOFs", "GB", "numerics.memory_budget",
                  "smallest size that fits is"):
        assert words in msg, msg


def test_demo_size_has_the_bounds_of_scene_files(tmp_path, capsys):
    out = tmp_path / "demo"
    for size, words in (("100", "--size: 100 mm is not allowed; allowed range (0, 21.5 mm]"),
                        ("0.01", "--size: 0.01 mm is too fine")):
        assert main(["demo", "--size", size, "--out", str(out), "--wear-duration", "0"]) == 2
        assert words in capsys.readouterr().err
    assert not out.exists()


def test_memory_budget_from_the_scene_and_the_environment(tmp_path, monkeypatch):
    geom = load_geometry("default")
    need = estimate_model(geom, 4e-3).memory / 1e9
    scene = _write_scene(tmp_path, mesh={"size": "4.0"},
                         numerics={"memory_budget": repr(0.5 * need)})
    with pytest.raises(SceneError, match=r"mesh.size: 4.0 mm is too fine.*the memory budget you "
                                         r"set.*smallest size that fits is \d"):
        load_scene(scene)
    # the size it proposes fits that budget, and a size just below it does not
    msg = str(pytest.raises(SceneError, load_scene, scene).value)
    fits = float(msg.rsplit("fits is ", 1)[1].split(" mm")[0]) * 1e-3
    assert estimate_model(geom, fits).memory <= 0.5 * need * 1e9
    assert estimate_model(geom, 0.95 * fits).memory > 0.5 * need * 1e9
    monkeypatch.setenv(MEMORY_ENV, repr(0.5 * need))
    with pytest.raises(SceneError, match=MEMORY_ENV):
        check_model_size(geom, 4e-3)
    monkeypatch.setenv(MEMORY_ENV, repr(2 * need))
    assert check_model_size(geom, 4e-3).dofs > 0
    monkeypatch.setenv(MEMORY_ENV, "lots")
    with pytest.raises(SceneError, match=f"{MEMORY_ENV}='lots'"):
        check_model_size(geom, 4e-3)


def test_brake_model_refuses_before_meshing(monkeypatch):
    import brakewear.model as model_mod
    from brakewear.model import BrakeModel

    def boom(*a, **k):
        raise AssertionError("meshed before the size was checked")
    monkeypatch.setitem(model_mod._MESHERS, "pad", boom)
    monkeypatch.setitem(model_mod._MESHERS, "rotor", boom)
    with pytest.raises(SceneError, match=r"size: 1e-05 m is too fine"):
        BrakeModel("default", size=1e-5)
    with pytest.raises(SceneError, match=r"size: 0.1 m is not allowed; allowed range \(0, "
                                         r"0.0215 m\]"):
        BrakeModel("default", size=0.1)


# ---------------------------------------------------------------- wear limits --

def _worn_scene(tmp_path, update: str, name: str) -> Path:
    """2 h of drag at 5 MPa on a coarse mesh (within its wear-through horizon, 2 h); a
    small pad limit ends it early."""
    return _write_scene(tmp_path, name=name, mesh={"size": "12.0"},
                        environment={"line_pressure": "5.0", "duration": "7200.0"},
                        numerics={"update": f'"{update}"'},
                        output={"figures": "false"},
                        **{"wear.pad": {"limit": "0.5"}})


@pytest.mark.parametrize("update", ["gap", "geometry"])
def test_pad_worn_through_ends_the_run_with_exit_code_4(tmp_path, capsys, update):
    scene = _worn_scene(tmp_path, update, f"{update}.toml")
    out = tmp_path / update
    assert main(["run", str(scene), "--out", str(out), "--quiet"]) == 4
    err = capsys.readouterr().err
    assert "pad worn through" in err and "r = " in err and "theta = " in err, err
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "worn_through"
    w = s["worn_through"]
    assert w["body"] == "pad" and w["limit_m"] == pytest.approx(0.5e-3, rel=1e-12)
    # the step that crossed the limit went past it by less than one step's wear, and
    # the time it was reached lies within that step
    assert w["limit_m"] <= w["depth_m"] < 2 * w["limit_m"]
    last = s["final"]
    assert last["time_s"] - last["dt_s"] <= w["time_s"] <= last["time_s"]
    assert last["pad_wear_max_m"] == pytest.approx(w["depth_m"], rel=1e-9)
    r_pad = load_geometry("default").pad
    eps = 1e-9 * r_pad.outer_radius                     # round-off of the node positions
    assert r_pad.inner_radius - eps <= w["r_m"] <= r_pad.outer_radius + eps
    assert (out / "history.csv").exists() and (out / "pad.pvd").exists()


def test_rotor_limit_through_wear_history():
    import brakewear as bw
    model = bw.BrakeModel("default", size=12e-3)
    limits = bw.WearLimits(pad=None, rotor=2e-7)
    law = bw.WearLaw(5e-15)
    with pytest.raises(WornThroughError) as e:
        for _ in bw.wear_history(
            Run(
                model,
                1e6,
                55.0,
                3600.0,
                law,
                bw.WearLaw(5e-14),
                mu=0.4,
                limits=limits,
                numerics=bw.Numerics(scheme="implicit"),
            )
        ):
            pass
    assert e.value.body == "rotor" and e.value.depth >= 2e-7
    assert "rotor worn to its limit" in str(e.value) and "wear.rotor.limit" in str(e.value)
    assert e.value.exit_code == 4


def test_default_limits_are_the_friction_layer_and_the_rotor_limit():
    from brakewear.model import BrakeModel
    from brakewear.wear.limits import GEOMETRY_MARGIN, ROTOR_LIMIT, WearLimits
    model = BrakeModel("default", size=12e-3)
    tf = model.geometry.pad.friction_thickness
    lim = WearLimits.for_model(model)
    assert lim.pad == tf and lim.rotor == ROTOR_LIMIT
    assert WearLimits.for_model(model, update="geometry").pad == pytest.approx(
        (1 - GEOMETRY_MARGIN) * tf, rel=1e-12)
    with pytest.raises(bw_errors().WearError, match="pad wear limit = -1"):
        WearLimits(pad=-1.0, rotor=None)


def bw_errors():
    import brakewear.errors as e
    return e


# --------------------------------------------------------------- plausibility --

@pytest.mark.parametrize("edits, words", [
    ({"interface": {"mu": "50.0"}}, "interface.mu: 50.0 is implausible"),
    ({"environment": {"line_pressure": "1e6"}},
     "environment.line_pressure: 1000000.0 MPa is implausible; brake line pressures stay "
     "below 25 MPa (250 bar); allowed: at most 100 MPa"),
    ({"environment": {"omega": "1e5"}}, "environment.omega: 100000.0 rad/s is implausible"),
    ({"environment": {"ambient": "900.0"}}, "environment.ambient: 900.0 C is implausible"),
])
def test_implausible_inputs_are_refused_naming_key_and_bound(tmp_path, edits, words):
    with pytest.raises(SceneError) as e:
        load_scene(_write_scene(tmp_path, **edits))
    assert words in str(e.value), str(e.value)
    assert "allowed" in str(e.value)


def test_unusual_inputs_are_logged_as_warnings(tmp_path, caplog):
    load_scene(_write_scene(tmp_path, interface={"mu": "1.2"}))
    assert any("interface.mu = 1.2 is unusual" in r.getMessage() for r in caplog.records)


# ----------------------------------------------------------- messages, units --

@pytest.mark.parametrize("edits, words", [
    ({"environment": {"ambient": "-300.0"}},
     "environment.ambient: -300.0 C is not allowed; it must be > -273.15 C"),
    ({"mesh": {"size": "1000.0"}}, "mesh.size: 1000.0 mm is not allowed; allowed range (0, "
                                   "21.5 mm]"),
    ({"wear.pad": {"T_threshold": "-280.0"}}, "wear.pad.T_threshold: -280.0 C"),
])
def test_messages_speak_the_users_units(tmp_path, edits, words):
    with pytest.raises(SceneError) as e:
        load_scene(_write_scene(tmp_path, **edits))
    assert words in str(e.value), str(e.value)


def test_unknown_geometry_name_names_scene_file_and_key(tmp_path):
    scene = _write_scene(tmp_path, scene={"geometry": '"no_such_brake"'})
    with pytest.raises(GeometryError) as e:
        load_scene(scene)
    msg = str(e.value)
    assert msg.startswith(f"{scene}: scene.geometry = 'no_such_brake'"), msg
    assert "unknown geometry name" in msg


def test_material_without_wear_names_file_and_key(tmp_path):
    from brakewear.geometry import geometry_file
    g = geometry_file("default").read_text()
    d = tomllib.loads(g)
    friction = d["pad"]["friction_material"]
    assert friction == "pad_resin"
    g += ('\n[materials.dustless]\ntype = "transversely_isotropic"\nbase = "pad_resin"\n'
          "E_p = 8.0\nE_t = 3.0\nnu_p = 0.25\nnu_tp = 0.2\nG_t = 1.5\nwear_k = 0.0\n")
    g = g.replace(f'friction_material = "{friction}"', 'friction_material = "dustless"')
    (tmp_path / "g.toml").write_text(g)
    scene = _write_scene(tmp_path, scene={"geometry": '"g.toml"'})
    with pytest.raises(SceneError) as e:
        load_scene(scene)
    msg = str(e.value)
    assert msg.startswith(f"{scene}: wear.pad.k:"), msg
    assert "'dustless'" in msg and "wear_k = 0.0" in msg and str(tmp_path / "g.toml") in msg


def test_a_byte_order_mark_is_accepted(tmp_path):
    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + scene_file("default").read_bytes())
    assert load_scene(p).name == "default"


def test_out_naming_a_file_is_refused_clearly(tmp_path, capsys):
    f = tmp_path / "taken"
    f.write_text("mine")
    assert main(["run", "default", "--out", str(f), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert f"--out = '{f}' is an existing file, not a folder" in err and "Errno" not in err
    assert f.read_text() == "mine"


def test_version_and_python_m():
    import brakewear
    for cmd in ([sys.executable, "-m", "brakewear", "--version"],):
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=60, cwd=ROOT)
        assert r.returncode == 0, r.stderr
        assert r.stdout.strip() == f"brakewear {brakewear.__version__}"
    r = subprocess.run([sys.executable, "-m", "brakewear", "run", "no_such_scene"],
                       capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert r.returncode == 2 and "unknown scene name 'no_such_scene'" in r.stderr


def test_offscreen_figures_keep_vtk_warnings_off_the_terminal(tmp_path):
    pytest.importorskip("pyvista")
    code = (
        "from brakewear.output.figures import plot_named_surfaces\n"
        "from brakewear.geometry import load_geometry\n"
        "from brakewear.mesh import brake_meshes\n"
        f"plot_named_surfaces(brake_meshes(load_geometry(), size=12e-3), r'{tmp_path}/s.png')\n"
    )
    env = dict(os.environ, DISPLAY=":99")           # a display that is not there
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=120, cwd=ROOT, env=env)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "s.png").stat().st_size > 20_000
    assert "X server" not in r.stderr and "WARN" not in r.stderr, r.stderr


# ------------------------------------------------------------ meshes in, out --

@pytest.fixture(scope="module")
def coarse_pad():
    return pad_mesh(load_geometry("default"), 8e-3)


def _facet_coordinates(mesh, name):
    """The named facets as sorted rows of sorted vertex coordinates (numbering-free)."""
    f = mesh.facets[:, mesh.boundaries[name]]
    xyz = np.sort(mesh.p[:, f].transpose(2, 1, 0).reshape(f.shape[1], -1), axis=1)
    return xyz[np.lexsort(xyz.T[::-1])]


@pytest.mark.parametrize("suffix", [".msh", ".vtu", ".vtk"])
def test_mesh_round_trip_keeps_named_surfaces_and_volumes(tmp_path, coarse_pad, suffix):
    m = coarse_pad
    path = write_mesh(tmp_path / f"pad{suffix}", m, point_data={"z": m.p[2]})
    if suffix == ".msh":
        assert path.read_bytes().startswith(b"$MeshFormat\n2.2"), "not a gmsh 2.2 file"
    back = read_mesh(path)
    assert back.nvertices == m.nvertices and back.nelements == m.nelements
    assert sorted(back.boundaries) == sorted(m.boundaries)
    assert sorted(back.subdomains) == sorted(m.subdomains)
    scale = np.abs(m.p).max()
    for name in m.boundaries:
        a, b = _facet_coordinates(m, name), _facet_coordinates(back, name)
        assert a.shape == b.shape, name
        assert np.abs(a - b).max() <= 1e-12 * scale, name
    for name in m.subdomains:
        assert len(back.subdomains[name]) == len(m.subdomains[name]), name


def test_hdf5_formats_need_h5py_and_say_so(tmp_path, coarse_pad):
    try:
        import h5py  # noqa: F401
        pytest.skip("h5py is installed: .xdmf works")
    except ImportError:
        pass
    with pytest.raises(MeshFileError, match=r"\.xdmf format is stored in HDF5 and needs h5py"):
        write_mesh(tmp_path / "pad.xdmf", coarse_pad)


def test_missing_group_names_the_group_and_the_file(tmp_path, coarse_pad):
    import skfem as fem
    m = coarse_pad
    bnd = {k: v for k, v in m.boundaries.items() if k != "abutment"}
    cut = fem.MeshTet(m.p, m.t, bnd, m.subdomains)
    path = write_mesh(tmp_path / "pad.msh", cut)
    scene = _write_scene(tmp_path, mesh={"pad_file": '"pad.msh"'})
    with pytest.raises(SceneError) as e:
        load_scene(scene)
    msg = str(e.value)
    assert "mesh.pad_file" in msg and str(path) in msg and "['abutment']" in msg, msg


def test_a_scene_with_a_gmsh_pad_gives_the_built_in_pressure(tmp_path):
    """The built-in pad written as gmsh and read back through mesh.pad_file."""
    geom = load_geometry("default")
    write_mesh(tmp_path / "pad.msh", pad_mesh(geom, 12e-3))
    base = dict(mesh={"size": "12.0"}, environment={"duration": "60.0"},
                numerics={"steps": "1"}, output={"figures": "false"})
    own = _write_scene(tmp_path, "own.toml", **{**base, "mesh": {"size": "12.0",
                                                                 "pad_file": '"pad.msh"'}})
    ref = _write_scene(tmp_path, "ref.toml", **base)
    sc = load_scene(own)
    assert sc.mesh_files == {"pad": str(tmp_path / "pad.msh")}
    from brakewear.output.runs import run_scene
    a = run_scene(sc, tmp_path / "a")
    b = run_scene(load_scene(ref), tmp_path / "b")
    pa, pb = a["final"]["pressure_max_Pa"], b["final"]["pressure_max_Pa"]
    assert pa == pytest.approx(pb, rel=1e-8), (pa, pb)
    assert a["final"]["normal_force_N"] == pytest.approx(b["final"]["normal_force_N"], rel=1e-8)
    assert a["final"]["pad_wear_max_m"] == pytest.approx(b["final"]["pad_wear_max_m"], rel=1e-8)


def test_brake_model_takes_a_users_pad_mesh(tmp_path):
    from brakewear.model import BrakeModel
    geom = load_geometry("default")
    path = write_mesh(tmp_path / "pad.msh", pad_mesh(geom, 12e-3))
    own = BrakeModel(geom, size=12e-3, meshes={"pad": path})
    ref = BrakeModel(geom, size=12e-3)
    ra, rb = solve_tied(own, 1e6), solve_tied(ref, 1e6)
    pa = np.sort(ra.interface_pressure)
    pb = np.sort(rb.interface_pressure)
    assert np.abs(pa - pb).max() <= 1e-6 * np.abs(pb).max()
    with pytest.raises(SceneError, match="'piston' is not a meshed body"):
        BrakeModel(geom, size=12e-3, meshes={"piston": path})


def test_brake_model_refuses_implausible_loads_before_solving():
    from brakewear.model import BrakeModel
    m = BrakeModel("default", size=12e-3)
    with pytest.raises(
        SceneError,
        match=r"line_pressure: 1000000000000.0 Pa is implausible.*at most "
        r"1e\+08 Pa",
    ):
        solve_tied(m, 1e12)
    with pytest.raises(SceneError, match=r"mu: 50.0 is implausible.*at most 2"):
        m.contact_system(1e6, mu=50.0)
