"""Contact pairs: slave nodes against a master surface (meshed or rigid), their gaps and drag."""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..errors import ContactError
from ..mesh.quadratic import SlaveBasis, slave_basis
from ..mesh.surface import is_quadratic, surface_nodes, tributary_areas
from .quadratic import dual_rigid_pair, dual_surface_pair
from .surface import mortar_coupling, project_nodes

logger = logging.getLogger(__name__)

__all__ = ["ContactPair", "ContactSystem", "pair_to_surface", "pair_to_rigid", "merge_pairs",
           "rotor_drag", "plane_height"]


@dataclass
class ContactPair:
    """A slave node set against a master surface (deformable or rigid).

    All node indices are global (stacked bodies).  ``coupling`` (sparse,
    n_slave x n_nodes) expresses the master displacement seen by each slave
    node as a weighted sum of master nodes (rows sum to one); a rigid master
    has ``coupling = None``.  ``normal`` is the master's outward unit normal
    (pointing toward the slave), ``g0`` the initial normal gap (> 0 open).
    Friction: the master drags the slave along ``drag`` (unit tangential
    vectors, e.g. the rotor's surface velocity at the slave node) with a
    traction ``mu p``; the master gets the opposite.  ``mu`` is one number or
    one per slave node (a friction law evaluated at each node's pressure, speed
    and temperature; :meth:`set_mu`).

    A quadratic slave face (:mod:`~brakewear.contact.quadratic`) has its
    nodes -- vertices and mid-edge nodes -- in a transformed displacement
    basis: ``basis`` (:class:`~brakewear.mesh.quadratic.SlaveBasis`; None for a
    linear face) says how, and the solvers carry the problem into it.
    ``area`` then holds the integrals of the transformed functions (the
    consistent nodal loads of a unit pressure, all positive), so that
    ``force / area`` is the nodal coefficient of the dual pressure.
    """

    slave: np.ndarray
    area: np.ndarray
    normal: np.ndarray
    g0: np.ndarray
    coupling: sp.csr_matrix | None = None
    mu: float | np.ndarray = 0.0
    drag: np.ndarray | None = None
    name: str = "contact"
    basis: SlaveBasis | None = None

    def __post_init__(self):
        n = self.slave.size
        self.set_mu(self.mu)
        for key in ("area", "g0"):
            if getattr(self, key).shape != (n,):
                raise ContactError(f"{self.name}: {key} must have shape ({n},)")
        if self.coupling is not None:
            self.coupling = sp.csr_matrix(self.coupling)

    def set_mu(self, mu) -> None:
        """Set the friction coefficient: a number, or an array with one per slave node
        (each >= 0); ``mu > 0`` anywhere needs the pair's sliding direction."""
        n = self.slave.size
        if np.ndim(mu) == 0:
            mu = float(mu)
        else:
            mu = np.array(mu, dtype=float)
            if mu.shape != (n,):
                raise ContactError(f"{self.name}: mu has shape {mu.shape}; need a number or ({n},),"
                                   " one per slave node")
        if np.any(np.asarray(mu) < 0) or not np.all(np.isfinite(mu)):
            shown = mu if np.ndim(mu) == 0 else f"min {np.min(mu)!r}"
            raise ContactError(f"{self.name}: friction coefficient mu = {shown}; need mu >= 0")
        if np.any(np.asarray(mu) > 0) and (self.drag is None or self.drag.shape != (3, n)):
            raise ContactError(f"{self.name}: mu > 0 needs a drag direction (3, {n}) per slave "
                               "node; the pair was built without friction (build it with mu > 0)")
        self.mu = mu

    @property
    def frictional(self) -> bool:
        """Whether any slave node carries friction."""
        return bool(np.any(np.asarray(self.mu) > 0))

    def traction(self) -> np.ndarray:
        """``mu drag`` (3, n_slave): the friction load on each slave node per newton of
        its normal force."""
        return np.asarray(self.mu) * self.drag

    @property
    def rigid(self) -> bool:
        return self.coupling is None

    def gaps(self, u: np.ndarray) -> np.ndarray:
        """Normal gap (m) at each slave node for the displacement ``u`` (DOF ``3 node + i``):
        ``g0`` plus the normal component of the slave's displacement relative to the
        master point under it (> 0 open, < 0 penetrating).  On a quadratic face,
        the weak gap of each node (``u`` taken into the transformed basis)."""
        if self.basis is not None:
            u = self.basis.dof_matrix(u.size, inverse=True) @ u
        us = u.reshape(-1, 3)[self.slave].T
        rel = us if self.rigid else us - (self.coupling @ u.reshape(-1, 3)).T
        return self.g0 + np.einsum("ij,ij->j", self.normal, rel)


