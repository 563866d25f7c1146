"""Benchmarks: ``brakewear bench elasticity|contact|wear [--json]``.

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

Contact (``brakewear bench contact [--json] [--sizes 5e4 1.5e5 5e5] [--cases
hertz brake] [--direct-max N] [--repeats N]``): each case and size in a fresh
process (after a tiny warm-up case), measured after assembly.  The contact
solve and the elasticity solve are each timed twice in the process and the
faster counts (``*_pair`` keys: both times), as in the wear benchmark: on
the shared machine single timings scatter by 10-30 %, and both solves are
treated alike.

``hertz``
    the Hertz model of :mod:`brakewear.verification` (rigid sphere on a
    quarter block, Boussinesq far field), ``h/a`` chosen for the DOF count.
    ``contact_solve_s`` is the first, cold :func:`~brakewear.contact.solve_contact`
    of the far-field force iteration (active set from the initial gaps);
    ``contact_outer_s`` all of them; ``p0_error``/``a_error`` at convergence.
    ``elasticity_solve_s``: AMG setup + CG of the same stiffness with the final
    contact nodes held along z by Dirichlet conditions (same tolerance 1e-10).
    ``fixed_set_solve_s``: one ``solve_contact`` given the converged active set
    and the last far field (its own hierarchy, CG from zero), the like-for-like
    of the direct KKT solve at that set.
``brake``
    the default brake, elastic rotor, 1 MPa line pressure, ``mu = 0.4``: the
    steps of :meth:`BrakeModel.solve_contact`, ``contact_solve_s`` the
    ``solve_contact`` call (everything in it: operators, the AMG setup and
    refreshes, the solves).  ``elasticity_solve_s``: the AMG setup + CG of
    :meth:`BrakeModel.solve_tied` (pad tied to the rotor; its assembly
    excluded, its AMG setup included).  A wear step's cost: ``contact_hierarchy_s``
    (:func:`~brakewear.contact.contact_preconditioner`, once per wear run) and
    ``contact_step_s``, a solve with that hierarchy from the converged active set.

``ratio`` = contact / elasticity.  Up to ``direct_max_dofs`` the saddle-point
system at the converged active set (:func:`kkt_system`) is factorised and
solved with SuperLU (``direct_kkt_superlu_s``) and, if the optional
benchmark-only package ``pypardiso`` (MKL PARDISO) is installed, PARDISO
(``direct_kkt_pardiso_s``, real unsymmetric; for the symmetric Hertz system
also ``direct_kkt_pardiso_sym_s``, symmetric indefinite on the upper
triangle; None without it); ``direct_kkt_s`` is the fastest,
``kkt_multiplier_diff`` its ``max|lambda_kkt - lambda| / max|lambda|``
against ``solve_contact``, ``speedup_vs_direct = direct_kkt_s /
contact_solve_s``.  pypardiso is not a runtime dependency of brakewear.
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
    "CONTACT_SIZES",
    "CONTACT_CASES",
    "brake_resolution",
    "kkt_system",
    "run_contact_case",
    "bench_contact",
    "format_contact_table",
    "WEAR_SIZES",
    "run_wear_case",
    "bench_wear",
    "format_wear_table",
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


def _peak_rss_mb() -> float:
    import resource

    r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return r / 1024.0 if sys.platform != "darwin" else r / 2 ** 20


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


#: Target DOF counts and cases of ``brakewear bench contact``.
CONTACT_SIZES = (50e3, 150e3, 500e3)


CONTACT_CASES = ("hertz", "brake")


#: Largest system whose KKT system is also factorised (SuperLU and PARDISO).
CONTACT_DIRECT_MAX = 200_000


#: Brake case: line pressure (Pa), friction coefficient and contact tolerance.
BRAKE_PRESSURE = 1.0e6


BRAKE_MU = 0.4


BRAKE_TOL = 1e-9


_BRAKE_REF = (0.0025, 81_570)  # default mesh size (m) and its DOF count


_CONTACT_TIME_KEYS = ("assemble_s", "contact_solve_s", "elasticity_solve_s", "dirichlet_s",
                      "direct_kkt_superlu_s", "direct_kkt_pardiso_s", "direct_kkt_s",
                      "contact_outer_s", "contact_hierarchy_s", "contact_step_s",
                      "fixed_set_solve_s", "direct_kkt_pardiso_sym_s", "direct_active_set_s")


def brake_resolution(target_dofs: float) -> tuple[float, "object"]:
    """Mesh size (m) of the default brake with about ``target_dofs`` DOFs and the model."""
    from ..model import BrakeModel

    size = _BRAKE_REF[0] * (_BRAKE_REF[1] / float(target_dofs)) ** (1.0 / 3.0)
    model = BrakeModel(size=size, rotor="elastic")
    for _ in range(2):
        err = model.dofs / float(target_dofs)
        if abs(math.log(err)) < 0.06:
            break
        size *= err ** (1.0 / 3.0)
        model = BrakeModel(size=size, rotor="elastic")
    return size, model


def kkt_system(K, f, fixed, fixed_values, pair, active):
    """The saddle-point system at a fixed active set, Dirichlet DOFs removed.

    Unknowns ``(u_free, lambda)`` (``lambda`` = normal contact force of each
    active slave node, > 0 in compression)::

        [ K_ff   -(C_f^T + G_f) ] [u]   [ f_f - K_fc u_c      ]
        [ -C_f    0             ] [l] = [ g0 + C_c u_c        ]

    ``C`` (one row per active slave node) is the normal gap ``n . (u_s - sum
    W u_m)`` including the coupling to the master nodes, ``G`` the sliding
    friction load per unit normal force (drag on the slave, opposite on its
    masters).  Without friction the matrix is symmetric (indefinite).
    Returns (matrix CSR, rhs, free DOFs, active slave indices).
    """
    import scipy.sparse as sp

    from ..contact.elimination import _friction_operators

    N = K.shape[0]
    idx = np.flatnonzero(active)
    s, n = pair.slave[idx], pair.normal[:, idx]
    k = np.arange(idx.size)
    rows, cols, vals = [], [], []
    for i in range(3):
        rows.append(k)
        cols.append(3 * s + i)
        vals.append(n[i])
    if not pair.rigid:
        Wc = pair.coupling[idx].tocoo()
        for i in range(3):
            rows.append(Wc.row)
            cols.append(3 * Wc.col + i)
            vals.append(-Wc.data * n[i, Wc.row])
    C = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(idx.size, N))
    B = C.T.tocsr()
    if pair.mu > 0:
        G, _ = _friction_operators(N, [pair], [np.asarray(active, dtype=bool)])
        B = (B + G).tocsr()
    isfixed = np.zeros(N, dtype=bool)
    isfixed[fixed] = True
    free = np.flatnonzero(~isfixed)
    uc = np.zeros(N)
    uc[fixed] = fixed_values
    K = K.tocsr()
    Kf = K[free][:, free]
    rhs_u = (np.asarray(f, dtype=float) - K @ uc)[free]
    rhs_l = pair.g0[idx] + C @ uc
    M = sp.bmat([[Kf, -B[free]], [-C[:, free], None]], format="csr")
    return M, np.concatenate([rhs_u, rhs_l]), free, idx


def symmetric_upper(M):
    """The upper triangle of a symmetric sparse matrix with every diagonal entry
    stored (explicit zeros on the multiplier block), as PARDISO's symmetric
    matrix types require; CSR with sorted indices."""
    import scipy.sparse as sp

    U = sp.triu(M, format="coo")
    off = U.row != U.col
    n = M.shape[0]
    d = np.zeros(n)
    np.add.at(d, U.row[~off], U.data[~off])
    rows = np.concatenate([U.row[off], np.arange(n)])
    cols = np.concatenate([U.col[off], np.arange(n)])
    vals = np.concatenate([U.data[off], d])
    out = sp.csr_matrix((vals, (rows, cols)), shape=M.shape)  # keeps the explicit zeros
    out.sort_indices()
    return out


def _kkt_solves(M, rhs, n_u: int, lam_ref: np.ndarray, row: dict, superlu: bool = True,
                symmetric: bool = False) -> None:
    """Factorise and solve the KKT system with SuperLU and (if installed) PARDISO:
    as a real unsymmetric matrix (type 11) and, for a symmetric system (no
    friction), also as a symmetric indefinite one (type -2, Bunch-Kaufman
    pivoting on the upper triangle: about half the factor)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    scale = max(np.abs(lam_ref).max(), 1e-300)
    best = None
    if superlu:
        t0 = time.perf_counter()
        lu = spla.splu(sp.csc_matrix(M))
        x = lu.solve(rhs)
        row["direct_kkt_superlu_s"] = time.perf_counter() - t0
        del lu
        row["kkt_multiplier_diff_superlu"] = float(np.abs(x[n_u:] - lam_ref).max() / scale)
        best = ("superlu", row["direct_kkt_superlu_s"], row["kkt_multiplier_diff_superlu"])
    try:
        import pypardiso  # optional, benchmark only (MKL PARDISO); not a runtime dependency
    except ImportError:
        pypardiso = None
    if pypardiso is not None:
        solver = pypardiso.PyPardisoSolver()  # mtype 11: real unsymmetric
        t0 = time.perf_counter()
        x = solver.solve(sp.csr_matrix(M), rhs)  # analysis + factorisation + solve
        row["direct_kkt_pardiso_s"] = time.perf_counter() - t0
        solver.free_memory(everything=True)
        row["kkt_multiplier_diff_pardiso"] = float(np.abs(x[n_u:] - lam_ref).max() / scale)
        if best is None or row["direct_kkt_pardiso_s"] < best[1]:
            best = ("pardiso", row["direct_kkt_pardiso_s"], row["kkt_multiplier_diff_pardiso"])
        if symmetric:
            solver = pypardiso.PyPardisoSolver(mtype=-2)  # real symmetric indefinite
            t0 = time.perf_counter()
            U = symmetric_upper(M)
            x = solver.solve(U, rhs)
            row["direct_kkt_pardiso_sym_s"] = time.perf_counter() - t0
            solver.free_memory(everything=True)
            row["kkt_multiplier_diff_pardiso_sym"] = float(np.abs(x[n_u:] - lam_ref).max()
                                                           / scale)
            if row["direct_kkt_pardiso_sym_s"] < best[1]:
                best = ("pardiso-sym", row["direct_kkt_pardiso_sym_s"],
                        row["kkt_multiplier_diff_pardiso_sym"])
    if best is not None:
        row["direct_kkt_solver"], row["direct_kkt_s"], row["kkt_multiplier_diff"] = best


