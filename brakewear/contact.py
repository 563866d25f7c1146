"""Interfaces between bodies: node-to-surface projection and tied constraints.

Slave nodes (for the pad-rotor interface, the pad's friction-face nodes) are
projected onto master facets (the rotor's friction face).  The projection
gives, per slave node, the master facet, the barycentric weights of the
projected point, the signed normal gap and the master's outward normal.

A *tie* glues the slave nodes to the master surface: every slave DOF equals
the master displacement interpolated at its projection.  It is imposed by
multi-point-constraint elimination, ``u = P u_r``, which keeps the reduced
system ``P^T K P`` symmetric positive definite for pyamg; the interface
traction is recovered as the slave nodes' residual forces ``K u - f``.  The
same projection and elimination are the building blocks of frictional
contact, where only the normal component is tied on the active set.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem as fem
from scipy.spatial import cKDTree

from .solvers import PatchedMatrix

logger = logging.getLogger(__name__)

__all__ = [
    "ContactSearchError",
    "ContactLostError",
    "ActiveSetError",
    "ContactPair",
    "ContactResult",
    "pair_to_surface",
    "pair_to_rigid",
    "solve_contact",
    "contact_preconditioner",
    "Projection",
    "facet_normals",
    "project_nodes",
    "surface_nodes",
    "tributary_areas",
    "tie_prolongation",
]


class ContactSearchError(RuntimeError):
    """A slave node found no master facet within the search radius."""


@dataclass
class Projection:
    """Projection of slave points on a master surface (arrays over slave points)."""

    facet: np.ndarray   # (n,) index into mesh.facets of the master facet
    nodes: np.ndarray   # (3, n) master vertex indices of that facet
    weights: np.ndarray  # (3, n) barycentric weights of the projected point
    gap: np.ndarray     # (n,) signed normal distance, > 0 outside the master body
    normal: np.ndarray  # (3, n) master outward unit normal
    distance: np.ndarray  # (n,) distance from the point to the facet (0 if it projects inside)


def facet_normals(mesh: fem.Mesh, facets: np.ndarray) -> np.ndarray:
    """Outward unit normals (3, n) of boundary ``facets`` (P1 vertex triangle)."""
    f = mesh.facets[:, facets]
    p = mesh.p
    n = np.cross(p[:, f[1]] - p[:, f[0]], p[:, f[2]] - p[:, f[0]], axis=0)
    n /= np.linalg.norm(n, axis=0)
    # orient away from the owning element's centroid
    elem = mesh.f2t[0, facets]
    cen = p[:, mesh.t[:4, elem]].mean(axis=1)
    sign = np.sign(np.einsum("ij,ij->j", n, p[:, f[0]] - cen))
    return n * sign


def surface_nodes(mesh: fem.Mesh, facets) -> np.ndarray:
    """Sorted vertex indices of named facets (or facet indices)."""
    if isinstance(facets, str):
        facets = mesh.boundaries[facets]
    return np.unique(mesh.facets[:, facets])


def tributary_areas(mesh: fem.Mesh, facets, nodes: np.ndarray | None = None) -> np.ndarray:
    """Area belonging to each vertex of a facet set (a third of each adjacent triangle).

    Returned for ``nodes`` (default: :func:`surface_nodes`), in that order.
    """
    if isinstance(facets, str):
        facets = mesh.boundaries[facets]
    f = mesh.facets[:, facets]
    p = mesh.p
    area = 0.5 * np.linalg.norm(np.cross(p[:, f[1]] - p[:, f[0]], p[:, f[2]] - p[:, f[0]],
                                         axis=0), axis=0)
    acc = np.zeros(mesh.nvertices)
    for a in range(3):
        np.add.at(acc, f[a], area / 3.0)
    if nodes is None:
        nodes = np.unique(f)
    return acc[nodes]


def project_nodes(points: np.ndarray, mesh: fem.Mesh, facets, search_radius: float | None = None,
                  candidates: int = 12, tol: float = 1e-9) -> Projection:
    """Project ``points`` (3, n) onto the master facets of ``mesh``.

    Candidates are the ``candidates`` facets with the nearest centroids; the
    chosen facet is the one whose closest point is nearest (a point that
    projects inside a facet has distance 0 in-plane).  Raises
    :class:`ContactSearchError` naming the first point that is farther than
    ``search_radius`` from every candidate.
    """
    if isinstance(facets, str):
        facets = mesh.boundaries[facets]
    facets = np.asarray(facets)
    points = np.asarray(points, dtype=float)
    f = mesh.facets[:, facets]
    p = mesh.p
    A, Bv, Cv = p[:, f[0]], p[:, f[1]], p[:, f[2]]
    tree = cKDTree(((A + Bv + Cv) / 3.0).T)
    k = min(candidates, facets.size)
    _, cand = tree.query(points.T, k=k)
    cand = cand.reshape(points.shape[1], k)
    a, b, c = A[:, cand], Bv[:, cand], Cv[:, cand]  # (3, n, k)
    x = points[:, :, None]
    e0, e1, d = b - a, c - a, x - a
    d00 = np.einsum("inj,inj->nj", e0, e0)
    d01 = np.einsum("inj,inj->nj", e0, e1)
    d11 = np.einsum("inj,inj->nj", e1, e1)
    d20 = np.einsum("inj,inj->nj", d, e0)
    d21 = np.einsum("inj,inj->nj", d, e1)
    den = d00 * d11 - d01 * d01
    v = (d11 * d20 - d01 * d21) / den
    w = (d00 * d21 - d01 * d20) / den
    u = 1.0 - v - w
    bary = np.stack([u, v, w])
    # clamp to the triangle for the in-plane distance (a simple, robust
    # approximation of the closest point: renormalised clipped weights)
    cl = np.clip(bary, 0.0, None)
    cl /= cl.sum(axis=0, keepdims=True)
    q = cl[0] * a + cl[1] * b + cl[2] * c
    nrm = np.cross(e0, e1, axis=0)
    nrm /= np.linalg.norm(nrm, axis=0)
    h = np.einsum("inj,inj->nj", d, nrm)
    inplane = np.linalg.norm(x - h * nrm - q, axis=0)
    inside = bary.min(axis=0) >= -tol
    score = np.where(inside, 0.0, inplane) + 1e-12 * np.abs(h)
    best = np.argmin(score, axis=1)
    rows = np.arange(points.shape[1])
    sel = cand[rows, best]
    weights = np.where(inside[rows, best], bary[:, rows, best], cl[:, rows, best])
    normal = facet_normals(mesh, facets[sel])
    proj = (weights[0] * A[:, sel] + weights[1] * Bv[:, sel] + weights[2] * Cv[:, sel])
    gap = np.einsum("ij,ij->j", points - proj, normal)
    dist = inplane[rows, best]
    if search_radius is not None:
        far = np.nonzero(np.hypot(dist, gap) > search_radius)[0]
        if far.size:
            i = far[0]
            raise ContactSearchError(
                f"{far.size} slave point(s) have no master facet within the search radius "
                f"{search_radius:.3g}; first: point {i} at {points[:, i]}, distance "
                f"{np.hypot(dist[i], gap[i]):.3g}")
    return Projection(facets[sel], f[:, sel], weights, gap, normal, dist)


def tie_prolongation(n_nodes: int, slave: np.ndarray, master_nodes: np.ndarray,
                     weights: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """Node-level prolongation of a tie: ``u_node = P u_retained``.

    ``slave`` (n,) are eliminated nodes (global numbering); ``master_nodes``
    (3, n) and ``weights`` (3, n) express each slave as a combination of
    master nodes, which must not be slaves themselves.  Returns ``P``
    (n_nodes x n_retained) and the retained node indices.  The vector
    prolongation for DOFs ``3 s + i`` is ``kron(P, I3)``.
    """
    slave = np.asarray(slave)
    is_slave = np.zeros(n_nodes, dtype=bool)
    is_slave[slave] = True
    if np.any(is_slave[master_nodes]):
        raise ValueError("tie_prolongation: a master node is also a slave node; "
                         "ties must not be chained")
    retained = np.nonzero(~is_slave)[0]
    col = -np.ones(n_nodes, dtype=np.int64)
    col[retained] = np.arange(retained.size)
    rows = np.concatenate([retained, np.repeat(slave, 3)])
    cols = np.concatenate([np.arange(retained.size), col[master_nodes.T.ravel()]])
    vals = np.concatenate([np.ones(retained.size), weights.T.ravel()])
    P = sp.csr_matrix((vals, (rows, cols)), shape=(n_nodes, retained.size))
    return P, retained


# ------------------------------------------------------------------ contact --

class ContactLostError(RuntimeError):
    """No node is left in contact: the load separates the bodies."""


class ActiveSetError(RuntimeError):
    """The active-set iteration did not settle (names its figures)."""


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
    traction ``mu p``; the master gets the opposite.
    """

    slave: np.ndarray
    area: np.ndarray
    normal: np.ndarray
    g0: np.ndarray
    coupling: sp.csr_matrix | None = None
    mu: float = 0.0
    drag: np.ndarray | None = None
    name: str = "contact"

    def __post_init__(self):
        n = self.slave.size
        if self.mu < 0 or not np.isfinite(self.mu):
            raise ValueError(f"{self.name}: friction coefficient mu = {self.mu!r}; need mu >= 0")
        if self.mu > 0 and (self.drag is None or self.drag.shape != (3, n)):
            raise ValueError(f"{self.name}: mu > 0 needs a drag direction (3, {n}) per slave node")
        for key in ("area", "g0"):
            if getattr(self, key).shape != (n,):
                raise ValueError(f"{self.name}: {key} must have shape ({n},)")
        if self.coupling is not None:
            self.coupling = sp.csr_matrix(self.coupling)

    @property
    def rigid(self) -> bool:
        return self.coupling is None


