"""The contact benchmark (``brakewear bench contact``): Hertz and the default brake, the
contact solve against one elasticity solve and the direct KKT references."""
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

from ..errors import BenchError
from ..static import solve_tied
from .common import fmt, peak_rss_mb
from .kkt import direct_active_set_row, kkt_solves, kkt_system

logger = logging.getLogger(__name__)


__all__ = [
    "CONTACT_SIZES",
    "CONTACT_CASES",
    "CONTACT_SUPERLU_MAX",
    "brake_resolution",
    "run_contact_case",
    "bench_contact",
    "format_contact_table",
]

#: the default sizes (``--sizes 5e4 1.5e5 5e5`` adds the 500k class, about a minute a case)
CONTACT_SIZES = (50e3, 150e3)


CONTACT_CASES = ("hertz", "brake")


#: Largest system whose KKT system is also factorised (PARDISO, when installed).
CONTACT_DIRECT_MAX = 200_000


#: Largest system whose KKT system SuperLU factorises by default: at the 150k class its
#: fill takes minutes (``--superlu-max 2e5`` runs it there too)
CONTACT_SUPERLU_MAX = 60_000


#: Brake case: line pressure (Pa), friction coefficient and contact tolerance.
BRAKE_PRESSURE = 1.0e6


BRAKE_MU = 0.4


BRAKE_TOL = 1e-9


_BRAKE_REF = (0.0025, 81_570)  # default mesh size (m) and its DOF count


_CONTACT_TIME_KEYS = ("assemble_s", "contact_solve_s", "elasticity_solve_s", "dirichlet_s",
                      "direct_kkt_superlu_s", "direct_kkt_pardiso_s", "direct_kkt_s",
                      "contact_outer_s", "contact_hierarchy_s", "contact_step_s",
                      "fixed_set_solve_s", "direct_kkt_pardiso_sym_s", "direct_active_set_s")


