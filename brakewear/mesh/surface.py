"""Surfaces of a mesh: outward facet normals, the nodes of a named facet set, tributary areas.

The geometry that contact, heat and wear all need of a body's surface, with
no solver behind it.
"""
from __future__ import annotations

import logging

import numpy as np
import skfem as fem

logger = logging.getLogger(__name__)

__all__ = ["facet_normals", "surface_nodes", "tributary_areas"]


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
