"""The rotor as a brake engineer draws it: friction ring, mounting hat, vented cheeks.

The section of a hat rotor is a union of rectangles in (r, z), turned about
the axis: the friction ring (``inner_radius < r < outer_radius``,
``-t < z < 0``), the cylindrical hat wall on the outboard side (``z < -t``)
and the flange at its end, whose mounting face is clamped by the hub out to
the bolt circle.  Where the wall does not reach under the ring (a wall whose
outer surface is the ring's inner radius), the ring is continued inward over
the top of the wall: that neck is what joins them.

The mesh is one structured (r, theta, z) grid holding every break of the
section (radii and heights of all blocks); its hexahedral cells outside the
union are dropped and the rest split into six tetrahedra each (the Kuhn split
of :mod:`brakewear.mesh.structured`), so the blocks share their nodes and the
mesh is conforming by construction.  A vented ring drops the channel cells
between straight radial vanes of constant width: the theta grid carries the
vane edges (the ring's fine grid over the pad arc is refined to hit them),
and the map to physical space bends each radial grid line so that the vane
walls are planes (:func:`vane_warp`).  P2 edge nodes are placed with the same
map, so the curved surfaces are represented to second order.
"""
from __future__ import annotations

import logging
from typing import TYPE_CHECKING

import numpy as np
import skfem as fem

from ..errors import GeometryError, MeshError
from .grids import _body_size, _check_size_order, _n_cells, _ring_theta
from .structured import graded, mapped_mesh, structured_tets
from .topology import _with_boundaries, _with_subdomains, ensure_topology

if TYPE_CHECKING:  # imported for annotations only: geometry sits above mesh
    from ..geometry import BrakeGeometry

logger = logging.getLogger(__name__)

__all__ = ["full_rotor_mesh", "rotor_volume", "vane_edges", "vane_warp"]


def _mm(x: float) -> str:
    return f"{1e3 * x:.6g} mm"


def _check_hat(geom: BrakeGeometry) -> None:
    """Refuse a hat that does not make one connected rotor, naming the field."""
    ro_, hat = geom.rotor, geom.rotor.hat
    if hat is None:
        raise GeometryError("rotor.hat is missing: rotor.mount = 'hat' needs a [rotor.hat] table "
                            "(height, wall_radius, wall_thickness, flange_thickness, bore_radius, "
                            "bolt_circle_radius)")
    for k in ("height", "wall_radius", "wall_thickness", "flange_thickness", "bore_radius",
              "bolt_circle_radius"):
        v = getattr(hat, k)
        if not np.isfinite(v) or v <= 0.0:
            raise GeometryError(f"rotor.hat.{k} = {_mm(v)} is not allowed; it must be > 0")
    wi, wo = hat.wall_radius - 0.5 * hat.wall_thickness, hat.wall_radius + 0.5 * hat.wall_thickness
    if not ro_.inner_radius <= wo < ro_.outer_radius:
        raise GeometryError(
            f"rotor.hat.wall_radius = {_mm(hat.wall_radius)} with wall_thickness = "
            f"{_mm(hat.wall_thickness)} puts the wall's outer surface at {_mm(wo)}: the hat does "
            f"not meet the ring; allowed: {_mm(ro_.inner_radius)} <= wall_radius + "
            f"wall_thickness/2 < {_mm(ro_.outer_radius)} (rotor inner and outer radius)")
    if not 0.0 < hat.bore_radius < wi:
        raise GeometryError(f"rotor.hat.bore_radius = {_mm(hat.bore_radius)} is not allowed; it "
                            f"must lie inside the wall's inner surface, < {_mm(wi)}")
    if not hat.bore_radius < hat.bolt_circle_radius <= wo:
        raise GeometryError(f"rotor.hat.bolt_circle_radius = {_mm(hat.bolt_circle_radius)} is not "
                            f"allowed; allowed: {_mm(hat.bore_radius)} (bore) < bolt_circle_radius "
                            f"<= {_mm(wo)} (wall outer surface)")
    if not hat.flange_thickness < hat.height:
        raise GeometryError(f"rotor.hat.flange_thickness = {_mm(hat.flange_thickness)} is not "
                            f"allowed; it must be less than rotor.hat.height = {_mm(hat.height)}")


