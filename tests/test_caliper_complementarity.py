"""The complementarity fallback of the caliper's joint solve
(brakewear.caliper.complementarity) on small constructed problems: a mixed
problem (contact-like pairs, an equality, a normal row and its friction row)
with a known solution, slipping and sticking; and a 3x3 P-matrix problem on
which the plain Newton-min (primal-dual active-set) iteration cycles from six of
its eight starting states (Ben Gharbia & Gilbert, Math. Programming 134, 2012,
349-364) while both damped methods find its solution."""
import itertools

import numpy as np
import pytest
import scipy.sparse as sp

from brakewear.caliper.complementarity import (
    SLIP_DOWN_CODE,
    SLIP_UP_CODE,
    StateProblem,
    damped_newton,
    fischer_newton,
    solve_states,
)
from brakewear.errors import ComplementarityError
from brakewear.solvers.kept_factorisation import FULL, IDENT, SingularState

TOL = 1e-12          # relative to the problem's largest unknown or residual


def _problem(M, b, comp, fr=(), normal=None, mu=()):
    N = b.size
    fr = np.asarray(fr, dtype=int)
    normal = sp.csr_matrix((0, N)) if normal is None else sp.csr_matrix(normal)
    mu = np.asarray(mu, dtype=float)

    def solve(code):
        A, r = np.eye(N), np.zeros(N)
        full = code == FULL
        A[full], r[full] = M[full], b[full]
        for j, k in enumerate(fr):
            if code[k] in (SLIP_UP_CODE, SLIP_DOWN_CODE):
                s = 1.0 if code[k] == SLIP_UP_CODE else -1.0
                A[k] = -s * mu[j] * normal[j].toarray()[0]
                A[k, k] += 1.0
        if abs(np.linalg.det(A)) < 1e-12 * np.abs(A).max() ** N:
            raise SingularState("singular state (test)")
        return np.linalg.solve(A, r)

    return StateProblem(M, b, np.ones(N), np.ones(N), np.asarray(comp), fr, normal, mu, solve)


def _conditions(prob, z):
    """The largest violation of the problem's conditions at ``z``, relative."""
    w = prob.residual(z)
    size = max(np.abs(z).max(), np.abs(w).max(), 1e-300)
    c, f, e = prob.comp, prob.fr, prob.eq
    v = [np.maximum(-z[c], 0).max(initial=0), np.maximum(-w[c], 0).max(initial=0),
         np.abs(z[c] * w[c]).max(initial=0) / size, np.abs(w[e]).max(initial=0)]
    if f.size:
        N = prob.normal @ z
        bound = prob.mu * np.maximum(N, 0)
        v.append(np.maximum(np.abs(z[f]) - bound, 0).max())
        slip_up, slip_down = z[f] >= bound * (1 - 1e-9), z[f] <= -bound * (1 - 1e-9)
        stick = ~(slip_up | slip_down)
        v += [np.abs(w[f][stick]).max(initial=0), np.maximum(w[f][slip_up], 0).max(initial=0),
              np.maximum(-w[f][slip_down], 0).max(initial=0)]
    return max(v) / size


def _accept(prob):
    return lambda code, z: _conditions(prob, z) <= TOL


def _mixed(slip: bool):
    """Four contact-like pairs (two closed, two open), an equality, a normal row
    (closed) and its friction row (slipping up, or sticking): the solution ``z*``
    and ``b = M z* - w*`` chosen."""
    rng = np.random.default_rng(3)
    B = rng.normal(size=(7, 7))
    M = B @ B.T + 7.0 * np.eye(7)
    mu = 0.3
    z = np.array([0.5, 0.0, 0.3, 0.0, 0.7, 0.4, mu * 0.4 if slip else 0.05])
    w = np.array([0.0, 0.2, 0.0, 0.1, 0.0, 0.0, -0.05 if slip else 0.0])
    normal = np.zeros((1, 7))
    normal[0, 5] = 1.0
    prob = _problem(M, M @ z - w, [0, 1, 2, 3, 5], [6], normal, [mu])
    return prob, z


@pytest.mark.parametrize("slip", [True, False])
@pytest.mark.parametrize("method", [damped_newton, fischer_newton])
def test_a_mixed_problem_with_a_known_solution(method, slip):
    prob, z_star = _mixed(slip)
    code, z, its = method(prob, np.zeros(7), _accept(prob))
    assert np.abs(z - z_star).max() <= 1e-12 * np.abs(z_star).max()
    expected = np.array([FULL, IDENT, FULL, IDENT, FULL, FULL,
                         SLIP_UP_CODE if slip else FULL])
    assert np.array_equal(code, expected)
    assert its < 20


# the plain Newton-min iteration cycles on this P-matrix problem (solution: 1/3 each)
_M3 = np.array([[1.0, 2.0, 0.0], [0.0, 1.0, 2.0], [2.0, 0.0, 1.0]])
_B3 = np.ones(3)


def _plain_newton_min(prob, code, max_iter=20):
    """The plain (full-step) Newton-min iteration from ``code``: the codes met."""
    seen = []
    for _ in range(max_iter):
        z = prob.solve(code)
        seen.append(code.tobytes())
        new = prob.code(z, prob.residual(z))
        if np.array_equal(new, code) or new.tobytes() in seen:
            return seen, bool(np.array_equal(new, code))
        code = new
    return seen, False


@pytest.mark.parametrize("start", [c for c in itertools.product([IDENT, FULL], repeat=3)
                                   if len(set(c)) > 1])
def test_the_damped_methods_solve_a_problem_the_plain_iteration_cycles_on(start):
    prob = _problem(_M3, _B3, [0, 1, 2])
    code0 = np.array(start, dtype=np.int8)
    seen, settled = _plain_newton_min(prob, code0)
    assert not settled and len(seen) >= 3               # the plain iteration cycles
    z0 = prob.solve(code0)
    for method in (damped_newton, fischer_newton):
        code, z, _ = method(prob, z0, _accept(prob))
        assert np.abs(z - 1.0 / 3.0).max() <= 1e-14
        assert np.array_equal(code, np.full(3, FULL))


def test_no_solution_is_a_named_error_with_its_figures():
    """``z >= 0, Mz - b >= 0`` infeasible (M = -1, b = 1): neither method finds a state."""
    prob = _problem(-np.eye(2), np.ones(2), [0, 1])
    with pytest.raises(ComplementarityError) as e:
        solve_states(prob, np.zeros(2), _accept(prob), "test problem")
    assert "test problem" in str(e.value)
    assert {"newton_iterations", "fischer_iterations", "fischer_merit"} <= set(e.value.figures)
