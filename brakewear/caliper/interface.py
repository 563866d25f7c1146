"""The pads as the caliper holds them: contact with a rigid piston, fingers and abutments.

:class:`CaliperInterface` answers the wear loop's question (the pressure at
the pads' friction nodes for a gap offset) for a model whose piston is a rigid
body in its bore (``BrakeModel(piston="rigid")``): the caliper's rows
(:mod:`brakewear.caliper.rows`: the piston's rim, its bore and seal, the
fingers, the abutments, with their friction) and the pad-rotor contact, all
condensed onto their nodes (:mod:`brakewear.caliper.condensation`),
solved by nested active sets (:mod:`brakewear.caliper.sets`).

The bracket's rails and the pad's clip hold the end faces' mean
displacements (:func:`~brakewear.caliper.parts.bracket_springs`), so
they take the pad's in-plane motion but leave its tilt to the rows, and the
pads' free modes are exactly free.  Like the condensed interface this is
for gap-offset wear with linear elasticity (a worn geometry is not
followed), on linear meshes.
"""
from __future__ import annotations

import copy
import dataclasses
import logging
import time

import numpy as np

from ..checks import fail
from ..contact.supports import support_springs
from ..errors import ContactError, SolverError, WearError
from ..interfaces.condensed import CondensedInterface
from ..interfaces.fe import METHOD, FEInterface
from ..interfaces.protocol import InterfaceSolution, StepCompliance
from ..interfaces.registry import register_interface
from .condensation import condense_caliper
from .joint import JointSets
from .parts import bracket_springs
from .rows import caliper_rows
from .sets import RowSets

logger = logging.getLogger(__name__)

__all__ = ["CaliperInterface"]

#: the solvers of the contact and the rows: one active-set iteration over both (the
#: default), or a fixed point of the rows' state around the contact's active sets
SOLVERS = {"joint": JointSets, "nested": RowSets}
#: the shares of the gap offset and the thermal load a solve that fails from the rows' last
#: state is taken through, from the flat state
CONTINUATION = (0.0, 0.25, 0.5, 0.75, 1.0)


