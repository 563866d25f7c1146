"""The bodies of a tribometer test, meshed fine at the contact and condensed onto it.

A test has two bodies: the *slave* (the one that stays in the contact's frame:
the flat of a fretting test, the pin, the block) below its contact face, and
the *master* (the counterface that moves through the contact: the cylinder,
the disc, the ring) above it.  Each is meshed with triangles (plane strain)
or tetrahedra, refined where it touches: a coarse box is refined (skfem's
conforming adaptive refinement) until every element is smaller than ``h``
plus ``growth`` times its distance from the contact zone, then mapped to the
body's shape (a cylinder's or sphere's face, a ring).  Away from the contact
the elements grow geometrically, so a body many contact widths across costs
little more than its contact zone.

Each body is then condensed onto its contact-face nodes: one sparse
factorisation of its stiffness (fixed where it is supported) and one solve
per face DOF give the compliance ``C`` (m/N) of the face under nodal forces,
which is all the frictional contact needs (:mod:`brakewear.contact.friction`).
The factorisation is kept for the displacement fields written to the VTU
files.
"""
from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem as fem
from skfem.models.elasticity import lame_parameters, linear_elasticity

from ..errors import MeshError
from ..fem.assembly import assemble_stiffness
from ..materials import Isotropic
from ..mesh.surface import tributary_areas
from ..solvers.threads import blas_threads

logger = logging.getLogger(__name__)

__all__ = ["Body", "box_mesh", "block", "ring", "condense", "mirrored", "face_interpolation",
           "face_triangles"]


@dataclass
class Body:
    """One body of a test, condensed onto its contact face.

    Attributes
    ----------
    name : str
    mesh : skfem.MeshTri or skfem.MeshTet
        In the body's own coordinates (the contact face near height 0).
    material : Isotropic
    face : ndarray
        Node numbers of the contact-face nodes (sorted by x in plane strain).
    x : ndarray
        (dim, n) their coordinates (m).
    area : ndarray
        (n,) their tributary lengths (plane strain, m) or areas (m^2).
    compliance : ndarray
        (n dim, n dim) displacement of the face nodes per unit nodal force
        (m/N), per node the components (x[, y], z).
    whole_face : bool
        The contact face is the body's whole end (a flat pin): its rim is the
        body's edge, not the edge of a finely meshed zone.
    """

    name: str
    mesh: fem.Mesh
    material: Isotropic
    face: np.ndarray
    x: np.ndarray
    area: np.ndarray
    compliance: np.ndarray
    whole_face: bool = False
    _solve: Callable = field(repr=False, default=None)
    nodal_dofs: np.ndarray = field(repr=False, default=None)

    @property
    def dim(self) -> int:
        return self.mesh.p.shape[0]

    def displacement(self, forces: np.ndarray) -> np.ndarray:
        """(nnodes, dim) displacement field under the face forces ``forces``
        ((n, dim), N) -- for the output files."""
        f = np.zeros(self.nodal_dofs.shape[1] * self.dim)
        f[self.nodal_dofs[:, self.face].T.ravel()] = np.asarray(forces, dtype=float).ravel()
        return self._solve(f)[self.nodal_dofs].T


def mirrored(body: Body, name: str) -> Body:
    """The mirror image of ``body`` through its contact face's plane (z -> -z): the
    same compliance with the signs of its normal-tangential terms flipped, at the
    cost of none of its solves.  Two bodies of one material and shape on either
    side of a flat contact are a body and its mirror."""
    d = body.dim
    sign = np.tile(np.r_[np.ones(d - 1), -1.0], body.face.size)
    p = body.mesh.p.copy()
    p[-1] *= -1.0
    t = body.mesh.t.copy()
    t[[0, 1]] = t[[1, 0]]                        # keep the elements' orientation
    mesh = type(body.mesh)(p, t)

    def solve(f):
        flip = np.ones_like(f)
        flip[body.nodal_dofs[-1]] = -1.0
        return flip * body._solve(flip * f)

    return Body(name=name, mesh=mesh, material=body.material, face=body.face,
                x=p[:, body.face], area=body.area,
                compliance=sign[:, None] * body.compliance * sign[None, :], _solve=solve,
                nodal_dofs=body.nodal_dofs)