def direct_active_set(K, f, fixed, fixed_values, pair, gap_tol: float, symmetric: bool,
                      release_tol: float = 1e-6, max_iter: int = 30) -> dict:
    """A direct active-set solve: the primal-dual rule of ``solve_contact``
    with every set's KKT system (:func:`kkt_system`) factorised by MKL
    PARDISO (symmetric indefinite where ``symmetric``, else real
    unsymmetric), from the same start (the nodes with ``g0 <= gap_tol``).

    What a direct solver does with a cold contact problem, the like-for-like
    of a cold ``solve_contact``.  Returns ``time_s`` (PARDISO's analysis,
    factorisation and solve of every set plus the gaps and the update; the
    KKT assemblies apart in ``assembly_s``, since :func:`kkt_system` slices
    ``K`` anew for every set where a direct code would do it once: leaving
    them out favours the direct solve), ``iterations``,
    the final ``active`` set and its ``force`` (multipliers per slave node),
    or ``None`` without pypardiso.  Raises ``RuntimeError`` if the set does
    not settle in ``max_iter``.
    """
    try:
        import pypardiso
    except ImportError:
        return None

    N = K.shape[0]
    uc = np.zeros(N)
    uc[fixed] = fixed_values
    active = pair.g0 <= gap_tol
    t_solve = t_assembly = 0.0
    # one wrapper for all sets: its construction finds the MKL library (0.1 s), no PARDISO work
    solver = pypardiso.PyPardisoSolver(mtype=-2 if symmetric else 11)
    for it in range(1, max_iter + 1):
        t0 = time.perf_counter()
        M, rhs, free, idx = kkt_system(K, f, fixed, fixed_values, pair, active)
        M = symmetric_upper(M) if symmetric else M
        t1 = time.perf_counter()
        x = solver.solve(M, rhs)  # analysis + factorisation + solve of this set
        solver.free_memory(everything=True)
        u = uc.copy()
        u[free] = x[:free.size]
        lam = np.zeros(pair.slave.size)
        lam[idx] = x[free.size:]
        gaps = np.where(active, 0.0, pair.gaps(u))
        ltol = release_tol * max(np.abs(lam).max(), 1e-300)
        new = (active & (lam > -ltol)) | (~active & (gaps < -gap_tol))
        t_solve += time.perf_counter() - t1
        t_assembly += t1 - t0
        if np.array_equal(new, active):
            return {"time_s": t_solve, "assembly_s": t_assembly, "iterations": it,
                    "active": active, "force": lam}
        active = new
    raise RuntimeError(f"direct active-set solve: no settled set in {max_iter} iterations")


