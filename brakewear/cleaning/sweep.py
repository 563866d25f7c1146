"""The design curve: P(clean within N stops) over the routines a car maker may program.

Every routine of a grid (speed, deceleration, spacing) runs on the same draws
of the inputs (:func:`~brakewear.cleaning.priors.draw`), each run one task
(:func:`~brakewear.cleaning.sample.run_routine`) on any
``concurrent.futures.Executor`` -- a process pool, or a dask.distributed
client's executor (:func:`executor`).  A journal (JSON lines) keeps each
result as it arrives, so a long sweep resumes where it stopped.

Per routine: P(clean within N stops) for every N (the chosen criterion,
:mod:`~brakewear.cleaning.criteria`) with its Wilson interval, the runs that
failed (counted as not cleaned, and reported), the first stop's line pressure
and each candidate criterion's P.  :func:`best_routine` picks the routine
that reaches a probability: the fewest stops, then the lowest deceleration,
then the lowest speed (then the longest spacing).
"""
from __future__ import annotations

import hashlib
import json
import logging
import time
from collections.abc import Callable, Iterator
from concurrent.futures import Executor, ProcessPoolExecutor
from contextlib import contextmanager
from dataclasses import asdict
from pathlib import Path

import numpy as np

from ..duty import KMH
from .criteria import CRITERIA

logger = logging.getLogger(__name__)

