"""The condensed interface: the FE contact model's answer at the cost of a dense solve.

:class:`CondensedInterface` answers the wear loop's question (the pressure at
the pad's friction nodes for a gap offset) from the FE model condensed onto
those nodes (:mod:`brakewear.interfaces.condensation`).  Each contact solve is an
active-set iteration on a dense system of the active nodes,

    [Hn + mu Ht + diag(c)]_AA lam_A + E_A alpha = -q_A,
    (E^T + mu Dt)_A lam_A = -(zf p_line + Z^T load),

with ``q = g0 + offset + hf p_line`` (plus the thermal load's gap) and ``c``
the implicit step's wear compliance per newton (``eps / area``; zero for a
rigid contact).  The system of every node in contact is factorised once per
friction coefficient and compliance, and each set is solved from it with
its open nodes held by a small Schur system (:class:`DenseSets`; a wear
history with fixed steps reuses both step after step), on one BLAS thread.
The active-set policy is the FE solves' (:mod:`brakewear.contact.active_set`),
so the answer is the FE answer.

Where it applies: gap-offset wear (the meshes do not move) with linear
elasticity, P1 or P2 meshes.  A gap offset beyond ``valid_fraction`` of the friction face's
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
from ..solvers.threads import blas_threads
from .condensation import check_scene_size, condense
from .fe import METHOD, FEInterface
from .protocol import InterfaceSolution, StepCompliance
from .registry import register_interface

logger = logging.getLogger(__name__)

__all__ = ["CondensedInterface"]

#: factorisations kept per interface (friction x compliance, or sets x friction x
#: compliance), and the Schur systems of the sets solved from them
_KEEP = 4
_SETS = 16
#: nodes whose base columns are solved together
_BLOCK = 32


def solve_dense_sets(problem, g: np.ndarray, active, gap_tol: float, compliant: bool,
                     tol: float, name: str) -> tuple[np.ndarray, dict]:
    """The exact active-set solve of a dense contact problem (``DenseSets``),
    from ``active`` or else the FE solves' start: the closed nodes (within
    ``gap_tol`` without a compliance), else the closest ones.  Returns the
    active set and the driver's report."""
    if active is not None:
        start = np.asarray(active, dtype=bool)
    else:
        start = g <= (0.0 if compliant else gap_tol)
        if not start.any():
            start = g <= g.min() + (1e-12 * max(np.abs(g).max(), 1e-300) if compliant
                                    else gap_tol)
    options = replace(COMPLIANT, loose_tol=None) if compliant else EXACT
    driver = ActiveSetDriver(options, tol, exact=True, name=name)
    return driver.run(problem, start), driver.report()


