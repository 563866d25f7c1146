"""One cleaning routine on one draw of the inputs: the brake's start, the stops, the
criteria after each.

:func:`run_routine` builds the draw's brake (:func:`~brakewear.cleaning.brake.cleaning_brake`),
its car (the draw's mass and road load on the car given, friction only), its
rust layer, its start -- the pads bedded square to the rotor
(:func:`~brakewear.cleaning.steady.bedded_gap` of the draw's brake with its
pads held square, :func:`~brakewear.cleaning.brake.held_brake`, under the
bedding duty of the draw's ``bedding_heat``; plus the face's
``static_coning``) or, as a labelled scenario, a new pad against a coned
rotor (``coning``) -- and the rotor's heat, runs the routine through
:func:`brakewear.duty.run_schedule`
(:func:`~brakewear.cleaning.routine.routine_run`) and judges every candidate
criterion after each stop (:class:`~brakewear.cleaning.criteria.CleaningCriteria`).
It stops once the chosen criterion is met (or runs every stop with
``run_to_end``).  The answer is plain data (JSON), with the error of a
solver that failed instead of a result.
"""
from __future__ import annotations

import logging
import time
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from ..errors import SolverError
from .criteria import CRITERIA, CleaningCriteria, CriteriaSettings

logger = logging.getLogger(__name__)

__all__ = ["RoutineSettings", "run_routine", "bedding_duty", "HOT_BEDDING"]

#: the hot bedding: a burnish of firm stops (Raybestos' procedure: 8 moderate stops
#: 40-10 mph, 8 harder 60-10 mph, 5 hard 80-20 mph, a quarter to three quarters of a
#: mile apart): (stops, from km/h, to km/h, m/s^2, s start to start)
HOT_BEDDING = ((8, 64.0, 16.0, 2.5, 30.0), (8, 97.0, 16.0, 4.0, 40.0),
               (5, 129.0, 32.0, 6.0, 45.0))
#: the bedding duty's deceleration (m/s^2): its line pressure
BEDDING_DECEL = 2.0


@dataclass(frozen=True)
class RoutineSettings:
    """How a routine is run (not what it is): the brake's geometry file, mesh size (m)
    and element order, the brake (``"caliper"``: the pads as the caliper holds them;
    ``"held"``: held square, the only one on quadratic meshes), its start
    (``"bedded"`` or ``"new"``), the stops' heat, the wear loop's pressure tolerance,
    the reduced rotor's Krylov blocks, the criteria, whether every stop runs after
    the chosen criterion is met and whether the maps of the first and last stop
    are kept."""

    geometry: str = "floating"
    size: float = 4e-3
    order: int = 1
    brake: str = "caliper"
    start: str = "bedded"
    heat: bool = True
    dp_tol: float = 0.05
    blocks: int = 3
    criteria: CriteriaSettings = field(default_factory=CriteriaSettings)
    run_to_end: bool = False
    maps: bool = False


_HOT: dict = {}
#: this process's bedded states of the pads held square, by level and friction
_BEDDED: dict = {}


def bedding_duty(draw: dict, settings: RoutineSettings, vehicle, mu: float, clamp_area: float,
                 r_eff: float):
    """The draw's bedding duty: one load at the line pressure of a
    :data:`BEDDING_DECEL` stop, with ``bedding_heat`` times the hot bedding's mean
    thermal coning (:data:`HOT_BEDDING` run through the reduced rotor) times the
    draw's ``thermal_coning_factor``."""
    from ..duty import KMH, line_pressure_for_torque
    from .bedding import BeddingDuty

    torque = vehicle.stop_torque(80 * KMH, 0.0, BEDDING_DECEL)
    P = line_pressure_for_torque(torque, mu, clamp_area, r_eff)
    heat = draw.get("bedding_heat", 0.0)
    coning = 0.0
    if heat > 0 and settings.heat:
        coning = heat * draw.get("thermal_coning_factor", 1.0) * hot_coning(settings, vehicle)
    return BeddingDuty((P,), (1.0,), (coning,), source=f"bedding_heat {heat:.3g}")


