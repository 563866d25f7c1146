"""Step control of the wear loop: how long the next step is, and whether a step is accepted.

The step is the smallest of

- ``end``: what remains of the history;
- ``max_dh``: no pad node wears more than its limit (``max_dh``, or
  ``dh_fraction`` of the pad element under it) in one step (pad + rotor);
- ``stability`` (explicit scheme): explicit Euler on the wear ODE
  ``dg/dt = c p(g)`` is monotone while ``dt c_i dp_i/dg`` stays below one;
  the pressure's response to a local gap change is bounded by the row sums
  of the friction face's normal stiffness (Gershgorin, docs: theory), so
  ``dt <= stability / max_i(c_i s_i / A_i)``;
- ``rotor_stability``: where the rotor's ring-averaged wear is explicit (the
  ``implicit_pad`` scheme, and an implicit step taken explicitly below
  ``implicit_floor``) its own bound applies, ``dt <= stability / max_j(sum_i
  c_i s_i / A_ring_j)`` over the pad nodes ``i`` above ring ``j`` (a ring's
  gap change moves the pressure of the pad nodes over it, whose wear is
  spread over the whole ring: a fast-wearing rotor layer makes it the binding
  limit).  The ``implicit`` scheme solves the rings with the pad (backward
  Euler on both surfaces) and has no bound;
- ``first`` (implicit schemes, first step): the explicit bound as a first
  guess of the time scale on which the pressure moves;
- ``growth``: at most twice the last step (``dp_tol`` control), or
  ``wear_tol``: the step the wear-error control aims at.

A step whose pressure changes by more than ``dp_tol`` (or, with
``wear_tol``, whose embedded local wear error ``dt/2 |rate(p_end) -
rate(p_start)|`` exceeds it), or that loses the contact, is retried smaller.
With ``steps`` the steps are equal and always accepted.

Both measures are taken over the pad's friction face in the numerics'
``norm`` (:func:`face_norm`): by default the largest nodal values
(``"max"``), the pressure change relative to the peak pressure; or
area-weighted (``"l2"``), the pressure change relative to the pressure,
``||p_end - p_start|| / ||p_start||``, and the wear error as its root mean
square over the face, so that a node entering contact counts by its
tributary area and the steps do not multiply as the mesh is refined.
"""
from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import StepSizeError
from .numerics import Numerics, NumericsError

logger = logging.getLogger(__name__)

__all__ = ["StepControl", "WEAR_TOL_GROWTH", "face_norm"]

#: Largest growth of the step from one step to the next under ``wear_tol``
#: control (docs: wear, "Step convergence": 2, 4 and 8 give the same runs within
#: one step; 4 saves the step after the first guess, adds no retry).
WEAR_TOL_GROWTH = 4.0


def face_norm(values: np.ndarray, area: np.ndarray | None, norm: str = "l2") -> float:
    """The size of a nodal field over the friction face.

    Parameters
    ----------
    values : ndarray
        One value per pad friction node.
    area : ndarray or None
        The nodes' tributary areas (m^2); None: equal weights of 1.
    norm : {"l2", "max"}
        ``"l2"``: ``(sum_i A_i x_i^2)^(1/2)``, the area-weighted L2 norm,
        which tends to ``(int x^2 dA)^(1/2)`` under mesh refinement;
        ``"max"``: ``max_i |x_i|`` (0 for no nodes).

    Returns
    -------
    float

    Raises
    ------
    NumericsError
        ``norm`` is neither.
    """
    x = np.asarray(values, dtype=float)
    if norm == "max":
        return float(np.abs(x).max()) if x.size else 0.0
    if norm != "l2":
        raise NumericsError(f"numerics.norm: {norm!r} is not allowed; allowed: 'l2', 'max'")
    w = np.ones_like(x) if area is None else np.asarray(area, dtype=float)
    return float(np.sqrt(np.dot(w, x * x)))


