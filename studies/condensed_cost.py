"""What the condensed interface costs and saves, against FE contact, by mesh size.

For the default brake (elastic rotor) at each target DOF count: the two-surface
running-in of ``brakewear bench wear`` (1 MPa, 55 rad/s, mu 0.4, ``steps``
fixed implicit steps over an hour) on the FE interface and on the condensed
one, one plain FE contact solve, the condensation (its factorisation and
column solves, its memory), and a sweep of ``pressures`` line pressures run
on the condensed interface end to end (0.5-1.5 MPa; the one condensation included) against
the same number of FE running-ins (the FE sweep is timed as that many times
the FE running-in measured here: each is one such run at another load).  The
agreement of the two interfaces' final pad wear and pressure is reported
beside the times.

Run ``python studies/condensed_cost.py [--sizes 1e4 3e4 1e5] [--steps 200] [--out docs]``;
writes ``data/condensed_cost.json`` and ``figures/condensed_cost.png``.

``--amg-columns N`` times the alternative to the condensation's sparse LU
instead: ``N`` of its columns (contact nodes spread over the friction face),
each by CG preconditioned with the wear loop's AMG hierarchy
(:func:`brakewear.contact.compliant_preconditioner`) built on the same
supported stiffness, against the LU condensation of the same model (its
seconds per column, the factorisations included); the AMG columns are checked
against the LU's.  Writes ``data/condensed_amg.json``.
"""
from __future__ import annotations

import argparse
import json
import logging
import time
from pathlib import Path

import numpy as np

from brakewear import CondensedInterface, FEInterface, Numerics, WearLaw, wear_history
from brakewear.bench.contact import brake_resolution
from brakewear.materials import MATERIALS
from brakewear.wear import Run

logger = logging.getLogger("condensed_cost")


def _running_in(model, itf, steps: int, line_pressure: float = 1e6):
    g = model.geometry
    pad = WearLaw(g.pad.friction_material.wear_k or MATERIALS["pad_resin"].wear_k)
    rotor = WearLaw(g.rotor.material.wear_k or MATERIALS["grey_cast_iron"].wear_k)
    t0 = time.perf_counter()
    last, times = None, []
    for last in wear_history(  # noqa: B007  (the last step)
        Run(
            model,
            line_pressure,
            55.0,
            3600.0,
            pad,
            rotor,
            0.4,
            interface=itf,
            numerics=Numerics(steps=steps, scheme="implicit"),
        )
    ):
        times.append(time.perf_counter() - t0 - sum(times))
    _running_in.step_times = np.array(times)
    return last, time.perf_counter() - t0


def _plain_solves(fe, clock) -> list:
    """The times (``clock``) of two plain contact solves: the first pays for
    first-call set-up."""
    out = []
    for _ in range(2):
        t0 = clock()
        fe.solve(np.zeros(fe.area.size), None)
        out.append(clock() - t0)
    return out