def hot_coning(settings: RoutineSettings, vehicle) -> float:
    """The hot bedding's mean thermal coning (m, weighted by each stop's rotor angle)."""
    from ..duty import KMH
    from ..thermal.reduced import HAT_CONING_PER_K
    from .brake import reduced_rotor

    key = (settings.geometry, settings.size, settings.blocks)
    if key not in _HOT:
        heat = reduced_rotor(settings.geometry, settings.size, settings.blocks)
        per_k, total, weight = HAT_CONING_PER_K, 0.0, 0.0
        for n, v0, v1, a, interval in HOT_BEDDING:
            for _ in range(n):
                e = vehicle.stop_energy(v0 * KMH, v1 * KMH, a)
                u = np.full(heat.inputs.size, 2 * 2 * e["face_J"] / e["duration"] * heat.share
                            / heat.inputs.size)
                start = heat.coning(per_k)
                heat.heat(u, e["duration"], vehicle.rotor_speed(v0 * KMH),
                          vehicle.rotor_speed(v1 * KMH))
                angle = (v0 ** 2 - v1 ** 2) * KMH ** 2 / (2 * a) / vehicle.tyre_radius
                total += 0.5 * (start + heat.coning(per_k)) * angle
                weight += angle
                heat.cool(interval - e["duration"], vehicle.rotor_speed(v1 * KMH))
        _HOT[key] = total / weight
    return _HOT[key]


def _bedded_reference(draw, settings, vehicle, mu, k_pad, k_rotor, band, t):
    """The held brake of the draw's levels and its bedded state, cold, at the line
    pressure of a bedding stop (:func:`bedding_duty`, its own line pressure kept) and
    the friction coefficient to 0.05: one solve per process and level
    (:mod:`brakewear.cleaning.steady`)."""
    from .brake import brake_levels, held_brake
    from .steady import bedded_gap

    mu_q = round(mu / 0.05) * 0.05
    key = (settings.geometry, settings.size, settings.order, brake_levels(draw), mu_q)
    _, held = held_brake(draw, settings.geometry, settings.size, settings.order)
    if key not in _BEDDED:
        duty = bedding_duty({}, settings, vehicle, mu_q, held.model.geometry.clamp_area,
                            0.5 * sum(band))
        path = _bedded_file(key, duty, k_pad, k_rotor)
        state = _read_bedded(path, duty)
        if state is None:
            state = bedded_gap(held, duty, mu=mu_q, k_pad=k_pad, k_rotor=k_rotor, band=band,
                               thickness=t)
            _write_bedded(path, state)
        if len(_BEDDED) > 200:
            _BEDDED.clear()
        _BEDDED[key] = state
    return held, _BEDDED[key]


def _bedded_file(key, duty, k_pad, k_rotor):
    """The disk cache file of a bedded reference (beside the condensations; None: none)."""
    import hashlib

    from ..geometry import geometry_file
    from ..interfaces.condensation import cache_dir

    folder = cache_dir(None)
    if folder is None:
        return None
    text = geometry_file(key[0]).read_text()
    h = hashlib.sha1(repr((text, key[1:], duty.line_pressure, k_pad, k_rotor)).encode())
    return folder / f"bedded-{h.hexdigest()[:20]}.npz"


def _read_bedded(path, duty):
    from .bedding import BeddedState

    if path is None or not path.exists():
        return None
    try:
        with np.load(path) as z:
            return BeddedState(np.array(z["gap"]), np.array(z["pressure"]), int(z["iterations"]),
                               int(z["solves"]), list(z["residuals"]), duty, {"cached": str(path)})
    except (OSError, KeyError, ValueError):
        return None


