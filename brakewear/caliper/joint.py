"""The caliper's rows and the pad-rotor contact on one kept factorisation.

:class:`JointSets` solves what :class:`~brakewear.caliper.sets.RowSets`
solves -- the condensed pad-rotor contact held by the caliper's rows and rigid
parts -- with the whole system of a state in one set of equations,

    contact node i in contact:  H_i lam_c + c_i lam_i + Hcs_i lam_s + E_i alpha = -q_i,
    rows that hold:             Hsc_k lam_c + (Hss_k + comp_k e_k) lam_s + Es_k alpha
                                - R_k q = -gap_k,
    open nodes and rows:        lam_k = 0,
    slipping rows:              lam_k = +-mu_k cap_k lam_s,
    the pads' free modes:       D lam_c + Es^T lam_s = rhs,
    rigid parts:                R^T lam_s + K_q q = p f_q.

For each state of the rows (each normal row closed or open, each friction row
off, sticking or slipping either way) the contact's active set is iterated to
its end (the condensed solves' driver); the rows' state is then updated from
that solution (the primal-dual rule on the normal rows, Coulomb's law on the
friction rows).  A change that leaves a rigid part free, leads back to a state
met before, or loses the contact is replaced by a smaller one: its worse half
by violation, ..., one row (from the last state that settled).  A rows' state
that still does not settle is found by the damped Newton methods of
:mod:`~brakewear.caliper.complementarity` on the whole system, checked for its
equations' residuals (:class:`~brakewear.errors.ComplementarityError` if not).

Every state's system is solved from one kept factorisation
(:class:`~brakewear.solvers.kept_factorisation.KeptFactorisation`): the
system of a reference state at the reference friction with no wear
compliance, equilibrated once, and a Woodbury correction for the equations
whose kind differs.  The implicit step's compliance ``c`` and the rings' wear
enter as a perturbation ``P`` of that system, solved by GMRES
right-preconditioned with the exact solve of the state (the compliance of a
wear step is a few percent of the pad's own: 4-8 iterations to 1e-14); a
perturbation that does not converge is factorised as a reference of its own,
and another friction coefficient is a new reference.  The state found is
solved once more with one step of iterative refinement against its own
equations: the answer is the direct FE solve of the state to 1e-14 of the
clamp force in the contact forces (tests)."""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from ..contact.active_set import EXACT, Margins, pdas_update
from ..errors import ActiveSetError, ComplementarityError, ContactLostError, SolverError
from ..interfaces.condensed import solve_dense_sets
from ..solvers.kept_factorisation import (
    FULL,
    IDENT,
    KeptFactorisation,
    SingularState,
    equilibrate,
    gmres,
)
from .complementarity import SLIP_DOWN_CODE, SLIP_UP_CODE, StateProblem, solve_states
from .sets import CLOSED, MAX_OUTER, OFF, OPEN, SLIP_DOWN, SLIP_UP, STICK, RowSets, RowSolution

logger = logging.getLogger(__name__)

__all__ = ["JointSets"]

#: GMRES: relative residual sought, accepted, and iterations before the perturbation is
#: factorised instead
_GMRES_TOL, _GMRES_ACCEPT, _GMRES_MAX = 1e-14, 1e-12, 40
#: equation codes of slipping friction rows (beyond IDENT and FULL)
_SLIP_UP, _SLIP_DOWN = SLIP_UP_CODE, SLIP_DOWN_CODE
#: a damped Newton state's residuals allowed, relative to its equations' terms
_EQUILIBRIUM = 1e-10


