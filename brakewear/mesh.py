"""Parametric tetrahedral meshes of brake components; meshio in and out.

Every component (rotor ring, pad sector, piston) is a structured block of
hexahedra in *parametric* coordinates -- (r, theta, z) for the ring and the
pad, a mapped square for the piston disc -- split into six tetrahedra each
(Kuhn split: every hexahedron is cut along its main diagonal, so neighbouring
faces always get the same diagonal and the mesh is conforming).  Grading is a
matter of choosing the coordinate arrays.  The parametric block is mapped to
physical space; P2 meshes place their edge nodes with the same map, so curved
surfaces are represented exactly to second order (isoparametric).
"""
from __future__ import annotations

import logging
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Sequence

import numpy as np
import skfem as fem

if TYPE_CHECKING:  # imported for annotations only: geometry sits above mesh
    from .geometry import BrakeGeometry
    from .materials import Material

logger = logging.getLogger(__name__)

__all__ = [
    "facet_indices",
    "graded",
    "structured_tets",
    "mapped_mesh",
    "cylindrical",
    "annulus_mesh",
    "rotor_mesh",
    "pad_mesh",
    "piston_mesh",
    "brake_meshes",
    "component_materials",
    "element_materials",
    "MeshFileError",
    "read_mesh",
    "write_mesh",
]

# The six tetrahedra of the Kuhn split, as corners (dx, dy, dz) of the unit cube:
# one monotone lattice path from (0,0,0) to (1,1,1) per permutation of the axes.
_KUHN = []
for _perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
    _c = [0, 0, 0]
    _path = [tuple(_c)]
    for _ax in _perm:
        _c[_ax] = 1
        _path.append(tuple(_c))
    _KUHN.append(_path)



def facet_indices(mesh: fem.Mesh, facets) -> np.ndarray:
    """Facet indices of a named facet set, or the given indices.

    A name the mesh does not have raises ``KeyError`` listing the names it has.
    """
    if isinstance(facets, str):
        if facets not in (mesh.boundaries or {}):
            raise KeyError(f"mesh has no facets named {facets!r}; named facets: "
                           f"{sorted(mesh.boundaries or {})}")
        facets = mesh.boundaries[facets]
    return np.asarray(facets)

def graded(a: float, b: float, n: int, ratio: float = 1.0, toward: str = "a") -> np.ndarray:
    """``n + 1`` points from ``a`` to ``b``, geometrically graded.

    ``ratio`` is the size of the largest cell over the smallest one; the small
    cells sit at ``toward`` (``"a"``, ``"b"`` or ``"both"`` for a symmetric
    grading with the coarsest cells in the middle).
    """
    if n < 1:
        raise ValueError(f"graded: n = {n} cells is not allowed; need n >= 1")
    if ratio < 1.0:
        raise ValueError(f"graded: ratio = {ratio} is not allowed; need ratio >= 1")
    if toward == "both":
        n1 = n // 2
        mid = 0.5 * (a + b)
        if n1 == 0:
            return np.array([a, b], dtype=float)
        left = graded(a, mid, n1, ratio, "a")
        right = graded(mid, b, n - n1, ratio, "b")
        return np.concatenate([left, right[1:]])
    if toward not in ("a", "b"):
        raise ValueError(f"graded: toward = {toward!r}; allowed: 'a', 'b', 'both'")
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
                    periodic_y: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Kuhn-split tetrahedra on the tensor grid ``x`` x ``y`` x ``z``.

    Returns parametric nodes ``p`` (3, N) and tetrahedra ``t`` (4, 6 * nhex).
    With ``periodic_y`` the last ``y`` layer is the first one again (a closed
    ring): ``y[-1]`` must be ``y[0]`` plus the period and is not a node.
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
    t = np.vstack([np.vstack([corners[c] for c in path]) for path in _KUHN]).reshape(6, 4, -1)
    t = t.transpose(1, 0, 2).reshape(4, -1)
    return p, t


_TOPOLOGY_CACHE = ("_facets", "_t2f", "_f2t", "_edges", "_t2e")


