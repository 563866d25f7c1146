"""The condensed interface: the FE contact model's answer at the cost of a dense solve.

:class:`CondensedInterface` answers the wear loop's question (the pressure at
the pad's friction nodes for a gap offset) from the FE model condensed onto
those nodes (:mod:`brakewear.interfaces.condensation`).  Each contact solve is an
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
from ..errors import CondensedRangeError, WearError
from .condensation import condense
from .fe import FEInterface
from .protocol import InterfaceSolution

logger = logging.getLogger(__name__)

__all__ = ["CondensedInterface"]

#: factorisations kept per interface (sets x friction x compliance)
_KEEP = 8


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
              load: np.ndarray | None = None, mu: float | None = None) -> InterfaceSolution:
        """Contact with ``offset`` (m) added to the gap (the
        :class:`~brakewear.interfaces.Interface` protocol).  ``x0`` is not
        needed (every solve is direct); ``load`` is a nodal load of the
        model's DOFs (thermal strain), ``compliance`` (m/Pa per pad node) the
        implicit step's."""
        t0 = time.perf_counter()
        offset = np.asarray(offset, dtype=float)
        self._check_range(offset)
        if mu is not None:
            self.mu = float(mu)
        cond, p = self.cond, self.line_pressure
        q = self.g0 + offset + cond.hf * p
        rhs = -cond.zf * p
        if load is not None:
            dq, dz = self.thermal_gap(load)
            q, rhs = q + dq, rhs - dz
        H, D = self._operators(self.mu)
        c = None if compliance is None else np.asarray(compliance, dtype=float) / self.area
        if c is not None and (c.shape != q.shape or not np.all(np.isfinite(c)) or np.any(c <= 0)):
            raise ValueError(f"compliance must be ({q.size},) finite and > 0 m/Pa")
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
                f"{self.valid_fraction:g} of the face's element height "
                f"({self.max_offset[i] * 1e6:.1f} um): the worn geometry is no longer the "
                "condensed one. Use interface.model = 'fe' with numerics.update = 'geometry'")

    def _operators(self, mu: float):
        if mu not in self._H:
            cond = self.cond
            self._H = {mu: (cond.Hn + mu * cond.Ht if mu else cond.Hn,
                            cond.E.T + mu * cond.Dt if mu else cond.E.T)}
        return self._H[mu]

    def factorised(self, key, build):
        """The LU of ``key``'s system, from the kept ones or ``build()``."""
        lu = self._lu.get(key)
        if lu is not None:
            self._lu.move_to_end(key)
            return lu, False
        lu = build()
        self._lu[key] = lu
        while len(self._lu) > _KEEP:
            self._lu.popitem(last=False)
        return lu, True

    def thermal_gap(self, load: np.ndarray):
        """``(gap change per contact node, the free modes' share)`` of a nodal load."""
        if self._thermal is None:
            from .condensation import LoadGap

            self._thermal = LoadGap(self.fe.cs)
        return self._thermal(self.fe.cs.P.T @ load)


class _DenseSets:
    """One condensed contact solve as a :class:`~brakewear.contact.active_set.SetProblem`."""

    def __init__(self, itf, H, D, q, rhs, c):
        self.itf, self.H, self.D, self.q, self.rhs, self.c = itf, H, D, q, rhs, c
        self.E = itf.cond.E
        self.factorised = 0
        self.c_key = None if c is None else c.tobytes()

    def solve(self, active: np.ndarray, tol: float, rtol0: float | None) -> None:
        A = np.nonzero(active)[0]
        m = self.E.shape[1]
        key = (np.packbits(active).tobytes(), self.itf.mu, self.c_key)

        def build():
            n = A.size
            M = np.empty((n + m, n + m))
            M[:n, :n] = self.H[np.ix_(A, A)]
            if self.c is not None:
                M[np.arange(n), np.arange(n)] += self.c[A]
            M[:n, n:] = self.E[A]
            M[n:, :n] = self.D[:, A]
            M[n:, n:] = 0.0
            return lu_factor(M, check_finite=False)

        lu, new = self.itf.factorised(key, build)
        self.factorised += new
        x = lu_solve(lu, np.concatenate([-self.q[A], self.rhs]), check_finite=False)
        lam = np.zeros(self.q.size)
        lam[A] = x[:A.size]
        self.lam = lam
        self.g = self.q + self.H @ lam + self.E @ x[A.size:]
        if self.c is None:
            self.g[A] = 0.0

    def margins(self, active: np.ndarray, band: float) -> Margins:
        if self.c is None:
            bound = band * max(float(np.abs(self.lam).max()), 1e-300)
            return Margins(self.lam, bound, np.where(active, 0.0, -self.g), self.itf.gap_tol)
        force = -self.g / self.c
        fmax = max(float(force[active].max()) if active.any() else 0.0, 1e-300)
        return Margins(force, band * fmax, force, band * fmax)
