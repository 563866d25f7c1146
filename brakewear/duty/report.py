"""A scene's schedule run to files: one row per application, the pad per application.

:func:`run_schedule_files` runs :func:`brakewear.duty.run_schedule` for a
scene with a ``[schedule]`` and writes, into the run's folder,

* ``applications.csv``: per application its kind, start, duration, line
  pressure, deceleration, speeds, effective radius, torque, the vehicle's
  kinetic and regenerated energy and the demand on each face, the model's
  friction work per face, worn volumes, steps and the face temperature;
* ``pad.pvd`` / ``pad_NNNNN.vtu``: the pad after each braked application
  (pressure at its end, cumulative pad wear, contact status);
* ``summary.json``: the totals (energy demanded and dissipated per face,
  their largest relative difference, worn volumes, the largest wear) and the
  rotor's wear profile.
"""
from __future__ import annotations

import csv
import logging
import time
from pathlib import Path


from ..mesh.series import SeriesWriter, cell_nodes, face_fields
from ..rings import ring_profile
from .runner import run_schedule

logger = logging.getLogger(__name__)

__all__ = ["run_schedule_files", "APPLICATION_COLUMNS"]

#: the columns of applications.csv (SI units, energies per friction face)
APPLICATION_COLUMNS = ("index", "kind", "t_start", "duration", "line_pressure", "decel", "v0",
                       "v1", "omega0", "omega1", "rotor_angle", "r_eff", "torque", "kinetic_J",
                       "regenerated_J", "target_face_J", "friction_face_J", "pad_volume_m3",
                       "rotor_volume_m3", "steps", "pad_temperature_max", "run_s")


def run_schedule_files(scene, model, out: Path, pad_law, rotor_law, *, interface,
                       thermal=None, initial_gap=None, progress=None) -> dict:
    """Run ``scene.schedule`` on ``model`` and write the files above; the summary."""
    t0 = time.perf_counter()
    pad = model.meshes["pad"]
    series = SeriesWriter(out, "pad", pad.p, cell_nodes(pad))
    rows, last, n_braked = [], None, 0
    for rec in run_schedule(model, list(scene.schedule), pad_law, rotor_law, scene.interface.mu,
                            vehicle=scene.vehicle, numerics=scene.numerics, interface=interface,
                            thermal=thermal, initial_gap=initial_gap):
        rows.append({k: getattr(rec, k) for k in APPLICATION_COLUMNS})
        _write_csv(out / "applications.csv", rows)
        if rec.kind != "dwell":
            n_braked += 1
            fields = face_fields(pad.p.shape[1], interface.pad_nodes, pressure=rec.pressure,
                                 pad_wear=rec.pad_wear, active=rec.active)
            series.write(n_braked, rec.t_start + rec.duration, fields)
            last = rec
        if progress is not None:
            progress(rec)
    braked = [r for r in rows if r["kind"] != "dwell"]
    demand = sum(r["target_face_J"] for r in braked)
    dissipated = sum(r["friction_face_J"] for r in braked)
    summary = {
        "status": "finished", "applications": len(rows), "braked_applications": len(braked),
        "schedule_s": rows[-1]["t_start"] + rows[-1]["duration"],
        "energy": {"demanded_per_face_J": demand, "dissipated_per_face_J": dissipated,
                   "largest_relative_difference": max(
                       abs(r["friction_face_J"] / r["target_face_J"] - 1.0) for r in braked)},
        "pad_volume_m3": sum(r["pad_volume_m3"] for r in braked),
        "rotor_volume_m3": sum(r["rotor_volume_m3"] for r in braked),
        "pad_wear_max_m": float(last.pad_wear.max()),
        "rotor_wear_max_m": float(last.rotor_wear.max()),
        "line_pressure_range_Pa": [min(r["line_pressure"] for r in braked),
                                   max(r["line_pressure"] for r in braked)],
        "rotor_wear_profile": dict(zip(("r_m", "wear_m"), (
            a.tolist() for a in ring_profile(interface, last.rotor_wear)))),
        "run_s": time.perf_counter() - t0,
        "files": {"applications": "applications.csv", "pad": "pad.pvd"},
    }
    logger.info("schedule: %d applications, %.4g J demanded and %.4g J dissipated per face",
                len(rows), demand, dissipated)
    return summary


def _write_csv(path: Path, rows: list) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(APPLICATION_COLUMNS))
        w.writeheader()
        w.writerows(rows)
