"""The nested active sets of a condensed contact held by the caliper's rows.

:class:`RowSets` solves the condensed pad-rotor contact together with the
caliper's rows (:mod:`brakewear.caliper.rows`), given their condensation
(:class:`~brakewear.caliper.condensation.CaliperCondensation` or
any arrays of its shape: the contact nodes first, then the rows).

Outside, the rows' *state*: each normal row closed or open, each friction row
off (its normal row open), sticking or slipping one way or the other
(Coulomb's law along the row).  For a state the rows' equations and the
rigid parts' equilibrium,

    rows that hold (closed, sticking):  g_k = 0,
    open rows:                          lam_k = 0,
    slipping rows:                      lam_k = +-mu_k lam_normal(k),
    rigid parts:                        K_q q + R^T lam_s = p f_q,

are linear in the contact forces ``lam_c`` and the pads' free modes
``alpha``, so the rows' forces and the rigid DOFs are eliminated,
``lam_s = L0 + Lc lam_c + La alpha`` (kept per state).  Inside, the
pad-rotor contact is the condensed interface's active-set solve
(:class:`~brakewear.interfaces.condensed.DenseSets`, its factorisations kept
per state) of the system the elimination leaves:

    [H + Hcs Lc] lam_c + [E + Hcs La] alpha = -(q + Hcs L0),
    [D + Es^T Lc] lam_c + [Es^T La] alpha = -(zf p + Es^T L0).

Then the state is updated from the rows' forces and gaps -- a closed row
that pulls opens, an open one that penetrates closes (its friction slipping
against the slip it has, or sticking); a sticking row whose force exceeds
``mu lam_normal`` slips in its force's sense, a slipping row whose slip
turns to its force's sense sticks -- until it repeats.  A state
met again after others is a cycle: the update then changes one row at a
time.  The last state starts the next solve, so a wear history mostly needs
one pass.
"""
from __future__ import annotations

import logging
import warnings
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
from scipy.linalg import LinAlgWarning, lu_factor, lu_solve

from ..errors import SolverError
from ..interfaces.condensed import DenseSets, solve_dense_sets

logger = logging.getLogger(__name__)

__all__ = ["RowSets", "RowSolution", "MAX_OUTER"]

#: states whose eliminated systems are kept
_KEEP_STATES = 6
#: outer (row-state) iterations before a solve is refused
MAX_OUTER = 60

OPEN, CLOSED = 0, 1
OFF, STICK, SLIP_UP, SLIP_DOWN = 0, 1, 2, 3


@dataclass
class RowSolution:
    """A solve of :class:`RowSets`: the contact forces ``lam`` (N per node) and
    their set, the modes ``alpha``, the rows' forces ``force`` (N), gaps or slips
    ``gap`` (m) and ``state``, the rigid DOFs ``q`` and the outer iterations."""

    lam: np.ndarray
    active: np.ndarray
    alpha: np.ndarray
    force: np.ndarray
    gap: np.ndarray
    state: np.ndarray
    q: np.ndarray
    outer: int
    min_gap: float


