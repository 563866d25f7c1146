"""The figures of a wear run as its files hold them, one set for drags and schedules.

* :class:`WearStep` -- the state after an accepted step, what
  :func:`~brakewear.wear.wear_history` yields;
* :func:`thermal_state` -- the thermal figures after a thermal solve (face
  temperatures, heat into and convected from each body, balance error), as
  the fields of a :class:`~brakewear.wear.WearStep`;
* :func:`step_figures` -- a step's row of ``history.csv``, with
  :func:`thermal_columns` when coupled;
* :class:`HeatTally` -- the thermal columns of one application of a schedule
  (``applications.csv``) from its steps;
* :func:`temperature_field` -- a body's ``temperature_C`` for its VTU;
* :func:`thermal_record` -- the summary's ``thermal`` entry;
* :func:`end_record` -- the summary's ``status`` and ``ended`` entries: how
  the run ended and, when it ended early, why;
* :func:`archard_volumes` -- the worn volumes the step records imply;
* :func:`pr_spread` -- how far a pressure field is from ``p r = const``.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, TemperatureLimitError, WornThroughError

logger = logging.getLogger(__name__)

__all__ = ["WearStep", "thermal_state", "step_figures", "thermal_columns", "HeatTally",
           "temperature_field", "thermal_record", "end_record", "archard_volumes", "pr_spread"]

@dataclass
class WearStep:
    """State after an accepted step (cumulative quantities).

    Parameters
    ----------
    step, time, dt
        The step's number, the time at its end and its length (s).
    sliding_distance
        m at the pad's mean radius, since the start.
    pressure, active
        The pressure (Pa) and contact status at the pad's friction nodes at the
        start of the step.
    pad_wear, rotor_wear
        Cumulative depths (m) per pad friction node and per rotor wear node
        (face node or ring).
    pad_volume, rotor_volume
        m^3 worn from the pad and the rotor (sum of depth times area).
    pad_archard, rotor_archard
        m^3, the sum over the steps of ``k int p v dA dt`` with each law's ``k``.
    rejected, contact_solves
        Retries before this step was accepted; contact solves of this step
        (1 + rejected).
    solve_s
        s spent in contact solves in this step.
    limit
        What set the step: ``max_dh``, ``stability``, ``rotor_stability``,
        ``growth``, ``wear_tol``, ``first``, ``end``, ``fixed``.
    mu
        Friction coefficient in this step (with a friction law per node:
        friction force over normal force, ``sum mu p A / sum p A``).
    pad_temperature_max, rotor_temperature_max
        K, pad and rotor face, at the end of the step (thermal only).
    heat_balance_error
        ``|heat in - friction power| / power`` of this step.
    pressure_end, active_end
        The pressure (Pa) and contact status at the end of the step (the next
        one's start).
    explicit
        Whether the implicit scheme took this step explicitly (``implicit_floor``).
    mu_nodes
        mu per pad node in this step (a friction law's), or None.
    heat
        Thermal only: mean face temperatures (K) and the step's heat into pad
        and rotor and convected from each body (W).
    friction_work
        J on the modelled faces: ``friction_power`` at the start pressure and
        the mean speed, times ``dt`` (the heat put in).
    """

    step: int
    time: float
    dt: float
    sliding_distance: float
    pressure: np.ndarray
    active: np.ndarray
    pad_wear: np.ndarray
    rotor_wear: np.ndarray
    pad_volume: float
    rotor_volume: float
    pad_archard: float
    rotor_archard: float
    rejected: int
    contact_solves: int
    solve_s: float
    limit: str
    mu: float = 0.0
    pad_temperature_max: float = float("nan")
    rotor_temperature_max: float = float("nan")
    heat_balance_error: float = float("nan")
    pressure_end: np.ndarray | None = None
    active_end: np.ndarray | None = None
    explicit: bool = False
    mu_nodes: np.ndarray | None = None
    heat: dict | None = None
    friction_work: float = 0.0


C0 = 273.15         # K at 0 C


def thermal_state(th, T_rot=None) -> dict:
    """The figures after the last solve of the thermal model ``th``, named as the
    fields of a :class:`~brakewear.wear.WearStep`: the largest face temperatures
    of pad and rotor (K), the solve's relative heat-balance error, and ``heat``
    (the mean face temperatures, K; the net heat into each body, W: its friction
    share plus the net contact exchange, so that the two sum to the friction
    power; the heat convected (and radiated) from each body, W).  ``T_rot`` is
    the rotor temperature under the pad of a rigid rotor (default: the thermal
    model's, the ambient)."""
    T_pad = th.face_temperature("pad")
    if "rotor" in th.bodies:
        T_rot = th.face_temperature("rotor")
    elif T_rot is None:
        T_rot = th.rotor_temperature_under_pad()
    b = th.heat_balance()
    return {"pad_temperature_max": float(T_pad.max()),
            "rotor_temperature_max": float(T_rot.max()),
            "heat_balance_error": float(b["relative_error"]),
            "heat": {"pad_T_mean": float(T_pad.mean()), "rotor_T_mean": float(T_rot.mean()),
                     **{f"heat_{k}_W": v["heat_in_W"] - v["to_contact_W"]
                        for k, v in b["bodies"].items()},
                     **{f"convected_{k}_W": v["convected_W"] for k, v in b["bodies"].items()}}}


def thermal_columns(s) -> dict:
    """The thermal columns of a step ``s`` (a :class:`~brakewear.wear.WearStep`, or
    any object with the fields of :func:`thermal_state`); {} without thermal."""
    if s.heat is None or np.isnan(s.pad_temperature_max):
        return {}
    return {"pad_T_max_C": s.pad_temperature_max - C0,
            "rotor_T_max_C": s.rotor_temperature_max - C0,
            "pad_T_mean_C": s.heat["pad_T_mean"] - C0,
            "rotor_T_mean_C": s.heat["rotor_T_mean"] - C0,
            **{k: v for k, v in s.heat.items() if k.endswith("_W")},
            "heat_balance_error": s.heat_balance_error}


def step_figures(s, itf, mu: float) -> dict:
    """Per-step figures of a wear step (the rows of history.csv)."""
    p, act, A, r = s.pressure, s.active, itf.area, itf.r
    F = float((p * A).sum())
    pr = (p * r)[act]
    return {
        "step": s.step, "time_s": s.time, "dt_s": s.dt, "limit": s.limit,
        "sliding_distance_m": s.sliding_distance,
        "pad_wear_max_m": float(s.pad_wear.max()), "pad_wear_mean_m": float(
            (s.pad_wear * A).sum() / A.sum()),
        "rotor_wear_max_m": float(s.rotor_wear.max()),
        "pressure_max_Pa": float(p.max()), "contact_fraction": float(A[act].sum() / A.sum()),
        "pr_spread": float((pr.max() - pr.min()) / pr.mean()) if pr.size else float("nan"),
        "normal_force_N": F,
        "mu": s.mu,
        "torque_Nm": float(((s.mu if s.mu_nodes is None else s.mu_nodes) * p * A * r)
                           .sum()),
        "pad_volume_m3": s.pad_volume, "rotor_volume_m3": s.rotor_volume,
        "rejected": s.rejected, "contact_solves": s.contact_solves, "solve_s": s.solve_s,
        **thermal_columns(s),
    }


class HeatTally:
    """The thermal columns of one application from the steps it took (:meth:`add`).

    :meth:`columns` gives the face temperatures at its end (``pad_T_max_C``,
    ``pad_T_mean_C``, ``rotor_T_max_C``, ``rotor_T_mean_C``), their highest
    values at the ends of its steps (the same names with ``_peak_C``), the heat
    into and convected from each body over it (``heat_pad_J``,
    ``convected_rotor_J``, ...: the steps' powers times their lengths) and the
    largest relative heat-balance error of its steps.
    """

    _T = ("pad_T_max_C", "pad_T_mean_C", "rotor_T_max_C", "rotor_T_mean_C")

    def __init__(self):
        self.last: dict = {}
        self.peak: dict = {}
        self.energy: dict = {}
        self.error = 0.0

    def add(self, s, dt: float) -> None:
        """The step ``s`` (as for :func:`thermal_columns`) of length ``dt`` (s)."""
        c = thermal_columns(s)
        if not c:
            return
        for k in self._T:
            self.peak[k] = max(self.peak.get(k, -np.inf), c[k])
        for k, v in c.items():
            if k.endswith("_W"):
                self.energy[k[:-2] + "_J"] = self.energy.get(k[:-2] + "_J", 0.0) + v * dt
        self.error = max(self.error, c["heat_balance_error"])
        self.last = c

    def columns(self) -> dict | None:
        """The application's thermal columns (None: no thermal step was added)."""
        if not self.last:
            return None
        return {**{k: self.last[k] for k in self._T},
                **{k.replace("_C", "_peak_C"): self.peak[k] for k in self._T},
                **self.energy, "heat_balance_error": self.error}


def temperature_field(thermal, body: str, n: int) -> dict:
    """``{"temperature_C": ...}`` of ``body`` for its VTU (``n`` mesh nodes), or {}
    without a thermal model or a field of that body on those nodes."""
    if thermal is None or body not in thermal.bodies or thermal.T[body].size != n:
        return {}
    return {"temperature_C": thermal.T[body] - C0}


def thermal_record(thermal, last) -> dict:
    """The summary's ``thermal`` entry: settings, the pad's heat share, the bound
    and the final face temperatures and heat balance.  ``last``: the run's last
    :class:`~brakewear.wear.WearStep` (or a schedule's last
    :class:`~brakewear.duty.ApplicationRecord`), for its face temperatures (K)."""
    return {"settings": {k: v for k, v in thermal.settings.items()
                         if k != "convection_facets"},
            "pad_share": float(np.mean(thermal.partition)), "T_max_K": thermal.T_max,
            "final": {"pad_T_max_C": last.pad_temperature_max - C0,
                      "rotor_T_max_C": last.rotor_temperature_max - C0,
                      "heat_balance": {k: v for k, v in thermal.heat_balance().items()
                                       if k != "bodies"}}}


def end_record(exc: BaseException | None) -> dict:
    """``status`` and ``ended`` of a summary: how the run ended.

    ``status`` is ``"finished"`` (``exc`` None), ``"worn_through"`` (a surface
    reached its limit), ``"temperature_limit"`` (a face passed ``T_max``),
    ``"solver_error"`` (any other solver error), ``"input_error"`` (an input
    found wrong only when the run reached it) or ``"interrupted"``
    (``KeyboardInterrupt``, Ctrl-C).  ``ended`` is None for a finished run,
    else the reason: the error's kind, its message, its figures and where it
    happened (the step, the application), as far as the error holds them.
    """
    if exc is None:
        return {"status": "finished", "ended": None}
    status = ("worn_through" if isinstance(exc, WornThroughError) else
              "temperature_limit" if isinstance(exc, TemperatureLimitError) else
              "interrupted" if isinstance(exc, KeyboardInterrupt) else
              "input_error" if isinstance(exc, InputError) else "solver_error")
    reason = str(exc) or ("interrupted by the user (Ctrl-C)" if status == "interrupted"
                          else type(exc).__name__)
    return {"status": status, "ended": {
        "error": type(exc).__name__, "reason": reason,
        "figures": _plain(exc.record() if isinstance(exc, WornThroughError) else
                          getattr(exc, "figures", None) or {}),
        "where": dict(getattr(exc, "where", None) or {})}}


def archard_volumes(itf, history: list, pad_law, rotor_law, omega: float,
                    scheme: str) -> tuple[float, float]:
    """The worn volumes a wear history's records imply: ``sum k p v A dt`` per surface.

    The implicit schemes wear the pad with the end-of-step pressure (unless the
    step was taken explicitly), ``"implicit"`` the rotor too, ``"implicit_pad"``
    the rotor with the start's.  Against the history's own ``pad_volume`` and
    ``rotor_volume`` this checks the bookkeeping of a run (conservation).

    Parameters
    ----------
    itf
        The run's interface (its pad nodes' ``r`` and ``area``).
    history
        The :class:`~brakewear.wear.WearStep` records of the run, in order.
    pad_law, rotor_law
        The wear laws (``rate(p, v)``); ``rotor_law`` None: the rotor does not wear.
    omega
        Rotor speed (rad/s), constant over the run.
    scheme
        The run's ``Numerics.scheme``.

    Returns
    -------
    tuple of float
        Pad and rotor volume (m^3).
    """
    v = omega * itf.r
    pad = rot = 0.0
    for s in history:
        end = scheme != "explicit" and not s.explicit
        p_pad = s.pressure_end if end else s.pressure
        p_rot = s.pressure_end if end and scheme == "implicit" else s.pressure
        pad += float((pad_law.rate(p_pad, v) * itf.area).sum()) * s.dt
        if rotor_law is not None:
            rot += float((rotor_law.rate(p_rot, v) * itf.area).sum()) * s.dt
    return pad, rot


def pr_spread(p: np.ndarray, r: np.ndarray, active: np.ndarray, area: np.ndarray) -> dict:
    """How far a pressure field is from the run-in state ``p r = const`` over the contact.

    Parameters
    ----------
    p, r, area
        Nodal pressure (Pa), radius (m) and area (m^2) of the pad's friction nodes.
    active
        The nodes in contact (boolean mask).

    Returns
    -------
    dict
        ``range_over_mean``: ``(max - min) / mean`` of ``p r``; ``cv``: its
        area-weighted coefficient of variation.  Both are 0 at the steady state
        of uniform wear on a disc.
    """
    pr, A = (p * r)[active], area[active]
    m = float((A * pr).sum() / A.sum())
    return {"range_over_mean": float((pr.max() - pr.min()) / m),
            "cv": float(np.sqrt((A * (pr - m) ** 2).sum() / A.sum()) / m)}


def _plain(d: dict) -> dict:
    """JSON-ready values: numpy scalars and arrays as numbers and lists."""
    return {k: (v.tolist() if isinstance(v, (np.ndarray, np.generic)) else v)
            for k, v in d.items()}
