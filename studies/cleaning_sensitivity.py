"""What decides the cleaning routine: variance-based sensitivity (Sobol indices with
bootstrap intervals, SALib) and the tornado, both at the routine's point
(docs/cleaning.md, "What decides the routine").

:func:`sobol` samples the inputs of :func:`cleaning_routine.inputs` by SALib's
Sobol sequence (Saltelli's scheme, ``n_base (D + 2)`` runs for ``D`` inputs)
in probability space -- each input's probability, turned into its value by its
prior's inverse distribution -- and gives SALib's first-order and total
indices with their 95 % bootstrap intervals (``SALib.analyze.sobol``) of two
outputs: the band's cleaned share after the routine's stops (the worse face),
and whether it cleaned (0 or 1).  :func:`tornado` moves one input at a time to
its prior's 5 % and 95 % points, the others at their medians: the Monte
Carlo's own ranges.

SALib is optional (``pip install "brakewear[study]"``).

Run ``python studies/cleaning_sensitivity.py --decel 1.5 --speed 80 --stops 12
--n-base 64 --out docs``.
"""
from __future__ import annotations

import argparse
import sys
import time
from concurrent.futures import Executor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import cleaning_routine as cr  # noqa: E402
from sweep_executor import add_executor_options, study_executor  # noqa: E402


def sobol_indices(names: list, priors: dict, model, n_base: int, seed: int = 11,
                  num_resamples: int = 1000) -> dict:
    """SALib's Sobol indices of ``model`` (a function of a list of input dicts that
    returns one array of outputs per output name, ``{name: array}``) over
    ``priors``: ``{output: {input: {S1, S1_conf, ST, ST_conf}}}`` (the ``_conf``
    the 95 % bootstrap half-widths), and the samples and outputs."""
    from SALib.analyze import sobol as analyze
    from SALib.sample import sobol as sample

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


def _outputs(runs: list, stops: int) -> dict:
    """The cleaned share after ``stops`` (1 once cleaned) and whether it cleaned."""
    return {"cleaned_share": [1.0 if r["stops_to_clean"] is not None and
                              r["stops_to_clean"] <= stops else
                              (r["cleaned"][stops - 1] if len(r["cleaned"]) >= stops else
                               (r["cleaned"][-1] if r["cleaned"] else 0.0)) for r in runs],
            "cleaned": [float(r["stops_to_clean"] is not None and r["stops_to_clean"] <= stops)
                        for r in runs]}


def sobol(decel: float, speed: float, stops: int, n_base: int = 64,
          executor: Executor | None = None, out=None, seed: int = 11, **settings) -> dict:
    """Sobol indices of the routine ``stops`` friction-only stops from ``speed`` km/h at
    ``decel`` m/s^2 (see the module); writes ``data/cleaning_sobol.json``."""
    st = {**cr.DEFAULTS, **settings, "stops": stops}
    pri = cr.inputs(st["brake"])
    names = list(pri)
    t0 = time.perf_counter()

    def model(xs):
        runs = cr.map_tasks([dict(st, **x, decel=decel, speed=speed) for x in xs], executor)
        model.failed = sum("error" in r for r in runs)
        return _outputs(runs, stops)

    res = sobol_indices(names, pri, model, n_base, seed)
    result = {"decel": decel, "speed": speed, "stops": stops, "n_base": n_base,
              "runs": len(res["inputs"]), "failed": model.failed, "settings": st,
              "priors": {k: [p.kind, p.a, p.b, p.unit, p.source] for k, p in pri.items()},
              **res, "wall_s": time.perf_counter() - t0}
    if out is not None:
        cr.write_result(out, "cleaning_sobol", result, plot_sobol)
    return result


