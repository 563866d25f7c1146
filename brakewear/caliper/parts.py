"""The caliper's rigid parts: a piston's motion, its seal's springs, the housing, the bracket.

The kinematics and the springs of :mod:`brakewear.caliper.rows`'s parts:

* :class:`CaliperParts`: the rigid DOFs (each piston's six about the centre
  of its face; the floating housing's axial position) and the prescribed
  motions of the housing's bore and jaw under the clamp force;
* :func:`seal_springs`: the seal's ring of springs from its section and the
  rubber's modulus (closed forms of :mod:`brakewear.caliper.analytic`), and
  :func:`seal_stiffness`: what they give the rigid DOFs, with the hydraulic
  loads;
* :func:`part_loads`: the forces on each rigid part of a solved state;
* :func:`bracket_springs`: the rails and the pad's clip on the end faces'
  mean displacements.
"""
from __future__ import annotations

import logging
import math

import numpy as np
import scipy.sparse as sp

from ..contact.supports import face_weights, spring_faces

logger = logging.getLogger(__name__)

__all__ = ["CaliperParts", "rigid_map", "seal_springs", "seal_stiffness", "part_loads",
           "bracket_springs", "ring_points", "SEAL_POINTS"]

#: points of a seal's ring of springs
SEAL_POINTS = 64

_EZ = np.array([0.0, 0.0, 1.0])


def ring_points(centre: np.ndarray, radius: float, count: int, phase: float = 0.0):
    """``count`` points on a circle about the z axis through ``centre`` (3, count)
    and their radial unit vectors."""
    phi = phase + 2.0 * np.pi * np.arange(count) / count
    e_r = np.vstack([np.cos(phi), np.sin(phi), np.zeros(count)])
    return centre[:, None] + radius * e_r, e_r


