"""Geometry files: the default loads in SI units; every bad input names its field."""
from __future__ import annotations

import copy
import dataclasses
import math

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

import brakewear.mesh as bmesh
from brakewear.errors import GeometryError
from brakewear.geometry import (
    BrakeGeometry,
    available_geometries,
    geometry_file,
    geometry_from_dict,
    load_geometry,
)
from brakewear.materials import MATERIALS


@pytest.fixture(scope="module")
def default_dict():
    res = geometry_file("default")
    return tomllib.loads(res.read_text())


def modified(d, path, value):
    """A deep copy of ``d`` with ``path`` ("pad.inner_radius", "caliper.fingers[0].radius")
    set (or deleted if value is ...)."""
    d = copy.deepcopy(d)
    keys = path.split(".")
    node = d
    for k in keys[:-1]:          # "name[i]" indexes an array of tables
        name, _, i = k.rstrip("]").partition("[")
        node = node[name][int(i)] if i else node.setdefault(k, {})
    if value is ...:
        del node[keys[-1]]
    else:
        node[keys[-1]] = value
    return d


def test_default_loads_in_si():
    g = load_geometry()
    assert isinstance(g, BrakeGeometry)
    assert "default" in available_geometries()
    checks = {
        "rotor.inner_radius": (g.rotor.inner_radius, 0.090),
        "rotor.outer_radius": (g.rotor.outer_radius, 0.150),
        "rotor.thickness": (g.rotor.thickness, 0.024),
        "pad.inner_radius": (g.pad.inner_radius, 0.095),
        "pad.outer_radius": (g.pad.outer_radius, 0.138),
        "pad.arc_angle": (g.pad.arc_angle, math.radians(55.0)),
        "pad.friction_thickness": (g.pad.friction_thickness, 0.0105),
        "pad.backplate_thickness": (g.pad.backplate_thickness, 0.0055),
        "piston.radius": (g.piston.radius, 0.1165),
        "piston.bore_diameter": (g.piston.bore_diameter, 0.057),
    }
    for name, (got, want) in checks.items():
        assert got == pytest.approx(want, rel=1e-12), f"{name} = {got!r}, want {want!r}"
    assert g.rotor.material is MATERIALS["grey_cast_iron"]
    assert g.pad.friction_material is MATERIALS["pad_resin"]
    assert g.pad.backplate_material is MATERIALS["steel"]
    assert g.piston.material is MATERIALS["steel"]
    assert 0.0005 < g.mesh.size < 0.01 and g.mesh.order == 1
    assert g.pad.leading_angle < g.pad.center_angle < g.pad.trailing_angle


def test_units_m_rad_give_the_same_geometry(default_dict):
    d = copy.deepcopy(default_dict)
    d["units"] = {"length": "m", "angle": "rad", "modulus": "Pa"}
    for sec, fields in d.items():
        if sec in ("units", "materials"):
            continue
        for k, v in fields.items():
            if isinstance(v, float) and k in ("arc_angle", "center_angle", "angle", "rotor_margin"):
                fields[k] = math.radians(v)
            elif isinstance(v, float) and not k.endswith(("ratio", "factor")):
                fields[k] = v / 1000.0
    a, b = geometry_from_dict(d), load_geometry("default")
    for part in ("rotor", "pad", "piston", "mesh"):
        for k, v in vars(getattr(a, part)).items():
            w = getattr(getattr(b, part), k)
            if isinstance(v, float):
                assert v == pytest.approx(w, rel=1e-12), f"{part}.{k}: {v} (m/rad) vs {w} (mm/deg)"