@dataclass
class ContactSystem:
    """An assembled contact problem (retained-node numbering after ties), as
    :meth:`brakewear.model.BrakeModel.contact_system` builds it."""

    K: sp.csr_matrix
    f: np.ndarray
    fixed: np.ndarray
    coords: np.ndarray
    pair: ContactPair
    P: sp.csr_matrix       # retained DOFs -> all DOFs
    col: np.ndarray        # global node -> retained node (-1: eliminated)
    clamp_force: float
    supports: list = field(default_factory=list)  # rigid stops (abutments), no friction


def pair_to_surface(slave_mesh: fem.Mesh, slave_facets, slave_offset: int,
                    master_mesh: fem.Mesh, master_facets, master_offset: int,
                    mu: float = 0.0, drag=None, search_radius: float | None = None,
                    exclude: np.ndarray | None = None, method: str = "segment",
                    level: int | None = None, n_nodes: int | None = None,
                    name: str = "contact") -> ContactPair:
    """A contact pair between two meshed bodies (offsets = first global node of each).

    ``method``: ``"node"`` -- classic one-pass node-to-surface (each slave
    node coupled to the master at its own projection); ``"segment"`` (default)
    -- the coupling weighted over each slave node's tributary area
    (:func:`mortar_coupling`, ``4**level`` points per slave facet), which
    passes the contact patch test on non-matching meshes.  ``drag`` is a
    callable ``x (3, n) -> (3, n)`` giving the master's surface velocity
    direction at slave positions (used when ``mu > 0``).  ``exclude`` lists
    vertex indices of the slave mesh to leave out (e.g. nodes with supported
    normal DOFs); ``n_nodes`` is the global node
    count (default: just enough for the master).

    A quadratic slave mesh (``MeshTet2``) gets the dual mortar pair of
    :mod:`~brakewear.contact.quadratic` whatever ``method`` says (its slave
    nodes are the face's vertices and mid-edge nodes; ``level`` subdivides
    its quadrature, 2 by default: 112 points per slave facet); a linear slave
    face against a quadratic master is refused.
    """
    if method not in ("node", "segment"):
        raise ContactError(f"{name}: method = {method!r}; allowed: 'node', 'segment'")
    N = (max(master_offset + master_mesh.p.shape[1], slave_offset + slave_mesh.p.shape[1])
         if n_nodes is None else n_nodes)
    if is_quadratic(slave_mesh):
        q = dual_surface_pair(slave_mesh, slave_facets, master_mesh, master_facets,
                              master_mesh.p.shape[1], 2 if level is None else level,
                              search_radius)
        W = sp.csr_matrix((q["W"].data, q["W"].indices + master_offset, q["W"].indptr),
                          shape=(q["slave"].size, N))
        return _quadratic_pair(slave_mesh, q, slave_offset, W, exclude, mu, drag, name)
    if is_quadratic(master_mesh):
        raise ContactError(f"{name}: a linear slave face against a quadratic master is not "
                           "supported; make the quadratic body the slave or use one order")
    slave = surface_nodes(slave_mesh, slave_facets)
    x = slave_mesh.p[:, slave]
    pr = project_nodes(x, master_mesh, master_facets, search_radius=search_radius)
    if method == "node":
        area = tributary_areas(slave_mesh, slave_facets, slave)
        rows = np.repeat(np.arange(slave.size), 3)
        W = sp.csr_matrix((pr.weights.T.ravel(), (rows, pr.nodes.T.ravel() + master_offset)),
                          shape=(slave.size, N))
        g0 = pr.gap
    else:
        W, g0, area = mortar_coupling(slave_mesh, slave_facets, slave, master_mesh, master_facets,
                                      master_mesh.nvertices, 2 if level is None else level,
                                      search_radius)
        W = sp.csr_matrix((W.data, W.indices + master_offset, W.indptr), shape=(slave.size, N))
    if exclude is not None:
        keep = ~np.isin(slave, exclude)
        slave, area, g0, W = slave[keep], area[keep], g0[keep], W[keep]
        pr.normal = pr.normal[:, keep]
    d = _unit_tangential(drag(slave_mesh.p[:, slave]), pr.normal) if mu > 0 else None
    return ContactPair(slave + slave_offset, area, pr.normal, g0, W, mu, d, name)


