"""The elastic foundation as the wear loop's interface model (:class:`FoundationInterface`)."""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from ..errors import ContactLostError, FoundationSolveError, WearError
from ..mesh.rings import ring_wear_nodes
from ..mesh.surface import surface_nodes
from ..registry import OptionKey
from .protocol import InterfaceSolution, StepCompliance
from .registry import register_interface

logger = logging.getLogger(__name__)

__all__ = ["FoundationInterface", "ring_fixed_point"]


@register_interface
class FoundationInterface:
    """An elastic-foundation (Winkler) interface as the wear loop's interface model.

    Wraps a :class:`brakewear.interfaces.WinklerInterface` (pad face on a rigid
    backing, foundation modulus per node); the rotor wears by rings of the pad
    nodes' radii as an unmeshed rotor does.  Milliseconds per solve.  The
    implicit step puts the step's wear compliance in series with the
    foundation: modulus ``1 / (1/k + eps)``.

    Parameters
    ----------
    model
        The :class:`~brakewear.model.BrakeModel`.
    winkler
        The :class:`~brakewear.interfaces.WinklerInterface` of its pad face.
    line_pressure
        The line pressure it is posed at (Pa).
    mu
        The friction coefficient.
    """

    #: a nodal load (thermal strain) has no place in a foundation
    accepts_load = False
    #: its nodes are the pad's in place; one mu; linear faces; built at its line pressure
    follows_geometry = per_node_friction = quadratic = any_line_pressure = False
    #: the rings' depths of an implicit step are iterated around its solve
    implicit_rings = True
    #: why it lacks the others (the end of a scene's message)
    why_not = {"accepts_load": "the foundation takes no thermal-strain load (it would be "
                               "dropped)",
               "per_node_friction": "the foundation takes one mu",
               "any_line_pressure": "the foundation is built at one line pressure",
               "follows_geometry": "the foundation does not move with the meshes",
               "quadratic": "the foundation is built on linear faces",
               "fe_answer": "the Winkler interface: its own modelling error dominates "
                            "(docs/winkler_running_in.md)"}

    #: ``interface.model = "winkler"`` in a scene, with its keys of ``[interface]``
    name = "winkler"
    keys = (OptionKey("winkler_modulus", "num", None, lo=0.0, unit="Pa/m", allow_none=True,
                      doc="foundation modulus; none: Johnson's layer modulus of the "
                          "friction layer"),
            OptionKey("winkler_rotor", "str", "rigid", choices=("rigid", "foundation"),
                      doc="the rotor's half thickness as a second layer in series"))

    @classmethod
    def build(cls, request) -> FoundationInterface:
        """The foundation of a scene's run (:class:`~brakewear.interfaces.BuildRequest`):
        Johnson's layer modulus unless ``winkler_modulus``."""
        from .winkler_bed import WinklerInterface
        opt = request.options
        winkler = WinklerInterface.from_model(request.model, modulus=opt["winkler_modulus"],
                                              rotor=opt["winkler_rotor"])
        return cls(request.model, winkler, request.line_pressure, request.mu)

    def __init__(self, model, winkler, line_pressure: float, mu: float = 0.0):
        self.model, self.winkler, self.line_pressure, self.mu = model, winkler, line_pressure, mu
        pad = model.meshes["pad"]
        self.pad_nodes = surface_nodes(pad, "friction")
        if winkler.nodes is not None and not np.array_equal(winkler.nodes, self.pad_nodes):
            raise WearError("the foundation's nodes are not the pad's friction nodes of this "
                            "model (build it with WinklerInterface.from_model(model))")
        self.x = pad.p[:, self.pad_nodes]
        self.r = np.hypot(self.x[0], self.x[1])
        self.area = np.asarray(winkler.area, dtype=float)
        self.rotor_nodes = None
        self.W, self.ring, self.rotor_area, self.rotor_x = ring_wear_nodes(self.r)
        self.normal_stiffness = np.asarray(winkler.modulus) * self.area

    @property
    def settings(self) -> dict:
        """Its own settings: the foundation modulus per node (Pa/m)."""
        return {"modulus": np.asarray(self.winkler.modulus, dtype=float)}

    def solve(self, offset: np.ndarray, active, *, compliance=None, x0=None, load=None,
              mu: float | None = None) -> InterfaceSolution:
        """The foundation's pressure with ``offset`` (m) added to the gap (the
        :class:`~brakewear.interfaces.Interface` protocol).  ``active`` and ``x0``
        are not needed (a foundation solve is direct); a nodal ``load`` has no
        place in a foundation and is refused.  A ``compliance`` with rings
        (:class:`~brakewear.interfaces.StepCompliance`) is solved by
        :func:`ring_fixed_point` around the foundation's solve."""
        if load is not None:
            raise WearError("the foundation interface takes no nodal load (thermal strain); "
                            "use the FE interface for thermal coupling")
        if mu is not None:
            if np.ndim(mu):
                raise WearError("the foundation interface takes one friction coefficient; a "
                                "friction law per node (mu(p, v, T)) needs the FE or the "
                                "condensed interface")
            self.mu = float(mu)
        w = self.winkler
        comp = StepCompliance.of(compliance)
        if comp is not None:
            w = w.with_modulus(1.0 / (1.0 / np.asarray(w.modulus) + comp.pad))

        def pressure(extra):
            res = w.solve(self.line_pressure, self.mu, gap=offset + extra)
            if not res.active.any():
                raise ContactLostError("foundation: no node in contact")
            return res

        info = {}
        if comp is not None and comp.rings:
            res, info = ring_fixed_point(pressure, comp, self.area,
                                         self.area * np.asarray(w.modulus, dtype=float))
        else:
            res = pressure(0.0)
        return InterfaceSolution(res.pressure, res.active, None,
                                 {"iterations": res.iterations, "time_s": res.time_s, **info})


