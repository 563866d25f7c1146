"""A scene's schedule run to files: one row per application, the pad per application.

:func:`run_schedule_files` runs :func:`brakewear.duty.run_schedule` for a
scene with a ``[schedule]`` and writes, into the run's folder,

* ``applications.csv``: per application its kind, whether it braked, start,
  duration, line pressure, deceleration, speeds, effective radius (at its start
  and its mean over the rotor angle), torque, the vehicle's kinetic energy, the
  parts regenerated and taken by the road load, and the demand on each face, the model's
  friction work per face, worn volumes, steps and the pad face temperature
  (K); with thermal coupling also the thermal columns of
  :class:`~brakewear.wear.records.HeatTally` (face temperatures of pad and
  rotor at the end and their peaks, C; heat into and convected from each
  body, J; the largest heat-balance error of its steps);
* ``pad.pvd`` / ``pad_NNNNN.vtu``: the pad after each braked application
  (pressure at its end, cumulative pad wear, contact status) and, with thermal
  coupling, ``temperature_C``, also after each dwell (its cooling; no contact);
* ``rotor.pvd`` / ``rotor_NNNNN.vtu`` (elastic rotor): ``rotor_wear`` and
  ``temperature_C`` at the same times;
* ``applications.png`` (when the scene's ``output.figures`` is on): the
  energy bookkeeping, line pressure, worn volumes and face temperatures per
  application (:func:`application_figure`);
* ``summary.json``: the totals (energy demanded and dissipated per face,
  their largest relative difference, worn volumes, the largest wear), the
  rotor's wear profile and, with thermal coupling, ``thermal``: the settings
  and the final state (:func:`~brakewear.wear.records.thermal_record`).
"""
from __future__ import annotations

import csv
import json
import logging
import time
from pathlib import Path

import numpy as np

from ..errors import BrakewearError, InputError
from ..mesh.rings import ring_profile
from ..mesh.series import SeriesWriter, cell_nodes, face_fields
from ..wear.records import end_record, temperature_field, thermal_record
from .runner import run_schedule

logger = logging.getLogger(__name__)

__all__ = ["run_schedule_files", "APPLICATION_COLUMNS"]

#: the columns of applications.csv (SI units, energies per friction face)
APPLICATION_COLUMNS = ("index", "kind", "braked", "t_start", "duration", "line_pressure", "decel",
                       "v0", "v1", "omega0", "omega1", "rotor_angle", "r_eff", "r_eff_mean",
                       "torque", "kinetic_J", "regenerated_J", "road_J", "propulsion_J",
                       "road_net_J", "target_face_J",
                       "friction_face_J",
                       "pad_volume_m3", "rotor_volume_m3", "steps", "pad_temperature_max",
                       "run_s")


def run_schedule_files(run, out: Path, *, title: str = "", figures: bool = False,
                       progress=None) -> dict:
    """Run the schedule of ``run`` (a :class:`~brakewear.wear.Run` with a schedule and
    its interface built) and write the files above; the summary.  ``figures``:
    ``applications.png`` too, titled ``title``.

    A schedule that ends early (a worn-through surface, a face past ``T_max``,
    a solver error, Ctrl-C) writes the summary of the applications it finished,
    with its ``status`` and the reason (``ended``:
    :func:`~brakewear.wear.records.end_record`), then raises the error with that
    summary as its ``summary`` attribute."""
    t0 = time.perf_counter()
    interface, thermal = run.interface, run.thermal
    write = _Frames(run.model, out, interface, thermal)
    rows, final = [], None
    try:
        for rec in run_schedule(run):
            rows.append({**{k: getattr(rec, k) for k in APPLICATION_COLUMNS},
                         **(rec.heat or {})})
            _write_csv(out / "applications.csv", rows)
            if rec.braked or thermal is not None:    # a pause changes temperatures only
                write(rec)
            final = rec
            if progress is not None:
                progress(rec)
    except (BrakewearError, KeyboardInterrupt) as exc:
        if isinstance(exc, InputError) and not rows:    # refused before it ran
            raise
        summary = {**_summary(rows, final, interface, thermal, write, t0), **end_record(exc)}
        (out / "summary.json").write_text(json.dumps(summary, indent=2, default=float))
        exc.summary = summary
        raise
    summary = _summary(rows, final, interface, thermal, write, t0)
    if figures:
        summary["files"]["figure"] = str(application_figure(rows, out / "applications.png",
                                                            title))
    logger.info("schedule: %d applications, %.4g J demanded and %.4g J dissipated per face",
                len(rows), summary["energy"]["demanded_per_face_J"],
                summary["energy"]["dissipated_per_face_J"])
    return summary


