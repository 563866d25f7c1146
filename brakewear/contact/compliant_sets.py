"""The set problems of a compliant contact solve (the implicit wear step).

:class:`CompliantSets` is the plain one: ``K_d`` plus the springs of the
active nodes of one compliant pair.  :class:`SupportedSets` adds rigid
support pairs.

:func:`~brakewear.contact.compliant.solve_compliant_contact` models the
pad-rotor interface as springs of compliance ``eps_i``; the pad's abutments
in the bracket (:mod:`~brakewear.contact.supports`) are rigid stops with no
compliance.  Their active constraints are eliminated as in the Lagrange
solve (:mod:`~brakewear.contact.elimination`): ``u = P x + c`` with each
active stop node's normal DOF a dummy, so the operator of one active set is

    A = P^T (K_d + C_A^T kappa C_A) P   (dummy rows: K's diagonal),

still symmetric positive definite without friction, and the sliding friction
``G_A kappa C_A`` of the compliant pair enters as ``P^T G_A kappa C_A P``.
The base hierarchy of ``K_d`` preconditions every set through a refreshed
copy (its update ``A - K_d`` is local to the contact and stop rows).  A stop's
multiplier is the normal component of the residual at its node, as in
:func:`~brakewear.contact.solve_contact`; every pair keeps its own active set
in one flat array (compliant nodes first, then each stop pair).
"""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from ..errors import ContactError
from ..solvers.operators import ProductSum
from .active_set import Margins
from .elimination import _mask_fixed, _prolongation, _reduced_start, _set_delta

logger = logging.getLogger(__name__)

__all__ = ["CompliantSets", "SupportedSets"]


class CompliantSets:
    """The compliant contact problem of one active set after another (a
    :class:`~brakewear.contact.active_set.SetProblem`): ``K_d`` plus the springs
    of the active nodes, preconditioned by a refreshed copy of the base hierarchy."""

    def __init__(self, pair, kappa, C, G, Kd, fd, base, x, rings=None):
        self.pair, self.kappa, self.C, self.G, self.Kd, self.fd = pair, kappa, C, G, Kd, fd
        self.base, self.x = base, x
        self.rings = rings      # a RingBlock: the rotor's ring depths as extra unknowns
        self.key = None
        self.lin = 0

    @property
    def u(self) -> np.ndarray:
        """The displacement of the last solution (all DOFs)."""
        return self.x

    def _new_set(self, active: np.ndarray) -> None:
        pair, C = self.pair, self.C
        Ca = C[active]
        ka = self.kappa[active]
        D = (Ca.T @ sp.diags(ka) @ Ca).tocsr()
        self.b = self.fd - Ca.T @ (ka * pair.g0[active])
        self.amg = self.base.refreshed(self.Kd + D, dA=D)
        self.Aop = None
        if self.G is not None:
            # friction = G lambda with lambda = -kappa (g0 + C u): linear in u
            Ga = self.G[:, active]
            E = (Ga @ sp.diags(ka) @ Ca).tocsr()
            self.b = self.b - Ga @ (ka * pair.g0[active])
            self.Aop = ProductSum(self.amg.A, [(1, E, None)])
        if self.rings is not None:
            self.rings.for_set(active, Ca, None if self.G is None else self.G[:, active])

    def solve(self, active: np.ndarray, tol: float, rtol0: float | None) -> None:
        key = np.packbits(active).tobytes()
        if key != self.key:
            self._new_set(active)
            self.key = key
        self.amg.tol = tol
        if self.rings is not None:
            op = self.amg.A if self.Aop is None else self.Aop
            self.x = self.rings.solve(self.amg, op, self.b, self.x, tol, rtol0)
            self.lin += self.amg.info.iterations
            return
        self.x = self.amg.solve(self.b, x0=self.x, A=self.Aop,
                                krylov="gmres" if self.G is not None else "cg", rtol0=rtol0)
        self.lin += self.amg.info.iterations

    def gaps(self, u: np.ndarray) -> np.ndarray:
        """The gap of every compliant node at displacement ``u`` (m), the rotor's
        ring wear of the step included."""
        g = self.pair.g0 + self.C @ u
        return g if self.rings is None else g + self.rings.gap()

    def margins(self, active: np.ndarray, band: float) -> Margins:
        """An active node stays while its spring force is above ``-band`` x the
        largest, an open node enters when its spring would be compressed by more
        than ``band`` x the largest."""
        force = -self.kappa * self.gaps(self.x)
        fmax = max(float(force[active].max()) if active.any() else 0.0, 1e-300)
        return Margins(force, band * fmax, force, band * fmax)


