"""The reference, the files and the figure of ``studies/speed_vs_error.py``: run time
against error for the modelling choices of a wear run, with their Pareto front."""
from __future__ import annotations

import csv
import json
import logging
from pathlib import Path

import numpy as np

from brakewear.output.figures import label_log_axis

logger = logging.getLogger("speed_vs_error")

CSV_FIELDS = ["name", "group", "size_m", "steps", "scheme", "update", "rotor", "interface",
              "dofs", "pad_nodes", "run_s", "cpu_s", "time_ratio", "cpu_ratio", "contact_solves",
              "err_pad_wear_l2",
              "err_pressure_l2", "err_pad_wear_max", "err_pressure_max", "err_r_eff",
              "err_rotor_wear_l2", "base_err_pad_wear_l2", "base_err_pressure_l2", "failed"]


COLORS = {"mesh size": "C0", "wear step": "C1", "geometry update": "C2", "rotor": "C3",
          "interface": "C4"}


def pareto(points: list[tuple[float, float]]) -> list[int]:
    """Indices of the non-dominated (time, error) points, by increasing time."""
    idx = sorted(range(len(points)), key=lambda i: points[i])
    front, best = [], np.inf
    for i in idx:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def _scatter(ax, runs, key, tkey, ref=None, label_groups=None, star="reference"):
    """Log-log (time, error) points with labels; returns the floor used for error 0."""
    errs = [r[key]["pad_wear_l2"] for r in runs]
    floor = 0.3 * min([e for e in errs if e > 0] or [1e-3])
    pts = []
    for r, e in zip(runs, errs):
        y = max(e, floor)
        pts.append((r[tkey], y))
        is_ref = r is ref
        ax.loglog(r[tkey], y, "*" if is_ref else "o", color=COLORS[r["group"]],
                  ms=14 if is_ref else 8)
        if label_groups is None or r["group"] in label_groups or is_ref:
            name = r["name"].replace(" (reference)", "") + (f" = {star}" if is_ref else "")
            # geometry update below, explicit to the left: clear of each other
            dx, dy, ha = ((6, -11, "left") if r["group"] == "geometry update" else
                          (-7, 4, "right") if r.get("scheme") == "explicit" else (6, 3, "left"))
            ax.annotate(name, (r[tkey], y), textcoords="offset points", xytext=(dx, dy),
                        ha=ha, fontsize=7.5)
    front = pareto(pts)
    ax.loglog([pts[i][0] for i in front], [pts[i][1] for i in front], "k--", lw=0.8,
              label="Pareto front")
    if min(errs) == 0:
        ax.axhline(floor, color="0.7", lw=0.6)
        ax.text(0.01, floor, " error 0 drawn here", transform=ax.get_yaxis_transform(),
                ha="left", va="bottom", fontsize=7, color="0.4")
    ax.grid(True, which="both", alpha=0.3)
    return floor


