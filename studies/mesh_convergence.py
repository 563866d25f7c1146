"""Mesh convergence of the default scene's running-in, with Richardson estimates.

The physics of ``geometry/scenes/default.toml`` (1 MPa line pressure, 55 rad/s,
mu 0.4, the materials' Archard laws for pad and rotor, elastic rotor, piston
load as a traction, implicit backward Euler, gap-offset update, one hour of
drag) on a family of meshes refined uniformly in all directions: level ``n``
has the in-plane size ``H / n`` on pad and rotor and ``n`` element layers
through the friction layer (graded toward the friction face by the geometry's
``pad_z_ratio``), through the backplate and through the rotor half (graded by
``rotor_z_ratio``), so the element shapes stay the same from level to level.
Every mesh takes the same equal implicit steps (no step control), so the
time-discretisation error is common to all levels and the differences
between levels are the mesh's alone.

Quantities, at the end of the run (and at ``t_mid``, for
``studies/speed_vs_error.py``, whose runs last that long):

- pad wear: maximum, worn volume ``sum(A w)``, and the field on a fixed
  r-theta grid over the pad face (linear interpolation of each mesh's
  friction-node values in (x, y));
- the largest contact pressure at the end and the pressure field on the grid;
- the rotor wear profile against r on a fixed radius grid;
- the effective friction radius ``sum(p A r) / sum(p A)``.

For a scalar ``f`` on the three finest levels (``f1`` coarsest, ratio ``r``)
the observed rate is ``p = log((f1 - f2) / (f2 - f3)) / log(r)`` and the
Richardson estimate ``f0 = f3 + (f3 - f2) / (r^p - 1)``; a sequence whose
differences change sign is not in the asymptotic range, and is reported so
(no estimate).  Fields use the norms of the differences for ``p`` and the same
formula point by point; each mesh's error is its relative L2 distance
(area-weighted on the grid) from the estimated field.

Run ``python studies/mesh_convergence.py [--levels 2 3 4 6 9] [--out DIR]``;
writes ``DIR/data/mesh_convergence.json`` and ``DIR/figures/mesh_convergence.png``
and prints the table of docs/performance.md, "Mesh convergence of the
running-in".
"""
from __future__ import annotations

import argparse
import json
import logging
import math
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator

from brakewear import Numerics
from brakewear.errors import InputError
from brakewear.interfaces import FEInterface
from brakewear.model import BrakeModel
from brakewear.scene import load_scene
from brakewear.wear import wear_history
from brakewear.wear import Run

logger = logging.getLogger(__name__)

#: level n: in-plane size H / n (m) and n layers through each layer of pad and rotor
H = 18e-3
SCALARS = ("pad_wear_max", "pad_wear_volume", "pressure_max", "r_eff", "rotor_wear_max")
FIELDS = ("pad_wear", "pressure", "rotor_wear")


# ----------------------------------------------------------- Richardson --
def observed_rate(f: tuple, r: tuple) -> float:
    """Observed order of three values ``f`` (coarse to fine) at refinement ratios
    ``r = (h1 / h2, h2 / h3)``; nan where the differences change sign or vanish.

    Equal ratios: ``log((f1 - f2) / (f2 - f3)) / log(r)``; unequal ones: the
    fixed point of Celik et al. (J. Fluids Eng. 130, 2008), eq. (3)."""
    e21, e32 = f[0] - f[1], f[1] - f[2]
    if e32 == 0 or e21 == 0 or e21 / e32 <= 0:
        return float("nan")
    r21, r32 = r
    p = math.log(e21 / e32) / math.log(r32)
    for _ in range(100):        # p = (log(e21 / e32) + q(p)) / log(r32)
        if p <= 0:
            break
        q = math.log((r32 ** p - 1.0) / (r21 ** p - 1.0))
        p_new = (math.log(e21 / e32) + q) / math.log(r32)
        if abs(p_new - p) < 1e-12:
            p = p_new
            break
        p = p_new
    return float(p)


