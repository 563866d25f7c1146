"""The floating caliper's solves over routines drawn from the priors: how many fail.

Each routine is one run of :func:`brakewear.cleaning.sample.run_routine` (the
floating caliper as it holds its pads, both faces, the stops' heat, the rust
law, 20 stops) with its inputs drawn from the priors
(:func:`brakewear.cleaning.priors.draw`; the pads bedded) and its stops drawn
from the design curve's grid (deceleration 0.5-3 m/s^2, 50 / 80 / 100 km/h,
120 or 300 s apart).  A share ``tail`` of the routines is drawn from the
adverse tail instead: a new pad (the labelled scenario) against the static
coning of the top quarter of its prior (beyond 37.5 um), thermal coning above
its median, the slower half of the convection, stops from 100 km/h at 1-3
m/s^2 -- the outboard face's static plus thermal non-conformity then passes
55 um, where the pad's contact resultant reaches the edge of the fingers'
footprint.

Reported: the routines run, those that raised a solver error (the goal is
none), the routines whose outboard non-conformity (static coning plus the
largest thermal coning of its stops) passed 55 um, the wall time and the
routines' own CPU time (median and 90 %).

Run ``python studies/caliper_robustness.py --routines 1000 [--size 4] [--out docs]``.
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from brakewear.cleaning.car import packaged_car
from brakewear.cleaning.priors import cleaning_inputs, draw, values
from brakewear.cleaning.sample import RoutineSettings
from brakewear.cleaning.sweep import executor as sweep_executor
from brakewear.cleaning.sweep import routine_task, run_task

DECELS = (0.5, 0.75, 1.0, 1.5, 2.0, 3.0)
SPEEDS = (50.0, 80.0, 100.0)
INTERVALS = (120.0, 300.0)
STOPS = 20
#: the outboard face's non-conformity (um) beyond which the nested solves used to fail
EDGE_UM = 55.0


def tail_draw(n: int, seed: int) -> list[dict]:
    """``n`` draws of the inputs from the adverse tail (see the module)."""
    pri = cleaning_inputs("new")
    rng = np.random.default_rng(seed)
    u = rng.random((n, len(pri)))
    names = list(pri)
    squeeze = {"coning": (0.75, 1.0), "thermal_coning_factor": (0.5, 1.0),
               "convection_factor": (0.0, 0.5)}
    for k, (a, b) in squeeze.items():
        j = names.index(k)
        u[:, j] = a + (b - a) * u[:, j]
    return [values(dict(zip(names, row)), pri) for row in u]


def tasks(n: int, tail: float = 0.25, seed: int = 37, size: float = 4.0) -> list[dict]:
    """The routines: ``n`` in all, a share ``tail`` of them from the adverse tail."""
    n_tail = int(round(tail * n))
    rng = np.random.default_rng(seed + 1)
    car, out = packaged_car("study"), []
    for x in draw(n - n_tail, seed, cleaning_inputs("bedded")):
        t = routine_task(x, float(rng.choice(SPEEDS)), float(rng.choice(DECELS)),
                         float(rng.choice(INTERVALS)), STOPS,
                         RoutineSettings(size=size * 1e-3, run_to_end=True), car)
        out.append(dict(t, tail=False))
    for x in tail_draw(n_tail, seed + 2):
        t = routine_task(x, 100.0, float(rng.uniform(1.0, 3.0)), 120.0, STOPS,
                         RoutineSettings(size=size * 1e-3, start="new", run_to_end=True), car)
        out.append(dict(t, tail=True))
    return out


def _run(task: dict) -> dict:
    t0 = time.process_time()
    r = run_task({k: v for k, v in task.items() if k != "tail"})
    r["cpu_s"] = time.process_time() - t0
    return r


def main(routines: int = 1000, tail: float = 0.25, executor=None, workers: int = 2,
         out=None, seed: int = 37, progress=None, size: float = 4.0) -> dict:
    """Run the routines (see the module); the figures, written to
    ``data/caliper_robustness.json`` in ``out`` (and each routine, as it ends, to
    ``data/caliper_robustness.jsonl``).  ``progress(done, total, run, wall_s)`` is
    called as each routine ends."""
    todo = tasks(routines, tail, seed, size)
    journal = None
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        journal = (Path(out) / "data" / "caliper_robustness.jsonl").open("w")
    t0 = time.perf_counter()
    own = executor is None
    ctx = sweep_executor(None, workers) if own else None
    ex = ctx.__enter__() if own else executor
    try:
        kw = {"chunksize": 1} if own else {}
        runs = []
        for r in ex.map(_run, todo, **kw):
            runs.append(r)
            if journal is not None:
                t = todo[len(runs) - 1]
                journal.write(json.dumps({"index": len(runs) - 1, "tail": t["tail"],
                                          "cpu_s": r["cpu_s"], "error": r.get("error")}) + "\n")
                journal.flush()
            if progress is not None:
                progress(len(runs), len(todo), r, time.perf_counter() - t0)
    finally:
        if own:
            ctx.__exit__(None, None, None)
        if journal is not None:
            journal.close()
    wall = time.perf_counter() - t0
    failed = [{"index": i, "tail": t["tail"], "decel": t["decel"], "speed": t["speed_kmh"],
               "error": r["error"]} for i, (t, r) in enumerate(zip(todo, runs)) if "error" in r]
    edge = []
    for t, r in zip(todo, runs):
        th = max((row["thermal_coning_um"] for row in r.get("rows", [])), default=0.0)
        edge.append(abs(t["draw"].get("coning", t["draw"].get("static_coning", 0.0))) * 1e6
                    + th)
    cpu = np.array([r["cpu_s"] for r in runs])
    result = {"routines": len(todo), "tail": int(sum(t["tail"] for t in todo)),
              "failed": len(failed), "failures": failed,
              "beyond_edge": int(sum(e > EDGE_UM for e in edge)),
              "nonconformity_um_max": float(max(edge)), "wall_s": wall,
              "cpu_s_median": float(np.median(cpu)), "cpu_s_p90": float(np.quantile(cpu, 0.9)),
              "stops_run": int(sum(len(r.get("rows", [])) for r in runs)),
              "settings": {"size": size, "seed": seed, "tail": tail, "workers": workers}}
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / "caliper_robustness.json").write_text(json.dumps(result, indent=1))
    return result


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--routines", type=int, default=1000)
    ap.add_argument("--tail", type=float, default=0.25)
    ap.add_argument("--size", type=float, default=4.0, help="mm")
    ap.add_argument("--seed", type=int, default=37)
    ap.add_argument("--out", default=None)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--dask", nargs="?", const="local", default=None)
    a = ap.parse_args(argv)
    failed = [0]

    def progress(done, total, run, wall):
        failed[0] += "error" in run
        if done % 25 == 0 or "error" in run:
            print(f"{done}/{total} routines, {failed[0]} failed, {wall:.0f} s"
                  + (f": {run['error'][:160]}" if "error" in run else ""), flush=True)
    with sweep_executor(a.dask, a.workers) as ex:
        r = main(a.routines, a.tail, executor=ex, workers=a.workers, out=a.out, seed=a.seed,
                 progress=progress, size=a.size)
    print(f"{r['routines']} routines ({r['tail']} from the adverse tail, {r['beyond_edge']} "
          f"beyond {EDGE_UM:g} um of outboard non-conformity, at most "
          f"{r['nonconformity_um_max']:.1f} um): {r['failed']} failed; {r['wall_s']:.0f} s wall, "
          f"CPU per routine {r['cpu_s_median']:.2f} s (median), {r['cpu_s_p90']:.2f} s (90 %)")
    for f in r["failures"][:10]:
        print(f"  routine {f['index']} ({'tail' if f['tail'] else 'priors'}, {f['decel']:g} "
              f"m/s^2 from {f['speed']:g} km/h): {f['error'][:200]}")
    return r


if __name__ == "__main__":
    _cli()
