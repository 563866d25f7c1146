"""BLAS threads: run the AMG setup and the Krylov solves with one BLAS thread."""
from __future__ import annotations

import ctypes
import logging
import os
from contextlib import contextmanager

logger = logging.getLogger(__name__)

__all__ = []


_BLAS_CONTROLS: list | None = None


def _openblas_controls() -> list:
    """(get, set) thread-count functions of every OpenBLAS loaded in this process.

    NumPy and SciPy each bundle their own OpenBLAS; both are found through
    ``/proc/self/maps`` (Linux).  Elsewhere, or if the symbols are missing,
    the list is empty and nothing is changed.
    """
    global _BLAS_CONTROLS
    if _BLAS_CONTROLS is None:
        _BLAS_CONTROLS = []
        try:
            with open("/proc/self/maps") as fh:
                paths = sorted({ln.split()[-1] for ln in fh
                                if "openblas" in os.path.basename(ln.split()[-1]).lower()
                                and ".so" in ln})
        except OSError:
            paths = []
        for path in paths:
            try:
                lib = ctypes.CDLL(path)
            except OSError:
                continue
            for prefix in ("scipy_openblas", "openblas"):
                for suffix in ("64_", ""):
                    get = getattr(lib, f"{prefix}_get_num_threads{suffix}", None)
                    put = getattr(lib, f"{prefix}_set_num_threads{suffix}", None)
                    if get is not None and put is not None:
                        get.restype, put.argtypes = ctypes.c_int, [ctypes.c_int]
                        _BLAS_CONTROLS.append((get, put))
                        break
                else:
                    continue
                break
    return _BLAS_CONTROLS


@contextmanager
def _single_threaded_blas():
    """Run the block with one OpenBLAS thread, then restore the counts.

    The AMG setup and the Krylov solves make thousands of level-1 BLAS calls
    (dot products, norms) on vectors of 10^4-10^5 entries, and SuperLU's
    coarse solves level-2 ones; the sparse kernels themselves are single
    threaded.  With OpenBLAS's default threads each such call costs
    milliseconds of spinning and waking on a loaded machine: measured on the
    105k brake with 2 threads, twice the CPU time of the solve with 1
    (docs/performance.md, "AMG settings").
    """
    saved = [(get(), put) for get, put in _openblas_controls()]
    for _, put in saved:
        put(1)
    try:
        yield
    finally:
        for n, put in saved:
            put(n)
