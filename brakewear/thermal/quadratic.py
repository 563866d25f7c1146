"""Temperatures of a brake model of quadratic (P2) tetrahedra, carried on its vertices.

A model of P2 tetrahedra gets a linear (P1) temperature field on the same
elements: conduction, capacity and convection are those of the *vertex
mesh* (the P2 mesh's corner nodes and elements, which is the mesh an order-1
model of the same geometry has), solved by the :class:`ThermalModel` of that
linear twin. Why not a quadratic temperature: the temperature loads the
elasticity only through ``alpha (T - T_ref)``, and the strain of a P2
displacement is linear in each element, as a P1 temperature is, so the
thermal strain keeps the displacement's degree; conduction over a pad or a
rotor is smooth away from the face and costs an eighth of the P2 node count
on the vertices.

What crosses between the two fields:

- **heat in**: the friction power of each P2 face node, ``q_j A_j`` (``A_j``
  the integral of its transformed basis function, the area the contact
  pressure is defined on), goes to the face's vertices by the transpose of
  the vertex-to-node interpolation (a mid-edge node's power half to each end
  of its edge). The energy balance is exact: the vertices receive the nodes'
  total power;
- **temperatures out**: at a P2 node, the P1 field's value (a mid-edge node
  the mean of its edge's ends), for ``mu(T)``, ``k(T)``, the records and the
  ``temperature_C`` of the tetra10 VTU;
- **thermal strain**: ``int eps(v) : C : alpha (T - T_ref) I`` with the P2
  test functions ``v`` and the P1 temperature, on the P2 mesh's geometry.

:func:`~brakewear.thermal.ThermalModel` builds this for a model of order 2;
geometry update (moving worn faces) is refused with P2 meshes before this is
built.
"""
from __future__ import annotations

import logging
from collections.abc import Mapping

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..errors import ThermalError
from ..mesh.quadratic import quadratic_face_areas
from ..mesh.surface import face_nodes, surface_nodes
from .partition import heat_flux
from .strain import model_thermal_load, thermal_stress

logger = logging.getLogger(__name__)

__all__ = ["QuadraticThermal", "vertex_mesh", "vertex_interpolation", "linear_twin"]


def vertex_mesh(mesh: fem.MeshTet2) -> fem.MeshTet1:
    """The P1 mesh of a P2 mesh's vertices and elements, with its named facets and
    subdomains (facet and element numbering unchanged)."""
    nv = mesh.nvertices
    v = fem.MeshTet1(np.ascontiguousarray(mesh.p[:, :nv]), np.ascontiguousarray(mesh.t[:4]),
                     _boundaries=dict(mesh.boundaries or {}),
                     _subdomains=dict(mesh.subdomains or {}))
    if not np.array_equal(v.facets, mesh.facets):
        raise ThermalError("vertex mesh: the facets of the P2 mesh's vertices are numbered "
                           "differently; its named facets cannot be carried over")
    return v


def vertex_interpolation(mesh: fem.MeshTet2) -> sp.csr_matrix:
    """``I`` (all nodes x vertices): the P1 field's value at every node of a P2 mesh
    (a vertex its own; the mid-edge node ``nvertices + e`` the mean of edge ``e``'s ends)."""
    nv, ne = mesh.nvertices, mesh.edges.shape[1]
    rows = np.concatenate([np.arange(nv), nv + np.arange(ne), nv + np.arange(ne)])
    cols = np.concatenate([np.arange(nv), mesh.edges[0], mesh.edges[1]])
    vals = np.concatenate([np.ones(nv), np.full(2 * ne, 0.5)])
    return sp.csr_matrix((vals, (rows, cols)), shape=(nv + ne, nv))


def linear_twin(model):
    """The order-1 model on the vertices of a P2 ``model``'s meshes: the same brake,
    bodies, layout and materials, each body's mesh its :func:`vertex_mesh`."""
    return model.remeshed({b: vertex_mesh(m) for b, m in model.meshes.items()}, order=1)


