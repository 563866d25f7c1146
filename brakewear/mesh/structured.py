"""Structured tetrahedral meshes: graded coordinates, the Kuhn split, mapped and annular blocks.

A block of hexahedra in parametric coordinates is split into six tetrahedra
each (Kuhn split: every hexahedron is cut along its main diagonal, so
neighbouring faces get the same diagonal and the mesh is conforming), then
mapped to physical space; P2 edge nodes are placed with the same map.
"""
from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np
import skfem as fem

from ..errors import MeshError
from .topology import _with_boundaries

logger = logging.getLogger(__name__)

__all__ = ["graded", "structured_tets", "mapped_mesh", "cylindrical", "annulus_mesh", "KUHN"]


# The six tetrahedra of the Kuhn split, as corners (dx, dy, dz) of the unit cube:
# one monotone lattice path from (0,0,0) to (1,1,1) per permutation of the axes.
KUHN = []


for _perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
    _c = [0, 0, 0]
    _path = [tuple(_c)]
    for _ax in _perm:
        _c[_ax] = 1
        _path.append(tuple(_c))
    KUHN.append(_path)


def graded(a: float, b: float, n: int, ratio: float = 1.0, toward: str = "a") -> np.ndarray:
    """``n + 1`` points from ``a`` to ``b``, geometrically graded.

    ``ratio`` is the size of the largest cell over the smallest one; the small
    cells sit at ``toward`` (``"a"``, ``"b"`` or ``"both"`` for a symmetric
    grading with the coarsest cells in the middle).
    """
    if n < 1:
        raise MeshError(f"graded: n = {n} cells is not allowed; need n >= 1")
    if ratio < 1.0:
        raise MeshError(f"graded: ratio = {ratio} is not allowed; need ratio >= 1")
    if toward == "both":
        n1 = n // 2
        mid = 0.5 * (a + b)
        if n1 == 0:
            return np.array([a, b], dtype=float)
        left = graded(a, mid, n1, ratio, "a")
        right = graded(mid, b, n - n1, ratio, "b")
        return np.concatenate([left, right[1:]])
    if toward not in ("a", "b"):
        raise MeshError(f"graded: toward = {toward!r}; allowed: 'a', 'b', 'both'")
    if n == 1 or ratio == 1.0:
        s = np.linspace(0.0, 1.0, n + 1)
    else:
        q = ratio ** (1.0 / (n - 1))
        h = q ** np.arange(n)
        s = np.concatenate([[0.0], np.cumsum(h)]) / h.sum()
    if toward == "b":
        s = 1.0 - s[::-1]
    return a + (b - a) * s


