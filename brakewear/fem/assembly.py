"""Fast assembly of the elasticity stiffness, tested against scikit-fem's forms.

:func:`assemble_stiffness` takes the basis-function gradients, quadrature
weights and DOF numbering from a scikit-fem ``Basis`` (chunk by chunk, via
``Basis(..., elements=chunk)``), forms all element matrices of a chunk at
once as ``B^T C B`` with batched matrix products, and adds them into a
3x3-block (BSR) matrix whose sparsity pattern is computed once per mesh
(:class:`BlockPattern`).  No per-element temporaries outlive a chunk, so
peak memory is the matrix plus one chunk.  The tests check it against
:func:`brakewear.fem.elasticity_form` to round-off.
:func:`stiffness_update` reintegrates only the elements that moved.

DOF numbering everywhere is scikit-fem's for ``ElementVector``: scalar DOF
``s`` (a vertex, or an edge for P2) owns vector DOFs ``3 s + i``, i = x, y, z.
"""
from __future__ import annotations

import logging
import os
from collections import deque
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..errors import MeshError
from .forms import _VOIGT, _intorder, scalar_element

logger = logging.getLogger(__name__)

__all__ = ["BlockPattern", "assemble_stiffness", "stiffness_update"]


#: Worker threads of :func:`assemble_stiffness` (element matrices of the next
#: chunks are computed while the current ones are added into the matrix).
_ASSEMBLY_THREADS = min(2, os.cpu_count() or 1)


Groups = Sequence[tuple[np.ndarray | None, np.ndarray]]


@dataclass
class BlockPattern:
    """Node-level sparsity of a vector FE matrix on one mesh, built once.

    ``indptr``/``indices`` describe the scalar (node-to-node) graph; the vector
    matrix is stored as BSR with 3x3 blocks on that graph.  ``keys`` are the
    sorted global keys ``row * n + col`` used to locate element entries.
    """

    n: int
    indptr: np.ndarray
    indices: np.ndarray
    keys: np.ndarray

    @classmethod
    def from_element_dofs(cls, sdofs: np.ndarray, n: int, chunk: int = 200_000) -> BlockPattern:
        nb, ne = sdofs.shape
        graph = None
        for s in range(0, ne, chunk):
            d = sdofs[:, s:s + chunk]
            rows = np.repeat(d, nb, axis=0).ravel()
            cols = np.tile(d, (nb, 1)).ravel()
            g = sp.csr_matrix((np.ones(rows.size, dtype=np.int8), (rows, cols)), shape=(n, n))
            g.data[:] = 1
            graph = g if graph is None else graph + g
            graph.data[:] = 1
        graph.sort_indices()
        rowi = np.repeat(np.arange(n, dtype=np.int64), np.diff(graph.indptr))
        keys = rowi * n + graph.indices
        return cls(n, graph.indptr.astype(np.int64), graph.indices.astype(np.int32), keys)

    @property
    def nnzb(self) -> int:
        return self.indices.size

    def lookup(self) -> sp.csr_matrix:
        """The node graph as CSR whose values are the block positions (for :meth:`positions`)."""
        return sp.csr_matrix((np.arange(self.nnzb, dtype=np.int64), self.indices, self.indptr),
                             shape=(self.n, self.n))

    def positions(self, d: np.ndarray, lookup: sp.csr_matrix | None = None) -> np.ndarray:
        """Block positions of all (a, b) pairs of element DOFs ``d`` (nb, ne) -> (ne, nb, nb).

        Looked up row by row in the CSR graph (``lookup``, from :meth:`lookup`;
        built here if not given): each search runs over one short row instead
        of the whole key array.
        """
        nb, ne = d.shape
        if lookup is None:
            lookup = self.lookup()
        dT = np.ascontiguousarray(d.T)
        rows = np.repeat(dT, nb, axis=1).ravel()
        cols = np.tile(dT, (1, nb)).ravel()
        pos = np.asarray(lookup[rows, cols]).ravel()
        return pos.reshape(ne, nb, nb)


def _as_groups(mesh: fem.Mesh, materials) -> list[tuple[np.ndarray | None, np.ndarray]]:
    """Normalise ``materials`` to a list of (element indices or None, 6x6 C)."""
    if hasattr(materials, "voigt"):
        return [(None, materials.voigt())]
    arr = np.asarray(materials) if not isinstance(materials, (list, tuple)) else None
    if arr is not None and arr.shape == (6, 6):
        return [(None, arr.astype(float))]
    out = []
    for elems, mat in materials:
        C = mat.voigt() if hasattr(mat, "voigt") else np.asarray(mat, dtype=float)
        out.append((None if elems is None else np.asarray(elems), C))
    return out


