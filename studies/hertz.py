"""Hertz: a rigid sphere pressed into an elastic half-space, 3D quarter model.

The model (set-up, far-field conditions, mesh, measured errors) lives in
:mod:`brakewear.contact.hertz`, so that ``brakewear bench contact`` can use it
from an installed package; its names are re-exported here.  This script
runs the convergence study.

Run ``python studies/hertz.py [--out DIR] [--data DIR] [--levels H/A ...]``:
prints the table and writes ``hertz_convergence.png``, ``hertz_pressure.png``
(to ``--out``, default ``docs/figures``) and ``hertz_convergence.csv``/``.json``
(to ``--data``, default ``docs/data``).
"""
from __future__ import annotations

import argparse
import csv
import json
import logging
from pathlib import Path

import numpy as np

from brakewear.analytic import hertz_sphere_pressure
from brakewear.contact.hertz import (  # noqa: F401
    A0,
    DELTA,
    ES,
    FINE_XY,
    FINE_Z,
    FIT_R,
    GAP_TOL,
    GROWTH,
    L_OVER_A,
    MATERIAL,
    RECOVERY,
    HertzProblem,
    R,
    axis,
    block_mesh,
    boussinesq,
    hertz_dofs,
    hertz_problem,
    hertz_resolution,
    measure,
    mirrored_tets,
    recovered_pressure,
    solve,
    solve_problem,
    sphere_height,
)

logger = logging.getLogger(__name__)

def rate(h, e) -> float:
    """Observed rate: slope of log(error) against log(h)."""
    return float(np.polyfit(np.log(h), np.log(np.abs(e)), 1)[0])


CSV_KEYS = ("h_over_a", "split", "dofs", "time_s", "p0_err", "a_err", "delta_err", "l2_err",
            "l2_inner_err", "p0_nodal_err", "l2_nodal_err", "F", "outer_iterations",
            "active_set_iterations", "n_active", "linear")
LEVELS = (1 / 2, 1 / 3, 1 / 4, 1 / 6, 1 / 8)


def main(levels=LEVELS, out: str | Path | None = None, profile_level: int = -1,
         split: str = "mirrored", data: str | Path | None = None) -> dict:
    """Solve on each ``h/a`` of ``levels`` (quarter model, tetrahedral ``split``);
    the observed rates of the L2 pressure errors.  Figures go to ``out``, the
    numbers (``hertz_convergence.csv``, ``.json``) to ``data`` (default ``out``)."""
    rows = [solve(h, split=split) for h in levels]
    for x in rows:
        x["split"] = split
    result = {"rows": rows, "split": split, "finest": rows[-1]}
    for key in ("l2_err", "l2_inner_err", "l2_nodal_err"):
        result[key.replace("_err", "_rate")] = rate(levels, [x[key] for x in rows])
    if out is not None:
        out = Path(out)
        data = out if data is None else Path(data)
        for d in (out, data):
            d.mkdir(parents=True, exist_ok=True)
        with open(data / "hertz_convergence.csv", "w", newline="") as fh:
            wr = csv.writer(fh)
            wr.writerow(CSV_KEYS)
            for x in rows:
                wr.writerow([x[k] for k in CSV_KEYS])
        summary = {k: v for k, v in result.items() if k.endswith("_rate")}
        summary.update({"split": split, "levels": list(levels), "recovery_width_over_h": RECOVERY,
                        "finest": {k: rows[-1][k] for k in CSV_KEYS}})
        (data / "hertz_convergence.json").write_text(json.dumps(summary, indent=1) + "\n")
        _plot_convergence(result, out / "hertz_convergence.png")
        _plot_pressure(rows[profile_level], out / "hertz_pressure.png")
    return result