def structured_tets(x: np.ndarray, y: np.ndarray, z: np.ndarray,
                    periodic_y: bool = False, mirror_below: int | None = None
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Kuhn-split tetrahedra on the tensor grid ``x`` x ``y`` x ``z``.

    Returns parametric nodes ``p`` (3, N) and tetrahedra ``t`` (4, 6 * nhex).
    With ``periodic_y`` the last ``y`` layer is the first one again (a closed
    ring): ``y[-1]`` must be ``y[0]`` plus the period and is not a node.
    With ``mirror_below = k`` the hexahedra of the layers below ``z[k]`` are
    split as the mirror image in z of the Kuhn split: on a grid symmetric
    about ``z[k]`` the mesh is then its own mirror image through that plane
    (both splits cut the plane's faces along the same diagonal, so the mesh
    stays conforming).
    """
    x, y, z = (np.asarray(a, dtype=float) for a in (x, y, z))
    nx, ny, nz = len(x), len(y), len(z)
    nyn = ny - 1 if periodic_y else ny
    X, Y, Z = np.meshgrid(x, y[:nyn], z, indexing="ij")
    p = np.vstack([X.ravel(), Y.ravel(), Z.ravel()])
    idx = np.arange(nx * nyn * nz).reshape(nx, nyn, nz)
    if periodic_y:
        idx = np.concatenate([idx, idx[:, :1, :]], axis=1)
    corners = {}
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                corners[(dx, dy, dz)] = idx[dx:nx - 1 + dx, dy:ny - 1 + dy, dz:nz - 1 + dz].ravel()
    t = np.vstack([np.vstack([corners[c] for c in path]) for path in KUHN]).reshape(6, 4, -1)
    if mirror_below is not None:
        below = np.broadcast_to(np.arange(nz - 1) < mirror_below,
                                (nx - 1, ny - 1, nz - 1)).ravel()
        flipped = np.vstack([np.vstack([corners[(dx, dy, 1 - dz)] for dx, dy, dz in path])
                             for path in KUHN]).reshape(6, 4, -1)
        t = np.where(below, flipped, t)
    t = t.transpose(1, 0, 2).reshape(4, -1)
    return p, t


def cylindrical(p: np.ndarray) -> np.ndarray:
    """Map parametric (r, theta, z) to Cartesian (x, y, z)."""
    r, th, z = p
    return np.vstack([r * np.cos(th), r * np.sin(th), z])


def _oriented(p: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Swap two vertices of negatively oriented tetrahedra."""
    a = p[:, t[1]] - p[:, t[0]]
    b = p[:, t[2]] - p[:, t[0]]
    c = p[:, t[3]] - p[:, t[0]]
    det = np.einsum("ij,ij->j", a, np.cross(b, c, axis=0))
    t = t.copy()
    neg = det < 0
    t[[1, 2]] = np.where(neg, t[[2, 1]], t[[1, 2]])
    return t


def mapped_mesh(p_param: np.ndarray, t: np.ndarray,
                mapping: Callable[[np.ndarray], np.ndarray],
                order: int = 1, period: np.ndarray | None = None) -> fem.Mesh:
    """A tetrahedral mesh from parametric nodes mapped to physical space.

    ``order=2`` returns an isoparametric :class:`skfem.MeshTet2` whose edge
    nodes are the map of the parametric edge midpoints.  ``period`` (3,) gives
    the period of each parametric coordinate (0 for none): edges that cross the
    seam of a closed ring are then unwrapped before taking their midpoint.
    """
    x = mapping(p_param)
    t = _oriented(x, t)
    if order == 1:
        return fem.MeshTet(x, t)
    if order != 2:
        raise MeshError(f"mesh order = {order!r} is not supported; allowed: 1, 2")
    m1 = fem.MeshTet(p_param, t, validate=False)
    a, b = p_param[:, m1.edges[0]], p_param[:, m1.edges[1]]
    d = b - a
    if period is not None:
        per = np.asarray(period, dtype=float)[:, None]
        d = np.where(per > 0, d - per * np.round(d / np.where(per > 0, per, 1.0)), d)
    mid = a + 0.5 * d
    doflocs = np.hstack([x, mapping(mid)])
    return fem.MeshTet2(doflocs, t)


def annulus_mesh(ri: float, ro: float, height: float, nr: int, ntheta: int, nz: int = 1,
                 angle: float = 2 * np.pi, theta0: float = 0.0, order: int = 1,
                 r_ratio: float = 1.0) -> fem.Mesh:
    """A ring (or ring sector of ``angle`` radians) ``ri < r < ro``, ``0 < z < height``.

    Facets are named: ``inner``, ``outer``, ``bottom``, ``top`` and, for a
    sector, ``theta0`` and ``theta1`` (the two cut faces).
    """
    if not (0 < ri < ro):
        raise MeshError(f"annulus_mesh: need 0 < ri < ro, got ri={ri}, ro={ro}")
    full = np.isclose(angle, 2 * np.pi)
    r = graded(ri, ro, nr, r_ratio, "a")
    th = theta0 + np.linspace(0.0, angle, ntheta + 1)
    z = np.linspace(0.0, height, nz + 1)
    p, t = structured_tets(r, th, z, periodic_y=full)
    period = np.array([0.0, 2 * np.pi if full else 0.0, 0.0])
    m = mapped_mesh(p, t, cylindrical, order=order, period=period)
    tol = 1e-9 * ro
    # facet centroids of a P1 ring sit inside the circle by the chord sag, so
    # the curved faces are told apart by a quarter of the smallest radial cell
    rtol = 0.25 * np.diff(r).min()
    names = {
        "inner": lambda X: np.abs(np.hypot(X[0], X[1]) - ri) < rtol,
        "outer": lambda X: np.abs(np.hypot(X[0], X[1]) - ro) < rtol,
        "bottom": lambda X: np.abs(X[2]) < tol,
        "top": lambda X: np.abs(X[2] - height) < tol,
    }
    if not full:
        for key, ang in (("theta0", theta0), ("theta1", theta0 + angle)):
            n = np.array([-np.sin(ang), np.cos(ang)])
            names[key] = (lambda X, n=n: np.abs(n[0] * X[0] + n[1] * X[1]) < 1e-6 * ro)
    return _with_boundaries(m, names)
