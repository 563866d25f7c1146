"""Mesh files in and out: meshio formats with the named surfaces of brakewear.

:func:`write_mesh` writes a mesh (and point or cell data) with its named facet
sets and subdomains; :func:`read_mesh` reads tetrahedral meshes back, with
the named sets restored from the file's tags.
"""
from __future__ import annotations

import logging
from os import PathLike
from pathlib import Path
from typing import Sequence

import numpy as np
import skfem as fem

from ..errors import MeshFileError
from .structured import _oriented
from .topology import _with_boundaries, _with_subdomains, ensure_topology

logger = logging.getLogger(__name__)

__all__ = ["read_mesh", "write_mesh"]


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