def _check_vents(geom: BrakeGeometry) -> None:
    ro_, v = geom.rotor, geom.rotor.vents
    if not 0.0 < v.cheek_thickness < 0.5 * ro_.thickness:
        raise GeometryError(f"rotor.vents.cheek_thickness = {_mm(v.cheek_thickness)} is not "
                            f"allowed; allowed: 0 < cheek_thickness < thickness / 2 = "
                            f"{_mm(0.5 * ro_.thickness)}")
    if isinstance(v.vane_count, bool) or int(v.vane_count) != v.vane_count or v.vane_count < 1:
        raise GeometryError(f"rotor.vents.vane_count = {v.vane_count!r} is not allowed; it must be "
                            "a whole number >= 1")
    w_max = 2.0 * ro_.inner_radius * np.sin(np.pi / v.vane_count)
    if not 0.0 < v.vane_width < w_max:
        raise GeometryError(f"rotor.vents.vane_width = {_mm(v.vane_width)} is not allowed; "
                            f"{v.vane_count} vanes must leave channels at the inner radius: "
                            f"0 < vane_width < {_mm(w_max)}")


def _section(geom: BrakeGeometry) -> dict:
    """The section's breaks: radii and heights of the ring, neck, wall and flange."""
    ro_, hat, vents = geom.rotor, geom.rotor.hat, geom.rotor.vents
    t = ro_.thickness
    s = {"ri": ro_.inner_radius, "ro": ro_.outer_radius, "t": t, "hat": ro_.mount == "hat",
         "c": vents.cheek_thickness if vents is not None else None}
    s["r_lo"] = s["ri"]
    if s["hat"]:
        wi = hat.wall_radius - 0.5 * hat.wall_thickness
        wo = hat.wall_radius + 0.5 * hat.wall_thickness
        s.update(wi=wi, wo=wo, bore=hat.bore_radius, bolt=hat.bolt_circle_radius,
                 zb=-t - hat.height, zf=-t - hat.height + hat.flange_thickness,
                 r_lo=min(s["ri"], wi))
    # the neck over the wall: whole thickness of a solid ring, the outboard cheek of a vented one
    s["z_neck"] = -t + s["c"] if vents is not None else 0.0
    return s


def vane_edges(geom: BrakeGeometry) -> tuple[np.ndarray, float]:
    """Parametric vane centres (rad) and half-angle ``b`` of a vented ring.

    Vane ``k`` is centred on ``pad.center_angle + (k + 1/2) 2 pi / N``; in
    parameter space it spans ``theta_k -+ b`` with ``b = asin(w / (2 r_m))``
    at the ring's mid radius ``r_m``; :func:`vane_warp` maps it onto the
    slab of constant width ``w``.
    """
    v, ro_ = geom.rotor.vents, geom.rotor
    n = int(v.vane_count)
    centres = geom.pad.center_angle + (np.arange(n) + 0.5) * 2.0 * np.pi / n
    r_m = 0.5 * (ro_.inner_radius + ro_.outer_radius)
    return centres, float(np.arcsin(0.5 * v.vane_width / r_m))


def vane_warp(geom: BrakeGeometry):
    """The map (r, theta, z) -> (x, y, z) of a vented ring: the cylindrical map
    after a shift of theta that turns the vane edges ``theta_k -+ b`` into
    ``theta_k -+ asin(w / 2r)`` (straight walls at distance ``w/2`` from the
    vane's radial centre line), linear in theta between edges and monotone as
    long as the vanes do not overlap.  Radii below the ring's inner radius
    take the shift of the inner radius: the map keeps every radius, so the
    hat's surfaces of revolution are unchanged."""
    centres, b = vane_edges(geom)
    ro_, w = geom.rotor, geom.rotor.vents.vane_width
    knots = np.ravel(np.column_stack([centres - b, centres + b]))
    signs = np.tile([-1.0, 1.0], centres.size)
    order = np.argsort(np.mod(knots, 2 * np.pi))
    knots, signs = np.mod(knots, 2 * np.pi)[order], signs[order]

    def mapping(p: np.ndarray) -> np.ndarray:
        r, th, z = p
        a = np.arcsin(0.5 * w / np.clip(r, ro_.inner_radius, ro_.outer_radius))
        ph = th + np.interp(th, knots, signs, period=2 * np.pi) * (a - b)
        return np.vstack([r * np.cos(ph), r * np.sin(ph), z])

    return mapping


