"""The load-path keys of a geometry file: floating.toml loads in SI; every bad value is
refused before meshing with the file, the field, the value in the file's units and the range."""
from __future__ import annotations

import math

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from brakewear.errors import GeometryError
from brakewear.geometry import (
    CaliperGeometry,
    SupportGeometry,
    geometry_file,
    geometry_from_dict,
    load_geometry,
)
from test_geometry import modified


@pytest.fixture(scope="module")
def floating():
    return tomllib.loads(geometry_file("floating").read_text())


@pytest.fixture(scope="module")
def default():
    return tomllib.loads(geometry_file("default").read_text())


def test_bridge_keys_in_si(floating):
    g = geometry_from_dict(modified(modified(floating, "caliper.bridge_tilt", 0.08),
                                    "caliper.finger_stiffness", 500.0))
    assert g.caliper.bridge_tilt == pytest.approx(0.08e-3 / 1e3, rel=1e-12)     # rad/N
    assert g.caliper.finger_stiffness == pytest.approx(500e6 / 1e-3, rel=1e-12)  # Pa/m
    assert load_geometry("floating").caliper.bridge_tilt == 0.0                 # rigid bridge


def test_floating_loads_in_si():
    g = load_geometry("floating")
    assert g.caliper.type == "floating" and not g.caliper.symmetric
    assert [f.radius for f in g.caliper.fingers] == pytest.approx([0.126, 0.126], rel=1e-12)
    assert [f.angle for f in g.caliper.fingers] == pytest.approx([-math.radians(12),
                                                                  math.radians(12)], rel=1e-12)
    assert g.support == SupportGeometry("push", 2e-4, 1e9, 1e5, 0.2)
    assert g.rotor.mount == "hat" and g.rotor.hat.bolt_circle_radius == pytest.approx(0.05715)
    assert g.pad.backplate_radii == pytest.approx((0.090, 0.148), rel=1e-12)
    assert g.pad.leading_chamfer == pytest.approx((5e-3, 2e-3)) and g.pad.slot_width == 3e-3
    assert g.pad.slot_depth is None
    p = g.piston
    assert (p.diameter, p.rim_inner_diameter) == pytest.approx((0.057, 0.054))
    assert p.footprint_area == pytest.approx(0.25 * math.pi * (0.057**2 - 0.054**2), rel=1e-12)
    assert g.clamp_area == pytest.approx(0.25 * math.pi * 0.057**2, rel=1e-12)


def test_absent_keys_keep_the_idealised_brake():
    g = load_geometry("default")
    assert g.caliper == CaliperGeometry() and g.support == SupportGeometry()
    assert g.extra_pistons == () and g.rotor.mount == "ring_clamp"
    assert g.rotor.hat is None and g.rotor.vents is None
    assert g.pad.backplate_inner_radius is None and g.pad.backplate_outer_radius is None
    assert g.pad.leading_chamfer == (0.0, 0.0) and g.pad.slot_width == 0.0
    assert g.piston.rim_inner_diameter is None


def test_units_and_extra_pistons(floating, default):
    d = modified(floating, "units.stiffness", "kN/mm")
    assert geometry_from_dict(d).support.rail_stiffness == pytest.approx(1e12)
    d = modified(default, "caliper", {"type": "fixed", "pistons": [
        {"diameter": 20.0, "radius": 116.5, "angle": 20.0, "bore_diameter": 38.0,
         "rim_inner_diameter": 15.0}]})
    d = modified(d, "piston.diameter", 20.0)
    g = geometry_from_dict(d)
    (extra,) = g.extra_pistons
    assert extra.angle == pytest.approx(math.radians(20.0)) and extra.length == g.piston.length
    assert extra.rim_inner_diameter == pytest.approx(0.015)
    assert g.clamp_area == pytest.approx(0.25 * math.pi * (0.057**2 + 0.038**2), rel=1e-12)
    vents = {"cheek_thickness": 8.0, "vane_count": 37, "vane_width": 6.0}
    g = geometry_from_dict(modified(floating, "rotor.vents", vents))
    assert (g.rotor.vents.cheek_thickness, g.rotor.vents.vane_count) == (0.008, 37)


