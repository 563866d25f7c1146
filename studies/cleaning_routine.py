"""A cleaning routine for a car: P(clean) against the deceleration, the number of stops
and the speed, and the routine a car maker can program (docs/cleaning.md, "The
cleaning routine").

Each sample is one routine run on the brake: ``stops`` friction-only stops
(:meth:`brakewear.duty.Vehicle.with_friction_share`) of :func:`brakewear.duty.study_car`
from ``speed`` km/h to rest at ``decel`` m/s^2, ``interval`` s apart, the car
driving on at ``speed`` in between (the rotor cools at that speed); the rust law
(:class:`brakewear.cleaning.rust.RustLayer`: removal above its threshold, friction and pad
wear on rust) and the stops' own heat (:class:`brakewear.thermal.reduced.ReducedRotorHeat`
of the floating caliper's hat rotor: the elastic rotor's thermal coning under its
temperatures, times ``thermal_coning_factor``, added to the static ``coning`` stop by
stop)
enter every stop (:func:`brakewear.cleaning.routine.run_routine`).  The band is cleaned when
every ring of every modelled face has worn through its layer
(:mod:`brakewear.cleaning.corrosion`'s criterion).

The uncertain inputs (:func:`inputs`) are the rust law's (:data:`brakewear.cleaning.rust.RUST_PRIORS`),
the friction coefficient on iron, the static coning and the thermal coning per
kelvin, the pad's modulus, the car's mass and road load, and the load path's
parameters where the brake has them (``brake = "caliper"``).  The design curve
(:func:`design_curve`) runs the same ``n`` draws at every deceleration and speed:
P(clean within N stops) for every N up to ``stops``, with its Wilson interval.
The routine (:func:`routine`) is the fewest stops, then the lowest deceleration,
then the lowest speed, that reach the probability.  Sensitivity:
:mod:`cleaning_sensitivity` (Sobol indices from SALib, the tornado).

The brake (``brake``): ``"caliper"`` (the default) -- the model of
:func:`cleaning_stops.task_interface`, the floating caliper as it holds its pads (rigid
piston in its bore, fingers, abutments; the hat rotor; both faces judged), with its
load-path keys as inputs; or ``"idealised"`` -- the default brake's pad on a rigid
rotor (one face), condensed (:class:`brakewear.CondensedInterface`), the only one
whose mesh layers and element order the settings change.

Run ``python studies/cleaning_routine.py --decels 0.5 0.75 1 1.5 2 3 --speeds 50 80 100
--samples 200 --out docs`` (``--dask ADDRESS|local`` for a cluster).
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from concurrent.futures import Executor
from dataclasses import replace
from pathlib import Path

import numpy as np

from brakewear import MATERIALS, SolverError, WearLaw, load_geometry
from brakewear.cleaning.corrosion import nonconformity_gap
from brakewear.duty import KMH, repeated_stops, study_car
from brakewear.cleaning.routine import run_routine
from brakewear.cleaning.rust import RUST_PRIORS, Prior, RustLaw, RustLayer
from brakewear.thermal.reduced import HAT_CONING_PER_K
from brakewear.wear import Numerics

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cleaning_stops import wilson  # noqa: E402
from sweep_executor import add_executor_options, study_executor  # noqa: E402

logger = logging.getLogger("cleaning_routine")

DEFAULTS = dict(stops=20, interval=120.0, brake="caliper", size=4.0, order=1,
                friction_layers=None, backplate_layers=None, dp_tol=0.05, touch=0.02,
                heat=True, blocks=3, load_path=None)

#: the pad modulus is sampled on these levels (x the resin's; one condensation each)
PAD_MODULUS_LEVELS = (0.7, 1.0, 1.4)

#: the inputs besides the rust law's: name -> Prior (study units are SI)
OTHER_PRIORS = {
    "mu": Prior("normal", 0.40, 0.03, "",
                "one pad type's friction on iron: 0.34-0.46 at two standard deviations within "
                "the 0.3-0.5 of passenger-car pads (references.md)"),
    "coning": Prior("uniform", 15e-6, 45e-6, "m",
                    "estimate: the static non-conformity of a rotor and pad, 15-45 um across "
                    "the pad (cleaning.md)"),
    "thermal_coning_factor": Prior("uniform", 0.8, 1.2, "",
                                   "estimate: the elastic hat rotor's thermal coning (the 3D FE "
                                   "2-4 % above the converged section model, thermal.md) "
                                   "+-20 % for other hats and their expansion"),
    "convection_factor": Prior("uniform", 1.0, 3.0, "",
                               "estimate: the laminar rotating disc (SpeedConvection.solid, "
                               "thermal.md) is the least a rotor sheds; a wheel housing's air "
                               "flow and radiation (6-18 W/m2K at 200-400 C, eps 0.6) add up "
                               "to as much again or twice"),
    "pad_modulus": Prior("lognormal", 1.0, 0.25, "",
                         "estimate: friction materials span 1-15 GPa (references.md); one pad "
                         "type's modulus a factor 0.5-1.9 of the resin's, sampled on the levels "
                         "0.7, 1.0, 1.4"),
    "mass": Prior("uniform", 1600.0, 2100.0, "kg", "references.md, 'The study's car'"),
    "rolling_resistance": Prior("uniform", 0.0065, 0.012, "", "references.md, 'The study's car'"),
    "drag_area": Prior("uniform", 0.50, 0.72, "m^2", "references.md, 'The study's car'"),
    "drivetrain_drag": Prior("uniform", 10.0, 80.0, "N", "references.md, 'The study's car'"),
}


def inputs(brake: str = "caliper") -> dict:
    """The uncertain inputs: name -> :class:`~brakewear.cleaning.rust.Prior` (the rust law's, the
    others of :data:`OTHER_PRIORS`, and for ``brake = "caliper"`` the load path's keys,
    uniform over their plausible ranges)."""
    out = {**RUST_PRIORS, **OTHER_PRIORS}
    if brake == "caliper":
        out.update(_load_path_priors())
    return out


def _load_path_priors() -> dict:
    """The load path's keys of the geometry file, uniform over their plausible ranges
    (``brakewear.geometry.sections.LOAD_PATH_KEYS``, in the file's units)."""
    import cleaning_stops as cs

    cases = cs.load_path_cases()
    keys = sorted({k for c in cases.values() for k in c})
    out = {}
    for k in keys:
        lo, hi = cases[f"{k} low"][k], cases[f"{k} high"][k]
        out[f"load_path:{k}"] = Prior("uniform", lo, hi, "file units",
                                      "the plausible range of docs/load_path.md")
    return out


def draw(n: int, seed: int = 37, brake: str = "caliper") -> list[dict]:
    """``n`` independent draws of :func:`inputs` (their probabilities from a seeded
    generator, through each prior's inverse distribution)."""
    pri = inputs(brake)
    u = np.random.default_rng(seed).random((n, len(pri)))
    return [values(dict(zip(pri, row)), pri) for row in u]


def values(u: dict, priors: dict | None = None) -> dict:
    """The inputs at probabilities ``u`` (name -> 0..1)."""
    pri = inputs() if priors is None else priors
    return {k: float(pri[k].sample(np.array([p]))[0]) for k, p in u.items()}


def medians(brake: str = "caliper") -> dict:
    """Every input at its median."""
    return values({k: 0.5 for k in inputs(brake)}, inputs(brake))


# ------------------------------------------------------------------ one sample --
_BUILT: dict = {}


def _level(modulus: float) -> float:
    levels = np.array(PAD_MODULUS_LEVELS)
    return float(levels[np.argmin(np.abs(np.log(levels / modulus)))])


def _brake(task: dict):
    """``(model, interface)`` of a task, one per worker and brake (the condensation from
    the cache)."""
    level = _level(task.get("pad_modulus", 1.0))
    lp = {k.split(":", 1)[1]: v for k, v in task.items() if k.startswith("load_path:")}
    key = (task["brake"], task["size"], task["order"], task["friction_layers"],
           task["backplate_layers"], level)
    if task["brake"] == "caliper":
        import cleaning_stops as cs
        t = dict(geometry="floating", size=task["size"], pad_modulus=level, mu=0.4,
                 interface="condensed", load_path=lp or None)
        return cs.task_interface(t)
    if key not in _BUILT:
        from brakewear import BrakeModel, CondensedInterface
        import cleaning_stops as cs
        g = cs.task_geometry(level, "default")
        mesh = replace(g.mesh, order=task["order"],
                       friction_layers=task["friction_layers"],
                       backplate_layers=task["backplate_layers"])
        model = BrakeModel(replace(g, mesh=mesh), size=task["size"] * 1e-3, rotor="rigid")
        _BUILT.clear()
        _BUILT[key] = (model, CondensedInterface(model, 1e6, 0.4))
    return _BUILT[key]


def _reduced(task: dict):
    """The floating caliper's hat rotor, reduced (one per worker), from ambient."""
    key = ("heat", task["size"], task["blocks"])
    if key not in _BUILT:
        from brakewear import BrakeModel
        from brakewear.thermal import SpeedConvection, ThermalModel
        from brakewear.thermal.reduced import ReducedRotorHeat
        g = load_geometry("floating")
        m = BrakeModel(g, size=task["size"] * 1e-3, layout="full", rotor="elastic")
        th = ThermalModel(m, h_conv={"pad": 40.0, "rotor": SpeedConvection.solid()})
        from brakewear.thermal.coning import RotorConing
        band = (g.pad.inner_radius, g.pad.outer_radius)
        heat = ReducedRotorHeat(th, band=band, blocks=task["blocks"])
        heat.add_coning(RotorConing(th, band))
        _BUILT[key] = heat
    heat = _BUILT[key]
    heat.restore((np.zeros_like(heat.a), 0.0))
    heat.convection_factor = task.get("convection_factor", 1.0)
    return heat


def _judge(itf, r_in, r_out, thickness, threshold):
    """The cleaning criterion: per face where the brake models both."""
    import brakewear.cleaning.corrosion as cl
    if hasattr(cl, "BandCriterion"):
        return cl.BandCriterion(itf, r_in, r_out, thickness, threshold)
    c = cl.CorrodedRotor(itf, r_in, r_out, thickness, 1.0, 1.0, threshold)
    c.cleaned_fractions = lambda w: {"in": c.cleaned_fraction(w)}
    c.touched_fractions = lambda p: {"in": c.touched_fraction(p)}
    return c


def run_sample(task: dict) -> dict:
    """One routine (``task``: :data:`DEFAULTS`, the inputs, ``decel`` m/s^2 and
    ``speed`` km/h); a solver failure returns its error (counted as not cleaned)."""
    from threadpoolctl import threadpool_limits

    try:
        with threadpool_limits(limits=1, user_api="blas"):
            return _run_sample(task)
    except SolverError as e:
        logger.warning("sample failed: %s", e)
        return {"error": f"{type(e).__name__}: {e}", "stops_to_clean": None, "cleaned": []}


def _run_sample(task: dict) -> dict:
    t0 = time.perf_counter()
    model, itf = _brake(task)
    g = model.geometry
    r_in, r_out = g.pad.inner_radius, g.pad.outer_radius
    law = RustLaw(**{k: task[k] for k in RUST_PRIORS})
    rust = RustLayer(itf, law, MATERIALS["grey_cast_iron"].wear_k,
                     WearLaw(MATERIALS["pad_resin"].wear_k))
    judge = _judge(itf, r_in, r_out, law.thickness, task["touch"] * 1e6)
    car = study_car(**{k: task[k] for k in ("mass", "rolling_resistance", "drag_area",
                                            "drivetrain_drag")}).with_friction_share(1.0)
    v0 = task["speed"] * KMH
    sched = repeated_stops(task["stops"], v0, decel=task["decel"], interval=task["interval"],
                           dwell_speed=v0)
    gap0 = nonconformity_gap(itf.x, r_in, r_out, g.rotor.thickness, task["coning"])
    heat = _reduced(task) if task["heat"] else None
    num = Numerics(scheme="implicit", max_dh=0.1 * law.thickness, dp_tol=task["dp_tol"])
    cleaned, touched, rows = [], [], []
    for res in run_routine(model, itf, sched, car, rust, task["mu"], numerics=num, gap0=gap0,
                           heat=heat,
                           coning_per_k=task["thermal_coning_factor"] * HAT_CONING_PER_K):
        rec = res.record
        if rec.kind != "stop":
            continue
        faces = judge.cleaned_fractions(rec.rotor_wear)
        cleaned.append(min(faces.values()))
        touched.append(min(judge.touched_fractions(rec.pressure).values()))
        rows.append({"line_pressure_MPa": rec.line_pressure / 1e6, "mu": res.mu,
                     "thermal_coning_um": res.thermal_coning * 1e6,
                     "T_ring_C": None if res.T_ring is None else res.T_ring - 273.15,
                     "T_hat_C": None if res.T_hat is None else res.T_hat - 273.15,
                     "face_kJ": rec.target_face_J / 1e3, "drift": rec.torque_drift,
                     "faces": faces})
        if cleaned[-1] >= 1.0:
            break
    clean = next((i + 1 for i, c in enumerate(cleaned) if c >= 1.0), None)
    return {"stops_to_clean": clean, "cleaned": cleaned, "touched": touched, "rows": rows,
            "run_s": time.perf_counter() - t0}


# ---------------------------------------------------------------- the curve --
def _key(task: dict) -> str:
    import hashlib
    return hashlib.sha1(json.dumps(task, sort_keys=True, default=str).encode()).hexdigest()


def map_tasks(tasks: list, executor: Executor | None, workers: int = 2,
              journal: Path | None = None) -> list:
    """:func:`run_sample` of every task on ``executor`` (default: a process pool).  With
    ``journal`` (a JSON-lines file) each result is appended as it arrives and the tasks
    already there are not run again: a long sweep resumes where it stopped."""
    done = {}
    if journal is not None and Path(journal).exists():
        for line in Path(journal).read_text().splitlines():
            if line.strip():
                d = json.loads(line)
                done[d["key"]] = d["result"]
    keys = [_key(t) for t in tasks]
    todo = [t for t, k in zip(tasks, keys) if k not in done]
    own = executor is None
    ctx = study_executor(None, workers) if own else None
    ex = ctx.__enter__() if own else executor
    try:
        chunk = {"chunksize": max(1, len(todo) // (8 * workers))} if own else {}
        fh = open(journal, "a") if journal is not None else None
        try:
            for t, r in zip(todo, ex.map(run_sample, todo, **chunk)):
                k = _key(t)
                done[k] = r
                if fh is not None:
                    fh.write(json.dumps({"key": k, "result": r}) + "\n")
                    fh.flush()
        finally:
            if fh is not None:
                fh.close()
    finally:
        if own:
            ctx.__exit__(None, None, None)
    return [done[k] for k in keys]


def design_curve(decels, speeds, n: int = 200, executor: Executor | None = None, out=None,
                 seed: int = 37, targets=(0.9, 0.95), **settings) -> dict:
    """P(clean within N stops) at every deceleration (m/s^2) and speed (km/h) over the
    same ``n`` draws of the inputs; the routines reaching ``targets``.  Writes
    ``data/cleaning_routine.json`` and the figures to ``out``, and each run as it
    ends to ``data/cleaning_routine_runs.jsonl`` (run again, the runs there are
    taken from it: a long sweep resumes).  The wall time then counts this call's
    runs only; ``cost_per_sample_s`` is the runs' own mean."""
    st = {**DEFAULTS, **settings}
    unknown = set(settings) - set(DEFAULTS)
    if unknown:
        raise ValueError(f"settings {sorted(unknown)} are not allowed; allowed: "
                         f"{', '.join(DEFAULTS)}")
    samples = draw(n, seed, st["brake"])
    grid = [(float(v), float(a)) for v in speeds for a in sorted(decels)]
    tasks = [dict(st, **x, decel=a, speed=v) for v, a in grid for x in samples]
    t0 = time.perf_counter()
    journal = None
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        journal = Path(out) / "data" / "cleaning_routine_runs.jsonl"
    runs = map_tasks(tasks, executor, journal=journal)
    wall = time.perf_counter() - t0
    points = []
    for j, (v, a) in enumerate(grid):
        rr = runs[j * n:(j + 1) * n]
        s2c = [r["stops_to_clean"] for r in rr]
        p = [sum(s is not None and s <= N for s in s2c) / n for N in range(1, st["stops"] + 1)]
        points.append({"speed": v, "decel": a, "stops_to_clean": s2c, "P": p,
                       "interval_95": [wilson(round(x * n), n) for x in p],
                       "failed": sum("error" in r for r in rr),
                       "cleaned_last": [r["cleaned"][-1] if r["cleaned"] else 0.0 for r in rr],
                       "line_pressure_MPa": float(np.median([r["rows"][0]["line_pressure_MPa"]
                                                            for r in rr if r.get("rows")])),
                       "thermal_coning_um_max": float(np.max(
                           [max((x["thermal_coning_um"] for x in r["rows"]), default=0.0)
                            for r in rr if r.get("rows")] or [0.0]))})
    times = [r["run_s"] for r in runs if "run_s" in r]
    result = {"settings": st, "samples": n, "seed": seed, "inputs": list(inputs(st["brake"])),
              "draws": samples, "points": points,
              "routines": {str(t): routine(points, t) for t in targets},
              "cost_per_sample_s": float(np.mean(times)) if times else None,
              "wall_s": wall, "runs": len(tasks)}
    if out is not None:
        write(result, Path(out))
    return result


def routine(points: list, target: float) -> dict | None:
    """The routine reaching P >= ``target``: the fewest stops, then the lowest
    deceleration, then the lowest speed; ``None`` if none does."""
    best = None
    for pt in points:
        N = next((i + 1 for i, p in enumerate(pt["P"]) if p >= target), None)
        if N is None:
            continue
        key = (N, pt["decel"], pt["speed"])
        if best is None or key < best[0]:
            best = (key, pt, N)
    if best is None:
        return None
    _, pt, N = best
    lo, hi = pt["interval_95"][N - 1]
    return {"stops": N, "speed_kmh": pt["speed"], "decel": pt["decel"], "P": pt["P"][N - 1],
            "interval_95": [lo, hi], "line_pressure_MPa": pt["line_pressure_MPa"],
            "words": f"{N} friction-only stops from {pt['speed']:g} km/h at "
                     f"{pt['decel']:g} m/s^2, {DEFAULTS['interval']:g} s apart"}


def write_result(out, name: str, result: dict, plot=None) -> None:
    """``data/<name>.json`` and, with ``plot``, ``figures/<name>.png`` in ``out``."""
    out = Path(out)
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / f"{name}.json").write_text(json.dumps(result, indent=1))
    if plot is not None:
        (out / "figures").mkdir(parents=True, exist_ok=True)
        plot(result, out / "figures" / f"{name}.png")


def write(result: dict, out: Path, name: str = "cleaning_routine") -> None:
    write_result(out, name, result, plot_curve)


def plot_curve(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pts, N = result["points"], result["settings"]["stops"]
    speeds = sorted({p["speed"] for p in pts})
    fig, axes = plt.subplots(1, len(speeds) + 2, figsize=(4.2 * (len(speeds) + 2), 4))
    for ax, v in zip(axes, speeds):
        row = [p for p in pts if p["speed"] == v]
        a = [p["decel"] for p in row]
        M = np.array([p["P"] for p in row]).T
        im = ax.imshow(M * 100, origin="lower", aspect="auto", cmap="viridis", vmin=0,
                       vmax=100, extent=(-0.5, len(a) - 0.5, 0.5, N + 0.5))
        cs = ax.contour(np.arange(len(a)), np.arange(1, N + 1), M, levels=[0.9, 0.95],
                        colors=["w", "r"], linewidths=1)
        ax.clabel(cs, fmt={0.9: "0.9", 0.95: "0.95"}, fontsize=7)
        ax.set_xticks(range(len(a)), [f"{x:g}" for x in a])
        ax.set(xlabel="deceleration (m/s^2)", ylabel="stops",
               title=f"P(clean) (%), stops from {v:g} km/h")
    fig.colorbar(im, ax=axes[len(speeds) - 1])
    bx, cx = axes[-2], axes[-1]
    for v in speeds:
        row = [p for p in pts if p["speed"] == v]
        a = [p["decel"] for p in row]
        q = np.array([np.quantile(p["cleaned_last"], (0.1, 0.5, 0.9)) for p in row])
        ln, = cx.plot(a, q[:, 1], "o-", label=f"{v:g} km/h, median")
        cx.fill_between(a, q[:, 0], q[:, 2], color=ln.get_color(), alpha=0.15)
    cx.set(xlabel="deceleration (m/s^2)", ylabel=f"worse face's band cleaned, {N} stops",
           ylim=(-0.02, 1.02), title="cleaned share (median, 10-90 %)")
    cx.legend(fontsize=8)
    for v in speeds:
        row = [p for p in pts if p["speed"] == v]
        a = [p["decel"] for p in row]
        P = [p["P"][-1] for p in row]
        lo = [p["interval_95"][-1][0] for p in row]
        hi = [p["interval_95"][-1][1] for p in row]
        bx.errorbar(a, P, yerr=[np.array(P) - lo, np.array(hi) - P], marker="o", capsize=3,
                    label=f"{v:g} km/h")
    bx.axhline(0.9, color="k", ls="--", lw=0.8)
    bx.axhline(0.95, color="r", ls="--", lw=0.8)
    bx.set(xlabel="deceleration (m/s^2)", ylabel=f"P(clean within {N} stops)", ylim=(-0.02, 1.02),
           title=f"{result['samples']} samples each, 95 % intervals")
    bx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--decels", type=float, nargs="+", default=[0.5, 0.75, 1.0, 1.5, 2.0, 3.0])
    ap.add_argument("--speeds", type=float, nargs="+", default=[50.0, 80.0, 100.0])
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--stops", type=int, default=DEFAULTS["stops"])
    ap.add_argument("--brake", choices=("idealised", "caliper"), default=DEFAULTS["brake"])
    ap.add_argument("--size", type=float, default=DEFAULTS["size"])
    ap.add_argument("--no-heat", dest="heat", action="store_false")
    ap.add_argument("--out", default=None)
    add_executor_options(ap)
    a = ap.parse_args(argv)
    with study_executor(a.dask, a.workers) as ex:
        r = design_curve(a.decels, a.speeds, a.samples, executor=ex, out=a.out, stops=a.stops,
                         brake=a.brake, size=a.size, heat=a.heat)
    for t, rt in r["routines"].items():
        print(f"P >= {t}: " + ("none in the grid" if rt is None else
                              f"{rt['words']} (P = {rt['P']:.3f}, 95 % {rt['interval_95'][0]:.3f}"
                              f"..{rt['interval_95'][1]:.3f})"))
    print(f"{r['runs']} runs, {r['cost_per_sample_s']:.2f} s per sample, {r['wall_s']:.0f} s")
    return r


if __name__ == "__main__":
    logging.basicConfig(level=logging.WARNING)
    _cli()