def _in_vane(geom: BrakeGeometry, th: np.ndarray) -> np.ndarray:
    centres, b = vane_edges(geom)
    pitch = 2.0 * np.pi / centres.size
    d = np.mod(th - centres[0] + 0.5 * pitch, pitch) - 0.5 * pitch
    return np.abs(d) < b


def _theta(geom: BrakeGeometry, h: float) -> np.ndarray:
    """The ring's theta grid; with vents, every vane edge is a node and grid
    nodes closer than a third of their cell to an edge give way to it."""
    th = _ring_theta(geom, h)
    if geom.rotor.vents is None:
        return th
    centres, b = vane_edges(geom)
    t0 = th[0]
    edges = t0 + np.mod(np.ravel(np.column_stack([centres - b, centres + b])) - t0, 2 * np.pi)
    base = th[:-1]
    cell = np.minimum(np.diff(th), np.roll(np.diff(th), 1))  # smaller neighbouring cell
    dist = np.abs(base[:, None] - np.concatenate([edges, edges - 2 * np.pi,
                                                  edges + 2 * np.pi])[None]).min(axis=1)
    keep = base[dist > cell / 3.0]
    nodes = np.unique(np.concatenate([keep, edges]))
    return np.concatenate([nodes, [nodes[0] + 2 * np.pi]])


def _cells(a: float, b: float, h: float, at_least: int = 1) -> np.ndarray:
    return np.linspace(a, b, max(at_least, int(np.ceil((b - a) / h - 1e-9))) + 1)


def _join(*parts: np.ndarray) -> np.ndarray:
    return np.concatenate([parts[0]] + [p[1:] for p in parts[1:]])


def _merged(x: np.ndarray, scale: float) -> np.ndarray:
    """Sorted grid values with those closer than ``1e-9 scale`` merged (a wall
    whose outer radius is the ring's inner radius up to round-off must not
    leave a cell of zero width)."""
    x = np.unique(x)
    keep = np.concatenate([[True], np.diff(x) > 1e-9 * scale])
    return x[keep]


def _radii(s: dict, h: float, h_hat: float) -> np.ndarray:
    """r grid: the ring at ``h``; below it the hat's breaks at ``h_hat``, two
    cells at least across the wall."""
    ring = _cells(s["ri"], s["ro"], h, 2)
    if not s["hat"]:
        return ring
    breaks = np.unique(np.round([s["bore"], s["bolt"], s["wi"], s["wo"], s["ri"]], 12))
    breaks = breaks[breaks <= s["ri"]]
    parts = [_cells(a, b, h_hat, 2 if (a >= s["wi"] - 1e-12 and b <= s["wo"] + 1e-12) else 1)
             for a, b in zip(breaks[:-1], breaks[1:])]
    inner = _join(*parts) if parts else np.array([s["ri"]])
    # a wall reaching under the ring: its breaks inside the ring become ring nodes
    tol = 1e-9 * s["ro"]
    extra = [x for x in (s["wi"], s["wo"]) if s["ri"] + tol < x < s["ro"] - tol]
    if extra:
        ring = np.unique(np.concatenate([ring, extra]))
        lo, hi = max(s["wi"], s["ri"]), s["wo"]
        if not ((ring > lo + 1e-12) & (ring < hi - 1e-12)).any():  # two cells across the wall
            ring = np.unique(np.concatenate([ring, [0.5 * (lo + hi)]]))
    return _merged(np.concatenate([inner, ring]), s["ro"])


def _heights(geom: BrakeGeometry, s: dict, h: float, h_hat: float) -> np.ndarray:
    """z grid: the ring graded toward both friction faces (as the plain ring),
    the cheeks and channel of a vented ring, the hat's wall and flange."""
    ms, t, c = geom.mesh, s["t"], s["c"]
    if c is None:
        half = 0.5 * t
        nz = ms.rotor_layers or _n_cells(half, 0.5 * h, ms.rotor_z_ratio)
        z = graded(-half, 0.0, nz, ms.rotor_z_ratio if nz > 1 else 1.0, "b")
        ring = np.concatenate([-t - z[::-1], z[1:]])
    else:
        nz = ms.rotor_layers or _n_cells(c, 0.5 * h, ms.rotor_z_ratio)
        cheek = graded(-c, 0.0, nz, ms.rotor_z_ratio if nz > 1 else 1.0, "b")
        n_ch = max(2, int(np.ceil((t - 2 * c) / h - 1e-9)))
        n_ch += n_ch % 2  # even: the mid-plane is a node (the half ring)
        ring = _join(-t - cheek[::-1], np.linspace(-t + c, -c, n_ch + 1), cheek)
    if not s["hat"]:
        return ring
    return _join(_cells(s["zb"], s["zf"], h_hat, 2), _cells(s["zf"], -t, h_hat, 2), ring)