class SupportedSets(CompliantSets):
    """The compliant problem with rigid stops eliminated: its unknowns ``x`` are
    those of the current set (``u = P x + c``, :attr:`u`); ``support_force``
    and ``support_gap`` hold the stops' state after each :meth:`margins`."""

    def __init__(self, pair, kappa, C, G, Kd, fd, base, x, supports, is_fixed, gap_tol,
                 rings=None):
        super().__init__(pair, kappa, C, G, Kd, fd, base, None, rings)
        self.supports, self.is_fixed, self.gap_tol = supports, is_fixed, gap_tol
        self.u_last = x          # the displacement the next set starts from
        self.ns = pair.slave.size
        self.offsets = np.cumsum([self.ns] + [s.slave.size for s in supports])
        self.diagK = Kd.diagonal()
        self.support_force = [np.zeros(s.slave.size) for s in supports]
        self.support_gap = [s.gaps(x) if x is not None else s.g0.copy() for s in supports]

    @property
    def u(self) -> np.ndarray:
        return self.P @ self.x + self.c

    def split(self, flat: np.ndarray):
        """The compliant pair's part of a flat per-node array and each stop's part."""
        return flat[:self.ns], [flat[a:b] for a, b in zip(self.offsets[:-1], self.offsets[1:])]

    def _new_set(self, active: np.ndarray) -> None:
        N = self.Kd.shape[0]
        if self.x is not None:
            self.u_last = self.u
        a_c, a_s = self.split(active)
        P, c, elim = _prolongation(N, self.supports, a_s)
        clash = np.flatnonzero(self.is_fixed[elim])
        if clash.size:
            raise ContactError(f"DOF {elim[clash[0]]} is supported and the normal DOF of an "
                               "abutment (stop) node; a node cannot be both")
        g0 = self.pair.g0[a_c]
        Ca, ka = self.C[a_c], self.kappa[a_c]
        D = (Ca.T @ sp.diags(ka) @ Ca).tocsr()
        M = (self.Kd + D).tocsr()
        b = self.fd - Ca.T @ (ka * g0)
        E = None
        if self.G is not None:
            Ga = self.G[:, a_c]
            E = (Ga @ sp.diags(ka) @ Ca).tocsr()
            b = b - Ga @ (ka * g0)
        dM = _mask_fixed(_set_delta(M, P, elim, self.is_fixed, self.diagK), self.is_fixed)
        A = (M + dM).tocsr()
        self.b = P.T @ (b - M @ c - (E @ c if E is not None else 0.0))
        self.b[elim] = 0.0
        self.b[self.is_fixed] = 0.0
        self.M, self.E, self.b_full, self.P, self.c = M, E, b, P, c
        self.amg = self.base.refreshed(A, dA=(D + dM).tocsr())
        if self.rings is not None:
            self.rings.for_set(a_c, Ca, None if self.G is None else self.G[:, a_c], P, c)
        self.Aop = None
        if E is not None:
            PtE = (P.T @ E).tocsr()
            self.Aop = ProductSum(A, [(1, PtE, P)])
        # warm start: the last displacement in this set's unknowns
        self.x = None if self.u_last is None else _reduced_start(self.u_last, self.supports,
                                                                 a_s)

    def margins(self, active: np.ndarray, band: float) -> Margins:
        """Compliant nodes as in the plain problem (spring force against ``band`` x
        the largest); a stop node stays while its multiplier is above ``-band`` x its
        pair's largest, enters when it penetrates by more than the gap tolerance."""
        a_c, a_s = self.split(active)
        u = self.u
        force = -self.kappa * self.gaps(u)
        fmax = max(float(force[a_c].max()) if a_c.any() else 0.0, 1e-300)
        r = self.M @ u - self.b_full
        if self.E is not None:
            r = r + self.E @ u
        if self.rings is not None:
            r = r + self.rings.force_residual()
        r = r.reshape(-1, 3)
        bound = np.full(self.ns, band * fmax)
        stay, sb, enter, eb = [force], [bound], [force], [bound]
        for k, (s, a) in enumerate(zip(self.supports, a_s)):
            lam = np.where(a, np.einsum("ij,ij->j", s.normal, r[s.slave].T), 0.0)
            self.support_force[k], self.support_gap[k] = lam, s.gaps(u)
            stay.append(lam)
            sb.append(np.full(lam.size, band * max(np.abs(lam).max(initial=0.0), 1e-300)))
            enter.append(-np.where(a, 0.0, self.support_gap[k]))
            eb.append(np.full(lam.size, self.gap_tol))
        return Margins(np.concatenate(stay), np.concatenate(sb), np.concatenate(enter),
                       np.concatenate(eb))