class JointSets(RowSets):
    """The contact and the caliper's rows in one active-set iteration (see the module).

    Parameters as :class:`~brakewear.caliper.sets.RowSets`, and
    ``max_changes``: equations that may differ from the kept factorisation's
    state before the state at hand is factorised.
    """

    def __init__(self, cond, rows, gap_tol: float, tol: float = 1e-9, max_changes: int = 48):
        super().__init__(cond, rows, gap_tol, tol)
        self.n_c, self.m, self.ns = cond.n_c, cond.E.shape[1], rows.n
        self.nq = rows.K_q.shape[0]
        n_c, m, ns = self.n_c, self.m, self.ns
        self.C = slice(0, n_c)
        self.Mo = slice(n_c, n_c + m)
        self.S = slice(n_c + m, n_c + m + ns)
        self.Q = slice(n_c + m + ns, n_c + m + ns + self.nq)
        self.N = n_c + m + ns + self.nq
        self.max_changes = max_changes
        self.scale = None             # (row, column) equilibration, from the first system
        self.refs: dict = {}          # "rigid" / "exact" -> (key, mu, c, comp, KeptFactorisation)
        self.counts = {"solves": 0, "gmres": 0, "exact_references": 0}
        self._rings = None            # (rings' key, their gap operator)
        self._hc_kept = None          # (mu, H's contact columns with friction)

    # ---------------------------------------------------------------- systems --
    def _hc(self, mu) -> np.ndarray:
        """Every row's gap per newton at each contact node, with its friction at ``mu``
        (kept for the last ``mu``)."""
        key = np.asarray(mu, dtype=float).tobytes()
        if self._hc_kept is None or self._hc_kept[0] != key:
            n_c = self.n_c
            mu_v = np.broadcast_to(np.asarray(mu, dtype=float), (n_c,))
            self._hc_kept = (key, self.cond.H[:, :n_c] + self.cond.Ht * mu_v[None, :])
        return self._hc_kept[1]

    def _full(self, mu, c, comp) -> np.ndarray:
        """Every equation in its holding form (contact nodes in contact, rows that
        hold) at friction ``mu``, compliance ``c`` (or None) and rings ``comp``."""
        cond, rows, n_c = self.cond, self.rows, self.n_c
        C, Mo, S, Q = self.C, self.Mo, self.S, self.Q
        mu_v = np.broadcast_to(np.asarray(mu, dtype=float), (n_c,))
        Hc = self._hc(mu)
        M = np.zeros((self.N, self.N))
        M[C, C] = Hc[:n_c]
        if c is not None:
            M[C, C][np.diag_indices(n_c)] += c
        if comp is not None:
            M[C, C] += comp.ring_compliance()
        M[C, Mo] = cond.E[:n_c]
        M[C, S] = cond.H[:n_c, n_c:]
        M[Mo, C] = cond.E[:n_c].T + cond.Dt * mu_v[None, :]
        M[Mo, S] = cond.E[n_c:].T
        M[S, C] = Hc[n_c:]
        M[S, Mo] = cond.E[n_c:]
        M[S, S] = cond.H[n_c:, n_c:] + np.diag(rows.compliance)
        M[S, Q] = -rows.R
        M[Q, S] = rows.R.T
        M[Q, Q] = rows.K_q
        return M

    def _special(self, ks: np.ndarray, codes: np.ndarray) -> np.ndarray:
        """The slipping friction rows' equations ``lam_k -+ mu_k cap_k lam_s = 0`` in
        the scaled unknowns, divided by the row's own scale."""
        rows, dc, s0 = self.rows, self.scale[1], self.S.start
        j = ks - s0
        out = np.zeros((ks.size, self.N))
        sign = np.where(codes == _SLIP_UP, 1.0, -1.0)
        cap = rows.cap[j].toarray() * (sign * rows.mu[j])[:, None]
        out[:, self.S] = -cap * dc[self.S][None, :] / dc[ks][:, None]
        out[np.arange(ks.size), ks] += 1.0
        return out

    def _reference(self, kind: str, mu, c, comp):
        """A kept factorisation of the system at ``mu``, ``c``, ``comp`` (made now)."""
        M = self._full(mu, c, comp)
        if self.scale is None:
            self.scale = equilibrate(M)
        dr, dc = self.scale
        kf = KeptFactorisation(dr[:, None] * M * dc[None, :], self._special, self.max_changes)
        ref = (self._key(mu, c, comp), np.array(mu, dtype=float), c, comp, kf)
        self.refs[kind] = ref
        return ref

    @staticmethod
    def _key(mu, c, comp) -> bytes:
        return (np.asarray(mu, dtype=float).tobytes() + b"|"
                + (b"" if c is None else np.asarray(c).tobytes()) + b"|"
                + (b"" if comp is None else comp.ring_key))

    def _code(self, act: np.ndarray, st: np.ndarray) -> np.ndarray:
        """Each equation's kind in a state (contact set ``act``, rows' state ``st``)."""
        code = np.full(self.N, FULL, dtype=np.int8)
        code[self.C] = np.where(act, FULL, IDENT)
        rows = self.rows
        rc = np.where(self._holding(st), FULL, IDENT).astype(np.int8)
        fr = ~rows.normal
        rc[fr & (st == SLIP_UP)] = _SLIP_UP
        rc[fr & (st == SLIP_DOWN)] = _SLIP_DOWN
        code[self.S] = rc
        return code

    def _perturbation(self, ref, mu, c, comp, code):
        """``z' -> P z'`` in the scaled equations (None when there is none): the
        compliance, rings and friction that differ from the reference's."""
        _, mu_r, c_r, comp_r, _ = ref
        n_c, cond = self.n_c, self.cond
        dmu = np.broadcast_to(np.asarray(mu, dtype=float) - mu_r, (n_c,))
        dc = (np.zeros(n_c) if c is None else c) - (0.0 if c_r is None else c_r)
        same_rings = (comp is None and comp_r is None) or (
            comp is not None and comp_r is not None and comp.ring_key == comp_r.ring_key)
        if not dmu.any() and not np.any(dc) and same_rings:
            return None
        ring, ring_r = self._ring_op(comp), self._ring_op(comp_r)
        dr, dcs = self.scale
        keep = (code == FULL) * dr
        keep[self.Q] = 0.0
        C, Mo, S = self.C, self.Mo, self.S
        friction = bool(dmu.any())

        def apply(zs: np.ndarray) -> np.ndarray:
            lam = zs[C] * dcs[C]
            out = np.zeros(self.N)
            out[C] = dc * lam
            if not same_rings:
                if ring is not None:
                    out[C] += ring(lam)
                if ring_r is not None:
                    out[C] -= ring_r(lam)
            if friction:
                f = dmu * lam
                t = cond.Ht @ f
                out[C] += t[:n_c]
                out[S] = t[n_c:]
                out[Mo] = cond.Dt @ f
            return out * keep
        return apply

    def _ring_op(self, comp):
        """``lam -> the gap the rings' wear of ``comp`` opens``, from dense thin factors
        (kept for the last rings' step)."""
        if comp is None:
            return None
        key = comp.ring_key
        if self._rings is None or self._rings[0] != key:
            B = comp.ring_gap.toarray()
            G = comp.ring_force_depth().toarray()
            self._rings = (key, lambda lam: B @ (G @ lam))
        return self._rings[1]

    def _solve_code(self, code, b, mu, c, comp, refine: bool = False) -> np.ndarray:
        """The solution (unscaled) of the state ``code`` with the right-hand side ``b``;
        ``refine``: one step of iterative refinement against the state's own
        equations (the Woodbury corrections lose a few digits of the system's)."""
        self.counts["solves"] += 1
        key = self._key(mu, c, comp)
        exact = self.refs.get("exact")
        if exact is not None and exact[0] == key:
            ref = exact
        else:
            ref = self.refs.get("rigid")
            if ref is None or not np.array_equal(ref[1], np.asarray(mu, dtype=float)):
                # another friction coefficient (the next stop's): a new reference, as a
                # friction perturbation costs a product with the friction compliance
                ref = self._reference("rigid", mu, None, None)
        dr, dcs = self.scale
        bs = np.where(code == FULL, dr * b, 0.0)
        kf = ref[4]
        prep = kf.prepare(code)
        z = kf.solve(prep, bs)
        P = self._perturbation(ref, mu, c, comp, code)
        if P is not None:
            self.counts["gmres"] += 1
            nb = float(np.linalg.norm(bs))
            r0 = -P(z)
            u, res, its = gmres(lambda v: v + P(kf.solve(prep, v)), r0, _GMRES_TOL * nb,
                                _GMRES_MAX)
            z = z + kf.solve(prep, u)
            if not res <= _GMRES_ACCEPT * nb:
                # not a small perturbation of the reference: factorise it as one
                self.counts["exact_references"] += 1
                logger.debug("caliper: GMRES at %.2e after %d iterations; exact reference",
                             res / max(nb, 1e-300), its)
                ref = self._reference("exact", mu, c, comp)
                kf = ref[4]
                prep = kf.prepare(code)
                z = kf.solve(prep, bs)
                P = self._perturbation(ref, mu, c, comp, code)
        if refine:
            r = bs - kf.product(code, z)
            if P is not None:
                r -= P(z)
            z = z + kf.solve(prep, r)
        return z * dcs

    # ------------------------------------------------------------------ solve --
    def solve(self, q_c: np.ndarray, rhs_c: np.ndarray, gap_s: np.ndarray, line_pressure: float,
              compliance: np.ndarray | None, active: np.ndarray | None,
              start_gap: np.ndarray, ring_H=None, ring_key: bytes = b"",
              rings=None) -> RowSolution:
        """As :meth:`RowSets.solve`; the rings' step comes as ``rings`` (a
        :class:`~brakewear.interfaces.StepCompliance` whose rings are on), not as
        a dense ``ring_H``; a rows' state that does not settle as the module says."""
        rows = self.rows
        F = line_pressure * rows.hydraulic_area
        b = np.concatenate([-q_c, rhs_c, -gap_s, line_pressure * rows.f_q])
        comp = rings if rings is not None and rings.rings else None
        problem = _RowState(self, b, compliance, comp, q_c, gap_s)
        damped = False
        try:
            st, act, outer = self._row_iteration(problem, start_gap, active, compliance, F)
        except SolverError as e:
            logger.info("caliper: %s; the contact and the rows by damped Newton", e)
            st, act, outer = self._damped(problem, F, e)
            damped = True
        problem.st = st
        problem.solve(act, self.tol, None, refine=True)
        lam, alpha, lam_s, q, g, g_s = problem.result()
        if damped:
            res = self._equilibrium(problem, act, st)
            if max(res.values()) > _EQUILIBRIUM:
                raise ComplementarityError(
                    f"caliper: the state found by damped Newton leaves residuals "
                    f"{', '.join(f'{k} {v:.1e}' for k, v in res.items())} of its equations' "
                    f"terms (allowed {_EQUILIBRIUM:.0e})", figures=res)
        self.state = st
        return RowSolution(lam, act, alpha, lam_s, g_s, st.copy(), q, outer, float(g.min()))

    def _row_iteration(self, problem, start_gap, active, compliance, F):
        """The rows' state iterated around the contact's active sets (see the module):
        ``(rows' state, contact set, outer iterations)``."""
        st, act = self.state.copy(), active
        seen: set = set()
        back = None              # (the last settled rows' state, its contact set, moves left)
        for outer in range(1, MAX_OUTER + 1):
            problem.st = st
            try:
                act_new, _ = solve_dense_sets(problem, start_gap, act, self.gap_tol,
                                              compliance is not None, self.tol,
                                              "pad-rotor (caliper)")
            except (ContactLostError, ActiveSetError, SingularState) as e:
                # this rows' state does not hold the pads on the rotor: back to the last
                # settled state, and the next smaller change from it
                seen.add(st.tobytes())
                if back is None:
                    initial = self._initial_state()
                    if np.array_equal(st, initial):
                        raise
                    logger.info("caliper: the rows' last state fails (%s); from the initial "
                                "state", e)
                    st, act = initial, None
                    continue
                st = next((c for c in back[2] if c.tobytes() not in seen), None)
                if st is None:
                    raise SolverError(f"caliper: every change of the rows' state from the last "
                                      f"settled one loses the contact ({e})") from e
                act = back[1]
                continue
            act = act_new
            lam, alpha, lam_s, q, g, g_s = problem.result()
            new = self._update(st, lam_s, g_s, F)
            if np.array_equal(new, st):
                return st, act, outer
            seen.add(st.tobytes())
            # the change, or (when it leaves a rigid part free or leads back to a state met
            # before) the worse half of it, ..., one row: the largest violation first
            moves = self._row_changes(st, new, lam_s, g_s, F, singles=True)
            back = (st, act, moves)
            nxt = next((c for c in moves if c.tobytes() not in seen), None)
            if nxt is None:
                raise SolverError(f"caliper rows: every change of their state leads back to "
                                  f"one met before ({self._violations(st, lam_s, g_s)})")
            st = nxt
        raise SolverError(f"caliper rows: their state did not settle in {MAX_OUTER} "
                          f"iterations ({self._violations(st, lam_s, g_s)})")

    def _damped(self, problem, F: float, cause: SolverError):
        """The state by :func:`~brakewear.caliper.complementarity.solve_states` from the
        last solution ``problem`` holds (or from rest), checked: ``(rows' state,
        contact set, iterations)``.  Raises
        :class:`~brakewear.errors.ComplementarityError`."""
        if self.scale is None:
            self.scale = equilibrate(self._full(self.mu, None, None))
        z0 = np.zeros(self.N)
        if problem.lam is not None:
            z0[self.C], z0[self.Mo] = problem.lam, problem.alpha
            z0[self.S], z0[self.Q] = problem.lam_s, problem.q
        band = EXACT.release_tol
        M = self._full(self.mu, problem.cc, problem.comp)

        def accept(code, z) -> bool:
            act, st = self._state_of(code)
            problem.st = st
            problem.set_solution(act, code, z)
            if not np.array_equal(pdas_update(act, problem.margins(act, band)), act):
                return False
            lam, alpha, lam_s, q, g, g_s = problem.result()
            return bool(np.array_equal(self._update(st, lam_s, g_s, F), st))

        rows, dr, dc = self.rows, *self.scale
        fr = np.nonzero(~rows.normal)[0]
        normal = sp.hstack([sp.csr_matrix((fr.size, self.S.start)), rows.cap[fr],
                            sp.csr_matrix((fr.size, self.nq))]).tocsr()
        prob = StateProblem(M, problem.b, dr, dc,
                            np.concatenate([np.arange(self.n_c),
                                            self.S.start + np.nonzero(rows.normal)[0]]),
                            self.S.start + fr, normal, rows.mu[fr],
                            lambda code: self._solve_code(code, problem.b, self.mu, problem.cc,
                                                          problem.comp))
        try:
            code, _, its, method = solve_states(prob, z0, accept, "caliper")
        except ComplementarityError as e:
            raise ComplementarityError(f"{cause}; {e}", figures=e.figures) from e
        self.counts[method] = self.counts.get(method, 0) + 1
        act, st = self._state_of(code)
        return st, act, its

    def _equilibrium(self, problem, act, st) -> dict:
        """The refined solution's residuals, each relative to its equations' terms: the
        pads' free modes' and the rigid parts' equilibrium (forces and moments), the
        contact nodes in contact and the rows that hold."""
        M = self._full(self.mu, problem.cc, problem.comp)
        z = np.concatenate([problem.lam, problem.alpha, problem.lam_s, problem.q])
        r = np.abs(M @ z - problem.b)
        size = np.abs(M) @ np.abs(z) + np.abs(problem.b)
        rel = r / np.where(size > 0, size, 1.0)
        hold = self._code(act, st) == FULL
        return {"modes": float(rel[self.Mo].max(initial=0.0)),
                "rigid_parts": float(rel[self.Q].max(initial=0.0)),
                "contact": float(rel[self.C][hold[self.C]].max(initial=0.0)),
                "rows": float(rel[self.S][hold[self.S]].max(initial=0.0))}

    def _state_of(self, code: np.ndarray):
        """``(contact set, rows' state)`` of equation codes (:meth:`_code`'s inverse)."""
        rows = self.rows
        act = code[self.C] == FULL
        rc = code[self.S]
        st = np.where(rows.normal, np.where(rc == FULL, CLOSED, OPEN), OFF)
        fr = ~rows.normal
        st[fr & (rc == FULL)] = STICK
        st[fr & (rc == _SLIP_UP)] = SLIP_UP
        st[fr & (rc == _SLIP_DOWN)] = SLIP_DOWN
        return act, st.astype(np.int8)

    # ---------------------------------------------------------------- helpers --
    def _contact_gaps(self, act, lam, lam_s, alpha, q_c, cc, comp, Hc) -> np.ndarray:
        """Every contact node's gap: the open nodes' from the compliance, the others'
        from their equations (``-c lam``, 0 when rigid)."""
        n_c, cond = self.n_c, self.cond
        g = -(0.0 if cc is None else cc) * lam
        g = np.where(act, g, 0.0)
        if not act.all():
            # products with the whole blocks: cheaper than gathering the open rows
            go = q_c + Hc[:n_c] @ lam + cond.H[:n_c, n_c:] @ lam_s + cond.E[:n_c] @ alpha
            if comp is not None:
                go = go + self._ring_op(comp)(lam)
            g = np.where(act, g, go)
        return g

    def _row_changes(self, st, new_st, lam_s, g_s, F, singles: bool = False):
        """Parts of the rows' change ``st -> new_st`` whose states hold every rigid
        part, by violation: all the changes, the worse half, ..., the worst one (and
        with ``singles`` each other one alone)."""
        rows = self.rows
        ftol, gtol = self._tolerances(lam_s, F)
        d = np.nonzero(new_st != st)[0]
        if not d.size:
            return
        viol = np.abs(np.where(rows.normal[d], np.minimum(lam_s[d], 0.0) / ftol
                               + np.minimum(g_s[d], 0.0) / gtol, g_s[d] / gtol))
        d = d[np.argsort(-viol, kind="stable")]
        k = d.size
        while k >= 1:
            part = st.copy()
            part[d[:k]] = new_st[d[:k]]
            part = self._consistent(part)
            if not np.array_equal(part, st) and self._holds(part):
                yield part
            k //= 2
        for i in d[1:] if singles else ():
            one = st.copy()
            one[i] = new_st[i]
            one = self._consistent(one)
            if not np.array_equal(one, st) and self._holds(one):
                yield one


