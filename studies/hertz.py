"""Hertz: a rigid sphere pressed into an elastic half-space, 3D quarter model.

The model (set-up, far-field conditions, mesh, measured errors) lives in
:mod:`brakewear.verification`, so that ``brakewear bench contact`` can use it
from an installed package; its names are re-exported here.  This script
runs the convergence study.

Run ``python studies/hertz.py [--out DIR]``: prints the table and writes
``hertz_convergence.csv``/``.png`` and ``hertz_pressure.png``.
"""
from __future__ import annotations

import argparse
import csv
import logging
from pathlib import Path

import numpy as np

from brakewear.analytic import hertz_sphere_pressure
from brakewear.verification import (A0, DELTA, ES, FINE_XY, FINE_Z, FIT_R, GAP_TOL,  # noqa: F401
                                    GROWTH, L_OVER_A, MATERIAL, R, HertzProblem, axis,
                                    block_mesh, boussinesq, hertz_dofs, hertz_problem,
                                    hertz_resolution, measure, mirrored_tets, solve,
                                    solve_problem, sphere_height)

logger = logging.getLogger(__name__)

def rate(h, e) -> float:
    """Observed rate: slope of log(error) against log(h)."""
    return float(np.polyfit(np.log(h), np.log(np.abs(e)), 1)[0])


CSV_KEYS = ("h_over_a", "dofs", "time_s", "p0_err", "a_err", "delta_err", "l2_err", "F",
            "outer_iterations", "active_set_iterations", "n_active", "linear")


def main(levels=(1 / 2, 1 / 3, 1 / 4, 1 / 6, 1 / 8), out: str | Path | None = None,
         profile_level: int = -1) -> dict:
    """Solve on each ``h/a`` of ``levels``; the rate of the L2 pressure error."""
    rows = [solve(h) for h in levels]
    result = {"rows": rows, "l2_rate": rate(levels, [x["l2_err"] for x in rows]),
              "finest": rows[-1]}
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        with open(out / "hertz_convergence.csv", "w", newline="") as fh:
            wr = csv.writer(fh)
            wr.writerow(CSV_KEYS)
            for x in rows:
                wr.writerow([x[k] for k in CSV_KEYS])
        _plot_convergence(result, out / "hertz_convergence.png")
        _plot_pressure(rows[profile_level], out / "hertz_pressure.png")
    return result


def _plot_convergence(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from brakewear.figures import label_log_axis

    rows = result["rows"]
    h = np.array([x["h_over_a"] for x in rows])
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.loglog(h, [x["l2_err"] for x in rows], "o-",
              label=f"L2 pressure error (rate {result['l2_rate']:.2f})")
    ax.loglog(h, [abs(x["p0_err"]) for x in rows], "s--", label="|peak pressure error|")
    ax.loglog(h, [abs(x["a_err"]) for x in rows], "^--", label="|contact radius error|")
    ax.loglog(h, [abs(x["delta_err"]) for x in rows], "v--", label="|approach error|")
    label_log_axis(ax.xaxis, h)
    ax.set_xlabel("element size at the patch h / a")
    ax.set_ylabel("relative error")
    ax.set_title("Hertz sphere on a flat, 3D quarter model (P1)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _plot_pressure(row: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pr = row["profile"]
    a, p0 = row["a"], row["p0"]
    r = pr["r"]
    near = r < 1.6 * a
    rr = np.linspace(0.0, 1.6 * a, 400)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(rr / a, hertz_sphere_pressure(rr, row["F"], R, ES) / 1e9, "k-",
            label="Hertz (at the computed F)")
    ax.plot(r[near] / a, pr["p"][near] / 1e9, ".", ms=3, alpha=0.6,
            label=f"FE nodal pressure, h/a = {row['h_over_a']:.3g}")
    ax.set_xlabel("r / a")
    ax.set_ylabel("contact pressure (GPa)")
    ax.set_title(f"Hertz pressure: p0 error {100 * row['p0_err']:+.2f} %, "
                 f"a error {100 * row['a_err']:+.2f} %")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--levels", type=float, nargs="+", default=[1 / 2, 1 / 3, 1 / 4, 1 / 6, 1 / 8],
                    help="element sizes h/a at the patch")
    args = ap.parse_args()
    res = main(levels=tuple(args.levels), out=args.out)
    print(f"{'h/a':>7} {'dofs':>8} {'time s':>7} {'p0 err':>9} {'a err':>9} {'delta err':>9} "
          f"{'L2 err':>9} {'outer':>5} {'AS it':>5}")
    for x in res["rows"]:
        print(f"{x['h_over_a']:>7.4f} {x['dofs']:>8} {x['time_s']:>7.1f} {x['p0_err']:>+9.2e} "
              f"{x['a_err']:>+9.2e} {x['delta_err']:>+9.2e} {x['l2_err']:>9.2e} "
              f"{x['outer_iterations']:>5} {x['active_set_iterations']:>5}")
    print(f"L2 pressure error rate: {res['l2_rate']:.2f}")
