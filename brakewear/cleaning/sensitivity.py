"""What decides a routine: variance-based sensitivity (Sobol indices) and the tornado.

:func:`sobol_indices` samples the inputs by SALib's Sobol sequence (Saltelli's
scheme: ``N (D + 2)`` evaluations for ``D`` inputs) in probability space --
each input's probability turned into its value by its prior's inverse
distribution -- and gives the first-order and total indices with their 95 %
bootstrap intervals (``SALib.analyze.sobol``).  :func:`routine_sobol` does so
for one routine's outputs: the chosen criterion's value after the routine's
stops (1 once met) and whether it is met.  :func:`tornado` moves one input at
a time to its prior's 5 % and 95 % points, the others at their medians.

SALib is optional (``pip install "brakewear[study]"``); it is imported only here.
"""
from __future__ import annotations

import logging
from collections.abc import Callable
from concurrent.futures import Executor

import numpy as np

from ..errors import DependencyError

logger = logging.getLogger(__name__)

__all__ = ["sobol_indices", "routine_outputs", "routine_sobol", "tornado", "widest_interval"]


def sobol_indices(names: list, priors: dict, model: Callable, n_base: int, seed: int = 11,
                  num_resamples: int = 1000) -> dict:
    """SALib's Sobol indices of ``model`` over ``priors``.

    Parameters
    ----------
    names
        The inputs, each a key of ``priors``.
    priors
        name -> :class:`~brakewear.cleaning.rust.Prior`.
    model
        A function of a list of input dicts returning ``{output: array}``.
    n_base
        Saltelli's base sample size ``N`` (a power of two).
    seed, num_resamples
        The sequence's scrambling seed and the bootstrap's resamples.

    Returns
    -------
    dict
        ``{"indices": {output: {input: {S1, S1_conf, ST, ST_conf}}}, "inputs", "outputs"}``,
        the ``_conf`` the 95 % bootstrap half-widths.
    """
    try:
        from SALib.analyze import sobol as analyze
        from SALib.sample import sobol as sample
    except ImportError:
        raise DependencyError("Sobol indices need SALib: pip install 'brakewear[study]'") from None
    problem = {"num_vars": len(names), "names": list(names), "bounds": [[0.0, 1.0]] * len(names)}
    U = sample.sample(problem, n_base, calc_second_order=False, scramble=True, seed=seed)
    # the inverse distributions are infinite at 0 and 1 (normal, lognormal)
    U = np.clip(U, 0.5 / (n_base * 64), 1.0 - 0.5 / (n_base * 64))
    xs = [{k: float(priors[k].sample(np.array([u]))[0]) for k, u in zip(names, row)}
          for row in U]
    Y = model(xs)
    out = {}
    for key, y in Y.items():
        y = np.asarray(y, dtype=float)
        if np.ptp(y) == 0:             # no variance: no index to give
            out[key] = {k: dict(S1=0.0, S1_conf=0.0, ST=0.0, ST_conf=0.0) for k in names}
            continue
        r = analyze.analyze(problem, y, calc_second_order=False, num_resamples=num_resamples,
                            conf_level=0.95, seed=seed)
        out[key] = {k: {s: float(r[s][i]) for s in ("S1", "S1_conf", "ST", "ST_conf")}
                    for i, k in enumerate(names)}
    return {"indices": out, "inputs": xs, "outputs": {k: np.asarray(v).tolist()
                                                      for k, v in Y.items()}}


def widest_interval(indices: dict) -> float:
    """The widest 95 % interval (twice the half-width) of any index of any output."""
    return max(2 * v[s] for out in indices.values() for v in out.values()
               for s in ("S1_conf", "ST_conf"))


def routine_outputs(runs: list, stops: int, chosen: str) -> dict:
    """The chosen criterion's value after ``stops`` (1 once met; a failed run 0) and
    whether it is met within them."""
    share, met = [], []
    for r in runs:
        n = r.get("stops_to_clean")
        vals = r.get("criteria", {}).get(chosen, {}).get("values", [])
        done = n is not None and n <= stops
        share.append(1.0 if done else (vals[min(stops, len(vals)) - 1] if vals else 0.0))
        met.append(float(done))
    return {"criterion_value": share, "cleaned": met}


def routine_sobol(priors: dict, speed_kmh: float, decel: float, interval: float, stops: int,
                  settings, car, n_base: int = 128, seed: int = 11,
                  ex: Executor | None = None, journal=None, progress=None) -> dict:
    """Sobol indices of one routine (see the module); ``failed``: runs whose solver
    failed (counted as not cleaned)."""
    from .sweep import map_tasks, routine_task

    names = list(priors)
    failed = []

    def model(xs):
        tasks = [routine_task(x, speed_kmh, decel, interval, stops, settings, car) for x in xs]
        runs = map_tasks(tasks, ex, journal=journal, progress=progress)
        failed.extend(r["error"] for r in runs if "error" in r)
        return routine_outputs(runs, stops, settings.criteria.chosen)

    res = sobol_indices(names, priors, model, n_base, seed)
    res.update(failed=len(failed), errors=failed[:5], runs=len(res["inputs"]),
               widest_interval=widest_interval(res["indices"]))
    return res


def tornado(priors: dict, medians: dict, run: Callable, quantiles=(0.05, 0.95)) -> list:
    """Each input at its prior's ``quantiles``, the others at ``medians``: ``run``
    (a function of a list of input dicts returning one output each) of every case,
    as rows ``{input, quantile, value, output}`` (the first the medians')."""
    cases = [("median", None, None)] + [(k, q, float(priors[k].sample(np.array([q]))[0]))
                                        for k in priors for q in quantiles]
    xs = [{**medians, **({} if k == "median" else {k: v})} for k, q, v in cases]
    ys = run(xs)
    return [{"input": k, "quantile": q, "value": v, "output": y}
            for (k, q, v), y in zip(cases, ys)]