def run_size(target: float, steps: int = 200, pressures: int = 10) -> dict:
    """One mesh size: the figures of the module docstring."""
    size, model = brake_resolution(target)
    fe = FEInterface(model, 1e6, 0.4)
    solve_s = _plain_solves(fe, time.perf_counter)
    t0 = time.perf_counter()
    cd = CondensedInterface(model, 1e6, 0.4, fe=fe, cache=False)
    condense_s = time.perf_counter() - t0
    a, fe_s = _running_in(model, fe, steps)
    b, cd_s = _running_in(model, cd, steps)
    cd_times = _running_in.step_times
    t0 = time.perf_counter()
    sweep = CondensedInterface(model, 1e6, 0.4, fe=fe, cache=False)
    for p in np.linspace(0.5e6, 1.5e6, pressures):
        _running_in(model, sweep.at_line_pressure(p), steps, p)
    sweep_s = time.perf_counter() - t0
    info = cd.cond.info
    return {"target_dofs": target, "size_mm": size * 1e3, "dofs": int(model.dofs),
            "contact_nodes": int(fe.area.size), "steps": steps,
            "fe_contact_solve_s": min(solve_s), "condense_s": condense_s,
            "condense_over_contact": condense_s / min(solve_s),
            "factor_s": sum(b_["factor_s"] for b_ in info["bodies"]),
            "column_solves_s": sum(b_["solve_s"] for b_ in info["bodies"]),
            "factor_entries": sum(b_["factor_nnz"] for b_ in info["bodies"]),
            "compliance_MB": info["bytes"] / 1e6,
            "fe_step_s": fe_s / steps, "condensed_step_s": cd_s / steps,
            # the median step, and the median of the second half (the contact has settled)
            "condensed_step_median_s": float(np.median(cd_times)),
            "condensed_settled_step_median_s": float(np.median(cd_times[steps // 2:])),
            "step_ratio": fe_s / cd_s, "fe_running_in_s": fe_s, "condensed_running_in_s": cd_s,
            "sweep_pressures": pressures, "condensed_sweep_s": sweep_s,
            "fe_sweep_s": pressures * fe_s, "sweep_ratio": pressures * fe_s / sweep_s,
            "pad_wear_rel_diff": float(np.abs(a.pad_wear - b.pad_wear).max()
                                       / np.abs(a.pad_wear).max()),
            "pressure_rel_diff": float(np.abs(a.pressure_end - b.pressure_end).max()
                                       / np.abs(a.pressure_end).max())}


def amg_columns(target: float, columns: int = 8, tol: float = 1e-12) -> dict:
    """One mesh size: seconds per condensation column by the sparse LU (the whole
    condensation over its columns) and by AMG-preconditioned CG to ``tol`` (over the
    columns that reach it; the others are counted, with the residual they stalled at)."""
    from brakewear import ConvergenceError
    from brakewear.contact import compliant_preconditioner, constraint_rows
    from brakewear.interfaces import Supported

    size, model = brake_resolution(target)
    fe = FEInterface(model, 1e6, 0.4)
    cs = fe.cs
    t0 = time.perf_counter()
    cd = CondensedInterface(model, 1e6, 0.4, fe=fe, cache=False)
    condense_s = time.perf_counter() - t0
    Hn, n = cd.cond.Hn, cd.cond.n
    sup = Supported(cs)         # the DOFs the condensation holds
    t0 = time.perf_counter()
    amg = compliant_preconditioner(cs.K, np.flatnonzero(sup.held), cs.coords, tol=tol)
    setup_s = time.perf_counter() - t0
    C = constraint_rows(cs.pair, cs.K.shape[0]).tocsr()
    CT = C.T.tocsc()
    nodes = np.unique(np.linspace(0, n - 1, columns).round().astype(int))
    seconds, iterations, diff, stalled = [], [], [], []
    for i in nodes:
        b = np.where(sup.held, 0.0, CT[:, i].toarray().ravel())
        t0 = time.perf_counter()
        try:
            y = amg.solve(b)
        except ConvergenceError:
            stalled.append(amg.info.relative_residual)
            continue
        seconds.append(time.perf_counter() - t0)
        iterations.append(amg.info.iterations)
        diff.append(float(np.abs(C @ y - Hn[:, i]).max() / np.abs(Hn[:, i]).max()))
    if not seconds:
        raise ConvergenceError(f"no AMG-CG column reached {tol:g}: stalled at {stalled}")
    bodies = cd.cond.info["bodies"]
    return {"target_dofs": target, "size_mm": size * 1e3, "dofs": int(model.dofs),
            "contact_nodes": n, "tol": tol, "lu_condense_s": condense_s,
            "lu_factor_s": sum(b_["factor_s"] for b_ in bodies),
            "lu_column_solves_s": sum(b_["solve_s"] for b_ in bodies),
            "lu_s_per_column": condense_s / n,
            "amg_setup_s": setup_s, "amg_columns": int(nodes.size),
            "amg_s_per_column": float(np.mean(seconds)),
            "amg_s_per_column_range": [min(seconds), max(seconds)],
            "amg_iterations": iterations, "amg_stalled_residuals": stalled,
            "amg_all_columns_s": setup_s + n * float(np.mean(seconds)),
            "amg_column_rel_diff": max(diff)}


def cost_row(model, label: str) -> dict:
    """The condensation (no cache) against one plain FE contact solve of ``model``
    (the faster of two), in process CPU time: a row of the fit
    :func:`brakewear.interfaces.condensation_solves` is made from."""
    fe = FEInterface(model, 1e6, 0.4)
    cpu = _plain_solves(fe, time.process_time)
    c0 = time.process_time()
    cd = CondensedInterface(model, 1e6, 0.4, fe=fe, cache=False)
    cond = time.process_time() - c0
    return {"mesh": label, "dofs": int(model.dofs), "contact_nodes": int(fe.area.size),
            "fe_contact_solve_cpu_s": min(cpu), "condensation_cpu_s": cond,
            "factor_entries": sum(b["factor_nnz"] for b in cd.cond.info["bodies"]),
            "condensation_over_fe_solve": cond / min(cpu)}


def auto_main(sizes=(1e4, 3e4, 1e5), scene: bool = True, out=None) -> list:
    """:func:`cost_row` of the bench's meshes at ``sizes`` and of the default
    scene's mesh; writes ``data/condensed_auto.json`` to ``out``."""
    from brakewear.scene import load_scene

    rows = [cost_row(brake_resolution(t)[1], f"default brake, uniform {t:g} target (bench "
                                             "wear's)") for t in sizes]
    if scene:
        rows.append(cost_row(load_scene("default").build_model(), "the default scene's"))
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / "condensed_auto.json").write_text(json.dumps(
            {"what": "the condensation against one FE contact solve, process CPU time",
             "command": "python studies/condensed_cost.py --auto-fit --out docs",
             "rows": rows}, indent=1) + "\n")
    return rows


def amg_main(sizes=(1e5,), columns: int = 8, out=None) -> list:
    """:func:`amg_columns` at each size; writes ``data/condensed_amg.json`` to ``out``."""
    rows = [amg_columns(target, columns) for target in sizes]
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / "condensed_amg.json").write_text(json.dumps(rows, indent=1))
    return rows


def main(sizes=(1e4, 3e4, 1e5), steps: int = 200, pressures: int = 10, out=None) -> list:
    rows = []
    for target in sizes:
        rows.append(run_size(target, steps, pressures))
        logger.info("%s", rows[-1])
    if out is not None:
        out = Path(out)
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "condensed_cost.json").write_text(json.dumps(rows, indent=1))
        plot(rows, out / "figures" / "condensed_cost.png")
    return rows