def richardson(f: tuple, r: tuple) -> dict:
    """Rate, Richardson estimate of the converged value and each value's relative
    error from it, for a scalar sequence ``f`` (coarse to fine) of at least three."""
    f = tuple(float(v) for v in f)
    p = observed_rate(f[-3:], r[-2:])
    if not (np.isfinite(p) and p > 0):
        return {"rate": p, "estimate": None, "errors": [None] * len(f), "asymptotic": False}
    f0 = f[-1] + (f[-1] - f[-2]) / (r[-1] ** p - 1.0)
    return {"rate": p, "estimate": f0, "errors": [v / f0 - 1.0 for v in f], "asymptotic": True,
            "estimate_rate1": f[-1] + (f[-1] - f[-2]) / (r[-1] - 1.0)}


def field_richardson(fields: list, weights: np.ndarray, r: tuple) -> dict:
    """The same for fields on a common grid: the rate from the L2 norms of the
    differences, the estimated field point by point, each field's relative L2
    error from it, and ``shift_rate1``: how far (relative L2) the estimate at
    rate 1 lies from it (the errors' uncertainty where the rate is not settled)."""
    w = np.asarray(weights, dtype=float)

    def norm(a):
        return float(np.sqrt((w * a ** 2).sum()))

    f1, f2, f3 = (np.asarray(a, dtype=float) for a in fields[-3:])
    d21, d32 = norm(f2 - f1), norm(f3 - f2)
    p = observed_rate((0.0, d21, d21 + d32), r[-2:]) if d21 > 0 and d32 > 0 else float("nan")
    if not (np.isfinite(p) and p > 0):
        return {"rate": p, "field": None, "errors": [None] * len(fields), "asymptotic": False,
                "differences": [d21, d32]}
    f0 = f3 + (f3 - f2) / (r[-1] ** p - 1.0)
    n0 = norm(f0)
    return {"rate": p, "field": f0, "errors": [norm(np.asarray(a) - f0) / n0 for a in fields],
            "asymptotic": d32 < d21, "differences": [d21, d32],
            "shift_rate1": d32 * abs(1.0 / (r[-1] - 1.0) - 1.0 / (r[-1] ** p - 1.0)) / n0}


# ----------------------------------------------------------------- runs --
def level_settings(n: float, h_unit: float = H) -> dict:
    """Mesh keys of level ``n``: size ``h_unit / n`` and ``round(n)`` layers each."""
    k = max(1, int(round(n)))
    return {"size": round(h_unit / n, 12), "friction_layers": k, "backplate_layers": k,
            "rotor_layers": k}


def grids(geom, n_r: int = 24, n_t: int = 40) -> dict:
    """Cell-centred r-theta points on the pad face (m) with their areas, their radii,
    and the points of the arc at the mid radius with their angles."""
    pad = geom.pad
    dr = (pad.outer_radius - pad.inner_radius) / n_r
    dt = pad.arc_angle / n_t
    r = pad.inner_radius + dr * (np.arange(n_r) + 0.5)
    t = pad.leading_angle + dt * (np.arange(n_t) + 0.5)
    R, T = np.meshgrid(r, t, indexing="ij")
    r_mid = 0.5 * (pad.inner_radius + pad.outer_radius)
    return {"xy": np.vstack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel()]),
            "area": (R * dr * dt).ravel(), "r": r, "r_weight": np.full(n_r, dr),
            "theta": t, "arc_xy": r_mid * np.vstack([np.cos(t), np.sin(t)])}


def interpolate(values, xy, target):
    """``values`` given at ``xy`` (2, n), linearly interpolated at ``target`` (2, m);
    the nearest value outside the hull of ``xy``."""
    lin = LinearNDInterpolator(xy.T, values)(target.T)
    miss = np.isnan(lin)
    if miss.any():
        lin[miss] = NearestNDInterpolator(xy.T, values)(target.T[miss])
    return lin


def _profile(rotor_x, wear, r_grid):
    """Rotor wear against radius: the mean per node radius, interpolated on ``r_grid``."""
    rr = np.round(np.hypot(rotor_x[0], rotor_x[1]), 9)
    radii, inv = np.unique(rr, return_inverse=True)
    mean = np.bincount(inv, wear) / np.bincount(inv)
    return np.interp(r_grid, radii, mean)


