"""The caliper's parts as the pads meet them: a rigid piston in its bore, the housing, the rows.

A floating caliper holds its pads through a handful of parts whose stiffness
decides how far a pad may tilt.  Here each is what a brake engineer draws:

* the **piston**, a rigid body (six DOFs about the centre of its face),
  pushed by the hydraulic force ``p A_bore`` toward the pad;
* its **seal**, a ring of springs between the piston and the housing's
  groove: axial and circumferential shear and radial compression of the
  rubber section (:func:`seal_springs`), soft in tilt;
* the **bore wall**, a rigid cylinder ``clearance`` away from the piston,
  met only at the two ends of the guided length (unilateral rows at
  ``n_bore`` angles each, with friction along the axis on each end's ring as
  a whole: the rigid piston slides at once);
* the **rim**, the piston's annular face on the backplate: unilateral rows
  at points on the rim's inner and outer edge, so the pad can rock on either
  edge, each through its share of the cup wall's axial compliance
  (``piston.length / (E A_rim)`` over the rim), with friction in the
  backplate's plane on the rim as a whole;
* the **housing** (floating caliper, full model), sliding on its pins: one
  DOF, its axial position; its fingers press the outboard pad through a
  layer of ``finger_stiffness`` (unilateral rows over the finger
  footprints, each with the layer's compliance).  As the housing opens
  under the clamp force its jaw turns by ``bridge_tilt F`` and its bore by
  ``bore_tilt F`` (prescribed motions, a gap change per unit line pressure);
* the **abutments** of the bracket (push or pull support): unilateral rows
  over radial bands of each backplate end face, with friction along the
  rotor axis on the face as a whole (its mean slip, bounded by mu times the
  face's normal force; the pad's clip and the rails are springs in ``K``).

A *row* ``k`` joins a "plus" side (a pad through the FE model, or a rigid
part) to a "minus" side (a rigid part, or the fixed bracket) at a point
``x_k`` along a unit direction ``n_k``: its gap (or, for a friction row,
its slip) is

    g_k = g0_k + p g1_k + n_k . (u_plus(x_k) - u_minus(x_k)),

written ``g = g0 + p g1 + C u - R q`` with ``u`` the FE displacement and
``q`` the rigid DOFs; its force ``lam_k`` acts as ``+n_k lam_k`` on the plus
side and ``-n_k lam_k`` on the minus side.  A normal row is unilateral
(``g >= 0``, ``lam >= 0``, complementary; the fingers' rows through their
layer's compliance); a friction row ``k`` of normal row ``j`` is Coulomb's
law along ``n_k``: ``|lam_k| <= mu_k lam_j``, sticking (no slip) below it.
The slip is measured from the unloaded brake: each solve is one application
from rest.  The rows' solution is :mod:`brakewear.caliper.interface`'s.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from ..contact.supports import SUPPORT_ENDS, abutment_faces, end_normal, face_weights
from ..contact.surface import project_nodes
from ..errors import ContactError
from .parts import CaliperParts, ring_points, seal_springs, seal_stiffness

logger = logging.getLogger(__name__)

__all__ = ["CaliperRows", "caliper_rows", "ROW_COUNTS"]

#: points per row family: rim angles per edge, bore angles per end, finger rings,
#: abutment bands per end face
ROW_COUNTS = {"rim": 16, "bore": 12, "finger_rings": 2, "abutment_bands": 6}

_EZ = np.array([0.0, 0.0, 1.0])


@dataclass
class CaliperRows:
    """The caliper's rows and rigid parts (see the module).

    Attributes
    ----------
    C : scipy.sparse.csr_matrix
        (n, N) the rows' FE part in the contact system's retained DOFs.
    R : ndarray
        (n, nq) the rows' rigid part.
    g0, g1 : ndarray
        (n,) gap at rest (m) and its change per pascal of line pressure (m/Pa).
    friction_of : ndarray
        (n,) a normal row of a friction row (the first of its ``cap``), -1 for a
        normal row.
    cap : scipy.sparse.csr_matrix
        (n, n) the normal rows whose force bounds each friction row's:
        ``|lam_k| <= mu_k (cap lam)_k``: every normal row of the surface a
        friction row acts on as a whole (the rim, a bore end's ring, an
        abutment's end face).
    mu : ndarray
        (n,) friction coefficient of each friction row (0 for normal rows).
    compliance : ndarray
        (n,) m/N of a normal row's layer (the fingers'), 0 elsewhere.
    point, direction : ndarray
        (3, n) where each row acts and its unit direction ``n_k``.
    plus, minus : list of str
        Each row's sides: ``"pad"`` (the FE model), a rigid part (``"piston
        in"``, ``"piston out"``, ``"housing"``) or ``"bracket"``.
    group : list of str
        Each row's family, e.g. ``"rim in"``, ``"bore in"``, ``"fingers"``,
        ``"abutment trailing (inboard)"``.
    K_q, f_q : ndarray
        (nq, nq) the seals' stiffness on the rigid DOFs and (nq,) their load per
        pascal of line pressure (hydraulic force, the bore's prescribed tilt).
    dofs : list of str
        Names of the rigid DOFs, e.g. ``"piston in uz"``, ``"housing uz"``.
    bodies : dict
        Rigid part -> (first DOF, number of DOFs, reference point (3,)).
    hydraulic_area : float
        Bore area of one piston (m^2).
    """

    C: sp.csr_matrix
    R: np.ndarray
    g0: np.ndarray
    g1: np.ndarray
    friction_of: np.ndarray
    cap: sp.csr_matrix
    mu: np.ndarray
    compliance: np.ndarray
    point: np.ndarray
    direction: np.ndarray
    plus: list
    minus: list
    group: list
    K_q: np.ndarray
    f_q: np.ndarray
    dofs: list
    bodies: dict
    hydraulic_area: float
    info: dict = field(default_factory=dict)
    parts: object = field(default=None, repr=False)

    @property
    def n(self) -> int:
        return int(self.g0.size)

    @property
    def normal(self) -> np.ndarray:
        """(n,) bool: the normal (unilateral) rows."""
        return self.friction_of < 0

    def subset(self, keep) -> CaliperRows:
        """The rows ``keep`` (a mask or indices; a kept friction row's normal row must be
        kept too) with the same rigid parts."""
        idx = np.arange(self.n)[keep]
        new = -np.ones(self.n, dtype=np.int64)
        new[idx] = np.arange(idx.size)
        fr = self.friction_of[idx]
        cap = self.cap[idx]
        if cap[:, np.setdiff1d(np.arange(self.n), idx)].nnz:
            raise ContactError("a kept friction row's normal rows are not kept")
        pick = lambda v: [v[i] for i in idx]  # noqa: E731
        return replace(self, C=self.C[idx], R=self.R[idx], g0=self.g0[idx], g1=self.g1[idx],
                       friction_of=np.where(fr >= 0, new[np.maximum(fr, 0)], -1),
                       cap=cap[:, idx].tocsr(),
                       mu=self.mu[idx], compliance=self.compliance[idx],
                       point=self.point[:, idx], direction=self.direction[:, idx],
                       plus=pick(self.plus), minus=pick(self.minus), group=pick(self.group))

    def rows_of(self, group: str) -> np.ndarray:
        """Indices of the rows of one family."""
        return np.array([i for i, g in enumerate(self.group) if g == group], dtype=np.int64)








class _Rows:
    """Rows as they are added; :meth:`build` makes the :class:`CaliperRows`."""

    def __init__(self, parts: CaliperParts):
        self.parts = parts
        self.rows = []

    def add(self, x, n, plus, minus, group, g0=0.0, cap=(), mu=0.0, compliance=0.0,
            fe=None) -> int:
        """A row (see :class:`CaliperRows`); ``cap``: a friction row's normal rows."""
        self.rows.append(dict(x=np.asarray(x, dtype=float), n=np.asarray(n, dtype=float),
                              plus=plus, minus=minus, group=group, g0=float(g0),
                              cap=tuple(cap), mu=float(mu), compliance=float(compliance),
                              fe=fe))
        return len(self.rows) - 1

    def build(self, col: np.ndarray, n_dofs: int, K_q, f_q, info) -> CaliperRows:
        P, rows = self.parts, self.rows
        n = len(rows)
        R = np.zeros((n, P.nq))
        g1 = np.zeros(n)
        ri, ci, vi = [], [], []
        for k, r in enumerate(rows):
            x, d = r["x"], r["n"]
            R[k] = d @ P.map(r["minus"], x) - d @ P.map(r["plus"], x)
            g1[k] = d @ (P.prescribed(r["plus"], x) - P.prescribed(r["minus"], x))
            if r["fe"] is not None:
                nodes, w = r["fe"]
                c = col[nodes]
                if np.any(c < 0):
                    raise ContactError(f"{r['group']}: a pad node of the row is tied (eliminated)")
                for i in range(3):
                    ri.append(np.full(c.size, k))
                    ci.append(3 * c + i)
                    vi.append(w * d[i])
        C = sp.csr_matrix((np.concatenate(vi), (np.concatenate(ri), np.concatenate(ci))),
                          shape=(n, n_dofs))
        get = lambda key: np.array([r[key] for r in rows])  # noqa: E731
        ci = [np.array(r["cap"], dtype=np.int64) for r in rows]
        cap = sp.csr_matrix((np.ones(sum(c.size for c in ci)),
                             (np.repeat(np.arange(n), [c.size for c in ci]),
                              np.concatenate(ci))), shape=(n, n))
        first = np.array([c[0] if c.size else -1 for c in ci])
        return CaliperRows(C=C, R=R, g0=get("g0"), g1=g1, friction_of=first, cap=cap,
                           mu=get("mu"), compliance=get("compliance"),
                           point=np.array([r["x"] for r in rows]).T,
                           direction=np.array([r["n"] for r in rows]).T,
                           plus=[r["plus"] for r in rows], minus=[r["minus"] for r in rows],
                           group=[r["group"] for r in rows], K_q=K_q, f_q=f_q, dofs=P.dofs,
                           bodies=P.bodies, hydraulic_area=P.g.piston.hydraulic_area,
                           info=info, parts=P)


def _disc_points(centre: np.ndarray, radius: float, rings: int):
    """Points and areas covering a disc: ``rings`` rings of 6, 12, ... points at the
    mid-radii of equal-width annuli, each point its share of its annulus."""
    pts, area = [], []
    for k in range(rings):
        a, b = k * radius / rings, (k + 1) * radius / rings
        m = 6 * (k + 1)
        x, _ = ring_points(centre, 0.5 * (a + b), m, phase=np.pi / m * k)
        pts.append(x)
        area.append(np.full(m, np.pi * (b * b - a * a) / m))
    return np.hstack(pts), np.concatenate(area)


def _on_face(mesh, facets, points: np.ndarray, offset: int):
    """``(global nodes (3, n), weights (3, n))`` of the face ``facets`` under ``points``
    (their x, y; the face is flat)."""
    pr = project_nodes(points, mesh, facets)
    return pr.nodes + offset, pr.weights


def _rim_and_bore(rows: _Rows, mesh, offset: int, side: str) -> None:
    P = rows.parts
    pis, guide = P.g.piston, P.g.piston.guide
    s = P.z_sign(side)
    body = f"piston {side}"
    c = P.face_centre(side)
    back = ("back_in" if side == "in" else "back_out") if "back_in" in mesh.boundaries else "back"
    radii = ((0.5 * pis.rim_inner_diameter, 0.5 * pis.diameter) if pis.rim_inner_diameter
             else (0.5 * 0.5 * pis.diameter, 0.5 * pis.diameter))
    normal, fe = [], []
    # the piston is a cup: its rim presses through the wall's axial compliance,
    # length / (E A) over the rim's points together
    n_pts = len(radii) * ROW_COUNTS["rim"]
    c_wall = n_pts * pis.length / (pis.material.elastic.E * pis.footprint_area)
    for rad in radii:
        x, _ = ring_points(c, rad, ROW_COUNTS["rim"])
        nodes, w = _on_face(mesh, back, x, offset)
        for j in range(x.shape[1]):
            normal.append(rows.add(x[:, j], -s * _EZ, "pad", body, f"rim {side}",
                                   compliance=c_wall, fe=(nodes[:, j], w[:, j])))
            fe.append((nodes[:, j], w[:, j] / (len(radii) * x.shape[1])))
    if guide.rim_friction > 0:
        # the rim's friction on the rim as a whole: the pad's mean slip over the rim's
        # points against the piston's, bounded by mu times the rim's whole force
        nodes = np.concatenate([f[0] for f in fe])
        w = np.concatenate([f[1] for f in fe])
        for t in (P.e, P.t):
            rows.add(c, t, "pad", body, f"rim {side} friction", cap=normal,
                     mu=guide.rim_friction, fe=(nodes, w))
    wall = P.housing_part(side, "bore")
    mouth = P.mouth(side)
    for depth in (0.0, guide.engagement):
        centre = mouth + s * depth * _EZ
        x, e_r = ring_points(centre, 0.5 * pis.diameter, ROW_COUNTS["bore"])
        ring = [rows.add(x[:, j], e_r[:, j], wall, body, f"bore {side}", g0=guide.clearance)
                for j in range(x.shape[1])]
        if guide.bore_friction > 0:
            # the bore's friction on the guide ring as a whole (as the rim's): the rigid
            # piston slides along the bore at once, however many points it touches
            rows.add(centre, _EZ, wall, body, f"bore {side} friction", cap=ring,
                     mu=guide.bore_friction)


def _fingers(rows: _Rows, mesh, offset: int) -> None:
    P = rows.parts
    cal = P.g.caliper
    z = -P.t_r - P.g.pad.thickness
    for f in cal.fingers:
        a = P.g.pad.center_angle + f.angle
        centre = np.array([f.radius * math.cos(a), f.radius * math.sin(a), z])
        x, area = _disc_points(centre, 0.5 * f.diameter, ROW_COUNTS["finger_rings"])
        nodes, w = _on_face(mesh, "back_out", x, offset)
        for j in range(x.shape[1]):
            rows.add(x[:, j], _EZ, "pad", "housing jaw", "fingers",
                     compliance=1.0 / (cal.finger_stiffness * area[j]),
                     fe=(nodes[:, j], w[:, j]))


def _abutments(rows: _Rows, mesh, offset: int) -> None:
    P = rows.parts
    sup, pad = P.g.support, P.g.pad
    if sup.type == "bilateral":
        return
    bearing = sup.bearing_end
    for end in SUPPORT_ENDS:
        e = end_normal(pad, end)
        normal = e if (sup.type == "push" and end == "leading") else -e
        g0 = 0.0 if end == bearing else sup.clearance
        for pad_side, facets in abutment_faces(mesh, end).items():
            nodes, w = face_weights(mesh, facets)
            r = np.hypot(mesh.p[0, nodes], mesh.p[1, nodes])
            edges = np.linspace(r.min(), r.max(), ROW_COUNTS["abutment_bands"] + 1)
            band = np.clip(np.searchsorted(edges, r, side="right") - 1, 0, edges.size - 2)
            face = []
            for b in np.unique(band):
                m = band == b
                wb = w[m] / w[m].sum()
                x = mesh.p[:, nodes[m]] @ wb
                face.append(rows.add(x, normal, "pad", "bracket",
                                     f"abutment {end} ({pad_side})", g0=g0,
                                     fe=(nodes[m] + offset, wb)))
            if sup.abutment_friction > 0:
                # the friction on the end face as a whole: the backplate's end slides
                # along the abutment at once (its mean slip), bounded by mu times the
                # face's whole normal force; per band, the bands would share one slip
                # and their stick or slip would be decided by the backplate's stiffness
                wf = w / w.sum()
                rows.add(mesh.p[:, nodes] @ wf, _EZ, "pad", "bracket",
                         f"abutment {end} ({pad_side}) friction", cap=face,
                         mu=sup.abutment_friction, fe=(nodes + offset, wf))




def caliper_rows(geometry, pad_mesh, pad_offset: int, col: np.ndarray, n_dofs: int,
                 full: bool) -> CaliperRows:
    """The rows and rigid parts of a caliper (see the module) for the pad mesh
    ``pad_mesh`` (its first global node ``pad_offset``; ``col``: global node ->
    retained node of the contact system, ``n_dofs`` its DOFs).  ``full``: both
    pads (the full model); else the inboard pad alone (the housing held)."""
    if geometry.extra_pistons:
        raise ContactError(f"the rigid piston's load path has one piston per side; the "
                         f"geometry has {1 + len(geometry.extra_pistons)}")
    P = CaliperParts(geometry, full)
    rows = _Rows(P)
    for side in P.sides:
        _rim_and_bore(rows, pad_mesh, pad_offset, side)
    if P.floating:
        _fingers(rows, pad_mesh, pad_offset)
    _abutments(rows, pad_mesh, pad_offset)
    K_q, f_q = seal_stiffness(P)
    seal = seal_springs(geometry.piston.guide, 0.5 * geometry.piston.diameter)
    info = {"seal": {k: v for k, v in seal.items()}, "rows": len(rows.rows), "dofs": P.nq}
    out = rows.build(col, n_dofs, K_q, f_q, info)
    logger.info("caliper rows: %d (%d normal), %d rigid DOFs", out.n, int(out.normal.sum()),
                P.nq)
    return out