FINGER = {"diameter": 20.0, "radius": 126.0, "angle": 0.0}
HAT = {"height": 42.0, "wall_radius": 87.0, "wall_thickness": 6.0, "flange_thickness": 7.0,
       "bore_radius": 33.0, "bolt_circle_radius": 57.15}


BAD = [
    # (base, path, value, field, texts that must appear: the value and the allowed range)
    ("f", "caliper.fingers[0].radius", 141.0, "caliper.fingers[0].radius",
     ["141 mm", "[100 mm, 138 mm]", "backplate radii [90 mm, 148 mm]"]),
    ("f", "caliper.fingers[1].angle", 25.0, "caliper.fingers[1].angle",
     ["25 deg", "allowed |caliper.fingers[1].angle| <= 22.9479 deg"]),
    ("f", "caliper.fingers[1].angle", -11.0, "caliper.fingers[1]", ["overlaps caliper.fingers[0]"]),
    ("f", "caliper.fingers[0].diameter", 0.0, "caliper.fingers[0].diameter", ["> 0"]),
    ("f", "caliper.fingers[0].colour", 1, "caliper.fingers[0].colour", ["allowed fields"]),
    ("f", "caliper.type", "fixed", "caliper.fingers", ["fixed caliper has pistons on both sides"]),
    ("f", "caliper.type", "sliding", "caliper.type", ["'sliding'", "'fixed', 'floating'"]),
    ("f", "caliper.fingers", [], "caliper.fingers", ["floating caliper needs"]),
    ("f", "caliper.fingers", FINGER, "caliper.fingers", ["array of tables"]),
    ("d", "caliper", {"type": "floating"}, "caliper.fingers", ["floating caliper needs"]),
    ("d", "caliper", {"type": "fixed", "pistons": [{"diameter": 40.0, "radius": 116.5,
                                                    "angle": 10.0}]},
     "caliper.pistons[0]", ["overlaps piston"]),
    ("d", "caliper", {"type": "fixed", "pistons": [{"diameter": 40.0, "radius": 80.0}]},
     "caliper.pistons[0].radius", ["80 mm", "[115 mm, 118 mm]"]),
    ("f", "piston.radius", 121.0, "piston.radius", ["121 mm", "[118.5 mm, 119.5 mm]"]),
    ("f", "piston.rim_inner_diameter", 57.0, "piston.rim_inner_diameter",
     ["57 mm", "(0, 57 mm)"]),
    ("d", "piston.diameter", 57.0, "piston.radius", ["the pad radii", "exceeds the radial"]),
    ("f", "rotor.mount", "bolted", "rotor.mount", ["'bolted'", "'ring_clamp', 'hat'"]),
    ("f", "rotor.mount", ..., "rotor.hat", ["rotor.mount = 'ring_clamp'"]),
    ("f", "rotor.hat", ..., "rotor.hat", ["needs a [rotor.hat] table"]),
    ("f", "rotor.hat.wall_radius", 80.0, "rotor.hat.wall_radius",
     ["80 mm", "does not meet", "[87 mm, 93 mm)"]),
    ("f", "rotor.hat.wall_radius", 93.0, "rotor.hat.wall_radius", ["93 mm", "[87 mm, 93 mm)"]),
    ("f", "rotor.hat.bore_radius", 85.0, "rotor.hat.bore_radius", ["85 mm", "(0, 84 mm)"]),
    ("f", "rotor.hat.bolt_circle_radius", 30.0, "rotor.hat.bolt_circle_radius",
     ["30 mm", "(33 mm, 84 mm)"]),
    ("f", "rotor.hat.bolt_circle_radius", 84.0, "rotor.hat.bolt_circle_radius",
     ["84 mm", "(33 mm, 84 mm)"]),
    ("f", "rotor.hat.height", 7.0, "rotor.hat.height", ["7 mm", "> flange_thickness = 7 mm"]),
    ("f", "rotor.hat.height", ..., "rotor.hat.height", ["missing"]),
    ("f", "pad.backplate_inner_radius", 87.0, "pad.backplate_inner_radius",
     ["87 mm", ">= 90 mm", "hat wall"]),
    ("d", "pad.backplate_inner_radius", 96.0, "pad.backplate_inner_radius",
     ["96 mm", "(0, 95 mm]"]),
    ("d", "pad.backplate_outer_radius", 130.0, "pad.backplate_outer_radius",
     ["130 mm", ">= pad.outer_radius = 138 mm"]),
    ("f", "rotor.vents", {"cheek_thickness": 12.0, "vane_count": 37, "vane_width": 6.0},
     "rotor.vents.cheek_thickness", ["12 mm", "(0, 12 mm)"]),
    ("f", "rotor.vents", {"cheek_thickness": 8.0, "vane_count": 100, "vane_width": 6.0},
     "rotor.vents.vane_width", ["6 mm", "(0, 5.65487 mm)"]),
    ("f", "rotor.vents", {"cheek_thickness": 8.0, "vane_count": 2.5, "vane_width": 6.0},
     "rotor.vents.vane_count", ["2.5", ">= 1"]),
    ("f", "pad.slot_width", 85.0, "pad.slot_width", ["85 mm", "[0, 80.4205 mm)"]),
    ("f", "pad.slot_depth", 11.0, "pad.slot_depth", ["11 mm", "(0, 10.5 mm]"]),
    ("d", "pad.slot_depth", 5.0, "pad.slot_depth", ["without a slot"]),
    ("f", "pad.leading_chamfer", [5.0, 10.5], "pad.leading_chamfer",
     ["10.5 mm", "[0, 10.5 mm)"]),
    ("f", "pad.trailing_chamfer", [5.0, 0.0], "pad.trailing_chamfer", ["[5 mm, 0 mm]", "[0, 0]"]),
    ("f", "pad.trailing_chamfer", [110.0, 1.0], "pad.trailing_chamfer",
     ["5 mm + 110 mm", "< the arc length at the mean radius, 111.832 mm"]),
    ("f", "pad.leading_chamfer", [-1.0, 1.0], "pad.leading_chamfer", ["-1.0 mm", ">= 0"]),
    ("f", "pad.leading_chamfer", 5.0, "pad.leading_chamfer", ["[length, depth]"]),
    ("f", "support.type", "clamp", "support.type", ["'clamp'", "'bilateral', 'push', 'pull'"]),
    ("f", "support.clearance", -0.1, "support.clearance", ["-0.1 mm", ">= 0"]),
    ("f", "support.type", "bilateral", "support.clearance", ["0.2 mm", "'push' / 'pull'"]),
    ("f", "support.rail_stiffness", 0.0, "support.rail_stiffness", ["0.0 N/mm", "> 0"]),
    ("f", "support.spring_stiffness", -5.0, "support.spring_stiffness", ["-5.0 N/mm", "> 0"]),
    ("f", "support.type", ..., "support.type", ["missing"]),
    ("f", "units.stiffness", "lbf/in", "units.stiffness", ["'lbf/in'", "'N/m', 'N/mm', 'kN/mm'"]),
    ("f", "caliper.bridge_tilt", -0.1, "caliper.bridge_tilt", ["-0.1 mrad/kN", ">= 0 mrad/kN"]),
    ("f", "caliper.finger_stiffness", 0.0, "caliper.finger_stiffness",
     ["0.0 MPa/mm", "> 0 MPa/mm"]),
    ("f", "caliper.bridge_tilt", "0.1", "caliper.bridge_tilt", ["'0.1'", "expected a number"]),
    ("d", "caliper", {"type": "fixed", "bridge_tilt": 0.1}, "caliper.bridge_tilt",
     ["caliper.type = 'fixed'", "floating caliper"]),
    ("f", "piston.bore_clearance", 0.0, "piston.bore_clearance", ["0.0 mm", "> 0 mm"]),
    ("f", "piston.seal_position", 19.0, "piston.seal_position", ["19 mm", "[1.5 mm, 18.5 mm]"]),
    ("f", "piston.seal_height", 25.0, "piston.seal_height", ["25.0 mm", "<= 20 mm"]),
    ("f", "piston.seal_modulus", -6.0, "piston.seal_modulus", ["-6.0 MPa", "> 0 MPa"]),
    ("f", "piston.rim_friction", 1.5, "piston.rim_friction", ["1.5", ">= 0 and <= 1"]),
    ("f", "piston.stand_out", "5", "piston.stand_out", ["'5'", "expected a number"]),
    ("f", "support.abutment_friction", -0.1, "support.abutment_friction", ["-0.1", ">= 0"]),
    ("f", "caliper.bore_tilt", -1.0, "caliper.bore_tilt", ["-1.0 mrad/kN", ">= 0 mrad/kN"]),
    ("d", "caliper", {"type": "fixed", "bore_tilt": 0.1}, "caliper.bore_tilt",
     ["caliper.type = 'fixed'"]),
]