def snapshot(itf, step, grid) -> dict:
    """The quantities of one state of a run."""
    p, A, x = np.clip(step.pressure_end, 0.0, None), itf.area, itf.x
    return {"time_s": float(step.time), "pad_wear_max": float(step.pad_wear.max()),
            "pad_wear_volume": float((A * step.pad_wear).sum()),
            "pressure_max": float(p.max()), "r_eff": float((p * A * itf.r).sum() / (p * A).sum()),
            "rotor_wear_max": float(step.rotor_wear.max()),
            "pad_wear": interpolate(step.pad_wear, x[:2], grid["xy"]),
            "pad_wear_arc": interpolate(step.pad_wear, x[:2], grid["arc_xy"]),
            "pressure": interpolate(p, x[:2], grid["xy"]),
            "rotor_wear": _profile(itf.rotor_x, step.rotor_wear, grid["r"])}


def run_mesh(scene, mesh: dict, steps: int, t_mid: float | None = None, order: int = 1,
             grid: dict | None = None) -> dict:
    """The scene's running-in on one mesh (``mesh``: [mesh] keys in m), equal
    implicit steps; the quantities at the end (and at ``t_mid``) and the cost."""
    g = scene.geometry
    geom = replace(g, mesh=replace(g.mesh, order=order, **mesh))
    grid = grids(geom) if grid is None else grid
    t0, c0 = time.perf_counter(), time.process_time()
    model = BrakeModel(geom, rotor=scene.rotor, piston=scene.piston)
    itf = FEInterface(model, scene.line_pressure, scene.interface.mu)
    pad_law, rotor_law = scene.wear_laws()
    num = Numerics(scheme="implicit", update="gap", steps=steps)
    snaps, solves = {}, 0
    for s in wear_history(Run(model, scene.line_pressure, scene.omega, scene.duration, pad_law, rotor_law, scene.interface.mu, numerics=num, interface=itf)):
        solves += s.contact_solves
        if t_mid is not None and "mid" not in snaps and s.time >= t_mid * (1 - 1e-9):
            snaps["mid"] = snapshot(itf, s, grid)
    snaps["end"] = snapshot(itf, s, grid)
    return {"mesh": dict(mesh), "order": order, "dofs": int(model.dofs),
            "pad_nodes": int(itf.area.size), "steps": steps, "contact_solves": solves,
            "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0, **snaps}


def analyse(runs: list, ratios: tuple, grid: dict, when: str = "end") -> dict:
    """Rates, Richardson estimates and errors of every quantity over ``runs``."""
    out = {}
    for q in SCALARS:
        out[q] = richardson([r[when][q] for r in runs], ratios)
    for q in FIELDS:
        w = grid["r_weight"] if q == "rotor_wear" else grid["area"]
        out[q] = field_richardson([r[when][q] for r in runs], w, ratios)
    for q in (*SCALARS, *FIELDS):      # every consecutive triple: is the rate settled?
        rates = []
        for i in range(len(runs) - 2):
            sub = [r[when][q] for r in runs[i:i + 3]]
            est = (richardson(sub, ratios[i:i + 2]) if q in SCALARS else field_richardson(
                sub, grid["r_weight"] if q == "rotor_wear" else grid["area"], ratios[i:i + 2]))
            rates.append(est["rate"])
        out[q]["rates"] = rates
        settle(out[q])
    return out


def settle(est: dict) -> None:
    """No estimate (in place) where the rate of the triple before the finest was not
    positive (one positive rate after a sign change is not a converging trend) or the
    last rate is below 0.5 (the estimate would lie many last differences away)."""
    rates = est.get("rates", [])
    if len(rates) >= 2 and not (rates[-2] > 0 and rates[-1] >= 0.5):
        est.update(asymptotic=False, errors=[None] * len(est["errors"]))
        est["estimate" if "estimate" in est else "field"] = None


def main(levels=(2, 3, 4, 6, 9), steps: int = 48, t_mid: float = 1200.0, orders=(1,),
         candidates=(), scene: str = "default", duration: float | None = None,
         out: str | Path | None = "docs", figures: bool = True) -> dict:
    """Run the convergence study; returns the results (and writes them under ``out``).

    ``levels``: the level numbers ``n`` (coarse to fine; at least three);
    ``candidates``: further [mesh] settings measured against the estimate
    (e.g. the default scene's); ``orders``: element orders (a refused order is
    skipped with a logged note); ``duration`` shortens the scene's run."""
    sc = load_scene(scene)
    if duration is not None:
        sc = replace(sc, duration=float(duration))
    t_mid = None if t_mid is not None and t_mid > sc.duration else t_mid
    levels = tuple(levels)
    if len(levels) < 3 or list(levels) != sorted(levels):
        raise ValueError(f"levels = {levels!r}: need three or more, coarse to fine")
    grid = grids(sc.geometry)
    ratios = tuple(b / a for a, b in zip(levels[:-1], levels[1:]))
    t_all = time.perf_counter()
    result = {"case": {"scene": scene, "duration_s": sc.duration, "steps": steps,
                       "t_mid_s": t_mid, "line_pressure": sc.line_pressure,
                       "omega": sc.omega, "mu": sc.interface.mu, "H_m": H,
                       "levels": list(levels), "ratios": list(ratios)},
              "orders": {}, "notes": [], "load_before": os.getloadavg()[0]}
    for order in orders:
        runs = []
        for n in levels:
            logger.info("P%d level %s: %s", order, n, level_settings(n))
            try:
                runs.append({"level": n, **run_mesh(sc, level_settings(n), steps, t_mid,
                                                    order, grid)})
            except InputError as exc:
                note = f"P{order} skipped: {exc}"
                logger.warning(note)
                result["notes"].append(note)
                break
        if len(runs) < len(levels):
            continue
        res = {"runs": runs, "end": analyse(runs, ratios, grid, "end")}
        if t_mid is not None:
            res["mid"] = analyse(runs, ratios, grid, "mid")
        cands = [{"level": None, **run_mesh(sc, dict(c), steps, t_mid, order, grid)}
                 for c in candidates]
        res["candidates"] = cands
        _errors(res, grid)
        result["orders"][f"P{order}"] = res
    result["total_s"] = time.perf_counter() - t_all
    result["grid"] = {k: np.asarray(v).tolist() for k, v in grid.items()}
    result["load_after"] = os.getloadavg()[0]
    if out is not None:
        write(result, Path(out), figures)
    return result


def _errors(res: dict, grid: dict) -> None:
    """Each run's (and candidate's) relative errors from the estimates, in place."""
    for when in ("end", "mid"):
        if when not in res:
            continue
        est = res[when]
        for r in res["runs"] + res["candidates"]:
            e = {}
            for q in SCALARS:
                f0 = est[q]["estimate"]
                e[q] = None if f0 is None else r[when][q] / f0 - 1.0
            for q in FIELDS:
                f0 = est[q]["field"]
                w = grid["r_weight"] if q == "rotor_wear" else grid["area"]
                e[q] = None if f0 is None else float(
                    np.sqrt((w * (r[when][q] - f0) ** 2).sum() / (w * f0 ** 2).sum()))
            r.setdefault("errors", {})[when] = e


# --------------------------------------------------------------- output --
def json_record(result: dict) -> dict:
    rec = dict(result)
    rec["orders"] = {}
    for name, res in result["orders"].items():
        res = dict(res)
        finest = res["runs"][-1]
        for key in ("runs", "candidates"):     # profiles are kept, grid fields not
            res[key] = [{k: v if k not in ("end", "mid") or r is finest else
                         {q: x for q, x in v.items() if q not in ("pad_wear", "pressure")}
                         for k, v in r.items()} for r in res[key]]
        rec["orders"][name] = res
    return rec


def write(result: dict, out: Path, figures: bool = True) -> None:
    """``out/data/mesh_convergence.json`` and ``out/figures/mesh_convergence.png``."""
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / "mesh_convergence.json").write_text(
        json.dumps(json_record(result), indent=1,
                   default=lambda x: x.tolist() if hasattr(x, "tolist") else float(x)))
    if figures and result["orders"]:
        (out / "figures").mkdir(parents=True, exist_ok=True)
        plot(result, out / "figures" / "mesh_convergence.png")


