"""Signs of life from inside long solves, for a progress display.

A wear step of a large model can spend minutes in one contact solve, and a
progress bar fed by accepted steps would then stand still.  The iterative
solvers call :func:`beat` once per iteration (an active-set iteration, a wear
step's retry); a display registers a listener with :func:`listening` and
shows the latest beat.  With no listener a beat costs one check of an empty
list.  The library never prints: what a beat shows is the listener's choice::

    from brakewear.solvers.heartbeat import listening

    seen = []
    with listening(lambda what, figures: seen.append(what)):
        ...   # run; each solver iteration calls the listener
"""
from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager

__all__ = ["beat", "listening"]

_listeners: list = []


def beat(what: str, **figures) -> None:
    """Tell the listeners that ``what`` is under way, with its ``figures``
    (e.g. ``beat("contact", iteration=7, active=105)``)."""
    for listener in _listeners:
        listener(what, figures)


@contextmanager
def listening(listener: Callable[[str, dict], None]) -> Iterator[None]:
    """Call ``listener(what, figures)`` at every :func:`beat` inside the block."""
    _listeners.append(listener)
    try:
        yield
    finally:
        _listeners.remove(listener)
