"""Thermal coupling of a model of quadratic (P2) tetrahedra: a linear temperature on
its vertices (brakewear.thermal.quadratic).

Checked: the interpolation to the P2 nodes; uniform warming of a free body is
stress-free to round-off (the thermal-strain load of a P1 temperature on P2 test
functions is the one the P2 stiffness balances exactly); the heat that enters is
the friction power over the P2 face, to round-off; a thermal wear run on P2
agrees with the same run on P1 elements of the same vertices.
"""
import numpy as np
import pytest

from brakewear import Numerics, WearLaw
from brakewear.errors import ThermalError
from brakewear.geometry import load_geometry
from brakewear.interfaces import FEInterface
from brakewear.model import BrakeModel
from brakewear.thermal import QuadraticThermal, ThermalModel, vertex_interpolation
from brakewear.wear import Run, wear_history

SIZE = 9e-3
PAD, ROTOR = WearLaw(5e-15), WearLaw(5e-16)


@pytest.fixture(scope="module")
def models():
    g = load_geometry()
    return {order: BrakeModel(g, size=SIZE, order=order) for order in (1, 2)}


def test_a_p2_model_gets_the_vertex_field(models):
    th = ThermalModel(models[2])
    assert isinstance(th, QuadraticThermal)
    assert isinstance(ThermalModel(models[1]), ThermalModel)
    for b in th.bodies:
        mesh = models[2].meshes[b]
        assert th.vertex_model.T[b].size == mesh.nvertices
        assert th.T[b].size == mesh.p.shape[1]
    with pytest.raises(ThermalError, match="not supported with P2"):
        th.follow(models[2])


def test_vertex_interpolation_is_the_linear_field(models):
    mesh = models[2].meshes["rotor"]
    I = vertex_interpolation(mesh)
    assert np.allclose(np.asarray(I.sum(axis=1)).ravel(), 1.0, rtol=0, atol=1e-15)
    # z is linear along every edge (the arcs lie in planes of constant z)
    z = mesh.p[2]
    assert np.allclose(I @ z[:mesh.nvertices], z, rtol=0, atol=1e-12 * np.abs(z).max())


def test_uniform_warming_of_a_free_body_is_stress_free(models):
    m = models[2]
    th = ThermalModel(m)
    dT = 80.0
    T = {b: np.full(th.vertex_model.T[b].size, th.T_ref + dT) for b in th.bodies}
    f = th.thermal_load(T)
    mesh = m.meshes["rotor"]                                   # one material
    o = 3 * m.offsets["rotor"]
    f_rotor = f[o:o + 3 * mesh.p.shape[1]]
    alpha = m.geometry.rotor.material.thermal.alpha
    u = (alpha * dT * mesh.p.T).ravel()                        # free expansion, DOF 3 s + i
    r = m.stiffness("rotor") @ u - f_rotor
    assert np.linalg.norm(r) < 1e-10 * np.linalg.norm(f_rotor)
    # and the thermal stress of that expansion is zero
    th.vertex_model.T = T
    pad_u = np.zeros(3 * m.meshes["pad"].p.shape[1])
    sig = th.stresses({"rotor": u, "pad": pad_u})["rotor"]
    E = m.geometry.rotor.material.elastic.E
    assert np.abs(sig).max() < 1e-9 * E * alpha * dT


def test_the_heat_in_is_the_friction_power_over_the_p2_face(models):
    th = ThermalModel(models[2])
    rng = np.random.default_rng(3)
    q = 1e5 * rng.random(th.pad_nodes.size)
    th.step(q, 0.5)
    b = th.heat_balance()
    assert b["friction_power_W"] == pytest.approx(q @ th.pad_area, rel=1e-12)
    assert b["relative_error"] < 1e-10
    with pytest.raises(ThermalError, match="one value per P2 pad friction node"):
        th.step(q[:-1], 0.5)


def test_a_thermal_wear_run_on_p2_agrees_with_p1(models):
    rise = {}
    for order, m in models.items():
        th = ThermalModel(m)
        itf = FEInterface(m, 1e6, 0.4)
        for s in wear_history(
            Run(
                m,
                1e6,
                55.0,
                60.0,
                PAD,
                ROTOR,
                0.4,
                interface=itf,
                thermal=th,
                numerics=Numerics(scheme="implicit", update="gap", steps=6),
            )
        ):
            assert s.heat_balance_error < 1e-10
        T0 = th.T_ambient
        rise[order] = np.array([s.pad_temperature_max - T0, s.rotor_temperature_max - T0])
        # the pad's face temperature per P2 face node, for mu(T) and k(T)
        assert th.face_temperature("pad").shape == itf.pad_nodes.shape
        assert th.rotor_temperature_under_pad().shape == itf.pad_nodes.shape
    # a minute's drag heats both faces by about 250 K; the orders differ by the
    # pressure field (P2 resolves the backplate's bending), not by the heat
    assert np.all(rise[1] > 100.0)
    assert np.allclose(rise[2], rise[1], rtol=0.05)
