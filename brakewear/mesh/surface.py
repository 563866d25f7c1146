"""Surfaces of a mesh: outward facet normals, the nodes of a named facet set, tributary areas.

The geometry that contact, heat and wear all need of a body's surface, with
no solver behind it.
"""
from __future__ import annotations

import logging

import numpy as np
import skfem as fem

logger = logging.getLogger(__name__)

__all__ = ["facet_normals", "surface_nodes", "tributary_areas", "is_quadratic",
           "quadratic_faces", "face_nodes"]


#: the mid-edge nodes of a quadratic facet, between its vertices (0, 1), (1, 2), (0, 2)
FACE_EDGES = ((0, 1), (1, 2), (0, 2))


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


def is_quadratic(mesh: fem.Mesh) -> bool:
    """Whether the mesh carries mid-edge nodes (``MeshTet2``: P2)."""
    return isinstance(mesh, fem.MeshTet2)


def quadratic_faces(mesh: fem.Mesh, facets) -> np.ndarray:
    """Nodes (6, nf) of quadratic facets: the three vertices of ``mesh.facets`` in
    their order, then the mid-edge nodes of edges (0, 1), (1, 2), (0, 2)
    (:data:`FACE_EDGES`) as scalar DOF numbers (edge ``e`` is node
    ``nvertices + e``, column of ``mesh.p``)."""
    if isinstance(facets, str):
        facets = mesh.boundaries[facets]
    f = mesh.facets[:, np.asarray(facets)]
    nv = mesh.nvertices
    e = np.sort(mesh.edges, axis=0)
    keys = e[0].astype(np.int64) * nv + e[1]
    order = np.argsort(keys)
    out = [f[0], f[1], f[2]]
    for a, b in FACE_EDGES:
        k = np.minimum(f[a], f[b]).astype(np.int64) * nv + np.maximum(f[a], f[b])
        out.append(nv + order[np.searchsorted(keys, k, sorter=order)])
    return np.vstack(out)


def face_nodes(mesh: fem.Mesh, facets) -> np.ndarray:
    """Sorted node numbers of named facets (or facet indices): their vertices
    (:func:`surface_nodes`) and, on a quadratic mesh, their mid-edge nodes too."""
    if not is_quadratic(mesh):
        return surface_nodes(mesh, facets)
    return np.unique(quadratic_faces(mesh, facets))
