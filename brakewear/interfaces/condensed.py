"""The condensed interface: the FE contact model's answer at the cost of a dense solve.

:class:`CondensedInterface` answers the wear loop's question (the pressure at
the pad's friction nodes for a gap offset) from the FE model condensed onto
those nodes (:mod:`brakewear.interfaces.compliance`).  Each contact solve is an
active-set iteration on a dense system of the active nodes,

    [Hn + mu Ht + diag(c)]_AA lam_A + E_A alpha = -q_A,
    (E^T + mu Dt)_A lam_A = -(zf p_line + Z^T load),

with ``q = g0 + offset + hf p_line`` (plus the thermal load's gap) and ``c``
the implicit step's wear compliance per newton (``eps / area``; zero for a
rigid contact).  Its LU factorisation is kept for the next solve with the
same set, friction coefficient and compliance (a wear history with fixed
steps reuses it step after step).  The active-set policy is the FE solves'
(:mod:`brakewear.contact.active_set`), so the answer is the FE answer.

Where it applies: gap-offset wear (the meshes do not move) with linear
elasticity.  A gap offset beyond ``valid_fraction`` of the friction face's
element height raises :class:`~brakewear.errors.CondensedRangeError`, which
names the FE interface with the geometry update as the alternative.
"""
from __future__ import annotations

import copy
import logging
import time
from collections import OrderedDict
from dataclasses import replace

import numpy as np
from scipy.linalg import lu_factor, lu_solve

from ..contact.active_set import COMPLIANT, EXACT, ActiveSetDriver, Margins
from ..errors import CondensedRangeError, ContactError, WearError
from .compliance import condense
from .fe import FEInterface
from .protocol import InterfaceSolution

logger = logging.getLogger(__name__)

__all__ = ["CondensedInterface"]

#: factorisations kept per interface (sets x friction x compliance)
_KEEP = 8
#: largest change of the active set solved by an update of a kept factorisation
_UPDATE_MAX = 48


