"""Friction and wear laws per node: the per-node calls of the existing laws."""
import numpy as np
import pytest

from brakewear.errors import InputError
from brakewear.laws import FrictionLaw, WearLaw

#: nodes of a contact: pressures (Pa, with tension and lift-off), speeds (m/s), T (K)
P = np.array([-2e5, 0.0, 3e5, 1.2e6, 4.7e6, 7.9e6])
V = np.array([2.0, 5.5, 11.0, 17.0, 23.0, 29.0])
T = np.array([300.0, 350.0, 420.0, 500.0, 610.0, 700.0])


# ---------------------------------------------------------------- the existing laws --

def test_existing_laws_answer_per_node_with_their_own_numbers():
    mu = FrictionLaw(0.4)
    assert not mu.needs_temperature
    np.testing.assert_array_equal(mu.mu_at(P, V), np.full(P.shape, 0.4))
    fade = FrictionLaw(0.42, slope=-4e-4, T_ref=623.15, mu_min=0.2)
    assert fade.needs_temperature
    np.testing.assert_array_equal(fade.mu_at(P, V, T), fade.mu(T))
    assert fade.mu_at(P, V).shape == P.shape          # T None: mu0 at every node

    k = WearLaw(5e-15)
    assert not k.needs_temperature and (k.a, k.b) == (1.0, 1.0)
    np.testing.assert_array_equal(k.coefficient_at(P, V), np.full(P.shape, 5e-15))
    np.testing.assert_array_equal(k.rate(P, V), 5e-15 * np.clip(P, 0, None) * V)
    hot = WearLaw(5e-15, T_threshold=503.15, activation_energy=8e4)
    assert hot.needs_temperature
    np.testing.assert_array_equal(hot.coefficient_at(P, V, T), hot.coefficient(T))
    # one node's speed broadcast against the nodes' pressures
    assert hot.coefficient_at(P[:, None], 3.0, T[None, :]).shape == (6, 6)


def test_a_layered_rotor_law_gives_the_coefficient_its_rate_uses():
    from brakewear.cleaning import LayeredWearLaw

    law = LayeredWearLaw(2e-14, factor=np.array([1.0, 1.0, 0.05, 0.05, 1.0, 0.05]))
    k = law.coefficient_at(P, V)
    np.testing.assert_array_equal(k, 2e-14 * law.factor)
    np.testing.assert_allclose(law.rate(P, V), k * np.clip(P, 0, None) * V, rtol=1e-15)


@pytest.mark.parametrize("law", [FrictionLaw(0.4), WearLaw(5e-15)])
def test_existing_laws_refuse_a_negative_speed(law):
    call = law.mu_at if isinstance(law, FrictionLaw) else law.coefficient_at
    with pytest.raises(InputError, match=r"sliding speed -2\.0 m/s"):
        call(P, -V)