class _RowState:
    """The contact of one rows' state as a
    :class:`~brakewear.contact.active_set.SetProblem` of the contact nodes (the
    rows' state ``st`` set before each inner iteration)."""

    def __init__(self, js: JointSets, b, cc, comp, q_c, gap_s):
        self.js, self.b, self.cc, self.comp, self.q_c, self.gap_s = js, b, cc, comp, q_c, gap_s
        self.st = None
        self.lam = None
        self.Hc = js._hc(js.mu)

    def solve(self, active: np.ndarray, tol: float, rtol0, refine: bool = False) -> None:
        js = self.js
        code = js._code(active, self.st)
        z = js._solve_code(code, self.b, js.mu, self.cc, self.comp, refine)
        self.set_solution(active, code, z)

    def set_solution(self, active: np.ndarray, code: np.ndarray, z: np.ndarray) -> None:
        """Take ``z`` (unscaled, of the state ``code``) as the last solve's solution."""
        js = self.js
        self.active = active
        self.lam = np.where(active, z[js.C], 0.0)
        self.alpha, self.q = z[js.Mo], z[js.Q]
        self.lam_s = np.where(code[js.S] == IDENT, 0.0, z[js.S])
        self.g = js._contact_gaps(active, self.lam, self.lam_s, self.alpha, self.q_c, self.cc,
                                  self.comp, self.Hc)

    def margins(self, active: np.ndarray, band: float) -> Margins:
        if self.cc is None:
            bound = band * max(float(np.abs(self.lam).max()), 1e-300)
            return Margins(self.lam, bound, np.where(active, 0.0, -self.g), self.js.gap_tol)
        force = -self.g / self.cc
        fmax = max(float(force[active].max()) if active.any() else 0.0, 1e-300)
        return Margins(force, band * fmax, force, band * fmax)

    def result(self):
        """``(lam, alpha, lam_s, q, g, g_s)`` of the last solve, the rows' gaps added."""
        rows, cond, n_c = self.js.rows, self.js.cond, self.js.n_c
        g_s = (self.gap_s + self.Hc[n_c:] @ self.lam + cond.H[n_c:, n_c:] @ self.lam_s
               + cond.E[n_c:] @ self.alpha - rows.R @ self.q + rows.compliance * self.lam_s)
        return self.lam, self.alpha, self.lam_s, self.q, self.g, g_s
