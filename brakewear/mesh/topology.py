"""Mesh topology: named facet sets, facet-to-element tables computed once and kept.

scikit-fem builds the facet and edge tables of a mesh on first use; the
helpers here build them once and carry them (and the named boundaries and
subdomains) over to a moved copy of the mesh, whose topology is unchanged.
"""
from __future__ import annotations

import logging

import numpy as np
import skfem as fem

from ..errors import MeshError
from .skfem_compat import copy_topology, has_topology, set_topology

logger = logging.getLogger(__name__)

__all__ = ["facet_indices", "ensure_topology", "keep_topology"]


def facet_indices(mesh: fem.Mesh, facets) -> np.ndarray:
    """Facet indices of a named facet set, or the given indices.

    A name the mesh does not have raises :class:`~brakewear.errors.MeshError` listing the
    names it has.
    """
    if isinstance(facets, str):
        if facets not in (mesh.boundaries or {}):
            raise MeshError(f"mesh has no facets named {facets!r}; named facets: "
                            f"{sorted(mesh.boundaries or {})}")
        facets = mesh.boundaries[facets]
    return np.asarray(facets)


def ensure_topology(mesh: fem.Mesh) -> fem.Mesh:
    """Fill skfem's cached ``facets``, ``t2f`` and ``f2t`` of a tetrahedral mesh.

    Gives exactly what skfem computes lazily (facets as sorted vertex
    triples in lexicographic order, ``t2f`` per local facet, ``f2t`` with -1
    outside), but sorts one int64 key per facet instead of running
    ``np.unique(axis=1)`` over vertex triples, several times faster on a big
    mesh.  Returns ``mesh`` (modified in place); leaves it alone if the
    caches exist or the key would overflow.
    """
    if has_topology(mesh):
        return mesh
    t = mesh.t
    n = int(t.max()) + 1
    if not isinstance(mesh, (fem.MeshTet1, fem.MeshTet2)) or float(n) ** 3 >= 2.0 ** 62:
        return mesh
    ne = t.shape[1]
    fidx = mesh.elem.refdom.facets
    f = np.sort(np.hstack([t[ix] for ix in fidx]), axis=0)
    key = (f[0].astype(np.int64) * n + f[1]) * n + f[2]
    order = np.argsort(key)
    ks = key[order]
    new = np.empty(ks.size, dtype=bool)
    new[0] = True
    np.not_equal(ks[1:], ks[:-1], out=new[1:])
    del ks
    starts = np.flatnonzero(new)
    # first and last occurrence (in skfem's local-facet-major order) of each facet
    first = np.minimum.reduceat(order, starts)
    last = np.maximum.reduceat(order, starts)
    inv = np.empty(key.size, dtype=np.intp)
    inv[order] = np.cumsum(new) - 1
    del order, new, key
    f2t = np.empty((2, starts.size), dtype=np.int32)
    f2t[0] = first % ne
    f2t[1] = np.where(first == last, -1, last % ne)
    return set_topology(mesh, np.ascontiguousarray(f[:, first]), inv.reshape(len(fidx), ne),
                        f2t)


def keep_topology(new: fem.Mesh, old: fem.Mesh) -> fem.Mesh:
    """Carry skfem's cached topology over to a copy with the same ``t`` (the
    copies made by ``with_boundaries``/``with_subdomains`` start empty)."""
    return copy_topology(new, old)


def _with_boundaries(mesh: fem.Mesh, boundaries: dict) -> fem.Mesh:
    """``mesh.with_boundaries(boundaries)`` (boundary facets only), faster.

    The topology is built by the fast route and kept by the copy; the
    midpoints of the boundary facets are computed once for all tests instead
    of those of every facet once per test.  Same facet sets as skfem's.
    """
    ensure_topology(mesh)
    sets = {}
    if any(callable(v) for v in boundaries.values()):
        bf = np.nonzero(mesh.f2t[1] == -1)[0].astype(np.int32)
        midp = mesh.p[:, mesh.facets[:, bf]].mean(axis=1)
        for name, test in boundaries.items():
            if callable(test):
                sets[name] = bf[np.asarray(test(midp), dtype=bool)]
    sets = {name: sets.get(name, test) for name, test in boundaries.items()}
    return keep_topology(mesh.with_boundaries(sets), mesh)


def _with_subdomains(mesh: fem.Mesh, subdomains: dict) -> fem.Mesh:
    """``mesh.with_subdomains``; the copy keeps the cached topology."""
    return keep_topology(mesh.with_subdomains(subdomains), mesh)