__all__ = ["wilson", "executor", "map_tasks", "design_curve", "curve_point", "best_routine",
           "routine_task", "run_task", "prepare_task", "prepare"]


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score interval (95 % by default) of a probability seen ``k`` times
    in ``n``."""
    if n == 0:
        return 0.0, 1.0
    p = k / n
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return max(0.0, float(c - h)), min(1.0, float(c + h))


@contextmanager
def executor(dask: str | None = None, workers: int = 2) -> Iterator[Executor]:
    """A ``ProcessPoolExecutor(workers)``, or with ``dask`` a dask.distributed
    client's executor (a scheduler address, or ``"local"``: a local cluster of
    ``workers`` single-threaded processes, closed on leaving).  dask is optional,
    imported only then."""
    if not dask:
        with ProcessPoolExecutor(max_workers=workers) as ex:
            yield ex
        return
    from dask.distributed import Client

    kw = dict(n_workers=workers, threads_per_worker=1, processes=True,
              dashboard_address=None)
    with (Client(**kw) if dask == "local" else Client(dask)) as client:
        yield client.get_executor()


def routine_task(draw: dict, speed_kmh: float, decel: float, interval: float, stops: int,
                 settings, car) -> dict:
    """One task: a draw, a routine and how to run it (plain data, picklable)."""
    return {"draw": draw, "speed_kmh": float(speed_kmh), "decel": float(decel),
            "interval": float(interval), "stops": int(stops),
            "settings": asdict(settings), "car": asdict(car)}


def run_task(task: dict) -> dict:
    """:func:`~brakewear.cleaning.sample.run_routine` of a :func:`routine_task`."""
    from ..duty import Vehicle
    from .criteria import CriteriaSettings
    from .routine import Routine
    from .sample import RoutineSettings, run_routine

    st = dict(task["settings"])
    st["criteria"] = CriteriaSettings(**st["criteria"])
    routine = Routine(task["stops"], task["speed_kmh"] * KMH, task["decel"], task["interval"])
    return run_routine(task["draw"], routine, Vehicle(**task["car"]), RoutineSettings(**st))


def prepare_task(task: dict) -> dict:
    """Build what the routines of a task's draw share -- its brake's condensations (the
    caliper's and, bedded, the pads held square with their bedded state) and the reduced
    rotor -- into the disk caches; returns the seconds it took."""
    from ..duty import Vehicle
    from ..materials import MATERIALS
    from .brake import cleaning_brake, reduced_rotor
    from .criteria import CriteriaSettings
    from .sample import RoutineSettings, _bedded_reference

    t0 = time.perf_counter()
    st = dict(task["settings"])
    st["criteria"] = CriteriaSettings(**st["criteria"])
    settings = RoutineSettings(**st)
    draw = task["draw"]
    model, _ = cleaning_brake(draw, settings.geometry, settings.size)
    if settings.start == "bedded":
        g = model.geometry
        car = Vehicle(**task["car"]).with_friction_share(1.0)
        _bedded_reference(draw, settings, car, draw.get("mu", 0.4),
                          MATERIALS["pad_resin"].wear_k, MATERIALS["grey_cast_iron"].wear_k,
                          (g.pad.inner_radius, g.pad.outer_radius), g.rotor.thickness)
    if settings.heat:
        reduced_rotor(settings.geometry, settings.size, settings.blocks)
    return {"seconds": time.perf_counter() - t0}


def prepare(draws: list, settings, car, ex: Executor | None = None, workers: int = 2,
            progress: Callable | None = None) -> int:
    """:func:`prepare_task` once for each brake the draws use (their levels and
    friction to 0.05), on ``ex``: the routines that follow read it from the caches.
    ``progress(done, total)`` is called as each brake is built; returns their count."""
    from .brake import brake_levels

    seen, tasks = set(), []
    for d in draws:
        key = (brake_levels(d), round(d.get("mu", 0.4) / 0.05))
        if key not in seen:
            seen.add(key)
            tasks.append(routine_task(d, 50.0, 1.0, 120.0, 1, settings, car))
    logger.info("building %d brakes' condensations and bedded states", len(tasks))
    map_tasks(tasks, ex, workers=workers, function=prepare_task, progress=progress)
    return len(tasks)


def _key(task: dict) -> str:
    return hashlib.sha1(json.dumps(task, sort_keys=True, default=str).encode()).hexdigest()


def map_tasks(tasks: list, ex: Executor | None = None, *, journal: Path | None = None,
              progress: Callable | None = None, workers: int = 2,
              function: Callable = run_task) -> list:
    """``function`` of every task on ``ex`` (default: a process pool of ``workers``),
    in the tasks' order.  ``journal``: a JSON-lines file each result is appended
    to as it arrives; tasks already there are not run again.  ``progress``:
    called with ``(done, total)`` as results arrive."""
    done = {}
    if journal is not None and Path(journal).exists():
        for line in Path(journal).read_text().splitlines():
            if line.strip():
                d = json.loads(line)
                done[d["key"]] = d["result"]
    keys = [_key(t) for t in tasks]
    todo = [(k, t) for k, t in zip(keys, tasks) if k not in done]
    if progress is not None:
        progress(len(tasks) - len(todo), len(tasks))
    if todo:
        with (_own(workers) if ex is None else _given(ex)) as run_on:
            fh = open(journal, "a") if journal is not None else None
            try:
                futures = {run_on.submit(function, t): k for k, t in todo}
                from concurrent.futures import as_completed
                for fut in as_completed(futures):
                    k = futures[fut]
                    done[k] = fut.result()
                    if fh is not None:
                        fh.write(json.dumps({"key": k, "result": done[k]}) + "\n")
                        fh.flush()
                    if progress is not None:
                        progress(sum(kk in done for kk in keys), len(tasks))
            finally:
                if fh is not None:
                    fh.close()
    return [done[k] for k in keys]


@contextmanager
def _own(workers: int):
    with ProcessPoolExecutor(max_workers=workers) as ex:
        yield ex


@contextmanager
def _given(ex):
    yield ex


def curve_point(runs: list, stops: int, chosen: str) -> dict:
    """P(clean within N) for N = 1..``stops`` of one routine's runs (a failed run counts
    as not cleaned), its Wilson intervals, and each candidate's P after ``stops``."""
    n = len(runs)
    s2c = [r.get("stops_to_clean") for r in runs]
    P = [sum(s is not None and s <= N for s in s2c) / n for N in range(1, stops + 1)]
    others = {}
    for c in CRITERIA:
        met = [r.get("criteria", {}).get(c, {}).get("stops_to_meet") for r in runs]
        others[c] = sum(m is not None for m in met) / n
    rows = [r["rows"][0] for r in runs if r.get("rows")]
    return {"stops_to_clean": s2c, "P": P,
            "interval_95": [wilson(round(p * n), n) for p in P],
            "failed": sum("error" in r for r in runs),
            "errors": [r["error"] for r in runs if "error" in r][:5],
            "P_by_criterion": others, "chosen": chosen,
            "line_pressure_MPa": float(np.median([x["line_pressure_MPa"] for x in rows]))
            if rows else None,
            "run_s": [r.get("run_s") for r in runs]}


