"""A brake model: components, the interfaces between them, and their loads.

:class:`BrakeModel` builds only what it is asked for: the half model (one pad,
the rotor's inboard half) or the full one (both pads, the whole rotor), the
piston as a body tied to the backplate or as the caliper's footprint loads
(:mod:`brakewear.caliper.loads`); stiffness matrices are assembled once and kept.
Global numbering: the scalar DOFs of the bodies are stacked in the order of
``bodies``; vector DOF ``3 s + i``.  With quadratic meshes (``order=2``) a
body's nodes are its vertices, then its mid-edge nodes; the pad's friction
face is then the slave face of a dual mortar pair
(:mod:`brakewear.contact.quadratic`), the contact system in its transformed
unknowns.

A model is data -- meshes, materials, stiffness matrices, loads, supports and
the contact system -- as a scikit-fem mesh or basis is: it does not solve.  Its
static solves are functions that take it (:func:`brakewear.static.solve_tied`,
:func:`brakewear.static.solve_contact`), as are the wear loop, the thermal
model and the geometry update.
"""
from __future__ import annotations

import copy
import logging
import time
from os import PathLike

import numpy as np
import scipy.sparse as sp

from .caliper.loads import (
    clamp_loads,
    pad_support_dofs,
    resolve_layout,
    uniform_traction,
)
from .checks import check_line_pressure, check_plausible
from .contact.basis import check_supports
from .contact.pairs import (
    ContactPair,
    ContactSystem,
    merge_pairs,
    pair_to_rigid,
    pair_to_surface,
    plane_height,
    rotor_drag,
)
from .contact.quadratic import face_values
from .contact.supports import with_supports
from .contact.surface import project_nodes, tie_prolongation
from .errors import MeshError, MotionError, SceneError
from .fem.assembly import BlockPattern, assemble_stiffness
from .fem.boundary import boundary_dofs
from .geometry.files import load_geometry
from .geometry.parts import BrakeGeometry
from .mesh.brake import (
    component_materials,
    element_materials,
    pad_mesh,
    piston_mesh,
    rotor_mesh,
)
from .mesh.estimate import check_model_size
from .mesh.io import read_body_mesh
from .mesh.mirror import mirrored_pads, whole_thickness_meshes
from .mesh.quadratic import quadratic_face_areas, slave_basis
from .mesh.surface import face_nodes, is_quadratic, quadratic_faces, tributary_areas

logger = logging.getLogger(__name__)

__all__ = ["BrakeModel"]

_MESHERS = {"rotor": rotor_mesh, "pad": pad_mesh, "piston": piston_mesh}