def _direct_active_set_row(row: dict, K, f, fixed, fixed_values, pair, gap_tol: float,
                           symmetric: bool, res) -> None:
    """``direct_active_set_s`` and its checks against ``solve_contact``'s result ``res``."""
    out = direct_active_set(K, f, fixed, fixed_values, pair, gap_tol, symmetric)
    if out is None:
        row["direct_active_set_s"] = None
        return
    lam = res.force[0]
    row["direct_active_set_s"] = out["time_s"]
    row["direct_active_set_assembly_s"] = out["assembly_s"]
    row["direct_active_set_iterations"] = out["iterations"]
    row["direct_active_set_same_set"] = bool(np.array_equal(out["active"], res.active[0]))
    row["direct_active_set_force_diff"] = float(np.abs(out["force"] - lam).max()
                                                / max(np.abs(lam).max(), 1e-300))


def _contact_row_base(case: str, target: float) -> dict:
    row = {"case": case, "target_dofs": int(target)}
    for k in ("direct_kkt_superlu_s", "direct_kkt_pardiso_s", "direct_kkt_s", "direct_kkt_solver",
              "kkt_multiplier_diff", "kkt_multiplier_diff_superlu", "kkt_multiplier_diff_pardiso",
              "kkt_size", "p0_error", "a_error", "speedup_vs_direct"):
        row[k] = None
    if case == "hertz":  # frictionless: its KKT system is symmetric
        row["direct_kkt_pardiso_sym_s"] = row["kkt_multiplier_diff_pardiso_sym"] = None
    return row


def _faster_of_two(run):
    """``run()`` twice: the faster time, both times, the last result.

    Contact and elasticity solves are both timed this way (the wear
    benchmark does the same): single timings on the shared machine scatter
    by 10-30 %.  The suspected first-solve penalty of a fresh process did
    not show in the session-4 pairs (the first run was the faster in 4 of 6
    contact pairs), so the minimum is only a noise filter.
    """
    times, out = [], None
    for _ in range(2):
        out = None  # the first result's memory is free before the second run
        t0 = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - t0)
    return min(times), times, out