@register_interface
class CondensedInterface:
    """The FE contact interface condensed onto the pad's friction nodes.

    Parameters
    ----------
    model, line_pressure, mu, tol
        As :class:`~brakewear.interfaces.FEInterface` (which this one builds,
        or takes as ``fe``, for the contact geometry and the thermal load).
    cache
        Where the condensed compliance is kept (a directory; None: the default
        of :func:`~brakewear.interfaces.condensation.cache_dir`; False: nowhere).
    valid_fraction
        The largest gap offset (worn depths and initial gap) allowed, as a
        share of the height of the pad's elements at its friction face.
    fe
        The FE interface to condense (None: one is built).
    memory_budget
        GB allowed for the condensation (checked before it starts).

    Notes
    -----
    The rotor's and the pad's surfaces, areas and rings, and the normal
    stiffness the step control uses, are those of the FE interface, so a
    history run on either takes the same steps.
    """

    #: the thermal-strain load enters as a gap change (one linear solve per load)
    accepts_load = True
    #: mu per node; at another line pressure (the load's share scales); P2 faces
    per_node_friction = any_line_pressure = quadratic = True
    #: the rings' wear of an implicit step adds its rank-n_ring compliance
    implicit_rings = True
    #: the condensation is of the unmoved meshes
    follows_geometry = False
    why_not = {"follows_geometry": "the condensation is of the unmoved meshes"}
    #: its pressure is the FE contact's, to the solvers' tolerance
    fe_answer = True

    #: ``interface.model = "condensed"`` in a scene, with its keys of ``[interface]``
    name = "condensed"
    keys = (METHOD,)

    @classmethod
    def build(cls, request) -> CondensedInterface:
        """The interface of a scene's run (:class:`~brakewear.interfaces.BuildRequest`),
        condensing the FE interface an ``"auto"`` choice built, if it did."""
        return cls(request.model, request.line_pressure, request.mu, request.numerics.tol,
                   memory_budget=request.numerics.memory_budget, fe=request.built.get("fe"))

    @classmethod
    def check_scene(cls, scene) -> None:
        """The scene's condensation fits the memory
        (:func:`~brakewear.interfaces.condensation.check_scene_size`)."""
        check_scene_size(scene)

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
        from ..motion.brake import surface_element_height

        self.valid_fraction = float(valid_fraction)
        self.max_offset = self.valid_fraction * surface_element_height(
            model.meshes["pad"], "friction")
        self._H = {}                        # mu -> (H, D)
        self._lu = OrderedDict()            # (set, mu, compliance) -> LU of the set's system
        self._bases = OrderedDict()         # (mu, compliance) -> _Base: every node's system
        self._thermal = None                # the load -> gap operator, built on first use
        self._ringed = {}                   # (mu, rings' step) -> H with the rings' compliance

    # -------------------------------------------------------------- protocol --
    def at_line_pressure(self, line_pressure: float) -> CondensedInterface:
        """This interface under another line pressure (Pa): the condensation and
        its factorisations shared (the load's share scales)."""
        new = copy.copy(self)
        new.fe = self.fe.at_line_pressure(line_pressure)
        new.line_pressure = line_pressure
        return new

    @property
    def settings(self) -> dict:
        """Its own settings: the contact solves' tolerance and the range of gap
        offsets it answers (a share of the face elements' height)."""
        return {"tol": float(self.tol), "valid_fraction": self.valid_fraction}

    def rebuilt(self, model, opening: float = 0.0):
        raise WearError("the condensed interface is for gap-offset wear: the geometry update "
                        "moves the meshes, which a condensation cannot follow; use "
                        "interface.model = 'fe' with numerics.update = 'geometry'")

    def solve(self, offset: np.ndarray, active: np.ndarray | None, *,
              compliance: StepCompliance | np.ndarray | None = None,
              x0: np.ndarray | None = None, load: np.ndarray | None = None,
              mu=None) -> InterfaceSolution:
        """Contact with ``offset`` (m) added to the gap (the
        :class:`~brakewear.interfaces.Interface` protocol).  ``x0`` is not
        needed (every solve is direct); ``load`` is a nodal load of the
        model's DOFs (thermal strain), ``compliance`` the implicit step's (a
        :class:`~brakewear.interfaces.StepCompliance`, whose rings add their
        rank-``n_ring`` compliance to the dense one, or the pad's alone in
        m/Pa per pad node), ``mu`` a number or one per pad friction node."""
        t0 = time.perf_counter()
        offset = np.asarray(offset, dtype=float)
        self.check_range(offset)
        if mu is not None:
            self.set_mu(mu)
        cond, p = self.cond, self.line_pressure
        q = self.g0 + offset + cond.hf * p
        rhs = -cond.zf * p
        if load is not None:
            dq, dz = self.thermal_gap(load)
            q, rhs = q + dq, rhs - dz
        H, D = self._operators(self.mu)
        comp = StepCompliance.of(compliance)
        c = None if comp is None else comp.pad / self.area
        if c is not None and c.shape != q.shape:
            raise ContactError(f"compliance must be ({q.size},) finite and > 0 m/Pa")
        rings = comp is not None and comp.rings
        ring_key = comp.ring_key if rings else b""
        g = self.g0 + offset
        with blas_threads(1):
            if rings:
                # the rings' wear over the step: the gap per newton,
                # W diag(1/A_ring) W^T diag(eps_rot)
                H = self._with_rings(H, comp, ring_key)
            problem = DenseSets(self, H, D, q, rhs, c, ring_key)
            act, report = solve_dense_sets(problem, g, active, self.gap_tol, c is not None,
                                           self.tol, "pad-rotor (condensed)")
        lam = problem.lam
        pressure = (lam if c is None else np.maximum(lam, 0.0)) / self.area
        info = {**report, "factorisations": problem.factorised,
                "updates": problem.updated,
                "normal_force": float(lam.sum()), "min_gap": float(problem.g.min()),
                "time_s": time.perf_counter() - t0}
        if rings:
            info["ring_depth"] = comp.ring_depth_of_forces(lam)
        return InterfaceSolution(pressure, act, None, info)

    # --------------------------------------------------------------- helpers --
    def check_range(self, offset: np.ndarray) -> None:
        """Refuse a gap offset (m) beyond the range where the condensation holds
        (:class:`~brakewear.errors.CondensedRangeError`); subclasses call it too."""
        over = np.abs(offset) - self.max_offset
        i = int(np.argmax(over))
        if over[i] > 0:
            raise CondensedRangeError(
                f"condensed interface: the gap offset at pad node {int(self.pad_nodes[i])} "
                f"(r = {self.r[i] * 1e3:.1f} mm) is {abs(offset[i]) * 1e6:.1f} um, beyond "
                f"its limit of {self.max_offset[i] * 1e6:.1f} um ({self.valid_fraction:g} of "
                "the height of the elements at the face): the worn geometry is no longer the "
                "condensed one. Use interface.model = 'fe' with numerics.update = 'geometry'")

    def set_mu(self, mu) -> None:
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

    def _with_rings(self, H: np.ndarray, comp: StepCompliance, key: bytes) -> np.ndarray:
        """``H`` plus the rings' compliance (dense, rank ``n_ring``), kept while the
        friction and the rings' step stay the same: fixed steps assemble nothing."""
        k = (self.mu_key, key)
        got = self._ringed.get(k)
        if got is None:
            got = H + comp.ring_compliance()
            self._ringed = {k: got}
        return got

    def thermal_gap(self, load: np.ndarray):
        """``(gap change per contact node, the free modes' share)`` of a nodal load."""
        if self._thermal is None:
            from .condensation import LoadGap

            self._thermal = LoadGap(self.fe.cs)
        return self._thermal(self.fe.cs.P.T @ load)


