"""The elasticity benchmark (``brakewear bench elasticity``): a clamped P1 ring under the pad
footprint's pressure, mesh, assembly, AMG setup and solve from 30k to 1M DOFs."""
from __future__ import annotations

import json
import logging
import math
import statistics
import subprocess
import sys
import time
from collections.abc import Sequence

import numpy as np

from .common import fmt, peak_rss_mb

logger = logging.getLogger(__name__)


__all__ = [
    "DEFAULT_SIZES",
    "ring_resolution",
    "run_elasticity_case",
    "bench_elasticity",
    "fit_exponent",
    "format_table",
]

DEFAULT_SIZES = (30e3, 100e3, 300e3, 1e6)


#: Pad pressure of the benchmark case (Pa).
PRESSURE = 1.0e6


#: Relative residual the AMG-CG solve must reach.
TOL = 1e-8


_TIME_KEYS = ("mesh_s", "assemble_s", "amg_setup_s", "solve_s", "total_s", "direct_s")


def _ring_dims() -> dict:
    """Rotor ring half and pad footprint of the default geometry (SI units)."""
    from ..geometry.files import load_geometry

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




def run_elasticity_case(target_dofs: float, direct_max_dofs: int = 100_000) -> dict:
    """Build, assemble and solve the benchmark case once in this process; return its figures."""
    import scipy.sparse as sp  # noqa: F401  (import cost outside the timings)

    from ..fem.assembly import assemble_stiffness
    from ..fem.boundary import apply_dirichlet, assemble_pressure, boundary_dofs
    from ..mesh.structured import annulus_mesh
    from ..solvers.amg import amg_solver
    from ..solvers.direct import direct_solve

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
    peak = peak_rss_mb()
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
        row["peak_rss_direct_mb"] = peak_rss_mb()
    return row


def _run_child(target: float, direct_max_dofs: int) -> dict:
    cmd = [sys.executable, "-m", "brakewear.bench", "--_child",
           json.dumps({"target": float(target), "direct_max_dofs": int(direct_max_dofs)})]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(
            f"benchmark child for {target:.0f} DOFs failed (exit {proc.returncode}):\n"
            f"{proc.stderr.strip()[-2000:]}"
        )
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
    """One row from repeated runs: medians of timings and memory, the rest from the first."""
    row = dict(runs[0])
    for k in _TIME_KEYS + ("peak_rss_mb", "peak_rss_direct_mb", "iterations", "rel_residual"):
        vals = [r[k] for r in runs if r.get(k) is not None]
        if vals:
            row[k] = (
                float(statistics.median(vals))
                if k != "iterations"
                else int(statistics.median(vals))
            )
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
                   f"{fmt(r.get('direct_s'), '8.2f'):>8} {fmt(ratio, '7.1f'):>7} "
                   f"{fmt(r.get('direct_max_diff'), '8.1e'):>8}")
    k = fit_exponent(rows)
    out.append(
        f"total time ~ dofs^{k:.2f}" if k is not None else "total time exponent: one size only"
    )
    out.append(
        "dir/AMG = direct_s / (amg_setup_s + solve_s); max diff = max|u_amg - u_direct| / max|u|"
    )
    return "\n".join(out)


#: Target DOF counts and cases of ``brakewear bench contact``.