def _run_hertz(target: float, direct_max_dofs: int, superlu_max_dofs: int) -> dict:
    from ..contact.lagrange import solve_contact
    from ..fem.boundary import apply_dirichlet
    from ..solvers.amg import amg_solver
    from ..verification import (
        DELTA,
        GAP_TOL,
        hertz_force,
        hertz_problem,
        hertz_resolution,
        solve_problem,
    )

    row = _contact_row_base("hertz", target)
    ha = hertz_resolution(target)
    prob = hertz_problem(ha)
    pair = prob.pair
    row.update({"dofs": prob.dofs, "h_over_a": ha, "assemble_s": prob.setup_s,
                "slave_nodes": int(pair.slave.size)})
    t0 = time.perf_counter()
    out, res, F_bc = solve_problem(prob, linear="amg")
    row["contact_outer_s"] = time.perf_counter() - t0
    # the cold first solve of that iteration once more: the faster of the two, as the
    # elasticity solve (_faster_of_two)
    t0 = time.perf_counter()
    solve_contact(prob.K, np.zeros(prob.dofs), prob.fixed, prob.mesh.p, [pair],
                  fixed_values=prob.fixed_values(hertz_force()), linear="amg", tol=1e-10,
                  gap_tol=GAP_TOL * DELTA)
    cold = time.perf_counter() - t0
    row.update({
        "contact_solve_s": min(out["solve_s"][0], cold),
        "contact_solve_s_pair": [float(out["solve_s"][0]), cold],
        "active_set_iterations": int(out["active_set_iterations_per_solve"][0]),
        "linear_iterations": int(out["linear_iterations_per_solve"][0]),
        "outer_iterations": int(out["outer_iterations"]),
        "outer_solve_s": [float(v) for v in out["solve_s"]],
        "outer_active_set_iterations": [int(v) for v in out["active_set_iterations_per_solve"]],
        "outer_linear_iterations": [int(v) for v in out["linear_iterations_per_solve"]],
        "n_active": int(res.active[0].sum()), "amg_builds_last": int(res.info["amg_builds"]),
        "p0_error": float(out["p0_err"]), "a_error": float(out["a_err"]),
        "l2_error": float(out["l2_err"]), "gap_tol": GAP_TOL * DELTA,
    })
    # the direct KKT solve's like-for-like, as for the brake: one solve at the converged
    # set and the last far field from nothing (its own hierarchy, CG from zero)
    t0 = time.perf_counter()
    fixed_set = solve_contact(prob.K, np.zeros(prob.dofs), prob.fixed, prob.mesh.p, [pair],
                              fixed_values=prob.fixed_values(F_bc), linear="amg", tol=1e-10,
                              gap_tol=GAP_TOL * DELTA, initial_active=res.active)
    row["fixed_set_solve_s"] = time.perf_counter() - t0
    row["fixed_set_linear_iterations"] = int(fixed_set.info["linear_iterations"])
    row["fixed_set_active_set_iterations"] = int(fixed_set.info["active_set_iterations"])
    row["fixed_set_diff"] = float(np.abs(fixed_set.u - res.u).max() / np.abs(res.u).max())
    del fixed_set
    # the same stiffness with the final contact nodes held along the normal (z)
    act = res.active[0]
    s = pair.slave[act]
    zdofs = 3 * s + 2
    fixed = np.concatenate([prob.fixed, zdofs])
    vals = np.concatenate([prob.fixed_values(F_bc), pair.g0[act] / -pair.normal[2, act]])
    t0 = time.perf_counter()
    Kd, fd = apply_dirichlet(prob.K.tobsr(blocksize=(3, 3)), np.zeros(prob.dofs), fixed, vals)
    row["dirichlet_s"] = time.perf_counter() - t0

    def elasticity():
        solver = amg_solver(Kd, coords=prob.mesh.p, fixed=fixed, tol=1e-10)
        return solver, solver.solve(fd)

    row["elasticity_solve_s"], row["elasticity_solve_s_pair"], (solver, u) = \
        _faster_of_two(elasticity)
    row["elasticity_iterations"] = int(solver.info.iterations)
    row["elasticity_kind"] = ("AMG setup + CG (tol 1e-10) of the same K, final contact nodes "
                              "held along z, far field as in the last contact solve")
    row["elasticity_vs_contact_diff"] = float(np.abs(u - res.u).max() / np.abs(res.u).max())
    del solver, Kd
    row["peak_rss_mb"] = _peak_rss_mb()
    if prob.dofs <= direct_max_dofs:
        M, rhs, free, idx = kkt_system(prob.K, np.zeros(prob.dofs), prob.fixed,
                                       prob.fixed_values(F_bc), pair, act)
        row["kkt_size"] = int(M.shape[0])
        _kkt_solves(M, rhs, free.size, res.force[0][idx], row,
                    superlu=prob.dofs <= superlu_max_dofs, symmetric=True)
        del M
        # the cold first solve's problem (far field of Hertz's F(delta)), solved directly
        vals0 = prob.fixed_values(hertz_force())
        cold = solve_contact(prob.K, np.zeros(prob.dofs), prob.fixed, prob.mesh.p, [pair],
                             fixed_values=vals0, linear="amg", tol=1e-10,
                             gap_tol=GAP_TOL * DELTA)
        _direct_active_set_row(row, prob.K, np.zeros(prob.dofs), prob.fixed, vals0, pair,
                               GAP_TOL * DELTA, True, cold)
    return row