class _Base:
    """The factorised system of every node in contact under one friction and
    compliance, and its solved columns (in fixed blocks of nodes)."""

    def __init__(self, lu, n: int, m: int):
        self.lu, self.n, self.m = lu, n, m
        self.columns = np.zeros((n + m, n))     # base^-1 e_j, column j once solved
        self.solved = np.zeros(-(-n // _BLOCK), dtype=bool)
        self.sets: OrderedDict = OrderedDict()  # set -> (LU of its Schur system, its columns)

    def columns_of(self, nodes: np.ndarray) -> np.ndarray:
        """``base^-1 e_j`` of each node (the unit load that holds it), solved
        block by block: a block of :data:`_BLOCK` consecutive nodes at once,
        always the same block, so a column does not depend on which sets
        asked first (a resumed run repeats the uninterrupted one)."""
        for b in np.unique(nodes // _BLOCK):
            if not self.solved[b]:
                js = np.arange(b * _BLOCK, min((b + 1) * _BLOCK, self.n))
                V = np.zeros((self.n + self.m, js.size))
                V[js, np.arange(js.size)] = 1.0
                self.columns[:, js] = lu_solve(self.lu, V, check_finite=False)
                self.solved[b] = True
        return self.columns[:, nodes]


class DenseSets:
    """One condensed contact solve as a :class:`~brakewear.contact.active_set.SetProblem`.

    The system of a set ``A`` (the rows of ``H + diag(c)`` of its nodes and
    the ``m`` free modes, their block ``Q`` zero unless the caliper's rows
    hold them, :mod:`brakewear.caliper.sets`) is the system of every node (the *base*, factorised
    once per friction and compliance) with the open nodes ``R`` held at
    ``lam = 0`` by multipliers: ``z = y - X w`` with ``y = base^-1 b``, the
    base's solved unit columns ``X`` of ``R`` (each solved once per base)
    and the Schur system ``X_RR w = y_R`` of ``|R|`` unknowns (its LU kept
    per set, with the columns it takes).  A settled contact meets the same
    set step after step at the cost of a triangular solve pair and a
    product with the columns of its open nodes.  A set with more open
    nodes than half its active ones, or whose Schur solve does not satisfy
    the set's equations to 1e-12 of their terms, is factorised on its own
    (the LU kept per set).  Every choice depends on the set alone, never on
    the sets met before, so a resumed run repeats the uninterrupted one.
    """

    def __init__(self, itf, H, D, q, rhs, c, ring_key: bytes = b"", E=None, Q=None):
        self.itf, self.H, self.D, self.q, self.rhs, self.c = itf, H, D, q, rhs, c
        # the modes' columns and, where the caliper's rows hold the modes, their own
        # block (:mod:`brakewear.caliper.sets`); else the condensation's, 0
        self.E = itf.cond.E if E is None else E
        self.Q = Q
        self.alpha = np.zeros(self.E.shape[1])
        self.factorised = self.updated = 0
        self.c_key = None if c is None else c.tobytes() + ring_key

    def solve(self, active: np.ndarray, tol: float, rtol0: float | None) -> None:
        itf, n = self.itf, self.q.size
        key = (itf.mu_key, self.c_key)
        rem = np.nonzero(~active)[0]
        state = None
        if 2 * rem.size <= n - rem.size:
            # the gaps of the open nodes only: the set's equations give the others
            z, w = self._schur(self._base(key), active, rem)
            state = self._gap(z, active, rem, w)
            if not rem.size:
                pass
            elif self._solves(*state, active):
                self.updated += 1
            else:
                state = None
        if state is None:
            set_key = (np.packbits(active).tobytes(), *key)
            lu = itf._lu.get(set_key)
            if lu is None:
                lu = itf._lu[set_key] = self._factor(active)
                self.factorised += 1
                while len(itf._lu) > _KEEP:
                    itf._lu.popitem(last=False)
            itf._lu.move_to_end(set_key)
            state = self._gap(self._direct(lu, active), active, rem)
        self.lam, self.g = state
        if self.c is None:
            self.g[active] = 0.0

    # ------------------------------------------------------------------ --
    def _block(self, rows, cols):
        """Rows ``rows`` and columns ``cols`` of ``H + diag(c)`` (node numbers)."""
        M = self.H.take(rows, axis=0).take(cols, axis=1)
        if self.c is not None:
            at = np.full(self.q.size, -1, dtype=np.int64)
            at[cols] = np.arange(cols.size)
            i = np.nonzero(at[rows] >= 0)[0]
            M[i, at[rows[i]]] += self.c[rows[i]]
        return M

    def _comply(self, lam):
        """The compliance's share of the active rows: ``c lam`` (0 when rigid)."""
        return 0.0 if self.c is None else self.c * lam

    def _factor(self, active):
        """The LU of the set's system (its nodes, then the modes)."""
        A = np.nonzero(active)[0]
        m, k = self.E.shape[1], A.size
        M = np.empty((k + m, k + m))
        M[:k, :k] = self._block(A, A)
        M[:k, k:] = self.E[A]
        M[k:, :k] = self.D[:, A]
        M[k:, k:] = 0.0 if self.Q is None else self.Q
        return lu_factor(M, check_finite=False)

    def _base(self, key) -> _Base:
        """The base of ``key`` (friction, compliance): every node in contact."""
        itf = self.itf
        base = itf._bases.get(key)
        if base is None:
            n = self.q.size
            base = itf._bases[key] = _Base(self._factor(np.ones(n, dtype=bool)), n,
                                           self.E.shape[1])
            self.factorised += 1
            while len(itf._bases) > _KEEP:
                itf._bases.popitem(last=False)
        itf._bases.move_to_end(key)
        return base

    def _direct(self, lu, active):
        """The solution ``z`` (n nodes, then m modes) from the set's own LU."""
        n, A = self.q.size, np.nonzero(active)[0]
        y = lu_solve(lu, np.concatenate([-self.q[A], self.rhs]), check_finite=False)
        z = np.zeros(n + self.E.shape[1])
        z[A], z[n:] = y[:A.size], y[A.size:]
        return z

    def _schur(self, base: _Base, active, rem):
        """The solution ``z`` from the base, the open nodes ``rem`` held, and the
        loads ``w`` that hold them."""
        y = lu_solve(base.lu, np.concatenate([-self.q, self.rhs]), check_finite=False)
        if not rem.size:
            return y, np.zeros(0)
        set_key = np.packbits(active).tobytes()
        got = base.sets.get(set_key)
        if got is None:                          # its LU and its (n + m) x |R| columns
            X = base.columns_of(rem)
            got = base.sets[set_key] = (lu_factor(X[rem], check_finite=False), X)
            while len(base.sets) > _SETS:
                base.sets.popitem(last=False)
        base.sets.move_to_end(set_key)
        lu, X = got
        w = lu_solve(lu, y[rem], check_finite=False)
        z = y - X @ w
        z[rem] = 0.0
        return z, w

    def _gap(self, z, active, rows=None, held=None):
        """The contact forces and gaps of a solution ``z`` of the embedded system:
        the gaps of ``rows`` (default every node) from the compliance, or, given
        ``held`` (the multipliers that hold them open in the base's system), as
        ``-held``; the others from the set's equations (``g = -c lam``, 0 when
        rigid), which a factorised system satisfies to round-off."""
        n = self.q.size
        lam = np.where(active, z[:n], 0.0)
        self.alpha = z[n:]
        if rows is None:
            return lam, self.q + self.H @ lam + self.E @ z[n:]
        g = -self._comply(lam) * active
        # the base's row of an open node reads g_i + w_i = 0: no product with H's rows
        g[rows] = -held if held is not None else (self.q[rows] + self.H[rows] @ lam
                                                  + self.E[rows] @ z[n:])
        return lam, g

    def _solves(self, lam, g, active) -> bool:
        """Whether ``lam`` (with its gaps ``g``) solves the set's equations to round-off."""
        r = g + self._comply(lam)
        ref = max(float(np.abs(self.q[active]).max()), float(np.abs((g - self.q)[active]).max()),
                  1e-300)
        bottom = self.D @ lam - self.rhs
        if self.Q is not None:
            bottom = bottom + self.Q @ self.alpha
        return bool(np.abs(r[active]).max() <= 1e-12 * ref and np.abs(bottom).max() <= 1e-12 * max(
            np.abs(self.rhs).max(), np.abs(self.D).max() * np.abs(lam).sum(), 1e-300))

    def margins(self, active: np.ndarray, band: float) -> Margins:
        if self.c is None:
            bound = band * max(float(np.abs(self.lam).max()), 1e-300)
            return Margins(self.lam, bound, np.where(active, 0.0, -self.g), self.itf.gap_tol)
        force = -self.g / self.c
        fmax = max(float(force[active].max()) if active.any() else 0.0, 1e-300)
        return Margins(force, band * fmax, force, band * fmax)
