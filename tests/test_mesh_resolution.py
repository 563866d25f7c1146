"""Per-body mesh resolution: layer counts and in-plane sizes from geometry and scene
files, the same meshes as before when they are not set, the size estimate, and bad
values refused naming the file, the key and the allowed range before meshing."""
from __future__ import annotations

import copy
import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

from brakewear.errors import GeometryError, SceneError
from brakewear.geometry import geometry_file, geometry_from_dict, load_geometry
from brakewear.geometry.parts import MESH_BODY_KEYS
from brakewear.mesh import estimate_model, pad_mesh, rotor_mesh
from brakewear.scene import load_scene, scene_file, scene_from_dict

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

H = 6e-3


def _with(geom, **kw):
    return dataclasses.replace(geom, mesh=dataclasses.replace(geom.mesh, **kw))


def _levels(mesh, sub):
    """Distinct z of the nodes of a subdomain (m)."""
    nodes = np.unique(mesh.t[:, mesh.subdomains[sub]])
    return np.unique(np.round(mesh.p[2, nodes], 12))


@pytest.fixture(scope="module")
def geom():
    return load_geometry()


def test_unset_keys_keep_the_meshes_of_the_size_rule(geom):
    # the rule at 6 mm: 3 graded friction layers, 1 backplate layer, 2 rotor layers
    pad, rot = pad_mesh(geom, size=H), rotor_mesh(geom, size=H)
    same = _with(geom, friction_layers=3, backplate_layers=1, rotor_layers=2, pad_size=H,
                 rotor_size=H)
    assert np.array_equal(pad.p, pad_mesh(same).p) and np.array_equal(pad.t, pad_mesh(same).t)
    assert np.array_equal(rot.p, rotor_mesh(same).p)


@pytest.mark.parametrize("n", [1, 2, 4])
def test_backplate_layers_appear_in_the_mesh(geom, n):
    m = pad_mesh(_with(geom, backplate_layers=n), size=H)
    z = _levels(m, "backplate")
    tf, tb = geom.pad.friction_thickness, geom.pad.backplate_thickness
    assert z.size == n + 1, z
    assert np.allclose(np.diff(z), tb / n, rtol=1e-9)
    assert z[0] == pytest.approx(tf) and z[-1] == pytest.approx(tf + tb)


def test_friction_layers_graded_toward_the_friction_face(geom):
    m = pad_mesh(_with(geom, friction_layers=5), size=H)
    dz = np.diff(_levels(m, "friction_layer"))
    assert dz.size == 5
    assert np.all(np.diff(dz) > 0), dz          # thinnest at z = 0
    assert dz[-1] / dz[0] == pytest.approx(geom.mesh.pad_z_ratio, rel=1e-9)


def test_rotor_layers_graded_toward_the_friction_face(geom):
    m = rotor_mesh(_with(geom, rotor_layers=4), size=H)
    z = np.unique(np.round(m.p[2], 12))
    dz = np.diff(z)
    assert z.size == 5 and z[-1] == 0.0
    assert np.all(np.diff(dz) < 0), dz          # thinnest at z = 0 (the top)
    assert dz[0] / dz[-1] == pytest.approx(geom.mesh.rotor_z_ratio, rel=1e-9)


def test_body_sizes_set_the_in_plane_cells_apart(geom):
    g = _with(geom, pad_size=4e-3)
    pad, rot = pad_mesh(g, size=H), rotor_mesh(g, size=H)
    assert pad.nvertices > pad_mesh(geom, size=H).nvertices
    assert rot.nvertices == rotor_mesh(geom, size=H).nvertices
    g = _with(geom, rotor_size=4e-3)
    assert rotor_mesh(g, size=H).nvertices > rot.nvertices


@pytest.mark.parametrize("kw", [{}, {"backplate_layers": 3}, {"friction_layers": 6,
                                                                "rotor_layers": 5},
                                {"pad_size": 4e-3, "rotor_size": 8e-3, "backplate_layers": 2}])
def test_size_estimate_counts_the_new_keys(geom, kw):
    g = _with(geom, **kw)
    est = estimate_model(g, H)
    for body, mesher in (("pad", pad_mesh), ("rotor", rotor_mesh)):
        m = mesher(g, size=H)
        assert est.nodes[body] == m.nvertices, body
        assert est.elements[body] == m.t.shape[1], body


@pytest.fixture(scope="module")
def geometry_dict():
    return tomllib.loads(geometry_file("default").read_text())


