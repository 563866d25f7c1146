"""The ``brakewear`` command line.

``brakewear demo`` runs the main job on the default brake: mesh, solve under
a line pressure with the pad tied to the rotor, write figures, VTU files and
a JSON summary.  ``brakewear bench elasticity`` measures the elasticity
solver.  Exit codes: 0 success, 2 bad input (the message names it), 3 a
solver that did not converge.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

__all__ = ["main", "run_demo"]


def run_demo(out: str | Path = "brakewear-out", geometry: str = "default",
             line_pressure_mpa: float = 1.0, piston: str = "traction",
             size_mm: float | None = None, figures: bool = True) -> dict:
    """Mesh the brake, solve it tied under the line pressure, write results; return the summary."""
    import numpy as np

    from .figures import plot_field, plot_named_surfaces
    from .mesh import write_mesh
    from .scene import BrakeModel

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    model = BrakeModel(geometry, piston=piston,
                       size=None if size_mm is None else size_mm * 1e-3)
    res = model.solve_tied(line_pressure_mpa * 1e6)
    summary = model.summary(res)
    vm = model.stresses(res)
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
        files.append(plot_field(pad, p / 1e6, out / "pad_interface_pressure.png",
                                f"Pad-rotor interface pressure, tied, {line_pressure_mpa:g} MPa line",
                                label="pressure (MPa)", cmap="inferno", facets="friction",
                                view=(0.0, 0.0, -1.0)))
        files.append(plot_field(model.meshes["rotor"], vm["rotor"] / 1e6,
                                out / "rotor_von_mises.png",
                                "Rotor von Mises stress (MPa)", label="von Mises (MPa)",
                                warp=res.u["rotor"].reshape(-1, 3).T, warp_scale=2e4))
    summary["run_s"] = time.perf_counter() - t0
    summary["files"] = [str(Path(f)) for f in files] + [str(out / "summary.json")]
    with open(out / "summary.json", "w") as fh:
        json.dump(summary, fh, indent=2)
    return summary


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="brakewear", description="Disc-brake pad and rotor wear by 3D FE.")
    ap.add_argument("-v", "--verbose", action="store_true", help="log progress")
    sub = ap.add_subparsers(dest="command", required=True)
    d = sub.add_parser("demo", help="the default brake end to end (the README's main job)")
    d.add_argument("--out", default="brakewear-out", help="output folder (default brakewear-out)")
    d.add_argument("--geometry", default="default", help="geometry name or .toml path")
    d.add_argument("--pressure", type=float, default=1.0, help="line pressure in MPa (default 1)")
    d.add_argument("--piston", choices=("traction", "body"), default="traction",
                   help="piston as a traction on the backplate or as a tied body")
    d.add_argument("--size", type=float, default=None, help="mesh size at the interface, mm")
    d.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    b = sub.add_parser("bench", help="benchmarks (timings and errors)")
    try:
        from .bench import add_bench_parser
        add_bench_parser(b.add_subparsers(dest="bench", required=True))
    except ImportError:  # pragma: no cover
        pass
    return ap


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    from .geometry import GeometryError
    from .materials import MaterialError
    from .scene import SceneError
    from .solvers import ConvergenceError
    try:
        if args.command == "demo":
            s = run_demo(args.out, args.geometry, args.pressure, args.piston, args.size,
                         figures=not args.no_figures)
            i = s["interface"]
            print(f"brakewear demo: {s['solver']['dofs']} DOFs, line pressure "
                  f"{s['line_pressure_Pa'] / 1e6:g} MPa, clamp force {s['clamp_force_N']:.1f} N")
            print(f"  interface: force {i['normal_force_N']:.3f} N (balance error "
                  f"{i['force_balance_error']:.1e}), pressure mean {i['pressure_mean_Pa'] / 1e6:.3f} "
                  f"MPa, max {i['pressure_max_Pa'] / 1e6:.3f} MPa")
            print(f"  solve: {s['solver']['iterations']} AMG-CG iterations, total {s['run_s']:.1f} s")
            print(f"  wrote: {', '.join(s['files'])}")
            return 0
        if args.command == "bench":
            from .bench import run_bench
            return run_bench(args)
    except (GeometryError, MaterialError, SceneError, ValueError) as e:
        print(f"brakewear: error: {e}", file=sys.stderr)
        return 2
    except ConvergenceError as e:
        print(f"brakewear: solver failed: {e}", file=sys.stderr)
        return 3
    return 1


if __name__ == "__main__":
    sys.exit(main())
