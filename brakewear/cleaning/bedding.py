"""The state service leaves a brake in: the pads bedded to their rotor.

Wear has a memory.  Archard wear drives the pad-rotor interface towards its
steady state, in which the gap no longer changes but by a rigid motion of
each pad: every pad node and every rotor ring then wears at one rate per
face, so the pressure stops moving (on a pad held square, ``p r`` constant:
``k p omega r`` the same everywhere).  A car's pads reach it through the
braking the car does -- its *duty*: the stops' line pressures, each weighted
by the rotor angle it slides, and the rotor's thermal coning in each -- and
keep it, against the cold rotor, when the car stands.

Two ways to the bedded state, on the same brake and interface:

* :func:`bedding_history` -- the reference: blocks of the duty's stops run by
  :func:`brakewear.duty.run_schedule` (the wear laws' coefficients times
  ``compress``: Archard wear depends on ``k`` times the sliding distance, so
  one application stands for ``compress`` of them while its wear steps keep
  the pressure change small), until the *first cold stop's* pressure -- a
  contact solve at the reference line pressure without the thermal coning,
  each face touching -- changes by less than ``tol`` (L2, area-weighted) over
  a block;
* :func:`brakewear.cleaning.steady.bedded_gap` -- the steady state solved
  directly, a few dozen contact solves at the duty's mean load.

A new pad, a re-machined rotor or a pad fitted to a worn rotor are other
scenarios: their gap is what they are given
(:func:`~brakewear.cleaning.corrosion.nonconformity_gap`), not this one.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from ..errors import WearError
from .corrosion import nonconformity_gap, outboard_nodes

logger = logging.getLogger(__name__)

__all__ = ["BeddingDuty", "BeddedState", "BeddingHistory", "bedding_history", "cold_pressure",
           "face_masks", "pressure_change", "face_radii", "coning_gap_of", "gauged", "OFF_FACE"]


@dataclass(frozen=True)
class BeddingDuty:
    """The loads a pad beds under (SI units).

    Attributes
    ----------
    line_pressure : tuple
        Each load case's line pressure (Pa).
    weight : tuple
        Each case's share of the wear: the rotor angle it slides (rad), or any
        multiple of it.
    coning : tuple
        Each case's thermal coning across the pad (m; 0: cold).
    omega : float
        A representative rotor speed (rad/s): it scales the rates, not the state.
    source : str
        Where the duty comes from, for records.
    """

    line_pressure: tuple
    weight: tuple
    coning: tuple
    omega: float = 50.0
    source: str = ""

    def __post_init__(self):
        n = len(self.line_pressure)
        if not (n and len(self.weight) == n and len(self.coning) == n):
            raise WearError(f"a bedding duty needs one weight and one coning per line pressure; "
                            f"got {n}, {len(self.weight)}, {len(self.coning)}")
        for name, vals, ok in (("line_pressure", self.line_pressure, lambda v: v > 0),
                               ("weight", self.weight, lambda v: v > 0),
                               ("coning", self.coning, lambda v: abs(v) < 1e-3)):
            bad = [v for v in vals if not (np.isfinite(v) and ok(v))]
            if bad:
                raise WearError(f"bedding duty: {name} = {bad[0]!r} is not allowed")

    def mean(self) -> BeddingDuty:
        """One case: the weighted mean line pressure and coning (the same steady state
        for a brake whose pressure is linear in them)."""
        w = np.asarray(self.weight, dtype=float) / np.sum(self.weight)
        return BeddingDuty((float(w @ self.line_pressure),), (1.0,),
                           (float(w @ self.coning),), self.omega, self.source)


@dataclass
class BeddedState:
    """What :func:`bedded_gap` found: the gap per pad friction node (m, the smallest
    of each face zero), the mean load's pressure (Pa), the iterations, the
    contact solves, the residual of each iteration (the rate's relative
    departure from uniform, L2 over the pressure) and the duty."""

    gap: np.ndarray
    pressure: np.ndarray
    iterations: int
    solves: int
    residuals: list
    duty: BeddingDuty
    extra: dict = field(default_factory=dict)


#: a pad node whose geometric gap exceeds this (m) is off the friction face (a chamfer,
#: a slot): no wear the bedding does closes it
OFF_FACE = 5e-6


def face_masks(itf, thickness: float | None, on_face: bool = False) -> list:
    """Masks of the pad friction nodes of each face (one mask without a thickness);
    ``on_face``: only the nodes on the flat face (geometric gap at most
    :data:`OFF_FACE`: not on a chamfer or in a slot)."""
    n = itf.area.size
    out = np.zeros(n, dtype=bool) if thickness is None else outboard_nodes(itf.x, thickness)
    flat = np.asarray(getattr(itf, "g0", np.zeros(n))) <= OFF_FACE if on_face else True
    return [m & flat for m in (~out, out) if m.any()]


def coning_gap_of(itf, band, thickness, coning: float) -> np.ndarray:
    """The gap of a rotor coning ``coning`` (m; 0 or any number) at the pad nodes."""
    if coning == 0.0:
        return np.zeros(itf.area.size)
    return nonconformity_gap(itf.x, *band, thickness if thickness is not None else 1.0, coning)


def gauged(g: np.ndarray, faces) -> np.ndarray:
    """``g`` with each face's smallest value zero (a uniform gap per face is the
    pad's own rigid motion)."""
    out = np.array(g, dtype=float)
    for m in faces:
        out[m] -= out[m].min()
    return out


