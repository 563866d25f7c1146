"""Geometry update of worn surfaces: move the faces, let the layer beneath follow.

The wear loop gives a worn depth ``h >= 0`` at every node of a worn surface
(the pad's and the rotor's ``friction`` facets).  Two ways to account for it:

* *gap offset* (``brakewear.wear``): the meshes stay and ``h`` is added to
  the contact gap -- cheap, valid while ``h`` is far below the element size;
* *geometry update* (this module): every surface node moves by ``h`` along
  the inward normal, and the nodes beneath follow with a weight that falls
  linearly from 1 at the surface to 0 at a chosen depth ``D`` (the *band*).
  A column of elements inside the band is compressed uniformly by the
  factor ``1 - h/D``, which is the gentlest compression that moves the face
  by ``h`` and keeps everything below ``D`` in place.  Elements with a moved
  vertex are the only ones whose stiffness changes, so only they are
  integrated again (:func:`brakewear.fem.stiffness_update`).

The motion is always computed from the *reference* (unworn) coordinates and
the *cumulative* wear, so repeated updates do not drift, and a step can be
redone with other depths.  A quality guard checks every moved element and
refuses the update (nothing is changed) if one is inverted or degenerate.
"""
from __future__ import annotations

import logging
import time

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..contact.surface import mortar_coupling
from ..errors import MeshError, MeshQualityError, MotionError
from ..fem.assembly import assemble_stiffness, stiffness_update
from ..mesh.quadratic import quadratic_face_areas
from ..mesh.skfem_compat import moved_mesh
from ..mesh.surface import is_quadratic, quadratic_faces, surface_nodes, tributary_areas
from ..mesh.topology import facet_indices
from .follower import SurfaceFollower

logger = logging.getLogger(__name__)

__all__ = [
    "element_volumes",
    "element_quality",
    "check_quality",
    "surface_element_height",
    "segment_average",
    "SurfaceFollower",
    "BrakeMotion",
    "DEFAULT_MIN_QUALITY",
]


#: Smallest accepted element quality (mean ratio, 1 = regular tetrahedron).
#: The default brake's meshes start at 0.56 (pad) and 0.13 (rotor); the pad
#: worn to half its friction layer keeps 0.37 (docs/motion.md).  A regular
#: tetrahedron squashed 10x has 0.32, 100x 0.07; 0.02 (about 600x) is degenerate.
DEFAULT_MIN_QUALITY = 0.02


def _corners(mesh: fem.Mesh) -> np.ndarray:
    if mesh.t.shape[0] < 4 or mesh.p.shape[0] != 3:
        raise MeshError(f"need a tetrahedral mesh in 3D; got {type(mesh).__name__} with "
                        f"t of shape {mesh.t.shape}")
    return mesh.p[:, mesh.t[:4]]  # (3, 4, ne)


def element_volumes(mesh: fem.Mesh) -> np.ndarray:
    """Signed volume of every tetrahedron (its straight-sided vertex tetrahedron).

    Positive for the orientation brakewear's meshes are built with; negative
    means inverted.
    """
    X = _corners(mesh)
    a, b, c = X[:, 1] - X[:, 0], X[:, 2] - X[:, 0], X[:, 3] - X[:, 0]
    return np.einsum("ij,ij->j", a, np.cross(b, c, axis=0)) / 6.0


def element_quality(mesh: fem.Mesh) -> np.ndarray:
    """Signed mean-ratio quality of every tetrahedron.

    ``q = sign(V) 12 (3 |V|)^(2/3) / sum of the six squared edge lengths``:
    1 for the regular tetrahedron, tending to 0 as the element flattens or
    degenerates, negative when it is inverted.  It is scale-invariant and
    sees every way a tetrahedron goes bad (flat, needle, sliver), which a
    volume ratio alone does not.
    """
    X = _corners(mesh)
    V = element_volumes(mesh)
    l2 = np.zeros(V.size)
    for i in range(4):
        for j in range(i + 1, 4):
            d = X[:, j] - X[:, i]
            l2 += np.einsum("ij,ij->j", d, d)
    return np.sign(V) * 12.0 * np.cbrt(3.0 * np.abs(V)) ** 2 / np.where(l2 > 0, l2, 1.0)