def tornado(decel: float, speed: float, stops: int, executor: Executor | None = None,
            out=None, quantiles=(0.05, 0.95), **settings) -> dict:
    """Each input at its prior's ``quantiles``, the others at their medians: the cleaned
    share after ``stops`` and the stops to clean (writes ``data/cleaning_tornado.json``)."""
    st = {**cr.DEFAULTS, **settings, "stops": stops}
    pri = cr.inputs(st["brake"])
    base = cr.medians(st["brake"])
    cases = [("median", None, None)] + [(k, q, float(pri[k].sample(np.array([q]))[0]))
                                        for k in pri for q in quantiles]
    tasks = [dict(st, **{**base, **({} if k == "median" else {k: v})}, decel=decel,
                  speed=speed) for k, q, v in cases]
    runs = cr.map_tasks(tasks, executor)
    outs = _outputs(runs, stops)
    rows = [{"input": k, "quantile": q, "value": v, "cleaned_share": c,
             "stops_to_clean": r["stops_to_clean"], "error": r.get("error")}
            for (k, q, v), c, r in zip(cases, outs["cleaned_share"], runs)]
    result = {"decel": decel, "speed": speed, "stops": stops, "quantiles": list(quantiles),
              "medians": base, "rows": rows}
    if out is not None:
        cr.write_result(out, "cleaning_tornado", result, plot_tornado)
    return result


#: the non-physical choices checked at the routine: name -> settings changed
CHOICES = {"default": {}, "mesh 3 mm": {"size": 3.0},
           "6 + 6 layers": {"friction_layers": 6, "backplate_layers": 6},
           "P2": {"order": 2}, "dp_tol 0.1": {"dp_tol": 0.1}, "dp_tol 0.025": {"dp_tol": 0.025},
           "touch 0.01 MPa": {"touch": 0.01}, "touch 0.05 MPa": {"touch": 0.05}}

#: the same on the floating caliper, whose model takes the mesh size only (its layers
#: and element order are the geometry file's): the mesh halved instead
CALIPER_CHOICES = {"default": {}, "mesh 6 mm": {"size": 6.0}, "mesh 4 mm": {"size": 4.0},
                   "dp_tol 0.1": {"dp_tol": 0.1}, "dp_tol 0.025": {"dp_tol": 0.025},
                   "touch 0.01 MPa": {"touch": 0.01}, "touch 0.05 MPa": {"touch": 0.05}}


def choices(decel: float, speed: float, stops: int, n: int = 100, target: float = 0.9,
            executor: Executor | None = None, out=None, cases=None, seed: int = 37,
            **settings) -> dict:
    """The routine's point under each non-physical choice of :data:`CHOICES` (mesh,
    element order, step control, touch threshold), the same ``n`` draws each: P(clean
    within N) for every N and the fewest stops reaching ``target``; writes
    ``data/cleaning_choices.json``."""
    st = {**cr.DEFAULTS, **settings, "stops": stops}
    if cases is None:
        cases = CALIPER_CHOICES if st["brake"] == "caliper" else CHOICES
    xs = cr.draw(n, seed, st["brake"])
    tasks = [dict(st, **ch, **x, decel=decel, speed=speed) for ch in cases.values() for x in xs]
    t0 = time.perf_counter()
    runs = cr.map_tasks(tasks, executor)
    rows = {}
    for i, name in enumerate(cases):
        rr = runs[i * n:(i + 1) * n]
        s2c = [r["stops_to_clean"] for r in rr]
        P = [sum(s is not None and s <= N for s in s2c) / n for N in range(1, stops + 1)]
        rows[name] = {"settings": cases[name], "P": P, "failed": sum("error" in r for r in rr),
                      "stops_for_target": next((N + 1 for N, p in enumerate(P) if p >= target),
                                               None),
                      "mean_stops_to_clean": float(np.mean([s for s in s2c if s is not None]))
                      if any(s is not None for s in s2c) else None,
                      "cleaned_share_mean": float(np.mean(_outputs(rr, stops)["cleaned_share"])),
                      "run_s": float(np.mean([r.get("run_s", np.nan) for r in rr]))}
    result = {"decel": decel, "speed": speed, "stops": stops, "samples": n, "target": target,
              "cases": rows, "wall_s": time.perf_counter() - t0}
    if out is not None:
        cr.write_result(out, "cleaning_choices", result)
    return result


