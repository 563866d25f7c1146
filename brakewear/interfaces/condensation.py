"""Condensing a finite-element contact model onto its contact nodes.

In gap-offset mode with linear elasticity, everything a wear step asks of the
finite-element model goes through the contact nodes.  With ``K u = f +
(C^T + mu G) lam`` (``C`` the normal-gap rows of the pad's friction nodes,
``G`` the nodal friction load per newton of normal force along the sliding
direction, ``lam`` the normal contact forces), the gap is

    g = g0 + offset + C K^+ f + C K^+ (C^T + mu G) lam + C Z alpha

where ``K^+`` is a generalised inverse of the supported stiffness and ``Z``
the rigid-body modes the supports leave free (the pad, held in-plane at its
abutments, floats along its normal: one mode), whose amplitudes ``alpha``
are fixed by equilibrium, ``Z^T (f + (C^T + mu G) lam) = 0``.  Condensing
computes, once per geometry and materials,

* ``Hn = C K^+ C^T`` and ``Ht = C K^+ G`` (n x n, m/N): the normal and the
  friction compliance as seen by the contact nodes;
* ``hf = C K^+ f`` per unit line pressure (m/Pa), ``E = C Z``, ``Dt = Z^T G``
  and ``zf = Z^T f`` per unit line pressure.

``K^+`` is applied by a sparse direct factorisation per body (SuperLU, the
fill-reducing ordering of ``K + K^T``), ``K^+ C^T`` in blocks of columns:
with ``K`` symmetric, ``Y = K^+ C^T`` gives every product above as ``Y^T B``
for the sparse ``B``, from ``n`` solves.  An AMG-preconditioned CG solve per
column (the wear loop's hierarchy) measured 0.49 s at 105k DOFs (28-31
iterations to 1e-12; 8 minutes for its 980 columns), and stalled on some
columns at 30k DOFs; the factorisations and their multi-column solves took
48.5 s in the same run (docs/condensed.md has the figures and the command).

The result is cached on disk (:func:`cache_dir`), keyed by a hash of every
array it is computed from, so sweeps of line pressure or wear law and resumed
runs do not recompute it.
"""
from __future__ import annotations

import hashlib
import logging
import os
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from ..checks import fail, shown_value
from ..contact.compliant import constraint_rows, drag_loads
from ..errors import SolverError, StoredFileError
from ..solvers.threads import blas_threads
from ..storage import load_arrays, save_arrays

logger = logging.getLogger(__name__)

__all__ = ["Condensation", "condense", "cache_dir", "condensation_memory", "check_scene_size",
           "CACHE_ENV",
           "Supported"]

#: environment variable naming the cache directory of condensed compliances
CACHE_ENV = "BRAKEWEAR_CACHE"
#: columns solved at once (bounds the block's memory: block x DOFs x 8 bytes)
BLOCK = 128
#: a mode counts as free when its support residual is below this share
_NULL_TOL = 1e-9
_KEYS = ("Hn", "Ht", "hf", "E", "Dt", "zf")


@dataclass
class Condensation:
    """The FE contact model condensed onto its ``n`` contact nodes (see the module).

    Attributes
    ----------
    Hn, Ht : ndarray
        (n, n) normal and unit-friction compliance (m/N).
    hf : ndarray
        (n,) gap change under the model's load per pascal of line pressure (m/Pa).
    E : ndarray
        (n, m) gap change per unit amplitude of each free rigid-body mode.
    Dt : ndarray
        (m, n) the modes' share of the unit friction loads (``Z^T G``); the
        normal share is ``E.T``.
    zf : ndarray
        (m,) the modes' share of the load per pascal of line pressure.
    key : str
        The cache key (a hash of the model's arrays).
    info : dict
        Figures: seconds, columns solved, factor sizes, bytes.
    """

    Hn: np.ndarray
    Ht: np.ndarray
    hf: np.ndarray
    E: np.ndarray
    Dt: np.ndarray
    zf: np.ndarray
    key: str = ""
    info: dict = field(default_factory=dict)

    @property
    def n(self) -> int:
        return int(self.Hn.shape[0])

    @property
    def nbytes(self) -> int:
        return int(sum(getattr(self, k).nbytes for k in _KEYS))


