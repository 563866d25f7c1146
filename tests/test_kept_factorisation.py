"""Dense systems of switching equations on one kept LU (brakewear.solvers.kept_factorisation):
the Woodbury solves against dense solves of the same system, the reference
taken over when too many equations differ, singular systems refused, GMRES."""
import numpy as np
import pytest

from brakewear.solvers.kept_factorisation import (
    FULL,
    IDENT,
    KeptFactorisation,
    SingularState,
    gmres,
)

N = 40


def _system(seed=0):
    rng = np.random.default_rng(seed)
    Ms = rng.random((N, N)) + N * np.eye(N)

    def special(ks, codes):
        out = np.zeros((ks.size, N))
        out[np.arange(ks.size), ks] = 1.0
        out[np.arange(ks.size), (ks + 1) % N] = np.where(codes == 2, 0.3, -0.3)
        return out
    return rng, Ms, special


def _dense(kf, code):
    return kf._rows(np.asarray(code, dtype=np.int8), np.arange(N))


@pytest.mark.parametrize("changes", [0, 3, 9])
def test_a_code_near_the_reference_is_solved_to_round_off(changes):
    rng, Ms, special = _system()
    kf = KeptFactorisation(Ms, special, max_changes=12)
    ref = np.full(N, FULL, dtype=np.int8)
    ref[:8] = IDENT
    kf.set_reference(ref)
    for _ in range(5):
        code = ref.copy()
        k = rng.choice(N, changes, replace=False)
        code[k] = rng.choice([IDENT, FULL, 2, 3], changes)
        r = rng.random(N)
        r[code == IDENT] = 0.0
        z = kf.solve(kf.prepare(code), r)
        zd = np.linalg.solve(_dense(kf, code), r)
        assert np.abs(z - zd).max() <= 1e-12 * np.abs(zd).max()
    assert kf.factorised == 1                    # no new reference for these


def test_a_code_far_from_the_reference_becomes_the_reference():
    rng, Ms, special = _system(1)
    kf = KeptFactorisation(Ms, special, max_changes=4)
    code = np.full(N, FULL, dtype=np.int8)
    kf.prepare(code)
    code[:10] = IDENT
    r = np.where(code == IDENT, 0.0, rng.random(N))
    p = kf.prepare(code)
    assert kf.factorised == 2 and p.K.size == 0
    z = kf.solve(p, r)
    assert np.abs(_dense(kf, code) @ z - r).max() <= 1e-12 * np.abs(r).max()
    # the product is the system's
    assert np.allclose(kf.product(code, z), _dense(kf, code) @ z, rtol=1e-13, atol=0)


def test_a_singular_code_is_refused():
    _, Ms, special = _system(2)
    Ms = Ms.copy()
    Ms[5] = Ms[6]                                # two equal full rows
    kf = KeptFactorisation(Ms, special)
    code = np.full(N, FULL, dtype=np.int8)
    code[5] = IDENT
    kf.set_reference(code)
    code[5] = FULL
    with pytest.raises(SingularState, match="singular"):
        kf.prepare(code)


def test_gmres_solves_a_small_perturbation_of_the_identity_fast():
    rng = np.random.default_rng(3)
    P = 0.05 * rng.standard_normal((N, N)) / np.sqrt(N)
    b = rng.random(N)
    u, res, its = gmres(lambda v: v + P @ v, b, 1e-14 * np.linalg.norm(b), 30)
    assert its <= 12, its
    assert np.linalg.norm(u + P @ u - b) <= 1e-13 * np.linalg.norm(b)
    assert res <= 1e-14 * np.linalg.norm(b) * 1.01
