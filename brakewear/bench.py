"""Benchmarks: ``brakewear bench elasticity [--json]``.

The elasticity benchmark solves a realistic static case at several sizes:
the friction-ring half of the default rotor (inner/outer radius and half
thickness from ``geometry/default.toml``) as a closed P1 ring, clamped at its
inner radius, loaded by a uniform pressure over the pad footprint (the pad's
radii and arc) on the friction face.  The mesh resolution is chosen so that
the number of DOFs is close to each target.

Every size runs in a fresh Python process (``python -m brakewear.bench
--_child ...``), so its ``peak_rss_mb`` is that size's own peak and nothing
is cached between sizes.  Measured per size:

``mesh_s``
    the mesh with its named boundaries (reported apart, not in the total),
``assemble_s``
    stiffness (with its sparsity pattern), pressure load, clamped DOFs and the
    Dirichlet elimination,
``amg_setup_s``, ``solve_s``, ``iterations``, ``rel_residual``
    the AMG hierarchy (:func:`brakewear.solvers.amg_solver`, rigid-body
    modes) and the AMG-CG solve to ``||r|| <= 1e-8 ||f||`` (true residual),
``total_s``
    ``assemble_s + amg_setup_s + solve_s``,
``peak_rss_mb``
    the process's peak resident memory after the AMG solve (before the
    direct solve, which is measured afterwards),
``direct_s``, ``direct_max_diff``
    SuperLU on the same system (:func:`brakewear.solvers.direct_solve`) up to
    ``direct_max_dofs`` (else ``None``) and ``max|u_amg - u_direct| / max|u|``.

:func:`fit_exponent` fits ``total_s ~ dofs^k``; every row carries the
``total_exponent`` of its run.

Run ``python -m brakewear.bench elasticity [--json] [--sizes 3e4 1e5 ...]``;
``brakewear bench elasticity`` is the same through the main CLI.
"""
from __future__ import annotations

import argparse
import json
import logging
import math
import os
import platform
import statistics
import subprocess
import sys
import time
from typing import Sequence

import numpy as np

logger = logging.getLogger(__name__)

__all__ = [
    "DEFAULT_SIZES",
    "ring_resolution",
    "run_elasticity_case",
    "bench_elasticity",
    "fit_exponent",
    "format_table",
    "add_bench_parser",
    "run_bench",
    "main",
]

#: Target DOF counts of ``brakewear bench elasticity``.
DEFAULT_SIZES = (30e3, 100e3, 300e3, 1e6)
#: Pad pressure of the benchmark case (Pa).
PRESSURE = 1.0e6
#: Relative residual the AMG-CG solve must reach.
TOL = 1e-8

_TIME_KEYS = ("mesh_s", "assemble_s", "amg_setup_s", "solve_s", "total_s", "direct_s")


def _ring_dims() -> dict:
    """Rotor ring half and pad footprint of the default geometry (SI units)."""
    from .geometry import load_geometry

    g = load_geometry("default")
    return dict(ri=g.rotor.inner_radius, ro=g.rotor.outer_radius, height=0.5 * g.rotor.thickness,
                pad_ri=g.pad.inner_radius, pad_ro=g.pad.outer_radius,
                pad_center=g.pad.center_angle, pad_arc=g.pad.arc_angle,
                material=g.rotor.material)


def _cells(h: float, d: dict) -> tuple[int, int, int]:
    nr = max(1, int(round((d["ro"] - d["ri"]) / h)))
    nth = max(8, int(round(np.pi * (d["ri"] + d["ro"]) / h)))
    nz = max(1, int(round(d["height"] / h)))
    return nr, nth, nz


def ring_resolution(target_dofs: float, dims: dict | None = None) -> tuple[int, int, int]:
    """Cells (radial, around, through the thickness) of a ring mesh of about
    ``target_dofs`` P1 DOFs with near-cubic cells."""
    d = _ring_dims() if dims is None else dims
    vol = np.pi * (d["ro"] ** 2 - d["ri"] ** 2) * d["height"]
    h0 = (3.0 * vol / float(target_dofs)) ** (1.0 / 3.0)
    best = None
    for h in h0 * np.linspace(0.7, 1.4, 400):
        nr, nth, nz = _cells(h, d)
        dofs = 3 * (nr + 1) * nth * (nz + 1)
        err = abs(math.log(dofs / float(target_dofs)))
        if best is None or err < best[0]:
            best = (err, (nr, nth, nz))
    return best[1]


def _peak_rss_mb() -> float:
    import resource

    r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return r / 1024.0 if sys.platform != "darwin" else r / 2 ** 20