BAD = [
    # (path, value, text that must appear in the message)
    ("units.length", ..., "units.length"),
    ("units.length", "inch", "units.length"),
    ("units.angle", "grad", "units.angle"),
    ("units.modulus", ..., "units.modulus"),
    ("rotor.colour", "grey", "rotor.colour"),
    ("gearbox", {"ratio": 3}, "gearbox"),
    ("rotor.inner_radius", ..., "rotor.inner_radius"),
    ("rotor.inner_radius", "ninety", "rotor.inner_radius"),
    ("rotor.inner_radius", True, "rotor.inner_radius"),
    ("rotor.inner_radius", -90.0, "rotor.inner_radius"),
    ("rotor.inner_radius", float("nan"), "rotor.inner_radius"),
    ("rotor.thickness", float("inf"), "rotor.thickness"),
    ("rotor.thickness", 0.0, "rotor.thickness"),
    ("rotor.inner_radius", 160.0, "rotor.inner_radius"),
    ("pad.inner_radius", 140.0, "pad.inner_radius"),
    ("pad.inner_radius", 85.0, "pad.inner_radius"),
    ("pad.outer_radius", 155.0, "pad.outer_radius"),
    ("pad.arc_angle", 0.0, "pad.arc_angle"),
    ("pad.arc_angle", 180.0, "pad.arc_angle"),
    ("pad.arc_angle", 200.0, "pad.arc_angle"),
    ("pad.friction_thickness", -1.0, "pad.friction_thickness"),
    ("pad.backplate_material", "unobtainium", "pad.backplate_material"),
    ("pad", [1, 2], "pad"),
    ("piston.diameter", 57.0, "piston.radius"),  # wider than the pad
    ("piston.radius", 100.0, "piston.radius"),  # footprint below pad.inner_radius
    ("piston.radius", 125.0, "piston.radius"),  # footprint beyond pad.outer_radius
    ("piston.angle", 20.0, "piston.angle"),  # footprint across the trailing end
    ("piston.angle", -40.0, "piston.angle"),  # piston off the pad
    ("piston.length", 0.0, "piston.length"),
    ("piston.material", 7, "piston.material"),
    ("mesh.size", ..., "mesh.size"),
    ("mesh.size", 0.0, "mesh.size"),
    ("mesh.size", 40.0, "mesh.size"),
    ("mesh.order", 3, "mesh.order"),
    ("mesh.order", 1.5, "mesh.order"),
    ("mesh.rotor_z_ratio", 0.5, "mesh.rotor_z_ratio"),
    ("mesh.rotor_margin", 170.0, "mesh.rotor_margin"),
    ("materials.goo", {"type": "isotropic", "E": 1.0, "nu": 0.5}, "materials.goo.nu"),
    ("materials.goo", {"type": "isotropic", "E": -1.0, "nu": 0.3}, "materials.goo.E"),
    ("materials.goo", {"type": "isotropic", "E": 1.0}, "materials.goo.nu"),
    ("materials.goo", {"type": "isotropic", "E": 1.0, "nu": 0.3, "rho": -5.0}, "materials.goo.rho"),
    (
        "materials.goo",
        {"type": "isotropic", "E": 1.0, "nu": 0.3, "color": 1},
        "materials.goo.color",
    ),
    ("materials.goo", {"type": "plastic", "E": 1.0, "nu": 0.3}, "materials.goo.type"),
    (
        "materials.goo",
        {
            "type": "transversely_isotropic",
            "E_p": 8.0,
            "E_t": 3.0,
            "nu_p": 0.6,
            "nu_tp": 0.2,
            "G_t": 1.5,
        },
        "materials.goo.nu_p",
    ),
    (
        "materials.goo",
        {
            "type": "transversely_isotropic",
            "E_p": 8.0,
            "E_t": 0.1,
            "nu_p": 0.3,
            "nu_tp": 0.9,
            "G_t": 1.5,
        },
        "materials.goo",
    ),
    ("materials.steel", {"type": "isotropic", "E": 1.0, "nu": 0.3}, "materials.steel"),
]


@pytest.mark.parametrize("path, value, field", BAD, ids=[f"{p}={v!r}" for p, v, _ in BAD])
def test_bad_input_names_the_field(default_dict, path, value, field):
    d = modified(default_dict, path, value)
    with pytest.raises(GeometryError) as info:
        geometry_from_dict(d, source="bad.toml")
    msg = str(info.value)
    assert field in msg, f"message does not name {field!r}: {msg}"
    assert msg.startswith("bad.toml"), f"message does not name the file: {msg}"