def _run_brake(target: float, direct_max_dofs: int, superlu_max_dofs: int) -> dict:
    from ..contact.lagrange import solve_contact

    row = _contact_row_base("brake", target)
    t0 = time.perf_counter()
    size, model = brake_resolution(target)
    row.update({"dofs": int(model.dofs), "size_m": size, "mesh_s": time.perf_counter() - t0,
                "mu": BRAKE_MU, "line_pressure_pa": BRAKE_PRESSURE})
    # exactly BrakeModel.solve_contact's steps, kept apart to reach K, the pair and the result
    t0 = time.perf_counter()
    K, P, retained, col = model._reduced(tie_interface=False)
    f = model.loads(BRAKE_PRESSURE)
    fixed_r = model._reduced_fixed(col)
    pair = model.contact_pair(BRAKE_MU, "segment")
    pair.slave = col[pair.slave]
    if pair.coupling is not None:
        pair.coupling = pair.coupling[:, retained].tocsr()
    Kr = (P.T @ K @ P).tocsr()
    fr = P.T @ f
    coords = model.coordinates()[:, retained]
    row["assemble_s"] = time.perf_counter() - t0
    row["slave_nodes"] = int(pair.slave.size)
    row["contact_solve_s"], row["contact_solve_s_pair"], res = _faster_of_two(
        lambda: solve_contact(Kr, fr, fixed_r, coords, [pair], tol=BRAKE_TOL, linear="amg"))
    row.update({"active_set_iterations": int(res.info["active_set_iterations"]),
                "linear_iterations": int(res.info["linear_iterations"]),
                "amg_builds": int(res.info["amg_builds"]),
                "amg_refreshes": int(res.info.get("amg_refreshes", 0)),
                "active_counts": [int(v) for v in res.info["active_counts"]],
                "n_active": int(res.active[0].sum()),
                "normal_force_n": float(res.info["normal_force"][0])})
    # the direct KKT solve's like-for-like: one eliminated AMG solve at the converged
    # set from nothing (its own hierarchy built at that set, FGMRES from zero, the
    # set confirmed once) -- the issue's "98k block with a fixed contact set"
    t0 = time.perf_counter()
    fixed_set = solve_contact(Kr, fr, fixed_r, coords, [pair], tol=BRAKE_TOL, linear="amg",
                              initial_active=res.active)
    row["fixed_set_solve_s"] = time.perf_counter() - t0
    row["fixed_set_linear_iterations"] = int(fixed_set.info["linear_iterations"])
    del fixed_set
    # a wear step: the hierarchy built once (contact_preconditioner, timed apart), the
    # solve started from the converged active set of the step before
    from ..contact.lagrange import contact_preconditioner

    t0 = time.perf_counter()
    base = contact_preconditioner(Kr, fixed_r, coords, [pair], tol=BRAKE_TOL)
    row["contact_hierarchy_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    step = solve_contact(Kr, fr, fixed_r, coords, [pair], tol=BRAKE_TOL, linear="amg",
                         solver=base, initial_active=res.active)
    row["contact_step_s"] = time.perf_counter() - t0
    row["contact_step_linear_iterations"] = int(step.info["linear_iterations"])
    row["contact_step_active_set_iterations"] = int(step.info["active_set_iterations"])
    row["contact_step_diff"] = float(np.abs(step.u - res.u).max() / np.abs(res.u).max())
    del base, step
    pair_s = []
    for _ in range(2):  # as _faster_of_two, on the solve's own setup + CG time
        tied = None
        tied = model.solve_tied(BRAKE_PRESSURE, tol=BRAKE_TOL)
        pair_s.append(float(tied.info["amg_setup_s"] + tied.info["solve_s"]))
    row["elasticity_solve_s"], row["elasticity_solve_s_pair"] = min(pair_s), pair_s
    row["elasticity_iterations"] = int(tied.info["iterations"])
    row["dirichlet_s"] = None
    row["elasticity_kind"] = ("BrakeModel.solve_tied (pad tied to rotor), AMG setup + CG "
                              "(tol 1e-9), its assembly excluded")
    del tied
    row["peak_rss_mb"] = _peak_rss_mb()
    if model.dofs <= direct_max_dofs:
        M, rhs, free, idx = kkt_system(Kr, fr, fixed_r, 0.0, pair, res.active[0])
        row["kkt_size"] = int(M.shape[0])
        _kkt_solves(M, rhs, free.size, res.force[0][idx], row,
                    superlu=model.dofs <= superlu_max_dofs)
        del M
        size = float(np.linalg.norm(coords.max(axis=1) - coords.min(axis=1)))
        _direct_active_set_row(row, Kr, fr, fixed_r, 0.0, pair, 1e-10 * size, False, res)
    return row


def run_contact_case(case: str, target_dofs: float, direct_max_dofs: int = CONTACT_DIRECT_MAX,
                     superlu_max_dofs: int | None = None) -> dict:
    """Build and solve one contact case (``"hertz"`` or ``"brake"``) in this process."""
    superlu_max_dofs = direct_max_dofs if superlu_max_dofs is None else superlu_max_dofs
    if case == "hertz":
        row = _run_hertz(target_dofs, direct_max_dofs, superlu_max_dofs)
    elif case == "brake":
        row = _run_brake(target_dofs, direct_max_dofs, superlu_max_dofs)
    else:
        raise ValueError(f"case = {case!r}; allowed: {', '.join(CONTACT_CASES)}")
    _ratios(row)
    return row


def _ratios(row: dict) -> None:
    """``ratio`` and the speed-ups against the direct KKT solve, from a row's times."""
    row["ratio"] = row["contact_solve_s"] / row["elasticity_solve_s"]
    direct = row.get("direct_kkt_s")
    for key, t in (("speedup_vs_direct", "contact_solve_s"),
                   ("speedup_vs_direct_fixed_set", "fixed_set_solve_s"),
                   ("speedup_vs_direct_step", "contact_step_s")):
        if t in row or key == "speedup_vs_direct":
            row[key] = None if direct is None or row.get(t) is None else direct / row[t]
    if "direct_active_set_s" in row:  # the cold problem solved directly, set by set
        d = row["direct_active_set_s"]
        row["speedup_vs_direct_active_set"] = None if d is None else d / row["contact_solve_s"]


def _run_contact_child(case: str, target: float, direct_max_dofs: int,
                       superlu_max_dofs: int | None) -> dict:
    cmd = [sys.executable, "-m", "brakewear.bench", "--_child",
           json.dumps({"bench": "contact", "case": case, "target": float(target),
                       "direct_max_dofs": int(direct_max_dofs),
                       "superlu_max_dofs": None if superlu_max_dofs is None
                       else int(superlu_max_dofs)})]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        raise RuntimeError(f"contact benchmark child ({case}, {target:.0f} DOFs) failed "
                           f"(exit {proc.returncode}):\n{proc.stderr.strip()[-2000:]}")
    return json.loads(lines[-1])


def _median_contact_row(runs: list[dict]) -> dict:
    row = dict(runs[0])
    for k in _CONTACT_TIME_KEYS + ("peak_rss_mb",):
        vals = [r[k] for r in runs if r.get(k) is not None]
        if vals:
            row[k] = float(statistics.median(vals))
    _ratios(row)
    row["repeats"] = len(runs)
    if len(runs) > 1:
        row["contact_solve_s_runs"] = [r["contact_solve_s"] for r in runs]
        row["elasticity_solve_s_runs"] = [r["elasticity_solve_s"] for r in runs]
        row["ratio_runs"] = [r["ratio"] for r in runs]
    return row


