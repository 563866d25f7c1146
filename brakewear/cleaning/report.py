"""What ``brakewear clean`` writes: the design curve, the routine table, the pads' maps
and a JSON summary.

Into the output folder:

* ``design_curve.csv`` / ``design_curve.json`` / ``design_curve.png`` -- P(clean
  within N stops) with its 95 % Wilson interval for every routine of the grid;
* ``routines.csv`` -- per target probability the routine that reaches it
  (fewest stops, then lowest deceleration, lowest speed, longest spacing),
  in a car maker's words, with its interval; ``none`` where no routine does;
* ``face_<in|out>_<first|last>.png`` and ``face_maps.csv`` -- the pads' pressure
  at the first and the last stop of the picked routine (the inputs at their
  medians), each face seen from the rotor, and each face's layer left ring by
  ring (``layer_left.png``);
* ``summary.json`` -- the input, the routines, the failures, the cost and the
  files; ``runs.jsonl`` -- every run as it ended (``--resume`` reads it).
"""
from __future__ import annotations

import csv
import json
import logging
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

from ..errors import SceneError

logger = logging.getLogger(__name__)

__all__ = ["check_clean_out", "clean_and_report", "plot_design_curve", "CLEAN_FILES"]

#: the files of a finished ``brakewear clean`` run
CLEAN_FILES = ("summary.json", "design_curve.json", "design_curve.csv", "design_curve.png",
               "routines.csv", "face_maps.csv", "layer_left.png", "runs.jsonl")


def check_clean_out(out, overwrite: bool = False, resume: bool = False) -> Path:
    """``out`` as a path; refused when it holds a ``brakewear clean`` run and neither
    ``overwrite`` nor ``resume`` is given (or both are)."""
    out = Path(out)
    if overwrite and resume:
        raise SceneError(f"--out = {str(out)!r}: --overwrite and --resume together; give one")
    held = [f for f in CLEAN_FILES if (out / f).is_file()]
    if held and not (overwrite or resume):
        raise SceneError(f"--out = {str(out)!r} already holds a run ({', '.join(held[:3])}"
                         f"{', ...' if len(held) > 3 else ''}); give --overwrite to replace "
                         "it, --resume to continue its sweep, or another --out")
    return out


class _Bar:
    """A progress bar in routines run (or brakes built), with its ETA (tqdm on stderr)."""

    def __init__(self, quiet: bool, unit: str = "routine", desc: str = "brakewear clean"):
        self.quiet, self.bar, self.unit, self.desc = quiet, None, unit, desc

    def __call__(self, done: int, total: int) -> None:
        if self.quiet:
            return
        if self.bar is None:
            from tqdm import tqdm
            self.bar = tqdm(total=total, unit=self.unit, desc=self.desc,
                            initial=done, smoothing=0.05)
        self.bar.n = done
        self.bar.refresh()
        if done >= total:
            self.close()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def clean_and_report(inp, out: Path, *, dask=None, workers: int = 2, quiet: bool = False,
                     overwrite: bool = False) -> dict:
    """Run the design curve of a checked input (:func:`~brakewear.cleaning.command.clean_input`)
    and write the files (see the module); returns the summary."""
    from .priors import cleaning_inputs, draw, medians
    from .sample import RoutineSettings
    from .sweep import design_curve, executor

    out.mkdir(parents=True, exist_ok=True)
    if overwrite:
        for f in CLEAN_FILES:
            (out / f).unlink(missing_ok=True)
    settings = RoutineSettings(geometry=inp.geometry, size=inp.size * 1e-3, start=inp.start,
                               heat=inp.heat)
    priors = cleaning_inputs(inp.start, inp.geometry)
    draws = draw(inp.samples, inp.seed, priors)
    bar, built = _Bar(quiet), _Bar(quiet, "brake", "building the brakes")
    t0 = time.perf_counter()
    try:
        with executor(dask, workers) as ex:
            curve = design_curve(draws, inp.speeds, inp.decels, inp.intervals, inp.stops,
                                 settings, inp.car, ex=ex, journal=out / "runs.jsonl",
                                 progress=bar, targets=inp.targets,
                                 prepared=built)
    finally:
        built.close()
        bar.close()
    files = write_curve(curve, out)
    files += write_maps(curve, medians(priors), settings, inp, out)
    summary = {"input": {k: v for k, v in asdict(inp).items() if k != "car"},
               "car": asdict(inp.car), "routines": curve["routines"],
               "failed": curve["failed"], "runs": curve["runs"],
               "cost_per_routine_s": curve["cost_per_routine_s"],
               "wall_s": time.perf_counter() - t0,
               "inputs": {k: [p.kind, p.a, p.b, p.unit, p.source] for k, p in priors.items()},
               "files": files + ["summary.json", "runs.jsonl"]}
    (out / "summary.json").write_text(json.dumps(summary, indent=1, default=str))
    return summary