def check_quality(mesh: fem.Mesh, body: str = "mesh", step=None,
                  min_quality: float = DEFAULT_MIN_QUALITY,
                  elements: np.ndarray | None = None, note: str = "") -> float:
    """Raise :class:`MeshQualityError` if an element's quality is below ``min_quality``.

    Parameters
    ----------
    mesh
        The tetrahedral mesh to check.
    body, step
        Named in the message (the body and the wear step being applied).
    min_quality
        Smallest accepted :func:`element_quality`, in (0, 1).
    elements
        Check only these elements (e.g. the ones that moved); default all.
    note
        Appended to the message (what the caller knows about the cause).

    Returns
    -------
    float
        The smallest quality found (1.0 if no element is checked).
    """
    if not (np.isfinite(min_quality) and 0.0 < min_quality < 1.0):
        raise MotionError(f"min_quality = {min_quality!r} is not allowed; need 0 < min_quality < 1")
    q = element_quality(mesh)
    idx = np.arange(mesh.nelements) if elements is None else np.asarray(elements, dtype=np.int64)
    if idx.size == 0:
        return 1.0
    k = int(idx[np.argmin(q[idx])])
    qmin = float(q[k])
    if not qmin >= min_quality:
        what = "inverted" if qmin < 0 else "degenerate" if qmin == 0 else "too flat or distorted"
        centre = mesh.p[:, mesh.t[:4, k]].mean(axis=1)
        bad = int(np.count_nonzero(q[idx] < min_quality))
        where = f"step {step}" if step is not None else "geometry update"
        raise MeshQualityError(
            f"{where}: {body} element {k} (centroid {np.array2string(centre, precision=5)} m) "
            f"has quality {qmin:.3g} ({what}); need >= min_quality {min_quality:g}; "
            f"{bad} element(s) below the bound" + (f"; {note}" if note else ""),
            step=step, body=body, element=k, quality=qmin, min_quality=min_quality)
    return qmin


def surface_element_height(mesh: fem.Mesh, facets) -> np.ndarray:
    """Height of the elements under each node of a surface.

    For every facet of the set, the height of its element over it (the
    distance from the opposite vertex, ``3 V / A``); per surface node the
    smallest over its facets.  Returned in the order of
    :func:`brakewear.mesh.surface.face_nodes` (on a quadratic mesh the
    mid-edge nodes too).  A wear step should move a node
    by a fraction of this, so that the first layer never collapses.
    """
    facets = facet_indices(mesh, facets)
    f = mesh.facets[:, facets]
    p = mesh.p
    area = 0.5 * np.linalg.norm(np.cross(p[:, f[1]] - p[:, f[0]], p[:, f[2]] - p[:, f[0]],
                                         axis=0), axis=0)
    vol = np.abs(element_volumes(mesh))[mesh.f2t[0, facets]]
    hf = 3.0 * vol / area
    if is_quadratic(mesh):              # every node of a quadratic facet, mid-edge ones too
        f = quadratic_faces(mesh, facets)
    out = np.full(mesh.p.shape[1], np.inf)
    for a in range(f.shape[0]):
        np.minimum.at(out, f[a], hf)
    return out[np.unique(f)]


def segment_average(mesh: fem.Mesh, facets="friction", level: int = 2) -> sp.csr_matrix:
    """The segment (weak) average of a nodal field over a surface, as a matrix.

    ``A[s, a] = int phi_s phi_a dA / int phi_s dA`` over the facets, integrated
    exactly as :func:`brakewear.contact.surface.mortar_coupling` integrates the weak
    gap of a ``method="segment"`` pair.  A face worn by the nodal depths
    ``h`` changes that pair's ``g0`` by ``A @ h`` (not by ``h``: the two differ
    where ``h`` is not constant, most at the face's edges), so a gap-offset
    update consistent with the geometry update adds ``A @ h_pad``.  Rows and
    columns in :func:`brakewear.mesh.surface.surface_nodes` order.
    """
    nodes = surface_nodes(mesh, facets)
    W, _, _ = mortar_coupling(mesh, facets, nodes, mesh, facets, mesh.nvertices, level)
    return W[:, nodes].tocsr()


def _check_wear(name: str, h, n: int, body: str, quadratic: bool = False) -> np.ndarray:
    """Validate a worn-depth array before anything is computed.  On a quadratic
    face the depths are coefficients of its transformed basis, which a depth
    profile with steps (the rotor's rings at the pad's radii) takes slightly
    below zero next to a step: up to 5 % of the largest one is allowed."""
    try:
        arr = np.asarray(h, dtype=float)
    except (TypeError, ValueError):
        raise MotionError(f"{name} must be an array of worn depths (m); got {type(h).__name__}") \
            from None
    if arr.shape != (n,):
        raise MotionError(f"{name} has shape {arr.shape}; need ({n},): one worn depth per node of "
                         f"the {body}'s friction face, in the order of surface_nodes(mesh, "
                         "'friction')")
    bad = np.nonzero(~np.isfinite(arr))[0]
    if bad.size:
        raise MotionError(f"{name}[{bad[0]}] = {float(arr[bad[0]])!r} is not allowed; worn "
                         f"depths must be finite ({bad.size} are not)")
    floor = -0.05 * max(float(arr.max()), 0.0) if quadratic and arr.size else 0.0
    neg = np.nonzero(arr < floor)[0]
    if neg.size:
        raise MotionError(f"{name}[{neg[0]}] = {float(arr[neg[0]])!r} m is not allowed; worn "
                          f"depths must be >= 0 (wear removes material; {neg.size} are "
                          "negative)")
    return arr