def rigid_map(point: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """``Phi`` (3, 6): the displacement at ``point`` of a rigid body whose motion is
    ``(t, omega)`` about ``reference``: ``t + omega x (point - reference)``."""
    d = np.asarray(point, dtype=float) - reference
    return np.hstack([np.eye(3), np.array([[0.0, d[2], -d[1]], [-d[2], 0.0, d[0]],
                                           [d[1], -d[0], 0.0]])])


class CaliperParts:
    """The rigid parts of a caliper (see the module): their DOFs and prescribed motions."""

    def __init__(self, geometry, full: bool):
        g, cal = geometry, geometry.caliper
        self.g = g
        pad = g.pad
        self.t_r = g.rotor.thickness
        self.sides = ("in", "out") if full and cal.type == "fixed" else ("in",)
        self.floating = full and cal.type == "floating"
        self.bodies, self.dofs, n = {}, [], 0
        for side in self.sides:
            self.bodies[f"piston {side}"] = (n, 6, self.face_centre(side))
            self.dofs += [f"piston {side} {c}" for c in ("ux", "uy", "uz", "rx", "ry", "rz")]
            n += 6
        if self.floating:
            self.bodies["housing"] = (n, 1, self.mouth("in"))
            self.dofs.append("housing uz")
            n += 1
        self.nq = n
        a0 = pad.center_angle
        self.e = np.array([math.cos(a0), math.sin(a0), 0.0])         # the pad's radial line
        self.t = np.array([-math.sin(a0), math.cos(a0), 0.0])        # and its tangent
        self.F1 = g.clamp_area                                        # N per Pa

    def z_sign(self, side: str) -> float:
        """+1: the piston pushes toward -z (inboard); -1 (outboard, mirrored)."""
        return 1.0 if side == "in" else -1.0

    def face_centre(self, side: str) -> np.ndarray:
        x, y = self.g.piston_center
        z = self.g.pad.thickness
        return np.array([x, y, z if side == "in" else -self.t_r - z])

    def mouth(self, side: str) -> np.ndarray:
        """Centre of the bore's mouth."""
        s = self.z_sign(side)
        return self.face_centre(side) + s * self.g.piston.guide.stand_out * _EZ

    def map(self, part: str, x: np.ndarray) -> np.ndarray:
        """(3, nq): the displacement at ``x`` of ``part`` per rigid DOF."""
        M = np.zeros((3, self.nq))
        if part in ("pad", "bracket"):
            return M
        name = "housing" if part.startswith("housing") else part
        if name not in self.bodies:         # a housing held (half model, fixed caliper)
            return M
        first, k, ref = self.bodies[name]
        if k == 6:
            M[:, first:first + 6] = rigid_map(x, ref)
        else:
            M[2, first] = 1.0
        return M

    def prescribed(self, part: str, x: np.ndarray) -> np.ndarray:
        """(3,) displacement at ``x`` of ``part`` per pascal of line pressure."""
        cal = self.g.caliper
        if part == "housing jaw" and cal.bridge_tilt > 0:
            # the jaw presses harder at larger radius: toward the pad (+z) by theta (e . x)
            return cal.bridge_tilt * self.F1 * float(self.e @ x) * _EZ
        if part == "housing bore" and cal.bore_tilt > 0:
            # the bore turns about the tangent through its mouth: the deep end outward
            w = cal.bore_tilt * self.F1 * self.t
            return np.cross(w, x - self.mouth("in"))
        return np.zeros(3)

    def housing_part(self, side: str, where: str) -> str:
        """The rigid part holding a piston's bore or the fingers."""
        if not self.floating:
            return "bracket"
        return f"housing {where}"


def seal_springs(guide, radius: float) -> dict:
    """Stiffness per unit circumference (N/m per m) of the seal's ring: ``axial``
    (axial shear of the section), ``tangential`` (circumferential shear) and
    ``radial`` (compression), at the seal's mean radius, and the totals they give
    a rigid piston: ``axial_total`` (N/m), ``radial_total`` (N/m, translation),
    ``tilt`` (N m/rad about a diameter in the seal's plane) and ``torsion`` (N m/rad).

    The axial and torsional totals are the bonded annulus's closed forms
    (:func:`~brakewear.caliper.analytic.bonded_ring_axial_stiffness`,
    :func:`~brakewear.caliper.analytic.bonded_ring_torsion_stiffness`; rubber ``G = E /
    3``); the radial one compresses the section with the long strip's modulus
    (:func:`~brakewear.caliper.analytic.bonded_strip_compression_modulus`), an estimate.
    """
    from .analytic import (
        bonded_ring_axial_stiffness,
        bonded_ring_torsion_stiffness,
        bonded_strip_compression_modulus,
        ring_tilt_stiffness,
    )

    E, w, h = guide.seal_modulus, guide.seal_width, guide.seal_height
    G = E / 3.0
    r_i, r_o = radius, radius + w
    r_m = radius + 0.5 * w
    ka = bonded_ring_axial_stiffness(G, r_i, r_o, h)
    kt = bonded_ring_torsion_stiffness(G, r_i, r_o, h)
    Ec = bonded_strip_compression_modulus(E, h, w)
    L = 2.0 * math.pi * r_m
    per = {"axial": ka / L, "tangential": kt / (L * r_m ** 2), "radial": Ec * h / w}
    per["radial_total"] = math.pi * r_m * (per["radial"] + per["tangential"])
    per.update(axial_total=ka, torsion=kt, tilt=ring_tilt_stiffness(ka, r_m), radius=r_m)
    return per


def _seal_points(P: CaliperParts, side: str) -> np.ndarray:
    """(3, m): the points of a piston's seal ring."""
    guide = P.g.piston.guide
    k = seal_springs(guide, 0.5 * P.g.piston.diameter)
    zs = P.mouth(side) + P.z_sign(side) * guide.seal_position * _EZ
    return ring_points(zs, k["radius"], SEAL_POINTS)[0]


def _seal_ring(P: CaliperParts, side: str):
    """Per point of a piston's seal ring: the relative displacement of piston and
    groove per rigid DOF (3, nq), the groove's prescribed motion per pascal (3,),
    and the springs ``[(direction, stiffness N/m)]`` of the point's share of the ring."""
    k = seal_springs(P.g.piston.guide, 0.5 * P.g.piston.diameter)
    x = _seal_points(P, side)
    dl = 2.0 * np.pi * k["radius"] / SEAL_POINTS
    wall = P.housing_part(side, "bore")
    for j in range(x.shape[1]):
        e_r = (x[:, j] - P.face_centre(side)) * np.array([1.0, 1.0, 0.0])
        e_r /= np.linalg.norm(e_r)
        e_t = np.cross(_EZ, e_r)
        yield (P.map(f"piston {side}", x[:, j]) - P.map(wall, x[:, j]),
               P.prescribed(wall, x[:, j]),
               ((e_r, k["radial"] * dl), (e_t, k["tangential"] * dl), (_EZ, k["axial"] * dl)))


def seal_stiffness(P: CaliperParts) -> tuple[np.ndarray, np.ndarray]:
    """The seals' stiffness on the rigid DOFs and their load per pascal (with the
    hydraulic forces on pistons and housing)."""
    K, f = np.zeros((P.nq, P.nq)), np.zeros(P.nq)
    A = P.g.piston.hydraulic_area
    for side in P.sides:
        s = P.z_sign(side)
        for rel, presc, springs in _seal_ring(P, side):
            for d, kd in springs:
                a = d @ rel
                K += kd * np.outer(a, a)
                f += kd * float(d @ presc) * a
        first = P.bodies[f"piston {side}"][0]
        f[first + 2] -= s * A               # the hydraulic force on the piston
        if P.floating:
            f[P.bodies["housing"][0]] += s * A      # and on the bore's bottom
    return K, f


def part_loads(rows, lam: np.ndarray, q: np.ndarray, line_pressure: float
               ) -> dict:
    """The forces on each rigid part of a solved state: part -> ``(forces (3, k),
    points (3, k))`` from the rows' forces ``lam`` (each ``-n lam`` on its minus
    side, ``+n lam`` on its plus side), the seals' springs at the rigid DOFs ``q``
    (evaluated ring point by ring point, not through ``K_q``) and the hydraulic
    pressure ``line_pressure`` (on each piston and, floating, the housing)."""
    P = rows.parts
    out = {}

    def put(part, F, x):
        part = "housing" if part.startswith("housing") else part
        if part == "pad":
            return
        out.setdefault(part, ([], []))
        out[part][0].append(np.asarray(F, dtype=float))
        out[part][1].append(np.asarray(x, dtype=float))
    for k in range(rows.n):
        F = rows.direction[:, k] * lam[k]
        put(rows.minus[k], -F, rows.point[:, k])
        put(rows.plus[k], F, rows.point[:, k])
    A = P.g.piston.hydraulic_area
    for side in P.sides:
        s = P.z_sign(side)
        wall = P.housing_part(side, "bore")
        for (rel, presc, springs), x in zip(_seal_ring(P, side), _seal_points(P, side).T):
            du = rel @ q - line_pressure * presc
            F = -sum(kd * float(d @ du) * d for d, kd in springs)
            put(f"piston {side}", F, x)
            put(wall, -F, x)
        put(f"piston {side}", -s * line_pressure * A * _EZ, P.face_centre(side))
        put(P.housing_part(side, "bore"), s * line_pressure * A * _EZ, P.face_centre(side))
    return {part: (np.array(F).T, np.array(x).T) for part, (F, x) in out.items()}


def bracket_springs(mesh, offset: int, pad_geometry, support, n_dofs: int) -> sp.csr_matrix:
    """The bracket's rails and the pad's clip as springs on the mean displacement of
    the faces they hold (``n_dofs`` square, the mesh's nodes from ``offset``): per
    end face a rail of ``rail_stiffness`` on the face's area-weighted mean radial
    displacement, and per pad the clip's ``spring_stiffness`` on the mean
    tangential displacement of both end faces.  Unlike springs node by node
    (:func:`~brakewear.contact.supports.support_springs`) they hold the pad in its
    plane without holding its tilt: an ear rocks on its rail.  Zero for a
    bilateral support."""
    if support.type == "bilateral":
        return sp.csr_matrix((n_dofs, n_dofs))
    radial, tangential, pads = spring_faces(mesh, pad_geometry)
    rows = []
    for ends in pads:
        rows += [(support.rail_stiffness, _mean_row(mesh, facets, radial)) for facets in ends]
        rows.append((support.spring_stiffness, _mean_row(mesh, np.concatenate(ends), tangential)))
    K = sp.csr_matrix((n_dofs, n_dofs))
    for k, (dofs, vals) in rows:
        a = sp.csr_matrix((vals, (np.zeros(vals.size, dtype=np.int64), dofs + 3 * offset)),
                          shape=(1, n_dofs))
        K = K + k * (a.T @ a)
    return K.tocsr()


def _mean_row(mesh, facets, d: np.ndarray):
    """DOFs (the mesh's) and weights of the mean displacement along ``d`` of ``facets``."""
    nodes, w = face_weights(mesh, facets)
    w = w / w.sum()
    dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
    return dofs, (w[:, None] * d[None, :]).ravel()