def _write_bedded(path, state) -> None:
    import os

    if path is None:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(f".{os.getpid()}.tmp.npz")
    np.savez(tmp, gap=state.gap, pressure=state.pressure, iterations=state.iterations,
             solves=state.solves, residuals=np.array(state.residuals))
    os.replace(tmp, path)


def _start_gap(draw, settings, model, itf, vehicle, mu, k_pad, k_rotor) -> tuple:
    """The gap the routine starts from and what the bedding solve reported."""
    from ..duty.vehicle import effective_radius
    from .bedding import coning_gap_of, face_masks, face_radii, gauged
    from .brake import transfer_gap
    from .corrosion import nonconformity_gap

    g = model.geometry
    band, t = (g.pad.inner_radius, g.pad.outer_radius), g.rotor.thickness
    if settings.start == "new":
        return nonconformity_gap(itf.x, *band, t, draw["coning"]), {"start": "new pad"}
    duty = bedding_duty(draw, settings, vehicle, mu, g.clamp_area, 0.5 * sum(band))
    held, ref = _bedded_reference(draw, settings, vehicle, mu, k_pad, k_rotor, band, t)
    # the pads held square are linear: the steady pressure scales with the line
    # pressure and so does the gap that carries it; bedded under a coning the gap is
    # the cold one less the coning's (tests/test_bedding.py)
    P, coning = duty.line_pressure[0], duty.coning[0]
    faces = face_masks(held, t)
    shape = gauged(ref.gap * (P / ref.duty.line_pressure[0])
                   - coning_gap_of(held, band, t, coning), faces)
    gap = shape if held is itf else transfer_gap(shape, held, itf)
    gap = gap + nonconformity_gap(itf.x, *band, t, draw.get("static_coning", 0.0))
    state = ref
    return gap, {"start": "bedded", "iterations": state.iterations, "solves": state.solves,
                 "duty_line_pressure_MPa": P / 1e6, "duty_coning_um": coning * 1e6,
                 "radii_mm": [r * 1e3 for r in face_radii(state.pressure, held, faces)],
                 "r_eff_mm": effective_radius(state.pressure, held.area, held.r) * 1e3}


def run_routine(draw: dict, routine, vehicle, settings: RoutineSettings | None = None) -> dict:
    """One routine on one draw (see the module); a solver failure returns
    ``{"error": ...}`` with the stops it ran.

    Parameters
    ----------
    draw
        The inputs (:func:`~brakewear.cleaning.priors.cleaning_inputs`), SI units.
    routine
        A :class:`~brakewear.cleaning.routine.Routine`.
    vehicle
        The car (:class:`~brakewear.duty.Vehicle`); the draw's ``mass``,
        ``rolling_resistance``, ``drag_area`` and ``drivetrain_drag`` replace its
        own, and it brakes by friction alone.
    settings
        :class:`RoutineSettings`.
    """
    from threadpoolctl import threadpool_limits

    settings = settings or RoutineSettings()
    t0 = time.perf_counter()
    out = {"stops_to_clean": None, "criteria": {}, "rows": []}
    try:
        with threadpool_limits(limits=1, user_api="blas"):
            _run(draw, routine, vehicle, settings, out)
    except SolverError as e:
        logger.warning("routine failed: %s", e)
        out["error"] = f"{type(e).__name__}: {e}"
    out["run_s"] = time.perf_counter() - t0
    return out