class CondensedInterface:
    """The FE contact interface condensed onto the pad's friction nodes.

    Parameters
    ----------
    model, line_pressure, mu, tol
        As :class:`~brakewear.interfaces.FEInterface` (which this one builds,
        or takes as ``fe``, for the contact geometry and the thermal load).
    cache
        Where the condensed compliance is kept (a directory; None: the default
        of :func:`~brakewear.interfaces.compliance.cache_dir`; False: nowhere).
    valid_fraction
        The largest gap offset (worn depths and initial gap) allowed, as a
        share of the height of the pad's elements at its friction face.
    memory_budget
        GB allowed for the condensation (checked before it starts).

    The rotor's and the pad's surfaces, areas and rings, and the normal
    stiffness the step control uses, are those of the FE interface, so a
    history run on either takes the same steps.
    """

    #: the thermal-strain load enters as a gap change (one linear solve per load)
    accepts_load = True

    def __init__(self, model, line_pressure: float, mu: float = 0.0, tol: float = 1e-9, *,
                 cache=None, valid_fraction: float = 0.25, fe: FEInterface | None = None,
                 memory_budget: float | None = None):
        if not (np.isfinite(valid_fraction) and 0 < valid_fraction <= 1):
            raise WearError(f"valid_fraction = {valid_fraction!r} is not allowed; need "
                            "0 < valid_fraction <= 1")
        self.fe = fe if fe is not None else FEInterface(model, line_pressure, mu, tol)
        fe = self.fe
        if fe.supports:
            # a unilateral stop is a second contact: no longer linear off the friction face
            raise WearError(f"the condensed interface needs a bilateral pad support; this "
                            f"contact system has {len(fe.supports)} abutment stop pair(s) "
                            "(push/pull support): use the FE interface")
        self.model, self.line_pressure, self.mu, self.tol = model, line_pressure, mu, tol
        for name in ("pad_nodes", "x", "r", "area", "rotor_nodes", "ring", "rotor_area",
                     "rotor_x", "W", "normal_stiffness", "g0"):
            setattr(self, name, getattr(fe, name))
        t0 = time.perf_counter()
        self.cond = condense(fe.cs, fe.line_pressure, cache=cache, memory_budget=memory_budget)
        self.condense_s = time.perf_counter() - t0
        coords = fe.cs.coords
        self.gap_tol = 1e-10 * float(np.linalg.norm(coords.max(axis=1) - coords.min(axis=1)))
        from ..motion import surface_element_height

        self.valid_fraction = float(valid_fraction)
        self.max_offset = self.valid_fraction * surface_element_height(
            model.meshes["pad"], "friction")
        self._H = {}                        # mu -> (H, D)
        self._lu = OrderedDict()            # (set, mu, compliance) -> LU of the set's system
        self._base = {}                     # (mu, compliance) -> (set, LU): the updates' base
        self._updated = {}                  # set -> times an update solved it
        self._thermal = None                # the load -> gap operator, built on first use

    # -------------------------------------------------------------- protocol --
    def at_line_pressure(self, line_pressure: float) -> "CondensedInterface":
        """This interface under another line pressure (Pa): the condensation and
        its factorisations shared (the load's share scales)."""
        new = copy.copy(self)
        new.fe = self.fe.at_line_pressure(line_pressure)
        new.line_pressure = line_pressure
        return new

    def rebuilt(self, model, opening: float = 0.0):
        raise WearError("the condensed interface is for gap-offset wear: the geometry update "
                        "moves the meshes, which a condensation cannot follow; use "
                        "interface.model = 'fe' with numerics.update = 'geometry'")

    def solve(self, offset: np.ndarray, active: np.ndarray | None, *,
              compliance: np.ndarray | None = None, x0: np.ndarray | None = None,
              load: np.ndarray | None = None, mu=None) -> InterfaceSolution:
        """Contact with ``offset`` (m) added to the gap (the
        :class:`~brakewear.interfaces.Interface` protocol).  ``x0`` is not
        needed (every solve is direct); ``load`` is a nodal load of the
        model's DOFs (thermal strain), ``compliance`` (m/Pa per pad node) the
        implicit step's, ``mu`` a number or one per pad friction node."""
        t0 = time.perf_counter()
        offset = np.asarray(offset, dtype=float)
        self._check_range(offset)
        if mu is not None:
            self._set_mu(mu)
        cond, p = self.cond, self.line_pressure
        q = self.g0 + offset + cond.hf * p
        rhs = -cond.zf * p
        if load is not None:
            dq, dz = self.thermal_gap(load)
            q, rhs = q + dq, rhs - dz
        H, D = self._operators(self.mu)
        c = None if compliance is None else np.asarray(compliance, dtype=float) / self.area
        if c is not None and (c.shape != q.shape or not np.all(np.isfinite(c)) or np.any(c <= 0)):
            raise ContactError(f"compliance must be ({q.size},) finite and > 0 m/Pa")
        problem = _DenseSets(self, H, D, q, rhs, c)
        g = self.g0 + offset
        if active is not None:
            start = np.asarray(active, dtype=bool)
        else:
            # the FE solves' start: the closed nodes, else the closest ones
            start = g <= (self.gap_tol if c is None else 0.0)
            if not start.any():
                start = g <= g.min() + (self.gap_tol if c is None
                                        else 1e-12 * max(np.abs(g).max(), 1e-300))
        options = EXACT if c is None else replace(COMPLIANT, loose_tol=None)
        driver = ActiveSetDriver(options, self.tol, exact=True, name="pad-rotor (condensed)")
        act = driver.run(problem, start)
        lam = problem.lam
        pressure = (lam if c is None else np.maximum(lam, 0.0)) / self.area
        info = {**driver.report(), "factorisations": problem.factorised,
                "updates": problem.updated,
                "normal_force": float(lam.sum()), "min_gap": float(problem.g.min()),
                "time_s": time.perf_counter() - t0}
        return InterfaceSolution(pressure, act, None, info)

    # --------------------------------------------------------------- helpers --
    def _check_range(self, offset: np.ndarray) -> None:
        over = np.abs(offset) - self.max_offset
        i = int(np.argmax(over))
        if over[i] > 0:
            raise CondensedRangeError(
                f"condensed interface: the gap offset at pad node {int(self.pad_nodes[i])} "
                f"(r = {self.r[i] * 1e3:.1f} mm) is {abs(offset[i]) * 1e6:.1f} um, beyond "
                f"its limit of {self.max_offset[i] * 1e6:.1f} um ({self.valid_fraction:g} of "
                "the height of the elements at the face): the worn geometry is no longer the "
                "condensed one. Use interface.model = 'fe' with numerics.update = 'geometry'")

    def _set_mu(self, mu) -> None:
        """A number, or one friction coefficient per pad node (a friction law's)."""
        n = self.area.size
        mu = float(mu) if np.ndim(mu) == 0 else np.array(mu, dtype=float)
        if np.ndim(mu) and mu.shape != (n,):
            raise WearError(f"mu has shape {mu.shape}; need a number or ({n},), one per pad "
                            "friction node")
        if np.any(np.asarray(mu) < 0) or not np.all(np.isfinite(mu)):
            raise WearError(f"mu = {mu!r} is not allowed; need friction coefficients >= 0")
        if np.any(np.asarray(mu) > 0) and self.fe.pair.drag is None:
            raise WearError(f"mu = {mu!r}: this condensed interface was built without "
                            "friction (no sliding direction); build it with mu > 0")
        self.mu = mu

    @property
    def mu_key(self):
        """``mu`` as a key of the factorisation caches."""
        return self.mu if np.ndim(self.mu) == 0 else self.mu.tobytes()

    def _operators(self, mu):
        """``(Hn + Ht diag(mu), E^T + Dt diag(mu))``: the friction of node j is
        ``mu_j lam_j`` along its sliding direction (column j of ``Ht`` and ``Dt``)."""
        key = self.mu_key
        if key not in self._H:
            cond = self.cond
            if not np.any(np.asarray(mu) > 0):
                ops = (cond.Hn, cond.E.T)
            elif np.ndim(mu) == 0:
                ops = (cond.Hn + mu * cond.Ht, cond.E.T + mu * cond.Dt)
            else:
                ops = (cond.Hn + cond.Ht * mu[None, :], cond.E.T + cond.Dt * mu[None, :])
            self._H = {key: ops}
        return self._H[key]

    def kept(self, key, lu, active) -> None:
        """Keep ``lu`` (the set ``active`` under the friction and compliance of
        ``key``) for reuse, and as the base of the updates of that friction
        and compliance."""
        self._lu[key] = lu
        while len(self._lu) > _KEEP:
            self._lu.popitem(last=False)
        self._base[key[1:]] = (active.copy(), lu)
        while len(self._base) > _KEEP:
            self._base.pop(next(iter(self._base)))

    def thermal_gap(self, load: np.ndarray):
        """``(gap change per contact node, the free modes' share)`` of a nodal load."""
        if self._thermal is None:
            from .compliance import LoadGap

            self._thermal = LoadGap(self.fe.cs)
        return self._thermal(self.fe.cs.P.T @ load)