def _summary(rows: list, final, interface, thermal, write, t0: float) -> dict:
    """The summary of the applications in ``rows`` (``final``: the last one's record)."""
    braked = [r for r in rows if r["braked"]]
    demand = sum(r["target_face_J"] for r in braked)
    dissipated = sum(r["friction_face_J"] for r in braked)
    wear = (final.pad_wear, final.rotor_wear) if final is not None else None
    return {
        **end_record(None), "applications": len(rows), "braked_applications": len(braked),
        "schedule_s": rows[-1]["t_start"] + rows[-1]["duration"] if rows else 0.0,
        "energy": {"demanded_per_face_J": demand, "dissipated_per_face_J": dissipated,
                   "largest_relative_difference": max(
                       (abs(r["friction_face_J"] / r["target_face_J"] - 1.0) for r in braked),
                       default=None)},
        "pad_volume_m3": sum(r["pad_volume_m3"] for r in braked),
        "rotor_volume_m3": sum(r["rotor_volume_m3"] for r in braked),
        "pad_wear_max_m": float(wear[0].max()) if wear else 0.0,
        "rotor_wear_max_m": float(wear[1].max()) if wear else 0.0,
        "line_pressure_range_Pa": [min(r["line_pressure"] for r in braked),
                                   max(r["line_pressure"] for r in braked)] if braked else None,
        "rotor_wear_profile": dict(zip(("r_m", "wear_m"), (
            a.tolist() for a in ring_profile(interface, wear[1])))) if wear else None,
        "run_s": time.perf_counter() - t0,
        "files": {"applications": "applications.csv", "pad": "pad.pvd",
                  "rotor": "rotor.pvd" if write.rotor is not None else None},
        "thermal": None if thermal is None or final is None else
        thermal_record(thermal, final),
    }


class _Frames:
    """The pad's (and an elastic rotor's) VTU series: one frame per application written."""

    def __init__(self, model, out: Path, itf, thermal):
        self.itf, self.thermal, self.n = itf, thermal, 0
        self.pad = model.meshes["pad"]
        self.pad_series = SeriesWriter(out, "pad", self.pad.p, cell_nodes(self.pad))
        rotor = model.meshes.get("rotor")
        self.rotor = (SeriesWriter(out, "rotor", rotor.p, cell_nodes(rotor))
                      if model.rotor == "elastic" and getattr(itf, "rotor_nodes", None)
                      is not None else None)
        self.n_rotor = None if self.rotor is None else rotor.p.shape[1]

    def __call__(self, rec) -> None:
        self.n += 1
        t, n_pad, th = rec.t_start + rec.duration, self.pad.p.shape[1], self.thermal
        p = rec.pressure if rec.pressure is not None else np.zeros(rec.pad_wear.size)
        act = rec.active if rec.active is not None else np.zeros(rec.pad_wear.size, bool)
        fields = face_fields(n_pad, self.itf.pad_nodes, pressure=p, pad_wear=rec.pad_wear,
                             active=act)
        self.pad_series.write(self.n, t, {**fields, **temperature_field(th, "pad", n_pad)})
        if self.rotor is not None:
            a = np.zeros(self.n_rotor)
            a[self.itf.rotor_nodes] = rec.rotor_wear
            self.rotor.write(self.n, t, {"rotor_wear": a,
                                         **temperature_field(th, "rotor", self.n_rotor)})


def application_figure(rows: list[dict], path: Path, title: str = "") -> Path:
    """``applications.png``: per braked application the energy bookkeeping (the
    vehicle's kinetic and regenerated energy, the demand on each friction face
    and the work the model dissipated there), the line pressure and the
    cumulative worn volumes, and with thermal coupling the face temperatures'
    peaks."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    braked = [r for r in rows if r["braked"]]
    n = np.array([r["index"] for r in braked])
    hot = "pad_T_max_peak_C" in braked[0]
    fig, ax = plt.subplots(1, 3 if hot else 2, figsize=(15 if hot else 10, 4))
    kJ = lambda key: [1e-3 * (r[key] or 0.0) for r in braked]  # noqa: E731
    ax[0].plot(n, kJ("kinetic_J"), "s-", label="vehicle: kinetic energy")
    ax[0].plot(n, kJ("regenerated_J"), "v-", label="vehicle: regenerated")
    ax[0].plot(n, kJ("road_J"), "^-", label="vehicle: road load")
    ax[0].plot(n, kJ("target_face_J"), "o-", label="demand on each friction face")
    ax[0].plot(n, kJ("friction_face_J"), "x", ms=9, label="model: friction work per face")
    ax[0].set(xlabel="application", ylabel="energy (kJ)", title="energy per application")
    ax[0].legend(fontsize=8)
    ax[1].plot(n, [1e-6 * r["line_pressure"] for r in braked], "o-", color="C0")
    ax[1].set(xlabel="application", ylabel="line pressure (MPa)",
              title="line pressure and worn volume")
    tw = ax[1].twinx()
    tw.plot(n, 1e9 * np.cumsum([r["pad_volume_m3"] for r in braked]), "C1--", label="pad")
    tw.plot(n, 1e9 * np.cumsum([r["rotor_volume_m3"] for r in braked]), "C2--",
            label="rotor face")
    tw.set_ylabel("worn volume, cumulative (mm^3), dashed")
    tw.legend(fontsize=8, loc="lower right")
    if hot:
        for key, label in (("pad_T_max_peak_C", "pad face"), ("rotor_T_max_peak_C", "rotor face")):
            ax[2].plot(n, [r[key] for r in braked], "o-", label=label)
        ax[2].set(xlabel="application", ylabel="temperature (C)",
                  title="hottest face temperature in each application")
        ax[2].legend(fontsize=8)
    from matplotlib.ticker import MaxNLocator
    for a in ax:
        a.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax[1].ticklabel_format(axis="y", useOffset=False)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _write_csv(path: Path, rows: list) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
