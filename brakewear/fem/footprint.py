"""Loads over footprints: a uniform traction on the part of a face inside a region.

A piston's rim, a caliper finger: the load a brake's caliper puts on a
backplate acts over a footprint (an annulus, a disc) whose edge does not
follow the mesh.  :func:`footprint_load` integrates the consistent nodal
loads of a uniform traction times the footprint's indicator over the named
facets, each facet cut into ``4**level`` sub-triangles with a 7-point rule
on each (:func:`brakewear.mesh.triangle.subdivided_rule`), so the footprint's
area and centre are mesh-independent to a small share of the element size at
its edge, and scales the result so its resultant is exactly the given force.  Linear facets use the
P1 shape functions, quadratic ones (``MeshTet2``) the six of the P2 triangle
on the facet's flat image.
"""
from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np
import skfem as fem

from ..errors import GeometryError
from ..mesh.surface import is_quadratic, quadratic_faces
from ..mesh.topology import ensure_topology, facet_indices
from ..mesh.triangle import subdivided_rule, tri6

logger = logging.getLogger(__name__)

__all__ = ["footprint_load", "annulus"]


def annulus(center: tuple[float, float], inner: float, outer: float) -> Callable:
    """Indicator ``x (3, n) -> bool (n,)`` of the annulus ``inner <= |x - c| < outer``
    in the (x, y) plane (``inner = 0``: a disc)."""
    cx, cy = center

    def inside(x: np.ndarray) -> np.ndarray:
        d = np.hypot(x[0] - cx, x[1] - cy)
        return (d >= inner) & (d < outer)
    return inside


def footprint_load(mesh: fem.Mesh, facets, inside: Callable, force: float,
                   direction=(0.0, 0.0, -1.0), level: int = 2) -> np.ndarray:
    """Nodal load vector (DOF ``3 node + i``) of a uniform traction over the
    part of ``facets`` where ``inside(x)`` holds, with resultant ``force * direction``.

    Parameters
    ----------
    mesh
        A tetrahedral mesh (P1 or P2).
    facets
        Facet name or indices (a flat face: the traction per unit area is
        uniform on its flat image).
    inside
        Indicator of the footprint, ``x (3, n) -> bool (n,)`` (:func:`annulus`).
    force, direction
        Total force (N) and its direction (normalised here).
    level
        Sub-triangle refinement of each facet (``7 * 4**level`` samples).

    Raises
    ------
    GeometryError
        The footprint misses every facet (nothing to load).
    """
    ensure_topology(mesh)
    idx = facet_indices(mesh, facets)
    quad = is_quadratic(mesh)
    nodes = quadratic_faces(mesh, idx) if quad else mesh.facets[:, idx]
    v = mesh.p[:, mesh.facets[:, idx]]                          # (3, 3, nf) vertices
    area = 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0], axis=0), axis=0)
    lam, wq = subdivided_rule(level)                            # weights sum to one
    N = tri6(lam) if quad else lam                              # (k, q) shape functions
    # sample points: the facet's own geometry (quadratic facets: P2 map)
    X = np.einsum("kq,ikf->iqf", N, mesh.p[:, nodes])           # (3, q, nf)
    w = inside(X.reshape(3, -1)).reshape(X.shape[1:]) * wq[:, None] * area[None, :]  # (q, nf)
    total = w.sum()
    if total <= 0.0:
        raise GeometryError("footprint_load: the footprint does not overlap the facets "
                            f"{facets if isinstance(facets, str) else '(given)'}; nothing to load")
    nodal = (N @ w) / total                                     # (k, nf), sums to 1
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    share = np.bincount(nodes.ravel(), weights=nodal.ravel(), minlength=mesh.p.shape[1])
    f = (force * share[:, None] * d[None, :]).ravel()
    logger.debug("footprint load: %.6g N over %.6g m^2 of %d facets", force, total,
                 int((w.sum(axis=0) > 0).sum()))
    return f
