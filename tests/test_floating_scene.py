"""The packaged floating-caliper scene (geometry/scenes/floating.toml): it loads by
name and by path, holds the floating brake's load path, and runs (on a coarse mesh
set through the scene API) as the full model with both pads worn."""
import sys
from dataclasses import replace
from pathlib import Path

import pytest

from brakewear.output.runs import run_scene
from brakewear.scene import OutputSpec, available_scenes, load_scene, scene_file

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]


def test_packaged_floating_scene_loads_by_name_and_path():
    assert "floating" in available_scenes()
    s = load_scene("floating")
    assert load_scene(ROOT / "geometry" / "scenes" / "floating.toml") == s
    g = s.geometry
    assert g.caliper.type == "floating" and len(g.caliper.fingers) == 2
    assert g.support.type == "push" and g.support.clearance == pytest.approx(2e-4)
    assert g.rotor.mount == "hat" and g.piston.rim_inner_diameter == pytest.approx(0.054)
    assert s.layout == "full" and s.piston == "traction" and s.rotor == "elastic"
    assert s.line_pressure == 1e6 and s.omega == 55.0 and s.duration == 3600.0
    assert s.interface.mu == 0.4
    mesh = tomllib.loads(scene_file("floating").read_text())["mesh"]
    assert s.mesh_size == pytest.approx(mesh.pop("size") * 1e-3)
    assert s.resolution == pytest.approx({k: v * 1e-3 if k.endswith("_size") else v
                                          for k, v in mesh.items()})


def test_packaged_floating_scene_runs_coarse(tmp_path):
    s = load_scene("floating")
    coarse = replace(s, mesh_size=8e-3, duration=300.0,
                     resolution={"rotor_size": 12e-3, "friction_layers": 2,
                                 "backplate_layers": 2, "rotor_layers": 2},
                     numerics=replace(s.numerics, steps=2),
                     output=OutputSpec(vtu_every=2, checkpoint_every=2, figures=False))
    model = coarse.build_model()
    assert model.layout == "full" and model.dofs < 15_000
    summary = run_scene(coarse, tmp_path)
    assert summary["steps"] == 2
    final = summary["final"]
    assert final["pad_wear_max_m"] > 0 and final["rotor_wear_max_m"] > 0
    # at 1 MPa the contact pressure stays within a few times the nominal pressure
    nominal = 1e6 * s.geometry.clamp_area / s.geometry.pad.area
    assert nominal < final["pressure_max_Pa"] < 10 * nominal


def test_inline_geometry_takes_the_load_path_tables():
    """The floating geometry written inline as [geometry] (docs/scenes.md's table:
    caliper, fingers, support, rotor.hat, rotor.vents) gives the packaged one."""
    from brakewear.geometry import geometry_file, load_geometry
    from brakewear.scene import scene_from_dict

    scene = tomllib.loads(scene_file("floating").read_text())
    del scene["scene"]["geometry"]
    scene["geometry"] = tomllib.loads(geometry_file("floating").read_text())
    scene["geometry"]["rotor"]["vents"] = {"cheek_thickness": 8.0, "vane_count": 37,
                                           "vane_width": 6.0}
    g = scene_from_dict(scene).geometry
    ref = load_geometry("floating")
    assert g.caliper == ref.caliper and g.support == ref.support
    assert g.rotor.hat == ref.rotor.hat and g.support.rail_stiffness == pytest.approx(1e9)
    assert g.rotor.vents.vane_count == 37 and g.rotor.vents.vane_width == pytest.approx(6e-3)