def _ensure_topology(mesh: fem.Mesh) -> fem.Mesh:
    """Fill skfem's cached ``facets``, ``t2f`` and ``f2t`` of a tetrahedral mesh.

    Gives exactly what skfem computes lazily (facets as sorted vertex
    triples in lexicographic order, ``t2f`` per local facet, ``f2t`` with -1
    outside), but sorts one int64 key per facet instead of running
    ``np.unique(axis=1)`` over vertex triples, several times faster on a big
    mesh.  Returns ``mesh`` (modified in place); leaves it alone if the
    caches exist or the key would overflow.
    """
    if hasattr(mesh, "_facets") and hasattr(mesh, "_f2t"):
        return mesh
    t = mesh.t
    n = int(t.max()) + 1
    if not isinstance(mesh, (fem.MeshTet1, fem.MeshTet2)) or float(n) ** 3 >= 2.0 ** 62:
        return mesh
    ne = t.shape[1]
    fidx = mesh.elem.refdom.facets
    f = np.sort(np.hstack([t[ix] for ix in fidx]), axis=0)
    key = (f[0].astype(np.int64) * n + f[1]) * n + f[2]
    order = np.argsort(key)
    ks = key[order]
    new = np.empty(ks.size, dtype=bool)
    new[0] = True
    np.not_equal(ks[1:], ks[:-1], out=new[1:])
    del ks
    starts = np.flatnonzero(new)
    # first and last occurrence (in skfem's local-facet-major order) of each facet
    first = np.minimum.reduceat(order, starts)
    last = np.maximum.reduceat(order, starts)
    inv = np.empty(key.size, dtype=np.intp)
    inv[order] = np.cumsum(new) - 1
    del order, new, key
    f2t = np.empty((2, starts.size), dtype=np.int32)
    f2t[0] = first % ne
    f2t[1] = np.where(first == last, -1, last % ne)
    mesh._facets = np.ascontiguousarray(f[:, first])
    mesh._t2f = inv.reshape(len(fidx), ne)
    mesh._f2t = f2t
    return mesh


def _keep_topology(new: fem.Mesh, old: fem.Mesh) -> fem.Mesh:
    """Carry skfem's cached topology over to a copy with the same ``t`` (the
    copies made by ``with_boundaries``/``with_subdomains`` start empty)."""
    if new.t is old.t or np.array_equal(new.t, old.t):
        for name in _TOPOLOGY_CACHE:
            if hasattr(old, name) and not hasattr(new, name):
                setattr(new, name, getattr(old, name))
    return new


def _with_boundaries(mesh: fem.Mesh, boundaries: dict) -> fem.Mesh:
    """``mesh.with_boundaries(boundaries)`` (boundary facets only), faster.

    The topology is built by the fast route and kept by the copy; the
    midpoints of the boundary facets are computed once for all tests instead
    of those of every facet once per test.  Same facet sets as skfem's.
    """
    _ensure_topology(mesh)
    sets = {}
    if any(callable(v) for v in boundaries.values()):
        bf = np.nonzero(mesh.f2t[1] == -1)[0].astype(np.int32)
        midp = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
        for name, test in boundaries.items():
            if callable(test):
                sets[name] = bf[np.asarray(test(midp), dtype=bool)]
    sets = {name: sets.get(name, test) for name, test in boundaries.items()}
    return _keep_topology(mesh.with_boundaries(sets), mesh)


def _with_subdomains(mesh: fem.Mesh, subdomains: dict) -> fem.Mesh:
    """``mesh.with_subdomains``; the copy keeps the cached topology."""
    return _keep_topology(mesh.with_subdomains(subdomains), mesh)


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
        raise ValueError(f"mesh order = {order!r} is not supported; allowed: 1, 2")
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
        raise ValueError(f"annulus_mesh: need 0 < ri < ro, got ri={ri}, ro={ro}")
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


# ----------------------------------------------------------------------------
# the parametric brake: rotor ring, pad sector, piston

def _n_cells(length: float, h_min: float, ratio: float) -> int:
    """Fewest cells whose geometric grading (``ratio``) has its smallest cell <= h_min."""
    n = 1
    while n < 100_000:
        x = graded(0.0, length, n, ratio, "a")
        if x[1] - x[0] <= 1.05 * h_min:
            return n
        n += 1
    raise ValueError(f"cannot grade {length} with smallest cell {h_min}")  # pragma: no cover