@register_interface
class CaliperInterface(CondensedInterface):
    """Contact of the pads held by a rigid piston, fingers and abutments (see the module).

    Parameters
    ----------
    model
        A :class:`~brakewear.model.BrakeModel` with ``piston = "rigid"``.
    line_pressure, mu, tol, cache, valid_fraction, memory_budget
        As :class:`~brakewear.interfaces.CondensedInterface`.
    solver
        ``"joint"`` (default): the contact and the rows in one active-set
        iteration on a kept factorisation (:class:`~brakewear.caliper.joint.JointSets`);
        ``"nested"``: a fixed point of the rows' state around the contact's
        active sets (:class:`~brakewear.caliper.sets.RowSets`), the reference.

    Attributes
    ----------
    rows : CaliperRows
        The caliper's rows and rigid parts.
    sets : JointSets or RowSets
        The solver; its ``state`` (the rows' last state) starts the next solve.
    """

    #: the thermal-strain load enters as a gap change of the contact nodes and the rows
    accepts_load = True
    #: built on linear meshes (the caliper's rows are node rows of linear faces)
    quadratic = False
    why_not = {"follows_geometry": "the condensation is of the unmoved meshes",
               "quadratic": "the caliper's rows are built on linear meshes"}
    #: a model of its own (the caliper's load path): FE contact's measured convergence
    #: does not rate it
    fe_answer = False

    #: ``interface.model = "caliper"`` in a scene, with its keys of ``[interface]``
    name = "caliper"
    keys = (METHOD,)

    @classmethod
    def build(cls, request) -> CaliperInterface:
        """The interface of a scene's run (:class:`~brakewear.interfaces.BuildRequest`)."""
        return cls(request.model, request.line_pressure, request.mu, request.numerics.tol,
                   memory_budget=request.numerics.memory_budget)

    @classmethod
    def check_scene(cls, scene) -> None:
        """A scene's caliper needs a rigid piston (``components.piston``)."""
        _rigid_piston(scene.piston)

    def __init__(self, model, line_pressure: float, mu: float = 0.0, tol: float = 1e-9, *,
                 cache=None, valid_fraction: float = 0.25, memory_budget: float | None = None,
                 solver: str = "joint"):
        if solver not in SOLVERS:
            raise WearError(f"solver = {solver!r} is not allowed; allowed: "
                            f"{', '.join(map(repr, SOLVERS))}")
        self.solver = solver
        if getattr(model, "piston", None) != "rigid":
            raise WearError("the caliper interface needs BrakeModel(piston='rigid'); this model "
                            f"has piston = {getattr(model, 'piston', None)!r}")
        if not (np.isfinite(valid_fraction) and 0 < valid_fraction <= 1):
            raise WearError(f"valid_fraction = {valid_fraction!r} is not allowed; need "
                            "0 < valid_fraction <= 1")
        if model.order != 1:
            raise WearError("the caliper interface needs a linear mesh (order = 1)")
        fe = FEInterface(model, line_pressure, mu, tol)
        fe.cs = _with_bracket_springs(model, fe.cs)
        self.fe = fe
        self.model, self.line_pressure, self.mu, self.tol = model, line_pressure, mu, tol
        for name in ("pad_nodes", "x", "r", "area", "rotor_nodes", "ring", "rotor_area",
                     "rotor_x", "W", "normal_stiffness", "g0"):
            setattr(self, name, getattr(fe, name))
        cs = fe.cs
        pad = model.meshes["pad"]
        self.rows = rows = caliper_rows(model.geometry, pad, model.offsets["pad"], cs.col,
                                        cs.K.shape[0], model.full)
        t0 = time.perf_counter()
        self.cond = condense_caliper(cs, rows.C, line_pressure, cache=cache,
                                     memory_budget=memory_budget)
        self.condense_s = time.perf_counter() - t0
        coords = cs.coords
        self.gap_tol = 1e-10 * float(np.linalg.norm(coords.max(axis=1) - coords.min(axis=1)))
        from ..motion.brake import surface_element_height

        self.valid_fraction = float(valid_fraction)
        self.max_offset = self.valid_fraction * surface_element_height(pad, "friction")
        self.sets = SOLVERS[solver](self.cond, rows, self.gap_tol, tol)
        self._thermal = None

    def solve(self, offset: np.ndarray, active: np.ndarray | None, *,
              compliance: StepCompliance | np.ndarray | None = None,
              x0: np.ndarray | None = None, load: np.ndarray | None = None,
              mu=None) -> InterfaceSolution:
        """Contact with ``offset`` (m) added to the gap (the
        :class:`~brakewear.interfaces.Interface` protocol; arguments as
        :meth:`CondensedInterface.solve`).  ``info["caliper"]`` holds the rows'
        forces (N), gaps or slips (m) and state, the rigid DOFs ``q``, the pads'
        free modes ``alpha``, the contact forces ``lam`` and the outer
        iterations."""
        t0 = time.perf_counter()
        offset = np.asarray(offset, dtype=float)
        self.check_range(offset)
        if mu is not None:
            self.set_mu(mu)
        self.sets.mu = self.mu
        cond = self.cond
        dq, dz = (np.zeros(cond.H.shape[0]), 0.0) if load is None else self.thermal_gap(load)
        g = self.g0 + offset
        comp = StepCompliance.of(compliance)
        cc = None if comp is None else comp.pad / self.area
        if cc is not None and cc.shape != g.shape:
            raise ContactError(f"compliance must be ({g.size},) finite and > 0 m/Pa")
        rings = comp is not None and comp.rings
        if isinstance(self.sets, JointSets):
            try:
                sol = self._sets_solve(offset, active, dq, dz, cc, comp)
            except SolverError as e:
                # a strongly coned state from the rows' last (or unloaded) state: reach it
                # from the flat one, the offset and the thermal load in steps
                logger.info("caliper: %s; solved again from the flat state in steps", e)
                sol = None
                for s in CONTINUATION:
                    sol = self._sets_solve(s * offset, active if sol is None else sol.active,
                                           s * dq, s * dz, cc, comp)
        else:
            sol = self._sets_solve(offset, active, dq, dz, cc, comp)
        pressure = (sol.lam if cc is None else np.maximum(sol.lam, 0.0)) / self.area
        info = {"outer_iterations": sol.outer, "normal_force": float(sol.lam.sum()),
                "min_gap": sol.min_gap, "time_s": time.perf_counter() - t0,
                "caliper": {"force": sol.force, "gap": sol.gap, "state": sol.state,
                            "q": sol.q, "alpha": sol.alpha, "lam": sol.lam}}
        if rings:
            info["ring_depth"] = comp.ring_depth_of_forces(sol.lam)
        return InterfaceSolution(pressure, sol.active, None, info)

    def _sets_solve(self, offset, active, dq, dz, cc, comp):
        """The rows' and the contact's solve with ``offset`` and the thermal load's gaps
        ``dq`` and modes' share ``dz``."""
        cond, rows, p = self.cond, self.rows, self.line_pressure
        n_c = cond.n_c
        g = self.g0 + offset
        rings = comp is not None and comp.rings
        gap_s = rows.g0 + p * (rows.g1 + cond.hf[n_c:]) + dq[n_c:]
        # the rings' wear over the step: a compliance among the contact nodes alone (the
        # caliper's rows do not wear)
        if isinstance(self.sets, JointSets):
            return self.sets.solve(g + p * cond.hf[:n_c] + dq[:n_c], -cond.zf * p - dz, gap_s,
                                   p, cc, active, g, rings=comp if rings else None)
        return self.sets.solve(g + p * cond.hf[:n_c] + dq[:n_c], -cond.zf * p - dz, gap_s,
                               p, cc, active, g,
                               ring_H=comp.ring_compliance() if rings else None,
                               ring_key=comp.ring_key if rings else b"")

    def at_line_pressure(self, line_pressure: float) -> CaliperInterface:
        """This interface under another line pressure (Pa): condensation, eliminated
        systems, factorisations and the rows' last state shared."""
        new = copy.copy(self)
        new.line_pressure = line_pressure
        new.fe = self.fe.at_line_pressure(line_pressure)
        return new

    def with_load_path(self, geometry) -> CaliperInterface:
        """This interface for ``geometry``: the same brake (rotor, pad, piston places,
        fingers, mesh) with other load-path parameters (seal, clearance, friction,
        bridge and bore tilt, stiffnesses) on the same meshes: the rows rebuilt, the
        condensation (which depends on the rows' places, not on those parameters) and
        the factorised stiffness shared."""
        g0 = self.model.geometry
        if (geometry.rotor, geometry.pad, geometry.mesh, geometry.caliper.fingers) != (
                g0.rotor, g0.pad, g0.mesh, g0.caliper.fingers) or (
                geometry.piston.diameter, geometry.piston.radius, geometry.piston.angle) != (
                g0.piston.diameter, g0.piston.radius, g0.piston.angle):
            raise WearError("with_load_path: the geometry must be this interface's brake with "
                            "other load-path parameters only")
        model = copy.copy(self.model)
        model.geometry = geometry          # the same meshes and stiffness
        rows = caliper_rows(geometry, model.meshes["pad"], model.offsets["pad"],
                            self.fe.cs.col, self.fe.cs.K.shape[0], model.full)
        if rows.C.shape != self.rows.C.shape or abs(rows.C - self.rows.C).max() != 0.0:
            raise WearError("with_load_path: the caliper's rows moved; build a new interface")
        new = copy.copy(self)
        new.model, new.rows = model, rows
        new.sets = SOLVERS[self.solver](self.cond, rows, self.gap_tol, self.tol)
        return new

    def supported(self):
        """The supported stiffness the condensation inverts (factorised on first use)."""
        if self._thermal is None:
            import scipy.sparse as sp

            from ..contact.compliant import constraint_rows
            from ..interfaces.condensation import Supported

            cs = self.fe.cs
            A = sp.vstack([constraint_rows(cs.pair, cs.K.shape[0]), self.rows.C]).tocsr()
            sup = self.cond.supported or Supported(cs, self.rows.C)
            self._thermal = (sup, A)
        return self._thermal[0]

    def thermal_gap(self, load: np.ndarray):
        """``(gap change per row (contact nodes, then the caliper's rows), the free
        modes' share)`` of a nodal load of the model's DOFs."""
        sup = self.supported()
        A = self._thermal[1]
        F = self.fe.cs.P.T @ load
        return A @ sup.apply(np.where(sup.held, 0.0, F)), sup.Z.T @ F


def _with_bracket_springs(model, cs):
    """``cs`` with the bracket's rails and the clip on the end faces' mean
    displacements (:func:`~brakewear.caliper.parts.bracket_springs`)
    instead of node by node."""
    g, pad, off = model.geometry, model.meshes["pad"], model.offsets["pad"]
    n = cs.P.shape[0]
    node = support_springs(pad, off, g.pad, g.support, n)
    mean = bracket_springs(pad, off, g.pad, g.support, n)
    K = (cs.K - cs.P.T @ node @ cs.P + cs.P.T @ mean @ cs.P).tocsr()
    K.eliminate_zeros()
    return dataclasses.replace(cs, K=K)


def _rigid_piston(piston: str) -> None:
    """A scene's ``interface.model = "caliper"`` needs the model's piston rigid."""
    if piston != "rigid":
        raise fail("interface.model", f"'caliper' holds the pads by a rigid piston in its bore "
                                      f"(BrakeModel(piston='rigid')); components.piston = "
                                      f"{piston!r} builds none: run it from Python "
                                      "(brakewear.Run(model, interface='caliper'))")