def write_curve(curve: dict, out: Path) -> list[str]:
    """``design_curve.json``, ``.csv``, ``.png`` and ``routines.csv``."""
    (out / "design_curve.json").write_text(json.dumps(curve, indent=1, default=str))
    with open(out / "design_curve.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["interval_s", "speed_kmh", "decel_m_s2", "stops", "P", "P_low_95",
                    "P_high_95", "failed", "line_pressure_MPa"])
        for pt in curve["points"]:
            for N, (p, (lo, hi)) in enumerate(zip(pt["P"], pt["interval_95"]), start=1):
                w.writerow([pt["interval"], pt["speed_kmh"], pt["decel"], N, f"{p:.4f}",
                            f"{lo:.4f}", f"{hi:.4f}", pt["failed"], pt["line_pressure_MPa"]])
    with open(out / "routines.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["target", "routine", "stops", "speed_kmh", "decel_m_s2", "interval_s",
                    "P", "P_low_95", "P_high_95", "line_pressure_MPa"])
        for t, r in curve["routines"].items():
            if r is None:
                w.writerow([t, "none in the ranges"] + [""] * 8)
            else:
                w.writerow([t, r["words"], r["stops"], r["speed_kmh"], r["decel"],
                            r["interval"], f"{r['P']:.4f}", f"{r['interval_95'][0]:.4f}",
                            f"{r['interval_95'][1]:.4f}", r["line_pressure_MPa"]])
    plot_design_curve(curve, out / "design_curve.png")
    return ["design_curve.json", "design_curve.csv", "design_curve.png", "routines.csv"]


def plot_design_curve(curve: dict, path: Path) -> None:
    """P(clean within the most stops) against the deceleration, one line per speed and
    spacing, with the 95 % intervals and the targets; and the stops a draw needs."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pts, N = curve["points"], curve["stops"]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.6))
    for t in sorted({p["interval"] for p in pts}):
        for v in sorted({p["speed_kmh"] for p in pts}):
            row = sorted((p for p in pts if p["speed_kmh"] == v and p["interval"] == t),
                         key=lambda p: p["decel"])
            a = [p["decel"] for p in row]
            P = np.array([p["P"][-1] for p in row])
            lo = P - [p["interval_95"][-1][0] for p in row]
            hi = [p["interval_95"][-1][1] for p in row] - P
            ls = "-" if t == min(p["interval"] for p in pts) else "--"
            ax.errorbar(a, P, yerr=[lo, hi], marker="o", ls=ls, capsize=3,
                        label=f"{v:g} km/h, {t:g} s apart")
            med = [np.median([s if s is not None else N + 1 for s in p["stops_to_clean"]])
                   for p in row]
            bx.plot(a, med, marker="o", ls=ls, label=f"{v:g} km/h, {t:g} s apart")
    for y, c in ((0.9, "k"), (0.95, "r")):
        ax.axhline(y, color=c, ls=":", lw=0.8)
    ax.set(xlabel="deceleration (m/s^2)", ylabel=f"P(clean within {N} stops)",
           ylim=(-0.02, 1.02), title=f"{curve['samples']} draws per routine, 95 % intervals")
    bx.axhline(N, color="0.5", lw=0.6)
    bx.set(xlabel="deceleration (m/s^2)", ylabel="stops to clean, median draw",
           ylim=(0, N + 1.5), title=f"above {N}: not clean within the routine")
    ax.legend(fontsize=7)
    bx.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _picked(curve: dict):
    """The routine the maps show: the first target's, else the point most likely clean."""
    for r in curve["routines"].values():
        if r is not None:
            return r["speed_kmh"], r["decel"], r["interval"], r["stops"]
    best = max(curve["points"], key=lambda p: (p["P"][-1], -p["decel"]))
    return best["speed_kmh"], best["decel"], best["interval"], curve["stops"]