BAD_GEOMETRY = [("backplate_layers", 0), ("friction_layers", 2.5), ("rotor_layers", True),
                ("backplate_layers", 201), ("rotor_layers", "3")]


@pytest.mark.parametrize("key, value", BAD_GEOMETRY)
def test_bad_layers_in_a_geometry_file_name_file_key_and_range(geometry_dict, key, value):
    d = copy.deepcopy(geometry_dict)
    d["mesh"][key] = value
    with pytest.raises(GeometryError) as info:
        geometry_from_dict(d, source="my_brake.toml")
    msg = str(info.value)
    assert msg.startswith("my_brake.toml: ") and f"mesh.{key}" in msg, msg
    assert repr(value) in msg and "[1, 200]" in msg, msg


def test_bad_body_size_in_a_geometry_file(geometry_dict):
    d = copy.deepcopy(geometry_dict)
    d["mesh"]["pad_size"] = 30.0
    with pytest.raises(
        GeometryError, match=r"my_brake.toml: mesh.pad_size: 30 mm .*\(0, 21.5 mm\]"
    ):
        geometry_from_dict(d, source="my_brake.toml")


def test_geometry_file_keys_reach_the_mesh(geometry_dict):
    d = copy.deepcopy(geometry_dict)
    d["mesh"].update(backplate_layers=3, pad_size=5.0)
    g = geometry_from_dict(d)
    assert g.mesh.backplate_layers == 3 and g.mesh.pad_size == pytest.approx(5e-3)
    assert _levels(pad_mesh(g), "backplate").size == 4


def _scene_file(tmp_path: Path, lines: str) -> Path:
    """The default scene with ``lines`` in place of its per-body mesh keys."""
    text = "\n".join(line for line in scene_file("default").read_text().splitlines()
                     if line.split("=")[0].strip() not in MESH_BODY_KEYS)
    text = text.replace("[mesh]\n", "[mesh]\n" + lines)
    p = tmp_path / "my_scene.toml"
    p.write_text(text)
    return p


@pytest.mark.parametrize("line, key, words", [
    ("backplate_layers = 0\n", "mesh.backplate_layers", "0 is not allowed; allowed: a whole "
                                                        "number of element layers in [1, 200]"),
    ("friction_layers = 1.5\n", "mesh.friction_layers", "expected a whole number"),
    ("rotor_layers = 500\n", "mesh.rotor_layers", "[1, 200]"),
    ("pad_size = 40.0\n", "mesh.pad_size", "40.0 mm is not allowed; it must be <= 21.5 mm"),
    ("rotor_size = -1.0\n", "mesh.rotor_size", "must be > 0"),
])
def test_bad_scene_keys_name_file_key_and_range(tmp_path, no_meshing, line, key, words):
    with pytest.raises(SceneError) as info:
        load_scene(_scene_file(tmp_path, line))
    msg = str(info.value)
    assert msg.startswith(str(tmp_path / "my_scene.toml")) and key in msg, msg
    assert words in msg, msg


def test_scene_keys_set_the_geometry_mesh(tmp_path, no_meshing):
    s = load_scene(_scene_file(tmp_path, "backplate_layers = 2\npad_size = 5.0\n"))
    assert s.resolution == {"backplate_layers": 2, "pad_size": pytest.approx(5e-3)}
    mesh = s.meshed_geometry.mesh
    assert mesh.backplate_layers == 2 and mesh.pad_size == 5e-3 and mesh.rotor_layers is None
    assert s.to_dict()["resolution"] == s.resolution
    base = dataclasses.replace(s, resolution={})
    assert s != base and base.meshed_geometry == base.geometry == s.geometry
    assert load_scene("default").resolution and not base.resolution
    # the same scene built in Python
    assert dataclasses.replace(base, resolution=s.resolution) == s


def test_scene_model_is_meshed_with_the_keys():
    s = dataclasses.replace(load_scene("default"), mesh_size=1.2e-2,
                            resolution={"backplate_layers": 3, "rotor_layers": 2})
    model = s.build_model()
    assert _levels(model.meshes["pad"], "backplate").size == 4
    assert np.unique(np.round(model.meshes["rotor"].p[2], 12)).size == 3


def test_scene_memory_check_counts_the_layers(no_meshing):
    d = tomllib.loads(scene_file("default").read_text())
    d["mesh"].update(rotor_layers=200, friction_layers=200, backplate_layers=200)
    d.setdefault("numerics", {})["memory_budget"] = 0.5
    with pytest.raises(SceneError, match="too fine for this machine"):
        scene_from_dict(d)