def _keep_cells(geom: BrakeGeometry, s: dict, r, th, z) -> np.ndarray:
    """Mask of the hexahedral cells (in structured_tets' order) inside the section."""
    rc, tc, zc = np.meshgrid(0.5 * (r[1:] + r[:-1]), 0.5 * (th[1:] + th[:-1]),
                             0.5 * (z[1:] + z[:-1]), indexing="ij")
    t = s["t"]
    ring = (rc > s["ri"]) & (zc > -t)
    if s["c"] is not None:
        channel = (zc > -t + s["c"]) & (zc < -s["c"])
        ring &= ~channel | _in_vane(geom, tc)
    keep = ring | ((rc > s["r_lo"]) & (zc > -t) & (zc < s["z_neck"]))
    if s["hat"]:
        keep |= (rc > s["wi"]) & (rc < s["wo"]) & (zc < -t)
        keep |= (rc > s["bore"]) & (rc < s["wo"]) & (zc < s["zf"])
    return keep.ravel()


def _facets(mesh: fem.Mesh, P: np.ndarray, s: dict, half: bool = False) -> dict:
    """Named boundary facets, told apart by their parametric (r, z) midpoints."""
    ensure_topology(mesh)
    bf = np.nonzero(mesh.f2t[1] == -1)[0]
    r, _, z = P[:, mesh.facets[:, bf]].mean(axis=1)
    tol, t, c = 1e-9 * s["ro"], s["t"], s["c"]
    on_in, on_out = np.abs(z) < tol, np.abs(z + t) < tol
    out = {"friction_in": on_in & (r > s["ri"]), "friction_out": on_out & (r > s["ri"]),
           "outer": np.abs(r - s["ro"]) < tol}
    out["friction"] = out["friction_in"] | out["friction_out"]
    if half:  # the inboard half of a ring without a hat: the names of rotor_mesh's half ring
        del out["friction_in"], out["friction_out"]
        out["midplane"] = np.abs(z + 0.5 * t) < tol
    named = out["friction"] | out["outer"] | out.get("midplane", False)
    if c is not None:
        out["vents"] = ((r > s["ri"] + tol) & (r < s["ro"] - tol) & (z > -t + c - tol)
                        & (z < -c + tol) & ~named)
        named |= out["vents"]
    if s["hat"]:
        out["rotor_clamp"] = (np.abs(z - s["zb"]) < tol) & (r < s["bolt"])
        out["hat"] = ~(named | out["rotor_clamp"])
    else:
        out["rotor_clamp"] = np.abs(r - s["ri"]) < tol
    return {k: bf[v].astype(np.int32) for k, v in out.items()}


