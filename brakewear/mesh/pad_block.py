"""The pad as one structured block: lining and backplate outlines, chamfers, a radial slot.

The pad is meshed on a parametric grid ``(r, s, z)``: ``r`` the radius,
``s`` an angle-like coordinate, ``z`` the height above the friction face.
The ``r`` grid holds both the backplate and the lining radii, the ``s`` grid
the pad ends, the chamfer starts and the slot edges, the ``z`` grid the
lining/backplate interface and the slot bottom; lining cells outside the
lining radii or inside the slot are dropped, so the rest is conforming.  The
map to Cartesian coordinates

- bends the slot edges ``s = center -+ sigma`` onto the straight walls
  ``theta = center -+ asin(w / 2r)`` (r clipped to the lining radii), so the
  walls are the two planes ``w/2`` either side of the centre line;
- lifts the lining's friction face by the chamfer height
  ``f(theta) = depth * (1 - (theta - theta_end) / (length / r_mean))``, linear
  from ``depth`` at the pad end to 0 at the chamfer start, and moves every
  lining node by ``(1 - z / t_f) f``, so the z-grading moves with the face and
  every element keeps a positive volume while ``depth < t_f``.

P2 meshes place their edge nodes with the same map (isoparametric), so the
chamfer faces and the curved faces are represented to second order.
"""
from __future__ import annotations

import logging
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
import skfem as fem

from .structured import mapped_mesh, structured_tets
from .topology import _with_boundaries, _with_subdomains, ensure_topology

if TYPE_CHECKING:  # imported for annotations only: geometry sits above mesh
    from ..geometry import BrakeGeometry, PadGeometry

logger = logging.getLogger(__name__)

__all__ = ["sector_pad_mesh", "pad_breaks", "OPTIONAL_FACES"]


#: facet sets named only where the pad has them
OPTIONAL_FACES = ("leading_chamfer", "trailing_chamfer", "slot")


def _segments(breaks: list[float], h: float, min_cells: Callable[[int], int]) -> np.ndarray:
    """Nodes over the sorted ``breaks`` with cells at most about ``h``; segment
    ``k`` has at least ``min_cells(k)`` cells."""
    out = [np.array([breaks[0]])]
    for k, (a, b) in enumerate(zip(breaks[:-1], breaks[1:])):
        n = max(min_cells(k), int(np.ceil((b - a) / h)))
        out.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(out)


def pad_breaks(pad: PadGeometry) -> dict[str, float]:
    """The parametric angles of the pad: ends, chamfer starts and slot edges (rad).

    Keys ``lead``, ``trail`` (pad ends), ``lead_start``, ``trail_start``
    (chamfer starts; the ends when there is no chamfer), ``center`` and
    ``sigma`` (half the slot's parametric angle, ``asin(w / 2 r_mean)``; 0
    without a slot), ``r_mean`` (the lining's mean radius, m).
    """
    r_mean = 0.5 * (pad.inner_radius + pad.outer_radius)
    lead, trail = pad.leading_angle, pad.trailing_angle
    return {"lead": lead, "trail": trail, "center": pad.center_angle, "r_mean": r_mean,
            "lead_start": lead + pad.leading_chamfer[0] / r_mean,
            "trail_start": trail - pad.trailing_chamfer[0] / r_mean,
            "sigma": float(np.arcsin(0.5 * pad.slot_width / r_mean))}


def _grids(pad: PadGeometry, b: dict, h: float, zf: np.ndarray, zb: np.ndarray):
    """The parametric grids ``r``, ``s``, ``z`` of the pad block."""
    ri, ro = pad.inner_radius, pad.outer_radius
    radii = sorted({*pad.backplate_radii, ri, ro})
    lining = radii.index(ri)
    r = _segments(radii, h, lambda k: 2 if k == lining else 1)
    slot = [b["center"] - b["sigma"], b["center"] + b["sigma"]] if b["sigma"] > 0 else []
    s_breaks = sorted({b["lead"], b["lead_start"], *slot, b["trail_start"], b["trail"]})
    # the cells along the arc are sized at the lining's mean radius
    s = _segments(s_breaks, h / b["r_mean"], lambda k: 2 if len(s_breaks) == 2 else 1)
    tf = pad.friction_thickness
    if pad.slot_width > 0 and pad.slot_depth is not None and pad.slot_depth < tf:
        sd = pad.slot_depth
        near = np.abs(zf - sd) < 0.25 * np.diff(zf).min()
        zf = np.sort(np.concatenate([zf[~near | (zf == 0) | (zf == tf)], [sd]]))
        zf = np.unique(zf)
    return r, s, np.concatenate([zf, zb[1:]])


