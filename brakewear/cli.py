"""The ``brakewear`` command line.

``brakewear run SCENE`` runs a scene (a packaged name such as ``default``
or a scene file, docs/scenes.md): the wear history with a progress bar in
simulated time, checkpoints in the output folder, ``--resume`` to continue;
a folder that already holds a run is refused unless ``--resume`` or
``--overwrite`` (:mod:`brakewear.output.folder`); ``--import`` your own parts.
``brakewear demo`` runs the main job on the default brake: mesh, solve under
a line pressure with the pad tied to the rotor, write figures, VTU files and
a JSON summary; then the default scene (running-in under drag) into
``OUT/running_in``.  ``brakewear bench elasticity`` measures the elasticity
solver.

Exit codes: 0 success; 2 bad input (the message names the file, the key and
what is allowed; no traceback); 3 a solver that failed (non-convergence, an
active set that cycles, no acceptable wear step, a degenerate element);
4 a surface worn to its limit (the pad through its friction layer, the rotor
to its wear limit: the run ends there, its files and summary.json are
written; the message says when and where); 130 interrupted (Ctrl-C; the
message says how to resume).  ``brakewear --version`` prints the version;
``python -m brakewear`` is the same command.  ``brakewear new-scene NAME``
writes a starting geometry and scene for your own brake
(:mod:`brakewear.scene.starter`).  ``brakewear clean`` answers which
friction-only stops clean a corroded rotor, and with what probability
(:mod:`brakewear.cleaning.command`).
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

from .output.progress import Progress
from .solvers.heartbeat import listening
from .static import body_stresses, solve_tied, static_summary

logger = logging.getLogger(__name__)

__all__ = ["main", "run_demo", "run_demo_wear", "run_scene_file"]


EXIT_OK, EXIT_BAD_INPUT, EXIT_SOLVER, EXIT_WORN_THROUGH, EXIT_INTERRUPTED = 0, 2, 3, 4, 130


def run_demo(out: str | Path = "brakewear-out", geometry: str = "default",
             line_pressure_mpa: float = 1.0, piston: str = "traction",
             size_mm: float | None = None, figures: bool = True,
             memory_budget: float | None = None, overwrite: bool = False) -> dict:
    """Mesh the brake, solve it tied under the line pressure, write results; return the summary.

    ``size_mm`` must lie in the bounds scene files allow (half the radial pad
    width) and fit ``memory_budget`` (GB; default ``BRAKEWEAR_MEMORY_GB`` or
    the available memory); nothing is written before the input is checked.
    An ``out`` that already holds a run is refused unless ``overwrite`` (its
    run's files are removed once the input is checked).
    """
    import numpy as np

    from .checks import check_number, check_plausible, user_units
    from .geometry.files import load_geometry
    from .mesh.estimate import check_model_size
    from .mesh.io import write_mesh
    from .model import BrakeModel
    from .output.face_maps import plot_face_map
    from .output.figures import plot_field, plot_named_surfaces
    from .output.folder import check_new_out, clear_run
    from .output.runs import check_out

    # the whole input is checked before anything is meshed or written
    out = check_new_out(check_out(out, "--out"), overwrite=overwrite, can_resume=False)
    geom = load_geometry(geometry)
    with user_units({"--pressure": ("MPa", 1e6, 0.0, line_pressure_mpa)}):
        check_number("--pressure", line_pressure_mpa * 1e6, 0.0, unit="Pa")
        check_plausible("--pressure", line_pressure_mpa * 1e6, "environment.line_pressure")
    size = None if size_mm is None else size_mm * 1e-3
    check_model_size(geom, size, "elastic", piston, key="--size", unit="mm",
                     budget_key="--memory-budget", budget_gb=memory_budget)
    t0 = time.perf_counter()
    model = BrakeModel(geom, piston=piston, size=size, memory_budget=memory_budget)
    if overwrite:
        clear_run(out)
    out.mkdir(parents=True, exist_ok=True)
    res = solve_tied(model, line_pressure_mpa * 1e6)
    summary = static_summary(model, res)
    vm = body_stresses(model, res)
    files = []
    for b in model.bodies:
        m = model.meshes[b]
        u = res.u[b].reshape(-1, 3).T
        files.append(write_mesh(out / f"{b}.vtu", m, point_data={
            "displacement": u.T, "von_mises": vm[b]}))
    pad = model.meshes["pad"]
    p = np.zeros(pad.nvertices)
    p[res.interface_nodes] = res.interface_pressure
    if figures:
        files.append(plot_named_surfaces(model.meshes, out / "brake_surfaces.png",
                                         title="default brake: named surfaces"))
        files.append(plot_face_map(pad, p / 1e6, out / "pad_interface_pressure.png",
                                   f"Pad-rotor interface pressure, tied, {line_pressure_mpa:g} "
                                   "MPa line pressure", "interface pressure (MPa)",
                                   geom.pad, cmap="inferno"))
        files.append(plot_field(model.meshes["rotor"], vm["rotor"] / 1e6,
                                out / "rotor_von_mises.png",
                                "Rotor von Mises stress, displacements x 20 000",
                                label="von Mises stress (MPa)",
                                warp=res.u["rotor"].reshape(-1, 3).T, warp_scale=2e4))
    summary["run_s"] = time.perf_counter() - t0
    summary["files"] = [str(Path(f)) for f in files] + [str(out / "summary.json")]
    with open(out / "summary.json", "w") as fh:
        json.dump(summary, fh, indent=2)
    return summary


def _print_schedule(scene: str, s: dict) -> None:
    """What `brakewear run` prints for a scene with a [schedule]."""
    e = s["energy"]
    print(f"brakewear run {scene}: {s['applications']} applications "
          f"({s['braked_applications']} braked) over {s['schedule_s']:.6g} s, {s['run_s']:.1f} s")
    print(f"  per face: {e['demanded_per_face_J'] / 1e3:.4g} kJ demanded, "
          f"{e['dissipated_per_face_J'] / 1e3:.4g} kJ dissipated (largest difference "
          f"{e['largest_relative_difference']:.1%}); pad wear max "
          f"{s['pad_wear_max_m'] * 1e6:.3f} um, rotor wear max "
          f"{s['rotor_wear_max_m'] * 1e6:.3f} um")
    th = s.get("thermal")
    if th is not None:
        print(f"  at the end: pad face {th['final']['pad_T_max_C']:.4g} C, rotor face "
              f"{th['final']['rotor_T_max_C']:.4g} C (max)")
    print(f"  wrote {s['out']}/: summary.json, applications.csv, pad.pvd"
          + (", rotor.pvd" if s["files"].get("rotor") else "") + ", scene.json")


def _announce(line: str) -> None:
    """A line about the run before its progress bar (the interface "auto" chose)."""
    print(line, flush=True)


def _print_run(scene: str, s: dict) -> None:
    """What `brakewear run` prints at the end of a drag."""
    f = s["final"]
    if s.get("already_finished"):
        print(f"brakewear run: {s['out']} already holds the finished run "
              f"({s['steps']} steps); nothing to do")
        return
    print(f"brakewear run {scene}: {s['steps']} steps to t = {f['time_s']:.6g} s, "
          f"{s['dofs']} DOFs, {s['contact_solves']} contact solves, {s['run_s']:.1f} s")
    print(f"  pad wear max {f['pad_wear_max_m'] * 1e6:.3f} um, mean "
          f"{f['pad_wear_mean_m'] * 1e6:.3f} um; rotor wear max "
          f"{f['rotor_wear_max_m'] * 1e6:.3f} um; max pressure "
          f"{f['pressure_max_Pa'] / 1e6:.3f} MPa; p r spread {f['pr_spread']:.3f}")
    print(f"  wrote {s['out']}/: summary.json, history.csv, pad.pvd"
          + (", rotor.pvd" if s["files"].get("rotor") else "")
          + ", checkpoint.npz, scene.json"
          + "".join(f", {Path(p).name}" for p in s.get("figures", [])))


def run_scene_file(scene: str, out: str | Path | None = None, resume: bool = False,
                   quiet: bool = False, overwrite: bool = False,
                   imports: tuple[str, ...] | list[str] = ()) -> dict:
    """Load a scene (name or file), check it, run it into ``out``; return the summary.

    ``out`` defaults to ``brakewear-<scene name>``; a folder that already holds
    a run is refused unless ``overwrite`` (its run's files are removed once the
    scene is checked) or ``resume``.  A progress bar (stderr) advances in
    simulated time unless ``quiet``; a ``resume`` of a finished run says so at
    once and draws none.  ``imports``: modules of a user's parts (``--import``).
    """
    from .errors import SolverError, WornThroughError
    from .output.folder import check_new_out, clear_run, finished_run
    from .output.runs import check_out, run_scene
    from .parts import import_parts
    from .scene import load_scene

    if out is not None:
        check_out(out, "--out")
    import_parts(imports, "--import")
    sc = load_scene(scene)
    if getattr(sc, "tribometer", False):       # a tribometer test (docs/validation.md)
        from .tribology.command import run_tribometer_file
        return run_tribometer_file(sc, out, resume=resume, quiet=quiet, overwrite=overwrite)
    out = check_out(Path(out) if out is not None else Path(f"brakewear-{sc.name}"), "--out")
    check_new_out(out, overwrite=overwrite, resume=resume)
    done = finished_run(out, sc.duration) if resume and not sc.schedule else None
    if done is not None:
        print(f"brakewear run: {out} holds a finished run ({done[0]} steps to t = "
              f"{done[1]:.6g} s); checking that its inputs are this scene's", flush=True)
    if overwrite:
        clear_run(out)
    if done is None:
        _print_accuracy(f"brakewear run {scene}", sc)
    bar = Progress(sc, quiet or done is not None)
    try:
        with listening(bar.beat):
            summary = run_scene(sc, out, resume=resume, progress=bar, announce=_announce)
    except KeyboardInterrupt:
        bar.close()
        raise _Interrupted(sc, out, bar.step) from None
    except (WornThroughError, SolverError) as exc:
        if getattr(exc, "summary", None) is not None:
            exc.summary["out"] = str(out)
        raise
    finally:
        bar.close()
    summary["out"] = str(out)
    return summary


def _print_accuracy(what: str, scene) -> None:
    """The first lines of a run: its mesh and the estimated error of its pad wear
    (:func:`brakewear.scene.accuracy.mesh_accuracy`); a warning (stderr) for a coarse mesh."""
    from .scene.accuracy import accuracy_lines, mesh_accuracy

    lines = accuracy_lines(mesh_accuracy(scene))
    print(f"{what}: " + "\n  ".join(s for s in lines if not s.startswith("warning:")),
          flush=True)
    for s in lines:
        if s.startswith("warning:"):
            print(f"brakewear: {s}", file=sys.stderr, flush=True)


def run_demo_wear(out: str | Path, duration: float | None = None, quiet: bool = False,
                  figures: bool = True) -> dict:
    """The demo's second half: the default scene (running-in under drag) into ``out``."""
    import dataclasses

    from .output.runs import run_scene
    from .scene import load_scene

    sc = load_scene("default")
    if duration is not None:
        sc = dataclasses.replace(sc, duration=float(duration))
    if not figures:
        sc = dataclasses.replace(sc, output=dataclasses.replace(sc.output, figures=False))
    _print_accuracy("brakewear demo, running-in", sc)
    bar = Progress(sc, quiet)
    try:
        with listening(bar.beat):
            summary = run_scene(sc, out, progress=bar, announce=_announce)
    finally:
        bar.close()
    summary["out"] = str(out)
    return summary


class _Interrupted(Exception):
    def __init__(self, scene, out, step):
        self.scene, self.out, self.step = scene, out, step


def _parser() -> argparse.ArgumentParser:
    from . import __version__
    ap = argparse.ArgumentParser(prog="brakewear", description="Disc-brake pad and rotor wear.")
    ap.add_argument("--version", action="version", version=f"brakewear {__version__}")
    ap.add_argument("-v", "--verbose", action="store_true", help="log progress")
    sub = ap.add_subparsers(dest="command", required=True)
    from .scene.reader import available_scenes
    names = ", ".join(available_scenes())
    r = sub.add_parser("run", help="run a scene: a wear history (docs/scenes.md)",
                       description=f"Run a scene file or a packaged scene ({names}): the "
                                   "wear history of the brake, written to --out.")
    r.add_argument("scene", help=f"packaged scene name ({names}) or path of a scene .toml file")
    r.add_argument("--out", default=None,
                   help="output folder (default brakewear-<scene name>)")
    r.add_argument("--resume", action="store_true",
                   help="continue from the checkpoint in --out (same scene)")
    r.add_argument("--overwrite", action="store_true",
                   help="replace the run that --out already holds (without it, such a "
                        "folder is refused)")
    r.add_argument("--quiet", action="store_true", help="no progress bar")
    r.add_argument("--import", dest="imports", action="append", default=[], metavar="MODULE",
                   help="import MODULE (a name or a .py file) first: it registers your own "
                        "parts (docs/extending.md); repeatable")
    n = sub.add_parser("new-scene", help="write a starting geometry and scene file for your "
                                         "own brake (docs/howto_own_brake.md)",
                       description="Write NAME.toml (a brake geometry) and NAME_scene.toml (a "
                                   "scene that runs it), annotated, to edit from your drawing; "
                                   "existing files are never overwritten.")
    n.add_argument("name", help="file name of the brake, without .toml (e.g. my_brake)")
    n.add_argument("--dir", default=".", help="folder to write into (default: here)")
    n.add_argument("--from", dest="start", choices=("default", "floating"), default="default",
                   help="the packaged brake to start from: default (one pad, fixed caliper, "
                        "solid ring) or floating (floating caliper, hat rotor, both pads)")
    d = sub.add_parser("demo", help="the default brake end to end (the README's main job)")
    d.add_argument("--out", default="brakewear-out", help="output folder (default brakewear-out)")
    d.add_argument("--overwrite", action="store_true",
                   help="replace the demo run that --out already holds")
    d.add_argument("--geometry", default="default", help="geometry name or .toml path")
    d.add_argument("--pressure", type=float, default=1.0, help="line pressure in MPa (default 1)")
    d.add_argument("--piston", choices=("traction", "body"), default="traction",
                   help="piston as a traction on the backplate or as a tied body")
    d.add_argument("--size", type=float, default=None,
                   help="mesh size at the interface, mm (at most half the radial pad width, "
                        "and the model must fit the memory)")
    d.add_argument("--memory-budget", type=float, default=None, metavar="GB",
                   help="memory the model may use, GB (default: BRAKEWEAR_MEMORY_GB or the "
                        "available memory)")
    d.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    d.add_argument("--wear-duration", type=float, default=None,
                   help="then run the default scene (running-in under drag) for this many "
                        "seconds of drag into OUT/running_in (default: the scene's own 3600 s; "
                        "0 skips it)")
    d.add_argument("--quiet", action="store_true", help="no progress bar")
    from .cleaning.command import add_clean_parser
    add_clean_parser(sub)
    b = sub.add_parser("bench", help="benchmarks (timings and errors)")
    try:
        from .bench import add_bench_parser
        add_bench_parser(b.add_subparsers(dest="bench", required=True))
    except ImportError:  # pragma: no cover
        pass
    return ap


def _new_scene(args) -> int:
    """``brakewear new-scene NAME``: the starting files, and what to do next."""
    from .scene.starter import write_new_scene

    geo, scn = write_new_scene(args.name, args.dir, args.start)
    print(f"brakewear new-scene: wrote {geo} (the brake) and {scn} (what to run), both the "
          f"packaged {args.start!r} brake until you edit them from your drawing "
          f"(docs/howto_own_brake.md); then:\n  brakewear run {scn}")
    return EXIT_OK


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    from .errors import InputError, SolverError, WornThroughError

    try:
        if args.command == "run":
            s = run_scene_file(args.scene, args.out, args.resume, args.quiet,
                               overwrite=args.overwrite, imports=args.imports)
            if "test" in s:
                from .tribology.command import summary_lines
                print("\n".join(summary_lines(args.scene, s)))
                return EXIT_OK
            if "braked_applications" in s:
                _print_schedule(args.scene, s)
                return EXIT_OK
            _print_run(args.scene, s)
            return EXIT_OK
        if args.command == "demo":
            s = run_demo(args.out, args.geometry, args.pressure, args.piston, args.size,
                         figures=not args.no_figures, memory_budget=args.memory_budget,
                         overwrite=args.overwrite)
            i = s["interface"]
            print(f"brakewear demo: {s['solver']['dofs']} DOFs, line pressure "
                  f"{s['line_pressure_Pa'] / 1e6:g} MPa, clamp force {s['clamp_force_N']:.1f} N")
            print(f"  interface: force {i['normal_force_N']:.3f} N (balance error "
                  f"{i['force_balance_error']:.1e}), pressure mean "
                  f"{i['pressure_mean_Pa'] / 1e6:.3f} MPa, max {i['pressure_max_Pa'] / 1e6:.3f} "
                  f"MPa\n  solve: {s['solver']['iterations']} AMG-CG iterations, total "
                  f"{s['run_s']:.1f} s")
            print(f"  wrote: {', '.join(s['files'])}")
            if args.wear_duration is None or args.wear_duration > 0:
                w = run_demo_wear(Path(args.out) / "running_in", args.wear_duration, args.quiet,
                                  figures=not args.no_figures)
                f = w["final"]
                print(f"brakewear demo, running-in (scene 'default', {w['dofs']} DOFs): "
                      f"{w['steps']} steps to t = {f['time_s']:.6g} s in {w['run_s']:.1f} s")
                print(f"  pad wear max {f['pad_wear_max_m'] * 1e6:.3f} um, contact "
                      f"{100 * f['contact_fraction']:.0f} % of the pad face, p r spread "
                      f"{f['pr_spread']:.3f}; wrote {w['out']}/")
            return 0
        if args.command == "new-scene":
            return _new_scene(args)
        if args.command == "clean":
            from .cleaning.command import clean_main
            return clean_main(args)
        if args.command == "bench":
            from .bench import run_bench
            return run_bench(args)
    except _Interrupted as e:
        ck = Path(e.out) / "checkpoint.npz"
        where = (f"the checkpoint {ck} holds the last saved step (every "
                 f"{e.scene.output.checkpoint_every} steps); continue with:\n  brakewear run "
                 f"{args.scene} --out {e.out} --resume"
                 + "".join(f" --import {m}" for m in args.imports) if ck.exists() else
                 "no checkpoint was written yet: run again without --resume")
        print(f"brakewear: interrupted at step {e.step}; {where}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except KeyboardInterrupt:
        print("brakewear: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except SolverError as e:
        out = getattr(e, "summary", None) or {}
        print(f"brakewear: solver failed ({type(e).__name__}): {e}"
              + (f"; summary.json (status {out['status']!r}) and the steps up to it are in "
                 f"{out['out']}" if "out" in out else ""), file=sys.stderr)
        return EXIT_SOLVER
    except WornThroughError as e:
        out = getattr(e, "summary", {}).get("out") or (args.out or "the output folder")
        print(f"brakewear: {e}; the steps up to it and summary.json (status "
              f"'worn_through') are in {out}", file=sys.stderr)
        return EXIT_WORN_THROUGH
    # InputError, and bad input that a library below reports as ValueError or OSError
    except (InputError, ValueError, OSError) as e:
        print(f"brakewear: error: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    return 1


if __name__ == "__main__":
    sys.exit(main())