def cache_dir(cache=None) -> Path | None:
    """The cache directory: ``cache`` (a path; False: no cache), else
    ``BRAKEWEAR_CACHE``, else ``~/.cache/brakewear/condensed``."""
    if cache is False:
        return None
    if cache not in (None, True):
        return Path(cache)
    env = os.environ.get(CACHE_ENV)
    if env:
        return Path(env)
    return Path.home() / ".cache" / "brakewear" / "condensed"


def condensation_memory(n_contact: int, n_dofs: int) -> float:
    """Bytes the condensation needs beyond the model: the two dense ``n x n``
    compliances, a block of solved columns and an estimate of the sparse
    factor (6 N^1.5 entries of 12 bytes for 3D P1 stiffness, from the
    factors measured at 30k and 70k DOFs)."""
    return 16.0 * n_contact ** 2 + 8.0 * BLOCK * n_dofs + 72.0 * n_dofs ** 1.5


def array_hash(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(str((a.dtype.str, a.shape)).encode())
        h.update(a.tobytes())
    return h.hexdigest()[:32]


def free_modes(K: sp.csr_matrix, coords: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """``Z`` (N x m, orthonormal columns): the rigid-body modes of each body of
    ``K`` that its supports leave free (checked: ``K Z`` vanishes)."""
    from ..contact.elimination import body_labels

    N = K.shape[0]
    labels = body_labels(K)
    labels = np.zeros(N // 3, dtype=np.int64) if labels is None else labels
    is_fixed = np.zeros(N, dtype=bool)
    is_fixed[fixed] = True
    cols = []
    for b in np.unique(labels):
        nodes = np.nonzero(labels == b)[0]
        x = coords[:, nodes] - coords[:, nodes].mean(axis=1, keepdims=True)
        R = np.zeros((3 * nodes.size, 6))
        for i in range(3):
            R[i::3, i] = 1.0
        # rotations about x, y, z: omega x r
        R[1::3, 3], R[2::3, 3] = -x[2], x[1]
        R[0::3, 4], R[2::3, 4] = x[2], -x[0]
        R[0::3, 5], R[1::3, 5] = -x[1], x[0]
        dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
        held = R[is_fixed[dofs]]
        if held.shape[0] == 0:
            V = np.eye(6)
        else:
            # only V is needed: the thin SVD (a full one holds a square U of the held DOFs)
            _, s, Vt = np.linalg.svd(held, full_matrices=held.shape[0] < 6)
            s = np.concatenate([s, np.zeros(6 - s.size)])
            V = Vt[s <= _NULL_TOL * max(s[0], 1e-300)].T
        if V.shape[1]:
            # springs to ground (a bracket's rails and clip) hold modes too: keep
            # those the stiffness itself leaves free
            B, _ = np.linalg.qr(R @ V)
            Kb = K[dofs][:, dofs]
            w, X = np.linalg.eigh(B.T @ (Kb @ B))
            scale = max(float(abs(Kb).sum(axis=1).max()), 1e-300)
            free = w <= _NULL_TOL * scale
            if not free.all():
                Q = np.linalg.lstsq(R @ V, B @ X[:, free], rcond=None)[0]
                V = V @ Q
        if V.shape[1]:
            Zb = np.zeros((N, V.shape[1]))
            Zb[dofs] = R @ V
            cols.append(Zb)
    if not cols:
        return np.zeros((N, 0))
    Z, _ = np.linalg.qr(np.hstack(cols))
    Z[is_fixed] = 0.0
    scale = abs(K).sum(axis=1).max()
    resid = np.abs(K @ Z).max() if Z.size else 0.0
    if resid > 1e-8 * scale:
        raise SolverError(f"condensation: the free rigid-body modes of the supported model are "
                          f"not in its null space (|K Z| = {resid:.3e} of {scale:.3e}); the "
                          "supports hold part of a body's rigid motion only")
    return Z


def _pinned(Z: np.ndarray, avoid: np.ndarray | None = None) -> np.ndarray:
    """One DOF per free mode, chosen so that holding them removes every mode
    (pivoted QR of ``Z^T``), away from the DOFs ``avoid`` (the contact
    nodes': holding one of them would leave its row of ``Hn`` empty)."""
    from scipy.linalg import qr

    if Z.shape[1] == 0:
        return np.zeros(0, dtype=np.int64)
    Z = Z.copy()
    if avoid is not None:
        Z[avoid] *= 1e-3
    _, _, piv = qr(Z.T, mode="economic", pivoting=True)
    return np.sort(piv[:Z.shape[1]])


class Supported:
    """The supported stiffness of a contact system, its free rigid-body modes held.

    The supports' DOFs and one DOF per rigid-body mode they leave free (chosen
    away from the contact nodes) are held: the result is a generalised inverse
    ``K^+`` for loads in equilibrium, the operator the condensation applies,
    by one sparse LU per body (factorised on first use).

    Parameters
    ----------
    cs : ContactSystem
        The contact system (:meth:`brakewear.BrakeModel.contact_system`).
    rows : sparse matrix, optional
        Further rows condensed with the contact nodes (the caliper's supports,
        :mod:`brakewear.caliper.interface`): their DOFs are not held either.

    Attributes
    ----------
    K : scipy.sparse.csr_matrix
        The stiffness.
    Z : ndarray
        (N, m) the free rigid-body modes, orthonormal columns.
    held : ndarray
        (N,) True on the held DOFs.
    keep : list of ndarray
        Each body's DOFs that are not held.
    """

    def __init__(self, cs, rows=None):
        from ..contact.elimination import body_labels

        self.K = K = cs.K.tocsr()
        N = K.shape[0]
        fixed = np.unique(np.asarray(cs.fixed, dtype=np.int64))
        self.Z = free_modes(K, cs.coords, fixed)
        self.held = np.zeros(N, dtype=bool)
        self.held[fixed] = True
        touched = np.unique(constraint_rows(cs.pair, N).indices)
        if rows is not None:        # further condensed rows (supports): not held either
            touched = np.union1d(touched, sp.csr_matrix(rows).indices)
        self.held[_pinned(self.Z, touched)] = True
        labels = body_labels(K)
        labels = np.zeros(N // 3, dtype=np.int64) if labels is None else labels
        dof_body = np.repeat(labels, 3)
        self.keep = [np.nonzero((dof_body == b) & ~self.held)[0] for b in np.unique(labels)]
        self._lu = [None] * len(self.keep)
        self.figures = [{} for _ in self.keep]

    def factor(self, i: int):
        """The LU of body ``i``'s free, unheld DOFs."""
        import scipy.sparse.linalg as spla

        if self._lu[i] is None:
            t0 = time.perf_counter()
            keep = self.keep[i]
            Kb = self.K[keep][:, keep].tocsc()
            self._lu[i] = lu = spla.splu(Kb, permc_spec="MMD_AT_PLUS_A",
                                         options={"SymmetricMode": True})
            # lu.nnz: the factor's own count (lu.L and lu.U would be copies of it)
            self.figures[i].update(dofs=int(keep.size), factor_s=time.perf_counter() - t0,
                                   factor_nnz=int(lu.nnz))
        return self._lu[i]

    def release(self, i: int) -> None:
        """Free body ``i``'s factorisation (refactorised on the next use)."""
        self._lu[i] = None

    def apply(self, F: np.ndarray) -> np.ndarray:
        """``K^+ F`` (zero on the held DOFs); ``F`` must be in equilibrium."""
        u = np.zeros(self.K.shape[0])
        for i, keep in enumerate(self.keep):
            u[keep] = self.factor(i).solve(F[keep])
        return u


def body_solves(sup: Supported, i: int, columns, products):
    """``Y^T B`` for ``Y = K_kk^-1 columns_k`` over body ``i``'s DOFs, in
    blocks of :data:`BLOCK` columns: one (n_columns x n_products) array."""
    lu = sup.factor(i)
    keep = sup.keep[i]
    t1 = time.perf_counter()
    Cb = columns[keep].tocsc()
    used = np.nonzero(np.diff(Cb.indptr))[0]
    Bb = products[keep].tocsr()
    out = np.zeros((columns.shape[1], products.shape[1]))
    for a in range(0, used.size, BLOCK):
        idx = used[a:a + BLOCK]
        Y = lu.solve(Cb[:, idx].toarray())
        out[idx] = (Bb.T @ Y).T
    sup.release(i)              # one body's factor alive at a time
    fig = sup.figures[i]
    fig.update(columns=int(used.size), solve_s=time.perf_counter() - t1)
    logger.info("condensation, body %d: %d DOFs, factor %.2f s (%d entries), %d columns "
                "%.2f s", i, fig["dofs"], fig["factor_s"], fig["factor_nnz"],
                fig["columns"], fig["solve_s"])
    return out


class LoadGap:
    """The gap change at the contact nodes under a nodal load (a thermal strain)
    and the free modes' share of it: ``(C K^+ F, Z^T F)``."""

    def __init__(self, cs):
        self.sup = Supported(cs)
        self.C = constraint_rows(cs.pair, cs.K.shape[0]).tocsr()

    def __call__(self, F: np.ndarray):
        sup = self.sup
        with blas_threads(1):
            u = sup.apply(np.where(sup.held, 0.0, F))
        return self.C @ u, sup.Z.T @ F


def condensation_key(cs) -> str:
    """The cache key of a contact system: a hash of its stiffness, supports,
    load per unit line pressure and contact geometry (normals, coupling,
    sliding direction)."""
    K = cs.K.tocsr()
    pr = cs.pair
    # the load's distribution, to 10 digits (a load scaled to another line pressure
    # differs in its last bits)
    f = cs.f / max(float(np.abs(cs.f).max()), 1e-300)
    parts = [K.data, K.indices, K.indptr, np.unique(cs.fixed), np.round(f * 1e10),
             pr.slave, pr.normal, np.zeros(0) if pr.drag is None else pr.drag, pr.area]
    if not pr.rigid:
        W = pr.coupling.tocsr()
        parts += [W.data, W.indices, W.indptr]
    return array_hash(*parts)


def condense(cs, line_pressure: float, *, cache=None, memory_budget: float | None = None
             ) -> Condensation:
    """Condense the contact system ``cs`` (:meth:`BrakeModel.contact_system`,
    built at ``line_pressure`` Pa) onto its contact nodes; read from or written
    to the cache (:func:`cache_dir`).  ``memory_budget`` (GB) bounds
    :func:`condensation_memory`, checked before any factorisation."""
    from ..mesh.estimate import memory_budget as budget

    key = condensation_key(cs)
    folder = cache_dir(cache)
    path = None if folder is None else folder / f"{key}.npz"
    if path is not None and path.exists():
        z = read_cache(path, _KEYS, _shapes_agree)
        if z is not None and z["hf"].size == cs.pair.slave.size:
            logger.info("condensation read from %s", path)
            return Condensation(*(z[k] for k in _KEYS), key=key,
                                info={"cached": str(path), "seconds": 0.0})
    N, ns = cs.K.shape[0], cs.pair.slave.size
    need = condensation_memory(ns, N)
    avail, source = budget(memory_budget)
    if need > avail:
        raise SolverError(f"condensing {ns} contact nodes of a {N}-DOF model needs about "
                          f"{need / 1e9:.1f} GB ({ns}^2 x 16 bytes of compliance, a "
                          f"{BLOCK}-column block and the sparse factor); {source} is "
                          f"{avail / 1e9:.1f} GB. Use a coarser mesh or the FE interface")
    cond = _compute(cs, line_pressure)
    cond.key = key
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        # atomic: a parallel reader sees all or nothing
        save_arrays(path, {k: getattr(cond, k) for k in _KEYS})
        cond.info["cached"] = str(path)
    return cond


def _shapes_agree(z: dict) -> bool:
    n, m = z["hf"].size, z["zf"].size
    return (z["Hn"].shape == z["Ht"].shape == (n, n) and z["E"].shape == (n, m)
            and z["Dt"].shape == (m, n))


def read_cache(path: Path, keys, agree) -> dict | None:
    """The arrays of the cache file ``path`` (``keys``), or None -- with a warning
    naming the file, which is removed -- when it is cut, damaged or not a cache
    (``agree(arrays)``: whether their shapes fit together): it is then computed anew."""
    try:
        z = load_arrays(path, "the condensation cache", required=keys)
        if all(z[k].dtype.kind == "f" for k in keys) and agree(z):
            return z
        reason = f"the condensation cache {path}'s arrays do not fit together"
    except StoredFileError as e:
        reason = str(e)
    logger.warning("%s: computing it again and replacing the file", reason)
    try:
        path.unlink()
    except OSError:
        pass
    return None


def _compute(cs, line_pressure: float) -> Condensation:
    """The condensation itself (no cache)."""
    t0 = time.perf_counter()
    sup = Supported(cs)
    N = sup.K.shape[0]
    pair, held, Z = cs.pair, sup.held, sup.Z
    mask = sp.diags((~held).astype(float))
    C = (constraint_rows(pair, N) @ mask).tocsr()
    G1 = drag_loads(pair, N, mu=1.0 if pair.drag is not None else 0.0).tocsr()
    f = np.where(held, 0.0, cs.f) / line_pressure
    B = sp.hstack([C.T, mask @ G1, sp.csc_matrix(f[:, None])]).tocsc()
    with blas_threads(1):
        YB = sum(body_solves(sup, i, C.T.tocsc(), B) for i in range(len(sup.keep)))
    ns = pair.slave.size
    cond = Condensation(Hn=YB[:, :ns], Ht=YB[:, ns:2 * ns], hf=YB[:, 2 * ns].copy(),
                        E=np.asarray(constraint_rows(pair, N) @ Z),
                        Dt=np.asarray((G1.T @ Z).T), zf=Z.T @ (cs.f / line_pressure))
    cond.info = {"seconds": time.perf_counter() - t0, "bodies": sup.figures,
                 "modes": Z.shape[1], "bytes": cond.nbytes}
    logger.info("condensed %d contact nodes of %d DOFs in %.1f s (%d free modes)", ns, N,
                cond.info["seconds"], Z.shape[1])
    return cond


def check_scene_size(scene) -> None:
    """``interface.model = "condensed"``: the condensation of the pad's contact nodes (two
    dense ``n x n`` compliances, :func:`condensation_memory`)
    fits the memory budget; estimated from the geometry like the model's size (a scene
    with its own pad mesh is checked when the run condenses)."""
    if "pad" in scene.mesh_files:
        return
    import math

    from ..caliper.loads import resolve_layout
    from ..mesh.estimate import estimate_model, memory_budget
    g = scene.meshed_geometry
    full = resolve_layout(scene.geometry, scene.layout, scene.rotor) == "full"
    est = estimate_model(g, scene.mesh_size, scene.rotor, scene.piston, full=full)
    pad, h = g.pad, g.mesh.pad_size or est.size
    nr = max(2, math.ceil((pad.outer_radius - pad.inner_radius) / h))
    nth = max(2, math.ceil(pad.arc_angle * 0.5 * (pad.inner_radius + pad.outer_radius) / h))
    n = (nr + 1) * (nth + 1) * (2 if full else 1)
    need = condensation_memory(n, est.dofs)
    avail, source = memory_budget(scene.numerics.memory_budget)
    if need > avail:
        raise fail("interface.model", f"'condensed' condenses about {n} pad contact nodes of "
                                      f"a {est.dofs}-DOF model at mesh.size = "
                                      f"{shown_value('mesh.size', est.size, 'm')}: about "
                                      f"{need / 1e9:.1f} GB, beyond {source} "
                                      f"({avail / 1e9:.1f} GB); use a coarser mesh or "
                                      "interface.model = 'fe'")