def pressure_change(p: np.ndarray, q: np.ndarray, area: np.ndarray) -> float:
    """The area-weighted L2 norm of ``p - q`` over that of ``q``."""
    return float(np.sqrt(np.sum(area * (p - q) ** 2) / max(np.sum(area * q ** 2), 1e-300)))


def face_radii(pressure: np.ndarray, itf, faces) -> list:
    """The effective radius (m) of the pressure on each face."""
    out = []
    for m in faces:
        load = np.maximum(pressure[m], 0.0) * itf.area[m]
        out.append(float(load @ itf.r[m] / load.sum()) if load.sum() > 0 else float("nan"))
    return out


@dataclass
class BeddingHistory:
    """What :func:`bedding_history` ran: the bedded gap (m, each face's smallest
    zero), the first cold stop's pressure (Pa) after each block, its change over
    each block (L2), each face's effective radius (m) after each block, the
    applications run (each standing for ``compress`` of the duty's), whether it
    settled, and in ``extra["duty"]`` the last block's duty (its braked
    applications' line pressures, rotor angles and thermal coning)."""

    gap: np.ndarray
    pressures: list
    changes: list
    radii: list
    applications: int
    compress: float
    settled: bool
    extra: dict = field(default_factory=dict)


def cold_pressure(itf, gap: np.ndarray, line_pressure: float, mu: float,
                  thickness: float | None, active=None):
    """The first cold stop's pressure: the contact at ``line_pressure`` on ``gap``
    with each face touching (no thermal coning)."""
    faces = face_masks(itf, thickness)
    return itf.at_line_pressure(line_pressure).solve(gauged(gap, faces), active, mu=mu)


def bedding_history(run, *, cold_line_pressure: float, tol: float = 0.005,
                    max_blocks: int = 60, compress: float = 1.0,
                    thickness: float | None = None) -> BeddingHistory:
    """Bed the pads by running ``run``'s schedule (one block of the duty) again and
    again (see the module).

    Parameters
    ----------
    run
        A :class:`~brakewear.wear.Run` with the block's schedule, its vehicle, the
        iron's wear laws (their ``k`` times ``compress`` are run), the interface
        (built), its states (the rotor's heat, the pads' touch) and the gap the
        pads start from (``initial_gap``: a new pad's).
    cold_line_pressure
        The line pressure (Pa) of the first cold stop.
    tol
        The change of the first cold stop's pressure over a block (L2) at which the
        pads count as bedded.
    compress
        Applications each stand for ``compress`` of the duty's (Archard's ``k s``).
    thickness
        The rotor's thickness (m; None: one face).

    Returns
    -------
    BeddingHistory
    """
    from dataclasses import replace as _replace

    from ..duty import run_schedule

    if not (np.isfinite(compress) and compress >= 1):
        raise WearError(f"compress = {compress!r} is not allowed; need >= 1")
    itf = run.interface
    faces = face_masks(itf, thickness)
    laws = {k: None if law is None else _replace(law, k=law.k * compress)
            for k, law in (("pad_law", run.pad_law), ("rotor_law", run.rotor_law))}
    gap = gauged(np.zeros(itf.area.size) if run.initial_gap is None else run.initial_gap,
                  faces)
    sol = cold_pressure(itf, gap, cold_line_pressure, run.mu, thickness)
    pressures, changes, radii, apps = [sol.pressure], [], [face_radii(sol.pressure, itf,
                                                                     faces)], 0
    cases: list = []
    for block in range(max_blocks):
        last, cases = None, []
        for rec in run_schedule(_replace(run, initial_gap=gap, **laws)):
            last, apps = rec, apps + 1
            if rec.braked:
                heat = rec.states.get("rotor_heat", {})
                cases.append((rec.line_pressure, rec.rotor_angle,
                              heat.get("thermal_coning", 0.0)))
        gap = gauged(gap + last.pad_wear + itf.W @ last.rotor_wear, faces)
        sol = cold_pressure(itf, gap, cold_line_pressure, run.mu, thickness, sol.active)
        changes.append(pressure_change(sol.pressure, pressures[-1], itf.area))
        pressures.append(sol.pressure)
        radii.append(face_radii(sol.pressure, itf, faces))
        logger.info("bedding block %d: the first cold stop's pressure changed by %.2e; "
                    "radii %s mm", block + 1, changes[-1],
                    ", ".join(f"{r * 1e3:.2f}" for r in radii[-1]))
        if changes[-1] <= tol:
            break
    duty = BeddingDuty(*(tuple(c) for c in zip(*cases)), source="the bedding history's "
                       "last block")
    return BeddingHistory(gap, pressures, changes, radii, apps, compress, changes[-1] <= tol,
                          {"duty": duty, "cold_line_pressure": cold_line_pressure})
