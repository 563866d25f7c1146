"""Hertz with quadratic (P2) against linear (P1) tetrahedra: errors, DOFs and run time.

The model is :mod:`brakewear.contact.hertz`'s (a rigid sphere on the quarter
half-space, Boussinesq far field, mirrored split), solved with P1 and with P2
elements of the same size ``h`` at the patch.  P1's peak pressure is the
tent-window recovery of the nodal forces (its nodal values carry the node-type
pattern of the mirrored split); P2's is the dual multiplier's nodal value,
unsmoothed, which is also what the wear loop reads on either order.

For each order the table gives the first ``h / a`` from which the targets
hold on every finer mesh of the study: peak pressure within ``P0_TARGET``,
contact radius within ``A_TARGET``, approach within ``DELTA_TARGET``.

Run ``python studies/hertz_p2.py [--out DIR] [--data DIR]``: prints the table,
writes ``hertz_p2.png`` (to ``--out``, default ``docs/figures``) and
``hertz_p2.json`` (to ``--data``, default ``docs/data``).  About 8 minutes on
two cores (P2 at h/a = 1/8: 320k DOFs, 5 GB).
"""
from __future__ import annotations

import argparse
import json
import logging
from pathlib import Path

import numpy as np

from brakewear.contact.hertz import solve

logger = logging.getLogger(__name__)

P1_LEVELS = (1 / 2, 1 / 3, 1 / 4, 1 / 6, 1 / 8, 1 / 12)
P2_LEVELS = (1 / 2, 1 / 3, 1 / 4, 1 / 5, 1 / 6, 1 / 8)
P0_TARGET, A_TARGET, DELTA_TARGET = 0.01, 0.02, 0.01
KEYS = ("h_over_a", "order", "dofs", "time_s", "p0_err", "p0_nodal_err", "a_err", "delta_err",
        "l2_err", "l2_inner_err", "n_active", "active_set_iterations", "linear")


def reached(rows: list, key: str, target: float) -> float | None:
    """The largest ``h / a`` from which ``|row[key]| <= target`` on every finer row."""
    rows = sorted(rows, key=lambda r: -r["h_over_a"])
    for i, r in enumerate(rows):
        if all(abs(x[key]) <= target for x in rows[i:]):
            return r["h_over_a"]
    return None


def summary(rows: list) -> dict:
    """Per order: where each target is reached, the L2 rate and the finest row."""
    out = {}
    for order in (1, 2):
        sel = [r for r in rows if r["order"] == order]
        if not sel:
            continue
        h = np.array([r["h_over_a"] for r in sel])
        out[f"P{order}"] = {
            "p0_from": reached(sel, "p0_err", P0_TARGET),
            "a_from": reached(sel, "a_err", A_TARGET),
            "delta_from": reached(sel, "delta_err", DELTA_TARGET),
            "peak_and_radius_from": _both(sel),
            "l2_rate": float(np.polyfit(np.log(h), np.log([r["l2_err"] for r in sel]), 1)[0]),
            "finest": {k: sel[-1][k] for k in KEYS},
        }
    if "P1" in out and "P2" in out:
        for key in ("p0_from", "a_from", "delta_from", "peak_and_radius_from"):
            a, b = out["P1"][key], out["P2"][key]
            out[f"coarser_{key}"] = None if a is None or b is None else b / a
    return out


def _both(rows: list) -> float | None:
    ok = [x for x in (reached(rows, "p0_err", P0_TARGET), reached(rows, "a_err", A_TARGET))]
    return None if None in ok else min(ok)


def main(p1_levels=P1_LEVELS, p2_levels=P2_LEVELS, out: str | Path | None = None,
         data: str | Path | None = None, linear: str = "amg") -> dict:
    """Solve Hertz on every level of both orders (one at a time, the same
    ``linear`` solver for all, so that the times compare); the rows, the
    :func:`summary` and, with ``out``, the figure and the JSON of the numbers."""
    rows = []
    for order, levels in ((1, p1_levels), (2, p2_levels)):
        for h in levels:
            r = solve(h, order=order, linear=linear)
            rows.append({k: r[k] for k in KEYS})
            logger.info("P%d h/a = %.4g: %d DOFs, %.1f s, p0 %+.2e a %+.2e delta %+.2e", order,
                        h, r["dofs"], r["time_s"], r["p0_err"], r["a_err"], r["delta_err"])
    result = {"rows": rows, "summary": summary(rows),
              "targets": {"p0": P0_TARGET, "a": A_TARGET, "delta": DELTA_TARGET}}
    if out is not None:
        out = Path(out)
        data = out if data is None else Path(data)
        for d in (out, data):
            d.mkdir(parents=True, exist_ok=True)
        (data / "hertz_p2.json").write_text(json.dumps(result, indent=1) + "\n")
        _figure(rows, out / "hertz_p2.png")
    return result


def _figure(rows: list, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.5))
    marks = {"p0_err": ("o", "peak pressure"), "a_err": ("s", "contact radius"),
             "delta_err": ("^", "approach")}
    for order, style in ((1, "--"), (2, "-")):
        sel = [r for r in rows if r["order"] == order]
        for key, (m, label) in marks.items():
            e = [max(abs(r[key]), 1e-6) for r in sel]
            for axis, x in ((ax, [r["h_over_a"] for r in sel]), (bx, [r["dofs"] for r in sel])):
                axis.loglog(x, e, style + m, color=f"C{order - 1}", label=f"P{order} {label}")
        nodal = [max(abs(r["p0_nodal_err"]), 1e-6) for r in sel] if order == 1 else None
        if nodal:
            ax.loglog([r["h_over_a"] for r in sel], nodal, ":x", color="0.5",
                      label="P1 peak pressure, nodal (unrecovered)")
    for axis in (ax, bx):
        axis.axhline(P0_TARGET, color="k", lw=0.6)
        axis.axhline(A_TARGET, color="k", lw=0.6, ls=":")
        axis.grid(True, which="both", alpha=0.3)
        axis.set_ylabel("|relative error|")
    from brakewear.output.figures import label_log_axis

    label_log_axis(ax.xaxis, sorted({r["h_over_a"] for r in rows}))
    ax.set_xlabel("element size at the patch h / a")
    ax.invert_xaxis()
    bx.set_xlabel("DOFs (quarter model)")
    ax.set_title("Hertz sphere, P1 (dashed) and P2 (solid): errors against h\n"
                 "(lines: the 1 % and 2 % targets)", fontsize=10)
    bx.set_title("... against DOFs", fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _table(result: dict) -> str:
    lines = [f"{'order':>5} {'h/a':>7} {'dofs':>7} {'time s':>7} {'p0 err':>9} {'p0 nodal':>9} "
             f"{'a err':>9} {'delta':>9} {'L2':>8}"]
    for r in result["rows"]:
        lines.append(f"{'P' + str(r['order']):>5} {r['h_over_a']:>7.4f} {r['dofs']:>7} "
                     f"{r['time_s']:>7.1f} {r['p0_err']:>+9.2e} {r['p0_nodal_err']:>+9.2e} "
                     f"{r['a_err']:>+9.2e} {r['delta_err']:>+9.2e} {r['l2_err']:>8.2e}")
    for k, v in result["summary"].items():
        if isinstance(v, dict):
            v = {key: x for key, x in v.items() if key != "finest"}
        lines.append(f"{k}: {v}")
    return "\n".join(lines)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures", help="directory of the figure")
    ap.add_argument("--data", default="docs/data", help="directory of the JSON numbers")
    args = ap.parse_args()
    logging.basicConfig(level=logging.INFO)
    print(_table(main(out=args.out, data=args.data)))