def run_elasticity_case(target_dofs: float, direct_max_dofs: int = 100_000) -> dict:
    """Build, assemble and solve the benchmark case once in this process; return its figures."""
    import scipy.sparse as sp  # noqa: F401  (import cost outside the timings)

    from .elasticity import apply_dirichlet, assemble_pressure, assemble_stiffness, boundary_dofs
    from .mesh import annulus_mesh
    from .solvers import amg_solver, direct_solve

    d = _ring_dims()
    nr, nth, nz = ring_resolution(target_dofs, d)

    t0 = time.perf_counter()
    m = annulus_mesh(d["ri"], d["ro"], d["height"], nr, nth, nz)
    mesh_s = time.perf_counter() - t0

    t0 = time.perf_counter()
    K, _ = assemble_stiffness(m, d["material"])
    # pad footprint on the friction face (z = height)
    top = m.boundaries["top"]
    mid = m.p[:, m.facets[:, top]].mean(axis=1)
    r = np.hypot(mid[0], mid[1])
    dth = np.angle(np.exp(1j * (np.arctan2(mid[1], mid[0]) - d["pad_center"])))
    loaded = top[(r > d["pad_ri"]) & (r < d["pad_ro"]) & (np.abs(dth) < 0.5 * d["pad_arc"])]
    f = assemble_pressure(m, loaded, PRESSURE)
    fixed = boundary_dofs(m, "inner")
    Kd, fd = apply_dirichlet(K, f, fixed)
    del K, f
    assemble_s = time.perf_counter() - t0

    t0 = time.perf_counter()
    solver = amg_solver(Kd, coords=m.p, fixed=fixed, tol=TOL)
    setup_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    u = solver.solve(fd)
    solve_s = time.perf_counter() - t0
    peak = _peak_rss_mb()
    rel = float(np.linalg.norm(fd - Kd @ u) / np.linalg.norm(fd))
    row = {
        "dofs": int(Kd.shape[0]),
        "nodes": int(m.p.shape[1]),
        "elements": int(m.t.shape[1]),
        "cells": [nr, nth, nz],
        "nnz": int(Kd.nnz),
        "mesh_s": mesh_s,
        "assemble_s": assemble_s,
        "amg_setup_s": setup_s,
        "solve_s": solve_s,
        "total_s": assemble_s + setup_s + solve_s,
        "iterations": int(solver.info.iterations),
        "rel_residual": rel,
        "amg_levels": len(solver.ml.levels),
        "operator_complexity": float(solver.ml.operator_complexity()),
        "peak_rss_mb": peak,
        "direct_s": None,
        "direct_max_diff": None,
        "max_u_m": float(np.abs(u).max()),
    }
    del solver
    if Kd.shape[0] <= direct_max_dofs:
        t0 = time.perf_counter()
        ud = direct_solve(Kd, fd, max_dofs=direct_max_dofs)
        row["direct_s"] = time.perf_counter() - t0
        row["direct_max_diff"] = float(np.abs(u - ud).max() / np.abs(ud).max())
        row["peak_rss_direct_mb"] = _peak_rss_mb()
    return row


def _run_child(target: float, direct_max_dofs: int) -> dict:
    cmd = [sys.executable, "-m", "brakewear.bench", "--_child",
           json.dumps({"target": float(target), "direct_max_dofs": int(direct_max_dofs)})]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"benchmark child for {target:.0f} DOFs failed (exit {proc.returncode}):\n"
                           f"{proc.stderr.strip()[-2000:]}")
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if not lines:
        raise RuntimeError(f"benchmark child for {target:.0f} DOFs printed no result:\n"
                           f"{proc.stdout[-1000:]}{proc.stderr[-1000:]}")
    return json.loads(lines[-1])


def fit_exponent(rows: Sequence[dict], key: str = "total_s") -> float | None:
    """Least-squares slope of ``log(key)`` against ``log(dofs)``; None for fewer than two sizes."""
    pts = [(r["dofs"], r[key]) for r in rows if r.get(key)]
    if len({p[0] for p in pts}) < 2:
        return None
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])


def _median_row(runs: list[dict]) -> dict:
    """One row from repeated runs: medians of the timings and memory, the rest from the first run."""
    row = dict(runs[0])
    for k in _TIME_KEYS + ("peak_rss_mb", "peak_rss_direct_mb", "iterations", "rel_residual"):
        vals = [r[k] for r in runs if r.get(k) is not None]
        if vals:
            row[k] = float(statistics.median(vals)) if k != "iterations" else int(statistics.median(vals))
    row["repeats"] = len(runs)
    if len(runs) > 1:
        row["total_s_runs"] = [r["total_s"] for r in runs]
    return row


def bench_elasticity(sizes: Sequence[float] = DEFAULT_SIZES, direct_max_dofs: int = 100_000,
                     repeats: int = 1, progress=None) -> list[dict]:
    """Run the elasticity benchmark; one dict per size (medians over ``repeats`` fresh processes).

    ``progress`` (optional) is called with each finished row.  Every row gets
    ``total_exponent``, the fitted exponent of ``total_s`` against ``dofs``
    over all sizes of the run (None for a single size).
    """
    rows = []
    for target in sizes:
        runs = []
        for rep in range(max(1, int(repeats))):
            logger.info("bench elasticity: %.0f DOFs, run %d of %d", target, rep + 1, repeats)
            runs.append(_run_child(target, direct_max_dofs))
        row = _median_row(runs)
        row["target_dofs"] = int(target)
        rows.append(row)
        if progress is not None:
            progress(row)
    k = fit_exponent(rows)
    for row in rows:
        row["total_exponent"] = k
    return rows