def plot_sobol(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keys = list(result["indices"])
    fig, axes = plt.subplots(1, len(keys), figsize=(6.5 * len(keys), 0.35 * len(
        result["indices"][keys[0]]) + 1.8), squeeze=False)
    for ax, key in zip(axes[0], keys):
        ind = result["indices"][key]
        names = sorted(ind, key=lambda k: -ind[k]["ST"])
        y = np.arange(len(names))
        for off, s, c in ((-0.18, "S1", "tab:blue"), (0.18, "ST", "tab:red")):
            ax.barh(y + off, [ind[k][s] for k in names], 0.34,
                    xerr=[ind[k][f"{s}_conf"] for k in names], color=c, alpha=0.8,
                    label={"S1": "first order", "ST": "total"}[s], capsize=2)
        ax.set_yticks(y, names, fontsize=8)
        ax.invert_yaxis()
        ax.axvline(0, color="k", lw=0.6)
        ax.set(xlabel="Sobol index (95 % bootstrap interval)",
               title=f"{key.replace('_', ' ')} after {result['stops']} stops")
        ax.legend(fontsize=8)
    fig.suptitle(f"{result['stops']} stops from {result['speed']:g} km/h at "
                 f"{result['decel']:g} m/s^2; {result['runs']} runs", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_tornado(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = result["rows"]
    base = rows[0]["cleaned_share"]
    names = list(dict.fromkeys(r["input"] for r in rows[1:]))
    lo = {r["input"]: r for r in rows[1:] if r["quantile"] == result["quantiles"][0]}
    hi = {r["input"]: r for r in rows[1:] if r["quantile"] == result["quantiles"][1]}
    span = {k: abs(hi[k]["cleaned_share"] - lo[k]["cleaned_share"]) for k in names}
    names.sort(key=lambda k: -span[k])
    fig, ax = plt.subplots(figsize=(8, 0.42 * len(names) + 1.5))
    for i, k in enumerate(names):
        for side, c in ((lo, "tab:blue"), (hi, "tab:red")):
            w = side[k]["cleaned_share"] - base
            ax.barh(i, w, left=base, color=c, alpha=0.8)
            ax.annotate(f"{side[k]['value']:.3g}", (base + w, i), xytext=(3 if w >= 0 else -3, 0),
                        textcoords="offset points", va="center", fontsize=7,
                        ha="left" if w >= 0 else "right")
    ax.axvline(base, color="k", lw=1)
    ax.set_yticks(range(len(names)), names, fontsize=8)
    ax.invert_yaxis()
    ax.set_xlabel(f"band cleaned after {result['stops']} stops (medians: {base:.2f}); blue "
                  f"{result['quantiles'][0]:.0%}, red {result['quantiles'][1]:.0%} point")
    ax.set_title(f"{result['stops']} stops from {result['speed']:g} km/h at "
                 f"{result['decel']:g} m/s^2", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--decel", type=float, required=True)
    ap.add_argument("--speed", type=float, required=True)
    ap.add_argument("--stops", type=int, required=True)
    ap.add_argument("--n-base", type=int, default=64)
    ap.add_argument("--brake", choices=("idealised", "caliper"), default=cr.DEFAULTS["brake"])
    ap.add_argument("--size", type=float, default=cr.DEFAULTS["size"])
    ap.add_argument("--tornado-only", action="store_true")
    ap.add_argument("--choices", type=int, default=0, metavar="N",
                    help="only the non-physical choices at the point, N draws each")
    ap.add_argument("--out", default=None)
    add_executor_options(ap)
    a = ap.parse_args(argv)
    if a.choices:
        with study_executor(a.dask, a.workers) as ex:
            c = choices(a.decel, a.speed, a.stops, a.choices, executor=ex, out=a.out,
                        brake=a.brake, size=a.size)
        for k, v in c["cases"].items():
            print(f"{k:16s} stops for P >= 0.9: {v['stops_for_target']}  P(last) {v['P'][-1]:.3f}"
                  f"  mean cleaned share {v['cleaned_share_mean']:.3f}  {v['run_s']:.1f} s per "
                  "sample")
        return {"choices": c}
    with study_executor(a.dask, a.workers) as ex:
        t = tornado(a.decel, a.speed, a.stops, ex, a.out, brake=a.brake, size=a.size)
        s = None if a.tornado_only else sobol(a.decel, a.speed, a.stops, a.n_base, ex, a.out,
                                              brake=a.brake, size=a.size)
    if s is not None:
        for k, v in sorted(s["indices"]["cleaned_share"].items(), key=lambda kv: -kv[1]["ST"]):
            print(f"{k:22s} S1 {v['S1']:6.3f} +- {v['S1_conf']:.3f}   ST {v['ST']:6.3f} +- "
                  f"{v['ST_conf']:.3f}")
    return {"tornado": t, "sobol": s}


if __name__ == "__main__":
    _cli()
