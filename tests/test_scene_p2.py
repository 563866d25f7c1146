"""Scenes on quadratic (P2) meshes: a tiny run end to end with its tetra10 VTU read
back, with and without thermal coupling, and the combinations quadratic meshes do
not support refused by name."""
import json
from dataclasses import replace

import meshio
import numpy as np
import pytest

from brakewear.errors import SceneError
from brakewear.mesh.series import cell_nodes
from brakewear.output.runs import run_scene
from brakewear.scene import InterfaceSpec, OutputSpec, Scene, ThermalSpec, load_scene
from brakewear.wear import Numerics

#: VTK's tetra10: the vertices, then the mid-edge nodes of these vertex pairs
VTK_EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))


def _small(**kw):
    s = load_scene("default")
    return Scene(**{**dict(geometry=s.geometry, mesh_size=1.8e-2, order=2, duration=20.0,
                           numerics=Numerics(steps=2, scheme="implicit"),
                           output=OutputSpec(vtu_every=1, figures=True),
                           interface=InterfaceSpec(mu=0.4)), **kw})


def _check_tetra10(m: meshio.Mesh) -> None:
    """Every pair of vertices has one mid-edge node, whichever cells share it (a wrong
    local edge order maps one pair to different nodes in differently numbered cells),
    near the middle of its edge (the brake's arcs curve the edges a little)."""
    (block,) = m.cells
    assert block.type == "tetra10"
    c, x = block.data.T, m.points
    pairs = {}
    for k, (a, b) in enumerate(VTK_EDGES):
        key = np.sort(np.vstack([c[a], c[b]]), axis=0)
        for lo, hi, mid in zip(key[0], key[1], c[4 + k]):
            assert pairs.setdefault((lo, hi), mid) == mid, f"edge ({lo}, {hi}): two nodes"
        edge = np.linalg.norm(x[c[a]] - x[c[b]], axis=1)
        off = np.linalg.norm(x[c[4 + k]] - 0.5 * (x[c[a]] + x[c[b]]), axis=1)
        assert (off < 0.1 * edge).all(), f"edge {k}: mid-edge node {off.max():.3g} m off"
    assert len(set(pairs.values())) == len(pairs)


def test_a_quadratic_scene_runs_and_writes_tetra10(tmp_path):
    summary = run_scene(_small(), tmp_path)
    assert summary["steps"] == 2 and summary["final"]["pressure_max_Pa"] > 0
    pad = meshio.read(sorted(tmp_path.glob("pad_*.vtu"))[-1])
    rotor = meshio.read(sorted(tmp_path.glob("rotor_*.vtu"))[-1])
    for m in (pad, rotor):
        _check_tetra10(m)
    wear, p = pad.point_data["pad_wear"], pad.point_data["pressure"]
    assert wear.max() == pytest.approx(summary["final"]["pad_wear_max_m"], rel=1e-9)
    assert p.max() > 0 and (p[wear == 0] == 0).all()
    assert rotor.point_data["rotor_wear"].max() > 0
    # as many points as the model's P2 nodes, so ParaView sees the quadratic fields
    model = _small().build_model()
    assert pad.points.shape[0] == model.meshes["pad"].p.shape[1]
    assert cell_nodes(model.meshes["pad"]).shape[0] == 10
    assert json.loads((tmp_path / "scene.json").read_text())["order"] == 2
    assert (tmp_path / "pad_wear.png").stat().st_size > 10_000


def test_a_quadratic_thermal_scene_writes_temperatures_at_every_node(tmp_path):
    summary = run_scene(_small(thermal=ThermalSpec(enabled=True)), tmp_path)
    th = summary["thermal"]["final"]
    assert 20.0 < th["pad_T_max_C"] < 900.0
    assert th["heat_balance"]["relative_error"] < 1e-10
    model = _small().build_model()
    for body in ("pad", "rotor"):
        mesh = model.meshes[body]
        T = meshio.read(sorted(tmp_path.glob(f"{body}_*.vtu"))[-1]).point_data["temperature_C"]
        assert T.shape == (mesh.p.shape[1],)                 # every P2 node
        # a linear field on the vertices: each mid-edge node the mean of its edge's ends
        mid = T[mesh.nvertices:]
        assert np.allclose(mid, 0.5 * (T[mesh.edges[0]] + T[mesh.edges[1]]), rtol=1e-12)
    pad = meshio.read(sorted(tmp_path.glob("pad_*.vtu"))[-1]).point_data["temperature_C"]
    assert pad.max() == pytest.approx(th["pad_T_max_C"], rel=1e-9)   # heated from its face


@pytest.mark.parametrize("change,key,alternative", [
    (dict(interface=InterfaceSpec(model="winkler")), "interface.model = 'winkler'",
     "interface.model = 'fe'"),
    (dict(numerics=Numerics(update="geometry"), thermal=ThermalSpec(enabled=True)),
     "update = 'geometry'", "numerics.update = 'gap'"),
])
def test_what_quadratic_scenes_do_not_support_is_refused_by_name(change, key, alternative):
    with pytest.raises(SceneError, match="mesh.order = 2 is not supported") as e:
        _small(**change)
    assert key in str(e.value) and alternative in str(e.value)
    assert "mesh.order = 1" in str(e.value)


def test_a_scene_order_other_than_1_or_2_is_refused():
    with pytest.raises(SceneError, match="mesh.order"):
        _small(order=3)


def test_a_quadratic_scene_runs_condensed_and_with_the_geometry_update(tmp_path):
    """P2 on the condensed interface gives the FE answer (both to 1e-12); the
    geometry update of the same run differs from the gap offset by the small
    change of the worn geometry's stiffness."""
    n = Numerics(steps=2, scheme="implicit", tol=1e-12)
    runs = {name: run_scene(_small(numerics=replace(n, update=update),
                                   interface=InterfaceSpec(mu=0.4, model=model),
                                   output=OutputSpec(vtu_every=1, figures=False)),
                            tmp_path / name)["final"]
            for name, model, update in (("fe", "fe", "gap"), ("condensed", "condensed", "gap"),
                                        ("geometry", "fe", "geometry"))}
    for key in ("pad_wear_max_m", "pressure_max_Pa", "rotor_wear_max_m"):
        assert runs["condensed"][key] == pytest.approx(runs["fe"][key], rel=1e-8), key
        assert runs["geometry"][key] == pytest.approx(runs["fe"][key], rel=1e-3), key
        assert runs["geometry"][key] != runs["fe"][key]