def bench_contact(sizes: Sequence[float] = CONTACT_SIZES, cases: Sequence[str] = CONTACT_CASES,
                  direct_max_dofs: float = CONTACT_DIRECT_MAX, repeats: int = 1,
                  superlu_max_dofs: float | None = None, progress=None) -> list[dict]:
    """Run the contact benchmark: one dict per case and size, each in fresh processes
    (medians over ``repeats``).  A case that fails gives a row with ``error``."""
    for case in cases:
        if case not in CONTACT_CASES:
            raise ValueError(f"case = {case!r}; allowed: {', '.join(CONTACT_CASES)}")
    rows = []
    for case in cases:
        for target in sizes:
            runs = []
            try:
                for rep in range(max(1, int(repeats))):
                    logger.info("bench contact: %s, %.0f DOFs, run %d of %d", case, target,
                                rep + 1, repeats)
                    runs.append(_run_contact_child(case, target, int(direct_max_dofs),
                                                   None if superlu_max_dofs is None
                                                   else int(superlu_max_dofs)))
                row = _median_contact_row(runs)
            except RuntimeError as exc:
                logger.warning("bench contact: %s at %.0f DOFs failed: %s", case, target, exc)
                row = {"case": case, "target_dofs": int(target), "error": str(exc)[-500:]}
            rows.append(row)
            if progress is not None:
                progress(row)
    return rows


def format_contact_table(rows: Sequence[dict]) -> str:
    """The contact rows as a readable text table."""
    head = (f"{'case':<6} {'dofs':>8} {'contact s':>9} {'elast s':>8} {'ratio':>6} {'AS its':>6} "
            f"{'lin its':>7} {'SuperLU s':>9} {'PARDISO s':>9} {'speed-up':>8} {'lam diff':>8} "
            f"{'p0 err':>8} {'a err':>8}")
    out = [head, "-" * len(head)]
    for r in rows:
        if "error" in r:
            out.append(f"{r['case']:<6} {r['target_dofs']:>8d} failed: {r['error'][-200:]}")
            continue
        out.append(f"{r['case']:<6} {r['dofs']:>8d} {r['contact_solve_s']:>9.2f} "
                   f"{r['elasticity_solve_s']:>8.2f} {r['ratio']:>6.2f} "
                   f"{r['active_set_iterations']:>6d} {r['linear_iterations']:>7d} "
                   f"{_fmt(r.get('direct_kkt_superlu_s'), '9.2f'):>9} "
                   f"{_fmt(r.get('direct_kkt_pardiso_s'), '9.2f'):>9} "
                   f"{_fmt(r.get('speedup_vs_direct'), '8.1f'):>8} "
                   f"{_fmt(r.get('kkt_multiplier_diff'), '8.1e'):>8} "
                   f"{_fmt(r.get('p0_error'), '+8.3f'):>8} {_fmt(r.get('a_error'), '+8.3f'):>8}")
    def summary(key, title, item):  # one line over the rows that have ``key``
        have = [r for r in rows if r.get(key) is not None]
        if have:
            out.append(title + ": " + "; ".join(
                f"{r['case']} {r['dofs']} DOFs: " + item(r) for r in have))

    summary("contact_step_s", "wear step (shared hierarchy, from the converged set)",
            lambda r: f"hierarchy {r['contact_hierarchy_s']:.2f} s once, step "
                      f"{r['contact_step_s']:.2f} s ({r['contact_step_linear_iterations']} its)")
    summary("fixed_set_solve_s", "one solve at the converged set, own hierarchy (the direct "
            "solve's like-for-like)",
            lambda r: f"{r['fixed_set_solve_s']:.2f} s ({r['fixed_set_linear_iterations']} its)"
                      + (f", direct / this {r['speedup_vs_direct_fixed_set']:.1f}"
                         if r.get("speedup_vs_direct_fixed_set") is not None else ""))
    summary("direct_active_set_s", "the cold problem solved directly (PARDISO on the KKT "
            "system of every active set)",
            lambda r: f"{r['direct_active_set_s']:.2f} s ({r['direct_active_set_iterations']} "
                      f"sets), direct / contact {r['speedup_vs_direct_active_set']:.1f}")
    out.append("ratio = contact / elasticity solve; speed-up = best direct KKT / contact solve; "
               "lam diff = max|lam_kkt - lam| / max|lam|")
    return "\n".join(out)


WEAR_SIZES = (3e4, 1e5)


