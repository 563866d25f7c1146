"""A wear history on disk: VTU time series (ParaView), a CSV of per-step figures, a JSON summary.

:func:`run_wear` drives :func:`brakewear.wear.wear_history` and writes

- ``pad.pvd`` + ``pad_NNNNN.vtu``: the pad mesh with the point fields
  ``pressure`` (Pa), ``pad_wear`` (m), ``active`` (1 in contact) on its
  friction face (zero elsewhere);
- ``rotor.pvd`` + ``rotor_NNNNN.vtu`` (elastic rotor): ``rotor_wear`` (m);
  quadratic (P2) models write ``tetra10`` cells, every mid-edge node a point;
- ``history.csv``: one row per accepted step;
- ``checkpoint.npz``: the loop's state (resume with ``resume=True``);
- ``summary.json``: what a user asks first (wear, pressure, steps, cost).

:func:`run_scene` does the same for a :class:`~brakewear.scene.Scene`, with
``scene.json`` (the scene in SI units) and PNG figures.  ParaView opens the
``.pvd`` files as time series.  A resumed run drops the files written after
its checkpoint and continues the series, so a run killed at any point and
resumed leaves the same files as an uninterrupted one.
"""
from __future__ import annotations

import csv
import json
import logging
import os
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..checks import file_messages, shown_value
from ..errors import SceneError, SolverError, StoredFileError, WearError, WornThroughError
from ..mesh.rings import ring_profile
from ..mesh.series import SeriesWriter, cell_nodes, face_fields
from ..scene.accuracy import mesh_accuracy
from ..scene.spec import first_difference
from ..storage import read_json, write_text
from ..wear.records import end_record, step_figures, temperature_field, thermal_record
from ..wear.run import Run
from ..wear.state import checkpoint_progress
from ..wear.stepper import WearStep, check_resume, wear_history

logger = logging.getLogger(__name__)

__all__ = ["run_wear", "run_scene", "ended_early", "check_out", "step_figures",
           "temperature_field", "thermal_record"]


