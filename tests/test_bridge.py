"""A compliant caliper bridge: the fingers' jaw turns under the clamp force and
moves the outboard pad's load toward the bridge.

The jaw pressure ``k max(0, delta + theta s)`` is checked against a brute-force
quadrature over the exact circular footprints (force, centre, lift-off), its
nodal loads against the same centre on a mesh, and the model's answer against
what the load path must do: the outboard centre of pressure moves out as the
bridge softens, the inboard one hardly, every pad stays in balance.
"""
from dataclasses import replace

import numpy as np
import pytest

from brakewear.caliper.loads import clamp_loads, jaw_pressure
from brakewear.errors import SceneError
from brakewear.geometry import load_geometry
from brakewear.mesh.brake import pad_mesh
from brakewear.mesh.mirror import mirrored_pads
from brakewear.model import BrakeModel
from brakewear.static import pad_balance, solve_contact, static_summary


@pytest.fixture(scope="module")
def floating():
    return load_geometry("floating")


def tilted(g, mrad_per_kN: float, mpa_per_mm: float = 1000.0):
    return replace(g, caliper=replace(g.caliper, bridge_tilt=mrad_per_kN * 1e-6,
                                      finger_stiffness=mpa_per_mm * 1e9))


def reference(g, jaw, n: int = 600):
    """Force (N) and first moment along the pad's centre line (N m) of each finger,
    by the midpoint rule on a polar grid over the exact footprint."""
    out = []
    for f in g.caliper.fingers:
        a = 0.5 * f.diameter
        rho = (np.arange(n) + 0.5) / n * a
        phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
        R, P = np.meshgrid(rho, phi)
        cx, cy = f.radius * np.cos(f.angle), f.radius * np.sin(f.angle)
        x = np.stack([cx + R * np.cos(P), cy + R * np.sin(P), 0 * R]).reshape(3, -1)
        dA = (R * (a / n) * (2 * np.pi / (2 * n))).ravel()
        p = jaw(x)
        out.append((p @ dA, (p * x[0]) @ dA))
    return np.array(out)


@pytest.mark.parametrize("tilt", [0.0, 0.1, 1.0])
def test_jaw_forces_balance_the_clamp_force_and_match_the_footprint_integral(floating, tilt):
    g = tilted(floating, tilt)
    F = 1e6 * g.clamp_area
    jaw = jaw_pressure(g, F)
    assert sum(jaw.forces) == pytest.approx(F, rel=1e-12)
    assert jaw.theta == pytest.approx(tilt * 1e-6 * F, rel=1e-15)
    ref = reference(g, jaw)
    assert np.allclose(jaw.forces, ref[:, 0], rtol=1e-4, atol=0)
    if tilt == 0.0:                              # a rigid bridge: a uniform pressure
        assert jaw.delta * jaw.stiffness == pytest.approx(F / (2 * g.caliper.fingers[0].area))
    if tilt == 1.0:                              # a soft bridge lifts the inner edges
        f = g.caliper.fingers[0]
        inner = np.array([[f.radius * np.cos(f.angle) - 0.45 * f.diameter], [0.0], [0.0]])
        assert jaw(inner)[0] == 0.0


def test_a_jaw_that_is_not_one_is_refused(floating):
    with pytest.raises(SceneError, match="bridge_tilt = -1e-07 rad/N"):
        jaw_pressure(replace(floating, caliper=replace(floating.caliper, bridge_tilt=-1e-7)), 1.0)


def test_full_contact_centre_in_closed_form(floating):
    # full contact over a disc of radius a: the centre moves out by a B / (4 A)
    g = tilted(floating, 0.05)
    jaw = jaw_pressure(g, 1e6 * g.clamp_area)
    f = g.caliper.fingers[0]
    a, s = 0.5 * f.diameter, f.radius * np.cos(f.angle)
    A, B = jaw.delta + jaw.theta * s, jaw.theta * a
    assert A > B > 0                             # the whole footprint is pressed
    ref = reference(g, jaw)
    assert ref[0, 1] / ref[0, 0] == pytest.approx(s + a * B / (4 * A), rel=1e-7)