class _DenseSets:
    """One condensed contact solve as a :class:`~brakewear.contact.active_set.SetProblem`.

    The system of a set ``S`` is embedded in all ``n`` nodes and the ``m``
    modes: ``T_S = [[P K P + I - P, P E], [D P, 0]]`` with ``P`` the set's
    mask and ``K = H + diag(c)`` (an open node's row says ``lam_i = 0``).  A
    set met before (same friction and compliance) reuses its LU; a set that
    differs from the last factorised one (the *base*) in at most
    :data:`_UPDATE_MAX` nodes is solved from the base's LU by the
    Sherman-Morrison-Woodbury formula (``T_S - T_base`` has rank at most
    twice the changed nodes), checked by its residual; any other set is
    factorised and becomes the base.
    """

    def __init__(self, itf, H, D, q, rhs, c):
        self.itf, self.H, self.D, self.q, self.rhs, self.c = itf, H, D, q, rhs, c
        self.E = itf.cond.E
        self.factorised = self.updated = 0
        self.c_key = None if c is None else c.tobytes()

    def solve(self, active: np.ndarray, tol: float, rtol0: float | None) -> None:
        itf, n = self.itf, self.q.size
        key = (np.packbits(active).tobytes(), itf.mu_key, self.c_key)
        lu = itf._lu.get(key)
        state = None
        if lu is not None:
            itf._lu.move_to_end(key)
            state = self._gap(self._solve_with(lu, active), active)
        else:
            base = itf._base.get(key[1:])
            # a set that updates have solved twice is factorised: a history that has
            # settled on it then solves it by two triangular solves (a contact that
            # spreads meets each set twice: at the end of a step and the start of
            # the next)
            if base is not None and itf._updated.get(key, 0) < 2:
                changed = int(np.count_nonzero(base[0] != active))
                if 0 < changed <= min(_UPDATE_MAX, n // 4):
                    state = self._gap(self._woodbury(active, *base), active)
                    if self._solves(*state, active):
                        self.updated += 1
                        itf._updated[key] = itf._updated.get(key, 0) + 1
                        while len(itf._updated) > 4 * _KEEP:
                            itf._updated.pop(next(iter(itf._updated)))
                    else:
                        state = None
            if state is None:
                lu = self._factor(active)
                itf.kept(key, lu, active)
                self.factorised += 1
                state = self._gap(self._solve_with(lu, active), active)
        self.lam, self.g = state
        if self.c is None:
            self.g[active] = 0.0

    # ------------------------------------------------------------------ --
    def _factor(self, active):
        A = np.nonzero(active)[0]
        m, k = self.E.shape[1], A.size
        M = np.empty((k + m, k + m))
        M[:k, :k] = self.H[np.ix_(A, A)]
        if self.c is not None:
            M[np.arange(k), np.arange(k)] += self.c[A]
        M[:k, k:] = self.E[A]
        M[k:, :k] = self.D[:, A]
        M[k:, k:] = 0.0
        return lu_factor(M, check_finite=False)

    def _full_rhs(self, active):
        n = self.q.size
        b = np.zeros(n + self.E.shape[1])
        b[:n] = np.where(active, -self.q, 0.0)
        b[n:] = self.rhs
        return b

    def _apply(self, lu, mask, V):
        """``T_mask^-1 V`` from the LU of ``mask``'s compressed system."""
        n = self.q.size
        idx = np.concatenate([np.nonzero(mask)[0], n + np.arange(self.E.shape[1])])
        Z = np.array(V, dtype=float, copy=True)
        Z[idx] = lu_solve(lu, V[idx], check_finite=False)
        return Z

    def _solve_with(self, lu, active):
        return self._apply(lu, active, self._full_rhs(active))

    def _rows(self, rows, mask):
        """Rows ``rows`` of the embedded ``T_mask``."""
        n = self.q.size
        R = np.zeros((rows.size, n + self.E.shape[1]))
        inside = mask[rows]
        r_in = rows[inside]
        R[inside, :n] = self.H[r_in] * mask
        if self.c is not None:
            R[np.nonzero(inside)[0], r_in] += self.c[r_in]
        R[inside, n:] = self.E[r_in]
        R[np.nonzero(~inside)[0], rows[~inside]] = 1.0
        return R

    def _woodbury(self, active, base_mask, lu):
        """The embedded system of ``active`` from the LU of ``base_mask``'s."""
        n = self.q.size
        d = np.nonzero(active != base_mask)[0]
        k = d.size
        X = self._rows(d, active) - self._rows(d, base_mask)      # changed rows
        s = np.where(active[d], 1.0, -1.0)
        Y = np.zeros((X.shape[1], k))                              # changed columns, other rows
        both = np.nonzero(active & base_mask)[0]
        Y[both] = self.H[np.ix_(both, d)] * s
        Y[n:] = self.D[:, d] * s
        U = np.zeros((X.shape[1], 2 * k))
        U[d, np.arange(k)] = 1.0
        U[:, k:] = Y
        W = self._apply(lu, base_mask, U)
        z0 = self._apply(lu, base_mask, self._full_rhs(active))
        cap = np.eye(2 * k) + np.vstack([X @ W, W[d]])
        return z0 - W @ np.linalg.solve(cap, np.concatenate([X @ z0, z0[d]]))

    def _gap(self, z, active):
        """The contact forces and gaps of a solution ``z`` of the embedded system."""
        n = self.q.size
        lam = np.where(active, z[:n], 0.0)
        return lam, self.q + self.H @ lam + self.E @ z[n:]

    def _solves(self, lam, g, active) -> bool:
        """Whether ``lam`` (with its gaps ``g``) solves the set's equations to round-off."""
        r = g if self.c is None else g + self.c * lam
        ref = max(float(np.abs(self.q[active]).max()), float(np.abs((g - self.q)[active]).max()),
                  1e-300)
        bottom = self.D @ lam - self.rhs
        return bool(np.abs(r[active]).max() <= 1e-12 * ref and np.abs(bottom).max() <= 1e-12 * max(
            np.abs(self.rhs).max(), np.abs(self.D).max() * np.abs(lam).sum(), 1e-300))

    def margins(self, active: np.ndarray, band: float) -> Margins:
        if self.c is None:
            bound = band * max(float(np.abs(self.lam).max()), 1e-300)
            return Margins(self.lam, bound, np.where(active, 0.0, -self.g), self.itf.gap_tol)
        force = -self.g / self.c
        fmax = max(float(force[active].max()) if active.any() else 0.0, 1e-300)
        return Margins(force, band * fmax, force, band * fmax)