class RowSets:
    """Contact of condensed nodes held by the caliper's rows (see the module).

    Parameters
    ----------
    cond
        ``H``, ``Ht``, ``hf``, ``E``, ``Dt``, ``zf``, ``n_c`` (the contact nodes'
        count): :class:`~brakewear.caliper.condensation.CaliperCondensation`.
    rows
        :class:`~brakewear.caliper.rows.CaliperRows` (``C`` is not used).
    gap_tol, tol
        Penetration tolerated (m) and the solves' tolerance.
    """

    def __init__(self, cond, rows, gap_tol: float, tol: float = 1e-9):
        self.cond, self.rows, self.gap_tol, self.tol = cond, rows, gap_tol, tol
        n_c = cond.n_c
        self._c, self._s = slice(0, n_c), slice(n_c, None)
        # the condensed interface's factorisations, kept per friction and rows' state
        self._H, self._lu, self._bases = {}, OrderedDict(), OrderedDict()
        self._eff, self._rows_lus = OrderedDict(), {}
        c, s = self._c, self._s
        # the blocks every solve reads (copies made once)
        self._Hss, self._Hcs = cond.H[s][:, s], cond.H[c][:, s]
        self._Es, self._Ec = cond.E[s], cond.E[c]
        self._fr = np.nonzero(~rows.normal)[0]
        self._cap_fr = rows.cap[self._fr].tocsr()
        self.mu = 0.0
        self.state = self._initial_state()
        self._state_key = self.state.tobytes()

    # ------------------------------------------------------------ states --
    def _initial_state(self) -> np.ndarray:
        rows = self.rows
        st = np.where(rows.normal, np.where(rows.g0 <= self.gap_tol, CLOSED, OPEN), STICK)
        st[~rows.normal] = np.where(self._on(st)[~rows.normal], STICK, OFF)
        return st.astype(np.int8)

    def _on(self, state: np.ndarray) -> np.ndarray:
        """(n,) bool: friction rows any of whose normal rows is closed."""
        closed = (self.rows.normal & (state == CLOSED)).astype(float)
        return (self.rows.cap @ closed) > 0

    @property
    def mu_key(self):
        """The factorisations' key: the friction coefficient and the rows' state."""
        mu = self.mu if np.ndim(self.mu) == 0 else self.mu.tobytes()
        return (mu, self._state_key)

    def _holding(self, state: np.ndarray) -> np.ndarray:
        """Rows whose gap (or slip) is held at zero: closed normal rows, sticking ones."""
        return np.where(self.rows.normal, state == CLOSED, state == STICK)

    # -------------------------------------------------------- operators --
    def _operators(self):
        """``(Hcc, Hsc, D)`` at the friction ``mu``: the contact block with the
        friction compliance, the rows' response to the contact forces, the
        modes' equation."""
        mu = self.mu
        key = mu if np.ndim(mu) == 0 else mu.tobytes()
        if key not in self._H:
            cond, c, s = self.cond, self._c, self._s
            m = np.broadcast_to(np.asarray(mu, dtype=float), (cond.n_c,))
            Hc = cond.H[:, c] + cond.Ht * m[None, :]     # every row under lam_c (+ friction)
            D = self._Ec.T + cond.Dt * m[None, :]
            self._H = {key: (Hc[c], Hc[s], D)}
        return self._H[key]

    def _effective(self, state: np.ndarray) -> dict:
        """The eliminated system of a rows' state (kept for :data:`_KEEP_STATES`)."""
        key = (self.mu_key[0], state.tobytes())
        if key in self._eff:
            self._eff.move_to_end(key)
            return self._eff[key]
        rows, cond = self.rows, self.cond
        Hcc, Hsc, D = self._operators()
        ns, nq = rows.n, rows.K_q.shape[0]
        h = np.nonzero(self._holding(state))[0]
        lu, scale = self._rows_lu(state)
        B = np.zeros((ns + nq, cond.n_c + cond.E.shape[1]))
        B[h, :cond.n_c] = -Hsc[h]
        B[h, cond.n_c:] = -self._Es[h]
        L = lu_solve(lu, scale[:, None] * B, check_finite=False)
        Lc, La = L[:ns, :cond.n_c], L[:ns, cond.n_c:]
        Hcs, Es = self._Hcs, self._Es
        eff = dict(lu=lu, scale=scale, L=L, H=Hcc + Hcs @ Lc, E=self._Ec + Hcs @ La,
                   D=D + Es.T @ Lc, Q=Es.T @ La, Hcs=Hcs, Es=Es)
        self._eff[key] = eff
        while len(self._eff) > _KEEP_STATES:
            self._eff.popitem(last=False)
        return eff

    def _rows_lu(self, state: np.ndarray):
        """The LU (row-scaled) of a state's rows-and-rigid-parts system, kept; refuses a
        state that leaves a rigid part free."""
        key = (self.mu_key[0], state.tobytes())
        if key in self._rows_lus:
            return self._rows_lus[key]
        rows = self.rows
        ns, nq = rows.n, rows.K_q.shape[0]
        h = np.nonzero(self._holding(state))[0]
        slip = np.nonzero((~rows.normal) & ((state == SLIP_UP) | (state == SLIP_DOWN)))[0]
        M = np.zeros((ns + nq, ns + nq))
        M[:ns, :ns] = np.eye(ns)
        M[h, :ns] = self._Hss[h]
        M[h, h] += rows.compliance[h]
        M[h, ns:] = -rows.R[h]
        sign = np.where(state[slip] == SLIP_UP, 1.0, -1.0)
        M[slip, :ns] -= (sign * rows.mu[slip])[:, None] * rows.cap[slip].toarray()
        M[ns:, :ns] = rows.R.T
        M[ns:, ns:] = rows.K_q
        scale = 1.0 / np.abs(M).max(axis=1)     # rows of forces, gaps and compliances
        with warnings.catch_warnings():          # a singular state is refused below
            warnings.simplefilter("ignore", LinAlgWarning)
            lu = lu_factor(scale[:, None] * M, check_finite=False)
        pivots = np.abs(np.diag(lu[0]))
        if not np.all(np.isfinite(pivots)) or pivots.min() <= 1e-14 * pivots.max():
            raise SolverError(f"caliper rows: their state leaves a rigid part free ({h.size} of "
                              f"{ns} rows hold, smallest pivot {pivots.min():.3g} of "
                              f"{pivots.max():.3g}): no closed row holds it")
        self._rows_lus[key] = (lu, scale)
        while len(self._rows_lus) > 8 * _KEEP_STATES:
            self._rows_lus.pop(next(iter(self._rows_lus)))
        return lu, scale

    # ------------------------------------------------------------- solve --
    def solve(self, q_c: np.ndarray, rhs_c: np.ndarray, gap_s: np.ndarray, line_pressure: float,
              compliance: np.ndarray | None, active: np.ndarray | None,
              start_gap: np.ndarray, ring_H: np.ndarray | None = None,
              ring_key: bytes = b"") -> RowSolution:
        """The contact and the rows for the contact nodes' gap ``q_c`` at zero force
        and the modes' right-hand side ``rhs_c``, the rows' gaps (slips) ``gap_s``
        at zero force and the rigid parts' load ``line_pressure f_q``;
        ``compliance`` (m/N per node) the implicit step's; ``active`` the contact
        set to start from (else the nodes of ``start_gap <= 0``); ``ring_H`` the
        implicit rings' compliance among the contact nodes (``ring_key`` tells it
        apart in the kept factorisations)."""
        rows = self.rows
        Hsc, Hss = self._operators()[1], self._Hss
        F = line_pressure * rows.hydraulic_area
        state, seen, act = self.state.copy(), set(), active
        for outer in range(1, MAX_OUTER + 1):  # noqa: B007  (the count is reported)
            self._state_key = state.tobytes()
            eff = self._effective(state)      # a state met here holds every rigid part
            b0 = np.zeros(rows.n + rows.K_q.shape[0])
            h = np.nonzero(self._holding(state))[0]
            b0[h] = -gap_s[h]
            b0[rows.n:] = line_pressure * rows.f_q
            y0 = lu_solve(eff["lu"], eff["scale"] * b0, check_finite=False)
            L0 = y0[:rows.n]
            problem = DenseSets(self, eff["H"] if ring_H is None else eff["H"] + ring_H,
                                 eff["D"], q_c + eff["Hcs"] @ L0, rhs_c - eff["Es"].T @ L0,
                                 compliance, ring_key, E=eff["E"], Q=eff["Q"])
            act = self._contact(problem, start_gap, compliance, act)
            lam_c, alpha = problem.lam, problem.alpha
            y = y0 + eff["L"] @ np.concatenate([lam_c, alpha])
            lam_s, q = y[:rows.n], y[rows.n:]
            g_s = (gap_s + Hsc @ lam_c + Hss @ lam_s + eff["Es"] @ alpha - rows.R @ q
                   + rows.compliance * lam_s)
            new = self._update(state, lam_s, g_s, F)
            if np.array_equal(new, state):
                break
            if new.tobytes() in seen or not self._holds(new):
                # a cycle, or a state that leaves a rigid part free: one row at a time
                new = self._one_change(state, new, lam_s, g_s, F)
            seen.add(state.tobytes())
            state = new
        else:
            raise SolverError(f"caliper rows: their state did not settle in {MAX_OUTER} "
                              f"iterations ({self._violations(state, lam_s, g_s)})")
        self.state = state
        return RowSolution(lam_c, act, alpha, lam_s, g_s, state.copy(), q, outer,
                           float(problem.g.min()))

    def _contact(self, problem, g, cc, active):
        """The inner active-set solve of the contact nodes (the FE solves' start)."""
        return solve_dense_sets(problem, g, active, self.gap_tol, cc is not None, self.tol,
                                "pad-rotor (caliper)")[0]

    def _tolerances(self, lam, F: float):
        fmax = max(float(np.abs(lam).max()) if lam.size else 0.0, F, 1e-300)
        return 1e-9 * fmax, self.gap_tol

    def _update(self, state, lam, g, F: float) -> np.ndarray:
        """The next state from the rows' forces and gaps (see the module)."""
        rows = self.rows
        ftol, gtol = self._tolerances(lam, F)
        new = state.copy()
        nrm = rows.normal
        closed = state == CLOSED
        new[nrm & closed & (lam < -ftol)] = OPEN
        new[nrm & ~closed & (g < -gtol)] = CLOSED
        k = self._fr
        cap = rows.mu[k] * (self._cap_fr @ np.maximum(lam, 0.0))
        st = state[k]
        nst = st.copy()
        on = self._on(new)[k]
        # a row that closes starts slipping against the slip it has, or sticks
        start = np.where(g[k] > gtol, SLIP_DOWN, np.where(g[k] < -gtol, SLIP_UP, STICK))
        nst[on & (st == OFF)] = start[on & (st == OFF)]
        over = on & (st == STICK) & (np.abs(lam[k]) > cap + ftol)
        nst[over] = np.where(lam[k][over] > 0, SLIP_UP, SLIP_DOWN)
        sign = np.where(st == SLIP_UP, 1.0, -1.0)
        slipping = on & ((st == SLIP_UP) | (st == SLIP_DOWN))
        # Coulomb: the force opposes the slip; a slip along the force sticks
        nst[slipping & (sign * g[k] > gtol)] = STICK
        nst[~on] = OFF
        new[k] = nst
        return new

    def _consistent(self, state: np.ndarray) -> np.ndarray:
        """``state`` with each friction row off where its normal rows are open and
        sticking where one of them closed while it was off."""
        fr = ~self.rows.normal
        on = self._on(state)
        out = state.copy()
        out[fr & ~on] = OFF
        out[fr & on & (state == OFF)] = STICK
        return out

    def _holds(self, state: np.ndarray) -> bool:
        """Whether a state holds every rigid part (its rows' system is regular)."""
        try:
            self._rows_lu(state)
        except SolverError:
            return False
        return True

    def _one_change(self, state, new, lam, g, F: float) -> np.ndarray:
        """Of the changes from ``state`` to ``new``, the one of the largest violation
        whose state holds every rigid part."""
        ftol, gtol = self._tolerances(lam, F)
        d = np.nonzero(new != state)[0]
        viol = np.abs(np.where(self.rows.normal[d], np.minimum(lam[d], 0.0) / ftol
                               + np.minimum(g[d], 0.0) / gtol, g[d] / gtol))
        for i in d[np.argsort(-viol)]:
            out = state.copy()
            out[i] = new[i]
            out = self._consistent(out)
            if not np.array_equal(out, state) and self._holds(out):
                return out
        raise SolverError(f"caliper rows: every change of their state leaves a rigid part "
                          f"free ({self._violations(state, lam, g)})")

    def _violations(self, state, lam, g) -> str:
        nrm = self.rows.normal
        closed = nrm & (state == CLOSED)
        return (f"{int(closed.sum())} of {int(nrm.sum())} normal rows closed, "
                f"largest tension {-min(0.0, float(lam[closed].min(initial=0.0))):.3g} N, "
                f"largest penetration {-min(0.0, float(g[nrm & ~closed].min(initial=0.0))):.3g} m")
