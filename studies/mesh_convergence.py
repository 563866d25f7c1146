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

The observed rates and the Richardson estimates from the three finest levels
are :mod:`brakewear.mesh.convergence`'s (scalars, and fields point by point on
the grid); each mesh's error is its relative L2 distance (area-weighted on the
grid) from the estimated field.

Run ``python studies/mesh_convergence.py [--levels 2 3 4 6 9] [--out DIR]``;
writes ``DIR/data/mesh_convergence.json`` and ``DIR/figures/mesh_convergence.png``
and prints the table of docs/performance.md, "Mesh convergence of the
running-in".
"""
from __future__ import annotations

import argparse
import json
import logging
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from brakewear import Numerics
from brakewear.errors import InputError
from brakewear.interfaces import FEInterface
from brakewear.mesh.convergence import (
    estimate,
    interpolate,
    pad_grid,
    radial_profile,
    relative_l2,
)
from brakewear.model import BrakeModel
from brakewear.scene import load_scene
from brakewear.wear import Run, wear_history

sys.path.insert(0, str(Path(__file__).resolve().parent))
from convergence_report import label, pct, plot, rates_line  # noqa: E402  (a sibling script)

logger = logging.getLogger(__name__)

#: level n: in-plane size H / n (m) and n layers through each layer of pad and rotor
H = 18e-3
SCALARS = ("pad_wear_max", "pad_wear_volume", "pressure_max", "r_eff", "rotor_wear_max")
FIELDS = ("pad_wear", "pressure", "rotor_wear")


# ----------------------------------------------------------------- runs --
def level_settings(n: float, h_unit: float = H) -> dict:
    """Mesh keys of level ``n``: size ``h_unit / n`` and ``round(n)`` layers each."""
    k = max(1, int(round(n)))
    return {"size": round(h_unit / n, 12), "friction_layers": k, "backplate_layers": k,
            "rotor_layers": k}


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
            "rotor_wear": radial_profile(itf.rotor_x, step.rotor_wear, grid["r"])}


def run_mesh(scene, mesh: dict, steps: int, t_mid: float | None = None, order: int = 1,
             grid: dict | None = None) -> dict:
    """The scene's running-in on one mesh (``mesh``: [mesh] keys in m), equal
    implicit steps; the quantities at the end (and at ``t_mid``) and the cost."""
    g = scene.geometry
    geom = replace(g, mesh=replace(g.mesh, order=order, **mesh))
    grid = pad_grid(geom) if grid is None else grid
    t0, c0 = time.perf_counter(), time.process_time()
    model = BrakeModel(geom, rotor=scene.rotor, piston=scene.piston)
    itf = FEInterface(model, scene.line_pressure, scene.interface.mu)
    pad_law, rotor_law = scene.wear_laws()
    num = Numerics(scheme="implicit", update="gap", steps=steps)
    snaps, solves = {}, 0
    for s in wear_history(
        Run(
            model,
            scene.line_pressure,
            scene.omega,
            scene.duration,
            pad_law,
            rotor_law,
            scene.interface.mu,
            numerics=num,
            interface=itf,
        )
    ):
        solves += s.contact_solves
        if t_mid is not None and "mid" not in snaps and s.time >= t_mid * (1 - 1e-9):
            snaps["mid"] = snapshot(itf, s, grid)
    snaps["end"] = snapshot(itf, s, grid)
    return {"mesh": dict(mesh), "order": order, "dofs": int(model.dofs),
            "pad_nodes": int(itf.area.size), "steps": steps, "contact_solves": solves,
            "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0, **snaps}


def analyse(runs: list, ratios: tuple, grid: dict, when: str = "end") -> dict:
    """Rates, settled Richardson estimates and errors of every quantity over ``runs``."""
    return {q: estimate([r[when][q] for r in runs], ratios, weights(q, grid))
            for q in (*SCALARS, *FIELDS)}


def weights(q: str, grid: dict) -> np.ndarray | None:
    """The grid's weights of field ``q`` (None: a scalar)."""
    return None if q in SCALARS else np.asarray(
        grid["r_weight"] if q == "rotor_wear" else grid["area"], dtype=float)


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
    grid = pad_grid(sc.geometry)
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
                e[q] = None if f0 is None else relative_l2(r[when][q], f0, weights(q, grid))
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
            f"{pct(e['pad_wear_max'])} | {pct(e['pad_wear_volume'])} | "
            f"{q['pressure_max'] / 1e6:.3f} | {pct(e['pressure_max'])} | {pct(e['r_eff'])} | "
            f"{rw} |")
    est = res[when]
    rates = rates_line(est, (*FIELDS, *SCALARS), "not asymptotic")
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