def test_messages_give_value_and_range(default_dict):
    with pytest.raises(GeometryError) as info:
        geometry_from_dict(modified(default_dict, "pad.inner_radius", 85.0))
    msg = str(info.value)
    assert "85 mm" in msg and "[90 mm, 150 mm]" in msg, msg
    with pytest.raises(GeometryError) as info:
        geometry_from_dict(modified(default_dict, "pad.arc_angle", 200.0))
    assert "200 deg" in str(info.value) and "(0, 180 deg)" in str(info.value), str(info.value)
    with pytest.raises(GeometryError) as info:
        geometry_from_dict(modified(default_dict, "rotor.material", "cheese"))
    for known in MATERIALS:
        assert known in str(info.value), f"{known!r} not listed: {info.value}"
    with pytest.raises(GeometryError) as info:
        geometry_from_dict(modified(default_dict, "materials.goo",
                                    {"type": "isotropic", "E": 1.0, "nu": 0.5}))
    assert "0.5" in str(info.value) and "(-1, 0.5)" in str(info.value), str(info.value)


def test_custom_materials(default_dict):
    d = modified(default_dict, "materials.soft_pad",
                 {"type": "transversely_isotropic", "E_p": 6.0, "E_t": 2.0, "nu_p": 0.25,
                  "nu_tp": 0.2, "G_t": 1.0, "wear_k": 1e-14})
    d = modified(d, "materials.iron2", {"type": "isotropic", "E": 120.0, "nu": 0.28, "rho": 7100.0})
    d = modified(d, "pad.friction_material", "soft_pad")
    d = modified(d, "rotor.material", "iron2")
    g = geometry_from_dict(d)
    fm = g.pad.friction_material
    assert fm.elastic.E_t == pytest.approx(2e9) and fm.wear_k == 1e-14
    assert fm.thermal == MATERIALS["pad_resin"].thermal  # defaults from the base material
    rm = g.rotor.material
    assert rm.elastic.E == pytest.approx(120e9) and rm.thermal.rho == 7100.0
    assert rm.thermal.c == MATERIALS["steel"].thermal.c
    assert "soft_pad" in g.materials and "steel" in g.materials


def test_file_errors(tmp_path, default_dict):
    bad = tmp_path / "broken.toml"
    bad.write_text("[rotor\ninner_radius = 1\n")
    with pytest.raises(GeometryError, match="broken.toml.*TOML"):
        load_geometry(bad)
    with pytest.raises(GeometryError, match="cannot read"):
        load_geometry(tmp_path / "missing.toml")
    with pytest.raises(GeometryError, match="packaged geometries: .*default"):
        load_geometry("no_such_brake")
    f = tmp_path / "mine.toml"
    text = (geometry_file("default")).read_text()
    f.write_text(text.replace("inner_radius = 95.0", "inner_radius = 140.0"))
    with pytest.raises(GeometryError) as info:
        load_geometry(str(f))
    assert str(f) in str(info.value) and "pad.inner_radius" in str(info.value), str(info.value)


def test_errors_come_before_meshing(tmp_path, monkeypatch):
    """A bad file fails in load_geometry; no mesh function is ever reached."""
    def boom(*args, **kwargs):
        raise AssertionError("meshing reached")

    for name in ("structured_tets", "mapped_mesh", "brake_meshes", "rotor_mesh", "pad_mesh"):
        monkeypatch.setattr(bmesh, name, boom)
    f = tmp_path / "bad.toml"
    text = (geometry_file("default")).read_text()
    f.write_text(text.replace("arc_angle = 55.0", "arc_angle = 190.0"))
    with pytest.raises(GeometryError, match="pad.arc_angle"):
        load_geometry(f)


def test_geometry_is_frozen():
    g = load_geometry()
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.rotor.inner_radius = 0.1  # type: ignore[misc]
