"""Mesh convergence of the default scene's running-in with quadratic (P2) elements,
and its error against run time beside the linear (P1) family.

The running-in of ``studies/mesh_convergence.py`` with ``BrakeModel(order=2)``
on that study's levels taken coarser (a quadratic tetrahedron carries a linear
bending stress through its thickness: one or two layers through the backplate
do not lock).  Each P2 mesh is measured against the converged estimate of the
P1 family (``docs/data/mesh_convergence.json``; where P1 has no estimate, its
finest mesh) and against the P2 family's own; the two estimates agree when
their pad wear fields lie within the sum of their uncertainties
(``shift_rate1``).

Run ``python studies/mesh_convergence_p2.py [--levels 1 1.5 2 3 4] [--out DIR]``:
writes ``DIR/data/mesh_convergence_p2.json`` (every run, the estimates, the
comparison and the error-against-time rows of both orders) and
``DIR/figures/mesh_convergence_p2.png``, and prints the tables of
docs/performance.md, "Quadratic (P2) elements on the running-in".
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

import numpy as np

from brakewear.mesh.convergence import fitted_rate, relative_l2
from brakewear.scene.accuracy import TARGET

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mesh_convergence as mc  # noqa: E402  (sibling scripts, not a package)
from convergence_report import order_table, pct, plot_p2, rates_line  # noqa: E402

logger = logging.getLogger(__name__)

ROOT = Path(__file__).resolve().parents[1]
#: the P1 study whose converged estimate the P2 meshes are measured against
P1_DATA = ROOT / "docs" / "data" / "mesh_convergence.json"
#: P2 levels (coarse to fine): 18, 12, 9, 6, 4.5 mm with 1, 2, 2, 3, 4 layers
LEVELS = (1.0, 1.5, 2.0, 3.0, 4.0)


# ------------------------------------------------------------ estimates --
def reference(record: dict, order: str = "P1", when: str = "end") -> dict:
    """The converged estimate of one order's family in a mesh-convergence record
    at ``when`` ("end" or "mid"; ``None`` where the family gave none) and the state
    of its finest mesh then."""
    res = record["orders"][order]
    est = res[when]
    fields = {}
    for q in mc.FIELDS:
        f = est[q]["field"]
        fields[q] = None if f is None else np.asarray(f, dtype=float)
    return {"order": order, "when": when, "scalars": {q: est[q]["estimate"] for q in mc.SCALARS},
            "fields": fields, "shift_rate1": est["pad_wear"].get("shift_rate1"),
            "finest": res["runs"][-1][when], "finest_label": mc.label(res["runs"][-1])}


def matching_state(case: dict, p1_case: dict) -> str:
    """Which state of the P1 record is the same run as the study's ``case``: "end"
    (same duration and steps) or "mid" (the P1 run at ``t_mid``, with the same step)."""
    if (case["duration_s"], case["steps"]) == (p1_case["duration_s"], p1_case["steps"]):
        return "end"
    dt, dt1 = case["duration_s"] / case["steps"], p1_case["duration_s"] / p1_case["steps"]
    if (p1_case.get("t_mid_s") is not None and abs(case["duration_s"] - p1_case["t_mid_s"])
            <= 1e-9 * case["duration_s"] and abs(dt - dt1) <= 1e-9 * dt1):
        return "mid"
    raise ValueError(f"the P1 record runs {p1_case['duration_s']:g} s in {p1_case['steps']} "
                     f"steps (a state at {p1_case.get('t_mid_s')} s), the P2 study "
                     f"{case['duration_s']:g} s in {case['steps']}: pass a P1 record of the "
                     "same run (or of one with the same step that passes its duration)")


def errors_from(end: dict, ref: dict, grid: dict) -> dict:
    """Relative errors of one run's end state from the reference ``ref``: from its
    estimate where it has one, else (key ``"<q>_vs_finest"``) from its finest mesh."""
    e = {}
    for q in mc.SCALARS:
        f0 = ref["scalars"][q]
        if f0 is not None:
            e[q] = end[q] / f0 - 1.0
        else:
            e[q + "_vs_finest"] = end[q] / ref["finest"][q] - 1.0
    for q in mc.FIELDS:
        f0 = ref["fields"][q]
        if f0 is not None:
            e[q] = relative_l2(end[q], f0, mc.weights(q, grid))
        elif q in ref["finest"] and q in end:
            e[q + "_vs_finest"] = relative_l2(end[q], ref["finest"][q], mc.weights(q, grid))
    return e


def agreement(own: dict, p1: dict, grid: dict) -> dict:
    """How far the P2 estimate lies from the P1 estimate: relative differences of
    the scalars, relative L2 distances of the fields, whether the pad wear fields
    agree within the sum of the two estimates' uncertainties, and the distance of
    the finest P2 mesh's pad wear from the finest P1 mesh's."""
    out = {"scalars": {}, "fields": {}}
    for q in mc.SCALARS:
        a, b = own["scalars"][q], p1["scalars"][q]
        out["scalars"][q] = None if a is None or b is None else a / b - 1.0
    for q in mc.FIELDS:
        a, b = own["fields"][q], p1["fields"][q]
        out["fields"][q] = None if a is None or b is None else relative_l2(
            a, b, mc.weights(q, grid))
    a, b = own["finest"].get("pad_wear"), p1["finest"].get("pad_wear")
    out["finest_pad_wear"] = (None if a is None or b is None
                              else relative_l2(a, b, mc.weights("pad_wear", grid)))
    d = out["fields"]["pad_wear"]
    s1, s2 = p1["shift_rate1"], own["shift_rate1"]
    band = None if s1 is None or s2 is None else s1 + s2
    out.update(pad_wear_band=band, pad_wear_agree=None if d is None or band is None
               else bool(d <= band))
    return out


# ----------------------------------------------------------------- runs --
def main(levels=LEVELS, steps: int = 48, duration: float | None = None,
         p1: str | Path | dict | None = P1_DATA, out: str | Path | None = "docs",
         figures: bool = True) -> dict:
    """The P2 family's running-in; returns the results (and writes them under ``out``).

    ``p1``: the P1 study's record (a dict as ``mesh_convergence.main`` returns it,
    or its JSON file) whose estimate the P2 meshes are measured against: of the
    same duration and steps, or with the same step and its ``t_mid`` at this
    study's duration.  ``None``: the P2 family alone."""
    t0 = time.perf_counter()
    res = mc.main(levels=levels, steps=steps, t_mid=None, orders=(2,), duration=duration,
                  out=None, figures=False)
    if "P2" not in res["orders"]:
        raise RuntimeError("P2 runs did not complete: " + "; ".join(res["notes"]))
    result = {**res, "total_s": time.perf_counter() - t0}
    if p1 is not None:
        compare(result, p1 if isinstance(p1, dict) else json.loads(Path(p1).read_text()))
    if out is not None:
        write(result, Path(out), figures)
    return result