def run_wear_case(target_dofs: float, steps: int = 200, update: str = "gap",
                  duration: float = 3600.0, size: float | None = None) -> dict:
    """Time a two-surface running-in of the default brake (elastic rotor).

    1 MPa line pressure, 55 rad/s, ``mu = 0.4``, the pad's and the rotor's
    Archard coefficients from their materials, the implicit scheme with
    ``steps`` fixed steps over ``duration`` s (so the step count is exact).

    Returns a dict: ``dofs``, ``steps``, ``contact_solves``, ``total_s`` (the
    interface's assembly plus every step), ``per_step_s = total_s / steps``,
    the shares of ``total_s`` spent in contact solves (``contact_share``: every
    solve of the loop, including its first one before step 1, which the first
    :class:`~brakewear.wear.WearStep` counts; ``step_solves_s`` is the
    records' own sum), in
    assembling the contact system (``assembly_share``: the first build and,
    in geometry mode, every rebuild) and in moving the worn meshes with their
    partial stiffness update (``motion_share``, 0 in gap mode);
    ``contact_solve_s``: one plain (rigid, Lagrange) contact solve of the same
    model from the initial gaps, timed in the same process before the run,
    and ``step_over_contact = per_step_s / contact_solve_s`` (the faster of
    two solves: the first pays for first-call set-up).  The ``*_cpu_s`` keys
    are the same in process CPU time (steadier on a shared machine).
    """
    from ..interfaces.fe import FEInterface
    from ..laws import WearLaw
    from ..materials import MATERIALS
    from ..model import BrakeModel
    from ..motion import BrakeMotion
    from ..wear import Numerics, wear_history

    if update not in ("gap", "geometry"):
        raise ValueError(f"update = {update!r} is not allowed; allowed: 'gap', 'geometry'")
    if int(steps) != steps or steps < 1:
        raise ValueError(f"steps = {steps!r} is not allowed; need a whole number >= 1")
    t0 = time.perf_counter()
    if size is None:
        size, model = brake_resolution(target_dofs)
    else:
        model = BrakeModel(size=size, rotor="elastic")
    model_s = time.perf_counter() - t0
    g = model.geometry
    pad_law = WearLaw(g.pad.friction_material.wear_k or MATERIALS["pad_resin"].wear_k)
    rotor_law = WearLaw(g.rotor.material.wear_k or MATERIALS["grey_cast_iron"].wear_k)
    spent = {"assembly": 0.0, "motion": 0.0, "contact": 0.0}
    originals = {}

    def timed(cls, name, key):
        fn = getattr(cls, name)
        originals[(cls, name)] = fn

        def wrapper(*a, **kw):
            t = time.perf_counter()
            try:
                return fn(*a, **kw)
            finally:
                spent[key] += time.perf_counter() - t
        setattr(cls, name, wrapper)

    try:
        timed(FEInterface, "rebuild", "assembly")
        timed(FEInterface, "solve", "contact")   # also the loop's first solve (no record)
        timed(BrakeMotion, "__init__", "motion")
        timed(BrakeMotion, "apply", "motion")
        t0 = time.perf_counter()
        itf = FEInterface(model, 1e6, 0.4)
        build_s = time.perf_counter() - t0
        # the plain solve twice: the first also pays for first-call set-up
        walls, cpus = [], []
        for _ in range(2):
            t1, c1 = time.perf_counter(), time.process_time()
            itf.solve(np.zeros(itf.area.size), None)
            walls.append(time.perf_counter() - t1)
            cpus.append(time.process_time() - c1)
        contact_solve_s, contact_solve_cpu = min(walls), min(cpus)
        spent["contact"] = 0.0
        if update == "geometry":     # the loop builds its own interface (timed as assembly)
            spent["assembly"] = 0.0
        t2, c2 = time.perf_counter(), time.process_time()
        record_s, solves, n = 0.0, 0, 0
        for s in wear_history(model, 1e6, 55.0, duration, pad_law, rotor_law, 0.4,
                              interface=itf if update == "gap" else None,
                              numerics=Numerics(steps=int(steps), scheme="implicit",
                                                update=update)):
            record_s += s.solve_s
            solves += s.contact_solves
            n += 1
        loop_s = time.perf_counter() - t2
        loop_cpu = time.process_time() - c2
    finally:
        for (cls, name), fn in originals.items():
            setattr(cls, name, fn)
    contact_s = spent["contact"]
    total_s = loop_s + (build_s if update == "gap" else 0.0)
    per_step = total_s / n
    return {"bench": "wear", "target_dofs": float(target_dofs), "size_m": float(size),
            "dofs": int(model.dofs), "update": update, "scheme": "implicit",
            "steps": int(n), "contact_solves": int(solves), "duration_s": float(duration),
            "model_s": model_s, "total_s": total_s, "per_step_s": per_step,
            "contact_s": contact_s, "step_solves_s": record_s, "assembly_s": spent["assembly"],
            "motion_s": spent["motion"], "contact_share": contact_s / total_s,
            "assembly_share": spent["assembly"] / total_s,
            "motion_share": spent["motion"] / total_s,
            "contact_solve_s": contact_solve_s, "step_over_contact": per_step / contact_solve_s,
            "per_step_cpu_s": loop_cpu / n, "contact_solve_cpu_s": contact_solve_cpu,
            "step_over_contact_cpu": loop_cpu / n / contact_solve_cpu,
            "peak_rss_mb": _peak_rss_mb(), "cpus": os.cpu_count()}


def bench_wear(sizes: Sequence[float] = WEAR_SIZES, steps: int = 200, update: str = "gap",
               duration: float = 3600.0, progress=None) -> list[dict]:
    """:func:`run_wear_case` at each target DOF count (in this process); one dict per size."""
    rows = []
    for target in sizes:
        rows.append(run_wear_case(target, steps, update, duration))
        if progress is not None:
            progress(rows[-1])
    return rows


def format_wear_table(rows: Sequence[dict]) -> str:
    out = [f"{'dofs':>8} {'update':>8} {'steps':>5} {'total s':>8} {'s/step':>7} "
           f"{'contact':>7} {'assembly':>8} {'motion':>6} {'solve s':>7} {'step/solve':>10}"]
    for r in rows:
        out.append(f"{r['dofs']:>8} {r['update']:>8} {r['steps']:>5} {r['total_s']:>8.1f} "
                   f"{r['per_step_s']:>7.2f} {r['contact_share']:>7.2f} "
                   f"{r['assembly_share']:>8.2f} {r['motion_share']:>6.2f} "
                   f"{r['contact_solve_s']:>7.2f} {r['step_over_contact']:>10.2f}")
    out.append("shares of total_s; solve s = one plain contact solve of the same model; "
               "step/solve = per-step time / that solve")
    return "\n".join(out)