def plot(rows: list, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    n = np.array([r["contact_nodes"] for r in rows])
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4))
    ax.loglog(n, [r["condense_s"] for r in rows], "o-", label="condensation")
    ax.loglog(n, [r["fe_contact_solve_s"] for r in rows], "s-", label="one FE contact solve")
    ax.loglog(n, [r["fe_step_s"] for r in rows], "^-", label="FE wear step")
    ax.loglog(n, [r["condensed_step_s"] for r in rows], "v-", label="condensed wear step")
    ax.set_xlabel("contact nodes")
    ax.set_ylabel("s")
    ax.legend(fontsize=8)
    ax.set_title("cost against contact nodes", fontsize=10)
    bx.semilogx(n, [r["condense_over_contact"] for r in rows], "o-",
                label="condensation / FE contact solve")
    bx.semilogx(n, [r["condense_s"] / max(r["fe_step_s"] - r["condensed_step_s"], 1e-9)
                    for r in rows], "^-", label="FE wear steps that pay for it")
    bx.set_xlabel("contact nodes")
    bx.legend(fontsize=8)
    bx.set_title("when condensing pays", fontsize=10)
    for a_, r in zip(ax.get_lines()[0].get_xdata(), rows):
        ax.annotate(f"{r['dofs'] / 1e3:.0f}k DOFs", (a_, r["condense_s"]), fontsize=7,
                    textcoords="offset points", xytext=(4, 4))
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    logging.basicConfig(level=logging.WARNING)
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=float, nargs="+", default=[1e4, 3e4, 1e5])
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--pressures", type=int, default=10)
    ap.add_argument("--out", default="docs")
    ap.add_argument("--amg-columns", type=int, default=0, metavar="N",
                    help="only time N condensation columns by AMG-preconditioned CG against "
                         "the sparse LU, at each of --sizes (writes data/condensed_amg.json)")
    ap.add_argument("--auto-fit", action="store_true",
                    help="only measure the condensation in FE contact solves (CPU time) at "
                         "each of --sizes and on the default scene's mesh (writes "
                         "data/condensed_auto.json, the rows interface 'auto' is fitted to)")
    a = ap.parse_args()
    if a.auto_fit:
        for r in auto_main(a.sizes, out=a.out):
            print(f"{r['mesh']}: {r['dofs']} DOFs, {r['contact_nodes']} contact nodes: "
                  f"condensation {r['condensation_cpu_s']:.1f} s CPU = "
                  f"{r['condensation_over_fe_solve']:.1f} FE contact solves")
    elif a.amg_columns:
        for r in amg_main(a.sizes, a.amg_columns, a.out):
            print(f"{r['dofs']:>7} DOFs {r['contact_nodes']:>5} nodes: per column, sparse LU "
                  f"{r['lu_s_per_column'] * 1e3:.0f} ms ({r['lu_condense_s']:.1f} s for all), "
                  f"AMG-CG {r['amg_s_per_column'] * 1e3:.0f} ms ({len(r['amg_iterations'])} of "
                  f"{r['amg_columns']} columns, {min(r['amg_iterations'])}-"
                  f"{max(r['amg_iterations'])} iterations to {r['tol']:g}, "
                  f"{len(r['amg_stalled_residuals'])} stalled; "
                  f"{r['amg_all_columns_s'] / 60:.1f} min for all, its "
                  f"{r['amg_setup_s']:.1f} s setup included); columns agree to "
                  f"{r['amg_column_rel_diff']:.1e}")
    else:
        for r in main(a.sizes, a.steps, a.pressures, a.out):
            print(f"{r['dofs']:>7} DOFs {r['contact_nodes']:>5} nodes: condense "
                  f"{r['condense_s']:.1f} s ({r['condense_over_contact']:.1f} contact solves, "
                  f"{r['compliance_MB']:.0f} MB); "
                  f"step FE {r['fe_step_s'] * 1e3:.0f} ms, condensed "
                  f"{r['condensed_step_s'] * 1e3:.2f} ms ({r['step_ratio']:.0f}x; median "
                  f"{r['condensed_step_median_s'] * 1e3:.2f} ms, settled "
                  f"{r['condensed_settled_step_median_s'] * 1e3:.2f} ms); sweep "
                  f"{r['sweep_ratio']:.1f}x; pad wear diff {r['pad_wear_rel_diff']:.1e}")