def _diameters(mesh: fem.Mesh) -> np.ndarray:
    e = mesh.p[:, mesh.t]
    k = mesh.t.shape[0]
    return np.max([np.linalg.norm(e[:, i] - e[:, j], axis=0)
                   for i in range(k) for j in range(i + 1, k)], axis=0)


def box_mesh(half_width: float, depth: float, zone: float, h: float, dim: int,
             growth: float = 0.35, below: bool = True, max_elements: int = 400_000) -> fem.Mesh:
    """A box ``|x| (, |y|) <= half_width`` from the contact face at 0 to ``-depth``
    (``below``) or ``+depth``, refined to ``h`` on the face within ``zone`` of
    the centre and graded by ``growth`` away from it.

    Raises
    ------
    MeshError
        Sizes that do not fit, or a mesh that would pass ``max_elements``.
    """
    if not (0 < h <= zone <= 1.5 * half_width and h < depth):
        raise MeshError(f"box_mesh: need 0 < h <= zone <= 1.5 half_width and h < depth; got h = "
                        f"{h:g} m, zone = {zone:g} m, half_width = {half_width:g} m, "
                        f"depth = {depth:g} m")
    n0 = max(2, int(round(half_width / min(half_width, depth))))
    side = np.linspace(-half_width, half_width, 2 * n0 + 1)
    nz = max(1, int(round(depth / (half_width / n0))))
    zs = np.linspace(-depth, 0.0, nz + 1) if below else np.linspace(0.0, depth, nz + 1)
    mesh = (fem.MeshTri.init_tensor(side, zs) if dim == 2
            else fem.MeshTet.init_tensor(side, side, zs))
    quiet = logging.getLogger("skfem.mesh.mesh")       # its refinement reorders arrays and says so
    level = quiet.level
    quiet.setLevel(logging.ERROR)
    try:
        return _refine(mesh, zone, h, dim, growth, max_elements)
    finally:
        quiet.setLevel(level)


def _refine(mesh, zone, h, dim, growth, max_elements):
    for _ in range(60):
        c = mesh.p[:, mesh.t].mean(axis=1)
        lateral = (np.abs(c[0]) if dim == 2 else np.hypot(c[0], c[1])) - zone
        dist = np.hypot(np.clip(lateral, 0.0, None), c[-1])
        marked = np.flatnonzero(_diameters(mesh) > (h + growth * dist) * (1.0 if dim == 2
                                                                           else 1.42))
        if not marked.size:
            break
        if mesh.t.shape[1] + 4 * marked.size > max_elements:
            raise MeshError(f"box_mesh: refining to h = {h:g} m over a zone of {zone:g} m "
                            f"passes {max_elements} elements; coarsen the contact mesh")
        mesh = mesh.refined(marked)
    return type(mesh)(np.ascontiguousarray(mesh.p), np.ascontiguousarray(mesh.t))


def block(name: str, material: Isotropic, half_width: float, depth: float, zone: float,
          h: float, dim: int, below: bool, profile: Callable | None = None,
          growth: float = 0.35, round_section: bool = False) -> Body:
    """A body meshed as a box (:func:`box_mesh`), its contact face at height 0 bent to
    ``profile`` (the face height, m, a function of x -- or of x, y in 3D), clamped
    on its far side, condensed onto the face nodes within ``zone``.

    The face of a cylinder or a sphere is the box's face lifted (``below = False``:
    the body above) or lowered by its profile, and the box's nodes follow with a
    weight that falls linearly to the far side, so the elements stay regular.
    ``round_section`` (3D): the box's square section mapped onto the disc of
    radius ``half_width`` (a cylindrical pin); its whole face is the contact face.
    """
    mesh = box_mesh(half_width, depth, zone if not round_section else half_width * 1.5,
                    h, dim, growth=growth, below=below)
    onface = np.isclose(mesh.p[-1], 0.0, atol=1e-9 * depth)
    if round_section:
        p = mesh.p.copy()
        u, v = p[0] / half_width, p[1] / half_width
        p[0] = half_width * u * np.sqrt(1.0 - v * v / 2.0)
        p[1] = half_width * v * np.sqrt(1.0 - u * u / 2.0)
        mesh = type(mesh)(p, np.ascontiguousarray(mesh.t))
        near = np.ones(mesh.nvertices, bool)
    else:
        lateral = mesh.p[:-1]
        near = (np.abs(lateral[0]) if dim == 2 else np.hypot(*lateral)) <= zone * (1 + 1e-9)
    lateral = mesh.p[:-1]
    face = np.flatnonzero(onface & near)
    if profile is not None:
        z = np.asarray(profile(*lateral), dtype=float)
        p = mesh.p.copy()
        p[-1] = p[-1] + z * (1.0 - np.abs(mesh.p[-1]) / depth)
        mesh = type(mesh)(p, np.ascontiguousarray(mesh.t))
    far = np.flatnonzero(np.isclose(mesh.p[-1], -depth if below else depth))
    if dim == 2:
        face = face[np.argsort(mesh.p[0, face])]
    body = condense(name, mesh, material, face, far)
    body.whole_face = round_section
    return body


