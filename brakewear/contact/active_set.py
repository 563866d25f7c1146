"""The active-set driver shared by every contact solve.

A contact solve alternates between two steps: solve the linear system of
one active set (the nodes held in contact), then decide the next set from
that solution.  The solvers differ only in the first step and in what
measures "in contact": a Lagrange solve (:func:`brakewear.contact.solve_contact`)
has multipliers on the active nodes and gaps on the open ones, the compliant
solve of an implicit wear step (:func:`brakewear.contact.solve_compliant_contact`)
has spring forces on both.  Everything else lives here, once:

* the **update rule**: an active node stays while its multiplier is not
  tensile beyond a release bound, an open node enters when it penetrates
  beyond an entry bound (the primal-dual active-set rule, :func:`pdas_update`);
* the **tolerance schedule**: loose (inexact) solves while the set moves, a
  medium tolerance once it has nearly settled, and one solve to the full
  tolerance that confirms the set it reproduces (:meth:`ActiveSetDriver.solve_tolerance`);
* **cycle handling**: a set that repeats turns the solves tight; then either
  the updates turn conservative (:func:`conservative_update`: add or release,
  never both) or the release band widens once (:attr:`ActiveSetOptions.on_cycle`);
* the guards: an empty set raises :class:`~brakewear.errors.ContactLostError`,
  an update that would empty a large set keeps its least tensile tenth, a set
  that never settles raises :class:`~brakewear.errors.ActiveSetError`.

A solver hands the driver a :class:`SetProblem`: ``solve(active, tol, rtol0)``
for one set and ``margins(active, band)`` for the state the solution leaves.
The sets are flat boolean arrays over every slave node of every pair.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Literal, NamedTuple, Protocol

import numpy as np

from ..errors import ActiveSetError, ContactError, ContactLostError
from ..solvers.heartbeat import beat

logger = logging.getLogger(__name__)

__all__ = [
    "ActiveSetOptions",
    "LAGRANGE",
    "COMPLIANT",
    "EXACT",
    "Margins",
    "SetProblem",
    "ActiveSetDriver",
    "pdas_update",
    "conservative_update",
]


@dataclass(frozen=True)
class ActiveSetOptions:
    """The policy and tuning of an active-set iteration (one frozen object).

    Attributes
    ----------
    max_iter : int
        Solves allowed before :class:`~brakewear.errors.ActiveSetError`.
    release_tol : float
        Release band, relative to the largest multiplier: an active node is
        released only when it pulls harder than this (a margin above the
        linear solver's noise, without which nodes at the contact edge can
        flip forever).
    loose_tol : float or None
        Relative tolerance of the first solve, and of every loose solve when
        ``inexact`` is None.  None: every solve is tight.
    inexact : float or None
        Loose solves after the first stop when they have cut their warm-start
        residual by this factor (an inexact active-set iteration).
    medium_tol : float or None
        Tolerance of the solves after the loose phase while the set still
        moves; a set that a medium solve reproduces is confirmed by one solve
        to the full tolerance.  None: straight to the full tolerance.
    settling : float
        An update that changes at most this share of the active nodes counts
        as "nearly settled" for the flip rule.
    flip_limit : int or None
        Under loose solves, a node that changes state this many times once
        the set has nearly settled turns every later solve tight (its state
        is being decided by the solver's noise).  None: no flip rule.
    wander : float or None
        A set that has not settled after this share of ``max_iter`` switches
        to conservative updates (whatever ``on_cycle``).  None: never.
    on_cycle : {"conservative", "widen"}
        What a repeated set does once the solves are tight: switch to
        :func:`conservative_update` for the rest of the solve, or widen the
        release and entry bands to ``cycle_band`` once (a second cycle then
        raises).
    cycle_band : float
        The widened band of ``on_cycle = "widen"``.
    keep_on_empty : float or None
        If an update would release every node of a set of more than one, keep
        this share of the set that pulls least (an overshoot on a very
        non-conformal start; an empty set is singular).  None: no rescue.
    """

    max_iter: int = 60
    release_tol: float = 1e-6
    loose_tol: float | None = 1e-2
    inexact: float | None = 1e-1
    medium_tol: float | None = 1e-6
    settling: float = 0.1
    flip_limit: int | None = 2
    wander: float | None = 1 / 3
    on_cycle: Literal["conservative", "widen"] = "conservative"
    cycle_band: float = 1e-3
    keep_on_empty: float | None = 0.1

    def __post_init__(self):
        if self.on_cycle not in ("conservative", "widen"):
            raise ContactError(f"on_cycle = {self.on_cycle!r}; allowed: 'conservative', 'widen'")
        if int(self.max_iter) < 1:
            raise ContactError(f"max_iter = {self.max_iter!r}; need >= 1")
        for name in ("loose_tol", "inexact", "medium_tol"):
            v = getattr(self, name)
            if v is not None and not (np.isfinite(v) and 0 < v < 1):
                raise ContactError(f"{name} = {v!r} is not allowed; need 0 < {name} < 1 or None")
        for name in ("release_tol", "cycle_band"):
            v = getattr(self, name)
            if not (np.isfinite(v) and 0 <= v < 1):
                raise ContactError(f"{name} = {v!r} is not allowed; need 0 <= {name} < 1")


#: rigid (Lagrange) contact: loose first solve to 1e-2, then warm starts cut by 10x,
#: medium solves to 1e-6 once the set repeats, conservative updates on a cycle
LAGRANGE = ActiveSetOptions()

#: compliant contact (implicit wear step): solves to 1e-4 while the set moves, the
#: band widened to 1e-3 on a cycle under tight solves, conservative updates once the
#: set has wandered for a third of the budget
COMPLIANT = ActiveSetOptions(loose_tol=1e-4, inexact=None, medium_tol=None, flip_limit=None,
                             on_cycle="widen", keep_on_empty=None)

#: exact (direct) solves: no tolerance schedule, conservative updates on a cycle
EXACT = ActiveSetOptions(loose_tol=None, inexact=None, medium_tol=None, flip_limit=None)


def _fmt(x) -> str:
    return "n/a" if x is None else f"{x:.2e}"


class Margins(NamedTuple):
    """The state a solution leaves, per slave node (flat over all pairs).

    An active node stays while ``stay > -stay_bound``; an open node enters
    when ``enter > enter_bound``.  For a Lagrange solve ``stay`` is the
    compressive multiplier and ``enter`` the penetration (minus the gap); for
    a compliant one both are the spring force.
    """

    stay: np.ndarray
    stay_bound: np.ndarray | float
    enter: np.ndarray
    enter_bound: np.ndarray | float


class SetProblem(Protocol):
    """What a contact solver supplies to :class:`ActiveSetDriver`."""

    def solve(self, active: np.ndarray, tol: float, rtol0: float | None) -> None:
        """Solve the system of ``active`` to relative tolerance ``tol`` (or, with
        ``rtol0``, until the warm start's residual is cut by that factor)."""

    def margins(self, active: np.ndarray, band: float) -> Margins:
        """The margins of the last solution, with release band ``band``."""


def pdas_update(active: np.ndarray, m: Margins) -> np.ndarray:
    """Primal-dual active set: stay if compressive, enter if penetrating."""
    return np.where(active, m.stay > -m.stay_bound, m.enter > m.enter_bound)


def conservative_update(active: np.ndarray, m: Margins) -> np.ndarray:
    """Add every penetrating node; if none, release the most tensile nodes only:
    those pulling at least half as hard as the worst one.  Adding and releasing
    never happen in the same iteration, which is what stops a cycle; releasing
    in bulk (rather than one node at a time) keeps large sets within budget."""
    pen = ~active & (m.enter > m.enter_bound)
    if pen.any():
        return active | pen
    worst = float(np.min(m.stay[active], initial=0.0)) if active.any() else 0.0
    return active & ~((m.stay < 0.5 * worst) & (m.stay < -m.stay_bound))


@dataclass
class ActiveSetDriver:
    """Run the active-set iteration of one :class:`SetProblem` under ``options``.

    Parameters
    ----------
    options : ActiveSetOptions
        Policy and tuning.
    tol : float
        The full tolerance of the linear solves.
    exact : bool
        The problem solves exactly (a direct factorisation): no tolerance
        schedule, and a set that reproduces itself is accepted at once.
    tight : bool
        Start with tight solves (a given start set taken as a good guess:
        a loose solve's noise would move its edge nodes).
    name : str
        Names the problem in messages.
    hint : str
        Appended to the message of a lost contact (e.g. the net load).
    """

    options: ActiveSetOptions
    tol: float
    exact: bool = False
    tight: bool = False
    name: str = "contact"
    hint: str = ""
    medium: bool = False
    conservative: bool = False
    widened: bool = False
    tight_reason: str | None = None
    tight_from: int | None = None
    counts: list = field(default_factory=list)
    solves: int = 0

    def __post_init__(self):
        if self.tight:
            self.tight_reason, self.tight_from = "given set", 1
        self.tight = self.tight or self.exact or self.options.loose_tol is None

    @property
    def band(self) -> float:
        return self.options.cycle_band if self.widened else self.options.release_tol

    def solve_tolerance(self) -> tuple[float, float | None]:
        """``(tol, rtol0)`` of the next solve under the schedule."""
        o = self.options
        if self.tight:
            return (max(self.tol, o.medium_tol) if self.medium else self.tol), None
        if self.solves == 0 or o.inexact is None:
            return max(self.tol, o.loose_tol), None
        return self.tol, o.inexact

    def _go_tight(self, reason: str, it: int, medium: bool) -> None:
        self.tight, self.tight_reason, self.tight_from = True, reason, it + 1
        self.medium = medium and self.options.medium_tol is not None

    def run(self, problem: SetProblem, active: np.ndarray) -> np.ndarray:
        """Iterate from ``active`` until a set reproduces itself under a tight
        solve; return it (the problem holds its solution)."""
        o = self.options
        active = np.asarray(active, dtype=bool).copy()
        seen: set = set()
        flips = np.zeros(active.size, dtype=np.int64)
        for it in range(1, o.max_iter + 1):
            if not active.any():
                raise ContactLostError(
                    f"{self.name}: no node is in contact after {it - 1} active-set "
                    f"iteration(s): the load separates the bodies{self.hint}",
                    figures=self.figures(problem))
            problem.solve(active, *self.solve_tolerance())
            self.solves += 1
            beat(self.name, iteration=it, active=int(active.sum()), max_iter=o.max_iter)
            m = problem.margins(active, o.release_tol)
            new = (conservative_update if self.conservative else pdas_update)(active, m)
            self.counts.append(int(active.sum()))
            if np.array_equal(new, active):
                if self.exact or (self.tight and not self.medium):
                    return active
                if self.tight:      # a medium solve reproduced its set: confirm it
                    self.medium = False
                else:
                    self._go_tight("set repeated", it, medium=True)
                continue
            if not new.any() and not self.tight:
                # a loose solve (from a start guess that is already near its
                # tolerance) cannot decide that the bodies separate: solve the
                # same set again, tightly
                self._go_tight("set would empty", it, medium=False)
                continue
            new = self._rescue_empty(active, new, m, it)
            if not self.tight:
                self._count_flips(active, new, flips, it)
            new, seen, done = self._on_repeat(problem, active, new, seen, m, it)
            if done:
                return active
            seen.add(np.packbits(active).tobytes())
            active = new
        raise ActiveSetError(
            f"{self.name}: active set did not settle in {o.max_iter} iterations (the budget "
            f"max_iter; active counts {self.counts[-6:]}, conservative={self.conservative}, "
            f"last relative residual {_fmt(self.figures(problem)['relative_residual'])})",
            figures=self.figures(problem))

    def _rescue_empty(self, active, new, m: Margins, it: int) -> np.ndarray:
        """The primal-dual rule released every node at once (an overshoot on a
        very non-conformal start): keep the tenth of the set that pulls least.
        A load that really lifts the pad off empties the set in a few such
        steps and ends in ContactLostError."""
        n_act = int(active.sum())
        if self.options.keep_on_empty is None or new.any() or n_act <= 1:
            return new
        keep = max(1, int(round(n_act * self.options.keep_on_empty, 9)))
        cut = np.sort(m.stay[active])[-keep]
        logger.info("%s: active set would empty after %d iterations; keeping the %d least "
                    "tensile nodes", self.name, it, keep)
        return active & (m.stay >= cut)

    def _count_flips(self, active, new, flips, it: int) -> None:
        """Once the set has nearly settled, a node that changes state a second
        time while the solves are loose is deciding on the solver's noise (a
        contact edge where the pressure goes to zero): from here on every solve
        is tight.  Large early updates do not count: there the primal-dual rule
        overshoots, which is no noise."""
        o = self.options
        if o.flip_limit is None:
            return
        changed = int(np.count_nonzero(active != new))
        if changed <= o.settling * max(int(active.sum()), 1):
            flips += active != new
            if int(flips.max()) >= o.flip_limit:
                self._go_tight("flip", it, medium=True)
                logger.debug("%s: a node flipped twice under loose solves; tight solves "
                             "from now on", self.name)

    def _on_repeat(self, problem, active, new, seen, m: Margins, it: int):
        """Cycle handling: returns ``(next set, seen sets, accept the current set)``."""
        o = self.options
        key = np.packbits(new).tobytes()
        # a set that wanders for a share of the budget without repeating exactly
        # (edge nodes flipping in turn, or the primal-dual rule overshooting on an
        # unsymmetric operator) turns conservative under either policy
        wandering = o.wander is not None and it >= int(o.max_iter * o.wander)
        if o.on_cycle == "conservative" or (wandering and not self.conservative):
            # under the conservative policy a set that repeats cycles as well
            if (key in seen or wandering) and not self.conservative:
                logger.info("%s: active set %s after %d iterations; switching to "
                            "conservative updates", self.name,
                            "cycles" if key in seen else "does not settle", it)
                self.conservative = True
                self.medium = False  # a loose solve's noise lets an edge node flip forever
                if not self.tight:
                    self._go_tight("conservative", it, medium=False)
                new = conservative_update(active, m)
            return new, seen, False
        if key not in seen:
            return new, seen, False
        if not self.tight:
            logger.debug("%s: loose active set repeats after %d iterations; tight solves "
                         "from here", self.name, it)
            self._go_tight("set repeated", it, medium=False)
            return new, set(), False
        if not self.widened:
            # a repeat under tight solves: a node at the contact edge that is in
            # tension when active and compressed when not (friction makes the
            # operator unsymmetric, so the sign rule need not have a fixed point);
            # a node keeps its status while its force is within the wider band
            self.widened = True
            new = pdas_update(active, problem.margins(active, self.band))
            logger.info("%s: active set repeats after %d iterations; status kept for "
                        "forces within %.0e of the largest", self.name, it, self.band)
            return new, set(), bool(np.array_equal(new, active))
        raise ActiveSetError(
            f"{self.name}: active set cycles after {it} iterations ({int(active.sum())} -> "
            f"{int(new.sum())} active) under tight solves, with a band of {self.band:.0e} "
            "of the largest force", figures=self.figures(problem))

    def figures(self, problem) -> dict:
        """The figures of an error: solves, the active-set sizes seen, the budget and
        the last linear solve's relative residual (None where the problem has none)."""
        res = getattr(problem, "last_residual", None)
        return {"iterations": self.solves, "max_iter": self.options.max_iter,
                "active_counts": list(self.counts), "conservative": self.conservative,
                "relative_residual": None if res is None else float(res)}

    def report(self) -> dict:
        """The driver's figures for a solver's ``info``."""
        return {"active_set_iterations": self.solves, "conservative": self.conservative,
                "active_counts": list(self.counts), "tight_from": self.tight_from,
                "tight_reason": self.tight_reason, "hysteresis_band": self.band}
