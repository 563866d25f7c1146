"""The caliper's contact and rows as one complementarity problem: damped Newton methods.

The pad-rotor contact held by the caliper's rows (:mod:`brakewear.caliper.joint`)
is a mixed complementarity problem in the unknowns ``z = (lam_c, alpha, lam_s,
q)`` of :class:`~brakewear.caliper.joint.JointSets`'s system, with ``w(z) = M z -
b`` the residuals of its equations in their holding form (the contact nodes'
gaps with the wear step's compliance, the rows' gaps and slips, the pads' free
modes' and the rigid parts' equilibrium):

    contact nodes, normal rows:  lam_k >= 0,  w_k >= 0,  lam_k w_k = 0,
    friction rows:               lam_k = proj[-mu_k N_k, mu_k N_k](lam_k - w_k),
                                 N_k = cap_k lam_s (Coulomb's law on the row's surface),
    free modes, rigid parts:     w_k = 0.

:class:`StateProblem` holds it: ``M``, ``b``, the equations' kinds, an
equilibration, and the exact solve of a *state* (each contact node and normal
row closed or open, each friction row sticking, slipping either way, or off:
one linear system, :meth:`JointSets._solve_code` on the kept factorisation).

Written as ``Phi(z) = 0`` with ``min(lam_k, w_k)`` and ``lam_k - proj(...)`` --
each unknown in the units of its column scale and each equation in those of
its row scale, so that the two arguments of a ``min`` are of one size --
``Phi`` is piecewise linear, and on each of its pieces it is the system of one
state.  The Newton step from ``z`` is therefore the solution ``z_N`` of the
state whose signs ``z`` selects -- the next iterate of a primal-dual
active-set iteration.  Full steps can cycle between states: a pad whose
contact resultant sits at the edge of its finger rows' footprint tips one
way in one state and back in the next.  :func:`damped_newton` takes a step
only as far as it reduces the merit ``theta = |Phi|^2 / 2`` by a share of its
directional derivative (Armijo's rule, halving the step): the damped Newton
method of Harker & Pang for complementarity problems in B-differentiable form
(Math. Programming 48, 1990, 339-357; Pang, Math. Programming 51, 1991,
101-131).  ``w`` is linear along the segment ``z + t (z_N - z)``, so the
trial steps cost no solve: one solve per iteration.  A state that leaves an
unknown undetermined (a rigid part free) is replaced by the state with the
open complementary equations nearest to closing closed, as many as hold it.

Where that method stalls (a singular piece, or a direction along which the
merit does not decrease), :func:`fischer_newton` minimises the merit of the
Fischer-Burmeister form (``a + b - sqrt(a^2 + b^2)`` for each complementary
pair, continuously differentiable squared) by Newton steps, Levenberg-Marquardt
steps where Newton's is not a descent direction, and Armijo's rule: a descent
method whose limit points are stationary points of the merit, which solve the
problem where the system is a P0 matrix (De Luca, Facchinei & Kanzow, Math.
Programming 75, 1996, 407-439).

Every iterate's state is solved exactly and offered to the caller's
``accept`` (the active-set solves' own tolerances: a contact node's tension
and an open node's penetration, a row's force and gap, a friction row's force
against its bound); only a state that passes is returned, so the answer is
the exact solution of a state that satisfies complementarity.
:func:`solve_states` runs both methods and raises
:class:`~brakewear.errors.ComplementarityError`, with its figures, when neither
finds one.
"""
from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..errors import ComplementarityError, SolverError
from ..solvers.kept_factorisation import FULL, IDENT, SingularState

logger = logging.getLogger(__name__)

__all__ = ["StateProblem", "damped_newton", "fischer_newton", "solve_states", "MAX_NEWTON",
           "MAX_FISCHER", "SLIP_UP_CODE", "SLIP_DOWN_CODE"]