def pair_to_rigid(slave_mesh: fem.Mesh, slave_facets, slave_offset: int, height,
                  side: int = 1, mu: float = 0.0, drag=None,
                  exclude: np.ndarray | None = None, name: str = "rigid contact",
                  level: int = 1) -> ContactPair:
    """A contact pair against a rigid surface ``z = height(x, y)``.

    ``side = +1``: the rigid body lies below the surface (normal +z);
    ``side = -1``: above it (normal -z).  Gaps are measured along z, the
    small-slope approximation that Hertz theory also makes.  ``exclude``
    lists node indices of the slave mesh to leave out.  A quadratic slave
    mesh gets the dual mortar pair of :mod:`~brakewear.contact.quadratic`
    (weak gaps integrated on ``4**level`` sub-triangles per facet).
    """
    if side not in (1, -1):
        raise ContactError(f"{name}: side = {side!r}; allowed: +1 (rigid below), -1 (rigid above)")
    if is_quadratic(slave_mesh):
        q = dual_rigid_pair(slave_mesh, slave_facets, height, side, level)
        return _quadratic_pair(slave_mesh, q, slave_offset, None, exclude, mu, drag, name)
    slave = surface_nodes(slave_mesh, slave_facets)
    area = tributary_areas(slave_mesh, slave_facets, slave)
    if exclude is not None:
        keep = ~np.isin(slave, exclude)
        slave, area = slave[keep], area[keep]
    x = slave_mesh.p[:, slave]
    normal = np.zeros_like(x)
    normal[2] = side
    g0 = side * (x[2] - np.asarray(height(x[0], x[1]), dtype=float))
    d = _unit_tangential(drag(x), normal) if mu > 0 else None
    return ContactPair(slave + slave_offset, area, normal, g0, None, mu, d, name)


def _quadratic_pair(slave_mesh, q: dict, offset: int, W, exclude, mu, drag,
                    name: str) -> ContactPair:
    """The :class:`ContactPair` of a quadratic face's dual mortar arrays ``q``."""
    slave, area, g0, normal = q["slave"], q["area"], q["g0"], q["normal"]
    if exclude is not None:
        keep = ~np.isin(slave, exclude)
        slave, area, g0, normal = slave[keep], area[keep], g0[keep], normal[:, keep]
        W = None if W is None else W[keep]
    d = _unit_tangential(drag(slave_mesh.p[:, slave]), normal) if mu > 0 else None
    return ContactPair(slave + offset, area, normal, g0, W, mu, d, name,
                       basis=slave_basis(q["nodes"], offset))


def rotor_drag(x: np.ndarray) -> np.ndarray:
    """The direction a rotor turning in +theta (about z) drags points ``x`` (3, n):
    ``(-y, x, 0)`` (unit after :func:`_unit_tangential`)."""
    return np.vstack([-x[1], x[0], np.zeros_like(x[0])])


def plane_height(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The height of the plane z = 0 (a rigid rotor's face) at ``(x, y)``."""
    return np.zeros_like(x)


def _unit_tangential(v: np.ndarray, n: np.ndarray) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    v = v - n * np.einsum("ij,ij->j", v, n)
    norm = np.linalg.norm(v, axis=0)
    if np.any(norm == 0):
        raise ContactError("drag direction is zero or normal to the surface at some slave node "
                           "(e.g. a node on the rotor axis)")
    return v / norm




def merge_pairs(pairs: list[ContactPair], name: str = "contact") -> ContactPair:
    """One pair of several with disjoint slave nodes (e.g. the two pads' friction
    faces against the rotor's two faces): slave nodes, areas, normals, gaps,
    coupling rows and drag joined and sorted by slave node."""
    if len(pairs) == 1:
        return pairs[0]
    rigid = {p.rigid for p in pairs}
    if len(rigid) > 1:
        raise ContactError(f"{name}: cannot merge rigid and deformable masters into one pair")
    slave = np.concatenate([p.slave for p in pairs])
    if np.unique(slave).size != slave.size:
        raise ContactError(f"{name}: the pairs share slave nodes; merged pairs need disjoint ones")
    cat = lambda key: np.concatenate([getattr(p, key) for p in pairs], axis=-1)  # noqa: E731
    coupling = None if rigid.pop() else sp.vstack([p.coupling for p in pairs], format="csr")
    fr = [p.frictional for p in pairs]
    drag = cat("drag") if all(fr) else None
    mu = (np.concatenate([np.broadcast_to(np.asarray(p.mu, dtype=float), p.slave.shape)
                          for p in pairs]) if any(fr) else 0.0)
    if np.ndim(mu) and np.all(mu == mu[0]):
        mu = float(mu[0])
    bases = [p.basis for p in pairs]
    basis = None
    if any(b is not None for b in bases):
        if any(b is None for b in bases):
            raise ContactError(f"{name}: cannot merge linear and quadratic slave faces")
        basis = SlaveBasis(np.concatenate([b.edge for b in bases]),
                           np.hstack([b.ends for b in bases]), bases[0].alpha)
    # in ascending slave order, the order of the face's node list (face_nodes)
    o = np.argsort(slave, kind="stable")
    pick = lambda a: None if a is None else (a[..., o] if np.ndim(a) else a)  # noqa: E731
    return ContactPair(slave[o], cat("area")[o], cat("normal")[:, o], cat("g0")[o],
                       None if coupling is None else coupling[o], pick(mu), pick(drag), name,
                       basis=basis)
