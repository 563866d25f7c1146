"""Mesh files in and out: meshio formats with the named surfaces of brakewear.

:func:`write_mesh` writes a mesh (and point or cell data) with its named facet
sets and subdomains; :func:`read_mesh` reads tetrahedral meshes back, with
the named sets restored from the file's tags.  ``.msh`` is gmsh 2.2 with
physical groups (never meshio's default for the suffix, ANSYS Fluent);
:func:`read_body_mesh` reads a user's mesh of one brake body and checks that
it has the named groups the model needs (:data:`MESH_GROUPS`).
"""
from __future__ import annotations

import logging
from collections.abc import Sequence
from os import PathLike
from pathlib import Path

import numpy as np
import skfem as fem

from ..errors import MeshError, MeshFileError
from .skfem_compat import decode_cell_data, encode_cell_data, mesh_with_sets
from .structured import _oriented
from .topology import _with_boundaries, _with_subdomains, ensure_topology

logger = logging.getLogger(__name__)

__all__ = ["read_mesh", "write_mesh", "read_body_mesh", "MESH_GROUPS"]


#: The named groups a mesh of each body needs: (surfaces, volumes).  The pad's
#: ``piston_face`` carries the piston's traction (``piston = "traction"``), its
#: ``back`` the tie to a meshed piston (``piston = "body"``).
MESH_GROUPS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "pad": (("friction", "abutment", "piston_face", "back"), ("friction_layer", "backplate")),
    "rotor": (("friction", "midplane", "rotor_clamp"), ("rotor",)),
    "piston": (("piston_face", "piston_back", "piston_side"), ("piston",)),
}


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