class BrakeMotion:
    """Worn geometry of a :class:`brakewear.model.BrakeModel`.

    The meshes of ``model`` when this is built are the reference (unworn)
    geometry.  :meth:`apply` gives the model of the worn geometry for the
    given *cumulative* depths, :attr:`model` (a new
    :class:`~brakewear.model.BrakeModel` from :meth:`BrakeModel.with_geometry`;
    the model passed in is never changed): new meshes of the moved bodies and,
    for the bodies already assembled, their stiffness updated by
    reintegrating only the elements that moved.  After it,
    ``motion.model.contact_system(...)`` is the contact problem of the worn
    brake (its gap ``g0`` holds the wear, since the faces moved apart).

    Parameters
    ----------
    model
        A BrakeModel (P1).  With ``rotor="rigid"`` only the pad moves.
    pad_depth
        Band depth under the pad's friction face (m); default the friction
        layer's thickness, so the backplate never moves.
    rotor_depth
        Band depth under the rotor's friction face (m); default a fifth of
        the meshed half thickness, raised to the next node layer.
    min_quality
        Quality guard (see :func:`element_quality`).
    """

    def __init__(self, model, pad_depth: float | None = None, rotor_depth: float | None = None,
                 min_quality: float = DEFAULT_MIN_QUALITY):
        if not (np.isfinite(min_quality) and 0.0 < min_quality < 1.0):
            raise MotionError(f"min_quality = {min_quality!r} is not allowed; "
                             "need 0 < min_quality < 1")
        self.model = model
        self.min_quality = float(min_quality)
        g = model.geometry
        tf = g.pad.friction_thickness
        pad_depth = tf if pad_depth is None else float(pad_depth)
        if not (np.isfinite(pad_depth) and 0 < pad_depth <= tf * (1 + 1e-9)):
            raise MotionError(f"pad_depth = {pad_depth!r} m is not allowed; need 0 < pad_depth "
                              f"<= the friction layer thickness {tf:g} m (the backplate must "
                              "not move)")
        self.followers: dict[str, SurfaceFollower] = {
            "pad": SurfaceFollower(model.meshes["pad"], "friction", pad_depth)}
        if "rotor" in model.bodies:
            half = 0.5 * g.rotor.thickness
            rotor_depth = 0.2 * half if rotor_depth is None else float(rotor_depth)
            if not (np.isfinite(rotor_depth) and 0 < rotor_depth <= half * (1 + 1e-9)):
                raise MotionError(f"rotor_depth = {rotor_depth!r} m is not allowed; need 0 < "
                                 f"rotor_depth <= the meshed half thickness {half:g} m")
            self.followers["rotor"] = SurfaceFollower(model.meshes["rotor"], "friction",
                                                      rotor_depth)
        self.reference = {b: model.meshes[b].p.copy() for b in self.followers}
        self.pad_wear = np.zeros(self.followers["pad"].nodes.size)
        self.rotor_wear = (np.zeros(self.followers["rotor"].nodes.size)
                           if "rotor" in self.followers else None)
        self.initial_quality = {b: float(element_quality(model.meshes[b]).min())
                                for b in self.followers}
        logger.info("brake motion: bands %s", ", ".join(
            f"{b} {f.depth * 1e3:.3g} mm ({f.band_nodes.size} nodes)"
            for b, f in self.followers.items()))

    @property
    def depths(self) -> dict:
        """Band depth of each moving body (m)."""
        return {b: f.depth for b, f in self.followers.items()}

    def surface_heights(self) -> dict:
        """Current :func:`surface_element_height` of each worn face (m)."""
        return {b: surface_element_height(self.model.meshes[b], "friction")
                for b in self.followers}

    def apply(self, pad_wear, rotor_wear=None, step=None, reassembly: str = "partial") -> dict:
        """Move the worn faces to the cumulative depths given; return figures.

        Parameters
        ----------
        pad_wear
            Worn depth (m, >= 0) of every pad friction node since the
            reference geometry, in ``surface_nodes(pad, "friction")`` order.
        rotor_wear
            The same for the rotor's friction nodes; None means zero.  Must
            be None (or zero) for a rigid rotor.
        step
            Wear step number, named in errors.
        reassembly
            ``"partial"`` (default: reintegrate the moved elements only) or
            ``"full"`` (assemble the whole body again; for checks).

        Returns
        -------
        dict
            ``step``, ``reassembly_s``, ``total_s`` and per moving body
            ``moved_nodes``, ``moved_elements``, ``elements``,
            ``min_quality`` (of the moved elements) and ``max_displacement``.

        Raises
        ------
        MotionError
            Wrong length, negative or non-finite depths (nothing changed).
        MeshQualityError
            A moved element would be inverted or degenerate (nothing changed).
        """
        if reassembly not in ("partial", "full"):
            raise MotionError(f"reassembly = {reassembly!r} is not allowed; "
                             "allowed: 'partial', 'full'")
        t0 = time.perf_counter()
        quad = is_quadratic(self.model.meshes["pad"])
        wear = {"pad": _check_wear("pad_wear", pad_wear, self.followers["pad"].nodes.size, "pad",
                                   quad)}
        if "rotor" in self.followers:
            n = self.followers["rotor"].nodes.size
            wear["rotor"] = np.zeros(n) if rotor_wear is None else _check_wear(
                "rotor_wear", rotor_wear, n, "rotor", quad)
        elif rotor_wear is not None and np.any(np.asarray(rotor_wear, dtype=float) != 0):
            raise MotionError("rotor_wear is not allowed with a rigid rotor (the plane z = 0 does "
                             "not move); pass None")
        model = self.model
        new_meshes, moved_elems, stats = {}, {}, {"step": step}
        for b, fol in self.followers.items():
            old = model.meshes[b]
            p = self.reference[b] + fol.displacement(wear[b])
            moved_n = np.any(p != old.p, axis=0)
            me = np.nonzero(moved_n[old.t].any(axis=0))[0]
            new = moved_mesh(old, p) if me.size else old
            qmin = 1.0
            if me.size:
                h = wear[b]
                qmin = check_quality(
                    new, b, step, self.min_quality, elements=me,
                    note=f"largest worn depth {h.max():.4g} m against the {b}'s moving band of "
                         f"{fol.depth:.4g} m" + (" (worn through the band)"
                                                 if h.max() >= fol.depth else ""))
            new_meshes[b], moved_elems[b] = new, me
            stats[b] = {"moved_nodes": int(moved_n.sum()), "moved_elements": int(me.size),
                        "elements": int(old.nelements), "min_quality": qmin,
                        "max_displacement": float(np.abs(p - self.reference[b]).max())}
        # every check passed: assemble, then commit
        t1 = time.perf_counter()
        newK = {}
        for b, new in new_meshes.items():
            done = model.assembled(b)
            if done is None or moved_elems[b].size == 0:
                continue
            K, pattern = done
            if reassembly == "full":
                newK[b], _ = assemble_stiffness(new, model.materials[b], pattern=pattern)
            else:
                newK[b] = stiffness_update(K, pattern, model.meshes[b], new,
                                           model.materials[b], moved_elems[b])
        t2 = time.perf_counter()
        self.model = model.with_geometry(
            {b: m for b, m in new_meshes.items() if moved_elems[b].size}, newK)
        self.pad_wear = wear["pad"].copy()
        if "rotor" in wear:
            self.rotor_wear = wear["rotor"].copy()
        stats["reassembly"] = reassembly
        stats["reassembly_s"] = t2 - t1
        stats["total_s"] = time.perf_counter() - t0
        logger.info("geometry update%s: %s; reassembly (%s) %.3f s", "" if step is None else
                    f" step {step}", ", ".join(
                        f"{b} {stats[b]['moved_elements']}/{stats[b]['elements']} elements moved, "
                        f"q_min {stats[b]['min_quality']:.3f}" for b in self.followers),
                    reassembly, t2 - t1)
        return stats

    def worn_volume(self) -> dict:
        """Volume removed so far per body, ``sum(h A)`` with the reference tributary areas."""
        out = {}
        for b, fol in self.followers.items():
            ref = moved_mesh(self.model.meshes[b], self.reference[b])
            h = self.pad_wear if b == "pad" else self.rotor_wear
            area = (quadratic_face_areas(ref, "friction")[1] if is_quadratic(ref)
                    else tributary_areas(ref, "friction", fol.nodes))
            out[b] = float((h * area).sum())
        return out