def compare(result: dict, p1_record: dict) -> None:
    """Measure the P2 runs of ``result`` against the P1 record's estimate (in place):
    each run's errors, the two estimates' agreement, the error-against-time rows."""
    grid = {k: np.asarray(v) for k, v in result["grid"].items()}
    p2 = result["orders"]["P2"]
    when = matching_state(result["case"], p1_record["case"])
    ref = reference(p1_record, "P1", when)
    for r in p2["runs"]:
        r["errors"]["p1_estimate"] = errors_from(r["end"], ref, grid)
    result["agreement"] = agreement(reference(result, "P2"), ref, grid)
    result["p1_field"] = ref["fields"]["pad_wear"]
    result["p1_reference"] = {"state": when, "finest": ref["finest_label"],
                              "estimate": ref["scalars"], "shift_rate1": ref["shift_rate1"]}
    result["rate_vs_p1"] = rate_vs(p2["runs"][-3:], "p1_estimate")
    result["error_vs_time"] = error_rows(p1_record, p2, when)
    result["cheapest"] = cheapest(result["error_vs_time"])


def rate_vs(runs: list, key: str = "p1_estimate") -> float | None:
    """Fitted order of the pad wear error (relative L2) of ``runs`` from the
    estimate ``key`` against the in-plane size: the slope of ``log(err)``
    against ``log(h)``; ``None`` where an error is missing or zero."""
    err = [r["errors"][key].get("pad_wear") for r in runs]
    if len(runs) < 2 or any(e is None or e <= 0 for e in err):
        return None
    return fitted_rate([r["mesh"]["size"] for r in runs], err)


def error_rows(p1_record: dict, p2: dict, when: str = "end") -> list:
    """One row per mesh of both orders: DOFs, times and the pad wear error (relative
    L2) from the P1 family's converged estimate (and, for P2, from its own)."""
    rows = []
    p1 = p1_record["orders"]["P1"]
    for kind, runs in (("level", p1["runs"]), ("candidate", p1["candidates"])):
        for r in runs:
            rows.append({"order": 1, "kind": kind, "level": r["level"], "mesh": mc.label(r),
                         "dofs": r["dofs"], "wall_s": r["wall_s"], "cpu_s": r["cpu_s"],
                         "err_pad_wear": r["errors"][when]["pad_wear"]})
    for r in p2["runs"]:
        rows.append({"order": 2, "kind": "level", "level": r["level"], "mesh": mc.label(r),
                     "dofs": r["dofs"], "wall_s": r["wall_s"], "cpu_s": r["cpu_s"],
                     "err_pad_wear": r["errors"]["p1_estimate"].get("pad_wear"),
                     "err_pad_wear_own": r["errors"]["end"]["pad_wear"]})
    return rows


def cheapest(rows: list, target: float = TARGET) -> dict:
    """Per order, the mesh of least CPU time whose pad wear error (from the P1
    estimate) is at most ``target``; ``None`` where no mesh reaches it."""
    best = {}
    for order in (1, 2):
        ok = [r for r in rows if r["order"] == order and r["err_pad_wear"] is not None
              and r["err_pad_wear"] <= target]
        best[f"P{order}"] = min(ok, key=lambda r: r["cpu_s"]) if ok else None
    return best