def full_rotor_mesh(geom: BrakeGeometry, size: float | None = None, order: int | None = None,
                    hat_size: float | None = None, half: bool = False) -> fem.Mesh:
    """The whole rotor: friction ring, with its hat (``rotor.mount = "hat"``)
    and its cheeks and vanes (``rotor.vents``), as one conforming mesh.

    The ring has the grids of :func:`brakewear.mesh.rotor_mesh` (``full``): in
    theta ``size`` over the pad arc plus ``mesh.rotor_margin``, coarser
    elsewhere, and through the thickness graded toward both friction faces
    (toward both faces of each cheek with vents; the channel at ``size``).
    The hat has cells of ``hat_size`` in r and z, two at least across the
    wall and the flange, and shares the ring's theta grid.

    Parameters
    ----------
    geom : BrakeGeometry
        The geometry (SI units); its rotor has a hat, vents or both.
    size, order
        As in :func:`brakewear.mesh.rotor_mesh`.
    hat_size : float, optional
        Element size (m) in the hat's section; default
        ``mesh.rotor_coarse_factor * size``.
    half : bool
        The inboard half (``-t/2 < z < 0``) of a vented ring without a hat,
        for a model with a mid-plane of symmetry: facets ``friction``
        (z = 0), ``midplane``, ``rotor_clamp``, ``outer``, ``vents``.

    Returns
    -------
    skfem.MeshTet or skfem.MeshTet2
        Facets ``friction_in`` (z = 0), ``friction_out`` (z = -t), ``friction``
        (both; r >= inner radius), ``outer`` (r = outer radius); with a hat
        ``rotor_clamp`` (the flange's mounting face out to the bolt circle) and
        ``hat`` (every other surface of the hat and the neck), without one
        ``rotor_clamp`` (r = inner radius); with vents ``vents`` (the channel
        walls).  Subdomains ``rotor`` (all), ``ring`` (z > -t) and ``hat``.
    """
    ro_ = geom.rotor
    h, order = _check_size_order(_body_size(geom, size, "rotor"),
                                 geom.mesh.order if order is None else order)
    if ro_.mount == "hat":
        if half:
            raise MeshError("a rotor with mount = 'hat' has no mid-plane of symmetry; "
                            "it is meshed whole (half=False)")
        _check_hat(geom)
    if ro_.vents is not None:
        _check_vents(geom)
    h_hat = geom.mesh.rotor_coarse_factor * h if hat_size is None else float(hat_size)
    if not np.isfinite(h_hat) or h_hat <= 0.0:
        raise MeshError(f"hat_size = {hat_size!r} is not allowed; it must be a number > 0 (m)")
    s = _section(geom)
    r, th, z = _radii(s, h, h_hat), _theta(geom, h), _heights(geom, s, h, h_hat)
    if half:
        z = z[z >= -0.5 * s["t"] - 1e-9 * s["ro"]]
    p, t = structured_tets(r, th, z, periodic_y=True)
    t = t[:, np.tile(_keep_cells(geom, s, r, th, z), 6)]
    used = np.unique(t)
    renum = np.full(p.shape[1], -1, dtype=np.int64)
    renum[used] = np.arange(used.size)
    P, t = np.ascontiguousarray(p[:, used]), np.ascontiguousarray(renum[t])
    mapping = vane_warp(geom) if ro_.vents is not None else None
    if mapping is None:
        from .structured import cylindrical as mapping
    m = mapped_mesh(P, t, mapping, order=order, period=np.array([0.0, 2 * np.pi, 0.0]))
    m = _with_boundaries(m, _facets(m, P, s, half))
    zc = P[2, t].mean(axis=0)
    m = _with_subdomains(m, {"rotor": np.arange(t.shape[1]), "ring": np.nonzero(zc > -s["t"])[0],
                             "hat": np.nonzero(zc < -s["t"])[0]})
    logger.debug("full rotor mesh (mount %s, vents %s): %d nodes, %d elements (order %d)",
                 ro_.mount, ro_.vents is not None, m.p.shape[1], m.t.shape[1], order)
    return m


def rotor_volume(geom: BrakeGeometry) -> float:
    """Volume (m^3) of the rotor of :func:`full_rotor_mesh`, in closed form:
    ring + neck + wall + flange, less the vent channels (a vane is the slab
    ``|y| < w/2`` between the ring's radii)."""
    s = _section(geom)
    ri, ro, t = s["ri"], s["ro"], s["t"]
    vol = np.pi * (ro ** 2 - ri ** 2) * t + np.pi * (ri ** 2 - s["r_lo"] ** 2) * (s["z_neck"] + t)
    if s["c"] is not None:
        v = geom.rotor.vents
        a = 0.5 * v.vane_width

        def chord(R):  # int_{-a}^{a} sqrt(R^2 - y^2) dy
            return a * np.sqrt(R ** 2 - a ** 2) + R ** 2 * np.arcsin(a / R)

        vane = chord(ro) - chord(ri)
        vol -= (np.pi * (ro ** 2 - ri ** 2) - v.vane_count * vane) * (t - 2 * s["c"])
    if s["hat"]:
        hat = geom.rotor.hat
        vol += np.pi * (s["wo"] ** 2 - s["bore"] ** 2) * hat.flange_thickness
        vol += np.pi * (s["wo"] ** 2 - s["wi"] ** 2) * (hat.height - hat.flange_thickness)
    return float(vol)
