"""Boundary conditions: supported DOFs and their elimination, tractions and pressures on facets."""
from __future__ import annotations

import logging
from collections.abc import Iterable, Sequence

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..mesh.topology import ensure_topology, facet_indices
from .forms import pressure_form, scalar_element, traction_form

logger = logging.getLogger(__name__)

__all__ = ["assemble_traction", "assemble_pressure", "boundary_dofs", "apply_dirichlet"]


def _vector_facet_basis(mesh: fem.Mesh, facets) -> fem.FacetBasis:
    # FacetBasis needs the facet-to-element maps of the whole mesh: build them
    # by the fast route if the mesh does not carry them yet
    ensure_topology(mesh)
    elem = fem.ElementVector(scalar_element(mesh))
    return fem.FacetBasis(mesh, elem, facets=facets, intorder=2 * elem.maxdeg,
                          disable_doflocs=True)


def assemble_traction(mesh: fem.Mesh, facets, t: Sequence[float]) -> np.ndarray:
    """Load vector of a constant traction ``t`` on named facets (or facet indices)."""
    return traction_form(t).assemble(_vector_facet_basis(mesh, facets))


def assemble_pressure(mesh: fem.Mesh, facets, p: float) -> np.ndarray:
    """Load vector of a pressure ``p`` pushing against the outward normal of ``facets``."""
    return pressure_form(p).assemble(_vector_facet_basis(mesh, facets))


def boundary_dofs(mesh: fem.Mesh, facets, components: Iterable[int] = (0, 1, 2)) -> np.ndarray:
    """Vector DOFs of the given components on named facets (or facet indices)."""
    facets = facet_indices(mesh, facets)
    if isinstance(scalar_element(mesh), fem.ElementTetP1):
        # P1: the scalar DOFs are the vertices of the facets, in ascending
        # order (what skfem's Dofs gives, without building all mesh edges)
        sdofs = np.unique(ensure_topology(mesh).facets[:, facets])
    else:
        # vertices of the facets plus edge DOFs for P2, in scalar numbering
        sdofs = fem.Dofs(mesh, scalar_element(mesh)).get_facet_dofs(facets).all()
    comps = np.asarray(list(components), dtype=np.int64)
    return (3 * sdofs[:, None] + comps[None, :]).ravel()


def _dirichlet_bsr(K: sp.bsr_matrix, fixed: np.ndarray) -> tuple[sp.bsr_matrix, np.ndarray]:
    """Zero rows/columns ``fixed`` of a square-block BSR matrix, keep their diagonal.

    Same result as adding the diagonal back with a BSR sum (all-zero blocks
    dropped), but touches only the blocks of fixed nodes and copies the big
    arrays once.
    """
    R = K.blocksize[0]
    nbr = K.shape[0] // R
    diag = K.diagonal()
    nodes = fixed.reshape(nbr, R).any(axis=1)
    counts = np.diff(K.indptr)
    brow = np.repeat(np.arange(nbr, dtype=K.indices.dtype), counts)
    cand = np.flatnonzero(nodes[brow] | nodes[K.indices])
    cb, cc = brow[cand], K.indices[cand]
    sub = K.data[cand].copy()
    rmask = fixed[R * cb[:, None] + np.arange(R)]
    cmask = fixed[R * cc[:, None] + np.arange(R)]
    sub[rmask[:, :, None] | cmask[:, None, :]] = 0.0
    on_diag = cb == cc
    if np.count_nonzero(on_diag & nodes[cb]) != np.count_nonzero(nodes):
        # a fixed node without a diagonal block: the general route adds one
        K_new = K.copy()
        K_new.data[cand] = sub
        K_new = K_new + sp.bsr_matrix(sp.diags(np.where(fixed, diag, 0.0)).tocsr(),
                                      blocksize=(R, R))
        return K_new, diag
    for c in range(R):
        r = R * cb + c
        sel = on_diag & fixed[r]
        sub[sel, c, c] = diag[r[sel]]
    keep = K.data.reshape(K.data.shape[0], -1).any(axis=1)
    keep[cand] = sub.any(axis=(1, 2))  # (no fixed DOF: no candidate block)
    if keep.all():
        data = K.data.copy()
        data[cand] = sub
        indices, indptr = K.indices.copy(), K.indptr.copy()
    else:
        newpos = np.cumsum(keep) - 1
        data = K.data[keep]
        kc = keep[cand]
        data[newpos[cand[kc]]] = sub[kc]
        indices = K.indices[keep]
        indptr = np.zeros_like(K.indptr)
        np.cumsum(np.bincount(brow[keep], minlength=nbr), out=indptr[1:])
    return sp.bsr_matrix((data, indices, indptr), shape=K.shape), diag


def apply_dirichlet(K: sp.spmatrix, f: np.ndarray, dofs: np.ndarray,
                    values: np.ndarray | float = 0.0) -> tuple[sp.spmatrix, np.ndarray]:
    """Impose ``u[dofs] = values`` symmetrically, keeping size and block structure.

    Rows and columns of ``dofs`` are zeroed, their diagonal keeps its value
    (so the scaling of the system is not disturbed) and the right-hand side
    carries the prescribed values.  Returns new arrays; ``K`` and ``f`` are
    not modified.
    """
    dofs = np.asarray(dofs, dtype=np.int64)
    N = K.shape[0]
    u0 = np.zeros(N)
    u0[dofs] = values
    fixed = np.zeros(N, dtype=bool)
    fixed[dofs] = True
    f_new = np.asarray(f, dtype=float) - K @ u0
    if (sp.isspmatrix_bsr(K) or isinstance(K, sp.bsr_array)) and K.blocksize[0] == K.blocksize[1]:
        K_new, diag = _dirichlet_bsr(K, fixed)
    elif sp.isspmatrix_bsr(K) or isinstance(K, sp.bsr_array):
        R, Cb = K.blocksize
        nbr = K.shape[0] // R
        brow = np.repeat(np.arange(nbr), np.diff(K.indptr))
        rmask = fixed[R * brow[:, None] + np.arange(R)]
        cmask = fixed[Cb * K.indices[:, None] + np.arange(Cb)]
        diag = K.diagonal()
        data = K.data.copy()
        data[rmask[:, :, None] | cmask[:, None, :]] = 0.0
        K_new = sp.bsr_matrix((data, K.indices.copy(), K.indptr.copy()), shape=K.shape)
        K_new = K_new + sp.bsr_matrix(
            sp.diags(np.where(fixed, diag, 0.0)).tocsr(), blocksize=(R, Cb)
        )
    else:
        K = K.tocsr()
        diag = K.diagonal()
        keep = sp.diags((~fixed).astype(float))
        K_new = (keep @ K @ keep + sp.diags(np.where(fixed, diag, 0.0))).tocsr()
    f_new[fixed] = diag[fixed] * u0[fixed]
    return K_new, f_new