def ring(name: str, material: Isotropic, radius: float, bore: float, zone: float, h: float,
         growth: float = 0.35) -> Body:
    """The half of a ring (outer radius ``radius``, bore ``bore``) that faces the
    contact, in plane strain: its lowest point at the origin, its centre at
    (0, radius); clamped on its bore, free at its horizontal diameter.  Meshed
    as a box in (arc length, depth) refined at the contact and bent onto the ring.
    """
    if not 0 < bore < radius:
        raise MeshError(f"ring: need 0 < bore < radius; got bore = {bore:g} m, radius = "
                        f"{radius:g} m")
    mesh = box_mesh(0.5 * np.pi * radius, radius - bore, zone, h, 2, growth=growth, below=False)
    s_, t_ = mesh.p
    theta, rho = s_ / radius, radius - t_
    p = np.vstack([rho * np.sin(theta), radius - rho * np.cos(theta)])
    face = np.flatnonzero(np.isclose(t_, 0.0) & (np.abs(s_) <= zone * (1 + 1e-9)))
    face = face[np.argsort(p[0, face])]
    bored = np.flatnonzero(np.isclose(t_, radius - bore))
    return condense(name, type(mesh)(p, np.ascontiguousarray(mesh.t)), material, face, bored)


def face_triangles(body: Body) -> np.ndarray:
    """(3, nt) the triangles of a 3D body's contact face, in its face numbering."""
    inside = np.full(body.mesh.nvertices, -1)
    inside[body.face] = np.arange(body.face.size)
    bf = body.mesh.boundary_facets()
    f = body.mesh.facets[:, bf]
    keep = np.all(inside[f] >= 0, axis=0)
    return inside[f[:, keep]]


def _stiffness(mesh: fem.Mesh, material: Isotropic):
    dim = mesh.p.shape[0]
    if dim == 3:
        K, _ = assemble_stiffness(mesh, material)
        basis = fem.Basis(mesh, fem.ElementVector(fem.ElementTetP1()))
        return sp.csr_matrix(K), basis
    basis = fem.Basis(mesh, fem.ElementVector(fem.ElementTriP1()))
    lam, mu = lame_parameters(material.E, material.nu)      # 2D: plane strain
    return linear_elasticity(lam, mu).assemble(basis).tocsr(), basis