def _two_sided(length: float, h_end: float, h_mid: float, growth: float = 1.3) -> np.ndarray:
    """Cell boundaries on [0, length]: ``h_end`` at both ends growing by ``growth``
    per cell up to ``h_mid`` in the middle (a coarse gap between two fine zones)."""
    if h_mid <= h_end:
        n = max(1, int(np.ceil(length / h_end)))
        return np.linspace(0.0, length, n + 1)
    ramp = [h_end * growth]
    while ramp[-1] * growth < h_mid:
        ramp.append(ramp[-1] * growth)
    ramp = np.array(ramp)
    middle = length - 2.0 * ramp.sum()
    if middle < h_mid:
        # too short for full ramps: a symmetric grading with the same end cell
        n = max(2, int(np.ceil(length / (0.5 * (h_end + h_mid)))))
        return graded(0.0, length, n, h_mid / h_end if n > 2 else 1.0, "both")
    n_mid = max(1, int(round(middle / h_mid)))
    cells = np.concatenate([ramp, np.full(n_mid, middle / n_mid), ramp[::-1]])
    x = np.concatenate([[0.0], np.cumsum(cells)])
    x[-1] = length
    return x


def _check_size_order(size: float, order: int) -> tuple[float, int]:
    size = float(size)
    if not np.isfinite(size) or size <= 0.0:
        raise ValueError(f"mesh size = {size!r} is not allowed; it must be a finite number > 0 (m)")
    if isinstance(order, bool) or order not in (1, 2):
        raise ValueError(f"mesh order = {order!r} is not allowed; allowed: 1, 2")
    return size, int(order)


def rotor_mesh(geom: BrakeGeometry, size: float | None = None, order: int | None = None) -> fem.Mesh:
    """The inboard half of the rotor friction ring, a closed (periodic) ring.

    ``z`` runs from ``-thickness/2`` (midplane) to ``0`` (friction face).  In
    theta the elements have the in-plane ``size`` (at the pad mid radius) over
    the pad arc plus ``geom.mesh.rotor_margin`` on both sides and grow to
    ``rotor_coarse_factor * size`` elsewhere; through the thickness they are
    ``size / 2`` thick at ``z = 0`` and grow by ``rotor_z_ratio``.

    Parameters
    ----------
    geom : BrakeGeometry
        The checked brake geometry (SI units).
    size, order
        Override ``geom.mesh.size`` (m) and ``geom.mesh.order``.

    Returns
    -------
    skfem.MeshTet or skfem.MeshTet2
        Facets ``friction`` (z = 0), ``midplane`` (z = -t/2), ``rotor_clamp``
        (inner radius) and ``outer``; subdomain ``rotor`` (all elements).
    """
    ms, ro_, pad = geom.mesh, geom.rotor, geom.pad
    h, order = _check_size_order(ms.size if size is None else size,
                                 ms.order if order is None else order)
    ri, ro, half = ro_.inner_radius, ro_.outer_radius, 0.5 * ro_.thickness
    r_ref = 0.5 * (pad.inner_radius + pad.outer_radius)
    r = np.linspace(ri, ro, max(2, int(np.ceil((ro - ri) / h))) + 1)
    # theta: fine over the pad arc (+ margin), a graded coarse gap elsewhere
    span = pad.arc_angle + 2.0 * ms.rotor_margin
    th0 = pad.center_angle - 0.5 * span
    n_fine = max(2, int(np.ceil(span * r_ref / h)))
    fine = np.linspace(0.0, span, n_fine + 1)
    dth = span / n_fine
    gap = _two_sided(2 * np.pi - span, dth, ms.rotor_coarse_factor * dth)
    th = th0 + np.concatenate([fine, span + gap[1:]])
    th[-1] = th0 + 2 * np.pi
    nz = _n_cells(half, 0.5 * h, ms.rotor_z_ratio)
    z = graded(-half, 0.0, nz, ms.rotor_z_ratio if nz > 1 else 1.0, "b")
    p, t = structured_tets(r, th, z, periodic_y=True)
    m = mapped_mesh(p, t, cylindrical, order=order, period=np.array([0.0, 2 * np.pi, 0.0]))
    tol = 1e-9 * ro
    rmid = 0.5 * (ri + ro)

    def side(X):
        return (np.abs(X[2]) > tol) & (np.abs(X[2] + half) > tol)

    m = _with_boundaries(m, {
        "friction": lambda X: np.abs(X[2]) < tol,
        "midplane": lambda X: np.abs(X[2] + half) < tol,
        "rotor_clamp": lambda X: side(X) & (np.hypot(X[0], X[1]) < rmid),
        "outer": lambda X: side(X) & (np.hypot(X[0], X[1]) > rmid),
    })
    m = _with_subdomains(m, {"rotor": np.arange(m.t.shape[1])})
    logger.debug("rotor mesh: %d nodes, %d elements (order %d)", m.p.shape[1], m.t.shape[1], order)
    return m