@pytest.mark.parametrize("base, path, value, field, texts", BAD,
                         ids=[f"{p}={v!r}" for _, p, v, _, _ in BAD])
def test_bad_value_names_field_value_and_range(floating, default, base, path, value, field,
                                               texts):
    d = modified(floating if base == "f" else default, path, value)
    with pytest.raises(GeometryError) as info:
        geometry_from_dict(d, source="bad.toml")
    msg = str(info.value)
    assert msg.startswith(f"bad.toml: {field}:"), msg
    for text in texts:
        assert text in msg, f"{text!r} not in: {msg}"


def test_bad_floating_file_fails_on_load(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(geometry_file("floating").read_text().replace("radius = 126.0", "radius = 145.0"))
    with pytest.raises(GeometryError, match=r"bad.toml: caliper.fingers\[0\].radius: 145 mm"):
        load_geometry(f)


def test_the_floating_snippet_of_the_docs_runs(capsys):
    """docs/geometry.md's floating-caliper snippet, run as written; its comments are its output."""
    import pathlib
    import re

    text = (pathlib.Path(__file__).parents[1] / "docs" / "geometry.md").read_text()
    (code,) = [b for b in re.findall(r"```python\n(.*?)```", text, re.S)
               if 'load_geometry("floating")' in b]
    exec(compile(code, "docs/geometry.md", "exec"), {})
    out = capsys.readouterr().out.splitlines()
    expected = [m.strip() for m in re.findall(r"# (.*)$", code, re.M)]
    assert out[:3] == expected, (out, expected)
    assert "slot" in out[3] and "leading_chamfer" in out[3]


def test_load_path_keys_in_si_and_their_plausible_ranges(floating, caplog):
    g = geometry_from_dict(modified(modified(floating, "piston.seal_modulus", 8.0),
                                    "support.abutment_friction", 0.3))
    assert g.piston.guide.seal_modulus == pytest.approx(8e6, rel=1e-12)          # MPa
    assert g.support.abutment_friction == pytest.approx(0.3, rel=1e-12)
    f = load_geometry("floating")
    assert f.piston.guide.clearance == pytest.approx(0.08e-3, rel=1e-12)         # mm
    # a value outside its plausible range loads, with a warning naming the key
    with caplog.at_level("WARNING"):
        geometry_from_dict(modified(floating, "piston.seal_modulus", 50.0), source="odd.toml")
    assert "piston.seal_modulus" in caplog.text and "unusual" in caplog.text
    assert "above 12 MPa" in caplog.text
    # the keys against each other: the seal closes the clearance
    d = modified(modified(floating, "piston.seal_width", 0.5), "piston.bore_clearance", 0.8)
    with pytest.raises(GeometryError, match=r"piston.bore_clearance: 0.8 mm .* < "
                                            r"piston.seal_width = 0.5 mm"):
        geometry_from_dict(d)
