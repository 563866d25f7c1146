"""Many cycles without simulating every one: the cycle jump and its step control.

Archard wear accumulates slowly against the time a cycle takes, so one
simulated cycle stands for the next ``N``: the kind's
:meth:`~brakewear.tribology.kinds.TribometerKind.advance` simulates one cycle with its
wear scaled by ``N`` (a reciprocating test books each increment's wear times
``N`` before the next increment: McColl, Ding and Leen's cycle jump; a sliding
test solves the revolution's contact with the ``N`` revolutions' wear in it:
backward Euler) and returns the jump's mean wear per cycle ``r``.  The jump's
error is estimated from the change of ``r`` between jumps::

    e = N / 2 max |r_n - r_(n-1)| * 2 N / (N + N_(n-1)),

and held below ``tol`` times the deepest wear: a jump over the bound is taken
again shorter, and the next one grows or shrinks by ``sqrt(tol / e)`` (the
error is second order in ``N``), between ``min_jump`` and ``max_jump``.  The
bound is relative, in depths only, so a test with ``k`` and one with ``2 k``
over half the cycles take the same jumps in ``k N`` and end on the same
profile to round-off (the ``k s`` equivalence of Podra and Andersson).
"""
from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import StepSizeError

logger = logging.getLogger(__name__)

__all__ = ["JumpControl", "Jump", "cycle_jumps"]


@dataclass(frozen=True)
class JumpControl:
    """The cycle jump's settings.

    Attributes
    ----------
    tol : float
        Bound of a jump's error over the deepest wear.
    first : float
        The first jump (cycles).
    min_jump, max_jump : float
        Bounds of a jump (cycles); ``fixed`` jumps of ``first`` cycles when True.
    max_rejects : int
        Rejected jumps in a row before :class:`~brakewear.errors.StepSizeError`.
    """

    tol: float = 0.02
    first: float = 1.0
    min_jump: float = 1.0
    max_jump: float = 1e9
    fixed: bool = False
    max_rejects: int = 20


@dataclass(frozen=True)
class Jump:
    """One accepted jump: its cycles, the estimated error, the rate it ended on."""

    cycles: float
    jump: float
    error: float
    simulated: int
    rejected: int
    wall_s: float


def _scale(depths: dict) -> float:
    return max((float(np.max(np.abs(h))) for h in depths.values() if h.size), default=0.0)


def cycle_jumps(advance: Callable, start, depths: dict, total: float, control: JumpControl,
                on_jump: Callable | None = None):
    """Integrate the wear of ``total`` cycles by jumps.

    Parameters
    ----------
    advance
        ``advance(depths, last, N) -> CycleResult``: one simulated cycle at
        ``depths`` from the previous result ``last`` with its wear scaled by
        ``N``; its ``rates`` are the jump's mean wear per cycle of each body.
    start
        The result the first cycle starts from.
    depths
        Body name -> (n,) initial worn depths (m).
    total
        Cycles to integrate.
    control
        :class:`JumpControl`.
    on_jump
        Called with ``(Jump, depths, CycleResult)`` after every accepted jump.

    Returns
    -------
    tuple
        ``(depths, last CycleResult, list of Jump)``.
    """
    t0 = time.perf_counter()
    last, r_prev, n_prev = start, None, None
    simulated, cycles = 0, 0.0
    N = control.first
    jumps: list[Jump] = []
    rejects = 0
    while cycles < total * (1 - 1e-12):
        N = min(N, total - cycles)
        res = advance(depths, last, N)
        simulated += 1
        trial = {b: depths[b] + N * res.rates[b] for b in depths}
        if r_prev is None:
            err = 0.0
        else:
            diff = max(float(np.max(np.abs(res.rates[b] - r_prev[b]))) for b in depths)
            err = N * diff / max(_scale(trial), 1e-300) * N / (N + n_prev)
        can_shrink = (not control.fixed) and N > control.min_jump * (1 + 1e-12)
        if err > control.tol and can_shrink:
            rejects += 1
            if rejects > control.max_rejects:
                raise StepSizeError(
                    f"cycle jump: {rejects} jumps in a row over the error bound "
                    f"{control.tol:g} at cycle {cycles:g} (last jump {N:g} cycles, error "
                    f"{err:.3g}); raise numerics.wear_tol or lower numerics.min_jump")
            N = max(control.min_jump, N * max(0.2, 0.9 * np.sqrt(control.tol / err)))
            continue
        rejects_here, rejects = rejects, 0
        depths, cycles = trial, cycles + N
        jumps.append(Jump(cycles=cycles, jump=N, error=err, simulated=simulated,
                          rejected=rejects_here, wall_s=time.perf_counter() - t0))
        if on_jump is not None:
            on_jump(jumps[-1], depths, res)
        last, r_prev, n_prev = res, res.rates, N
        if not control.fixed:
            grow = 4.0 if err == 0 else min(4.0, 0.9 * np.sqrt(control.tol / err))
            N = float(np.clip(N * grow, control.min_jump, control.max_jump))
    logger.info("cycle jumps: %d jumps over %g cycles, %d cycles simulated", len(jumps),
                cycles, simulated)
    return depths, last, jumps
