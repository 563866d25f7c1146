"""Run a tribometer scene: build the bodies, jump through the cycles, write the run.

:func:`run_tribometer` is what ``brakewear run <tribometer scene>`` does: it checks
the output folder, condenses the two bodies onto their contact faces, loads
the contact, integrates the test's cycles by cycle jumps
(:mod:`brakewear.tribology.jump`) and writes the files of
:mod:`brakewear.tribology.output`; the summary it returns (and writes) holds
the worn depths, areas or volumes of both bodies, the cost, and -- where the
scene names a measurement -- the computed figure against the measured one.
"""
from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .. import __version__
from ..checks import file_messages, read_csv_rows
from ..errors import SceneError
from ..solvers.threads import blas_threads
from .jump import JumpControl, cycle_jumps
from .output import RUN_FILES, FrameWriter, profile_figure, write_csv, write_json

logger = logging.getLogger(__name__)

__all__ = ["run_tribometer", "worn_figures", "clear_tribometer_run"]


def clear_tribometer_run(out: Path, scene) -> None:
    """Remove the files a run of ``scene`` writes from ``out`` (``--overwrite``)."""
    out = Path(out)
    for name in RUN_FILES:
        (out / name).unlink(missing_ok=True)
    for body in scene.bodies:
        for f in [*out.glob(f"{body}_*.vtu"), out / f"{body}.pvd"]:
            f.unlink(missing_ok=True)


def worn_figures(scene, pair, depths: dict) -> dict:
    """Body name -> its worn figures: ``depth_max``, ``depth_centre``, ``scar_width``
    (m), ``worn_area`` (plane strain, m^2 per m of length) or ``worn_volume`` (m^3;
    in plane strain too where the test has a width)."""
    out = {}
    for body in (pair.slave, pair.master):
        h = np.asarray(depths[body.name])
        lateral = body.x[:-1]
        r = np.abs(lateral[0]) if body.dim == 2 else np.hypot(*lateral)
        worn = h > 0.01 * h.max() if h.max() > 0 else np.zeros(h.size, bool)
        f = {"depth_max": float(h.max()),
             "depth_centre": float(h[np.argmin(r)]) if body.dim == 3 else
             float(np.interp(0.0, lateral[0], h)),
             "scar_width": float(lateral[0][worn].max() - lateral[0][worn].min())
             if body.dim == 2 and worn.any() else float(2 * r[worn].max()) if worn.any()
             else 0.0}
        total = float(h @ body.area)
        if body.dim == 2:
            f["worn_area"] = total
            width = getattr(scene.test, "width", None)
            if width:
                f["worn_volume"] = total * width
        else:
            f["worn_volume"] = total
        out[body.name] = f
    # a ring's uniform wear all round: its volume is the depth times its circumference
    ring = scene.test.capabilities.get("cycle") == "revolution" and pair.dim == 2
    if ring:
        name = pair.master.name
        R = scene.test.ring_radius
        out[name]["worn_area"] = float(np.mean(depths[name])) * 2 * math.pi * R
        out[name]["worn_volume"] = out[name]["worn_area"] * scene.test.width
        out[name]["scar_width"] = 2 * math.pi * R
    return out


def _validation(scene, figures: dict) -> dict:
    v = scene.validation
    if not v:
        return {}
    body, _, what = v["quantity"].partition(".")
    if body not in figures or what not in figures[body]:
        raise SceneError(f"validation.quantity: {v['quantity']!r}: the run has no such figure; "
                         f"it has {', '.join(f'{b}.{k}' for b in figures for k in figures[b])}")
    computed = figures[body][what]
    err = computed / v["measured"] - 1.0
    out = {**v, "computed": computed, "error": err, "within_tolerance": abs(err) <= v["tolerance"]}
    out["reference_errors"] = {k: computed / val - 1.0 for k, val in v["reference"].items()}
    return out


def _measured_profile(path: str) -> dict:
    """A measured profile: the columns ``x_mm``, ``depth_um`` and, for several tests,
    ``depth_min_um``, ``depth_max_um``."""
    rows, header = read_csv_rows(path, "the measured profile (validation.profile)")
    cols = {"x_m": ("x_mm", 1e-3), "depth_m": ("depth_um", 1e-6)}
    if "depth_min_um" in header:
        cols.update(depth_min_m=("depth_min_um", 1e-6), depth_max_m=("depth_max_um", 1e-6))
    try:
        return {k: [float(r[c]) * f for r in rows] for k, (c, f) in cols.items()}
    except (KeyError, TypeError, ValueError) as exc:
        raise SceneError(f"validation.profile: {path}: need the columns x_mm, depth_um "
                         f"(and optionally depth_min_um, depth_max_um) of numbers ({exc})"
                         ) from None


