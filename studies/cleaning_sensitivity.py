"""What decides the cleaning routine: Sobol indices with bootstrap intervals and the
tornado at one routine (docs/cleaning.md, "What decides it").

The package does the work (:mod:`brakewear.cleaning.sensitivity`): Saltelli's
sampling of every input of :func:`brakewear.cleaning.priors.cleaning_inputs`
(``N (D + 2)`` routines), SALib's first-order and total indices of the chosen
criterion's value after the routine's stops and of whether it was met, with
their 95 % bootstrap intervals; the tornado moves one input at a time to its
prior's 5 % and 95 % points.  SALib is optional (``pip install
"brakewear[study]"``).  Writes ``data/cleaning_sobol.json``,
``figures/cleaning_sobol.png`` (and the tornado's), the runs journalled in
``data/cleaning_sobol_runs.jsonl``.

Run ``python studies/cleaning_sensitivity.py --decel 1 --speed 50 --interval 120
--stops 5 --n-base 128 --size 4 --out docs``.
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from brakewear.cleaning.car import packaged_car
from brakewear.cleaning.criteria import CriteriaSettings
from brakewear.cleaning.priors import cleaning_inputs, medians
from brakewear.cleaning.sample import RoutineSettings
from brakewear.cleaning.sensitivity import routine_outputs, routine_sobol, tornado
from brakewear.cleaning.sweep import executor, map_tasks, routine_task

DEFAULTS = dict(decel=1.0, speed=50.0, interval=120.0, stops=5, n_base=128, size=4.0,
                start="bedded", seed=11)


def main(out=None, ex=None, with_tornado: bool = True, **settings) -> dict:
    """The Sobol indices (and the tornado) at the routine of ``settings``."""
    st = {**DEFAULTS, **settings}
    pri = cleaning_inputs(st["start"])
    run = RoutineSettings(size=st["size"] * 1e-3, start=st["start"])
    car = packaged_car("study")
    t0 = time.perf_counter()
    journal = None if out is None else Path(out) / "data" / "cleaning_sobol_runs.jsonl"
    if journal is not None:
        journal.parent.mkdir(parents=True, exist_ok=True)
    res = routine_sobol(pri, st["speed"], st["decel"], st["interval"], st["stops"], run, car,
                        n_base=st["n_base"], seed=st["seed"], ex=ex, journal=journal)
    res.update(settings=st, wall_s=time.perf_counter() - t0,
               priors={k: [p.kind, p.a, p.b, p.unit, p.source] for k, p in pri.items()})
    if with_tornado:
        def outputs(xs):
            runs = map_tasks([routine_task(x, st["speed"], st["decel"], st["interval"],
                                           st["stops"], run, car) for x in xs], ex)
            return routine_outputs(runs, st["stops"], CriteriaSettings().chosen)[
                "criterion_value"]
        res["tornado"] = tornado(pri, medians(pri), outputs)
    if out is not None:
        (Path(out) / "figures").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / "cleaning_sobol.json").write_text(
            json.dumps({k: v for k, v in res.items() if k != "inputs"}, indent=1))
        plot_sobol(res, Path(out) / "figures" / "cleaning_sobol.png")
    return res


def plot_sobol(res: dict, path: Path) -> None:
    """First-order and total indices with their 95 % intervals, per output."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keys = list(res["indices"])
    n = len(res["indices"][keys[0]])
    fig, axes = plt.subplots(1, len(keys), figsize=(6.5 * len(keys), 0.3 * n + 1.8),
                             squeeze=False)
    for ax, key in zip(axes[0], keys):
        ind = res["indices"][key]
        names = sorted(ind, key=lambda k: -ind[k]["ST"])
        y = np.arange(len(names))
        for off, s, c in ((-0.18, "S1", "tab:blue"), (0.18, "ST", "tab:red")):
            ax.barh(y + off, [ind[k][s] for k in names], 0.34,
                    xerr=[ind[k][f"{s}_conf"] for k in names], color=c, alpha=0.8,
                    label={"S1": "first order", "ST": "total"}[s], capsize=2)
        ax.set_yticks(y, [k.replace("load_path:", "") for k in names], fontsize=7)
        ax.invert_yaxis()
        ax.axvline(0, color="k", lw=0.6)
        ax.set(xlabel="Sobol index (95 % bootstrap interval)", title=key.replace("_", " "))
        ax.legend(fontsize=8)
    st = res["settings"]
    fig.suptitle(f"{st['stops']} stops from {st['speed']:g} km/h at {st['decel']:g} m/s^2, "
                 f"{st['interval']:g} s apart; {res['runs']} routines, {res['failed']} failed, "
                 f"widest interval {res['widest_interval']:.3f}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for k in ("decel", "speed", "interval", "size"):
        ap.add_argument(f"--{k}", type=float, default=DEFAULTS[k])
    for k in ("stops", "n_base", "seed"):
        ap.add_argument(f"--{k.replace('_', '-')}", dest=k, type=int, default=DEFAULTS[k])
    ap.add_argument("--start", choices=("bedded", "new"), default=DEFAULTS["start"])
    ap.add_argument("--no-tornado", dest="with_tornado", action="store_false")
    ap.add_argument("--out", default=None)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--dask", nargs="?", const="local", default=None)
    a = vars(ap.parse_args(argv))
    out, dask, workers = a.pop("out"), a.pop("dask"), a.pop("workers")
    with executor(dask, workers) as ex:
        r = main(out, ex, **a)
    for k, v in sorted(r["indices"]["criterion_value"].items(), key=lambda kv: -kv[1]["ST"]):
        print(f"{k:34s} S1 {v['S1']:6.3f} +- {v['S1_conf']:.3f}   ST {v['ST']:6.3f} +- "
              f"{v['ST_conf']:.3f}")
    print(f"{r['runs']} routines, {r['failed']} failed, widest 95 % interval "
          f"{r['widest_interval']:.3f}, {r['wall_s']:.0f} s")
    return r


if __name__ == "__main__":
    _cli()