class QuadraticThermal:
    """The brake's temperatures for a model of P2 tetrahedra (see the module docstring).

    Built by :class:`~brakewear.thermal.ThermalModel` when its model has order 2
    (``vertex_model``: the ThermalModel, with the same arguments, of
    :func:`linear_twin`); it answers the same calls with values at the P2
    model's nodes (``pad_nodes``: the P2 friction face, as the FE interface's).
    The temperatures ``T`` are at every P2 node; the state, the settings, the
    heat balance and the plausibility bound are the vertex field's
    (:attr:`vertex_model`).
    """

    def __init__(self, model, vertex_model):
        if getattr(model, "order", 1) != 2:
            raise ThermalError(f"QuadraticThermal needs a model of order 2, got {model.order}")
        self.model = model
        #: the thermal model of the order-1 twin on the vertices (:func:`linear_twin`)
        self.vertex_model = inner = vertex_model
        for b in inner.bodies:
            if not np.array_equal(inner.model.meshes[b].t, model.meshes[b].t[:4]):
                raise ThermalError(f"QuadraticThermal: the vertex model's {b} mesh is not the "
                                   "vertex mesh of the P2 model's")
        self._I = {b: vertex_interpolation(model.meshes[b]) for b in inner.bodies}
        pad = model.meshes["pad"]
        self.pad_nodes, self.pad_area = quadratic_face_areas(pad, "friction")
        if not np.array_equal(self.pad_nodes, face_nodes(pad, "friction")):
            raise ThermalError("the pad's friction face nodes do not match its face areas")
        x = pad.p[:, self.pad_nodes]
        self.pad_radius = np.hypot(x[0], x[1])
        # P2 face values from the vertex field's face values
        self._face = {b: self._I[b][face_nodes(model.meshes[b], "friction")]
                      [:, surface_nodes(model.meshes[b], "friction")].tocsr()
                      for b in inner.bodies}
        self._G: dict[str, sp.csr_matrix] = {}
        logger.info("thermal model of a P2 model: %s vertices for %s nodes",
                    {b: m.nvertices for b, m in model.meshes.items() if b in inner.bodies},
                    {b: m.p.shape[1] for b, m in model.meshes.items() if b in inner.bodies})

    # the vertex field's settings and state, as they are
    def __getattr__(self, name):
        if name in ("bodies", "partition", "T_max", "contact_conductance", "settings",
                    "T_ambient", "T_ref", "time", "omega", "heat", "cooling", "heat_balance",
                    "state_arrays", "load_state", "set_speed"):
            return getattr(self.__dict__["vertex_model"], name)
        raise AttributeError(name)

    @property
    def T(self) -> dict:
        """Temperature (K) at every node of each thermal body's P2 mesh."""
        return {b: self._I[b] @ T for b, T in self.vertex_model.T.items()}

    def flux(self, p: np.ndarray, mu, omega: float) -> np.ndarray:
        """``q = mu p omega r`` at the P2 pad friction nodes (W/m^2)."""
        if not (np.isfinite(omega) and omega >= 0):
            raise ThermalError(f"omega = {omega!r} rad/s is not allowed; need >= 0")
        return heat_flux(p, omega * self.pad_radius, mu)

    def _vertex_flux(self, q_pad: np.ndarray) -> np.ndarray:
        q = np.asarray(q_pad, dtype=float)
        if q.shape != self.pad_nodes.shape:
            raise ThermalError(f"q_pad has shape {q.shape}; need {self.pad_nodes.shape} (one "
                               "value per P2 pad friction node)")
        power = self._face["pad"].T @ (q * self.pad_area)      # W at the face's vertices
        return power / self.vertex_model.pad_area

    def step(self, q_pad: np.ndarray, dt: float) -> dict:
        """One implicit-Euler step under ``q_pad`` (W/m^2 at the P2 pad friction nodes)."""
        self.vertex_model.step(self._vertex_flux(q_pad), dt)
        return self.T

    def steady(self, q_pad: np.ndarray) -> dict:
        """Steady temperatures under ``q_pad`` (needs convection)."""
        self.vertex_model.steady(self._vertex_flux(q_pad))
        return self.T

    def face_temperature(self, body: str = "pad") -> np.ndarray:
        """Temperature (K) at the P2 friction-face nodes of ``body`` (sorted)."""
        if body not in self._face:
            raise ThermalError(f"body = {body!r} has no temperature field; thermal bodies: "
                               f"{tuple(self._face)}")
        return self._face[body] @ self.vertex_model.face_temperature(body)

    def rotor_temperature_under_pad(self) -> np.ndarray:
        """Rotor surface temperature seen by each P2 pad friction node (K)."""
        return self._face["pad"] @ self.vertex_model.rotor_temperature_under_pad()

    def thermal_load(self, T: Mapping[str, np.ndarray] | None = None) -> np.ndarray:
        """Thermal-strain load (3 * model.n_nodes,) in the P2 model's numbering, of the
        vertex temperatures ``T`` (default: the current ones)."""
        return model_thermal_load(self.model, self.bodies,
                                  self.vertex_model.T if T is None else T, self.T_ref, self._G)

    def stresses(self, u: Mapping[str, np.ndarray]) -> dict:
        """Element stresses ``C (eps - alpha dT I)`` per thermal body (6, n_elements)."""
        return {b: thermal_stress(self.model.meshes[b], u[b], self.model.materials[b],
                                  self.vertex_model.T[b] - self.T_ref, b) for b in self.bodies}

    def follow(self, model) -> None:
        raise ThermalError("moving worn faces (update = 'geometry') is not supported with "
                           "P2 meshes; use update = 'gap', or order 1")