# --------------------------------------------------------------- output --
def write(result: dict, out: Path, figures: bool = True) -> None:
    """``out/data/mesh_convergence_p2.json`` and ``out/figures/mesh_convergence_p2.png``."""
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / "mesh_convergence_p2.json").write_text(json.dumps(
        mc.json_record(result), indent=1,
        default=lambda x: x.tolist() if hasattr(x, "tolist") else float(x)))
    if figures and "error_vs_time" in result:
        (out / "figures").mkdir(parents=True, exist_ok=True)
        plot_p2(result, out / "figures" / "mesh_convergence_p2.png")


def p2_table(result: dict) -> str:
    """The P2 rows: each mesh's answers, cost and errors from both estimates."""
    lines = ["| P2 mesh (size, layers f/b/r) | DOFs | wall s | CPU s | pad wear max um | "
             "pad wear vol mm^3 | p max MPa | r_eff mm | err pad wear L2 (P1 est.) | "
             "err max (P1 est.) | err volume (P1 est.) | err r_eff (P1 est.) | "
             "err pad wear L2 (P2 est.) | err max (P2 est.) | rotor profile vs P1 finest |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in result["orders"]["P2"]["runs"]:
        q, own = r["end"], r["errors"]["end"]
        e1 = r["errors"].get("p1_estimate", {})
        lines.append(
            f"| n={r['level']:g}: {mc.label(r)} | {r['dofs']} | {r['wall_s']:.1f} | "
            f"{r['cpu_s']:.1f} | "
            f"{q['pad_wear_max'] * 1e6:.2f} | {q['pad_wear_volume'] * 1e9:.1f} | "
            f"{q['pressure_max'] / 1e6:.3f} | {q['r_eff'] * 1e3:.2f} | "
            f"{pct(e1.get('pad_wear'), False)} | {pct(e1.get('pad_wear_max'))} | "
            f"{pct(e1.get('pad_wear_volume'))} | {pct(e1.get('r_eff'))} | "
            f"{pct(own['pad_wear'], False)} | {pct(own['pad_wear_max'])} | "
            f"{pct(e1.get('rotor_wear_vs_finest'), False)} |")
    return "\n".join(lines)


def summary(result: dict) -> str:
    """Rates, the two estimates' agreement and the cheapest mesh within the target."""
    rates = rates_line(result["orders"]["P2"]["end"], (*mc.FIELDS, *mc.SCALARS),
                       "no estimate")
    lines = [f"P2 observed rates from the three finest levels: {rates}."]
    ag = result.get("agreement")
    if ag is not None:
        s = "".join(f"; {k} {pct(v)}" for k, v in ag["scalars"].items() if v is not None)
        lines.append(f"P2 estimate against P1 estimate: pad wear field "
                     f"{pct(ag['fields']['pad_wear'], False)} (relative L2; band "
                     f"{pct(ag['pad_wear_band'], False)}, agree: {ag['pad_wear_agree']}){s}; "
                     f"finest P2 mesh from finest P1 mesh {pct(ag['finest_pad_wear'], False)}.")
    for order, r in result.get("cheapest", {}).items():
        lines.append(f"{order}: cheapest within {TARGET:.0%}: " + (
            "none" if r is None else f"{r['mesh']} ({r['dofs']} DOFs, {r['cpu_s']:.1f} s CPU, "
            f"{r['err_pad_wear']:.2%})"))
    return "\n".join(lines)


#: the command line: flag and argparse keywords
OPTIONS = (("--levels", {"type": float, "nargs": "+", "default": list(LEVELS)}),
           ("--steps", {"type": int, "default": 48}),
           ("--duration", {"type": float, "help": "s (default: the scene's)"}),
           ("--p1", {"default": str(P1_DATA), "help": "the P1 study's JSON ('' for none)"}),
           ("--out", {"default": "docs"}),
           ("--replot", {"metavar": "JSON", "help": "only redraw the figure from a JSON"}))


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for flag, kw in OPTIONS:
        ap.add_argument(flag, **kw)
    a = ap.parse_args(argv)
    if a.replot:
        res = json.loads(Path(a.replot).read_text())
        (Path(a.out) / "figures").mkdir(parents=True, exist_ok=True)
        plot_p2(res, Path(a.out) / "figures" / "mesh_convergence_p2.png")
    else:
        logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(name)s %(message)s")
        mc.logger.setLevel(logging.INFO)
        res = main(levels=a.levels, steps=a.steps, duration=a.duration, p1=a.p1 or None,
                   out=a.out)
    print(p2_table(res), end="\n\n")
    if "error_vs_time" in res:
        print(order_table(res), end="\n\n")
    print(summary(res))
    if res.get("rate_vs_p1") is not None:
        print(f"P2 pad wear error from the P1 estimate against h, three finest levels: "
              f"order {res['rate_vs_p1']:.2f}")
    return res


if __name__ == "__main__":
    _cli()
