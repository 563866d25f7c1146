"""Coulomb friction with stick and slip on condensed contact nodes: a semi-smooth Newton.

The two bodies are condensed onto the contact nodes: ``C`` is the compliance
of their relative displacement there (m/N; ``C = C_A + Pi C_B Pi^T`` for a
slave body A and a master body B interpolated by ``Pi``), ordered per node
and per component ``(t1[, t2], n)``: the tangential components first, the
normal last.  The unknowns are the contact forces on the master body at each
node -- tangential ``T`` and normal ``N`` (compressive positive) -- the
master's rigid approach ``delta`` under the total normal load ``P``, and,
when the tangential load ``Q`` is given instead of the master's rigid shift
``s``, that shift.  With ``f`` the forces, the normal gap and the relative
tangential displacement are::

    g = g0 + (C f)_n - delta >= 0,     w = s + (C f)_t,

and Coulomb's law holds on the slip increment ``dw = w - w_prev`` of each
node (``w_prev``: the same material points' relative displacement at the
previous increment): ``|T| <= mu N``; ``dw = 0`` where ``|T| < mu N``
(stick); ``T = -mu N dw / |dw|`` where it slides (slip).

These are written, node by node, as the nonsmooth equations of Alart and
Curnier (Comput. Methods Appl. Mech. Engng 92, 1991) with a penalty-free
augmentation ``r`` (the node's normal stiffness ``1 / C_nn``)::

    N - max(0, N - r g) = 0,     T - proj(T - r dw, mu max(0, N - r g)) = 0,

with ``sum N = P`` and ``sum T = -Q`` (or ``s`` given; ``P`` and ``Q`` are the loads
applied to the master, the contact forces on it balance them), and solved by a
semi-smooth Newton method: each iteration's generalised Jacobian follows the
open / stick / slip state of every node, open nodes are eliminated (their
forces are zero), and a backtracking line search on the residual keeps the
iteration from cycling.  The answer is exact for the discrete problem to the
stated tolerance; a solve that does not reach it raises
:class:`~brakewear.errors.ConvergenceError` with its figures.

:func:`solve_sliding` is the case of gross sliding in a known direction
(pin on disc, block on ring): ``T = -mu N e`` at every node in contact, so
only the normal forces are unknown.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.linalg as la

from ..errors import ContactError, ContactLostError, ConvergenceError

logger = logging.getLogger(__name__)

__all__ = ["FrictionSolution", "solve_friction", "solve_sliding", "OPEN", "STICK", "SLIP"]

#: node states of a solution
OPEN, STICK, SLIP = 0, 1, 2


@dataclass(frozen=True)
class FrictionSolution:
    """One frictional contact solve on condensed nodes.

    Attributes
    ----------
    normal : ndarray
        (m,) normal contact forces on the master (N, compressive positive).
    tangential : ndarray
        (m, d - 1) tangential contact forces on the master (N).
    approach : float
        The master's rigid approach ``delta`` (m).
    shift : ndarray
        (d - 1,) the master's rigid tangential displacement ``s`` (m).
    w : ndarray
        (m, d - 1) relative tangential displacement of the surfaces (m).
    slip : ndarray
        (m, d - 1) its increment over the solve, ``w - w_prev`` (m).
    gap : ndarray
        (m,) normal gap after the solve (m; 0 where in contact).
    state : ndarray
        (m,) int, :data:`OPEN`, :data:`STICK` or :data:`SLIP`.
    iterations : int
    residual : float
        The final residual over the load (dimensionless).
    """

    normal: np.ndarray
    tangential: np.ndarray
    approach: float
    shift: np.ndarray
    w: np.ndarray
    slip: np.ndarray
    gap: np.ndarray
    state: np.ndarray
    iterations: int
    residual: float

    @property
    def forces(self) -> np.ndarray:
        """(m, d) the forces on the master per node, components ``(t1[, t2], n)``."""
        return np.column_stack([self.tangential, self.normal])


def _check(C, g0, P, d, mu):
    m = g0.size
    if C.shape != (m * d, m * d):
        raise ContactError(f"friction: the compliance has shape {C.shape}; need "
                           f"({m * d}, {m * d}) for {m} nodes of {d} components")
    if not (np.isfinite(P) and P > 0):
        raise ContactError(f"friction: the normal load P = {P!r} N is not allowed; need P > 0")
    if not (np.isfinite(mu) and mu >= 0):
        raise ContactError(f"friction: mu = {mu!r} is not allowed; need mu >= 0")


def _project(z, b):
    """The projection of the rows of ``z`` (m, k) on the discs of radii ``b`` (m,)."""
    nz = np.linalg.norm(z, axis=1)
    scale = np.where(nz > b, b / np.where(nz > 0, nz, 1.0), 1.0)
    return z * scale[:, None], nz


def solve_friction(C: np.ndarray, g0: np.ndarray, mu: float, P: float, *,
                   w_prev: np.ndarray | None = None, shift=None, Q=None,
                   start: FrictionSolution | None = None, tol: float = 1e-10,
                   max_iter: int = 80) -> FrictionSolution:
    """Frictional contact on condensed nodes under the normal load ``P``.

    Parameters
    ----------
    C
        (m d, m d) compliance of the relative displacement (m/N), per node the
        components ``(t1[, t2], n)``; ``d`` is 2 (plane) or 3.
    g0
        (m,) normal gap before the forces and the approach (m).
    mu
        Friction coefficient.
    P
        Total normal load (N; per unit length in plane strain).
    w_prev
        (m, d - 1) the relative tangential displacement of the same material
        points before this increment (default zero).
    shift, Q
        Exactly one: the master's rigid tangential displacement ``s`` (m,
        displacement control) or the tangential load applied to the master (N,
        force control; the contact forces on it sum to ``-Q``; ``|Q| < mu P``,
        else no static equilibrium exists).
    start
        A solution to start from (the previous increment's).
    tol
        Newton's tolerance on the residual over ``P``.

    Returns
    -------
    FrictionSolution

    Raises
    ------
    ContactError
        Bad shapes or values; ``|Q| >= mu P`` (the bodies slide as a whole).
    ConvergenceError
        Newton did not reach ``tol`` in ``max_iter`` iterations (its figures).
    ContactLostError
        No node is in contact.
    """
    g0 = np.asarray(g0, dtype=float).ravel()
    m = g0.size
    d = C.shape[0] // max(m, 1)
    _check(C, g0, P, d, mu)
    k = d - 1
    w_prev = np.zeros((m, k)) if w_prev is None else np.asarray(w_prev, float).reshape(m, k)
    if (shift is None) == (Q is None):
        raise ContactError("friction: give exactly one of shift (displacement control) and "
                           "Q (force control)")
    if Q is not None:
        Q = np.atleast_1d(np.asarray(Q, dtype=float))
        if np.linalg.norm(Q) >= mu * P:
            raise ContactError(f"friction: the tangential load |Q| = {np.linalg.norm(Q):g} N is "
                               f"not below mu P = {mu * P:g} N: no static equilibrium, the "
                               "bodies slide as a whole (control the shift instead)")
    else:
        shift = np.atleast_1d(np.asarray(shift, dtype=float))
    if start is None:              # the frictionless normal solution
        e = np.zeros(k)
        e[0] = 1.0
        free = solve_sliding(C, g0, 0.0, P, e, tol=max(tol, 1e-12))
        start = FrictionSolution(free.normal, np.zeros((m, k)), free.approach,
                                 np.zeros(k) if Q is not None else shift, w_prev.copy(),
                                 np.zeros((m, k)), free.gap, free.state, 0, free.residual)
    prob = _AlartCurnier(C, g0, mu, P, w_prev, Q, shift)
    x0 = np.concatenate([start.forces.ravel(), [start.approach],
                         start.shift if Q is not None else []])
    x, aux, it, res = _newton(prob, x0, tol, max_iter)
    g, w, dw, act, bound, z, nz = aux
    f = x[:m * d].reshape(m, d)
    N = np.where(act, f[:, -1], 0.0)
    if not np.any(N > 0):
        raise ContactLostError("frictional contact: no node is in contact under the load")
    T = f[:, :k]
    state = np.where(~act | (N <= 0), OPEN,
                     np.where(np.linalg.norm(T, axis=1) < mu * N * (1 - 1e-9), STICK, SLIP))
    return FrictionSolution(normal=N, tangential=T, approach=float(x[m * d]),
                            shift=np.asarray(x[m * d + 1:] if Q is not None else shift,
                                             dtype=float),
                            w=w, slip=dw, gap=np.where(act, 0.0, g), state=state,
                            iterations=it, residual=float(res))


class _AlartCurnier:
    """The nonsmooth residual of one frictional solve in the unknowns ``x = (f, delta[,
    s])`` and its generalised Jacobian."""

    def __init__(self, C, g0, mu, P, w_prev, Q, shift):
        self.C, self.g0, self.mu, self.P, self.w_prev, self.Q = C, g0, mu, P, w_prev, Q
        self.m = g0.size
        self.d = C.shape[0] // self.m
        self.k = self.d - 1
        self.r = 1.0 / np.diag(C)[self.d - 1::self.d]    # the nodes' normal stiffness, N/m
        self.nt = self.m * self.d
        self.nx = self.nt + 1 + (self.k if Q is not None else 0)
        self.shift = shift

    def split(self, x):
        f = x[:self.nt].reshape(self.m, self.d)
        s = x[self.nt + 1:] if self.Q is not None else self.shift
        return f, x[self.nt], s

    def __call__(self, x):
        m, d, k, nt, r = self.m, self.d, self.k, self.nt, self.r
        f, delta, s = self.split(x)
        u = (self.C @ f.ravel()).reshape(m, d)
        g = self.g0 + u[:, -1] - delta
        w = s + u[:, :k]
        dw = w - self.w_prev
        N, T = f[:, -1], f[:, :k]
        aug = N - r * g
        act = aug > 0
        bound = self.mu * np.where(act, aug, 0.0)
        z = T - r[:, None] * dw
        proj, nz = _project(z, bound)
        F = np.empty(self.nx)
        Fm = F[:nt].reshape(m, d)
        Fm[:, -1] = N - np.where(act, aug, 0.0)
        Fm[:, :k] = T - proj
        F[nt] = N.sum() - self.P
        if self.Q is not None:
            F[nt + 1:] = T.sum(axis=0) + self.Q
        return F, (g, w, dw, act, bound, z, nz)



def _newton(prob: _AlartCurnier, x, tol: float, max_iter: int):
    """Semi-smooth Newton with the open nodes eliminated and a backtracking line search
    on the residual's norm; returns ``(x, aux, iterations, residual / P)``."""
    F, aux = prob(x)
    res, it = np.linalg.norm(F) / prob.P, 0
    for it in range(1, max_iter + 1):
        dx = _newton_step(prob, F, aux)
        norm0, step = np.linalg.norm(F), 1.0
        for _ in range(12):                               # backtracking on |F|
            F1, aux1 = prob(x + step * dx)
            if np.linalg.norm(F1) <= (1.0 - 1e-4 * step) * norm0 or step < 1e-3:
                break
            step *= 0.5
        x, F, aux = x + step * dx, F1, aux1
        res = np.linalg.norm(F) / prob.P
        if res < tol:
            return x, aux, it, res
    act, slip = aux[3], aux[3] & (aux[6] > aux[4]) & (aux[4] > 0)
    raise ConvergenceError(
        f"frictional contact: the semi-smooth Newton did not reach {tol:g} in {max_iter} "
        f"iterations (residual {res:.3g} of the load; {int(act.sum())} of {prob.m} nodes in "
        f"contact, {int(slip.sum())} slipping)",
        figures={"iterations": max_iter, "relative_residual": res})


def _newton_step(prob: _AlartCurnier, F: np.ndarray, aux) -> np.ndarray:
    """The Newton step: the open nodes' rows are ``df = -f`` (their forces go to zero);
    the generalised Jacobian is built on the nodes in contact alone (their forces,
    the approach and, under force control, the shift), the open nodes' step entering
    its right-hand side through the compliance."""
    d, nt = prob.d, prob.nt
    act = aux[3]
    a, o = np.flatnonzero(act), np.flatnonzero(~act)
    dx = np.zeros(prob.nx)
    ocols = (o[:, None] * d + np.arange(d)).ravel()
    dx[ocols] = -F[ocols]
    acols = (a[:, None] * d + np.arange(d)).ravel()
    extra = prob.nx - nt                                  # the approach and the shift
    keep = np.concatenate([acols, nt + np.arange(extra)])
    J, shift_rows = _jacobian(prob, aux, a, acols)
    # the open nodes' step through the compliance: (C dx_open) in the active rows
    u = (prob.C[np.ix_(acols, ocols)] @ dx[ocols]).reshape(a.size, d) if o.size else \
        np.zeros((a.size, d))
    rhs = -F[keep] - _linearised(prob, aux, a, u, dx[ocols].reshape(o.size, d), shift_rows)
    try:
        dx[keep] = la.solve(J, rhs, check_finite=False)
    except (la.LinAlgError, ValueError):
        dx[keep] = la.lstsq(J, rhs, check_finite=False)[0]
    return dx


def _row_parts(prob: _AlartCurnier, aux, a):
    """Per active node: its state (stick, slip, free) and the slip rows' factors."""
    g, w, dw, act, bound, z, nz = aux
    slip = (nz[a] > bound[a]) & (bound[a] > 0)
    free = bound[a] <= 0
    stick = ~slip & ~free
    n = np.zeros((a.size, prob.k))
    n[slip] = z[a][slip] / nz[a][slip, None]
    bz = np.where(slip, bound[a] / np.where(nz[a] > 0, nz[a], 1.0), 0.0)
    Pn = np.eye(prob.k)[None] - n[:, :, None] * n[:, None, :]
    return stick, slip, free, n, bz, Pn


def _jacobian(prob: _AlartCurnier, aux, a, acols):
    """The generalised Jacobian of the Alart-Curnier residual on the active nodes
    (dense, rows and columns: their ``d`` components, then the approach and the
    shift)."""
    d, k, mu = prob.d, prob.k, prob.mu
    na, nk = a.size, acols.size
    extra = prob.nx - prob.nt
    r = prob.r[a]
    Ca = prob.C[np.ix_(acols, acols)].reshape(na, d, nk)         # (na, d, nk)
    stick, slip, free, n, bz, Pn = _row_parts(prob, aux, a)
    J = np.zeros((na, d, nk + extra))
    own = np.arange(na)
    J[:, -1, :nk] = r[:, None] * Ca[:, -1]                       # normal: r (C_n df - dd)
    J[:, -1, nk] = -r
    J[stick, :k, :nk] = r[stick, None, None] * Ca[stick, :k]     # stick: r dw
    for c in range(k):
        J[free, c, own[free] * d + c] = 1.0                      # free: T
    if slip.any():
        s_ = np.flatnonzero(slip)
        db = -mu * r[s_, None] * Ca[s_, -1]                      # (ns, nk)
        db[np.arange(s_.size), s_ * d + d - 1] += mu
        dz = -r[s_, None, None] * Ca[s_, :k]                     # (ns, k, nk)
        for c in range(k):
            dz[np.arange(s_.size), c, s_ * d + c] += 1.0
        dproj = n[s_, :, None] * db[:, None] + bz[s_, None, None] * np.einsum(
            "sab,sbj->saj", Pn[s_], dz)
        J[s_, :k, :nk] = -dproj
        for c in range(k):
            J[s_, c, s_ * d + c] += 1.0
        J[s_, :k, nk] = -n[s_] * (mu * r[s_])[:, None]
    shift_rows = None
    if extra > 1:                                                # force control: ds
        J[stick, :k, nk + 1:] = r[stick, None, None] * np.eye(k)[None]
        J[slip, :k, nk + 1:] = (bz[slip] * r[slip])[:, None, None] * Pn[slip]
        shift_rows = True
    sums = np.zeros((extra, nk + extra))
    sums[0, d - 1:nk:d] = 1.0                                    # sum N = P
    for c in range(extra - 1):
        sums[1 + c, c:nk:d] = 1.0                                # sum T = -Q
    return np.vstack([J.reshape(na * d, nk + extra), sums]), shift_rows


def _linearised(prob: _AlartCurnier, aux, a, u, dopen, shift_rows) -> np.ndarray:
    """What the open nodes' step ``dopen`` ((no, d)) changes in the active rows, through
    the displacement ``u`` ((na, d)) it causes there, and in the sums."""
    d, k, mu = prob.d, prob.k, prob.mu
    r = prob.r[a]
    stick, slip, free, n, bz, Pn = _row_parts(prob, aux, a)
    out = np.zeros((a.size, d))
    out[:, -1] = r * u[:, -1]
    out[stick, :k] = r[stick, None] * u[stick, :k]
    if slip.any():
        db = -mu * r[slip] * u[slip, -1]
        dz = -r[slip, None] * u[slip, :k]
        out[slip, :k] = -(n[slip] * db[:, None]
                          + bz[slip, None] * np.einsum("sab,sb->sa", Pn[slip], dz))
    extra = prob.nx - prob.nt
    sums = np.zeros(extra)
    if dopen.size:
        sums[0] = dopen[:, -1].sum()
        sums[1:] = dopen[:, :k].sum(axis=0)[:extra - 1]
    return np.concatenate([out.ravel(), sums])


def _winkler_approach(g0: np.ndarray, r: np.ndarray, P: float) -> float:
    """The approach at which nodal springs ``r`` over the gaps ``g0`` carry ``P``: a
    start that has nodes in contact."""
    lo, hi = float(np.min(g0)), float(np.min(g0)) + P / float(np.max(r))
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if np.sum(r * np.clip(mid - g0, 0.0, None)) < P:
            lo = mid
        else:
            hi = mid
    return hi


def solve_sliding(C: np.ndarray, g0: np.ndarray, mu: float, P: float, direction, *,
                  start: np.ndarray | None = None, tol: float = 1e-10,
                  max_iter: int = 60) -> FrictionSolution:
    """Contact in gross sliding along ``direction`` (the master's motion relative to
    the slave, a unit vector of the ``d - 1`` tangential components): every node in
    contact carries ``T = -mu N direction``, and only the normal forces are solved.

    Same parameters and result as :func:`solve_friction` (``w``, ``slip`` and
    ``shift`` are zero: the sliding distance is the caller's); ``start`` is a
    (m,) vector of normal forces.
    """
    g0 = np.asarray(g0, dtype=float).ravel()
    m = g0.size
    d = C.shape[0] // max(m, 1)
    _check(C, g0, P, d, mu)
    k = d - 1
    e = np.atleast_1d(np.asarray(direction, dtype=float))
    if e.shape != (k,) or not np.isclose(np.linalg.norm(e), 1.0):
        raise ContactError(f"sliding: direction {e!r} is not a unit vector of {k} components")
    Cr = C.reshape(m, d, m, d)
    # the normal displacement per normal force with its friction -mu N e
    Ceff = Cr[:, -1, :, -1] - mu * np.einsum("imjc,c->imj", Cr[:, -1:, :, :k], e)[:, 0]
    r = 1.0 / np.diag(Ceff)
    # primal-dual active set (the semi-smooth Newton of the normal problem with full
    # steps): solve for the set, then keep the nodes that press, add those that overlap
    if start is None:
        act = g0 <= _winkler_approach(g0, r, P)
    else:
        act = np.asarray(start, dtype=float) > 0
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007  (the count is reported)
        if not act.any():
            act = g0 <= np.min(g0)
        a = np.flatnonzero(act)
        K = np.zeros((a.size + 1, a.size + 1))
        K[:a.size, :a.size] = Ceff[np.ix_(a, a)]
        K[:a.size, a.size] = -1.0
        K[a.size, :a.size] = 1.0
        sol = la.solve(K, np.concatenate([-g0[a], [P]]), check_finite=False)
        N = np.zeros(m)
        N[a], delta = sol[:a.size], sol[a.size]
        g = g0 + Ceff @ N - delta
        new = (N > 0) | (~act & (g < -tol * P * float(np.mean(np.diag(Ceff)))))
        if np.array_equal(new, act):
            break
        act = new
    else:
        raise ConvergenceError(
            f"sliding contact: the active set did not settle in {max_iter} iterations "
            f"({int(act.sum())} of {m} nodes in contact)",
            figures={"iterations": max_iter, "relative_residual": float("nan")})
    res = 0.0
    g = g0 + Ceff @ N - delta
    N = np.where(act, N, 0.0)
    T = -mu * N[:, None] * e[None, :]
    z = np.zeros((m, k))
    return FrictionSolution(normal=N, tangential=T, approach=float(delta), shift=np.zeros(k),
                            w=z, slip=z, gap=np.where(act, 0.0, g),
                            state=np.where(act, SLIP, OPEN), iterations=it, residual=float(res))