def best_routine(points: list, target: float) -> dict | None:
    """The routine reaching P >= ``target``: the fewest stops, then the lowest
    deceleration, then the lowest speed, then the longest spacing; None if none."""
    best = None
    for pt in points:
        N = next((i + 1 for i, p in enumerate(pt["P"]) if p >= target), None)
        if N is None:
            continue
        key = (N, pt["decel"], pt["speed_kmh"], -pt["interval"])
        if best is None or key < best[0]:
            best = (key, pt, N)
    if best is None:
        return None
    _, pt, N = best
    lo, hi = pt["interval_95"][N - 1]
    return {"stops": N, "speed_kmh": pt["speed_kmh"], "decel": pt["decel"],
            "interval": pt["interval"], "P": pt["P"][N - 1], "interval_95": [lo, hi],
            "line_pressure_MPa": pt["line_pressure_MPa"],
            "words": f"{N} friction-only stop{'s' if N != 1 else ''} from "
                     f"{pt['speed_kmh']:g} km/h at {pt['decel']:g} m/s^2, "
                     f"{pt['interval']:g} s apart"}


def design_curve(draws: list, speeds, decels, intervals, stops: int, settings, car, *,
                 ex: Executor | None = None, journal: Path | None = None,
                 progress: Callable | None = None, targets=(0.9, 0.95),
                 workers: int = 2, prepared: Callable | None = None) -> dict:
    """Every routine of the grid on the same ``draws`` (see the module).

    Parameters
    ----------
    draws
        The inputs' draws (:func:`~brakewear.cleaning.priors.draw`).
    speeds, decels, intervals
        The grid: km/h, m/s^2, s (start to start).
    stops
        The most stops of a routine.
    settings, car
        :class:`~brakewear.cleaning.sample.RoutineSettings` and the
        :class:`~brakewear.duty.Vehicle`.
    ex, journal, progress, workers
        As :func:`map_tasks`.
    prepared
        Called with ``(done, total)`` as each brake is built (:func:`prepare`).
    targets
        The probabilities whose routines are picked (:func:`best_routine`).
    """
    grid = [(float(v), float(a), float(t)) for t in intervals for v in speeds
            for a in sorted(decels)]
    tasks = [routine_task(d, v, a, t, stops, settings, car) for v, a, t in grid for d in draws]
    t0 = time.perf_counter()
    brakes = prepare(draws, settings, car, ex, workers, progress=prepared)
    t_prepare = time.perf_counter() - t0
    runs = map_tasks(tasks, ex, journal=journal, progress=progress, workers=workers)
    wall = time.perf_counter() - t0
    n = len(draws)
    points = []
    for j, (v, a, t) in enumerate(grid):
        pt = curve_point(runs[j * n:(j + 1) * n], stops, settings.criteria.chosen)
        points.append({"speed_kmh": v, "decel": a, "interval": t, **pt})
    times = [r["run_s"] for r in runs if "run_s" in r]
    return {"samples": n, "stops": stops, "points": points,
            "routines": {str(t): best_routine(points, t) for t in targets},
            "failed": sum(p["failed"] for p in points), "runs": len(tasks),
            "cost_per_routine_s": float(np.mean(times)) if times else None,
            "brakes": brakes, "prepare_s": t_prepare,
            "wall_s": wall, "settings": asdict(settings), "car": asdict(car)}
