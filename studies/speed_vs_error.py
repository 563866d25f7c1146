"""Run time against error for the modelling choices a user has.

The same running-in of the default brake (1 MPa line pressure, 55 rad/s,
mu = 0.4, Archard pad k = 5e-15 1/Pa, rotor 5e-16 1/Pa, ``duration`` s) is run
with one modelling choice changed at a time, all in one process, and each
run's result is compared with the *reference*: the Richardson estimate of the
mesh-converged answer of ``studies/mesh_convergence.py`` at the same time
(its fields on a fixed r-theta grid, ``docs/data/mesh_convergence.json``;
elastic rotor, gap offset, implicit Euler with steps of ``duration /
ref_steps``), or, with ``reference=None`` or a file of another case, the
finest mesh of ``sizes``.

Choices (each against the reference, and the non-mesh ones also against the
*base* model of the same mesh, ``base_size``, so that the choice's own error
is seen apart from the mesh error):

- mesh size (``sizes``, reference settings otherwise);
- wear step: implicit with ``implicit_steps`` fixed steps, explicit with
  ``explicit_steps`` fixed steps (no step control);
- geometry update (``update="geometry"``) against gap offset;
- rigid against elastic rotor;
- FE contact against the Winkler foundation (uncalibrated: layer modulus;
  and stiffness-calibrated against one FE solve, whose cost is counted);
- element order: P1 against P2 timed on a single body, the thick cylinder of
  ``studies/cylinder_convergence.py`` (energy-norm error against Lame's
  closed form); the brake's own P1 against P2 contact patch is
  ``studies/brake_order.py`` (a wear history on P2 has no file output yet).

Error metrics (the comparison of fields on different meshes is done at the
reference's points -- the grid of the estimate, or the finest mesh's pad
friction nodes: each run's field is interpolated there linearly,
``LinearNDInterpolator`` in (x, y), nearest value outside its hull):

- ``pad_wear_l2``: area-weighted relative L2 of the pad wear after the
  running-in (the headline error);
- ``pressure_l2``: the same for the contact pressure at the end;
- ``pad_wear_max``, ``pressure_max``: relative error of the maxima;
- ``r_eff``: relative error of the effective friction radius
  ``sum(p A r) / sum(p A)`` (the torque at a given clamp force);
- ``rotor_wear_l2``: relative L2 of the rotor wear profile against r.

Run ``python studies/speed_vs_error.py [--out DIR] [--quick]``; writes
``speed_vs_error.json`` and ``.csv`` (DIR/data) and ``speed_vs_error.png``
(DIR/figures).
"""
from __future__ import annotations

import argparse
import csv
import importlib.util
import json
import logging
import os
import platform
import time
from pathlib import Path

import numpy as np

from brakewear.mesh.convergence import interpolate
from brakewear.mesh.surface import surface_nodes
from brakewear.interfaces import WinklerInterface, calibrate
from brakewear.model import BrakeModel
from brakewear.interfaces import CondensedInterface, FEInterface, FoundationInterface
from brakewear.wear import wear_history
from brakewear.laws.base import WearLaw
from brakewear import Numerics
from brakewear.static import solve_contact
from brakewear.wear import Run

logger = logging.getLogger(__name__)

PAD, ROTOR = WearLaw(5e-15), WearLaw(5e-16)
RUN = {"line_pressure": 1e6, "omega": 55.0, "mu": 0.4}


