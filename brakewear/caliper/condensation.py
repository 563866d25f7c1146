"""The FE model condensed onto the pad's contact nodes and the caliper's rows together.

The caliper's rows (:mod:`brakewear.caliper.rows`: the piston's rim, the
fingers, the abutments) touch the pads through the FE model, so they are
condensed with the contact nodes: with ``A = [C; Cs]`` (the contact nodes'
normal rows, then the caliper's rows), the condensation holds

* ``H = A K^+ A^T`` (n x n, m/N) and ``Ht = A K^+ G`` (n x n_c): how every row
  moves under a unit force on any row, and under the unit friction load of
  each contact node;
* ``hf = A K^+ f`` per pascal of line pressure, ``E = A Z``, ``Dt = Z^T G``,
  ``zf = Z^T f`` per pascal,

computed as :func:`brakewear.interfaces.condensation.condense` does for the
contact nodes alone (one sparse factorisation per body, ``K^+ A^T`` in
blocks of columns) and cached on disk under a key that adds the rows' hash.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..contact.compliant import constraint_rows, drag_loads
from ..errors import SolverError
from ..interfaces.condensation import (
    BLOCK,
    Supported,
    array_hash,
    body_solves,
    cache_dir,
    condensation_key,
    condensation_memory,
    read_cache,
)
from ..storage import save_arrays

logger = logging.getLogger(__name__)

__all__ = ["CaliperCondensation", "condense_caliper"]

_KEYS = ("H", "Ht", "hf", "E", "Dt", "zf")
#: the last condensation this process computed, with its factorised stiffness (the
#: arrays are never changed after: interfaces share them)
_LAST: dict = {}


@dataclass
class CaliperCondensation:
    """The FE model condensed onto the contact nodes (first ``n_c`` rows) and the
    caliper's rows (the rest); see the module."""

    H: np.ndarray
    Ht: np.ndarray
    hf: np.ndarray
    E: np.ndarray
    Dt: np.ndarray
    zf: np.ndarray
    n_c: int
    key: str = ""
    info: dict = field(default_factory=dict)
    #: the factorised stiffness it was computed with (None when read from the cache)
    supported: object = field(default=None, repr=False)


def _rows_key(cs, rows: sp.spmatrix) -> str:
    R = sp.csr_matrix(rows)
    return array_hash(np.frombuffer(condensation_key(cs).encode(), dtype=np.uint8),
                 R.data, R.indices, R.indptr)


def condense_caliper(cs, rows: sp.spmatrix, line_pressure: float, *, cache=None,
                     memory_budget: float | None = None) -> CaliperCondensation:
    """Condense the contact system ``cs`` onto its contact nodes and the caliper's
    ``rows`` (sparse, over ``cs``'s DOFs); read from or written to the cache."""
    from ..mesh.estimate import memory_budget as budget

    n_c = cs.pair.slave.size
    key = _rows_key(cs, rows)
    if key in _LAST:            # this process condensed it: its factorisation too
        return _LAST[key]
    folder = cache_dir(cache)
    path = None if folder is None else folder / f"caliper-{key}.npz"
    if path is not None and path.exists():
        z = read_cache(path, _KEYS, _shapes_agree)
        if z is not None and z["H"].shape[0] == n_c + rows.shape[0]:
            logger.info("caliper condensation read from %s", path)
            return CaliperCondensation(*(z[k] for k in _KEYS), n_c=n_c, key=key,
                                       info={"cached": str(path), "seconds": 0.0})
    N, n = cs.K.shape[0], n_c + rows.shape[0]
    need = condensation_memory(n, N)
    avail, source = budget(memory_budget)
    if need > avail:
        raise SolverError(f"condensing {n} contact nodes and caliper rows of a {N}-DOF model "
                          f"needs about {need / 1e9:.1f} GB; {source} is {avail / 1e9:.1f} GB. "
                          "Use a coarser mesh")
    cond = _compute(cs, sp.csr_matrix(rows), line_pressure)
    cond.key = key
    _LAST.clear()
    _LAST[key] = cond
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        save_arrays(path, {k: getattr(cond, k) for k in _KEYS})
        cond.info["cached"] = str(path)
    return cond


def _shapes_agree(z: dict) -> bool:
    n, m = z["H"].shape[0], z["zf"].size
    return (z["H"].shape == (n, n) and z["Ht"].shape[0] == n and z["hf"].shape == (n,)
            and z["E"].shape == (n, m) and z["Dt"].shape[0] == m)


def _compute(cs, rows: sp.csr_matrix, line_pressure: float) -> CaliperCondensation:
    t0 = time.perf_counter()
    sup = Supported(cs, rows)
    N = sup.K.shape[0]
    pair, held, Z = cs.pair, sup.held, sup.Z
    mask = sp.diags((~held).astype(float))
    A = sp.vstack([constraint_rows(pair, N), rows]).tocsr()
    Am = (A @ mask).tocsr()
    G1 = drag_loads(pair, N, mu=1.0 if pair.drag is not None else 0.0).tocsr()
    f = np.where(held, 0.0, cs.f) / line_pressure
    B = sp.hstack([Am.T, mask @ G1, sp.csc_matrix(f[:, None])]).tocsc()
    YB = sum(body_solves(sup, i, Am.T.tocsc(), B) for i in range(len(sup.keep)))
    n, n_c = A.shape[0], pair.slave.size
    cond = CaliperCondensation(H=YB[:, :n], Ht=YB[:, n:n + n_c], hf=YB[:, n + n_c].copy(),
                               E=np.asarray(A @ Z), Dt=np.asarray((G1.T @ Z).T),
                               zf=Z.T @ (cs.f / line_pressure), n_c=n_c)
    cond.info = {"seconds": time.perf_counter() - t0, "bodies": sup.figures,
                 "modes": Z.shape[1], "rows": n - n_c, "block": BLOCK}
    cond.supported = sup
    logger.info("condensed %d contact nodes and %d caliper rows of %d DOFs in %.1f s "
                "(%d free modes)", n_c, n - n_c, N, cond.info["seconds"], Z.shape[1])
    return cond
