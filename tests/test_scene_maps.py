"""Friction and wear maps in scene files: read when the scene is made, refused where
they cannot run, and a constant map is the number it holds."""
import csv
import json

import numpy as np
import pytest

from brakewear.errors import SceneError
from brakewear.output.runs import run_scene
from brakewear.scene import InterfaceSpec, OutputSpec, Scene, ThermalSpec, WearSpec, load_scene
from brakewear.wear import Numerics


def _map(path, value_col, value, T=False):
    """A map over 2 pressures x 2 speeds (x 2 temperatures) holding ``value``."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        f.write("# constant map for a test\n")
        w.writerow(["p_MPa", "v_m_s"] + (["T_C"] if T else []) + [value_col])
        for p in (0.1, 20.0):
            for v in (0.1, 50.0):
                for t in ((20.0, 600.0) if T else (None,)):
                    w.writerow([p, v] + ([t] if T else []) + [value])
    return str(path)


def _scene(**kw):
    s = load_scene("default")
    base = dict(geometry=s.geometry, mesh_size=1.2e-2, duration=600.0,
                numerics=Numerics(steps=2), output=OutputSpec(figures=False, vtu_every=1))
    return Scene(**{**base, **kw})


def test_constant_maps_run_the_numbers_bit_for_bit(tmp_path):
    """mu = 0.4 and the materials' k (pad 5e-15, rotor 5e-16 m^2/N) as maps give the
    history of the numbers exactly, and the summary names the maps."""
    mu = _map(tmp_path / "mu.csv", "mu", 0.4)
    kp = _map(tmp_path / "kp.csv", "k_m2_N", 5e-15)
    kr = _map(tmp_path / "kr.csv", "k_m2_N", 5e-16)
    plain = run_scene(_scene(interface=InterfaceSpec(mu=0.4)), tmp_path / "plain")
    mapped = run_scene(_scene(interface=InterfaceSpec(mu_map=mu),
                              pad_wear=WearSpec(k_map=kp), rotor_wear=WearSpec(k_map=kr)),
                       tmp_path / "mapped")
    rows = [list(csv.DictReader(open(tmp_path / d / "history.csv"))) for d in ("plain", "mapped")]
    for a, b in zip(*rows):
        for key in ("pad_wear_max_m", "rotor_wear_max_m", "pressure_max_Pa"):
            if key in a:
                assert a[key] == b[key], (key, a[key], b[key])
    a, b = plain["final"], mapped["final"]
    for key in a:
        if key in ("mu", "torque_Nm"):      # sum of mu_i p_i A_i r_i against mu sum(...)
            assert b[key] == pytest.approx(a[key], rel=1e-14)
        elif key != "solve_s":
            assert a[key] == b[key], key
    s = json.loads((tmp_path / "mapped" / "summary.json").read_text())
    assert s["mu"]["type"] == "FrictionMap" and s["mu"]["source"].endswith("mu.csv")
    assert s["pad_law"]["type"] == "WearMap" and s["pad_law"]["max"] == 5e-15


def test_scene_maps_are_refused_where_they_cannot_run(tmp_path, monkeypatch):
    import brakewear.model as scene_mod

    def no_meshing(*a, **k):
        raise AssertionError("meshed before the scene was checked")
    monkeypatch.setattr(scene_mod.BrakeModel, "__init__", no_meshing)
    hot = _map(tmp_path / "hot.csv", "mu", 0.4, T=True)
    with pytest.raises(SceneError, match=r"interface.mu_map.*temperature.*thermal.enabled"):
        _scene(interface=InterfaceSpec(mu_map=hot))
    _scene(interface=InterfaceSpec(mu_map=hot), thermal=ThermalSpec(enabled=True))
    flat = _map(tmp_path / "flat.csv", "mu", 0.4)
    with pytest.raises(SceneError, match=r"interface.mu_map.*'fe' or 'condensed'"):
        _scene(interface=InterfaceSpec(model="winkler", mu_map=flat))
    with pytest.raises(SceneError, match=r"wear.pad.k_map.*cannot be combined with k"):
        _scene(pad_wear=WearSpec(k=1e-15, k_map=_map(tmp_path / "k.csv", "k_m2_N", 5e-15)))
    bad = tmp_path / "bad.csv"
    bad.write_text("p_MPa,v_m_s,mu\n1,1,0.4\n1,2,nan\n2,1,0.4\n2,2,0.4\n")
    with pytest.raises(SceneError, match=r"interface.mu_map.*bad.csv.*row 3.*mu"):
        _scene(interface=InterfaceSpec(mu_map=str(bad)))
    with pytest.raises(SceneError, match="interface.map_outside"):
        InterfaceSpec(map_outside="extrapolate")


def test_scene_file_map_paths_are_relative_to_the_scene(tmp_path):
    _map(tmp_path / "mu.csv", "mu", 0.35)
    text = (load_scene.__globals__["scene_file"]("default").read_text()
            .replace('mu = 0.4                   # sliding friction coefficient',
                     'mu_map = "mu.csv"'))
    path = tmp_path / "scene.toml"
    path.write_text(text)
    s = load_scene(path)
    law = s.friction()
    assert law.table.source.endswith("mu.csv")
    assert np.all(law.mu_at(np.full(3, 1e6), np.ones(3)) == 0.35)