def mortar_coupling(slave_mesh: fem.Mesh, slave_facets, slave: np.ndarray,
                    master_mesh: fem.Mesh, master_facets, n_master_nodes: int,
                    level: int = 2, search_radius: float | None = None):
    """Segment-weighted coupling: ``W[s, m] = int phi_s psi_m dA / int phi_s dA``.

    ``phi_s`` are the slave surface's linear shape functions, ``psi_m`` the
    master's, evaluated at the projections of ``4**level`` points per slave
    facet (centroids of a regular subdivision).  With this coupling a uniform
    contact pressure maps to the consistent nodal loads of the master mesh,
    which is what one-point projection misses on non-matching meshes.
    Returns (W (n_slave x n_master_nodes), weak gap (n_slave,), area (n_slave,)).
    """
    if isinstance(slave_facets, str):
        slave_facets = slave_mesh.boundaries[slave_facets]
    # barycentric centroids of the subdivision of the reference triangle
    m = 2 ** level
    pts = []
    for i in range(m):
        for j in range(m - i):
            pts.append(((i + 1 / 3) / m, (j + 1 / 3) / m))          # upward triangles
            if i + j < m - 1:
                pts.append(((i + 2 / 3) / m, (j + 2 / 3) / m))      # downward triangles
    lam = np.array([[1 - a - b, a, b] for a, b in pts]).T          # (3, nq), equal weights
    nq = lam.shape[1]
    f = slave_mesh.facets[:, slave_facets]
    X = slave_mesh.p[:, f]                                          # (3 coords, 3 verts, nf)
    area = 0.5 * np.linalg.norm(np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0], axis=0), axis=0)
    xq = np.einsum("avf,vq->afq", X, lam).reshape(3, -1)            # (3, nf * nq)
    pr = project_nodes(xq, master_mesh, master_facets, search_radius=search_radius)
    wq = np.repeat(area / nq, nq).reshape(-1, nq).ravel()           # weight of each point
    col = -np.ones(slave_mesh.nvertices, dtype=np.int64)
    col[slave] = np.arange(slave.size)
    rows, cols, vals = [], [], []
    gap_num = np.zeros(slave.size)
    den = np.zeros(slave.size)
    phi = lam[:, None, :].repeat(f.shape[1], axis=1).reshape(3, -1)
    fv = np.repeat(f, nq, axis=1)                                   # slave vertex per point
    for a in range(3):
        sa = col[fv[a]]
        wa = wq * phi[a]
        np.add.at(den, sa, wa)
        np.add.at(gap_num, sa, wa * pr.gap)
        for b in range(3):
            rows.append(sa)
            cols.append(pr.nodes[b])
            vals.append(wa * pr.weights[b])
    W = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(slave.size, n_master_nodes))
    W = sp.diags(1.0 / den) @ W
    return W.tocsr(), gap_num / den, den