#: Newton iterations before a method gives up (damped Newton, Fischer-Burmeister)
MAX_NEWTON, MAX_FISCHER = 100, 200
#: Armijo's constant and the shortest step tried
_SIGMA, _T_MIN = 1e-4, 2.0 ** -40
#: equation codes of slipping friction rows (``lam_k = +-mu_k N_k``), beyond IDENT and FULL
SLIP_UP_CODE, SLIP_DOWN_CODE = 2, 3


@dataclass
class StateProblem:
    """A mixed complementarity problem whose pieces are linear systems (see the module).

    Attributes
    ----------
    M, b
        (N, N) every equation in its holding form and (N,) the right-hand side:
        ``w = M z - b``.
    dr, dc
        (N,) row and column scales (the equilibration the ``min`` is taken in).
    comp, fr
        Indices of the complementary equations (``z_k >= 0``, ``w_k >= 0``) and of
        the friction equations; every other equation is an equality.
    normal, mu
        (len(fr), N) sparse: each friction row's normal force ``N_k = normal_k z``;
        (len(fr),) its friction coefficient.
    solve
        ``solve(code) -> z``: the exact solution of a state's system (equation
        ``k`` the identity ``z_k = 0`` for :data:`IDENT`, ``w_k = 0`` for
        :data:`FULL`, ``z_k = +-mu_k N_k`` for the slip codes); raises
        :class:`~brakewear.solvers.kept_factorisation.SingularState`.
    """

    M: np.ndarray
    b: np.ndarray
    dr: np.ndarray
    dc: np.ndarray
    comp: np.ndarray
    fr: np.ndarray
    normal: sp.csr_matrix
    mu: np.ndarray
    solve: Callable[[np.ndarray], np.ndarray]

    def __post_init__(self):
        N = self.b.size
        eq = np.ones(N, dtype=bool)
        eq[self.comp] = eq[self.fr] = False
        self.eq = np.nonzero(eq)[0]
        self.normal = sp.csr_matrix(self.normal)
        self.pattern = (abs(self.normal) > 0).astype(float)   # a friction row's normal rows

    def residual(self, z: np.ndarray) -> np.ndarray:
        return self.M @ z - self.b

    def bound(self, z: np.ndarray) -> np.ndarray:
        """Each friction row's bound ``mu_k max(N_k, 0)`` in its scaled unknown."""
        return self.mu * np.maximum(self.normal @ z, 0.0) / self.dc[self.fr]

    def phi(self, z: np.ndarray, w: np.ndarray) -> np.ndarray:
        """``Phi`` (the min form, scaled) at ``z`` with ``w = M z - b``."""
        zs, ws = z / self.dc, self.dr * w
        out = ws.copy()
        c, f = self.comp, self.fr
        out[c] = np.minimum(zs[c], ws[c])
        bnd = self.bound(z)
        out[f] = zs[f] - np.clip(zs[f] - ws[f], -bnd, bnd)
        return out

    def code(self, z: np.ndarray, w: np.ndarray) -> np.ndarray:
        """The state whose piece of ``Phi`` holds at ``z``: a friction row is off when
        none of its normal rows is closed (as the rows' states have it)."""
        zs, ws = z / self.dc, self.dr * w
        code = np.full(zs.size, FULL, dtype=np.int8)
        c, f = self.comp, self.fr
        code[c] = np.where(zs[c] > ws[c], FULL, IDENT)
        on = (self.pattern @ (code == FULL).astype(float)) > 0
        bnd = self.bound(z)
        d = zs[f] - ws[f]
        fc = np.where(d > bnd, SLIP_UP_CODE, np.where(d < -bnd, SLIP_DOWN_CODE, FULL))
        code[f] = np.where(on, fc, IDENT).astype(np.int8)
        return code

    def scaled(self) -> np.ndarray:
        """``M`` in the scaled unknowns and equations (made once)."""
        if getattr(self, "_As", None) is None:
            self._As = self.dr[:, None] * self.M * self.dc[None, :]
        return self._As

    def fischer(self, z: np.ndarray, w: np.ndarray):
        """``(Phi_FB, J)``: the Fischer-Burmeister form of the complementary equations,
        the others as :meth:`phi`, and an element of its generalised Jacobian in the
        scaled unknowns."""
        dr, dc = self.dr, self.dc
        zs, ws = z / dc, dr * w
        As = self.scaled()
        out = ws.copy()
        J = As.copy()
        c = self.comp
        a, b = zs[c], ws[c]
        r = np.hypot(a, b)
        tiny = r <= 1e-300
        r = np.where(tiny, 1.0, r)
        da = np.where(tiny, 1.0 - np.sqrt(0.5), 1.0 - a / r)
        db = np.where(tiny, 1.0 - np.sqrt(0.5), 1.0 - b / r)
        out[c] = a + b - np.where(tiny, 0.0, r)
        J[c] = db[:, None] * As[c]
        J[c, c] += da
        f = self.fr
        bnd = self.bound(z)
        d = zs[f] - ws[f]
        out[f] = zs[f] - np.clip(d, -bnd, bnd)
        dbnd = (self.mu / dc[f])[:, None] * self.normal.toarray() * dc[None, :]
        dbnd[bnd <= 0] = 0.0
        up, down = d >= bnd, d <= -bnd
        stick = ~(up | down)
        J[f[~stick]] = 0.0
        J[f[~stick], f[~stick]] = 1.0
        J[f[up]] -= dbnd[up]
        J[f[down]] += dbnd[down]
        return out, J


