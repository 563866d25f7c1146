"""What a schedule carries from one application to the next besides the wear.

The wear of pad and rotor is the schedule's own state (:func:`~brakewear.duty.run_schedule`
carries it as the gap).  Other things a brake carries from application to
application -- a rust layer that changes the friction coefficient and the
wear laws, the rotor's temperatures that cone it -- are *schedule states*:
objects the run holds (``Run(..., states=[...])``) and the runner asks, in
the order given, at three points:

* ``before(app, context) -> dict or None`` -- before application ``app``
  runs; ``context`` holds its ``index``, the ``vehicle``, the brake's base
  friction coefficient ``mu`` and the ``offset`` (the gap offset per pad
  friction node the application starts from, the changes of the states before
  this one included).  The answer may hold ``"mu_factor"`` (the friction
  coefficient of this application is the base one times the product of the
  states' factors) and ``"gap"`` (m per pad friction node, added to the gap
  for this application only);
* ``step(pad_wear, rotor_wear)`` -- after each accepted wear step of a braked
  application, with the wear since the schedule's start (m, per pad friction
  node and per rotor wear node);
* ``after(record) -> dict or None`` -- once the application has run; what it
  answers is kept on the record under the state's ``name``
  (``record.states[name]``).

Values travel as arguments and answers: a state never reaches into the
runner.  A state is a part like an application (:mod:`brakewear.registry`):
its class carries its ``name`` and is registered (:func:`register_state`),
so that records name it and a user's state, defined outside the package, is
found as the built-in ones are; :func:`check_states` refuses an object that
is not of a registered kind, before anything runs.
"""
from __future__ import annotations

import logging
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np

from ..errors import DutyError
from ..registry import Registry

logger = logging.getLogger(__name__)

__all__ = ["ScheduleState", "register_state", "state_kinds", "check_states", "state_changes"]

_STATES = Registry("schedule state", "states", modules=("brakewear.cleaning.routine",),
                   members=("before", "step", "after"), error=DutyError)


@runtime_checkable
class ScheduleState(Protocol):
    """A state a schedule carries (see the module)."""

    name: ClassVar[str]

    def before(self, app: Any, context: dict) -> dict | None:
        """Changes for application ``app``: ``mu_factor`` and ``gap``."""

    def step(self, pad_wear: np.ndarray, rotor_wear: np.ndarray) -> None:
        """The wear since the schedule's start, after each accepted step."""

    def after(self, record: Any) -> dict | None:
        """What the state reports on the application's record."""


def register_state(part: type, *, replace: bool = False) -> type:
    """Add a state class to the kinds a run knows, by its ``name`` (a class decorator).

    Parameters
    ----------
    part
        The state's class (:class:`ScheduleState`): its ``name`` and its methods.
    replace
        Replace a kind of the same name (otherwise refused).

    Returns
    -------
    type
        ``part``.
    """
    return _STATES.register(part, replace=replace)


def state_kinds() -> tuple[str, ...]:
    """The registered kinds, in the order of registration.

    Returns
    -------
    tuple of str
        Their names.
    """
    return _STATES.names()


def check_states(states) -> tuple:
    """``states`` as a tuple, each an instance of a registered kind, one of each.

    Parameters
    ----------
    states
        The run's states.

    Returns
    -------
    tuple

    Raises
    ------
    DutyError
        Naming the first state that is not of a registered kind, or a second of one.
    """
    out = tuple(states or ())
    seen = set()
    for i, s in enumerate(out):
        if not any(isinstance(s, cls) for cls in _STATES):
            raise DutyError(f"states[{i}] = {type(s).__name__} is not a registered schedule "
                            f"state; registered kinds: {', '.join(state_kinds()) or 'none'} "
                            "(brakewear.duty.register_state)")
        if s.name in seen:
            raise DutyError(f"states[{i}]: a second state of kind {s.name!r}; a run takes one "
                            "of each kind")
        seen.add(s.name)
    return out


def state_changes(states, app, context: dict, n: int) -> tuple[float, np.ndarray]:
    """The product of the states' friction factors and the sum of their gaps for ``app``.

    Parameters
    ----------
    states
        The run's states, asked in order: each sees the offset with the gaps of
        the states before it.
    app
        The application about to run.
    context
        Its ``index``, the ``vehicle``, the base ``mu`` and the ``offset``.
    n
        The pad friction nodes.

    Returns
    -------
    tuple
        The friction factor and the gap (m, ``(n,)``).
    """
    factor, gap = 1.0, np.zeros(n)
    base = np.asarray(context["offset"], dtype=float)
    for s in states:
        change = s.before(app, {**context, "offset": base + gap}) or {}
        unknown = set(change) - {"mu_factor", "gap"}
        if unknown:
            raise DutyError(f"state {s.name!r} answered {sorted(unknown)}; a state's change "
                            "holds mu_factor and gap only")
        f = change.get("mu_factor", 1.0)
        if not (np.isfinite(f) and f > 0):
            raise DutyError(f"state {s.name!r}: mu_factor = {f!r}; need a finite value > 0")
        factor *= float(f)
        if change.get("gap") is not None:
            g = np.asarray(change["gap"], dtype=float)
            if g.shape != (n,) or not np.all(np.isfinite(g)):
                raise DutyError(f"state {s.name!r}: gap of shape {g.shape}; need {n} finite "
                                "values (m), one per pad friction node")
            gap = gap + g
    return factor, gap