def run_tribometer(scene, out: str | Path, *, progress: Callable | None = None,
             figures: bool | None = None) -> dict:
    """Run a tribometer scene into the folder ``out``; return its summary.

    Parameters
    ----------
    scene : TribometerScene
    out
        The output folder (created; the caller checks it may be written to).
    progress
        Called with ``(cycles done, cycles in all)`` after every jump.
    figures
        Draw ``profile.png`` (default: the scene's ``output.figures``).

    Returns
    -------
    dict
        The summary (also ``out/summary.json``).
    """
    with file_messages(scene.source, scene.user_units):
        measured = (_measured_profile(scene.validation["profile"])
                    if "profile" in scene.validation else None)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    kind = scene.test
    t0, c0 = time.perf_counter(), time.process_time()
    with blas_threads(1):
        pair = kind.build(scene)
        t_build = time.perf_counter() - t0
        start = kind.start(scene, pair)
        depths = {b.name: np.zeros(b.face.size) for b in (pair.slave, pair.master)}
        total = kind.cycles
        frames = FrameWriter(out, pair)
        frames.write(0.0, depths, start.pressure, start.forces, start.offset)
        marks = list(np.linspace(0.0, total, scene.output["frames"])[1:])
        history = []

        def on_jump(j, d, res):
            history.append(_row(scene, pair, j, d, res))
            while marks and j.cycles >= marks[0] * (1 - 1e-12):
                marks.pop(0)
                frames.write(j.cycles, d, res.pressure, res.forces, res.offset)
            if progress is not None:
                progress(j.cycles, total)

        n = scene.numerics
        control = JumpControl(tol=n["wear_tol"], first=n["first_jump"], min_jump=n["min_jump"],
                              max_jump=n["max_jump"], fixed=n["fixed_jump"])
        depths, last, jumps = cycle_jumps(
            lambda d, l, N: kind.advance(scene, pair, d, l, N), start, depths, total, control,
            on_jump)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    figs = worn_figures(scene, pair, depths)
    slave, master = kind.bodies
    summary = {
        "scene": scene.name, "test": kind.name, "version": __version__,
        "cycles": jumps[-1].cycles, "cycle": kind.capabilities["cycle"],
        "time_s": jumps[-1].cycles * kind.cycle_time,
        "jumps": len(jumps), "cycles_simulated": jumps[-1].simulated,
        "jumps_rejected": sum(j.rejected for j in jumps),
        "bodies": figs,
        "worn_ratio": (figs[slave].get("worn_area", figs[slave].get("worn_volume")) /
                       figs[master].get("worn_area", figs[master].get("worn_volume"))
                       if figs[master].get("worn_volume", figs[master].get("worn_area"))
                       else None),
        "k_ratio": scene.bodies[slave].k / scene.bodies[master].k
        if scene.bodies[master].k > 0 else None,
        "last_cycle": last.figures,
        "mesh": {"contact_size_m": scene.mesh["size"], "face_nodes": {
            pair.slave.name: int(pair.slave.face.size),
            pair.master.name: int(pair.master.face.size)},
            "nodes": {b.name: int(b.mesh.nvertices) for b in (pair.slave, pair.master)}},
        "cost": {"build_s": t_build, "run_s": wall, "cpu_s": cpu},
        "validation": _validation(scene, figs),
        "files": {"series": [f"{b}.pvd" for b in kind.bodies], "history": "history.csv",
                  "profile": "profile.csv"},
    }
    if measured is not None:
        summary["measured_profile"] = measured
    closed = kind.closed_form(scene)
    if closed is not None:
        got = figs[closed["body"]]
        summary["closed_form"] = {
            "body": closed["body"], "name": closed["name"],
            "figures": {k: {"closed_form": closed[k], "computed": got[k],
                            "error": got[k] / closed[k] - 1.0}
                        for k in ("depth_max", "scar_width", "worn_area", "worn_volume")
                        if k in closed and k in got and closed[k] > 0}}
    profiles = kind.profiles(pair, depths)
    rows = [{"body": b, "position_m": float(x), "depth_m": float(h)}
            for b, (xs, hs) in profiles.items() for x, h in zip(xs, hs)]
    write_csv(out / "profile.csv", rows)
    write_csv(out / "history.csv", history)
    write_json(out / "scene.json", scene.to_dict())
    if figures if figures is not None else scene.output["figures"]:
        profile_figure(out / "profile.png", scene, profiles, summary, closed)
        summary["files"]["figure"] = "profile.png"
    write_json(out / "summary.json", summary)
    logger.info("%s: %g %ss in %.1f s (%d simulated)", scene.name, summary["cycles"],
                summary["cycle"], wall, summary["cycles_simulated"])
    return summary


def _row(scene, pair, j, depths, res) -> dict:
    row = {"cycles": j.cycles, "time_s": j.cycles * scene.test.cycle_time, "jump": j.jump,
           "error_estimate": j.error, "cycles_simulated": j.simulated, "wall_s": j.wall_s}
    for body in (pair.slave, pair.master):
        h = depths[body.name]
        row[f"{body.name}_depth_max_m"] = float(h.max())
        row[f"{body.name}_worn_m{pair.dim}"] = float(h @ body.area)
    for k, v in res.figures.items():
        row[k] = v
    return row
