"""Both pads of a brake as one mesh: the inboard pad and its mirror image.

The full model (both friction faces of the rotor, :class:`~brakewear.model.BrakeModel`
with ``layout="full"``) carries the outboard pad as the inboard pad's mesh
mirrored through the rotor's mid-plane, in the same mesh object: the wear
loop, the outputs and the fields then work per node as for one pad, and the
two pads are told apart by their facet and subdomain names.  The inboard
pad's nodes come first (vertices, then on a quadratic mesh the mid-edge
nodes of both pads in the combined mesh's edge order).

Every named facet set ``NAME`` of the pad becomes ``NAME`` (both pads),
``NAME_in`` and ``NAME_out``; subdomains keep their names and cover both pads.
"""
from __future__ import annotations

import logging

import numpy as np
import skfem as fem

from ..errors import SceneError
from .structured import _oriented
from .surface import is_quadratic
from .topology import ensure_topology, keep_topology

logger = logging.getLogger(__name__)

__all__ = ["mirrored_pads", "whole_thickness_meshes", "OUTBOARD_SUFFIX", "INBOARD_SUFFIX"]

INBOARD_SUFFIX, OUTBOARD_SUFFIX = "_in", "_out"


def _keys(v: np.ndarray, n: int) -> np.ndarray:
    """One int64 key per column of sorted vertex indices (2 or 3 rows)."""
    v = np.sort(v, axis=0).astype(np.int64)
    k = v[0]
    for row in v[1:]:
        k = k * n + row
    return k


def _find(keys: np.ndarray, wanted: np.ndarray) -> np.ndarray:
    order = np.argsort(keys)
    pos = np.searchsorted(keys, wanted, sorter=order)
    idx = order[np.minimum(pos, keys.size - 1)]
    if not np.array_equal(keys[idx], wanted):  # pragma: no cover - topology is copied exactly
        raise RuntimeError("mirrored_pads: a facet or edge of the pad is missing from the union")
    return idx


def mirrored_pads(pad: fem.Mesh, mirror_z: float) -> fem.Mesh:
    """The pad mesh and its mirror image through the plane ``z = mirror_z``.

    Parameters
    ----------
    pad : skfem.MeshTet or skfem.MeshTet2
        The inboard pad (named facets and subdomains as :func:`~brakewear.mesh.brake.pad_mesh`).
    mirror_z : float
        The rotor's mid-plane (m): ``-thickness / 2``.

    Returns
    -------
    skfem.MeshTet or skfem.MeshTet2
        Both pads; facets ``NAME``, ``NAME_in``, ``NAME_out`` for every named
        facet set of ``pad``; subdomains as ``pad``'s, over both pads.
    """
    ensure_topology(pad)
    nv = pad.nvertices
    v = pad.p[:, :nv]
    vm = v.copy()
    vm[2] = 2.0 * mirror_z - vm[2]
    x = np.hstack([v, vm])
    t = _oriented(x, np.hstack([pad.t, pad.t + nv]))
    n = 2 * nv
    if is_quadratic(pad):
        m1 = fem.MeshTet(x, t)
        pe = np.sort(fem.MeshTet(v, pad.t, validate=False).edges, axis=0)
        mid_in = pad.p[:, nv:]
        e = np.sort(m1.edges, axis=0)
        out = e[0] >= nv
        src = _find(_keys(pe, nv), _keys(np.where(out, e - nv, e), nv))
        mid = mid_in[:, src].copy()
        mid[2, out] = 2.0 * mirror_z - mid[2, out]
        mesh = fem.MeshTet2(np.hstack([x, mid]), t)
    else:
        mesh = fem.MeshTet(x, t)
    ensure_topology(mesh)
    fkeys = _keys(mesh.facets, n)
    sets = {}
    for name, idx in (pad.boundaries or {}).items():
        f = pad.facets[:, idx]
        fin = _find(fkeys, _keys(f, n))
        fout = _find(fkeys, _keys(f + nv, n))
        sets[name + INBOARD_SUFFIX] = fin
        sets[name + OUTBOARD_SUFFIX] = fout
        sets[name] = np.concatenate([fin, fout])
    ne = pad.t.shape[1]
    subs = {k: np.concatenate([np.asarray(s), np.asarray(s) + ne])
            for k, s in (pad.subdomains or {}).items()}
    out_mesh = keep_topology(mesh.with_boundaries(sets), mesh)
    out_mesh = keep_topology(out_mesh.with_subdomains(subs), mesh)
    logger.debug("two pads: %d nodes, %d elements", out_mesh.p.shape[1], out_mesh.t.shape[1])
    return out_mesh


def whole_thickness_meshes(given: dict, mirror_z: float) -> dict:
    """A user's meshes (body -> mesh) for the full model: the pad mirrored into
    both pads; the rotor must be whole, both friction faces named.

    Raises
    ------
    SceneError
        A rotor mesh without ``friction_in`` and ``friction_out`` facets.
    """
    rotor = given.get("rotor")
    if rotor is not None and not {"friction_in", "friction_out"} <= set(rotor.boundaries or {}):
        raise SceneError("meshes: the full model needs a rotor mesh of the whole thickness "
                         "with facets 'friction_in' (z = 0) and 'friction_out' (z = "
                         f"-thickness); this one has {sorted(rotor.boundaries or {})}; use "
                         "layout = 'half'")
    if "pad" in given:
        given = {**given, "pad": mirrored_pads(given["pad"], mirror_z)}
    return given