def write_maps(curve: dict, draw: dict, settings, inp, out: Path) -> list[str]:
    """The picked routine run at the inputs' medians, its pads' pressure at its first and
    last stop on each face (pyvista) and each face's layer left (matplotlib), with
    ``face_maps.csv``."""
    from dataclasses import replace

    from ..duty import KMH
    from .routine import Routine
    from .sample import run_routine

    v, a, t, n = _picked(curve)
    res = run_routine(draw, Routine(n, v * KMH, a, t), inp.car,
                      replace(settings, maps=True, run_to_end=True))
    if "maps" not in res:
        logger.warning("the maps' routine failed: %s", res.get("error"))
        return []
    files = _face_pictures(res["maps"], settings, draw, out, f"{n} stops from {v:g} km/h at "
                                                               f"{a:g} m/s^2, {t:g} s apart")
    m0, m1 = res["maps"]["first"], res["maps"]["last"]
    with open(out / "face_maps.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["x_mm", "y_mm", "face", "pressure_first_MPa", "pressure_last_MPa"])
        for row in zip(m0["x_mm"], m0["y_mm"], m0["face"], m0["pressure_MPa"],
                       m1["pressure_MPa"]):
            w.writerow(row)
    _plot_layer(m1, draw, out / "layer_left.png")
    return files + ["face_maps.csv", "layer_left.png"]


def _face_pictures(maps, settings, draw, out: Path, words: str) -> list[str]:
    from ..output.face_maps import plot_face_map
    from .brake import cleaning_brake

    model, itf = cleaning_brake(draw, settings.geometry, settings.size)
    pad, files = model.meshes["pad"], []
    vmax = max(max(maps[w]["pressure_MPa"]) for w in ("first", "last"))
    for when in ("first", "last"):
        p = np.zeros(pad.nvertices)
        p[itf.pad_nodes] = maps[when]["pressure_MPa"]
        for face, view in (("in", (0.0, 0.0, -1.0)), ("out", (0.0, 0.0, 1.0))):
            name = f"face_{face}_{when}.png"
            plot_face_map(pad, p, out / name, f"{words}: {when} stop, "
                          f"{'inboard' if face == 'in' else 'outboard'} pad",
                          "contact pressure (MPa)", model.geometry.pad,
                          facets=f"friction_{face}", view=view, cmap="inferno",
                          clim=(0.0, vmax))
            files.append(name)
    return files


def _plot_layer(maps, draw, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = draw.get("thickness", 25e-6) * 1e6
    r, f, w = (np.array(maps[k]) for k in ("ring_radius_mm", "ring_face", "ring_wear_um"))
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for face, style in (("in", "o-"), ("out", "s-")):
        m = f == face
        if m.any():
            o = np.argsort(r[m])
            ax.plot(r[m][o], np.clip(h - w[m][o], 0, None), style,
                    label=f"{'inboard' if face == 'in' else 'outboard'} face")
    ax.set(xlabel="radius (mm)", ylabel="rust layer left (um)", ylim=(-0.05 * h, 1.05 * h),
           title=f"after the routine (layer {h:.3g} um at the start)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
