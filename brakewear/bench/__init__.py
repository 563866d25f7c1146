"""Benchmarks behind ``brakewear bench``: timings and errors, on the public API."""

from . import core
from .core import *  # noqa: F403

__all__ = [*core.__all__]