class BrakeModel:
    """The default brake (or any geometry file) as a set of tied bodies.

    Parameters
    ----------
    geometry
        A :class:`BrakeGeometry` or the name/path of a geometry file.
    rotor
        ``"elastic"`` (meshed, clamped at its hat radius) or ``"rigid"`` (the
        plane z = 0; nothing meshed).
    piston
        ``"traction"`` (default: the clamp force as a uniform traction on the
        backplate's piston footprint), ``"body"`` (the piston meshed, tied to
        the backplate) or ``"rigid"`` (a rigid piston in its bore and seal,
        rim, fingers and abutments one-sided with friction: the caliper's
        load path, :mod:`brakewear.caliper.rows`).
    size, order
        Mesh size (m) and element order; default from the geometry file.
        The size is checked before meshing: in (0, half the radial pad width]
        and small enough for ``memory_budget`` (GB; default
        ``BRAKEWEAR_MEMORY_GB`` or the available memory), see
        :func:`brakewear.mesh.estimate.check_model_size`.
    layout
        ``"half"``: one pad and the rotor's inboard half with a mirror plane,
        exact where both pads get the same load (a fixed caliper with equal
        opposed pistons) and the rotor is symmetric about its mid-plane;
        ``"full"``: both pads (one mesh, the outboard pad the mirror image of
        the inboard one, :func:`~brakewear.mesh.mirror.mirrored_pads`) and the
        whole rotor thickness, both friction faces in contact; ``"auto"``
        (default): ``"half"`` where its assumption holds, else ``"full"``.
    meshes
        Your own meshes for some bodies: body -> mesh file (gmsh ``.msh`` or
        any format :func:`~brakewear.mesh.read_mesh` reads) or ``skfem``
        mesh, with the named surfaces and volumes of :data:`MESH_GROUPS`;
        the other bodies are meshed from the geometry.
    memory_budget
        GB the model may use (None: ``BRAKEWEAR_MEMORY_GB`` or the available
        memory): the mesh size is checked against it before meshing.
    """

    def __init__(self, geometry: BrakeGeometry | str = "default", piston: str = "traction",
                 size: float | None = None, order: int | None = None, rotor: str = "elastic",
                 meshes: dict | None = None, memory_budget: float | None = None,
                 layout: str = "auto"):
        if piston not in ("traction", "body", "rigid"):
            raise SceneError(f"piston = {piston!r} is not allowed; allowed: 'traction', 'body', "
                             "'rigid'")
        if rotor not in ("elastic", "rigid"):
            raise SceneError(f"rotor = {rotor!r} is not allowed; allowed: 'elastic', 'rigid'")
        self.rotor = rotor
        self.geometry = geometry if isinstance(geometry, BrakeGeometry) else load_geometry(geometry)
        self.layout = resolve_layout(self.geometry, layout, rotor, strict=True)
        #: whether both pads and the whole rotor thickness are modelled
        self.full = self.layout == "full"
        order = self.geometry.mesh.order if order is None else order
        if isinstance(order, bool) or order not in (1, 2):
            raise SceneError(f"order = {order!r} is not allowed; allowed: 1, 2")
        self.order = int(order)
        self.piston = piston
        # a rigid rotor is the plane z = 0, not a mesh
        self.bodies = (("rotor",) if rotor == "elastic" else ()) + ("pad",) + (
            ("piston",) if piston == "body" else ())
        if unknown := sorted(set(meshes or {}) - set(self.bodies)):
            raise SceneError(f"meshes: {unknown[0]!r} is not a meshed body of this model; "
                             f"bodies: {', '.join(self.bodies)}")
        given = {b: read_body_mesh(m, b, piston) if isinstance(m, (str, PathLike)) else m
                 for b, m in (meshes or {}).items()}
        if self.full:
            given = whole_thickness_meshes(given, -0.5 * self.geometry.rotor.thickness)
        check_model_size(self.geometry, size, rotor, piston, key="size", unit="m",
                         budget_gb=memory_budget, budget_key="memory_budget",
                         nodes={b: m.p.shape[1] for b, m in given.items()}, order=order,
                         full=self.full)
        t0 = time.perf_counter()
        self.meshes = {b: given[b] if b in given else self._mesh(b, size, order)
                       for b in self.bodies}
        if wrong := [b for b, m in self.meshes.items() if is_quadratic(m) != (self.order == 2)]:
            raise SceneError(f"meshes: the {wrong[0]} mesh is not of order {self.order}; every "
                             "body of a model has the model's order")
        mats = component_materials(self.geometry)
        self.materials = {b: element_materials(self.meshes[b], mats[b]) for b in self.bodies}
        self.timings = {"mesh_s": time.perf_counter() - t0}
        self._number()
        self._K: dict[str, sp.spmatrix] = {}
        self._patterns: dict[str, BlockPattern] = {}

    def _mesh(self, body: str, size, order):
        if body == "rotor" and self.full:
            return rotor_mesh(self.geometry, size=size, order=order, full=True)
        m = _MESHERS[body](self.geometry, size=size, order=order)
        if body == "pad" and self.full:
            m = mirrored_pads(m, -0.5 * self.geometry.rotor.thickness)
        return m

    # ------------------------------------------------------------ pieces --
    @property
    def dofs(self) -> int:
        return 3 * self.n_nodes

    def stiffness(self, body: str) -> sp.spmatrix:
        """The body's stiffness (assembled on first use, then reused)."""
        if body not in self._K:
            K, pat = assemble_stiffness(self.meshes[body], self.materials[body],
                                        pattern=self._patterns.get(body))
            self._K[body], self._patterns[body] = K, pat
        return self._K[body]

    def assembled(self, body: str):
        """``(K, pattern)`` of a body whose stiffness is already assembled, else None
        (nothing is assembled here)."""
        if body not in self._K:
            return None
        return self._K[body], self._patterns[body]

    def with_geometry(self, meshes: dict, stiffness: dict | None = None) -> BrakeModel:
        """The same brake with some bodies' meshes replaced by moved ones (same
        topology, e.g. worn faces, :class:`~brakewear.motion.brake.BrakeMotion`).

        ``stiffness`` holds the moved bodies' stiffness where it is known; the
        others are assembled on first use.  Unchanged bodies share their
        meshes and matrices with this model, which itself is not changed.
        """
        for b, m in meshes.items():
            old = self.meshes.get(b)
            if old is None or m.t.shape != old.t.shape or m.p.shape != old.p.shape:
                raise MotionError(f"{b}: a moved mesh must have the topology of the model's "
                                  "mesh (same nodes and elements)")
        new = copy.copy(self)
        new.meshes = {**self.meshes, **meshes}
        new._K = {b: K for b, K in self._K.items() if b not in meshes}
        new._K.update(stiffness or {})
        new._patterns = dict(self._patterns)   # the block patterns follow the topology
        return new

    def remeshed(self, meshes: dict, order: int) -> BrakeModel:
        """The same brake (geometry, bodies, layout, element materials) on other meshes
        of every body, of element ``order`` (renumbered, nothing assembled)."""
        if set(meshes) != set(self.bodies):
            raise MeshError(f"remeshed: need a mesh of every body: {', '.join(self.bodies)}")
        new = copy.copy(self)
        new.order, new.meshes = int(order), dict(meshes)
        new._number()
        new._K, new._patterns = {}, {}
        return new

    def _number(self) -> None:
        """The global node numbering: the bodies' nodes stacked in ``bodies`` order."""
        self.offsets, self.n_nodes = {}, 0
        for b in self.bodies:
            self.offsets[b] = self.n_nodes
            self.n_nodes += self.meshes[b].p.shape[1]

    def _gdofs(self, body: str, local: np.ndarray) -> np.ndarray:
        return np.asarray(local) + 3 * self.offsets[body]

    def coordinates(self) -> np.ndarray:
        return np.hstack([self.meshes[b].p for b in self.bodies])

    def ties(self, interface: bool = True) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """(slave nodes, master nodes (3, n), weights (3, n)) in global node numbers.

        ``interface`` includes the pad-rotor tie (elastic rotor only).
        """
        out = []
        faces = ("friction_in", "friction_out") if self.full else ("friction",)
        pairs = [("pad", f, "rotor", f) for f in faces] if (
            interface and self.rotor == "elastic") else []
        if self.piston == "body":
            pairs.append(("piston", "piston_face", "pad", "back_in" if self.full else "back"))
        for sb, sf, mb, mf in pairs:
            smesh, mmesh = self.meshes[sb], self.meshes[mb]
            slave = face_nodes(smesh, sf)
            if mb == "rotor":     # chamfers leave the plane: only the face in touch is tied
                plane = -self.geometry.rotor.thickness if sf == "friction_out" else 0.0
                slave = slave[
                    np.abs(smesh.p[2, slave] - plane) < 1e-9 * self.geometry.pad.thickness
                ]
            proj = project_nodes(smesh.p[:, slave], mmesh, mf,
                                 search_radius=0.5 * self.geometry.mesh.size + 1e-9)
            nodes, weights, _ = face_values(mmesh, mf, proj)
            out.append((slave + self.offsets[sb], nodes + self.offsets[mb], weights))
        return out

    def loads(self, line_pressure: float) -> np.ndarray:
        """Global load vector for a line pressure (Pa): the clamp force
        ``p x clamp_area`` on each pad's back (:func:`~brakewear.caliper.loads.clamp_loads`);
        with a meshed piston its inboard share on the piston's back face."""
        f = np.zeros(self.dofs)
        g = self.geometry
        pad = self.meshes["pad"]
        if self.piston == "rigid":      # the caliper's rows carry the load to the pads
            return f
        if self.piston == "body":
            pm = self.meshes["piston"]
            fb = uniform_traction(pm, "piston_back", line_pressure * g.piston.hydraulic_area)
            f[3 * self.offsets["piston"]:3 * self.offsets["piston"] + fb.size] = fb
        fb = clamp_loads(g, pad, line_pressure, self.full,
                         sides=("out",) if self.piston == "body" else ("in", "out"))
        f[3 * self.offsets["pad"]:3 * self.offsets["pad"] + fb.size] = fb
        return f

    def fixed_dofs(self) -> np.ndarray:
        """Supports: the rotor's clamp (and mid-plane symmetry in the half
        model), a bilateral pad support, the piston guided by its bore."""
        parts = [self._gdofs("pad", pad_support_dofs(self.geometry, self.meshes["pad"]))]
        if self.rotor == "elastic":
            parts.append(self._gdofs("rotor", boundary_dofs(self.meshes["rotor"], "rotor_clamp")))
            if not self.full:
                parts.append(self._gdofs("rotor", boundary_dofs(self.meshes["rotor"], "midplane",
                                                                [2])))
        if self.piston == "body":
            pm = self.meshes["piston"]
            side = boundary_dofs(pm, "piston_side", [0, 1])
            # the rim of the piston face is tied to the backplate, not guided
            side = side[~np.isin(side // 3, face_nodes(pm, "piston_face"))]
            parts.append(self._gdofs("piston", side))
        return np.unique(np.concatenate(parts))

    # ------------------------------------------------------------- solve --
    def tie_reduction(self, tie_interface: bool):
        """The stiffness and the elimination of the ties (``tie_interface``: the pad's
        friction face to the rotor too): ``(K, P, retained nodes, node -> retained)``."""
        K = sp.block_diag([self.stiffness(b).tocsr() for b in self.bodies], format="csr")
        ties = self.ties(interface=tie_interface)
        if ties:
            Pn, retained = tie_prolongation(self.n_nodes, np.concatenate([s for s, _, _ in ties]),
                                            np.hstack([m for _, m, _ in ties]),
                                            np.hstack([w for _, _, w in ties]))
        else:
            Pn, retained = sp.identity(self.n_nodes, format="csr"), np.arange(self.n_nodes)
        P = sp.kron(Pn, sp.identity(3), format="csr")
        col = -np.ones(self.n_nodes, dtype=np.int64)
        col[retained] = np.arange(retained.size)
        return K, P, retained, col

    def reduced_fixed_dofs(self, col: np.ndarray, extra: np.ndarray | None = None
                           ) -> np.ndarray:
        """The supported DOFs (:meth:`fixed_dofs`, and ``extra``) in the retained
        numbering ``col`` of :meth:`tie_reduction`."""
        fixed = self.fixed_dofs() if extra is None else np.union1d(self.fixed_dofs(), extra)
        node, comp = fixed // 3, fixed % 3
        if np.any(col[node] < 0):
            raise SceneError("a supported DOF lies on a tied (eliminated) node; "
                             "supports and ties must not overlap")
        return 3 * col[node] + comp

    def by_body(self, u: np.ndarray) -> dict:
        """The displacement ``u`` (all DOFs) of each body: name -> its DOFs."""
        return {b: u[3 * self.offsets[b]:3 * (self.offsets[b] + self.meshes[b].p.shape[1])]
                for b in self.bodies}

    def friction_forces(self, r: np.ndarray):
        """The pad's friction nodes, the nodal forces (3, n) of the residual ``r``
        (all DOFs) on them and their areas.  On a quadratic face, in the
        transformed basis of its contact pair (:mod:`brakewear.mesh.quadratic`):
        there a uniform pressure gives every node its share of the area."""
        pad, off = self.meshes["pad"], self.offsets["pad"]
        nodes = face_nodes(pad, "friction")
        if is_quadratic(pad):
            r = slave_basis(quadratic_faces(pad, "friction"), off).dof_matrix(r.size).T @ r
        return nodes, r.reshape(-1, 3)[nodes + off].T, self.friction_areas()

    def friction_areas(self) -> np.ndarray:
        """Area of each pad friction node (``face_nodes(pad, "friction")`` order):
        tributary areas, or on a quadratic face the integrals of its transformed
        basis (:mod:`brakewear.contact.basis`)."""
        pad = self.meshes["pad"]
        if is_quadratic(pad):
            return quadratic_face_areas(pad, "friction")[1]
        return tributary_areas(pad, "friction", face_nodes(pad, "friction"))

    def rotor_normal_z(self, nodes: np.ndarray) -> np.ndarray:
        """z of the rotor face's normal toward the pad at pad friction ``nodes``:
        +1 on the inboard face, -1 on the outboard face of the full model (the
        compressive normal force on a node is its force's z times this)."""
        nz = np.ones(nodes.size)
        if self.full:
            nz[np.isin(nodes, face_nodes(self.meshes["pad"], "friction_out"))] = -1.0
        return nz

    def contact_pair(self, mu: float = 0.0, method: str = "segment",
                     search_radius: float | None = None) -> ContactPair:
        """The pad-rotor contact pair in global node numbers (rotor turning in +theta).

        ``search_radius`` (m): how far from the rotor face a pad node may lie and
        still be paired (default twice the mesh size; a worn geometry needs
        more: the worn depths open the gap).
        """
        drag = rotor_drag
        pad, off = self.meshes["pad"], self.offsets["pad"]
        if self.rotor == "rigid":
            return pair_to_rigid(pad, "friction", off, height=plane_height,
                                 side=1, mu=mu, drag=drag, name="pad-rotor")
        radius = 2.0 * self.geometry.mesh.size + 1e-9 if search_radius is None else search_radius
        faces = ("friction_in", "friction_out") if self.full else ("friction",)
        return merge_pairs([pair_to_surface(pad, f, off, self.meshes["rotor"], f,
                                            self.offsets["rotor"], mu=mu, drag=drag,
                                            method=method, n_nodes=self.n_nodes,
                                            search_radius=radius, name=f"pad-rotor {f}")
                            for f in faces], name="pad-rotor")

    def contact_system(self, line_pressure: float = 1e6, mu: float = 0.0,
                       method: str = "segment", search_radius: float | None = None
                       ) -> ContactSystem:
        """The assembled pad-rotor contact problem, for the Lagrange contact solve.

        :func:`brakewear.contact.lagrange.solve_contact` takes it.  Ties (piston) are
        already eliminated; node numbers are the retained ones.  A wear loop keeps this and
        only changes ``pair.g0``.
        """
        check_line_pressure(line_pressure)
        if not (np.isfinite(mu) and mu >= 0):
            raise SceneError(f"mu = {mu!r} is not allowed; need a friction coefficient >= 0")
        check_plausible("mu", float(mu), "interface.mu")
        K, P, retained, col = self.tie_reduction(tie_interface=False)
        f = self.loads(line_pressure)
        pair = self.contact_pair(mu, method, search_radius)
        if pair.basis is not None:
            # a quadratic friction face: the system in its transformed unknowns, u = T P x
            T = pair.basis.dof_matrix(self.dofs)
            check_supports(pair.basis.dof_matrix(self.dofs, inverse=True), self.fixed_dofs())
            P = (T @ P).tocsr()
            pair.basis = None
        pair.slave = col[pair.slave]
        if pair.coupling is not None:
            pair.coupling = pair.coupling[:, retained].tocsr()
        cs = ContactSystem(K=(P.T @ K @ P).tocsr(), f=P.T @ f, fixed=self.reduced_fixed_dofs(col),
                           coords=self.coordinates()[:, retained], pair=pair, P=P,
                           col=col, clamp_force=line_pressure * self.geometry.clamp_area)
        g = self.geometry
        return with_supports(cs, self.meshes["pad"], self.offsets["pad"], g.pad, g.support)
