"""The finite-element contact interface as the wear loop sees it (:class:`FEInterface`)."""
from __future__ import annotations

import copy
import dataclasses
import logging

import numpy as np

from ..checks import check_line_pressure
from ..contact.compliant import compliant_preconditioner, solve_compliant_contact
from ..contact.lagrange import contact_preconditioner, solve_contact
from ..mesh.quadratic import quadratic_face_areas, slave_basis
from ..mesh.rings import face_rings, ring_wear_nodes
from ..mesh.surface import face_nodes, is_quadratic, quadratic_faces, tributary_areas
from ..registry import OptionKey
from .protocol import InterfaceSolution, StepCompliance
from .registry import register_interface

logger = logging.getLogger(__name__)

__all__ = ["FEInterface"]

#: the FE contact discretisation (a key of the models built on FE contact)
METHOD = OptionKey("method", "str", "segment", choices=("segment",),
                   doc="FE contact discretisation")


@register_interface
class FEInterface:
    """The finite-element contact interface as the wear loop sees it.

    Holds the assembled contact system of a :class:`~brakewear.model.BrakeModel`
    and answers one question: the pressure at the pad's friction nodes for a
    given extra gap (the worn depths).  Also provides what the rotor's
    revolution-averaged wear needs: the coupling ``W`` from pad nodes to the
    rotor's wear nodes, their rings and areas.  With an elastic rotor the
    wear nodes are the rotor's friction-face nodes; with a rigid rotor (the
    plane z = 0, nothing meshed) they are rings at the radii of the pad's
    nodes, each carrying the annulus between its neighbours' mid-radii.

    On quadratic meshes (``BrakeModel(order=2)``) the friction nodes are the
    faces' vertices and mid-edge nodes, their areas the integrals of the
    transformed basis (:mod:`brakewear.mesh.quadratic`; all positive, summing
    to the face's area), the pressure the dual multiplier's nodal coefficient
    (contact force / area) and a nodal depth -- pad wear, gap offset -- the
    coefficient of that basis.  The rotor's wear nodes are its face's nodes in
    its own transformed basis, so ``W`` (pad node <- rotor node) carries the
    rotor's depths into the pad's weak gaps and volumes are ``area @ depth``
    on either face.

    Parameters
    ----------
    model
        The :class:`~brakewear.model.BrakeModel`.
    line_pressure
        The line pressure it is posed at (Pa).
    mu
        The friction coefficient (any mu > 0 builds the sliding directions).
    tol
        Relative tolerance of its contact solves.
    """

    #: the thermal-strain load enters its solves
    accepts_load = True
    #: :meth:`rebuilt` on a moved model; mu per node; P2 meshes; :meth:`at_line_pressure`
    follows_geometry = per_node_friction = quadratic = any_line_pressure = True
    #: the rings' depths of an implicit step are unknowns of its compliant solve
    implicit_rings = True
    #: its pressure is the FE contact's (the measured mesh convergence rates it)
    fe_answer = True

    #: ``interface.model = "fe"`` in a scene, with its keys of ``[interface]``
    name = "fe"
    keys = (METHOD,)

    @classmethod
    def build(cls, request) -> FEInterface:
        """The interface of a scene's run (:class:`~brakewear.interfaces.BuildRequest`):
        the one an ``"auto"`` choice built to decide, or a new one."""
        if "fe" in request.built:
            return request.built["fe"]
        return cls(request.model, request.line_pressure, request.mu, request.numerics.tol)

    def __init__(self, model, line_pressure: float, mu: float = 0.0, tol: float = 1e-9):
        self.model, self.line_pressure, self.mu, self.tol = model, line_pressure, mu, tol
        pad = model.meshes["pad"]
        self.pad_nodes = face_nodes(pad, "friction")
        self.x = pad.p[:, self.pad_nodes]
        self.r = np.hypot(self.x[0], self.x[1])
        self.area = _face_areas(pad, self.pad_nodes)
        if model.rotor == "elastic":
            rotor = model.meshes["rotor"]
            self.rotor_nodes = face = face_nodes(rotor, "friction")
            self.ring, _ = face_rings(model, rotor.p[:, face])
            self.rotor_area = _face_areas(rotor, face)
            self.rotor_x = rotor.p[:, face]
        else:
            self.rotor_nodes = None
            self._W, self.ring, self.rotor_area, self.rotor_x = ring_wear_nodes(self.r)
        self.rebuild()

    def rebuild(self, opening: float = 0.0) -> None:
        """(Re)build the contact system from the model's current meshes and stiffness.

        ``opening`` (m): the largest gap the worn surfaces have opened; the
        contact search reaches that much further.
        """
        model = self.model
        radius = 2.0 * model.geometry.mesh.size + 1e-9 + opening
        mu = self.mu      # a number, or one per pad node (a friction law's last values)
        self.cs = cs = model.contact_system(self.line_pressure, float(np.max(mu)),
                                            search_radius=radius)
        self.pair = pair = cs.pair
        # rigid stops without friction (the pad's abutments in the bracket), each with
        # its own active set; the last solve's sets start the next Lagrange solve
        self.supports = list(getattr(cs, "supports", None) or [])
        self.support_active = None
        if np.ndim(mu):
            pair.set_mu(mu)
        self.g0 = pair.g0.copy()
        if model.rotor == "elastic":
            face_r = cs.col[self.rotor_nodes + model.offsets["rotor"]]   # retained numbering
            self.W = pair.coupling[:, face_r].tocsr()
            rotor = model.meshes["rotor"]
            if is_quadratic(rotor):
                # rotor depths as coefficients of its face's transformed basis
                T = slave_basis(quadratic_faces(rotor, "friction"), 0).node_matrix(rotor.p.shape[1])
                self.W = (self.W @ T[self.rotor_nodes][:, self.rotor_nodes]).tocsr()
        else:
            self.W = self._W
        # hierarchies of this stiffness, built on first use and shared by every
        # solve (never modified: each solve refreshes its own copy)
        self._base = {}
        # normal stiffness row sums of the pad's friction face (Gershgorin bound
        # of the pressure response to a gap change, used by the stability bound)
        dz = 3 * pair.slave + 2
        self.normal_stiffness = np.asarray(abs(cs.K[dz][:, dz]).sum(axis=1)).ravel()

    def rebuilt(self, model, opening: float = 0.0) -> FEInterface:
        """This interface on ``model``, the same brake in a moved (worn) geometry
        (:class:`~brakewear.motion.brake.BrakeMotion`): the reference areas, radii and
        rotor rings stay, the contact system is the moved model's.  ``opening``
        (m): the largest gap the worn surfaces have opened."""
        new = copy.copy(self)
        new.model = model
        new.rebuild(opening)
        return new

    def at_line_pressure(self, line_pressure: float) -> FEInterface:
        """This interface under another line pressure (Pa): the load scaled, the
        assembled system, its hierarchies and the geometry shared (no assembly)."""
        check_line_pressure(line_pressure)
        scale = line_pressure / self.line_pressure
        new = copy.copy(self)
        new.line_pressure = line_pressure
        new.cs = dataclasses.replace(self.cs, f=self.cs.f * scale,
                                     clamp_force=self.cs.clamp_force * scale)
        return new

    @property
    def settings(self) -> dict:
        """Its own settings (the contact solves' tolerance): the rest of its
        system is the model's and the run's."""
        return {"tol": float(self.tol)}

    def solve(self, offset: np.ndarray, active: np.ndarray | None, *,
              compliance: StepCompliance | np.ndarray | None = None,
              x0: np.ndarray | None = None, load: np.ndarray | None = None,
              mu=None) -> InterfaceSolution:
        """Contact solve with ``offset`` (m) added to the gap (the
        :class:`~brakewear.interfaces.Interface` protocol).

        With ``compliance`` (a :class:`~brakewear.interfaces.StepCompliance`,
        or the pad's alone in m/Pa per pad node) the interface is a compliant
        layer: the implicit wear step (:mod:`brakewear.contact.compliant`; the
        rotor's rings, when the compliance has them, as extra unknowns,
        :mod:`brakewear.contact.compliant_rings`), whose Krylov solves start
        from ``x0`` (the previous step's displacement), when given.  ``load`` is an extra nodal
        load of the model's DOFs (the
        thermal strain), ``mu`` the friction coefficient of this solve (a number
        or one per pad friction node).

        The contact system's ``supports`` (rigid stops: the pad's abutments,
        :mod:`brakewear.contact.supports`) enter both paths; ``info`` then
        holds their normal force per pair (``support_normal_force``, N) and
        :attr:`support_active` their last active sets.
        """
        self.pair.g0 = self.g0 + offset
        if mu is not None:
            self.pair.set_mu(mu)
            self.mu = self.pair.mu
        cs = self.cs
        f = cs.f if load is None else cs.f + cs.P.T @ load
        supports = self.supports or None
        comp = StepCompliance.of(compliance)
        if comp is not None:
            if "compliant" not in self._base:
                self._base["compliant"] = compliant_preconditioner(
                    cs.K, cs.fixed, cs.coords, self.tol, supports=supports)
            rings = (comp.ring_gap, comp.ring_force_depth()) if comp.rings else None
            res = solve_compliant_contact(cs.K, f, cs.fixed, cs.coords, self.pair,
                                          comp.pad, initial_active=active, tol=self.tol,
                                          solver=self._base["compliant"], x0=x0,
                                          supports=supports, rings=rings)
            if supports:
                self.support_active = res.support_active
            return InterfaceSolution(res.pressure, res.active, res.u, res.info)
        pairs = [self.pair, *self.supports]
        if "contact" not in self._base:
            self._base["contact"] = contact_preconditioner(cs.K, cs.fixed, cs.coords,
                                                           pairs, tol=self.tol)
        init = None
        if active is not None:
            init = [np.asarray(active, dtype=bool)] + (
                self.support_active or [s.g0 <= 0 for s in self.supports])
        res = solve_contact(cs.K, f, cs.fixed, cs.coords, pairs, tol=self.tol,
                            initial_active=init, solver=self._base["contact"])
        info = res.info
        if self.supports:
            self.support_active = res.active[1:]
            info = {**info, "support_normal_force": info["normal_force"][1:],
                    "normal_force": info["normal_force"][:1]}
        return InterfaceSolution(res.pressure[0], res.active[0], res.u, info)


def _face_areas(mesh, nodes: np.ndarray) -> np.ndarray:
    """Areas of a friction face's nodes: tributary areas (linear face) or the
    integrals of the transformed basis (quadratic face)."""
    if is_quadratic(mesh):
        return quadratic_face_areas(mesh, "friction")[1]
    return tributary_areas(mesh, "friction", nodes)