def _run_wear_bench(args: argparse.Namespace) -> int:
    if not args.json:
        print(f"brakewear bench wear: {os.cpu_count()} CPUs, {args.steps} implicit steps, "
              f"update {args.update}, sizes {' '.join(f'{s:.0f}' for s in args.sizes)}",
              flush=True)

    def progress(row):
        print(json.dumps(row) if args.json else
              f"  {row['dofs']} DOFs: {row['per_step_s']:.2f} s/step, "
              f"{row['step_over_contact']:.2f} x a contact solve", flush=True)

    rows = bench_wear(args.sizes, args.steps, args.update, args.duration, progress)
    if not args.json:
        print(format_wear_table(rows))
    return 0


def _add_wear_parser(subparsers) -> None:
    w = subparsers.add_parser("wear", help="wear step cost against one contact solve",
                              description="Two-surface running-in of the default brake "
                                          "(implicit scheme, fixed steps): time per step and "
                                          "its shares, against one plain contact solve.")
    w.add_argument("--json", action="store_true", help="one JSON object per size and line")
    w.add_argument("--sizes", type=float, nargs="+", default=list(WEAR_SIZES), metavar="DOFS",
                   help="target DOF counts (default: 3e4 1e5)")
    w.add_argument("--steps", type=int, default=200, help="fixed wear steps (default 200)")
    w.add_argument("--update", choices=("gap", "geometry"), default="gap",
                   help="gap offset (default) or geometry update")
    w.add_argument("--duration", type=float, default=3600.0,
                   help="simulated drag, s (default 3600)")
    w.set_defaults(bench="wear", func=run_bench)


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
    ``elasticity [--json] [--sizes ...] [--direct-max N] [--repeats N]`` and
    ``contact [--json] [--sizes ...] [--cases hertz brake] [--direct-max N] [--repeats N]``.

    ``brakewear bench elasticity|contact`` is then run by :func:`run_bench` (also set
    as the ``func`` default of the parsed arguments).
    """
    e = subparsers.add_parser("elasticity", help="P1 elasticity: assembly, AMG setup and solve, memory",
                              description="P1 elasticity benchmark: the default rotor ring half, "
                                          "clamped inside, pad pressure; each size in a fresh process.")
    _add_elasticity_args(e)
    e.set_defaults(func=run_bench)
    c = subparsers.add_parser("contact", help="contact solve against one elasticity solve and "
                                              "direct KKT solvers",
                              description="Contact benchmark: Hertz (rigid sphere on a quarter "
                                          "block) and the default brake (mu = 0.4, elastic "
                                          "rotor); each case and size in a fresh process.")
    c.add_argument("--json", action="store_true",
                   help="one JSON object per case, size and line instead of a table")
    c.add_argument("--sizes", type=float, nargs="+", default=list(CONTACT_SIZES), metavar="DOFS",
                   help="target DOF counts (default: 5e4 1.5e5 5e5)")
    c.add_argument("--cases", nargs="+", default=list(CONTACT_CASES), choices=CONTACT_CASES,
                   help="cases to run (default: hertz brake)")
    c.add_argument("--direct-max", type=float, default=CONTACT_DIRECT_MAX, dest="direct_max",
                   metavar="DOFS", help="largest model whose KKT system is also factorised "
                                        "(default 200000: the 150k-class sizes)")
    c.add_argument("--superlu-max", type=float, default=None, dest="superlu_max", metavar="DOFS",
                   help="largest model for SuperLU on the KKT system (default: --direct-max)")
    c.add_argument("--repeats", type=int, default=1,
                   help="fresh processes per case and size; timings are medians (default 1)")
    c.set_defaults(bench="contact", func=run_bench)
    _add_wear_parser(subparsers)


def run_bench(args: argparse.Namespace) -> int:
    """Run the benchmark chosen by ``args`` and print a table or JSON lines; exit code."""
    which = getattr(args, "bench", "elasticity")
    if which == "contact":
        return _run_contact_bench(args)
    if which == "wear":
        return _run_wear_bench(args)
    if which != "elasticity":
        print(f"unknown benchmark {args.bench!r}; available: elasticity, contact, wear",
              file=sys.stderr)
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


def _run_contact_bench(args: argparse.Namespace) -> int:
    if not args.json:
        print(f"brakewear bench contact: {os.cpu_count()} CPUs, Python {platform.python_version()}, "
              f"cases {' '.join(args.cases)}, sizes {' '.join(f'{s:.0f}' for s in args.sizes)}",
              flush=True)

    def progress(row):
        if args.json:
            print(json.dumps(row), flush=True)
        elif "error" in row:
            print(f"  {row['case']} {row['target_dofs']}: failed", flush=True)
        else:
            print(f"  {row['case']} {row['dofs']} DOFs: contact {row['contact_solve_s']:.2f} s, "
                  f"ratio {row['ratio']:.2f}", flush=True)

    rows = bench_contact(args.sizes, args.cases, args.direct_max, args.repeats,
                         superlu_max_dofs=args.superlu_max, progress=progress)
    if not args.json:
        print(format_contact_table(rows))
    return 1 if any("error" in r for r in rows) else 0


def _contact_child(opts: dict) -> int:
    if opts.get("warmup", True):
        # imports and first calls on a tiny model, outside the timings
        if opts["case"] == "hertz":
            run_contact_case("hertz", 3000, 0)
        else:
            run_contact_case("brake", 8000, 0)
    row = run_contact_case(opts["case"], opts["target"], opts["direct_max_dofs"],
                           opts.get("superlu_max_dofs"))
    print(json.dumps(row), flush=True)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["--_child"]:
        opts = json.loads(argv[1])
        if opts.get("bench") == "contact":
            return _contact_child(opts)
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