def pad_mesh(geom: BrakeGeometry, size: float | None = None, order: int | None = None) -> fem.Mesh:
    """The pad: an annular sector, friction layer on ``0 < z < friction_thickness``,
    backplate above it up to ``z = friction_thickness + backplate_thickness``.

    The rotor turns in +theta, so a rotor point enters under the pad at the
    smaller angle: ``leading`` is the end face at ``center - arc/2`` and
    ``trailing`` the one at ``center + arc/2``.

    Parameters
    ----------
    geom : BrakeGeometry
        The checked brake geometry (SI units).
    size, order
        Override ``geom.mesh.size`` (m) and ``geom.mesh.order``.

    Returns
    -------
    skfem.MeshTet or skfem.MeshTet2
        Subdomains ``friction_layer`` and ``backplate``; facets ``friction``
        (z = 0), ``back`` (top face), ``piston_face`` (back facets whose
        centroid lies inside the piston footprint), ``leading``, ``trailing``
        (whole end faces), ``abutment`` (both end faces, backplate part only),
        ``inner`` and ``outer`` (curved faces).
    """
    ms, pad, pis = geom.mesh, geom.pad, geom.piston
    h, order = _check_size_order(ms.size if size is None else size,
                                 ms.order if order is None else order)
    ri, ro, tf, tb = pad.inner_radius, pad.outer_radius, pad.friction_thickness, pad.backplate_thickness
    r_ref = 0.5 * (ri + ro)
    r = np.linspace(ri, ro, max(2, int(np.ceil((ro - ri) / h))) + 1)
    th = np.linspace(pad.leading_angle, pad.trailing_angle,
                     max(2, int(np.ceil(pad.arc_angle * r_ref / h))) + 1)
    nzf = _n_cells(tf, 0.5 * h, ms.pad_z_ratio)
    zf = graded(0.0, tf, nzf, ms.pad_z_ratio if nzf > 1 else 1.0, "a")
    zb = np.linspace(tf, tf + tb, max(1, int(np.ceil(tb / h))) + 1)
    z = np.concatenate([zf, zb[1:]])
    p, t = structured_tets(r, th, z)
    m = mapped_mesh(p, t, cylindrical, order=order)
    top = tf + tb
    tol = 1e-9 * ro
    xc, yc = geom.piston_center
    a = 0.5 * pis.diameter
    rmid = 0.5 * (ri + ro)

    def plane(ang):
        n = np.array([-np.sin(ang), np.cos(ang)])
        return lambda X: np.abs(n[0] * X[0] + n[1] * X[1]) < tol

    lead, trail = plane(pad.leading_angle), plane(pad.trailing_angle)

    def flat(X):
        return (np.abs(X[2]) < tol) | (np.abs(X[2] - top) < tol) | lead(X) | trail(X)

    m = _with_boundaries(m, {
        "friction": lambda X: np.abs(X[2]) < tol,
        "back": lambda X: np.abs(X[2] - top) < tol,
        "piston_face": lambda X: (np.abs(X[2] - top) < tol) & (np.hypot(X[0] - xc, X[1] - yc) < a),
        "leading": lead,
        "trailing": trail,
        "abutment": lambda X: (lead(X) | trail(X)) & (X[2] > tf),
        "inner": lambda X: ~flat(X) & (np.hypot(X[0], X[1]) < rmid),
        "outer": lambda X: ~flat(X) & (np.hypot(X[0], X[1]) > rmid),
    })
    m = _with_subdomains(m, {
        "friction_layer": lambda X: X[2] < tf,
        "backplate": lambda X: X[2] > tf,
    })
    logger.debug("pad mesh: %d nodes, %d elements (order %d)", m.p.shape[1], m.t.shape[1], order)
    return m


