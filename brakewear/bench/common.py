"""Helpers shared by the benchmarks: peak memory of this process, table cells."""
from __future__ import annotations

import sys

__all__ = ["peak_rss_mb", "fmt"]


def peak_rss_mb() -> float:
    import resource

    r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return r / 1024.0 if sys.platform != "darwin" else r / 2 ** 20


def fmt(v, spec: str, none: str = "-") -> str:
    return none if v is None else format(v, spec)