def _figures(model, out: Path, scene) -> list[str]:
    """The maps of the last step (:func:`brakewear.output.face_maps.run_maps`); wear,
    pressure and (thermal runs) temperature histories."""
    import csv

    import numpy as np

    from .face_maps import run_maps

    files = run_maps(model, out, scene.name)
    with open(out / "history.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    if rows:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        t = np.array([0.0] + [float(r["time_s"]) for r in rows])
        t_start = np.array([float(r["time_s"]) - float(r["dt_s"]) for r in rows])
        hot = "pad_T_max_C" in rows[0]
        fig, ax = plt.subplots(1, 3 if hot else 2, figsize=(15 if hot else 10, 4))
        for key, label in (("pad_wear_max_m", "pad, max"), ("pad_wear_mean_m", "pad, mean"),
                           ("rotor_wear_max_m", "rotor, max")):
            ax[0].plot(t, [0.0] + [1e6 * float(r[key]) for r in rows], label=label)
        ax[0].set(xlabel="time (s)", ylabel="wear depth (µm)", title="wear")
        ax[0].legend()
        ax[1].plot(t_start, [1e-6 * float(r["pressure_max_Pa"]) for r in rows], marker=".")
        ax[1].set(xlabel="time (s)", ylabel="max contact pressure (MPa)",
                  title="pressure at the start of each step")
        for key, label in (("pad_T_max_C", "pad face, max"), ("pad_T_mean_C", "pad face, mean"),
                           ("rotor_T_max_C", "rotor face, max"),
                           ("rotor_T_mean_C", "rotor face, mean")) if hot else ():
            ax[2].plot(t[1:], [float(r[key]) for r in rows], label=label)
        if hot:
            ax[2].set(xlabel="time (s)", ylabel="temperature (°C)",
                      title="face temperatures at the end of each step")
            ax[2].legend()
        fig.suptitle(f"{scene.name}: {scene.line_pressure / 1e6:g} MPa, "
                     f"{scene.omega:g} rad/s, " + (f"mu {scene.interface.mu:g}"
                                                   if scene.interface.mu_map is None
                                                   else "mu map"))
        fig.tight_layout()
        path = out / "history.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        files.append(str(path))
    return files


def law_record(law):
    """A friction coefficient or a law as JSON: a number stays; a law gives its type and
    fields, a map its source file, axes, outside behaviour and range of values."""
    if law is None or isinstance(law, (int, float)):
        return law
    if hasattr(law, "table"):
        t = law.table
        return {"type": type(law).__name__, "source": t.source, "axes": list(t.axes),
                "outside": t.outside, "min": float(t.values.min()),
                "max": float(t.values.max())}
    return {"type": type(law).__name__,
            **{k: v for k, v in vars(law).items() if not isinstance(v, np.ndarray)}}


def run_wear(run, out: str | os.PathLike, *, vtu_every: int = 10, resume: bool = False,
             progress=None, every: int = 10) -> dict:
    """Run a wear history and write it to ``out`` (see the module docstring).

    A surface worn to its limit, a face past ``T_max``, a solver error or
    Ctrl-C ends the run: the files and ``summary.json`` (its ``status`` and
    the reason, ``ended``: :func:`~brakewear.wear.records.end_record`) are
    written, then the error is raised with the summary as its ``summary``
    attribute.

    Parameters
    ----------
    run : brakewear.wear.Run
        A drag (:func:`~brakewear.wear.wear_history` runs it).
    out : str or os.PathLike
        The run's folder.
    vtu_every : int
        A VTU frame every that many steps (and the last).
    resume : bool
        Continue the run in ``out`` from its checkpoint.
    progress : callable, optional
        Called with each :class:`~brakewear.wear.WearStep` (e.g. to advance a
        progress bar).
    every : int
        A checkpoint every that many steps.

    Returns
    -------
    dict
        The summary (also written to ``summary.json``).
    """
    if not isinstance(run, Run):
        raise WearError(f"run = {type(run).__name__}: need a brakewear.Run "
                        "(run_wear(Run(model, line_pressure, omega, duration, pad_law, ...), out))")
    out = Path(out)
    ck = out / "checkpoint.npz"
    csv_path = out / "history.csv"
    start, rows = None, []
    if resume:
        if not ck.exists():
            raise WearError(f"resume=True but {ck} does not exist")
        start, t_start = checkpoint_progress(ck)
        rows = resumed_rows(csv_path, start, t_start)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    run = run.resolved()
    model, itf, duration = run.model, run.interface, run.duration
    pad, rotor = model.meshes["pad"], model.meshes.get("rotor")
    times = {int(r["step"]): float(r["time_s"]) for r in rows}
    pad_series = SeriesWriter(out, "pad", pad.p, cell_nodes(pad), start, times)
    rot_series = (SeriesWriter(out, "rotor", rotor.p, cell_nodes(rotor), start, times)
                  if model.rotor == "elastic" and itf.rotor_nodes is not None else None)
    # every node of the mesh (with the mid-edge nodes of a quadratic one)
    n_pad, last, thermal = pad.p.shape[1], None, run.thermal
    setup_s = time.perf_counter() - t0

    def write_vtu(s: WearStep) -> None:
        fields = face_fields(n_pad, itf.pad_nodes, pressure=s.pressure, pad_wear=s.pad_wear,
                             active=s.active)
        pad_series.write(s.step, s.time, {**fields, **temperature_field(thermal, "pad", n_pad)})
        if rot_series is not None:
            a = np.zeros(rotor.p.shape[1])
            a[itf.rotor_nodes] = s.rotor_wear
            rot_series.write(s.step, s.time,
                             {"rotor_wear": a, **temperature_field(thermal, "rotor", a.size)})

    def summarise(last: WearStep, worn) -> dict:
        return _summary(run, out, rows, last, worn, start=start, run_s=time.perf_counter() - t0,
                        setup_s=setup_s, rotor=rot_series is not None)

    # Order on disk: a step's VTU and history row, then (on the last step) the summary,
    # then the checkpoint (written by wear_history when the next step is asked for):
    # a kill at any point leaves a checkpoint that the history and files reach
    worn, summary = None, None     # what ended the run before its end (None: it finished)
    try:
        for s in wear_history(run, checkpoint=ck, resume=resume, every=every):
            rows.append(step_figures(s, itf, run.mu))
            final = s.time >= duration * (1 - 1e-12)
            if s.step % vtu_every == 0 or s.step == 1 or final:
                write_vtu(s)
            _write_csv(csv_path, rows)
            last = s
            if final and not getattr(s, "worn_through", False):
                summary = summarise(s, None)
            if progress is not None:
                progress(s)
    except (WornThroughError, SolverError, KeyboardInterrupt) as exc:
        worn = exc      # the run's end: its last step is written, the summary says why
        if last is None:
            raise ended_early(out, exc, {"steps": start or 0, "duration_s": duration,
                                         "line_pressure_Pa": run.line_pressure}) from None
        if not (last.step % vtu_every == 0 or last.step == 1
                or last.time >= duration * (1 - 1e-12)):
            write_vtu(last)
    if last is None:
        raise WearError(f"{out}: the checkpoint holds a finished run (t = {duration:g} s); "
                         "nothing to resume. Run without resume, or into another folder")
    if worn is not None or summary is None:
        summary = summarise(last, worn)
    if worn is not None:
        worn.summary = summary
        raise worn
    return summary


def _summary(run, out: Path, rows: list, last: WearStep, worn, *, start, run_s: float,
             setup_s: float, rotor: bool) -> dict:
    """The summary of a run that ended at ``last`` (``worn``: what ended it early, None:
    it finished), written to ``out/summary.json``."""
    model, itf, thermal = run.model, run.interface, run.thermal
    summary = {
        **end_record(worn),
        "worn_through": worn.record() if isinstance(worn, WornThroughError) else None,
        "line_pressure_Pa": run.line_pressure, "omega_rad_s": run.omega,
        "duration_s": run.duration, "mu": law_record(run.mu), "rotor": model.rotor,
        "dofs": int(model.dofs), "pad_law": law_record(run.pad_law),
        "rotor_law": law_record(run.rotor_law),
        "steps": last.step, "final": rows[-1],
        "contact_solves": int(sum(int(r["contact_solves"]) for r in rows)),
        "rejected": int(sum(int(r["rejected"]) for r in rows)),
        "pad_archard_m3": last.pad_archard, "rotor_archard_m3": last.rotor_archard,
        "rotor_wear_profile": dict(zip(("r_m", "wear_m"), (
            a.tolist() for a in ring_profile(itf, last.rotor_wear)))),
        "run_s": run_s, "setup_s": setup_s, "resumed_from_step": start,
        "files": {"pad": "pad.pvd", "rotor": "rotor.pvd" if rotor else None,
                  "history": "history.csv", "checkpoint": "checkpoint.npz"},
        "thermal": None if thermal is None else thermal_record(thermal, last),
    }
    write_text(out / "summary.json", json.dumps(summary, indent=2, default=float))
    return summary


def resumed_rows(path: Path, step: int, time_s: float) -> list[dict]:
    """The rows of ``history.csv`` a resume from a checkpoint at ``step``, ``time_s``
    keeps: steps 1 to ``step``, each once, the last at the checkpoint's time (the rows
    after it, written before a kill, are dropped: the resumed run writes them again).
    A history that is missing, cut short or does not belong to the checkpoint is a
    :class:`~brakewear.errors.StoredFileError` naming it: continuing it would lose
    or repeat steps."""
    remedy = ("run again without --resume (with --overwrite) to start the history from "
              "the beginning")
    if not path.exists():
        raise StoredFileError(f"--resume: {path} is missing, but the checkpoint is at step "
                              f"{step}: the history of steps 1 to {step} is lost; {remedy}",
                              path=path)
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
        steps = [int(r["step"]) for r in rows]
        times = {int(r["step"]): float(r["time_s"]) for r in rows}
    except (OSError, UnicodeDecodeError, csv.Error, KeyError, TypeError, ValueError) as e:
        raise StoredFileError(f"--resume: {path} is cut or damaged ({type(e).__name__}: {e}); "
                              f"{remedy}", path=path) from None
    kept = [r for r, s in zip(rows, steps) if s <= step]
    if [int(r["step"]) for r in kept] != list(range(1, step + 1)):
        have = sorted(set(s for s in steps if s <= step))
        shown = f"steps {have[0]} to {have[-1]} ({len(kept)} rows)" if have else "no step"
        raise StoredFileError(f"--resume: {path} holds {shown}, but the checkpoint is at step "
                              f"{step}: it needs steps 1 to {step}, each once (the file was "
                              f"cut or edited); {remedy}", path=path)
    if not np.isclose(times[step], time_s, rtol=1e-12, atol=0.0):
        raise StoredFileError(f"--resume: {path} has step {step} at t = {times[step]!r} s, the "
                              f"checkpoint at t = {time_s!r} s: they are of different runs; "
                              f"{remedy}", path=path)
    return kept


def ended_early(out: Path, exc: BaseException, summary: dict):
    """Write ``out/summary.json`` of a run that ``exc`` ended early: ``summary`` (what
    is known so far) with its status and the reason (:func:`~brakewear.wear.records.end_record`).
    Returns ``exc``, the summary as its ``summary`` attribute, to re-raise."""
    summary = {**summary, **end_record(exc)}
    out.mkdir(parents=True, exist_ok=True)
    write_text(out / "summary.json", json.dumps(summary, indent=2, default=float))
    exc.summary = summary
    return exc


def _write_csv(path: Path, rows: list) -> None:
    tmp = path.with_name("." + path.name + ".tmp")
    with open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, path)