def plot(result: dict, path: Path) -> None:
    """Three panels: all runs against the reference; the choices at the base mesh
    against the base model; element order on the cylinder."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = [r for r in result["runs"] if r.get("error")]
    c = result["case"]
    ref = next((r for r in runs if r["name"] == c["reference"]), None)
    base = [r for r in runs if r["name"] == c["base"]][0]
    tkey = "cpu_s" if all("cpu_s" in r for r in runs) else "run_s"
    tlabel = ("CPU time (s, model build + wear history)" if tkey == "cpu_s"
              else "run time (s, model build + wear history)")
    fig, axes = plt.subplots(1, 3, figsize=(18, 6.4),
                             gridspec_kw={"width_ratios": [1.3, 1.3, 1]})
    ax = axes[0]
    _scatter(ax, runs, "error", tkey, ref=ref, label_groups=("mesh size", "interface", "rotor"))
    for g, col in COLORS.items():
        ax.plot([], [], "o", color=col, label=g)
    ax.legend(fontsize=8, loc="center left")
    ax.set_xlabel(tlabel)
    ax.set_ylabel("pad wear error vs reference (relative L2)")
    ax.set_title(f"(a) all runs against the reference, {c['reference']}\n"
                 f"unlabelled: the wear-step / update choices at {base['size_m'] * 1e3:g} mm, "
                 "see (b)", fontsize=9)
    ax = axes[1]
    same = [r for r in runs if r.get("error_vs_base") is not None or r is base]
    for r in same:
        if r is base:
            r["_vs_base"] = {k: 0.0 for k in r["error"]}
        else:
            r["_vs_base"] = r["error_vs_base"]
    _scatter(ax, same, "_vs_base", tkey, ref=base, star="base")
    ax.set_xlabel(tlabel)
    ax.set_ylabel("pad wear difference vs the base model (relative L2)")
    ax.set_title(f"(b) each choice's own error: against the base model\n"
                 f"({base['size_m'] * 1e3:g} mm, implicit {c['ref_steps']} steps, gap offset, "
                 "elastic rotor, FE)", fontsize=9)
    ax2 = axes[2]
    eo = result.get("element_order") or []
    for order, mk in ((1, "o-"), (2, "s-")):
        rows = [r for r in eo if r["order"] == order]
        if rows:
            ax2.loglog([r["run_s"] for r in rows], [r["energy_error"] for r in rows], mk,
                       label=f"P{order}")
            for r in rows:
                ax2.annotate(f"{r['dofs']} dofs", (r["run_s"], r["energy_error"]),
                             textcoords="offset points", xytext=(4, 3), fontsize=7)
    if eo:
        lo, hi = min(r["run_s"] for r in eo), max(r["run_s"] for r in eo)
        label_log_axis(ax2.xaxis, [t for t in (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10)
                                   if lo / 2 <= t <= hi * 2])
    ax2.set_xlabel("wall time (s, assemble + AMG solve)")
    ax2.set_ylabel("energy-norm error vs Lame (relative)")
    ax2.set_title("(c) element order on a single body:\nthick cylinder, one static solve",
                  fontsize=9)
    ax2.grid(True, which="both", alpha=0.3)
    if eo:
        ax2.legend(fontsize=8)
    fig.suptitle(f"Speed against error: default brake, {c['duration_s']:g} s running-in at "
                 f"{c['line_pressure'] / 1e6:g} MPa, {c['omega']:g} rad/s, mu {c['mu']:g}",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def converged_reference(path, duration: float, ref_steps: int, run: dict) -> dict | None:
    """The Richardson estimate of ``path`` at ``duration`` as a reference run (the
    fields on the estimate's grid); None if the file is missing or was run for
    another case (loads, time, step)."""
    path = Path(path)
    if not path.is_file():
        logger.warning("no converged reference at %s: the finest mesh is the reference", path)
        return None
    data = json.loads(path.read_text())
    c = data["case"]
    when = ("end" if np.isclose(c["duration_s"], duration) else
            "mid" if c.get("t_mid_s") and np.isclose(c["t_mid_s"], duration) else None)
    est = data["orders"].get("P1", {}).get(when or "end")
    same = (when is not None and est is not None and all(
        np.isclose(c[k], run[k]) for k in ("line_pressure", "omega", "mu"))
        and np.isclose(c["duration_s"] / c["steps"], duration / ref_steps))
    if not same or est["pad_wear"]["field"] is None:
        logger.warning("%s is not this case at %g s (or has no estimate): the finest mesh is "
                       "the reference", path, duration)
        return None
    g = data["grid"]
    finest = data["orders"]["P1"]["runs"][-1][when]
    field = lambda q: np.array(est[q]["field"] if est[q]["field"] is not None  # noqa: E731
                               else finest[q])
    scalar = lambda q: (est[q]["estimate"] if est[q]["estimate"] is not None  # noqa: E731
                        else finest[q])
    return {"name": f"Richardson estimate ({path.name}, {when})", "_xy": np.array(g["xy"]),
            "_area": np.array(g["area"]), "_pad_wear": field("pad_wear"),
            "_pressure": field("pressure"), "_rotor_r": np.array(g["r"]),
            "_rotor_wear": field("rotor_wear"), "pad_wear_max_m": scalar("pad_wear_max"),
            "pressure_max_Pa": scalar("pressure_max"), "r_eff_m": scalar("r_eff")}


def write(result: dict, out: Path, figures: bool = True) -> None:
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / "speed_vs_error.json").write_text(json.dumps(result, indent=2,
                                                                 default=float))
    with open(out / "data" / "speed_vs_error.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=CSV_FIELDS, extrasaction="ignore")
        w.writeheader()
        for r in result["runs"]:
            row = dict(r)
            for k, v in (r.get("error") or {}).items():
                row[f"err_{k}"] = v
            for k, v in (r.get("error_vs_base") or {}).items():
                row[f"base_err_{k}"] = v
            w.writerow(row)
    if figures:
        (out / "figures").mkdir(parents=True, exist_ok=True)
        plot(result, out / "figures" / "speed_vs_error.png")


def table(result: dict) -> str:
    """The Markdown table of docs/performance.md, section 'Speed against error'."""
    lines = ["| choice | size mm | DOFs | wall s | CPU s | CPU / finest mesh | pad wear err | "
             "pressure err | r_eff err | rotor wear err | own error (pad wear vs base) |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in result["runs"]:
        if r.get("failed"):
            lines.append(f"| {r['name']} | | | | | | failed: {r['failed'][:60]} | | | | |")
            continue
        e, b = r["error"], r["error_vs_base"]
        lines.append(
            f"| {r['name']} | {r['size_m'] * 1e3:g} | {r['dofs']} | {r['run_s']:.1f} | "
            f"{r.get('cpu_s', float('nan')):.1f} | {r.get('cpu_ratio', float('nan')):.3f} | "
            f"{e['pad_wear_l2']:.2%} | {e['pressure_l2']:.2%} | "
            f"{e['r_eff']:+.2%} | {e['rotor_wear_l2']:.2%} | "
            + (f"{b['pad_wear_l2']:.2%} |" if b else "- |"))
    return "\n".join(lines)