def _run(draw, routine, vehicle, settings, out) -> None:
    from ..duty import run_schedule
    from ..laws.base import WearLaw
    from ..materials import MATERIALS
    from ..wear import Numerics
    from .brake import cleaning_brake, held_brake, reduced_rotor
    from .heat import RotorHeat
    from .routine import routine_run
    from .rust import RUST_PRIORS, RustLaw, RustLayer

    if settings.brake == "held":
        model, itf = held_brake(draw, settings.geometry, settings.size, settings.order)
    else:
        model, itf = cleaning_brake(draw, settings.geometry, settings.size)
    g = model.geometry
    band = (g.pad.inner_radius, g.pad.outer_radius)
    car = replace(vehicle, **{k: draw[k] for k in ("mass", "rolling_resistance", "drag_area",
                                                    "drivetrain_drag") if k in draw})
    car = car.with_friction_share(1.0)
    k_iron, k_pad = MATERIALS["grey_cast_iron"].wear_k, MATERIALS["pad_resin"].wear_k
    law = RustLaw(**{k: draw[k] for k in RUST_PRIORS if k in draw})
    rust = RustLayer(itf, law, k_iron, WearLaw(k_pad))
    gap0, out["start"] = _start_gap(draw, settings, model, itf, car, draw["mu"], k_pad, k_iron)
    heat = None
    if settings.heat:
        from ..thermal.reduced import HAT_CONING_PER_K
        reduced = reduced_rotor(settings.geometry, settings.size, settings.blocks,
                                draw.get("convection_factor", 1.0))
        heat = RotorHeat(reduced, itf, band, g.rotor.thickness,
                         draw.get("thermal_coning_factor", 1.0) * HAT_CONING_PER_K)
    judge = CleaningCriteria(itf, band, law.thickness, settings.criteria)
    num = Numerics(scheme="implicit", max_dh=0.1 * law.thickness, dp_tol=settings.dp_tol)
    run = routine_run(model, itf, car, rust, draw["mu"], routine, numerics=num, gap0=gap0,
                      heat=heat)
    values = {c: [] for c in CRITERIA}
    chosen = settings.criteria.chosen
    for rec in run_schedule(run):
        if not rec.braked:
            continue
        judged = judge.evaluate(rec.rotor_wear, rec.pressure)
        for c in CRITERIA:
            values[c].append(judged[c]["value"])
            met = out["criteria"].setdefault(c, {"stops_to_meet": None})
            if judged[c]["met"] and met["stops_to_meet"] is None:
                met["stops_to_meet"] = len(values[c])
        out["rows"].append(_row(rec, judged))
        if settings.maps and len(out["rows"]) == 1:
            out["maps"] = {"first": _maps(itf, judge, rec)}
        if out["criteria"][chosen]["stops_to_meet"] is not None and not settings.run_to_end:
            break
    for c in CRITERIA:
        out["criteria"][c]["values"] = values[c]
    out["stops_to_clean"] = out["criteria"][chosen]["stops_to_meet"]
    if settings.maps:
        out["maps"]["last"] = _maps(itf, judge, rec)


def _row(rec, judged: dict) -> dict:
    heat = rec.states.get("rotor_heat", {})
    return {"line_pressure_MPa": rec.line_pressure / 1e6, "mu": rec.mu,
            "decel": rec.decel, "r_eff_mm": rec.r_eff * 1e3,
            "thermal_coning_um": heat.get("thermal_coning", 0.0) * 1e6,
            "T_ring_C": heat["T_ring"] - 273.15 if heat else None,
            "T_hat_C": heat["T_hat"] - 273.15 if heat else None,
            "face_kJ": rec.target_face_J / 1e3, "drift": rec.torque_drift,
            "faces": {c: v["faces"] for c, v in judged.items() if v["faces"]}}


def _maps(itf, judge, rec) -> dict:
    """The pads' pressure and the rings' wear of a stop (mm, MPa, um)."""
    b = judge.band
    return {"x_mm": (itf.x[0] * 1e3).tolist(), "y_mm": (itf.x[1] * 1e3).tolist(),
            "face": judge.node_face.tolist(), "pressure_MPa": (rec.pressure / 1e6).tolist(),
            "ring_radius_mm": (b.radii * 1e3).tolist(), "ring_face": list(b.face),
            "ring_wear_um": (b.ring_means(rec.rotor_wear) * 1e6).tolist()}


def settings_dict(settings: RoutineSettings) -> dict:
    """``settings`` as plain data."""
    return asdict(settings)