def run_scene(scene, out: str | os.PathLike, resume: bool = False,
              progress: Callable | None = None, announce: Callable | None = None) -> dict:
    """Build a scene's model and run its wear history into ``out``; return the summary.

    Writes what :func:`brakewear.output.runs.run_wear` writes, plus
    ``scene.json`` (this scene, SI) and, with ``output.figures``, PNG
    figures.  ``resume=True`` continues from ``out/checkpoint.npz`` and
    refuses a folder written by a different scene or with other inputs
    (geometry and material data, laws, numerics, package version: the
    checkpoint's fingerprint), also when that run has already finished.  ``progress`` is
    called with each :class:`~brakewear.wear.WearStep`, ``announce`` with the
    line that says which interface ``interface.model = "auto"`` chose and why
    (also logged, and in ``summary.json``'s ``interface``).  Every bad-input
    error names the scene file and shows its values in the file's units.

    Parameters
    ----------
    scene
        The :class:`~brakewear.scene.Scene`.
    out
        The run folder.
    resume
        Continue from ``out/checkpoint.npz``.
    progress
        Called with each step (a drag) or each application's record (a
        schedule), or None.
    announce
        Called with the line naming the interface ``"auto"`` chose, or None.

    Returns
    -------
    dict
        The run's summary (as ``summary.json`` holds it).
    """
    with file_messages(scene.source, scene.user_units):
        return _run_scene(scene, out, resume, progress, announce)