# ------------------------------------------------------------------ runs --
def run_case(size: float, duration: float, steps: int, scheme: str = "implicit",
             update: str = "gap", rotor: str = "elastic", piston: str = "traction",
             interface: str = "fe", thermal: bool = False, pad_law: WearLaw = PAD,
             rotor_law: WearLaw = ROTOR, **run) -> dict:
    """One running-in; returns the final fields and the cost (s).

    ``interface``: ``"fe"``, ``"condensed"`` (its condensation in the cost),
    ``"winkler"`` (layer modulus) or
    ``"winkler_cal"`` (stiffness-calibrated against one FE solve, counted in
    the cost).  ``run_s`` is model build + (calibration) + the wear history.
    """
    run = {**RUN, **run}
    lp, om, mu = run["line_pressure"], run["omega"], run["mu"]
    t0, c0 = time.perf_counter(), time.process_time()
    model = BrakeModel("default", size=size, rotor=rotor, piston=piston)
    kw = {}
    if interface == "fe":
        if update == "gap":
            kw["interface"] = FEInterface(model, lp, mu)
    elif interface == "condensed":     # its condensation counted in the cost (no cache)
        kw["interface"] = CondensedInterface(model, lp, mu, cache=False)
    else:
        wi = WinklerInterface.from_model(model)
        if interface == "winkler_cal":
            wi = calibrate(wi, solve_contact(model, lp, mu), "stiffness", model=model).interface
        elif interface != "winkler":
            raise ValueError(f"interface = {interface!r}; allowed: 'fe', 'condensed', "
                             "'winkler', 'winkler_cal'")
        kw["interface"] = FoundationInterface(model, wi, lp, mu)
    if thermal:
        from brakewear.thermal import ThermalModel
        kw["thermal"] = ThermalModel(model, contact_conductance=1e5)
    if "interface" not in kw:
        kw["interface"] = FEInterface(model, lp, mu)
    itf = kw["interface"]
    last, solves, solve_s = None, 0, 0.0
    for s in wear_history(Run(model, lp, om, duration, pad_law, rotor_law, mu, **kw, numerics=Numerics(steps=steps, scheme=scheme, update=update))):
        last = s
        solves += s.contact_solves
        solve_s += s.solve_s
    run_s, cpu_s = time.perf_counter() - t0, time.process_time() - c0
    p_end = last.pressure_end
    pad = model.meshes["pad"]
    nodes = surface_nodes(pad, "friction")
    x = pad.p[:2, nodes]
    area = itf.area if itf is not None else None
    rr = np.hypot(itf.rotor_x[0], itf.rotor_x[1])
    order = np.argsort(rr)
    out = {
        "size_m": size, "duration_s": duration, "steps": steps, "scheme": scheme,
        "update": update, "rotor": rotor, "piston": piston, "interface": interface,
        "thermal": thermal, "dofs": int(model.dofs), "pad_nodes": int(nodes.size),
        "run_s": run_s, "cpu_s": cpu_s, "solve_s": solve_s, "contact_solves": solves,
        "_xy": x, "_area": area, "_pad_wear": last.pad_wear.copy(),
        "_pressure": np.asarray(p_end, dtype=float).copy(),
        "_rotor_r": rr[order], "_rotor_wear": last.rotor_wear[order].copy(),
        "pad_wear_max_m": float(last.pad_wear.max()),
        "pressure_max_Pa": float(np.max(p_end)),
        "r_eff_m": _r_eff(p_end, area, x),
    }
    if thermal:
        out["pad_temperature_max_K"] = last.pad_temperature_max
        out["rotor_temperature_max_K"] = last.rotor_temperature_max
    return out


def _r_eff(p, area, xy) -> float:
    f = np.clip(p, 0, None) * area
    return float((f * np.hypot(xy[0], xy[1])).sum() / f.sum())