@pytest.mark.parametrize("tilt, order, size", [(0.05, 1, 3e-3), (1.0, 1, 3e-3), (1.0, 2, 6e-3)])
def test_nodal_loads_carry_the_jaw_force_and_centre(floating, tilt, order, size):
    g = tilted(floating, tilt)
    both = mirrored_pads(pad_mesh(g, size=size, order=order), -0.5 * g.rotor.thickness)
    F = 1e6 * g.clamp_area
    f = clamp_loads(g, both, 1e6, full=True, sides=("out",)).reshape(-1, 3)
    assert f.sum(axis=0) == pytest.approx([0.0, 0.0, F], abs=1e-12 * F)
    ref = reference(g, jaw_pressure(g, F)).sum(axis=0)
    assert f[:, 2] @ both.p[0] / F == pytest.approx(ref[1] / ref[0], abs=0.02 * size)
    # linear: the load at three times the line pressure is three times the load
    f3 = clamp_loads(g, both, 3e6, full=True, sides=("out",)).reshape(-1, 3)
    assert np.allclose(f3, 3 * f, rtol=0, atol=1e-10 * F)


def test_a_stiff_bridge_gives_the_rigid_bridge_loads(floating):
    both = mirrored_pads(pad_mesh(floating, size=6e-3), -0.5 * floating.rotor.thickness)
    rigid = clamp_loads(floating, both, 1e6, full=True, sides=("out",))
    stiff = clamp_loads(tilted(floating, 1e-7), both, 1e6, full=True, sides=("out",))
    F = 1e6 * floating.clamp_area
    assert np.abs(stiff - rigid).max() < 1e-5 * F


def test_a_softer_bridge_moves_the_outboard_pressure_out(floating):
    cops, pins = [], []
    for tilt in (0.0, 0.1, 0.3):
        g = tilted(floating, tilt)
        m = BrakeModel(g, size=6e-3)
        res = solve_contact(m, 1e6, mu=0.4)
        s = static_summary(m, res)["faces"]
        cops.append([s[face]["centre_of_pressure_r_m"] for face in ("in", "out")])
        bal = pad_balance(m, res, 1e6)
        for face in ("in", "out"):
            assert bal[face]["force"] < 1e-8 and bal[face]["moment"] < 1e-8
        F = 1e6 * g.clamp_area
        ref = reference(g, jaw_pressure(g, F)).sum(axis=0)
        pins.append((bal["caliper"]["pin_moment_Nm"][1], F * ref[1] / ref[0]))
    cops = np.array(cops)
    d_in, d_out = np.diff(cops[:, 0]), np.diff(cops[:, 1])
    assert np.all(d_out > 1e-4), cops               # out by more than 0.1 mm per step
    assert np.all(np.abs(d_in) < 0.2 * d_out), cops
    # the pins carry the moment of the jaw's resultant about the piston's line:
    # it grows with the tilt as the jaw's centre moves out
    moments = np.array(pins)
    assert np.all(np.diff(moments[:, 0]) > 0)
    offsets = moments[:, 0] - moments[:, 1]          # minus F x_jaw: the piston's share
    assert np.allclose(offsets, offsets[0], rtol=0.02)


def test_the_study_tapers_the_outboard_wear(tmp_path):
    from studyload import load_study
    bt = load_study("bridge_tilt")
    mesh = bt.MESH | {"size": 6e-3, "pad_size": 6e-3, "rotor_size": 12e-3,
                      "friction_layers": 2, "backplate_layers": 2, "rotor_layers": 1}
    res = bt.main((0.0, 0.2), mesh, hours=0.25, steps=2, out=tmp_path)
    rigid, soft = (r["worn"]["faces"] for r in res["rows"])
    assert soft["out"]["taper"] > rigid["out"]["taper"] + 0.05
    assert soft["in"]["taper"] == pytest.approx(rigid["in"]["taper"], abs=0.02)
    # the same work on each face: the bridge moves wear, it does not make more
    for face in ("in", "out"):
        assert soft[face]["mean_um"] == pytest.approx(rigid[face]["mean_um"], rel=0.05)
    for name in ("data/bridge_tilt.json", "data/bridge_tilt.csv", "figures/bridge_tilt.png"):
        assert (tmp_path / name).stat().st_size > 0
