"""The cleaning routine for a car: the design curve P(clean within N stops) and the
routine a car maker can program (docs/cleaning.md, "The answer").

Every routine of the grid -- friction-only stops of the study car
(brakewear/data/cars/study_car.toml) from each speed at each deceleration,
each spacing apart -- runs on the same draws of the uncertain inputs
(:func:`brakewear.cleaning.priors.cleaning_inputs`), from the pads bedded to
the rotor (``--start new``: a new pad, the labelled scenario), heat on; the
package does the work (:func:`brakewear.cleaning.sweep.design_curve`, the same
as ``brakewear clean``).  This script writes the docs' figure and data:
``figures/cleaning_routine.png``, ``data/cleaning_routine.json`` and the runs'
journal ``data/cleaning_routine_runs.jsonl`` (run again, it resumes).

Run ``python studies/cleaning_routine.py --decels 0.5 1 1.5 2 3 --speeds 50 80 100
--intervals 120 300 --samples 200 --size 4 --out docs`` (``--dask [ADDRESS]``
for a cluster).
"""
from __future__ import annotations

import argparse
import json
import logging
from pathlib import Path

from brakewear.cleaning.car import packaged_car
from brakewear.cleaning.criteria import CriteriaSettings
from brakewear.cleaning.priors import cleaning_inputs, draw
from brakewear.cleaning.report import plot_design_curve
from brakewear.cleaning.sample import RoutineSettings
from brakewear.cleaning.sweep import design_curve, executor

logger = logging.getLogger("cleaning_routine")

DEFAULTS = dict(decels=(0.5, 1.0, 1.5, 2.0, 3.0), speeds=(50.0, 80.0, 100.0),
                intervals=(120.0, 300.0), samples=200, stops=20, size=4.0, start="bedded",
                heat=True, seed=37, chosen=CriteriaSettings().chosen)


def main(out=None, ex=None, name: str = "cleaning_routine", **settings) -> dict:
    """The design curve (see the module); ``settings`` override :data:`DEFAULTS`."""
    unknown = set(settings) - set(DEFAULTS)
    if unknown:
        raise ValueError(f"settings {sorted(unknown)} are not allowed; allowed: "
                         f"{', '.join(DEFAULTS)}")
    st = {**DEFAULTS, **settings}
    run = RoutineSettings(size=st["size"] * 1e-3, start=st["start"], heat=st["heat"],
                          criteria=CriteriaSettings(chosen=st["chosen"]))
    draws = draw(st["samples"], st["seed"], cleaning_inputs(st["start"]))
    journal = None
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        journal = Path(out) / "data" / f"{name}_runs.jsonl"
    curve = design_curve(draws, st["speeds"], st["decels"], st["intervals"], st["stops"], run,
                         packaged_car("study"), ex=ex, journal=journal)
    curve["study"] = st
    if out is not None:
        (Path(out) / "figures").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / f"{name}.json").write_text(json.dumps(curve, indent=1,
                                                                   default=str))
        plot_design_curve(curve, Path(out) / "figures" / f"{name}.png")
    return curve


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for k in ("decels", "speeds", "intervals"):
        ap.add_argument(f"--{k}", type=float, nargs="+", default=list(DEFAULTS[k]))
    for k in ("samples", "stops", "seed"):
        ap.add_argument(f"--{k}", type=int, default=DEFAULTS[k])
    ap.add_argument("--size", type=float, default=DEFAULTS["size"], help="mm")
    ap.add_argument("--start", choices=("bedded", "new"), default=DEFAULTS["start"])
    ap.add_argument("--no-heat", dest="heat", action="store_false")
    ap.add_argument("--chosen", default=DEFAULTS["chosen"], help="the criterion judged by")
    ap.add_argument("--name", default="cleaning_routine")
    ap.add_argument("--out", default=None)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--dask", nargs="?", const="local", default=None)
    a = vars(ap.parse_args(argv))
    out, dask, workers, name = a.pop("out"), a.pop("dask"), a.pop("workers"), a.pop("name")
    with executor(dask, workers) as ex:
        r = main(out, ex, name, **a)
    for t, rt in r["routines"].items():
        print(f"P >= {t}: " + ("none in the grid" if rt is None else
                              f"{rt['words']} (P = {rt['P']:.3f}, 95 % {rt['interval_95'][0]:.3f}"
                              f"..{rt['interval_95'][1]:.3f})"))
    print(f"{r['runs']} routines, {r['failed']} failed, {r['cost_per_routine_s']:.2f} s each, "
          f"{r['wall_s']:.0f} s")
    return r


if __name__ == "__main__":
    logging.basicConfig(level=logging.WARNING)
    _cli()