def _study(name: str):
    """The module ``studies/<name>.py`` (the studies are scripts, not a package)."""
    spec = importlib.util.spec_from_file_location(name, Path(__file__).with_name(f"{name}.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def errors(case: dict, ref: dict) -> dict:
    """Errors of ``case`` against ``ref`` (see the module docstring)."""
    X, A = ref["_xy"], ref["_area"]

    def l2(a, b):
        return float(np.sqrt((A * (a - b) ** 2).sum() / (A * b ** 2).sum()))

    if case is ref:
        wear, p = ref["_pad_wear"], ref["_pressure"]
    else:
        wear = interpolate(case["_pad_wear"], case["_xy"], X)
        p = interpolate(case["_pressure"], case["_xy"], X)
    # no wear outside the radii a run has wear nodes at (an unmeshed rotor's
    # rings span the pad's radii only)
    rw = np.interp(ref["_rotor_r"], case["_rotor_r"], case["_rotor_wear"], left=0.0, right=0.0)
    rA = ref["_rotor_wear"]
    return {
        "pad_wear_l2": l2(wear, ref["_pad_wear"]),
        "pressure_l2": l2(p, ref["_pressure"]),
        "pad_wear_max": case["pad_wear_max_m"] / ref["pad_wear_max_m"] - 1.0,
        "pressure_max": case["pressure_max_Pa"] / ref["pressure_max_Pa"] - 1.0,
        "r_eff": case["r_eff_m"] / ref["r_eff_m"] - 1.0,
        "rotor_wear_l2": float(np.sqrt(((rw - rA) ** 2).sum() / (rA ** 2).sum())),
    }


def element_order(ns_p1=(4, 8, 16), ns_p2=(2, 4, 8)) -> list[dict]:
    """P1 against P2 on the thick cylinder (the brake's: studies/brake_order.py)."""
    cyl = _study("cylinder_convergence")
    rows = []
    for order, ns in ((1, ns_p1), (2, ns_p2)):
        for n in ns:
            r = cyl.solve(n, order)
            rows.append({"name": f"P{order} cylinder n={n}", "order": order, "h_m": r["h"],
                         "dofs": int(r["dofs"]), "run_s": r["time_s"],
                         "energy_error": r["energy"], "l2_error": r["l2"]})
    return rows


#: the convergence study's results, whose estimate is the default reference
CONVERGED = Path(__file__).parents[1] / "docs" / "data" / "mesh_convergence.json"


def converged_reference(path, duration: float, ref_steps: int, run: dict) -> dict | None:
    """The Richardson estimate of ``path`` at ``duration`` as a reference run (the
    fields on the estimate's grid); None if the file is missing or was run for
    another case (loads, time, step)."""
    path = Path(path)
    if not path.is_file():
        logger.warning("no converged reference at %s: the finest mesh is the reference", path)
        return None
    data = json.loads(path.read_text())
    c, run = data["case"], {**RUN, **run}
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


def machine_state() -> dict:
    load = os.getloadavg() if hasattr(os, "getloadavg") else (np.nan,) * 3
    return {"cpus": os.cpu_count(), "load_average_1_5_15": list(load),
            "python": platform.python_version(), "platform": platform.platform(),
            "date_utc": time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime())}


def cases(sizes, base_size, ref_steps, implicit_steps, explicit_steps,
          finest_is_reference: bool = True) -> list[dict]:
    """The runs: (name, group, settings).  The last of ``sizes`` is the finest mesh
    (the reference if ``finest_is_reference``)."""
    mm = lambda s: f"{s * 1e3:g} mm"    # noqa: E731
    out = [{"name": f"mesh {mm(s)}", "group": "mesh size",
            "kw": {"size": s, "steps": ref_steps}} for s in sizes]
    if finest_is_reference:
        out[-1]["name"] += " (reference)"
    b = {"size": base_size}
    out += [{"name": f"implicit {n} steps", "group": "wear step",
             "kw": {**b, "steps": n}} for n in implicit_steps]
    out += [{"name": f"explicit {n} steps", "group": "wear step",
             "kw": {**b, "steps": n, "scheme": "explicit"}} for n in explicit_steps]
    out += [
        {"name": "geometry update", "group": "geometry update",
         "kw": {**b, "steps": ref_steps, "update": "geometry"}},
        {"name": "rigid rotor", "group": "rotor", "kw": {**b, "steps": ref_steps,
                                                          "rotor": "rigid"}},
        {"name": "condensed FE", "group": "interface",
         "kw": {**b, "steps": ref_steps, "interface": "condensed"}},
        {"name": "Winkler (layer modulus)", "group": "interface",
         "kw": {**b, "steps": ref_steps, "interface": "winkler"}},
        {"name": "Winkler (stiffness-calibrated)", "group": "interface",
         "kw": {**b, "steps": ref_steps, "interface": "winkler_cal"}},
    ]
    return out


def main(sizes=(12e-3, 8e-3, 6e-3, 5e-3, 4e-3), base_size: float = 8e-3, ref_steps: int = 16,
         implicit_steps=(2, 4, 8, 32), explicit_steps=(16, 64), duration: float = 1200.0,
         out: str | Path | None = "docs", figures: bool = True, order_study: bool = True,
         reference: str | Path | None = CONVERGED, **run) -> dict:
    """Run all cases in this process; returns the results (and writes them under ``out``).

    ``sizes`` must contain ``base_size``; its last entry is the finest mesh, the
    cost reference (``time_ratio``, ``cpu_ratio``) and, when ``reference`` (the
    convergence study's JSON) is None or of another case, the error reference.
    """
    sizes = tuple(sizes)
    if base_size not in sizes:
        raise ValueError(f"base_size = {base_size!r} must be one of sizes = {sizes!r}")
    state0 = machine_state()
    t_all = time.perf_counter()
    conv = (None if reference is None else
            converged_reference(reference, duration, ref_steps, run))
    todo = cases(sizes, base_size, ref_steps, implicit_steps, explicit_steps, conv is None)
    res = []
    for c in todo:
        logger.info("running %s", c["name"])
        try:
            r = run_case(duration=duration, **c["kw"], **run)
        except Exception as e:   # a choice that fails is a result too (e.g. explicit blow-up)
            logger.warning("%s failed: %s", c["name"], e)
            r = {"failed": f"{type(e).__name__}: {e}"}
        res.append({"name": c["name"], "group": c["group"], **r})
    finest = res[len(sizes) - 1]
    ref = finest if conv is None else conv
    base = res[sizes.index(base_size)]
    for r in res:
        if "failed" in r:
            r["error"], r["error_vs_base"] = None, None
            continue
        r["error"] = errors(r, ref)
        r["error_vs_base"] = errors(r, base) if r["group"] != "mesh size" else None
        r["time_ratio"] = r["run_s"] / finest["run_s"]
        r["cpu_ratio"] = r["cpu_s"] / finest["cpu_s"]
    result = {
        "case": {"geometry": "default", "duration_s": duration, **RUN, **run,
                 "pad_law_k": PAD.k, "rotor_law_k": ROTOR.k, "reference": ref["name"],
                 "finest": finest["name"], "base": base["name"], "ref_steps": ref_steps},
        "runs": [{k: v for k, v in r.items() if not k.startswith("_")} for r in res],
        "element_order": element_order() if order_study else [],
        "machine_before": state0, "machine_after": machine_state(),
        "total_s": time.perf_counter() - t_all,
        "command": "python studies/speed_vs_error.py",
    }
    if out is not None:
        write(result, Path(out), figures)
    return result


# --------------------------------------------------------------- output --
CSV_FIELDS = ["name", "group", "size_m", "steps", "scheme", "update", "rotor", "interface",
              "dofs", "pad_nodes", "run_s", "cpu_s", "time_ratio", "cpu_ratio", "contact_solves",
              "err_pad_wear_l2",
              "err_pressure_l2", "err_pad_wear_max", "err_pressure_max", "err_r_eff",
              "err_rotor_wear_l2", "base_err_pad_wear_l2", "base_err_pressure_l2", "failed"]


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
        from brakewear.output.figures import label_log_axis
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


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs", help="writes OUT/data and OUT/figures")
    ap.add_argument("--quick", action="store_true", help="tiny settings (a smoke run)")
    ap.add_argument("--duration", type=float, default=1200.0)
    ap.add_argument("--replot", metavar="JSON", help="only redraw the figure from a JSON")
    a = ap.parse_args(argv)
    if a.replot:
        res = json.loads(Path(a.replot).read_text())
        (Path(a.out) / "figures").mkdir(parents=True, exist_ok=True)
        plot(res, Path(a.out) / "figures" / "speed_vs_error.png")
        print(table(res))
        return res
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(name)s %(message)s")
    logger.setLevel(logging.INFO)
    kw = dict(sizes=(1.5e-2, 1.2e-2), base_size=1.5e-2, ref_steps=2, implicit_steps=(1,),
              explicit_steps=(2,)) if a.quick else {}
    res = main(out=a.out, duration=a.duration, **kw)
    print(table(res))
    return res


if __name__ == "__main__":
    _cli()