def _run_scene(scene, out, resume: bool, progress, announce=None) -> dict:
    out = check_out(out)
    record = scene.to_dict()
    rec_path = out / "scene.json"
    if resume and scene.schedule:
        raise SceneError("--resume: a scene with a [schedule] runs from its start (its "
                         "applications are not checkpointed); run it again without --resume")
    done = _resumable(scene, out, record, rec_path) if resume else None
    # every input is checked (and the run built) before anything is written to out
    run = scene.build_run(checkpoint=out / "checkpoint.npz" if resume else None)
    every = scene.output.checkpoint_every
    chosen = run.interface_record
    if chosen.get("reason"):
        logger.info("interface: %s (%s): %s", chosen["model"], chosen["requested"],
                    chosen["reason"])
        if announce is not None:
            announce(f"interface: {chosen['model']} ({chosen['requested']}): "
                     f"{chosen['reason']}")
    if done is not None:      # finished: nothing to run, once its inputs are the same
        check_resume(run, checkpoint=out / "checkpoint.npz", every=every)
        resumed_rows(out / "history.csv", done["steps"], checkpoint_progress(
            out / "checkpoint.npz")[1])
        logger.info("run in %s already finished (step %d)", out, done["steps"])
        if "accuracy" not in done:     # killed while its figures were drawn: draw them
            done = _scene_summary(scene, run, out, done, None)
        return done
    out.mkdir(parents=True, exist_ok=True)
    write_text(rec_path, json.dumps(record, indent=2))
    if scene.schedule:
        return _run_schedule_scene(scene, run, out, progress)
    worn = None
    try:
        summary = run_wear(run, out, vtu_every=scene.output.vtu_every, resume=resume,
                           progress=progress, every=every)
    except (WornThroughError, SolverError, KeyboardInterrupt) as exc:
        if getattr(exc, "summary", None) is None:
            raise
        worn, summary = exc, exc.summary
    summary = _scene_summary(scene, run, out, summary, worn)
    if worn is not None:
        raise worn
    return summary