def label(r: dict) -> str:
    m = r["mesh"]
    lay = "/".join(str(m.get(k, "-")) for k in ("friction_layers", "backplate_layers",
                                                "rotor_layers"))
    mm = lambda k: f"{m.get(k, m['size']) * 1e3:.3g}"    # noqa: E731
    size = (f"{mm('size')} mm" if mm("pad_size") == mm("rotor_size") == mm("size") else
            f"pad {mm('pad_size')} / rotor {mm('rotor_size')} mm")
    return f"{size}, {lay}"


def plot(result: dict, path: Path) -> None:
    """Four panels: errors against CPU time, pad wear along the mid-radius arc, the
    estimated pad wear field, the rotor wear profiles."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name, res = next(iter(result["orders"].items()))
    runs, cands, est, grid = res["runs"], res["candidates"], res["end"], result["grid"]
    fig, ax = plt.subplots(2, 2, figsize=(13, 10))
    _plot_errors(ax[0, 0], name, runs, cands)
    a = ax[0, 1]
    th = np.degrees(np.array(grid["theta"]))
    for r in runs:
        a.plot(th, np.array(r["end"]["pad_wear_arc"]) * 1e6, label=f"n={r['level']:g}: "
               + label(r))
    f0 = est["pad_wear"]["field"]
    if f0 is not None:
        arc = interpolate(np.array(f0), np.array(grid["xy"]), np.array(grid["arc_xy"]))
        a.plot(th, arc * 1e6, "k--", label="Richardson estimate")
    a.set_xlabel("theta (deg); the rotor enters at the leading edge, theta < 0")
    a.set_ylabel("pad wear at the mid radius (um)")
    a.set_title("(b) pad wear along the mid-radius arc", fontsize=9)
    a.grid(True, alpha=0.3)
    a.legend(fontsize=7)
    a = ax[1, 0]
    xy = np.array(grid["xy"])
    field = np.array(runs[-1]["end"]["pad_wear"] if f0 is None else f0)
    sc = a.tricontourf(xy[0] * 1e3, xy[1] * 1e3, field * 1e6, 20, cmap="viridis")
    fig.colorbar(sc, ax=a, label="pad wear (um)")
    a.set_aspect("equal")
    a.set_xlabel("x (mm)")
    a.set_ylabel("y (mm); the rotor turns toward +y")
    a.set_title("(c) pad wear at the end: " + ("finest mesh" if f0 is None
                                               else "Richardson estimate"), fontsize=9)
    a = ax[1, 1]
    rg = np.array(grid["r"]) * 1e3
    for r in runs:
        a.plot(rg, np.array(r["end"]["rotor_wear"]) * 1e6, label=f"n={r['level']:g}")
    if est["rotor_wear"]["field"] is not None:
        a.plot(rg, np.array(est["rotor_wear"]["field"]) * 1e6, "k--", label="estimate")
    a.set_xlabel("r (mm)")
    a.set_ylabel("rotor wear, mean over the ring (um)")
    a.set_title("(d) rotor wear profile at the end", fontsize=9)
    a.grid(True, alpha=0.3)
    a.legend(fontsize=7)
    c = result["case"]
    fig.suptitle(f"Mesh convergence: default scene, {c['duration_s']:g} s running-in at "
                 f"{c['line_pressure'] / 1e6:g} MPa, {c['omega']:g} rad/s, mu {c['mu']:g}, "
                 f"{c['steps']} implicit steps", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _plot_errors(a, name: str, runs: list, cands: list) -> None:
    """Panel (a): errors from the estimate against CPU time; candidates as stars."""
    for q, mk, lw in (("pad_wear", "o-", 2.0), ("pad_wear_max", "s-", 1.0),
                      ("pad_wear_volume", "^-", 1.0), ("r_eff", "d-", 1.0)):
        pts = [(r["cpu_s"], abs(r["errors"]["end"][q])) for r in runs
               if r["errors"]["end"][q] is not None]
        if pts:
            a.loglog(*zip(*pts), mk, lw=lw, ms=5 if lw < 2 else 7,
                     label="pad wear, relative L2 of the field" if q == "pad_wear" else
                     f"|{q}|")
    for r in runs:
        e = r["errors"]["end"]["pad_wear"]
        if e is not None:
            a.annotate(f"n={r['level']:g}", (r["cpu_s"], e), textcoords="offset points",
                       xytext=(5, 4), fontsize=8)
    key = []
    for i, r in enumerate(cands, 1):
        e = r["errors"]["end"]["pad_wear"]
        if e is not None:
            a.loglog(r["cpu_s"], e, "k*", ms=10, label="candidates (pad wear L2)"
                     if i == 1 else None)
            a.annotate(f"c{i}", (r["cpu_s"], e), textcoords="offset points",
                       xytext=(-4, -12), fontsize=8)
            key.append(f"c{i}: {label(r)}")
    a.axhline(0.02, color="0.6", lw=0.8, ls=":")
    if key:
        a.text(0.02, 0.02, "\n".join(key), transform=a.transAxes, fontsize=7,
               va="bottom", bbox={"facecolor": "white", "alpha": 0.8, "lw": 0.3})
    a.set_xlabel("CPU time of the run (s)")
    a.set_ylabel("relative error from the Richardson estimate")
    a.set_title(f"(a) {name}: error against cost; level n: size 18/n mm, n layers through "
                "friction layer, backplate, rotor half", fontsize=8.5)
    a.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=7.5, loc="upper right")


def _pct(v) -> str:
    return "-" if v is None else f"{v:+.2%}"


def table(result: dict, order: str = "P1", when: str = "end") -> str:
    """The Markdown table of docs/performance.md, 'Mesh convergence of the running-in'."""
    res = result["orders"].get(order)
    if res is None:
        return f"({order}: no rows)"
    lines = ["| mesh (size, layers f/b/r) | DOFs | wall s | CPU s | pad wear max um | "
             "pad wear vol mm^3 | err pad wear L2 | err max | err volume | p max MPa | "
             "err p max | err r_eff | err rotor wear |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in res["runs"] + res["candidates"]:
        q, e = r[when], r["errors"][when]
        name = ("candidate " if r["level"] is None else f"n={r['level']:g}: ") + label(r)
        l2 = "-" if e["pad_wear"] is None else f"{e['pad_wear']:.2%}"
        rw = "-" if e["rotor_wear"] is None else f"{e['rotor_wear']:.2%}"
        lines.append(
            f"| {name} | {r['dofs']} | {r['wall_s']:.1f} | {r['cpu_s']:.1f} | "
            f"{q['pad_wear_max'] * 1e6:.2f} | {q['pad_wear_volume'] * 1e9:.1f} | {l2} | "
            f"{_pct(e['pad_wear_max'])} | {_pct(e['pad_wear_volume'])} | "
            f"{q['pressure_max'] / 1e6:.3f} | {_pct(e['pressure_max'])} | {_pct(e['r_eff'])} | "
            f"{rw} |")
    est = res[when]
    rates = "; ".join(f"{k} {est[k]['rate']:.2f}" + ("" if est[k].get("asymptotic") else
                                                      " (not asymptotic)") + " (triples: "
                      + ", ".join(f"{x:.2f}" for x in est[k].get("rates", [])) + ")"
                      for k in (*FIELDS, *SCALARS))
    lines.append(f"\nObserved rates from the three finest levels: {rates}.")
    if est["pad_wear"].get("shift_rate1") is not None:
        lines.append(f"The pad wear estimate at rate 1 lies {est['pad_wear']['shift_rate1']:.2%} "
                     "(relative L2) from the one at the observed rate.")
    return "\n".join(lines)


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--levels", type=float, nargs="+", default=[2, 3, 4, 6, 9])
    ap.add_argument("--steps", type=int, default=48)
    ap.add_argument("--orders", type=int, nargs="+", default=[1])
    ap.add_argument("--duration", type=float, default=None, help="s (default: the scene's)")
    ap.add_argument("--candidate", action="append", default=[], metavar="KEY=VALUE,...",
                    help="further [mesh] settings (m), e.g. size=6e-3,backplate_layers=2")
    ap.add_argument("--out", default="docs")
    ap.add_argument("--replot", metavar="JSON", help="only redraw the figure from a JSON")
    a = ap.parse_args(argv)
    if a.replot:
        res = json.loads(Path(a.replot).read_text())
        plot(res, Path(a.out) / "figures" / "mesh_convergence.png")
        print(table(res))
        return res
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(name)s %(message)s")
    logger.setLevel(logging.INFO)
    cands = [{k: (int(v) if k.endswith("layers") else float(v)) for k, v in
              (kv.split("=") for kv in c.split(","))} for c in a.candidate]
    res = main(levels=a.levels, steps=a.steps, orders=a.orders, candidates=cands,
               duration=a.duration, out=a.out)
    for order in res["orders"]:
        print(f"{order}:\n{table(res, order)}\n")
    for note in res["notes"]:
        print(note)
    return res


if __name__ == "__main__":
    _cli()