def brake_resolution(target_dofs: float) -> tuple[float, object]:
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
    not show in measured pairs (the first run was the faster in 4 of 6
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
    from ..contact.hertz import (
        DELTA,
        GAP_TOL,
        hertz_force,
        hertz_problem,
        hertz_resolution,
        solve_problem,
    )
    from ..contact.lagrange import solve_contact
    from ..fem.boundary import apply_dirichlet
    from ..solvers.amg import amg_solver

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

    def elasticity(K=Kd, f=fd):
        solver = amg_solver(K, coords=prob.mesh.p, fixed=fixed, tol=1e-10)
        return solver, solver.solve(f)

    row["elasticity_solve_s"], row["elasticity_solve_s_pair"], (solver, u) = \
        _faster_of_two(elasticity)
    row["elasticity_iterations"] = int(solver.info.iterations)
    row["elasticity_kind"] = ("AMG setup + CG (tol 1e-10) of the same K, final contact nodes "
                              "held along z, far field as in the last contact solve")
    row["elasticity_vs_contact_diff"] = float(np.abs(u - res.u).max() / np.abs(res.u).max())
    del solver, elasticity, Kd      # the matrix's memory before the next measurement
    row["peak_rss_mb"] = peak_rss_mb()
    if prob.dofs <= direct_max_dofs:
        M, rhs, free, idx = kkt_system(prob.K, np.zeros(prob.dofs), prob.fixed,
                                       prob.fixed_values(F_bc), pair, act)
        row["kkt_size"] = int(M.shape[0])
        kkt_solves(M, rhs, free.size, res.force[0][idx], row,
                    superlu=prob.dofs <= superlu_max_dofs, symmetric=True)
        del M
        # the cold first solve's problem (far field of Hertz's F(delta)), solved directly
        vals0 = prob.fixed_values(hertz_force())
        cold = solve_contact(prob.K, np.zeros(prob.dofs), prob.fixed, prob.mesh.p, [pair],
                             fixed_values=vals0, linear="amg", tol=1e-10,
                             gap_tol=GAP_TOL * DELTA)
        direct_active_set_row(row, prob.K, np.zeros(prob.dofs), prob.fixed, vals0, pair,
                               GAP_TOL * DELTA, True, cold)
    return row


def _run_brake(target: float, direct_max_dofs: int, superlu_max_dofs: int) -> dict:
    from ..contact.lagrange import solve_contact

    row = _contact_row_base("brake", target)
    t0 = time.perf_counter()
    size, model = brake_resolution(target)
    row.update({"dofs": int(model.dofs), "size_m": size, "mesh_s": time.perf_counter() - t0,
                "mu": BRAKE_MU, "line_pressure_pa": BRAKE_PRESSURE})
    # exactly brakewear.static.solve_contact's steps, kept apart to reach K, the pair and the result
    t0 = time.perf_counter()
    cs = model.contact_system(BRAKE_PRESSURE, BRAKE_MU, "segment")
    Kr, fr, fixed_r, coords, pair = cs.K, cs.f, cs.fixed, cs.coords, cs.pair
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
    # set confirmed once) -- a block with a fixed contact set
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
        tied = solve_tied(model, BRAKE_PRESSURE, tol=BRAKE_TOL)
        pair_s.append(float(tied.info["amg_setup_s"] + tied.info["solve_s"]))
    row["elasticity_solve_s"], row["elasticity_solve_s_pair"] = min(pair_s), pair_s
    row["elasticity_iterations"] = int(tied.info["iterations"])
    row["dirichlet_s"] = None
    row["elasticity_kind"] = ("static.solve_tied (pad tied to rotor), AMG setup + CG "
                              "(tol 1e-9), its assembly excluded")
    del tied
    row["peak_rss_mb"] = peak_rss_mb()
    if model.dofs <= direct_max_dofs:
        M, rhs, free, idx = kkt_system(Kr, fr, fixed_r, 0.0, pair, res.active[0])
        row["kkt_size"] = int(M.shape[0])
        kkt_solves(M, rhs, free.size, res.force[0][idx], row,
                    superlu=model.dofs <= superlu_max_dofs)
        del M
        size = float(np.linalg.norm(coords.max(axis=1) - coords.min(axis=1)))
        direct_active_set_row(row, Kr, fr, fixed_r, 0.0, pair, 1e-10 * size, False, res)
    return row


def run_contact_case(case: str, target_dofs: float, direct_max_dofs: int = CONTACT_DIRECT_MAX,
                     superlu_max_dofs: int | None = CONTACT_SUPERLU_MAX) -> dict:
    """Build and solve one contact case (``"hertz"`` or ``"brake"``) in this process;
    SuperLU factorises the KKT system up to ``superlu_max_dofs`` (None: up to
    ``direct_max_dofs``, as PARDISO)."""
    superlu_max_dofs = direct_max_dofs if superlu_max_dofs is None else superlu_max_dofs
    if case == "hertz":
        row = _run_hertz(target_dofs, direct_max_dofs, superlu_max_dofs)
    elif case == "brake":
        row = _run_brake(target_dofs, direct_max_dofs, superlu_max_dofs)
    else:
        raise BenchError(f"case = {case!r}; allowed: {', '.join(CONTACT_CASES)}")
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
                  superlu_max_dofs: float | None = CONTACT_SUPERLU_MAX,
                  progress=None) -> list[dict]:
    """Run the contact benchmark: one dict per case and size, each in fresh processes
    (medians over ``repeats``).  A case that fails gives a row with ``error``."""
    for case in cases:
        if case not in CONTACT_CASES:
            raise BenchError(f"case = {case!r}; allowed: {', '.join(CONTACT_CASES)}")
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
                   f"{fmt(r.get('direct_kkt_superlu_s'), '9.2f'):>9} "
                   f"{fmt(r.get('direct_kkt_pardiso_s'), '9.2f'):>9} "
                   f"{fmt(r.get('speedup_vs_direct'), '8.1f'):>8} "
                   f"{fmt(r.get('kkt_multiplier_diff'), '8.1e'):>8} "
                   f"{fmt(r.get('p0_error'), '+8.3f'):>8} {fmt(r.get('a_error'), '+8.3f'):>8}")
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