def read_mesh(path: str | PathLike, required: Sequence[str] | None = None,
              required_volumes: Sequence[str] | None = None) -> fem.Mesh:
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
    required, required_volumes
        Boundary (surface) and subdomain (volume) names that must be present;
        their absence raises with the list of the tags found.

    Returns
    -------
    skfem.MeshTet

    Raises
    ------
    MeshFileError
        No tetrahedra, or a required tag is missing.
    """
    import meshio

    _need_h5py(path)
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
    mesh = ensure_topology(fem.MeshTet(p, t))
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
    _tags_from_cell_data(mio, blocks, tet_offset, renum, names, bnd, sub)
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
    enc_b, enc_s = decode_cell_data(mesh,
        {k: v[:1] for k, v in (mio.cell_data or {}).items() if k.startswith("skfem:")}
        if len(blocks) == 1 and blocks[0][0] == 0 else {})
    boundaries.update({k: np.asarray(v, dtype=np.int64) for k, v in enc_b.items()})
    subdomains.update(enc_s)
    if boundaries:
        mesh = _with_boundaries(mesh, boundaries)
    if subdomains:
        mesh = _with_subdomains(mesh, subdomains)
    for kind, need, have in (("surface", required, boundaries),
                             ("volume", required_volumes, subdomains)):
        miss = [nm for nm in need or () if nm not in have]
        if miss:
            raise MeshFileError(
                f"{path}: required {kind} group(s) {miss} not found; groups found: "
                f"surfaces {sorted(boundaries) or 'none'}, volumes {sorted(subdomains) or 'none'}")
    logger.info("read %s: %d nodes, %d tets, surfaces %s", path, p.shape[1], t.shape[1],
                sorted(boundaries))
    return mesh


#: meshio formats stored in HDF5: they need h5py (not a dependency of brakewear)
_HDF5_SUFFIXES = (".xdmf", ".xmf", ".med", ".h5m")


def _need_h5py(path) -> None:
    if Path(path).suffix.lower() in _HDF5_SUFFIXES:
        try:
            import h5py  # noqa: F401
        except ImportError:
            raise MeshFileError(
                f"{path}: the {Path(path).suffix} format is stored in HDF5 and needs h5py, "
                "which brakewear does not install (pip install h5py); or use .msh (gmsh) "
                "or .vtu") from None


def read_body_mesh(path: str | PathLike, body: str, piston: str = "traction") -> fem.Mesh:
    """A user's mesh of one brake body, with the groups of :data:`MESH_GROUPS` checked.

    Raises
    ------
    MeshFileError
        The file cannot be read, has no tetrahedra, or lacks a group; the
        message names the file, the group and the groups found.
    """
    if body not in MESH_GROUPS:
        raise MeshFileError(f"{path}: {body!r} is not a body with a mesh; allowed: "
                            f"{', '.join(MESH_GROUPS)}")
    surfaces, volumes = MESH_GROUPS[body]
    if body == "pad":
        surfaces = tuple(s for s in surfaces if s != ("back" if piston == "traction"
                                                      else "piston_face"))
    if not Path(path).is_file():
        raise MeshFileError(f"{path}: the {body} mesh file does not exist")
    return read_mesh(path, required=surfaces, required_volumes=volumes)


def _gmsh_blocks(mesh: fem.Mesh):
    """Cells, cell data and physical names of a gmsh file: one triangle block per
    named boundary, one tetrahedron block per subdomain (physical groups)."""
    cells, tags, names = [], [], {}
    tag = 0
    for name, facets in (mesh.boundaries or {}).items():
        tag += 1
        tri = mesh.facets[:, np.asarray(facets, dtype=np.int64)].T
        cells.append(("triangle", tri))
        tags.append(np.full(len(tri), tag))
        names[name] = np.array([tag, 2])
    owner = np.zeros(mesh.t.shape[1], dtype=np.int64)       # 0: in no physical volume
    for name, elems in (mesh.subdomains or {}).items():
        tag += 1
        elems = np.asarray(elems, dtype=np.int64)
        if (owner[elems] > 0).any():
            logger.warning("write_mesh: subdomain %r overlaps an earlier one; gmsh gives each "
                           "tetrahedron one physical volume (the first)", name)
        owner[elems[owner[elems] == 0]] = tag
        names[name] = np.array([tag, 3])
    for t in np.unique(owner):
        sel = np.nonzero(owner == t)[0]
        cells.append(("tetra", mesh.t[:, sel].T))
        tags.append(np.full(sel.size, t))
    return cells, {"gmsh:physical": tags, "gmsh:geometrical": tags}, names


def write_mesh(path: str | PathLike, mesh: fem.Mesh, point_data: dict | None = None,
               cell_data: dict | None = None) -> Path:
    """Write a tetrahedral mesh and fields with meshio (VTU unless the suffix says otherwise).

    Named boundaries and subdomains are stored with the skfem tag encoding
    (one integer per tetrahedron), which :func:`read_mesh` decodes; ``.msh``
    is written as gmsh 2.2 with a physical group per named boundary
    (triangles) and subdomain (tetrahedra).  HDF5 formats (``.xdmf``,
    ``.med``) need ``h5py``, which brakewear does not install.  A
    ``MeshTet2`` is written as its P1 vertices and cells; point data given at
    all P2 nodes is cut to the vertex values.

    Parameters
    ----------
    path
        Output file; without a suffix ``.vtu`` is appended.
    mesh : skfem.MeshTet or skfem.MeshTet2
        The mesh, with its named boundaries and subdomains.
    point_data : dict of str to ndarray, optional
        Nodal fields, shape (nvertices,) or (nvertices, k) (P2 node arrays are cut).
    cell_data : dict of str to ndarray, optional
        One value (or row) per element (not for ``.msh``).

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
            raise MeshError(f"write_mesh: point_data[{k!r}] has {v.shape[0]} values; "
                            f"need {nv} (one per vertex)")
        pdata[k] = v[:nv]
    cdata = {}
    for k, v in (cell_data or {}).items():
        v = np.asarray(v)
        if v.shape[0] != mesh.t.shape[1]:
            raise MeshError(f"write_mesh: cell_data[{k!r}] has {v.shape[0]} values; "
                            f"need {mesh.t.shape[1]} (one per element)")
        cdata[k] = [v]
    m1 = mesh_with_sets(fem.MeshTet, p, mesh.t, mesh.boundaries, mesh.subdomains)
    if path.suffix.lower() == ".msh":
        if cdata:
            # meshio cannot read back element data of a gmsh file with groups
            raise MeshFileError(f"write_mesh: {path}: cell_data cannot go into a gmsh .msh file "
                                "(physical groups only); write it to a .vtu file")
        cells, data, names = _gmsh_blocks(m1)
        meshio.write(path, meshio.Mesh(p.T, cells, point_data=pdata, cell_data=data,
                                       field_data=names), file_format="gmsh22", binary=True)
    else:
        _need_h5py(path)
        cdata.update(encode_cell_data(m1))
        meshio.write(path, meshio.Mesh(p.T, [("tetra", mesh.t.T)], point_data=pdata,
                                       cell_data=cdata))
    logger.info("wrote %s (%d nodes, %d tets)", path, nv, mesh.t.shape[1])
    return path


def _tags_from_cell_data(mio, blocks, tet_offset, renum, names, bnd, sub) -> None:
    """Surfaces (``bnd``) and volumes (``sub``) named by integer cell data: gmsh
    physical groups (named through ``names``) or other integer tags (added in place)."""
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
            # gmsh's physical tag 0 is "in no physical group"
            low = 1 if key == "gmsh:physical" else 0
            tags = np.unique(np.concatenate([a[a >= low] for _, _, a in items] or [[]]))
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
