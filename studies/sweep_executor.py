"""Where a study's sweep runs: a local process pool, or a dask.distributed cluster.

The cleaning studies map one task per sweep point (a line pressure, a
deceleration, a Monte Carlo sample) onto any ``concurrent.futures.Executor``;
their command lines choose it with ``--workers N`` and ``--dask ADDRESS|local``
(:func:`add_executor_options`, :func:`study_executor`).  dask is optional and
imported only when asked for.
"""
from __future__ import annotations

import argparse
from collections.abc import Iterator
from concurrent.futures import Executor, ProcessPoolExecutor
from contextlib import contextmanager


def add_executor_options(parser: argparse.ArgumentParser, workers: int = 2) -> None:
    """``--workers`` (process-pool workers) and ``--dask ADDRESS|local``."""
    parser.add_argument("--workers", type=int, default=workers,
                        help="process-pool workers (default %(default)s)")
    parser.add_argument("--dask", default=None, metavar="ADDRESS",
                        help="run on a dask.distributed scheduler at ADDRESS ('local': a local "
                             "cluster) instead of the process pool")


@contextmanager
def study_executor(dask: str | None = None, workers: int = 2) -> Iterator[Executor]:
    """An executor, shut down on leaving: a ``ProcessPoolExecutor(workers)``, or with
    ``dask`` a dask.distributed client's executor (``dask`` a scheduler address, or
    ``"local"``: a local cluster, closed with the client)."""
    if not dask:
        with ProcessPoolExecutor(max_workers=workers) as executor:
            yield executor
        return
    from dask.distributed import Client  # optional dependency

    with (Client() if dask == "local" else Client(dask)) as client:
        yield client.get_executor()