def _mapping(pad: PadGeometry, b: dict) -> Callable[[np.ndarray], np.ndarray]:
    """Parametric ``(r, s, z)`` to Cartesian ``(x, y, z)``: slot walls and chamfers."""
    ri, ro, tf = pad.inner_radius, pad.outer_radius, pad.friction_thickness
    (ll, dl), (lt, dt) = pad.leading_chamfer, pad.trailing_chamfer
    c, sig = b["center"], b["sigma"]

    def f(s):
        out = np.zeros_like(s)
        if ll > 0:
            out += dl * np.clip(1.0 - (s - b["lead"]) / (b["lead_start"] - b["lead"]), 0.0, 1.0)
        if lt > 0:
            out += dt * np.clip(1.0 - (b["trail"] - s) / (b["trail"] - b["trail_start"]), 0.0, 1.0)
        return out

    def theta(r, s):
        # piecewise linear in s between the breaks; the slot edges move with r
        if sig == 0:
            return s.copy()
        half = np.arcsin(0.5 * pad.slot_width / np.clip(r, ri, ro))
        S = [b["lead"], b["lead_start"], c - sig, c + sig, b["trail_start"], b["trail"]]
        T = [np.full_like(r, S[0]), np.full_like(r, S[1]), c - half, c + half,
             np.full_like(r, S[4]), np.full_like(r, S[5])]
        keep = [0] + [k for k in range(1, 6) if S[k] > S[k - 1]]
        S, T = np.array([S[k] for k in keep]), np.array([T[k] for k in keep])
        k = np.clip(np.searchsorted(S, s, side="right") - 1, 0, len(S) - 2)
        i = np.arange(s.size)
        w = (s - S[k]) / (S[k + 1] - S[k])
        return T[k, i] + w * (T[k + 1, i] - T[k, i])

    def mapping(p: np.ndarray) -> np.ndarray:
        r, s, z = p
        th = theta(r, s)
        zz = z.copy()
        lin = z < tf
        if ll > 0 or lt > 0:
            fs = f(s[lin])
            zz[lin] = fs + z[lin] * (tf - fs) / tf
        return np.vstack([r * np.cos(th), r * np.sin(th), zz])

    return mapping


def _kept(p: np.ndarray, t: np.ndarray, pad: PadGeometry, b: dict) -> np.ndarray:
    """Mask of the tetrahedra that are pad material (by parametric centroid)."""
    cr, cs, cz = p[:, t].mean(axis=1)
    lining = cz < pad.friction_thickness
    out = lining & ((cr < pad.inner_radius) | (cr > pad.outer_radius))
    if pad.slot_width > 0:
        depth = pad.friction_thickness if pad.slot_depth is None else pad.slot_depth
        out |= (np.abs(cs - b["center"]) < b["sigma"]) & (cz < depth)
    return ~out


def sector_pad_mesh(geom: BrakeGeometry, h: float, order: int, zf: np.ndarray,
                    zb: np.ndarray) -> fem.Mesh:
    """The pad mesh of :func:`brakewear.mesh.pad_mesh` on the through-thickness
    grids ``zf`` (friction layer, from 0) and ``zb`` (backplate); ``h`` is the
    in-plane size (m)."""
    pad = geom.pad
    b = pad_breaks(pad)
    r, s, z = _grids(pad, b, h, zf, zb)
    p, t = structured_tets(r, s, z)
    t = t[:, _kept(p, t, pad, b)]
    used, t = np.unique(t, return_inverse=True)
    p, t = p[:, used], t.reshape(4, -1)
    m = mapped_mesh(p, t, _mapping(pad, b), order=order)
    m = _with_boundaries(m, _facet_sets(m, p, geom, b))
    cz = p[2, m.t].mean(axis=0)
    m = _with_subdomains(m, {"friction_layer": np.flatnonzero(cz < pad.friction_thickness),
                             "backplate": np.flatnonzero(cz > pad.friction_thickness)})
    return m


def _facet_sets(m: fem.Mesh, p: np.ndarray, geom: BrakeGeometry, b: dict) -> dict:
    """The named boundary facets, told apart by their parametric centroids."""
    pad, pis = geom.pad, geom.piston
    ensure_topology(m)
    bf = np.flatnonzero(m.f2t[1] == -1).astype(np.int32)
    cr, cs, cz = p[:, m.facets[:, bf]].mean(axis=1)
    X = m.p[:, m.facets[:, bf]].mean(axis=1)
    tf, top = pad.friction_thickness, pad.thickness
    tz, ts = 1e-9 * top, 1e-9 * max(1.0, abs(b["trail"]))
    face = np.abs(cz) < tz
    back = np.abs(cz - top) < tz
    lead, trail = np.abs(cs - b["lead"]) < ts, np.abs(cs - b["trail"]) < ts
    slot = np.zeros_like(face)
    if pad.slot_width > 0:
        depth = tf if pad.slot_depth is None else pad.slot_depth
        slot = ((np.abs(cs - b["center"]) < b["sigma"] + ts) & (cz > tz) & (cz < depth + tz)
                & (cr > pad.inner_radius) & (cr < pad.outer_radius))
    xc, yc = geom.piston_center
    d = np.hypot(X[0] - xc, X[1] - yc)
    foot = (d < 0.5 * pis.diameter) & (d >= 0.5 * (pis.rim_inner_diameter or 0.0))
    side = ~(face | back | lead | trail | slot)
    sets = {
        "friction": face,
        "back": back,
        "piston_face": back & foot,
        "leading": lead,
        "trailing": trail,
        "abutment": (lead | trail) & (cz > tf),
        "abutment_leading": lead & (cz > tf),
        "abutment_trailing": trail & (cz > tf),
        "leading_chamfer": face & (cs < b["lead_start"] - ts),
        "trailing_chamfer": face & (cs > b["trail_start"] + ts),
        "slot": slot,
        "inner": side & (cr < b["r_mean"]),
        "outer": side & (cr > b["r_mean"]),
    }
    # a face the pad does not have is not named (a mesh file cannot hold an empty group)
    return {k: bf[v] for k, v in sets.items() if v.any() or k not in OPTIONAL_FACES}