def _scene_summary(scene, run, out: Path, summary: dict, worn) -> dict:
    """The run's summary with the scene's part (the interface chosen, the scene, the
    mesh's accuracy, the figures), written to ``out/summary.json``."""
    n, model = scene.numerics, run.model
    summary = {k: v for k, v in summary.items() if k != "already_finished"}
    summary["interface"] = run.interface_record
    summary["scene"] = {"name": scene.name, "source": scene.source,
                        "interface": scene.interface.model, "scheme": n.scheme,
                        "update": n.update, "mesh_size_m": model.geometry.mesh.size
                        if scene.mesh_size is None else scene.mesh_size}
    summary["accuracy"] = mesh_accuracy(scene)
    if scene.output.figures and "final" in summary and not isinstance(worn, KeyboardInterrupt):
        summary["figures"] = _figures(model, out, scene)
    write_text(out / "summary.json", json.dumps(summary, indent=2, default=float))
    return summary


def _run_schedule_scene(scene, run, out: Path, progress=None) -> dict:
    """A scene's [schedule]: applications.csv, the pad per application, summary.json
    (also when the schedule ends early: its status and the reason)."""
    from ..duty.report import run_schedule_files
    model, ended = run.model, None
    try:
        summary = run_schedule_files(run, out, title=scene.name, figures=scene.output.figures,
                                     progress=progress)
    except (WornThroughError, SolverError, KeyboardInterrupt) as exc:
        if getattr(exc, "summary", None) is None:
            raise
        ended, summary = exc, exc.summary
    summary["interface"] = run.interface_record
    summary["scene"] = {"name": scene.name, "source": scene.source, "scheme":
                        scene.numerics.scheme, "mesh_size_m": model.geometry.mesh.size
                        if scene.mesh_size is None else scene.mesh_size}
    summary["accuracy"] = mesh_accuracy(scene)
    write_text(out / "summary.json", json.dumps(summary, indent=2, default=float))
    if ended is not None:
        raise ended
    return summary


_REDO = "run again without --resume (with --overwrite) to redo the run"


def _resumable(scene, out: Path, record: dict, rec_path: Path) -> dict | None:
    """Check that ``out`` holds a run of ``scene`` to resume (raises SceneError
    naming the difference); its summary if that run has finished, else None
    (the inputs the scene resolves to are checked against the checkpoint's
    fingerprint once the model is built)."""
    ck = out / "checkpoint.npz"
    if not ck.exists():
        raise SceneError(f"--resume: {ck} does not exist (no checkpoint was written: "
                         "run without --resume to start)")
    # outputs may change on resume, and so may the duration under automatic
    # step control (a longer one extends the run)
    ignore = {"output"} | ({"duration"} if scene.numerics.steps is None else set())
    if rec_path.exists():
        old = read_json(rec_path, "--resume: the scene record", remedy=_REDO)
        diff = first_difference({k: v for k, v in old.items() if k not in ignore},
                                 {k: v for k, v in record.items() if k not in ignore})
        if diff is not None:
            raise SceneError(f"--resume: {out} holds a run of a different scene "
                             f"({diff}); resume with the same scene or choose another "
                             "--out")
    step_done, t_done = checkpoint_progress(ck)
    if t_done > scene.duration * (1 + 1e-12):
        reached = shown_value("environment.duration", t_done, "s")
        raise SceneError(f"--resume: the run in {out} has already reached t = {reached}, "
                         f"beyond environment.duration = "
                         f"{shown_value('environment.duration', scene.duration, 's')}; "
                         f"allowed: a duration >= {reached}")
    if t_done >= scene.duration * (1 - 1e-12):
        summ = out / "summary.json"
        if not summ.exists():
            raise SceneError(f"--resume: the run in {out} has finished (step "
                             f"{step_done}, t = {t_done:.6g} s) but its summary.json "
                             "is missing; run again without --resume to redo it")
        s = read_json(summ, "--resume: the summary", remedy=_REDO)
        if "steps" not in s:
            raise StoredFileError(f"--resume: the summary {summ} is not one of a finished run "
                                  f"(it has no 'steps'); {_REDO}", path=summ)
        s["already_finished"] = True
        return s
    return None


def check_out(out: str | os.PathLike, key: str = "out") -> Path:
    """The output folder ``out``, refused if it names an existing file (before any work)."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise SceneError(f"{key} = {str(out)!r} is an existing file, not a folder; give the "
                         "name of a folder to write into (it is made if missing)")
    for parent in out.parents:
        if parent.exists():
            if not parent.is_dir():
                raise SceneError(f"{key} = {str(out)!r}: {str(parent)!r} is a file, not a "
                                 "folder")
            break
    return out