def _disc_triangles(R: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """A triangulated disc of radius ``R``: concentric rings of nodes about
    ``h`` apart (alternate rings turned by half a step), Delaunay-connected."""
    from scipy.spatial import Delaunay

    nr = max(2, int(np.ceil(R / h)))
    pts = [np.zeros((2, 1))]
    for k, rk in enumerate(np.linspace(0.0, R, nr + 1)[1:], start=1):
        n = max(6, int(round(2 * np.pi * rk / h)))
        ang = (np.arange(n) + 0.5 * (k % 2)) * 2 * np.pi / n
        pts.append(rk * np.vstack([np.cos(ang), np.sin(ang)]))
    p = np.hstack(pts)
    tri = Delaunay(p.T).simplices.T
    return p, tri


def _extrude(p2: np.ndarray, tri: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Extrude triangles through the layers ``z`` into prisms of three tetrahedra.

    Each prism is split by the global vertex order (every quadrilateral side
    gets the diagonal from its lower-numbered bottom vertex to its
    higher-numbered top vertex), so neighbouring prisms always agree.
    """
    n2 = p2.shape[1]
    nz = len(z)
    p = np.vstack([np.tile(p2, nz), np.repeat(z, n2)])
    v = np.sort(tri, axis=0)
    tets = []
    for k in range(nz - 1):
        b0, b1, b2 = v + k * n2
        t0, t1, t2 = v + (k + 1) * n2
        tets += [np.vstack([b0, b1, b2, t2]), np.vstack([b0, b1, t1, t2]),
                 np.vstack([b0, t0, t1, t2])]
    return p, np.hstack(tets)


def piston_mesh(geom: BrakeGeometry, size: float | None = None, order: int | None = None) -> fem.Mesh:
    """The piston: a solid cylinder standing on the back of the pad.

    Concentric-ring triangulation of the footprint disc, extruded in z from
    the back of the pad (``z = friction_thickness + backplate_thickness``)
    over ``piston.length``.  For ``order=2`` the edge nodes on the cylinder
    wall are moved onto the circle.

    Returns
    -------
    skfem.MeshTet or skfem.MeshTet2
        Facets ``piston_face`` (bottom, on the backplate), ``piston_back``
        (top, hydraulic side) and ``piston_side``; subdomain ``piston``.
    """
    ms, pis = geom.mesh, geom.piston
    h, order = _check_size_order(ms.size if size is None else size,
                                 ms.order if order is None else order)
    R = 0.5 * pis.diameter
    z0 = geom.pad.thickness
    z1 = z0 + pis.length
    xc, yc = geom.piston_center
    p2, tri = _disc_triangles(R, h)
    z = np.linspace(z0, z1, max(2, int(np.ceil(pis.length / (1.5 * h)))) + 1)
    p, t = _extrude(p2, tri, z)
    on_wall = np.abs(np.hypot(p[0], p[1]) - R) < 1e-9 * R
    p = p + np.array([[xc], [yc], [0.0]])
    t = _oriented(p, t)
    if order == 1:
        m = fem.MeshTet(p, t)
    else:
        m1 = fem.MeshTet(p, t)
        e0, e1 = m1.edges
        mid = 0.5 * (p[:, e0] + p[:, e1])
        wall = on_wall[e0] & on_wall[e1]
        d = mid[:2, wall] - np.array([[xc], [yc]])
        mid[:2, wall] = np.array([[xc], [yc]]) + R * d / np.hypot(d[0], d[1])
        m = fem.MeshTet2(np.hstack([p, mid]), t)
    tol = 1e-9 * z1
    m = _with_boundaries(m, {
        "piston_face": lambda X: np.abs(X[2] - z0) < tol,
        "piston_back": lambda X: np.abs(X[2] - z1) < tol,
        "piston_side": lambda X: (np.abs(X[2] - z0) > tol) & (np.abs(X[2] - z1) > tol),
    })
    m = _with_subdomains(m, {"piston": np.arange(m.t.shape[1])})
    logger.debug("piston mesh: %d nodes, %d elements (order %d)", m.p.shape[1], m.t.shape[1], order)
    return m


def brake_meshes(geom: BrakeGeometry, size: float | None = None, order: int | None = None) -> dict[str, fem.Mesh]:
    """Meshes of the three bodies of a brake geometry.

    The bodies are separate meshes that do not match at their interfaces;
    contact and ties are made by projection elsewhere.  Coordinates: rotor
    axis = z, friction interface at z = 0, rotor below (z < 0), pad and
    piston above; the pad is centred on ``pad.center_angle``.

    Parameters
    ----------
    geom : BrakeGeometry
        A checked geometry (see :func:`brakewear.geometry.load_geometry`).
    size : float, optional
        In-plane element size at the friction interface (m); default
        ``geom.mesh.size``.
    order : int, optional
        1 (P1 ``MeshTet``) or 2 (isoparametric ``MeshTet2``); default
        ``geom.mesh.order``.

    Returns
    -------
    dict of str to skfem.Mesh
        Keys ``"rotor"``, ``"pad"``, ``"piston"``; see :func:`rotor_mesh`,
        :func:`pad_mesh`, :func:`piston_mesh` for the named facets and
        subdomains.
    """
    out = {"rotor": rotor_mesh(geom, size, order), "pad": pad_mesh(geom, size, order),
           "piston": piston_mesh(geom, size, order)}
    logger.info("brake meshes: %s", ", ".join(
        f"{k} {m.p.shape[1]} nodes / {m.t.shape[1]} tets" for k, m in out.items()))
    return out


def component_materials(geom: BrakeGeometry) -> dict[str, dict[str, Material]]:
    """Material of every subdomain of every mesh of :func:`brake_meshes`.

    Returns
    -------
    dict
        ``{"rotor": {"rotor": ...}, "pad": {"friction_layer": ...,
        "backplate": ...}, "piston": {"piston": ...}}``.
    """
    return {
        "rotor": {"rotor": geom.rotor.material},
        "pad": {"friction_layer": geom.pad.friction_material,
                "backplate": geom.pad.backplate_material},
        "piston": {"piston": geom.piston.material},
    }


def element_materials(mesh: fem.Mesh, mapping: dict) -> list[tuple[np.ndarray, Material]]:
    """Pair the subdomains of ``mesh`` with materials.

    Parameters
    ----------
    mesh : skfem.Mesh
        A mesh with the subdomains named in ``mapping``.
    mapping : dict of str to Material
        Subdomain name -> material (one entry of :func:`component_materials`).

    Returns
    -------
    list of (ndarray, Material)
        Element indices and their material, one pair per subdomain.

    Raises
    ------
    ValueError
        A subdomain is missing from the mesh, or the subdomains do not cover
        every element exactly once.
    """
    subs = mesh.subdomains or {}
    missing = [k for k in mapping if k not in subs]
    if missing:
        raise ValueError(f"element_materials: mesh has no subdomain {missing[0]!r}; "
                         f"its subdomains: {sorted(subs) or 'none'}")
    out = [(np.asarray(subs[k], dtype=np.int64), mat) for k, mat in mapping.items()]
    count = np.zeros(mesh.t.shape[1], dtype=np.int64)
    for idx, _ in out:
        np.add.at(count, idx, 1)
    if (count != 1).any():
        raise ValueError(
            f"element_materials: subdomains {sorted(mapping)} leave {(count == 0).sum()} "
            f"elements without a material and give {(count > 1).sum()} elements two or more")
    return out


# ----------------------------------------------------------------------------
# meshio in and out

class MeshFileError(ValueError):
    """A mesh file that cannot be used (no tetrahedra, missing tags, ...)."""


def _facet_index(mesh: fem.Mesh, tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Facet numbers of the triangles ``tri`` (3, n); -1 where none matches."""
    nv = mesh.p.shape[1]
    key_f = np.sort(mesh.facets, axis=0).astype(np.int64)
    key_f = (key_f[0] * nv + key_f[1]) * nv + key_f[2]
    order = np.argsort(key_f)
    key_t = np.sort(tri, axis=0).astype(np.int64)
    key_t = (key_t[0] * nv + key_t[1]) * nv + key_t[2]
    pos = np.clip(np.searchsorted(key_f[order], key_t), 0, len(order) - 1)
    hit = key_f[order][pos] == key_t
    return np.where(hit, order[pos], -1), hit


def read_mesh(path: str | PathLike, required: Sequence[str] | None = None) -> fem.Mesh:
    """Read a user's tetrahedral mesh with tagged surfaces (any meshio format).

    Named boundaries come from: triangle cell sets (e.g.
    ``meshio.Mesh(cell_sets={"friction": [...]})``); integer triangle tags
    ``gmsh:physical`` (named through ``field_data``, i.e. gmsh physical
    names, otherwise ``"gmsh:physical=<tag>"``); any other integer triangle
    cell data (a key with a single non-negative tag -- which is how meshio
    stores cell sets in VTU -- gives the key's name, otherwise
    ``"<key>=<tag>"``; negative tags mean untagged); and the skfem tag
    encoding written by :func:`write_mesh`.  Tetrahedron tags become
    subdomains the same way.
    Second-order tetrahedra (``tetra10``) are read as their corner vertices.

    Parameters
    ----------
    path
        Mesh file (``.msh``, ``.vtu``, ``.xdmf``, ``.med``, ...).
    required
        Boundary names that must be present; their absence raises with the
        list of the tags found.

    Returns
    -------
    skfem.MeshTet

    Raises
    ------
    MeshFileError
        No tetrahedra, or a required tag is missing.
    """
    import meshio

    try:
        mio = meshio.read(path)
    except Exception as exc:  # meshio raises many types
        raise MeshFileError(f"{path}: cannot read mesh: {exc}") from None
    blocks = [(i, c) for i, c in enumerate(mio.cells) if c.type in ("tetra", "tetra10")]
    if not blocks:
        raise MeshFileError(f"{path}: no tetrahedra in the file; cell types found: "
                            f"{sorted({c.type for c in mio.cells}) or 'none'}")
    t_all = np.vstack([c.data[:, :4] for _, c in blocks]).T
    used = np.unique(t_all)
    renum = -np.ones(len(mio.points), dtype=np.int64)
    renum[used] = np.arange(len(used))
    p = np.ascontiguousarray(mio.points[used, :3].T, dtype=float)
    if p.shape[0] != 3:
        raise MeshFileError(f"{path}: points have {p.shape[0]} coordinates; need 3")
    t = _oriented(p, renum[t_all])
    mesh = _ensure_topology(fem.MeshTet(p, t))
    names = {}
    for key, vals in (mio.field_data or {}).items():
        arr = np.atleast_1d(vals)
        if len(arr) >= 2:
            names[(int(arr[1]), int(arr[0]))] = key  # (dim, tag) -> name

    bnd: dict[str, list] = {}
    sub: dict[str, list] = {}
    tet_offset = np.cumsum([0] + [len(c.data) for _, c in blocks])
    for name, sets in (mio.cell_sets or {}).items():
        if name.startswith("gmsh:"):
            continue
        for i, c in enumerate(mio.cells):
            if i >= len(sets) or sets[i] is None or len(sets[i]) == 0:
                continue
            idx = np.asarray(sets[i], dtype=np.int64)
            if c.type == "triangle":
                bnd.setdefault(name, []).append(renum[c.data[idx].T])
            elif c.type in ("tetra", "tetra10"):
                j = [b for b, _ in blocks].index(i)
                sub.setdefault(name, []).append(tet_offset[j] + idx)
    for key, data in (mio.cell_data or {}).items():
        if key.startswith("skfem:") or (key.startswith("gmsh:") and key != "gmsh:physical"):
            continue
        # integer tags of triangles (dim 2) and tetrahedra (dim 3); negative = untagged
        found: dict[int, list] = {2: [], 3: []}
        for i, c in enumerate(mio.cells):
            arr = np.asarray(data[i])
            dim = 2 if c.type == "triangle" else 3 if c.type in ("tetra", "tetra10") else 0
            if dim and arr.ndim == 1 and np.issubdtype(arr.dtype, np.integer):
                found[dim].append((i, c, arr))
        for dim, items in found.items():
            tags = np.unique(np.concatenate([a[a >= 0] for _, _, a in items] or [[]]))
            for tag in tags.astype(np.int64):
                # a named physical group; a lone tag (meshio's conversion of a
                # cell set to cell data) takes the key's name; else "key=tag"
                nm = names.get((dim, int(tag)),
                               key if len(tags) == 1 and key != "gmsh:physical" else f"{key}={tag}")
                for i, c, arr in items:
                    sel = np.nonzero(arr == tag)[0]
                    if sel.size == 0:
                        continue
                    if dim == 2:
                        bnd.setdefault(nm, []).append(renum[c.data[sel].T])
                    else:
                        j = [b for b, _ in blocks].index(i)
                        sub.setdefault(nm, []).append(tet_offset[j] + sel)
    boundaries = {}
    for nm, parts in bnd.items():
        tri = np.hstack(parts)
        if (tri < 0).any():
            raise MeshFileError(f"{path}: surface tag {nm!r} uses nodes of no tetrahedron")
        f, hit = _facet_index(mesh, tri)
        if not hit.all():
            raise MeshFileError(f"{path}: surface tag {nm!r}: {(~hit).sum()} of {hit.size} "
                                "triangles are not faces of the tetrahedra")
        boundaries[nm] = np.unique(f)
    subdomains = {nm: np.unique(np.concatenate(parts)) for nm, parts in sub.items()}
    enc_b, enc_s = mesh._decode_cell_data(
        {k: v[:1] for k, v in (mio.cell_data or {}).items() if k.startswith("skfem:")}
        if len(blocks) == 1 and blocks[0][0] == 0 else {})
    boundaries.update({k: np.asarray(v, dtype=np.int64) for k, v in enc_b.items()})
    subdomains.update(enc_s)
    if boundaries:
        mesh = _with_boundaries(mesh, boundaries)
    if subdomains:
        mesh = _with_subdomains(mesh, subdomains)
    if required:
        miss = [nm for nm in required if nm not in boundaries]
        if miss:
            raise MeshFileError(
                f"{path}: required surface tag(s) {miss} not found; tags found: "
                f"surfaces {sorted(boundaries) or 'none'}, volumes {sorted(subdomains) or 'none'}")
    logger.info("read %s: %d nodes, %d tets, surfaces %s", path, p.shape[1], t.shape[1],
                sorted(boundaries))
    return mesh


def write_mesh(path: str | PathLike, mesh: fem.Mesh, point_data: dict | None = None,
               cell_data: dict | None = None) -> Path:
    """Write a tetrahedral mesh and fields with meshio (VTU unless the suffix says otherwise).

    Named boundaries and subdomains are stored with the skfem tag encoding
    (one integer per tetrahedron), which :func:`read_mesh` decodes.  A
    ``MeshTet2`` is written as its P1 vertices and cells; point data given at
    all P2 nodes is cut to the vertex values.

    Parameters
    ----------
    path
        Output file; without a suffix ``.vtu`` is appended.
    mesh : skfem.MeshTet or skfem.MeshTet2
    point_data : dict of str to ndarray, optional
        Nodal fields, shape (nvertices,) or (nvertices, k) (P2 node arrays are cut).
    cell_data : dict of str to ndarray, optional
        One value (or row) per element.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    import meshio

    path = Path(path)
    if path.suffix == "":
        path = path.with_suffix(".vtu")
    nv = mesh.t.max() + 1
    p = mesh.p[:, :nv]
    pdata = {}
    for k, v in (point_data or {}).items():
        v = np.asarray(v)
        if v.shape[0] < nv:
            raise ValueError(f"write_mesh: point_data[{k!r}] has {v.shape[0]} values; "
                             f"need {nv} (one per vertex)")
        pdata[k] = v[:nv]
    cdata = {}
    for k, v in (cell_data or {}).items():
        v = np.asarray(v)
        if v.shape[0] != mesh.t.shape[1]:
            raise ValueError(f"write_mesh: cell_data[{k!r}] has {v.shape[0]} values; "
                             f"need {mesh.t.shape[1]} (one per element)")
        cdata[k] = [v]
    m1 = fem.MeshTet(p, mesh.t, mesh._boundaries, mesh._subdomains, validate=False)
    cdata.update(m1._encode_cell_data())
    meshio.write(path, meshio.Mesh(p.T, [("tetra", mesh.t.T)], point_data=pdata,
                                   cell_data=cdata))
    logger.info("wrote %s (%d nodes, %d tets)", path, nv, mesh.t.shape[1])
    return path