def _tensor_matrix(C: np.ndarray) -> np.ndarray:
    """``M[(i, j), (k, l)] = C[v(i, k), v(j, l)]``, the 9x9 coupling of gradients.

    With engineering shear strains, the element matrix entry between
    component ``i`` of shape function ``a`` and component ``j`` of ``b`` is
    ``sum_kl grad_k(phi_a) M[(i, j), (k, l)] grad_l(phi_b)``.
    """
    C = np.asarray(C, dtype=float)
    i, j, k, l = np.meshgrid(*(np.arange(3),) * 4, indexing="ij")
    return C[_VOIGT[i, k], _VOIGT[j, l]].reshape(9, 9)


def _chunk_matrices(basis: fem.CellBasis, C: np.ndarray) -> np.ndarray:
    """Element stiffness matrices (ne, 3nb, 3nb) of one chunk, from skfem's basis."""
    nb = len(basis.basis)
    ne = basis.dx.shape[0]
    KT = _chunk_blocks(basis, _tensor_matrix(C))  # (9, ne, nb, nb)
    return KT.reshape(3, 3, ne, nb, nb).transpose(2, 3, 0, 4, 1).reshape(ne, 3 * nb, 3 * nb)


def _chunk_blocks(basis: fem.CellBasis, M: np.ndarray) -> np.ndarray:
    """Element matrices of one chunk by component pair: (9, ne, nb, nb), row ``3 i + j``.

    The gradient products ``dx g_a[k] g_b[l]`` of all quadrature points are
    summed first (9 numbers per pair of shape functions), then one matrix
    product with the 9x9 material coupling ``M`` gives all components: a
    single BLAS call per chunk instead of a small matrix product per element.
    """
    nb = len(basis.basis)
    ne = basis.dx.shape[0]
    return (M @ _chunk_products(basis)).reshape(9, ne, nb, nb)


def _chunk_products(basis: fem.CellBasis) -> np.ndarray:
    """``sum_q dx g_a[k] g_b[l]`` of one chunk, shape (9, ne * nb * nb), row ``3 k + l``."""
    nb = len(basis.basis)
    ne, nq = basis.dx.shape
    G = np.stack([basis.basis[a][0].grad for a in range(nb)])  # (nb, 3, ne, nq)
    P = np.empty((3, 3, ne, nb, nb)) if nq == 1 else np.zeros((3, 3, ne, nb, nb))
    for q in range(nq):
        g = np.ascontiguousarray(G[:, :, :, q].transpose(1, 2, 0))  # (3, ne, nb)
        gw = g * basis.dx[None, :, q, None]
        for k in range(3):
            # P[k, l, e, a, b] += dx g[k, e, a] g[l, e, b]
            if nq == 1:  # P1: write in place, no temporary
                np.multiply(gw[k, None, :, :, None], g[:, :, None, :], out=P[k])
            else:
                P[k] += gw[k, None, :, :, None] * g[:, :, None, :]
    return P.reshape(9, -1)


def _scatter_blocks(data, KT, pos):
    """Add the 3x3 element blocks ``KT`` (9 rows, one column per block entry)
    into the BSR block array ``data`` at block positions ``pos`` (modified)."""
    lo, hi = int(pos.min()), int(pos.max()) + 1
    pos = pos - lo
    band = data[lo:hi]
    for i in range(3):
        for j in range(3):
            band[:, i, j] += np.bincount(pos, weights=KT[3 * i + j], minlength=hi - lo)