def _newton_point(prob: StateProblem, code, z, w):
    """``(code, z_N)``: the solution of the state ``code``, or when that leaves an
    unknown undetermined (a body held by nothing), of the state with its open
    complementary equations closed, the nearest to closing first (the smallest
    ``w - lam`` in the scaled units), 1, 2, 4, ..., all of them until one is regular."""
    try:
        return code, prob.solve(code)
    except SingularState:
        pass
    c = prob.comp
    shut = c[code[c] == IDENT]
    order = shut[np.argsort(prob.dr[shut] * w[shut] - z[shut] / prob.dc[shut], kind="stable")]
    ks = [k for k in (2 ** np.arange(max(int(np.log2(max(order.size, 1))) + 1, 1)))
          if k < order.size] + [order.size]
    for k in ks:
        fix = code.copy()
        fix[order[:k]] = FULL
        try:
            return fix, prob.solve(fix)
        except SingularState:
            continue
    raise SolverError("a state leaves an unknown undetermined whatever it closes "
                      f"({order.size} open complementary equations)")


def damped_newton(prob: StateProblem, z0: np.ndarray, accept,
                  max_iter: int = MAX_NEWTON):
    """The problem ``prob`` from ``z0`` by the damped Newton method (see the module).

    Parameters
    ----------
    prob
        The :class:`StateProblem`.
    z0
        The start (unscaled unknowns).
    accept
        ``accept(code, z) -> bool``: whether the state ``code`` with its exact
        solution ``z`` satisfies complementarity within the caller's tolerances.

    Returns
    -------
    tuple
        ``(code, z, iterations)``: the state found and its solution.

    Raises
    ------
    SolverError
        No state found in ``max_iter`` iterations, or the merit does not decrease
        along a Newton direction (its figures named).
    """
    z = np.asarray(z0, dtype=float).copy()
    w = prob.residual(z)
    phi = prob.phi(z, w)
    theta = theta0 = 0.5 * float(phi @ phi)
    for it in range(1, max_iter + 1):
        code, zN = _newton_point(prob, prob.code(z, w), z, w)
        if accept(code, zN):
            return code, zN, it
        wN = prob.residual(zN)
        dz, dw = zN - z, wN - w
        t = 1.0
        while True:
            pt = prob.phi(z + t * dz, w + t * dw)
            th = 0.5 * float(pt @ pt)
            if th <= (1.0 - 2.0 * _SIGMA * t) * theta:
                break
            t *= 0.5
            if t < _T_MIN:
                raise SolverError(
                    f"damped Newton: the merit |Phi|^2/2 = {theta:.3g} (from {theta0:.3g}) "
                    f"does not decrease along the Newton direction after {it} iterations",
                    figures={"iterations": it, "merit": theta})
        z, w, theta = z + t * dz, w + t * dw, th
        logger.debug("damped Newton %d: step %.3g, merit %.3g", it, t, theta)
    raise SolverError(f"damped Newton: no state found in {max_iter} iterations (merit "
                      f"{theta:.3g} from {theta0:.3g})",
                      figures={"iterations": max_iter, "merit": theta})


