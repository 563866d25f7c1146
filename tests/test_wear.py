"""Wear laws and the conservative pad/rotor wear distribution."""
import numpy as np
import pytest

from brakewear.contact import pair_to_surface
from brakewear.errors import WearError
from brakewear.geometry import load_geometry
from brakewear.laws.base import WearLaw
from brakewear.mesh import pad_mesh, rotor_mesh
from brakewear.mesh.rings import rotor_rings, rotor_wear_rate
from brakewear.mesh.surface import surface_nodes, tributary_areas


def test_archard_is_k_p_v_and_rhee_exponents():
    law = WearLaw(k=5e-15)
    assert law.rate(2e6, 10.0) == pytest.approx(5e-15 * 2e6 * 10.0)
    assert law.rate(-1e6, 10.0) == 0.0  # tension does not wear
    rhee = WearLaw(k=1e-12, a=0.8, b=1.2)
    assert rhee.rate(1e6, 5.0) == pytest.approx(1e-12 * 1e6 ** 0.8 * 5.0 ** 1.2)


def test_arrhenius_above_threshold_only():
    law = WearLaw(k=1e-15, T_threshold=503.15, activation_energy=60e3)
    assert law.coefficient(400.0) == law.k  # below the threshold: base value
    k600 = law.coefficient(600.0)
    assert k600 == pytest.approx(1e-15 * np.exp(60e3 / 8.314462618 * (1 / 503.15 - 1 / 600)))
    assert k600 > 3 * law.k  # steep rise above ~230 C


@pytest.mark.parametrize("kw,field", [({"k": 0.0}, "k"), ({"k": -1e-15}, "k"),
                                      ({"k": 1e-15, "a": 0}, "a"),
                                      ({"k": 1e-15, "activation_energy": -1}, "activation")])
def test_bad_wear_input_names_the_parameter(kw, field):
    with pytest.raises(WearError, match=field):
        WearLaw(**kw)


def test_negative_speed_is_refused():
    with pytest.raises(WearError, match="speed"):
        WearLaw(k=1e-15).rate(1e6, -1.0)


def test_rotor_wear_conserves_volume_on_the_default_brake():
    g = load_geometry("default")
    pad, rotor = pad_mesh(g, size=6e-3), rotor_mesh(g, size=6e-3)
    pr = pair_to_surface(pad, "friction", 0, rotor, "friction", 0, n_nodes=rotor.nvertices)
    rng = np.random.default_rng(2)
    p = rng.uniform(0, 2e6, pr.slave.size)
    x = pad.p[:, pr.slave]
    v = 60.0 * np.hypot(x[0], x[1])
    law = WearLaw(k=5e-16)
    q = law.rate(p, v) * pr.area  # m^3/s removed from the rotor at each pad node
    face = surface_nodes(rotor, "friction")
    W = pr.coupling[:, face]
    ring, radii = rotor_rings(np.hypot(rotor.p[0, face], rotor.p[1, face]))
    A = tributary_areas(rotor, "friction", face)
    dh = rotor_wear_rate(q, W, ring, A)
    assert abs((dh * A).sum() - q.sum()) / q.sum() < 1e-12
    # the rotor wear is a function of radius alone
    for j in range(radii.size):
        assert np.ptp(dh[ring == j]) <= 1e-12 * dh.max()
    # rings outside the pad's radial band do not wear
    outside = (radii < g.pad.inner_radius - 6e-3) | (radii > g.pad.outer_radius + 6e-3)
    assert np.all(dh[np.isin(ring, np.nonzero(outside)[0])] == 0)


def test_a_law_that_sets_k_per_node_sets_its_rate_too():
    """The wear loop reads ``coefficient_at``; ``rate`` goes through it, so a law that
    changes k per node (a corroded ring's layer) changes both alike."""
    import numpy as np

    from brakewear.cleaning.corrosion import LayeredWearLaw
    factor = np.array([1.0, 5e-4, 1.0])
    law = LayeredWearLaw(1e-12, factor=factor)
    p, v = np.array([1e6, 1e6, 2e6]), np.array([10.0, 10.0, 5.0])
    assert np.allclose(law.rate(p, v), law.coefficient_at(p, v) * p * v, rtol=1e-15, atol=0)
    assert np.allclose(law.rate(p, v), 1e-12 * factor * p * v, rtol=1e-15, atol=0)