def assemble_stiffness(mesh: fem.Mesh, materials, pattern: BlockPattern | None = None,
                       chunk: int = 150_000, intorder: int | None = None,
                       elements: np.ndarray | None = None
                       ) -> tuple[sp.bsr_matrix, BlockPattern]:
    """Assemble the elastic stiffness as a 3x3-block BSR matrix.

    Parameters
    ----------
    mesh
        ``MeshTet`` (P1) or ``MeshTet2`` (P2, isoparametric).
    materials
        A material (anything with ``voigt()``), a 6x6 Voigt matrix, or a list
        of ``(element_indices, material_or_C)`` covering the mesh.
    pattern
        The mesh's :class:`BlockPattern` from an earlier call (reuse it when
        only coefficients or coordinates change).
    chunk
        Largest number of elements per chunk; bounds the temporary memory
        (chunks are also capped at about 64 MB of element matrices).
    elements
        Assemble only these elements (indices into ``mesh.t``); the result
        still has the whole mesh's shape and sparsity pattern.  Default: all.

    Returns
    -------
    K, pattern

    Notes
    -----
    Elements are processed in the order of their lowest DOF, so a chunk
    touches a narrow band of matrix rows on a mesh with local numbering and
    its scatter-add (``np.bincount``) works on that band only.
    """
    elem = scalar_element(mesh)
    groups = _as_groups(mesh, materials)
    q = _intorder(elem) if intorder is None else intorder
    # one Dofs for all chunks, and no global DOF locations per chunk: both
    # would otherwise be recomputed for the whole mesh by every chunk's Basis
    sd = fem.Dofs(mesh, elem)
    if pattern is None:
        pattern = BlockPattern.from_element_dofs(sd.element_dofs, sd.N)
    nb = elem.refdom.nnodes * elem.nodal_dofs + elem.refdom.nedges * elem.edge_dofs
    chunk = int(max(1, min(chunk, 8_000_000 // (9 * nb * nb))))
    data = np.zeros((pattern.nnzb, 3, 3))
    lookup = pattern.lookup()

    def compute(part, M):
        basis = fem.CellBasis(mesh, elem, intorder=q, elements=part, dofs=sd,
                              disable_doflocs=True)
        KT = _chunk_blocks(basis, M).reshape(9, -1)
        pos = pattern.positions(basis.element_dofs, lookup).ravel()
        return KT, pos

    def add(KT, pos):
        _scatter_blocks(data, KT, pos)

    subset = None if elements is None else _element_subset(mesh, elements, "assemble_stiffness")
    tasks = []
    covered = 0
    for elems, C in groups:
        idx = np.arange(mesh.nelements) if elems is None else np.asarray(elems)
        covered += idx.size
        if subset is not None:
            idx = idx[subset[idx]]
        M = _tensor_matrix(C)
        # local chunks: sort the elements by their lowest vertex
        idx = idx[np.argsort(mesh.t[:, idx].min(axis=0), kind="stable")]
        tasks += [(idx[s:s + chunk], M) for s in range(0, idx.size, chunk)]
    threads = min(_ASSEMBLY_THREADS, len(tasks))
    if threads > 1:
        # skfem's affine mapping fills its per-element arrays lazily, which is
        # not thread-safe: fill them here, before any worker runs
        mapping = mesh.mapping()
        for name in ("A", "b", "detA", "invA"):
            getattr(mapping, name, None)
    if threads <= 1:
        for part, M in tasks:
            add(*compute(part, M))
    else:
        # element matrices of the next chunks are computed in worker threads
        # (NumPy and BLAS release the GIL) while this thread adds the last
        # ones; at most threads + 1 chunks are alive at a time
        with ThreadPoolExecutor(threads) as pool:
            pending: deque = deque()
            for part, M in tasks:
                pending.append(pool.submit(compute, part, M))
                if len(pending) > threads:
                    add(*pending.popleft().result())
            while pending:
                add(*pending.popleft().result())
    if covered != mesh.nelements:
        raise MeshError(f"assemble_stiffness: the material groups cover {covered} elements, "
                        f"the mesh has {mesh.nelements}; every element needs one material")
    N = 3 * pattern.n
    K = sp.bsr_matrix((data, pattern.indices, pattern.indptr), shape=(N, N))
    return K, pattern


def _element_subset(mesh: fem.Mesh, elements, who: str) -> np.ndarray:
    """Boolean mask over ``mesh``'s elements from an index array (checked)."""
    idx = np.asarray(elements)
    if idx.ndim != 1 or not (idx.size == 0 or np.issubdtype(idx.dtype, np.integer)):
        raise MeshError(f"{who}: elements must be a 1-D array of element indices; "
                        f"got shape {idx.shape}, dtype {idx.dtype}")
    if idx.size and (idx.min() < 0 or idx.max() >= mesh.nelements):
        raise MeshError(f"{who}: element index {int(idx.min() if idx.min() < 0 else idx.max())} "
                        f"is out of range; the mesh has {mesh.nelements} elements")
    mask = np.zeros(mesh.nelements, dtype=bool)
    mask[idx] = True
    return mask


def stiffness_update(K: sp.bsr_matrix, pattern: BlockPattern, old_mesh: fem.Mesh,
                     new_mesh: fem.Mesh, materials, elements: np.ndarray,
                     chunk: int = 150_000, intorder: int | None = None) -> sp.bsr_matrix:
    """The stiffness after some elements moved: ``K - K_e(old) + K_e(new)``.

    Only ``elements`` are integrated, on both meshes; their differences are
    added into a copy of ``K``'s blocks.  Everything else (the pattern, the
    other elements' contributions) is kept, so the cost is proportional to
    the number of moved elements plus one copy of ``K``'s data.

    Parameters
    ----------
    K, pattern
        The current stiffness of ``old_mesh`` and its pattern, as returned by
        :func:`assemble_stiffness` (or an earlier :func:`stiffness_update`).
    old_mesh, new_mesh
        The same elements (identical ``t``) before and after the motion.
    materials
        As for :func:`assemble_stiffness`.
    elements
        Indices of the elements whose vertices moved.  Elements outside this
        set must have the same coordinates in both meshes, otherwise the
        result is wrong (not checked: it would cost a full pass).

    Returns
    -------
    scipy.sparse.bsr_matrix
        The stiffness of ``new_mesh``; equal to a full reassembly up to
        round-off.  ``K`` is not modified.
    """
    if old_mesh.t.shape != new_mesh.t.shape or not (
            old_mesh.t is new_mesh.t or np.array_equal(old_mesh.t, new_mesh.t)):
        raise MeshError("stiffness_update: old_mesh and new_mesh must have the same elements "
                        f"(t of shape {old_mesh.t.shape} vs {new_mesh.t.shape} or different "
                        "connectivity); a remeshed body needs a full assemble_stiffness")
    if type(old_mesh) is not type(new_mesh):
        raise MeshError(f"stiffness_update: mesh types differ ({type(old_mesh).__name__} vs "
                        f"{type(new_mesh).__name__})")
    N = 3 * pattern.n
    if K.shape != (N, N) or not (sp.isspmatrix_bsr(K) or isinstance(K, sp.bsr_array)) \
            or K.blocksize != (3, 3) or K.data.shape[0] != pattern.nnzb:
        raise MeshError(f"stiffness_update: K (shape {K.shape}, format {K.format}) is not the "
                        f"3x3-block matrix of this pattern ({N} x {N}, {pattern.nnzb} blocks)")
    mask = _element_subset(new_mesh, elements, "stiffness_update")
    elem = scalar_element(new_mesh)
    q = _intorder(elem) if intorder is None else intorder
    nb = elem.refdom.nnodes * elem.nodal_dofs + elem.refdom.nedges * elem.edge_dofs
    chunk = int(max(1, min(chunk, 8_000_000 // (9 * nb * nb))))
    data = K.data.copy()
    if not mask.any():
        return sp.bsr_matrix((data, pattern.indices, pattern.indptr), shape=(N, N))
    sd_old, sd_new = fem.Dofs(old_mesh, elem), fem.Dofs(new_mesh, elem)
    lookup = pattern.lookup()

    def basis(mesh, sd, part):
        # an affine mapping of the chunk only: the default one would compute
        # (and keep) the Jacobians of every element of the new mesh
        mapping = fem.MappingAffine(mesh, tind=part) if mesh.affine else None
        return fem.CellBasis(mesh, elem, mapping=mapping, intorder=q, elements=part, dofs=sd,
                             disable_doflocs=True)
    for elems, C in _as_groups(new_mesh, materials):
        idx = np.arange(new_mesh.nelements) if elems is None else np.asarray(elems)
        idx = idx[mask[idx]]
        idx = idx[np.argsort(new_mesh.t[:, idx].min(axis=0), kind="stable")]
        M = _tensor_matrix(C)
        for s in range(0, idx.size, chunk):
            part = idx[s:s + chunk]
            bn = basis(new_mesh, sd_new, part)
            # difference of the gradient products first: one product with M
            # per chunk, and what did not change cancels before it
            dP = _chunk_products(bn)
            dP -= _chunk_products(basis(old_mesh, sd_old, part))
            KT = M @ dP
            _scatter_blocks(data, KT, pattern.positions(bn.element_dofs, lookup).ravel())
    return sp.bsr_matrix((data, pattern.indices, pattern.indptr), shape=(N, N))