def fischer_newton(prob: StateProblem, z0: np.ndarray, accept,
                   max_iter: int = MAX_FISCHER):
    """The problem ``prob`` by Newton and Levenberg-Marquardt steps on its
    Fischer-Burmeister merit (see the module; arguments, result and errors as
    :func:`damped_newton`)."""
    z = np.asarray(z0, dtype=float).copy()
    w = prob.residual(z)
    phi, J = prob.fischer(z, w)
    psi = psi0 = 0.5 * float(phi @ phi)
    dc, dr, As = prob.dc, prob.dr, prob.scaled()
    for it in range(1, max_iter + 1):
        try:
            code, zc = _newton_point(prob, prob.code(z, w), z, w)
            if accept(code, zc):
                return code, zc, it
        except SolverError:
            pass
        g = J.T @ phi
        ds, slope = None, 0.0
        try:
            ds = -np.linalg.solve(J, phi)
            slope = float(g @ ds)
        except np.linalg.LinAlgError:
            pass
        if ds is None or not np.all(np.isfinite(ds)) or \
                not slope <= -1e-12 * float(ds @ ds) ** 1.05:
            # not a descent direction of the merit: Levenberg-Marquardt's
            A = J.T @ J
            nu = max(2.0 * psi, 1e-14 * float(np.abs(np.diag(A)).max()))
            A[np.diag_indices_from(A)] += nu
            ds = -np.linalg.solve(A, g)
            slope = float(g @ ds)
        dz, dw = ds * dc, (As @ ds) / dr
        t = 1.0
        while True:
            zt, wt = z + t * dz, w + t * dw
            pt, Jt = prob.fischer(zt, wt)
            pst = 0.5 * float(pt @ pt)
            if pst <= psi + _SIGMA * t * slope:
                break
            t *= 0.5
            if t < _T_MIN:
                raise SolverError(
                    f"Fischer-Burmeister: the merit {psi:.3g} (from {psi0:.3g}) does not "
                    f"decrease after {it} iterations", figures={"iterations": it, "merit": psi})
        z, w, phi, J, psi = zt, wt, pt, Jt, pst
        logger.debug("Fischer-Burmeister %d: step %.3g, merit %.3g", it, t, psi)
    raise SolverError(f"Fischer-Burmeister: no state found in {max_iter} iterations (merit "
                      f"{psi:.3g} from {psi0:.3g})",
                      figures={"iterations": max_iter, "merit": psi})


def solve_states(prob: StateProblem, z0: np.ndarray, accept, what: str = "complementarity"):
    """The damped Newton method, then the Fischer-Burmeister one (see the module).

    Parameters
    ----------
    prob, z0, accept
        As :func:`damped_newton`.
    what
        The problem's name in messages.

    Returns
    -------
    tuple
        ``(code, z, iterations, method)``: the state found, its solution, the
        iterations of both methods and the method that found it
        (``"newton"`` or ``"fischer"``).

    Raises
    ------
    ComplementarityError
        Neither method finds a state (both methods' figures).
    """
    try:
        code, z, its = damped_newton(prob, z0, accept)
        return code, z, its, "newton"
    except SolverError as e:
        logger.info("%s: %s; Fischer-Burmeister", what, e)
        first = e
    try:
        code, z, its = fischer_newton(prob, z0, accept)
    except SolverError as e:
        figures = {"newton_" + k: v for k, v in first.figures.items()}
        figures.update({"fischer_" + k: v for k, v in e.figures.items()})
        raise ComplementarityError(f"{what}: no state satisfies complementarity: {first}; "
                                   f"{e}", figures=figures) from e
    return code, z, first.figures.get("iterations", MAX_NEWTON) + its, "fischer"