def condense(name: str, mesh: fem.Mesh, material: Isotropic, face: np.ndarray,
             fixed: np.ndarray, chunk: int = 256) -> Body:
    """Factorise the body's stiffness (``fixed``: node numbers clamped in all
    components) and condense it onto the ``face`` nodes.

    Returns
    -------
    Body
        With the face's compliance and tributary areas.
    """
    dim = mesh.p.shape[0]
    K, basis = _stiffness(mesh, material)
    dofs = basis.nodal_dofs                                  # (dim, nnodes)
    fixed_dofs = dofs[:, np.asarray(fixed)].ravel()
    free = np.setdiff1d(np.arange(K.shape[0]), fixed_dofs)
    lu = spla.splu(sp.csc_matrix(K[free][:, free]), permc_spec="MMD_AT_PLUS_A")
    face = np.asarray(face)
    fd = dofs[:, face].T.ravel()                             # per node (x[, y], z)
    pos = np.full(K.shape[0], -1)
    pos[free] = np.arange(free.size)
    if np.any(pos[fd] < 0):
        raise MeshError(f"condense: a contact-face node of the {name} is also clamped")
    C = np.empty((fd.size, fd.size))
    with blas_threads(1):          # SuperLU's solves: OpenBLAS's threads only spin here
        for i in range(0, fd.size, chunk):
            cols = fd[i:i + chunk]
            B = np.zeros((free.size, cols.size))
            B[pos[cols], np.arange(cols.size)] = 1.0
            C[:, i:i + cols.size] = lu.solve(B)[pos[fd]]
    C = 0.5 * (C + C.T)

    def solve(f):
        u = np.zeros(K.shape[0])
        u[free] = lu.solve(f[free])
        return u

    if dim == 2:
        xs = mesh.p[0, face]
        seg = np.diff(xs)
        area = 0.5 * (np.concatenate([[0.0], seg]) + np.concatenate([seg, [0.0]]))
        # the end nodes carry the half segment beyond them too (the face goes on)
        area[0] += 0.5 * seg[0]
        area[-1] += 0.5 * seg[-1]
    else:
        area = _face_areas(mesh, face)
    logger.info("condensed the %s: %d DOFs onto %d face nodes", name, K.shape[0], face.size)
    return Body(name=name, mesh=mesh, material=material, face=face, x=mesh.p[:, face],
                area=area, compliance=C, _solve=solve, nodal_dofs=dofs)


def _face_areas(mesh: fem.Mesh, face: np.ndarray) -> np.ndarray:
    """Tributary areas of the face nodes: a third of each boundary triangle whose
    three nodes are face nodes."""
    inside = np.zeros(mesh.nvertices, bool)
    inside[face] = True
    bf = mesh.boundary_facets()
    f = bf[np.all(inside[mesh.facets[:, bf]], axis=0)]
    return tributary_areas(mesh, f, face)


def face_interpolation(master: np.ndarray, slave: np.ndarray, tris: np.ndarray | None = None
                       ) -> sp.csr_matrix:
    """(n_slave, n_master) linear interpolation of the master face at the slave points.

    Plane strain: ``master``, ``slave`` are x coordinates (master sorted);
    3D: (2, n) x, y coordinates and ``tris`` (3, nt) the master face's triangles.
    A slave point outside the master face gets an empty row.
    """
    if tris is None:
        xm, xs = np.asarray(master), np.asarray(slave)
        j = np.clip(np.searchsorted(xm, xs) - 1, 0, xm.size - 2)
        t = (xs - xm[j]) / (xm[j + 1] - xm[j])
        inside = (t >= -1e-9) & (t <= 1 + 1e-9)
        t = np.clip(t, 0.0, 1.0)
        rows = np.repeat(np.arange(xs.size), 2)
        cols = np.column_stack([j, j + 1]).ravel()
        vals = (np.column_stack([1 - t, t]) * inside[:, None]).ravel()
        return sp.csr_matrix((vals, (rows, cols)), shape=(xs.size, xm.size))
    m2 = fem.MeshTri(np.ascontiguousarray(master, dtype=float), np.ascontiguousarray(tris))
    pts = np.asarray(slave, dtype=float)
    elem = m2.element_finder()(pts[0], pts[1])
    corners = m2.p[:, m2.t[:, elem]]                          # (2, 3, n)
    T = np.stack([corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]], axis=1)
    lam = np.linalg.solve(T.transpose(2, 0, 1), (pts - corners[:, 0]).T[:, :, None])[:, :, 0]
    w = np.column_stack([1 - lam.sum(axis=1), lam])
    rows = np.repeat(np.arange(pts.shape[1]), 3)
    return sp.csr_matrix((w.ravel(), (rows, m2.t[:, elem].T.ravel())),
                         shape=(pts.shape[1], m2.p.shape[1]))