def ring_fixed_point(pressure, comp: StepCompliance, area: np.ndarray,
                     stiffness: np.ndarray, tol: float = 1e-12, max_iter: int = 60):
    """The rings' depths of an implicit step around a solve that does not hold them.

    ``pressure(extra)`` solves the contact with the extra gap ``extra`` (m per
    pad node) and returns a result with ``pressure`` (Pa); the rings' depths
    ``d`` of the step solve ``d = F(d)``, ``F(d) = ring_depth(pressure(ring_gap
    d))`` (:class:`~brakewear.interfaces.StepCompliance`).  For one contact set
    ``F`` is affine, ``F(d) = b - G K_eff B d`` (``B`` the rings' gaps, ``G``
    their depth per newton, ``K_eff`` the pad nodes' stiffness).  ``stiffness``
    (N/m per pad node) is the part of ``K_eff`` that acts node by node (a
    foundation's springs, the wear springs in series); the iteration is
    preconditioned by ``J = I + G diag(stiffness_A) B`` over the nodes in
    contact, ``d <- d + J^-1 (F(d) - d)``, whose error is multiplied by
    ``J^-1 G (diag(stiffness) - K_eff) B``: for a foundation on a rigid backing
    the difference is the backing's three rigid motions, so the iteration
    matrix has rank 3, its eigenvalues lie in ``[0, 1)`` whatever the wear
    coefficients, the step and the mesh, and Anderson acceleration (restarted
    when the contact set changes) settles a set in about four solves.  Stops
    when the depths change by less than ``tol`` of their size; returns
    ``(result, info)`` with ``info["ring_depth"]`` (m) and
    ``info["ring_iterations"]``.
    """
    G, B = comp.ring_force_depth(), comp.ring_gap
    m = B.shape[1]
    d = np.zeros(m)
    key, D, R = None, [], []       # the set of the history; iterates and their steps
    for k in range(1, max_iter + 1):
        res = pressure(B @ d)
        fd = G @ (res.pressure * area)
        size = max(float(np.abs(fd).max()), 1e-300)
        change = float(np.abs(fd - d).max())
        if change <= tol * size or not np.any(fd):
            return res, {"ring_depth": fd, "ring_iterations": k}
        act = res.pressure > 0
        if key is None or not np.array_equal(act, key):
            key, D, R = act, [], []
            J = np.eye(m) + (G[:, act] @ sp.diags(stiffness[act]) @ B[act]).toarray()
        r = np.linalg.solve(J, fd - d)
        D.append(d)
        R.append(r)
        if len(R) > 1:
            dR = np.diff(np.array(R[-8:]), axis=0).T
            dD = np.diff(np.array(D[-8:]), axis=0).T
            gamma = np.linalg.lstsq(dR, r, rcond=None)[0]
            d = d + r - (dD + dR) @ gamma
        else:
            d = d + r
    raise FoundationSolveError(
        f"foundation contact: the rings' wear of the implicit step did not settle in "
        f"{max_iter} solves (last change {change:.2e} m of {size:.2e} m)")