def pair_to_surface(slave_mesh: fem.Mesh, slave_facets, slave_offset: int,
                    master_mesh: fem.Mesh, master_facets, master_offset: int,
                    mu: float = 0.0, drag=None, search_radius: float | None = None,
                    exclude: np.ndarray | None = None, method: str = "segment",
                    level: int = 2, n_nodes: int | None = None,
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
    """
    if method not in ("node", "segment"):
        raise ValueError(f"{name}: method = {method!r}; allowed: 'node', 'segment'")
    slave = surface_nodes(slave_mesh, slave_facets)
    N = (max(master_offset + master_mesh.nvertices, slave_offset + slave_mesh.nvertices)
         if n_nodes is None else n_nodes)
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
                                      master_mesh.nvertices, level, search_radius)
        W = sp.csr_matrix((W.data, W.indices + master_offset, W.indptr), shape=(slave.size, N))
    if exclude is not None:
        keep = ~np.isin(slave, exclude)
        slave, area, g0, W = slave[keep], area[keep], g0[keep], W[keep]
        pr.normal = pr.normal[:, keep]
    d = _unit_tangential(drag(slave_mesh.p[:, slave]), pr.normal) if mu > 0 else None
    return ContactPair(slave + slave_offset, area, pr.normal, g0, W, mu, d, name)


def pair_to_rigid(slave_mesh: fem.Mesh, slave_facets, slave_offset: int, height,
                  side: int = 1, mu: float = 0.0, drag=None,
                  exclude: np.ndarray | None = None, name: str = "rigid contact") -> ContactPair:
    """A contact pair against a rigid surface ``z = height(x, y)``.

    ``side = +1``: the rigid body lies below the surface (normal +z);
    ``side = -1``: above it (normal -z).  Gaps are measured along z, the
    small-slope approximation that Hertz theory also makes.  ``exclude``
    lists vertex indices of the slave mesh to leave out.
    """
    if side not in (1, -1):
        raise ValueError(f"{name}: side = {side!r}; allowed: +1 (rigid below), -1 (rigid above)")
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


def _unit_tangential(v: np.ndarray, n: np.ndarray) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    v = v - n * np.einsum("ij,ij->j", v, n)
    norm = np.linalg.norm(v, axis=0)
    if np.any(norm == 0):
        raise ValueError("drag direction is zero or normal to the surface at some slave node "
                         "(e.g. a node on the rotor axis)")
    return v / norm


@dataclass
class ContactResult:
    """Contact solution: displacements and, per pair, the nodal contact state."""

    u: np.ndarray
    pressure: list       # per pair: (ns,) normal pressure (Pa), 0 where open
    force: list          # per pair: (ns,) normal nodal force (N)
    gap: list            # per pair: (ns,) normal gap after deformation (m)
    active: list         # per pair: (ns,) bool, in contact
    friction: list       # per pair: (3, ns) tangential nodal force on the slave (N)
    info: dict = field(default_factory=dict)


def _local_frames(n: np.ndarray):
    """For each normal: the DOF slot that becomes the eliminated (dummy) one
    (the dominant axis) and the tangential directions of the other two slots."""
    k = np.argmax(np.abs(n), axis=0)
    slots = np.array([[1, 2], [0, 2], [0, 1]])[k]  # (ns, 2) retained global axes
    T = np.zeros((2, 3, n.shape[1]))
    for a in range(2):
        e = np.zeros_like(n)
        e[slots[:, a], np.arange(n.shape[1])] = 1.0
        T[a] = e - n * np.einsum("ij,ij->j", e, n)  # e_j minus its normal part
    return k, slots, T


def _active_frames(pairs, active):
    """Per pair with active nodes: the pair, its mask, the active slave nodes, their
    normals and local frames (:func:`_local_frames`)."""
    for pr, act in zip(pairs, active):
        s = pr.slave[act]
        if s.size:
            n = pr.normal[:, act]
            yield (pr, act, s, n, *_local_frames(n))


def _prolongation(N: int, pairs, active):
    """``u = P x + c`` for the active constraints; also the dummy DOFs."""
    elim = []
    rows, cols, vals = [], [], []
    c = np.zeros(N)
    for pr, act, s, n, k, slots, T in _active_frames(pairs, active):
        elim.append(3 * s + k)
        for a in range(2):
            for i in range(3):
                rows.append(3 * s + i)
                cols.append(3 * s + slots[:, a])
                vals.append(T[a, i])
        if not pr.rigid:
            Wc = pr.coupling[np.nonzero(act)[0]].tocoo()
            sr, mr, w = s[Wc.row], Wc.col, Wc.data
            nr = n[:, Wc.row]
            for i in range(3):
                for j in range(3):
                    v = nr[i] * w * nr[j]
                    nz = v != 0
                    rows.append((3 * sr + i)[nz])
                    cols.append((3 * mr + j)[nz])
                    vals.append(v[nz])
        for i in range(3):
            c[3 * s + i] = -pr.g0[act] * n[i]
    elim = np.concatenate(elim) if elim else np.zeros(0, dtype=np.int64)
    slave_dofs = np.concatenate([3 * pr.slave[act][:, None] + np.arange(3)
                                 for pr, act in zip(pairs, active)]).ravel() \
        if any(a.any() for a in active) else np.zeros(0, dtype=np.int64)
    keep = np.ones(N, dtype=bool)
    keep[slave_dofs] = False
    idx = np.nonzero(keep)[0]
    rows.append(idx)
    cols.append(idx)
    vals.append(np.ones(idx.size))
    P = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(N, N))
    return P, c, elim


def _friction_operators(N: int, pairs, active):
    """``G`` (N x n_act): nodal friction load per unit normal force of each active
    slave node (drag on the slave, opposite on its master nodes); ``S`` (n_act x N):
    the normal component at each active slave node."""
    gr, gc, gv, sr, sc, sv = [], [], [], [], [], []
    col0 = 0
    for pr, act in zip(pairs, active):
        idx = np.nonzero(act)[0]
        k = np.arange(idx.size) + col0
        col0 += idx.size
        s = pr.slave[idx]
        for i in range(3):
            sr.append(k)
            sc.append(3 * s + i)
            sv.append(pr.normal[i, idx])
        if pr.mu == 0:
            continue
        t = pr.mu * pr.drag[:, idx]
        for i in range(3):
            gr.append(3 * s + i)
            gc.append(k)
            gv.append(t[i])
            if not pr.rigid:
                Wc = pr.coupling[idx].tocoo()
                gr.append(3 * Wc.col + i)
                gc.append(k[Wc.row])
                gv.append(-Wc.data * t[i, Wc.row])
    G = sp.csr_matrix((np.concatenate(gv), (np.concatenate(gr), np.concatenate(gc))),
                      shape=(N, col0))
    S = sp.csr_matrix((np.concatenate(sv), (np.concatenate(sr), np.concatenate(sc))),
                      shape=(col0, N))
    return G, S


def _gaps(u: np.ndarray, pr: ContactPair) -> np.ndarray:
    us = u.reshape(-1, 3)[pr.slave].T
    if pr.rigid:
        rel = us
    else:
        um = u.reshape(-1, 3)
        rel = us - (pr.coupling @ um).T
    return pr.g0 + np.einsum("ij,ij->j", pr.normal, rel)


def solve_contact(K: sp.spmatrix, f: np.ndarray, fixed: np.ndarray, coords: np.ndarray,
                  pairs: list, fixed_values: np.ndarray | float = 0.0, tol: float = 1e-9,
                  gap_tol: float | None = None,
                  max_iter: int = 60, linear: str = "amg", release_tol: float = 1e-6,
                  initial_active: list | None = None, solver=None) -> ContactResult:
    """Frictional node-to-surface contact by active sets on an eliminated system.

    Parameters
    ----------
    K, f
        Global stiffness (all bodies, DOF ``3 node + i``) and load.
    fixed, fixed_values
        Supported DOFs and their prescribed displacements (default 0).  A
        supported normal DOF on an active slave node is refused.
    coords
        Node coordinates (3, n_nodes) for the rigid-body near-nullspace.
    pairs
        :class:`ContactPair` list.
    tol
        Relative residual of each linear solve.
    gap_tol
        Penetration tolerated before a node is activated; default 1e-10 times
        the model size.
    linear
        ``"amg"`` (pyamg CG, hierarchy reused across iterations) or
        ``"direct"`` (small systems).
    release_tol
        A contact node is released only if its multiplier is below
        ``-release_tol * max |lambda|``: a margin above the linear solver's
        noise, without which nodes at the contact edge can flip forever.
    initial_active
        Starting active set per pair (default: the nodes with ``g0 <=
        gap_tol``, else the closest ones); a wear step passes the last one.
        A given set is taken as a good guess: every solve is then tight.
    solver
        A hierarchy from :func:`contact_preconditioner` for this ``K``,
        ``fixed`` and pair geometry, shared between solves (a wear loop).
        It is never modified: each active set gets a refreshed copy, so the
        result depends only on the inputs and this hierarchy, not on earlier
        solves.  Default: one is built at the initial active set.

    The active set follows the primal-dual rule (a node in contact stays if
    its multiplier is compressive, an open node enters if it penetrates).
    If an active set repeats (cycling), the update turns conservative: add
    penetrating nodes, release only the most tensile one per iteration.
    Sliding friction with a known slip direction is linear in the
    displacements (``mu`` times the normal reaction, along ``drag``), so it
    enters the operator itself: each active set is one flexible GMRES solve
    (AMG of the symmetric part as preconditioner), not a fixed point.

    Cost: per active set, ``P^T K P`` is ``K`` plus a difference local to
    the contact rows, and the AMG operators of every level are updated by
    that difference (the coarsest level is refactorised: a few hundredths of
    a second).  While the set moves, the first solve stops at
    ``1e-2`` and later ones at a tenth of their warm-start residual; once it
    repeats (or an edge node flips twice), the solves stop at ``1e-6`` while
    the set still changes, and one solve to ``tol`` confirms the last one.
    The near-nullspace keeps the rigid-body modes on the dummy DOFs, and the
    aggregates stay inside the bodies of ``K`` (:func:`_bodies`), so a
    hierarchy built at one set still serves the others (490k brake, final
    set: 34 FGMRES iterations refreshed from the all-closed set, 29 built
    there; 48 with aggregates across the interface).  Each new set starts
    from the last displacement (:func:`_reduced_start`).
    """
    from .solvers import amg_solver, direct_solve

    t_start = time.perf_counter()
    K = K.tocsr()
    N = K.shape[0]
    f = np.asarray(f, dtype=float)
    fixed = np.asarray(fixed, dtype=np.int64)
    fvals = np.broadcast_to(np.asarray(fixed_values, dtype=float), fixed.shape)
    fixed, first = np.unique(fixed, return_index=True)
    fvals = fvals[first]
    size = float(np.linalg.norm(coords.max(axis=1) - coords.min(axis=1)))
    gap_tol = 1e-10 * size if gap_tol is None else gap_tol
    if linear not in ("amg", "direct"):
        raise ValueError(f"linear = {linear!r}; allowed: 'amg', 'direct'")
    if initial_active is None:
        active = [pr.g0 <= gap_tol for pr in pairs]
        if not any(a.any() for a in active):  # first touch: the closest nodes
            gmin = min(pr.g0.min() for pr in pairs)
            active = [pr.g0 <= gmin + gap_tol for pr in pairs]
    else:
        active = [np.asarray(a, dtype=bool).copy() for a in initial_active]
    base_delta = None  # the base hierarchy's operator minus Kd, where known
    if solver is not None:
        _check_base(solver, N)
        known = getattr(solver, "contact_delta", None)  # set by contact_preconditioner
        if known is not None and known[0] is solver.A:
            base_delta = known[1]
    seen = set()
    flips = [np.zeros(pr.slave.size, dtype=np.int64) for pr in pairs]  # state changes per node
    conservative = False
    x = None
    lin_its, builds, refreshes, history = 0, 0, 0, []
    is_fixed = np.zeros(N, dtype=bool)
    is_fixed[fixed] = True
    u_fixed = np.zeros(N)
    u_fixed[fixed] = fvals
    frictional = any(pr.mu > 0 for pr in pairs)
    Kd = _dirichlet_base(K, is_fixed)
    diagK = K.diagonal()
    base = solver  # the hierarchy every refresh starts from; never modified here
    bodies = False  # node labels of K's bodies for the hierarchy's aggregates, when needed
    fine = None    # _SetOperators, from the second active set on
    coarse = None  # the base hierarchy's coarse operators in place (AMGSolver.level_buffers)
    refreshes_of_base = 0
    work = None    # the preconditioner of the current active set
    set_key = None
    # inexact phase: while the active set moves, each solve only has to cut its
    # warm-start residual by _INEXACT; once it stops moving, a tight solve confirms it.
    # A given initial set (a wear step, an outer iteration) is taken as nearly right:
    # tight solves from the start, since a loose one's noise moves edge nodes in and
    # out (measured on the 57k brake from its converged set: 48 iterations and a cycle
    # with a loose first solve, 39 and no change with a tight one)
    tight = initial_active is not None
    tight_reason = "given set" if tight else None  # why the solves went tight (info)
    tight_from = 1 if tight else None
    # after the loose phase the solves first stop at _MEDIUM: accurate enough to decide
    # the edge nodes, and if they still move, much cheaper than a solve to tol each time
    # (Hertz 491k made five tight solves of 16-19 iterations while its set shrank); a
    # set that a medium solve reproduces is then confirmed by one solve to tol
    medium = False
    ref_rate = None     # residual reduction per iteration of the first solve of >= 4 its
    for it in range(1, max_iter + 1):
        if not any(a.any() for a in active):
            raise ContactLostError(
                f"no node is in contact after {it - 1} active-set iteration(s): the load "
                f"separates the bodies (net load {f.reshape(-1, 3).sum(axis=0)} N). A contact "
                "solve needs a load that presses the surfaces together.")
        key = _set_key(active)
        if key != set_key:  # a new active set: its operator and preconditioner
            P, c, elim = _prolongation(N, pairs, active)
            clash = np.intersect1d(elim, fixed)
            if clash.size:
                raise ValueError(f"{clash.size} supported DOF(s) are the normal DOF of a contact "
                                 f"node (first: DOF {clash[0]}); a node cannot be both supported "
                                 "and in contact along the normal")
            if fine is None and set_key is not None and linear == "amg":
                # a second set in this solve: from now on each set's operator is formed
                # in place (one pass over K to set up, none per set)
                fine = _SetOperators(K, Kd, pairs, is_fixed)
            A, E, bd, dK = _contact_system(K, Kd, f, pairs, active, P, c, elim, is_fixed,
                                           u_fixed, frictional, diagK, fine)
            if x is not None:  # warm start: the last displacement in this set's unknowns
                x = _reduced_start(u, pairs, active)
            set_key = key
            if E is None:
                Aop = A
            elif linear == "direct":
                Aop = (A - E[0] @ E[1]).tocsr()
            else:
                Aop = spla.LinearOperator(
                    A.shape, matvec=lambda v, A=A, G=E[0], S=E[1]: A @ v - G @ (S @ v),
                    dtype=float)
            if linear == "amg":
                if base is None or (ref_rate is not None and _stale(work.info, ref_rate)):
                    # the first set, or the aggregates have gone stale: a hierarchy of this set
                    if bodies is False:
                        bodies = _bodies(K)
                    # the set's CSR operator serves as the finest level unless it lives
                    # in fine's buffer, which the next set overwrites
                    base = amg_solver(A.tobsr(blocksize=(3, 3)),
                                      B=_reduced_modes(coords, pairs, active, fixed), tol=tol,
                                      bodies=bodies, fine_csr=A if fine is None else None)
                    base_delta = dK
                    builds += 1
                    refreshes_of_base = 0
                    work = base
                else:  # same aggregates, operators of this set (base left as it is)
                    # A - base.A from the two small contact differences: at 490k DOFs the
                    # subtraction of the two full matrices took 0.7 s per set
                    # coarse operators in place from the second refresh of a big hierarchy
                    # on (_BUFFER_MIN_NNZ)
                    if fine is not None and refreshes_of_base >= 1 and \
                            (coarse is None or coarse.ml is not base.ml) and \
                            sum(lv.A.nnz for lv in base.ml.levels[1:]) >= _BUFFER_MIN_NNZ:
                        coarse = base.level_buffers(fine.Z)
                    work = base.refreshed(A, depth=_REFRESH_DEPTH,
                                          dA=None if base_delta is None else dK - base_delta,
                                          buffers=coarse)
                    refreshes += 1
                    refreshes_of_base += 1
        if linear == "direct":
            x = direct_solve(Aop, bd)
            its = "direct"
        else:
            work.tol = tol
            rtol0 = None
            if tight and medium:
                work.tol = max(tol, _MEDIUM)
            elif not tight:
                if x is None:
                    work.tol = max(tol, _FIRST)
                else:  # cut the warm start's residual by _INEXACT
                    rtol0 = _INEXACT
            x = work.solve(bd, x0=x, A=Aop, krylov="gmres" if frictional else "cg", rtol0=rtol0)
            its = work.info.iterations
            if ref_rate is None and its >= 4:
                # the reference rate of this hierarchy: a solve of at least 4 iterations
                # (Hertz at 491k: a 2-iteration first solve reduced 0.09 per iteration,
                # so every later tight solve at 0.3 looked stale and was rebuilt, 9 s each)
                ref_rate = work.info.convergence_factor
            lin_its += its
        u = P @ x + c
        logger.debug("active-set iteration %d: %d active, %s linear iterations", it,
                     sum(int(a.sum()) for a in active), its)
        r = (K @ u - f).reshape(-1, 3)
        lam = [np.where(a, np.einsum("ij,ij->j", pr.normal, r[pr.slave].T), 0.0)
               for pr, a in zip(pairs, active)]
        gaps = [np.where(a, 0.0, _gaps(u, pr)) for pr, a in zip(pairs, active)]
        ltol = [release_tol * max(np.abs(l).max(), 1e-300) for l in lam]
        update = _conservative_update if conservative else _pdas_update
        new_active = update(active, lam, gaps, gap_tol, ltol)
        same = all(np.array_equal(a, b2) for a, b2 in zip(active, new_active))
        history.append(int(sum(a.sum() for a in active)))
        if same:
            if (tight and not medium) or linear == "direct":
                break
            if tight:  # a medium solve reproduced its set: confirm it to tol
                medium = False
            else:
                tight, medium, tight_reason = True, True, "set repeated"
                tight_from = it + 1
            continue
        n_act = sum(int(a.sum()) for a in active)
        if not any(a.any() for a in new_active) and n_act > 1:
            # the primal-dual rule released every node at once (an overshoot on a
            # very non-conformal start; an empty set is singular): keep the tenth
            # of the set that pulls least.  A load that really lifts the pad off
            # empties the set in a few such steps and ends in ContactLostError.
            keep = max(1, n_act // 10)
            cut = np.sort(np.concatenate([l[a] for l, a in zip(lam, active)]))[-keep]
            new_active = [a & (l >= cut) for a, l in zip(active, lam)]
            logger.info("active set would empty after %d iterations; keeping the %d least "
                        "tensile nodes", it, keep)
        if not tight:
            # once the set has nearly settled, a node that changes state a second time
            # while the solves are loose is deciding on the solver's noise (a contact
            # edge where the pressure goes to zero): from here on every solve is tight.
            # Hertz at 151k wandered for 20 loose sets without repeating one exactly,
            # edge nodes flipping in turn.  Large early updates do not count: there the
            # primal-dual rule overshoots (Hertz at 491k: 1596 -> 864 -> 1255 active
            # nodes), which is no noise.  (Holding such nodes fixed and going on with
            # loose solves instead took more sets: Hertz 491k 51.7 s against 45.5 s.)
            changed = sum(int(np.count_nonzero(a != b2)) for a, b2 in zip(active, new_active))
            if changed <= _SETTLING * max(n_act, 1):
                for fl, a, b2 in zip(flips, active, new_active):
                    fl += a != b2
                if max(int(fl.max()) for fl in flips) >= 2:
                    tight, medium, tight_reason, tight_from = True, True, "flip", it + 1
                    logger.debug("a node flipped twice under loose solves; tight solves "
                                 "from now on")
        key = _set_key(new_active)
        # a set that repeats cycles; one that wanders for a third of the budget
        # without repeating exactly (edge nodes flipping in turn) is treated alike
        if (key in seen or it >= max_iter // 3) and not conservative:
            logger.info("active set %s after %d iterations; switching to conservative "
                        "updates", "cycles" if key in seen else "does not settle", it)
            conservative = True
            medium = False  # a loose solve's noise is what lets an edge node flip forever
            if not tight:
                tight, tight_reason, tight_from = True, "conservative", it + 1
            new_active = _conservative_update(active, lam, gaps, gap_tol, ltol)
        seen.add(_set_key(active))
        active = new_active
    else:
        raise ActiveSetError(
            f"active set did not settle in {max_iter} iterations (active counts "
            f"{history[-6:]}, conservative={conservative})")
    # final state and the checks every solve must pass
    gaps = [_gaps(u, pr) for pr in pairs]
    fric = [pr.mu * l * pr.drag if pr.mu > 0 else np.zeros((3, pr.slave.size))
            for pr, l in zip(pairs, lam)]
    pressure = [l / pr.area for l, pr in zip(lam, pairs)]
    info = {
        "active_set_iterations": it, "linear_iterations": lin_its, "amg_builds": builds,
        "amg_refreshes": refreshes,
        "conservative": conservative, "active_counts": history,
        "tight_from": tight_from, "tight_reason": tight_reason,
        "normal_force": [float(l.sum()) for l in lam],
        "min_multiplier": min(float(l.min()) for l in lam),
        "min_gap": min(float(g.min()) for g in gaps),
        "max_complementarity": max(float(np.abs(l * g).max()) for l, g in zip(lam, gaps)),
        "gap_tol": gap_tol, "time_s": time.perf_counter() - t_start,
    }
    if info["min_gap"] < -max(gap_tol, 1e-10 * size):
        raise ActiveSetError(f"penetration {info['min_gap']:.3e} m exceeds the gap tolerance "
                             f"{gap_tol:.1e} m after convergence")
    return ContactResult(u, pressure, lam, gaps, active, fric, info)


def _reduce_delta(K: sp.csr_matrix, P: sp.csr_matrix) -> sp.csr_matrix:
    """``P^T K P - K`` for a ``P`` that is the identity but in a few rows, without full-size products.

    With ``D = P - I`` (nonzero only in the constrained rows) and symmetric
    ``K``: ``P^T K P - K = K D + (K D)^T + D^T K D``; every product involves
    only the rows of the constrained DOFs (``K[:, rows] = K[rows]^T``).
    """
    D = (P - sp.identity(K.shape[0], format="csr")).tocsr()
    D.eliminate_zeros()
    rows = np.flatnonzero(np.diff(D.indptr))
    Dr = D[rows]
    Kr = K[rows]
    KD = (Kr.T @ Dr).tocsr()
    DKD = (Dr.T @ (Kr[:, rows] @ Dr)).tocsr()
    return (KD + KD.T + DKD).tocsr()


def _mask_fixed(M: sp.spmatrix, is_fixed: np.ndarray,
                keep_diagonal: bool = False) -> sp.csr_matrix:
    """``M`` without the rows and columns of supported DOFs (CSR, structure
    filtered); with ``keep_diagonal`` their stored diagonal entries stay."""
    M = M.tocsr()
    row = np.repeat(np.arange(M.shape[0]), np.diff(M.indptr))
    keep = ~is_fixed[row] & ~is_fixed[M.indices]
    if keep_diagonal:
        keep |= row == M.indices
    indptr = np.zeros(M.shape[0] + 1, dtype=M.indptr.dtype)
    np.cumsum(np.bincount(row[keep], minlength=M.shape[0]), out=indptr[1:])
    return sp.csr_matrix((M.data[keep], M.indices[keep], indptr), shape=M.shape)


def _mask_fixed_rows(M: sp.spmatrix, is_fixed: np.ndarray) -> sp.csr_matrix:
    """``M`` without the rows of supported DOFs."""
    return (sp.diags((~is_fixed).astype(float)) @ M.tocsr()).tocsr()


def _dirichlet_base(K: sp.csr_matrix, is_fixed: np.ndarray) -> sp.csr_matrix:
    """``K`` with the rows and columns of supported DOFs zeroed, their diagonal kept
    (one filtering pass; a stored diagonal entry is kept as it is)."""
    K = K.tocsr()
    if not K.has_canonical_format:
        K = K.copy()
        K.sum_duplicates()
    return _mask_fixed(K, is_fixed, keep_diagonal=True)


def _set_delta(K, P, elim, is_fixed, diagK):
    """``P^T K P - K`` with the eliminated normal DOFs as decoupled dummies
    (``K``'s diagonal); rows and columns of supported DOFs kept (masked by the caller)."""
    delta = _reduce_delta(K, P)
    if elim.size:
        N = K.shape[0]
        delta = delta + sp.csr_matrix((diagK[elim], (elim, elim)), shape=(N, N))
    return delta


class _SetOperators(PatchedMatrix):
    """``Kd + dK`` for every active set of one solve on a single sparsity pattern
    (:class:`~brakewear.solvers.PatchedMatrix`).

    The pattern is the union of ``Kd``'s and of the structural pattern ``Z``
    of the difference with *every* slave node active (absolute values
    multiplied, so no cancellation drops an entry) and the slave DOFs'
    diagonal (the dummy rows), which contains the difference of any active
    set.  A new set restores the previous set's entries to ``Kd`` and adds
    its own -- work in the size of the difference, where ``Kd + dK`` is a
    pass over the whole matrix (at 490k DOFs, 21M entries: 0.4-0.6 s per
    set).  ``Z`` also gives the coarse levels' patterns
    (:meth:`~brakewear.solvers.AMGSolver.level_buffers`).
    """

    def __init__(self, K, Kd, pairs, is_fixed):
        N = K.shape[0]
        P, _, _ = _prolongation(N, pairs, [np.ones(pr.slave.size, dtype=bool) for pr in pairs])
        D = abs(P - sp.identity(N, format="csr")).tocsr()
        D.eliminate_zeros()
        rows = np.flatnonzero(np.diff(D.indptr))
        Dr, Kr = D[rows], abs(K[rows])
        KD = (Kr.T @ Dr).tocsr()
        dofs = np.unique(np.concatenate([3 * pr.slave[:, None] + np.arange(3) for pr in pairs]
                                        ).ravel())
        Z = KD + KD.T + Dr.T @ (Kr[:, rows] @ Dr) + sp.csr_matrix(
            (np.ones(dofs.size), (dofs, dofs)), shape=(N, N))
        self.Z = _mask_fixed(Z, is_fixed)
        self.Z.eliminate_zeros()
        super().__init__(Kd, self.Z)


def _contact_system(K, Kd, f, pairs, active, P, c, elim, is_fixed, u_fixed, frictional,
                    diagK=None, fine: _SetOperators | None = None):
    """The eliminated system of one active set, supports applied.

    Returns ``A`` (SPD: ``P^T K P`` with a unit-scaled dummy row per eliminated
    normal DOF, supported rows/columns replaced by their diagonal), ``E`` (the
    sliding-friction term, the operator being ``A - E``; None without
    friction), the right-hand side and ``dK = A - Kd``, the small masked
    difference: only the rows of the contact nodes are recomputed.  With
    ``fine`` (:class:`_SetOperators`), ``A`` is formed in its buffer.
    """
    N = K.shape[0]
    diagK = K.diagonal() if diagK is None else diagK
    delta = _set_delta(K, P, elim, is_fixed, diagK)
    dK = _mask_fixed(delta, is_fixed)
    A = (Kd + dK).tocsr() if fine is None else fine.matrix(dK)
    b = P.T @ (f - K @ c)
    E = None
    if frictional:
        # sliding friction mu * lambda along a known direction is linear in u:
        # f_fr = G S (K u - f), S = normal rows of active slaves, G = drag loads
        # kept as the product of its two thin factors (n x n_act, n_act x n): the
        # product itself would have as many nonzeros as K
        G, S = _friction_operators(N, pairs, active)
        PG = (P.T @ G).tocsr()
        SKP = ((S @ K) @ P).tocsr()
        b = b + PG @ (S @ (K @ c - f))
        E = (_mask_fixed_rows(PG, is_fixed), _mask_fixed_rows(SKP.T, is_fixed).T.tocsr())
    b[elim] = 0.0
    if np.any(u_fixed):  # prescribed values to the right-hand side
        Au = K @ u_fixed + delta @ u_fixed
        if E is not None:
            Au = Au - PG @ (SKP @ u_fixed)
        b = b - Au
    b[is_fixed] = diagK[is_fixed] * u_fixed[is_fixed]
    return A, E, b, dK


def _reduced_start(u: np.ndarray, pairs, active) -> np.ndarray:
    """The reduced unknowns ``x`` of ``active``'s system that give ``u`` as closely
    as its constraints allow: the warm start after an active-set change.

    Reusing the last set's ``x`` instead would read a released node's dummy
    (0) as its normal displacement -- a jump of the pad's whole approach at
    every released node -- and a new contact node's axis components as its
    tangential coordinates (490k brake, cold solve: 66 linear iterations in
    11 sets that way, 58 in 10 with this start; the last sets begin 3-400x
    closer to their solution).  Here an open node takes ``u``; a contact node's
    two retained slots take the coordinates along its tangential directions
    ``T[a]`` (``u_s + alpha n`` with zero dominant component) and its dummy 0.
    """
    x = np.array(u, dtype=float)
    for _, _, s, n, k, slots, _ in _active_frames(pairs, active):
        idx = np.arange(s.size)
        us = u.reshape(-1, 3)[s]  # (ns, 3)
        alpha = -us[idx, k] / n[k, idx]
        for a in range(2):
            x[3 * s + slots[:, a]] = us[idx, slots[:, a]] + alpha * n[slots[:, a], idx]
        x[3 * s + k] = 0.0
    return x


def _set_key(active) -> bytes:
    return b"".join(np.packbits(a).tobytes() for a in active)


def _check_base(solver, N: int) -> None:
    from .solvers import AMGSolver

    if not isinstance(solver, AMGSolver) or solver.A.shape != (N, N):
        shape = getattr(getattr(solver, "A", None), "shape", None)
        raise ValueError(f"solver = {type(solver).__name__} (matrix shape {shape}); need the "
                         f"AMGSolver of contact_preconditioner() for this {N}-DOF system")


def contact_preconditioner(K: sp.spmatrix, fixed: np.ndarray, coords: np.ndarray, pairs: list,
                           active: list | None = None, tol: float = 1e-9):
    """AMG hierarchy of the eliminated contact operator, for ``solve_contact(..., solver=)``.

    Built at ``active`` (default: every slave node in contact).  The operator
    does not depend on the gaps ``g0``, the loads or the friction, so in a
    wear loop (constant ``K``, changing ``g0`` and active set) one hierarchy
    serves every step.  :func:`solve_contact` never modifies it: each active
    set gets its own refreshed copy (:meth:`AMGSolver.refreshed`), so a
    solve's result depends only on its inputs and this hierarchy, never on
    earlier solves.
    """
    from .solvers import amg_solver

    K = K.tocsr()
    N = K.shape[0]
    fixed = np.unique(np.asarray(fixed, dtype=np.int64))
    if active is None:
        active = [np.ones(pr.slave.size, dtype=bool) for pr in pairs]
    else:
        active = [np.asarray(a, dtype=bool) for a in active]
        for pr, a in zip(pairs, active):
            if a.shape != pr.slave.shape:
                raise ValueError(f"{pr.name}: active has shape {a.shape}; need {pr.slave.shape}")
    is_fixed = np.zeros(N, dtype=bool)
    is_fixed[fixed] = True
    P, c, elim = _prolongation(N, pairs, active)
    A, _, _, dK = _contact_system(K, _dirichlet_base(K, is_fixed), np.zeros(N), pairs, active,
                                  P, c, elim, is_fixed, np.zeros(N), False)
    solver = amg_solver(A.tobsr(blocksize=(3, 3)), B=_reduced_modes(coords, pairs, active, fixed),
                        tol=tol, bodies=_bodies(K), fine_csr=A)
    # its operator minus the Dirichlet-masked K, valid while solver.A is this operator:
    # solve_contact forms each set's update from it instead of subtracting two full matrices
    solver.contact_delta = (solver.A, dK)
    return solver


def _stale(info, ref_rate: float) -> bool:
    """The aggregates have gone stale when a solve on a refreshed copy needs
    twice the iterations per decade of residual of the reference solve (the
    first of at least 4 iterations): a reduction factor above the square root
    of the reference's.  Iteration
    counts are not compared: the solves stop at different tolerances."""
    return bool(info.iterations > 3 and info.convergence_factor > max(ref_rate, 1e-3) ** 0.5)


# coarse levels that see each active set: all of them.  With only the first coarse level
# updated (the coarsest keeping the base's LU), a hierarchy built at the all-closed start
# set preconditioned the 154k brake's final set at 40 FGMRES iterations to 1e-9 (27 with
# every level updated, 24 for one built at that set), went stale and was rebuilt once
# per cold solve: 9.1-9.7 s against 6.1-6.7 s with every level (57k: 72 -> 48 iterations)
_REFRESH_DEPTH = None
# coarse operators written in place (AMGSolver.level_buffers) only for hierarchies whose
# coarse levels hold at least this many entries: their setup (a copy of each coarse level
# and the search of the pushed-down pattern, which covers 14-31 % of the first coarse
# level) cost 0.14-0.26 s on the 57k brake and 0.47 s on the 154k one, against full sums
# of 0.02-0.04 s and about 0.08 s per refresh; at 490k (17M coarse entries) 0.9-1.8 s
# against 0.35-0.5 s per refresh, paid back from the third or fourth set
_BUFFER_MIN_NNZ = 10_000_000
_SETTLING = 0.1  # an update changing at most this share of the active nodes: nearly settled
_FIRST = 1e-2  # relative tolerance of the first, cold solve
_MEDIUM = 1e-6  # relative tolerance of the solves after the loose phase, before the last
_INEXACT = 1e-1  # intermediate solves cut their warm-start residual by this factor


def _pdas_update(active, lam, gaps, gap_tol, ltol):
    """Primal-dual active set: stay if compressive, enter if penetrating."""
    return [(a & (l > -lt)) | (~a & (g < -gap_tol)) for a, l, g, lt in zip(active, lam, gaps, ltol)]


def _conservative_update(active, lam, gaps, gap_tol, ltol):
    """Add every penetrating node; if none, release the most tensile nodes only:
    those pulling at least half as hard as the worst one.  Adding and releasing
    never happen in the same iteration, which is what stops a cycle; releasing
    in bulk (rather than one node at a time) keeps large sets within budget."""
    pen = [(~a) & (g < -gap_tol) for a, g in zip(active, gaps)]
    if any(p.any() for p in pen):
        return [a | p for a, p in zip(active, pen)]
    worst = min((float(np.min(np.where(a, l, np.inf))) for a, l in zip(active, lam) if a.any()),
                default=0.0)
    return [a & ~((l < 0.5 * worst) & (l < -lt)) for a, l, lt in zip(active, lam, ltol)]


def _bodies(K: sp.csr_matrix) -> np.ndarray | None:
    """Body label per node: the connected components of ``K``'s node graph
    (contact couples bodies only through the constraints); None for one body."""
    from scipy.sparse.csgraph import connected_components

    K = K.tocsr()
    first = K[::3]  # a node's x row couples to every node its y and z rows do
    graph = sp.csr_matrix((np.ones(first.nnz, dtype=np.int8), first.indices // 3,
                           first.indptr), shape=(K.shape[0] // 3, K.shape[0] // 3))
    n, labels = connected_components(graph, directed=False)
    return labels if n > 1 else None


def _reduced_modes(coords, pairs, active, fixed):
    from .solvers import rigid_body_modes

    return rigid_body_modes(coords, fixed)