def _fmt(v, spec: str, none: str = "-") -> str:
    return none if v is None else format(v, spec)


def format_table(rows: Sequence[dict]) -> str:
    """The rows as a readable text table, with the fitted exponent."""
    head = (f"{'dofs':>9} {'mesh s':>7} {'assem s':>7} {'setup s':>7} {'solve s':>7} "
            f"{'total s':>7} {'its':>4} {'rel res':>8} {'peak MB':>8} {'direct s':>8} "
            f"{'dir/AMG':>7} {'max diff':>8}")
    out = [head, "-" * len(head)]
    for r in rows:
        amg = r["amg_setup_s"] + r["solve_s"]
        ratio = r["direct_s"] / amg if r.get("direct_s") is not None else None
        out.append(f"{r['dofs']:>9d} {r['mesh_s']:>7.2f} {r['assemble_s']:>7.2f} "
                   f"{r['amg_setup_s']:>7.2f} {r['solve_s']:>7.2f} {r['total_s']:>7.2f} "
                   f"{r['iterations']:>4d} {r['rel_residual']:>8.1e} {r['peak_rss_mb']:>8.0f} "
                   f"{_fmt(r.get('direct_s'), '8.2f'):>8} {_fmt(ratio, '7.1f'):>7} "
                   f"{_fmt(r.get('direct_max_diff'), '8.1e'):>8}")
    k = fit_exponent(rows)
    out.append(f"total time ~ dofs^{k:.2f}" if k is not None else "total time exponent: one size only")
    out.append("dir/AMG = direct_s / (amg_setup_s + solve_s); max diff = max|u_amg - u_direct| / max|u|")
    return "\n".join(out)


# ------------------------------------------------------------------ CLI ---

def _add_elasticity_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true",
                   help="one JSON object per size and line instead of a table")
    p.add_argument("--sizes", type=float, nargs="+", default=list(DEFAULT_SIZES), metavar="DOFS",
                   help="target DOF counts (default: 3e4 1e5 3e5 1e6)")
    p.add_argument("--direct-max", type=int, default=100_000, dest="direct_max", metavar="DOFS",
                   help="largest system also solved by SuperLU (default 100000)")
    p.add_argument("--repeats", type=int, default=1,
                   help="fresh processes per size; timings are their medians (default 1)")
    p.set_defaults(bench="elasticity")


def add_bench_parser(subparsers) -> None:
    """Register the benchmarks as sub-commands of ``subparsers`` (the ``bench`` command's):
    ``elasticity [--json] [--sizes ...] [--direct-max N] [--repeats N]``.

    ``brakewear bench elasticity`` is then run by :func:`run_bench` (also set
    as the ``func`` default of the parsed arguments).
    """
    e = subparsers.add_parser("elasticity", help="P1 elasticity: assembly, AMG setup and solve, memory",
                              description="P1 elasticity benchmark: the default rotor ring half, "
                                          "clamped inside, pad pressure; each size in a fresh process.")
    _add_elasticity_args(e)
    e.set_defaults(func=run_bench)


def run_bench(args: argparse.Namespace) -> int:
    """Run the benchmark chosen by ``args`` and print a table or JSON lines; exit code."""
    if getattr(args, "bench", "elasticity") != "elasticity":
        print(f"unknown benchmark {args.bench!r}; available: elasticity", file=sys.stderr)
        return 2
    if not args.json:
        print(f"brakewear bench elasticity: {os.cpu_count()} CPUs, Python {platform.python_version()}, "
              f"sizes {' '.join(f'{s:.0f}' for s in args.sizes)}", flush=True)

    def progress(row):
        if args.json:
            print(json.dumps(row), flush=True)
        else:
            print(f"  {row['dofs']} DOFs: total {row['total_s']:.2f} s, "
                  f"peak {row['peak_rss_mb']:.0f} MB", flush=True)

    try:
        rows = bench_elasticity(args.sizes, args.direct_max, args.repeats,
                                progress=None if args.json else progress)
    except RuntimeError as exc:
        print(f"bench elasticity failed: {exc}", file=sys.stderr)
        return 1
    if args.json:
        for row in rows:
            print(json.dumps(row), flush=True)
    else:
        print(format_table(rows))
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["--_child"]:
        opts = json.loads(argv[1])
        if opts.get("warmup", True):
            # first calls pay for imports and library set-up; a tiny case
            # takes them so that the timed run measures the work itself
            run_elasticity_case(1500, 0)
        row = run_elasticity_case(opts["target"], opts["direct_max_dofs"])
        print(json.dumps(row), flush=True)
        return 0
    ap = argparse.ArgumentParser(prog="python -m brakewear.bench",
                                 description="brakewear performance benchmarks")
    add_bench_parser(ap.add_subparsers(dest="bench", metavar="BENCHMARK", required=True))
    return run_bench(ap.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