@dataclass
class StepControl:
    """The step-size policy of one history.

    Parameters
    ----------
    numerics : Numerics
        Scheme, tolerances and limits.
    duration : float
        Length of the history (s).
    dh_limit : ndarray
        Largest wear per step at each pad node (m).
    speed : ConstantSpeed or LinearSpeed, optional
        The rotor's speed profile: fixed steps are equal in rotor angle
        (:mod:`brakewear.wear.speed`).
    area : ndarray, optional
        Tributary area of each pad friction node (m^2), the weights of the
        ``"l2"`` measures (None: equal weights).
    """

    numerics: Numerics
    duration: float
    dh_limit: np.ndarray
    speed: object = None
    area: np.ndarray | None = None

    @property
    def fixed(self) -> bool:
        return self.numerics.steps is not None

    @property
    def on_wear_error(self) -> bool:
        return self.numerics.wear_tol is not None and not self.fixed

    def initial_dt(self) -> float | None:
        """The first step's target: equal steps, or None (the limits decide)."""
        return self.fixed_dt(0.0) if self.fixed else None

    def fixed_dt(self, now: float) -> float:
        """The fixed step from time ``now``: ``duration / steps``, or with a speed
        profile the time to the next of ``steps`` equal angles."""
        n = self.numerics.steps
        sp = self.speed
        profile = sp is not None and hasattr(sp, "omega0")
        total = sp.angle(self.duration) if profile else self.duration
        k = round((sp.angle(now) if profile else now) / total * n)
        if k + 1 >= n:      # the last step ends at the end, whatever the rounding
            return self.duration - now
        return (sp.time_at_angle(total * (k + 1) / n) if profile
                else self.duration * (k + 1) / n) - now

    def propose(self, dt_next: float | None, remaining: float, seen_rate: np.ndarray,
                worst: Callable[[], float],
                worst_rotor: Callable[[], float] | None = None,
                explicit_below: Callable[[], float] | None = None) -> tuple[float, str]:
        """The next step and what set it.

        ``seen_rate`` is the wear rate each pad node sees (pad + rotor under
        it, m/s); ``worst()`` the largest ``c_i s_i / A_i`` over the contact
        (1/s), evaluated only when a limit needs it; ``worst_rotor()`` the
        same for the rotor's ring wear alone (the bound of an explicit ring
        wear); ``explicit_below()`` the step (s) below which the
        ``implicit`` scheme takes a step explicitly (``implicit_floor``), where
        the rings' bound applies.
        """
        n = self.numerics
        if self.fixed:
            return min(dt_next, remaining), "fixed"
        cands = {"end": remaining}
        wearing = seen_rate > 0
        if np.any(wearing):
            cands["max_dh"] = float(np.min(self.dh_limit[wearing] / seen_rate[wearing]))
        explicit = n.scheme == "explicit"
        if (explicit and n.stability is not None) or dt_next is None:
            w = worst()
            if w > 0 and explicit and n.stability is not None:
                cands["stability"] = n.stability / w
            elif w > 0 and not explicit:
                # no bound, but the explicit one is the time scale on which the
                # pressure starts to move: a first guess that saves halvings
                cands["first"] = 1.0 / w
        if dt_next is not None:
            cands["growth" if n.wear_tol is None else "wear_tol"] = dt_next
        if not explicit and n.stability is not None and worst_rotor is not None and (
                n.scheme == "implicit_pad" or (explicit_below is not None
                                               and min(cands.values()) < explicit_below())):
            w = worst_rotor()
            if w > 0:
                cands["rotor_stability"] = n.stability / w
        limit = min(cands, key=cands.get)
        return cands[limit], limit

    def pressure_change(self, p_start: np.ndarray, p_end: np.ndarray) -> float:
        """The step's relative pressure change, the measure ``dp_tol`` bounds:
        ``||p_end - p_start|| / ||p_start||`` (``"l2"``), or the largest nodal
        change over the largest starting pressure (``"max"``)."""
        if self.numerics.norm == "max":
            return float(np.abs(p_end - p_start).max()) / max(float(p_start.max()), 1e-300)
        return face_norm(p_end - p_start, self.area) / max(face_norm(p_start, self.area), 1e-300)

    def wear_error(self, dt: float, rate_change: np.ndarray) -> float:
        """The step's embedded local error of the worn depth (m), the measure
        ``wear_tol`` bounds: ``dt/2`` times the change of the wear rate over the
        step (``rate_change``, m/s per pad node, pad + rotor under it), as its
        root mean square over the face (``"l2"``: ``||.|| / (sum A)^(1/2)``)
        or its largest nodal value (``"max"``)."""
        norm = self.numerics.norm
        size = face_norm(rate_change, self.area, norm)
        if norm == "l2":
            size /= np.sqrt(np.size(rate_change) if self.area is None
                            else float(np.sum(self.area)))
        return 0.5 * dt * size

    def accepts(self, change: float, est: float) -> bool:
        """Whether a step with relative pressure change ``change`` and local wear
        error estimate ``est`` (m) is accepted."""
        if self.on_wear_error:
            return est <= self.numerics.wear_tol
        return self.fixed or change <= self.numerics.dp_tol

    #: halvings whose pressure change stays within this factor of each other: the
    #: change does not shrink with the step, so it is a jump of the contact state
    #: (a pad rocking onto its other edge), which the shortest step spans
    JUMP_HALVINGS, JUMP_SPREAD = 4, 1.5

    def spans_jump(self, changes: list[float]) -> bool:
        """Whether the rejected attempts of one step met a jump rather than a step
        too long: under the ``dp_tol`` control (automatic steps), the pressure
        changes of the last :attr:`JUMP_HALVINGS` + 1 attempts, each at half the
        step of the one before, lie within a factor :attr:`JUMP_SPREAD` of each
        other (a change a step resolves shrinks with it, about in proportion)."""
        if self.fixed or self.on_wear_error or len(changes) <= self.JUMP_HALVINGS:
            return False
        last = changes[-self.JUMP_HALVINGS - 1:]
        return bool(np.all(np.isfinite(last)) and min(last) > 0
                    and max(last) <= self.JUMP_SPREAD * min(last))

    def retry(self, dt: float, est: float, rejected: int, step: int,
              change: float) -> tuple[float, str | None]:
        """The smaller step after ``rejected`` retries (and the limit it sets,
        None: unchanged); raises :class:`StepSizeError` past ``max_halvings``."""
        n = self.numerics
        if rejected > n.max_halvings:
            what = (f"pressure change {change:.2f} > dp_tol {n.dp_tol}" if n.wear_tol is None
                    else f"wear error estimate {est:.3e} m > wear_tol {n.wear_tol:.3e} m")
            raise StepSizeError(
                f"step {step}: no acceptable wear step after {rejected} "
                f"{'halvings' if n.wear_tol is None else 'retries'} (the budget "
                f"numerics.max_halvings = {n.max_halvings}; last dt {dt:.3e} s, {what})",
                figures={"step": step, "retries": rejected, "max_halvings": n.max_halvings,
                         "dt": dt, "pressure_change": change, "wear_error": est})
        if n.wear_tol is not None and np.isfinite(est):
            return dt * max(0.2, 0.9 * np.sqrt(n.wear_tol / est)), "wear_tol"
        return dt * 0.5, None       # contact lost, or the dp_tol control: halve

    def check_progress(self, step: int, t_before: float, t_after: float) -> None:
        """The loop's budget: raise :class:`StepSizeError` if accepted step ``step``
        did not advance the time, or if the history has used its budget of steps
        (``steps``, or ``max_steps`` under automatic control) short of its end."""
        n = self.numerics
        budget, key = (n.steps, "numerics.steps") if self.fixed else (n.max_steps,
                                                                       "numerics.max_steps")
        figures = {"step": step, "time": t_after, "duration": self.duration,
                   "dt": t_after - t_before, "budget": budget}
        if not t_after > t_before:
            raise StepSizeError(
                f"step {step}: the step from t = {t_before:.9g} s did not advance the time "
                f"(dt = {t_after - t_before:.3e} s of a {self.duration:.6g} s history); the "
                "loop stops here rather than repeat it", figures=figures)
        if step >= budget and t_after < self.duration * (1 - 1e-12):
            raise StepSizeError(
                f"step {step}: the history used its budget of {budget} steps ({key}) at "
                f"t = {t_after:.6g} s of {self.duration:.6g} s (last dt "
                f"{t_after - t_before:.3e} s)", figures=figures)

    def next_dt(self, dt: float, change: float, est: float, now: float = 0.0) -> float:
        """The next step's target: aim at 0.7 dp_tol (first-order change), never
        more than doubling; or at 0.9 wear_tol (second-order error: the square
        root of the ratio)."""
        n = self.numerics
        if self.fixed:
            return self.fixed_dt(now)
        if n.wear_tol is None:
            return dt * float(np.clip(0.7 * n.dp_tol / max(change, 1e-300), 0.25, 2.0))
        return dt * float(np.clip(0.9 * np.sqrt(n.wear_tol / max(est, 1e-300)),
                                  0.25, WEAR_TOL_GROWTH))
