"""BLAS threads: run the AMG setup, the Krylov solves and the condensed
interface's factorisations and dense solves with one BLAS thread (through
threadpoolctl, the scientific Python stack's own thread control)."""
from __future__ import annotations

import logging
from contextlib import contextmanager

from threadpoolctl import ThreadpoolController

logger = logging.getLogger(__name__)

__all__ = ["blas_threads"]


_CONTROLLER: ThreadpoolController | None = None


def _blas_controller() -> ThreadpoolController:
    """threadpoolctl's view of the BLAS libraries loaded in this process (NumPy and
    SciPy each bundle their own OpenBLAS), taken once, on first use: the solvers
    import SciPy before they get here."""
    global _CONTROLLER
    if _CONTROLLER is None:
        _CONTROLLER = ThreadpoolController()
    return _CONTROLLER


@contextmanager
def _single_threaded_blas():
    """Run the block with one OpenBLAS thread, then restore the counts.

    The AMG setup and the Krylov solves make thousands of level-1 BLAS calls
    (dot products, norms) on vectors of 10^4-10^5 entries, and SuperLU's
    coarse solves level-2 ones; the sparse kernels themselves are single
    threaded.  With OpenBLAS's default threads each such call costs
    milliseconds of spinning and waking on a loaded machine: measured on the
    105k brake with 2 threads, twice the CPU time of the solve with 1
    (docs/amg_settings.md).
    """
    with blas_threads(1):
        yield


@contextmanager
def blas_threads(threads: int = 1):
    """Run the block with ``threads`` BLAS threads (OpenBLAS, every copy loaded),
    then restore the counts.

    The condensed interface's sparse LU (SuperLU's supernodal kernels call
    BLAS) and its dense set solves run with one: OpenBLAS's threads spin
    while they wait, and beside another busy process on the same cores they
    took 3-4x the CPU time of one thread for the same work
    (docs/condensed.md, "Threads").  Nested blocks are allowed.
    """
    with _blas_controller().limit(limits=int(threads), user_api="blas"):
        yield