def _plot_convergence(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from brakewear.output.figures import label_log_axis

    rows = result["rows"]
    h = np.array([x["h_over_a"] for x in rows])
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.loglog(h, [x["l2_err"] for x in rows], "o-",
              label=f"L2 pressure error, recovered (rate {result['l2_rate']:.2f})")
    ax.loglog(h, [x["l2_inner_err"] for x in rows], "o:",
              label=f"... inside r < a - {RECOVERY:g} h (rate {result['l2_inner_rate']:.2f})")
    ax.loglog(h, [x["l2_nodal_err"] for x in rows], "x:", color="0.5",
              label=f"... nodal force / area (rate {result['l2_nodal_rate']:.2f})")
    ax.loglog(h, [abs(x["p0_err"]) for x in rows], "s--", label="|peak pressure error|")
    ax.loglog(h, [abs(x["a_err"]) for x in rows], "^--", label="|contact radius error|")
    ax.loglog(h, [abs(x["delta_err"]) for x in rows], "v--", label="|approach error|")
    label_log_axis(ax.xaxis, h)
    ax.set_xlabel("element size at the patch h / a")
    ax.set_ylabel("relative error")
    ax.set_title(f"Hertz sphere on a flat, 3D quarter model (P1, {result['split']} split)")
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
    a = row["a"]
    r = pr["r"]
    near = r < 1.6 * a
    rr = np.linspace(0.0, 1.6 * a, 400)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(rr / a, hertz_sphere_pressure(rr, row["F"], R, ES) / 1e9, "k-",
            label="Hertz (at the computed F)")
    ax.plot(r[near] / a, pr["p_nodal"][near] / 1e9, "x", ms=4, color="0.6",
            label=f"nodal force / tributary area, h/a = {row['h_over_a']:.3g}")
    ax.plot(r[near] / a, pr["p"][near] / 1e9, "o", ms=3, mfc="none", color="C0",
            label=f"recovered ({RECOVERY:g} h tent window)")
    ax.set_xlabel("r / a")
    ax.set_ylabel("contact pressure (GPa)")
    ax.set_title(f"Hertz pressure: p0 error {100 * row['p0_err']:+.2f} % "
                 f"(nodal {100 * row['p0_nodal_err']:+.1f} %), a error {100 * row['a_err']:+.2f} %",
                 fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures", help="directory of the figures")
    ap.add_argument("--data", default="docs/data", help="directory of the CSV/JSON numbers")
    ap.add_argument("--levels", type=float, nargs="+", default=list(LEVELS),
                    help="element sizes h/a at the patch")
    ap.add_argument("--split", default="mirrored", choices=("mirrored", "kuhn"),
                    help="tetrahedral split of the grid (default: mirror-symmetric)")
    ap.add_argument("--profile-level", type=int, default=-1,
                    help="index into --levels of the mesh shown in hertz_pressure.png")
    args = ap.parse_args()
    logging.basicConfig(level=logging.INFO)
    res = main(levels=tuple(args.levels), out=args.out, split=args.split,
               profile_level=args.profile_level, data=args.data)
    print(f"{'h/a':>7} {'dofs':>8} {'time s':>7} {'p0 err':>9} {'a err':>9} {'delta err':>9} "
          f"{'L2 err':>9} {'L2 inner':>9} {'p0 nodal':>9} {'L2 nodal':>9} {'outer':>5} "
          f"{'AS it':>5}")
    for x in res["rows"]:
        print(f"{x['h_over_a']:>7.4f} {x['dofs']:>8} {x['time_s']:>7.1f} {x['p0_err']:>+9.2e} "
              f"{x['a_err']:>+9.2e} {x['delta_err']:>+9.2e} {x['l2_err']:>9.2e} "
              f"{x['l2_inner_err']:>9.2e} {x['p0_nodal_err']:>+9.2e} {x['l2_nodal_err']:>9.2e} "
              f"{x['outer_iterations']:>5} {x['active_set_iterations']:>5}")
    print(f"observed L2 rates: recovered {res['l2_rate']:.2f}, inner {res['l2_inner_rate']:.2f}, "
          f"nodal {res['l2_nodal_rate']:.2f}")
