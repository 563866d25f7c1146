"""``brakewear clean``: the routine that cleans a corroded rotor, from the command line.

The question as a car maker asks it -- which friction-only stops clean the
rotor with a stated probability -- from a brake geometry, a car file (the
vehicle, its road load and its blending: :mod:`brakewear.cleaning.car`) and
the routine's ranges, or a ``[cleaning]`` table in a TOML file (a scene
file may carry one).  Every input is checked before anything runs
(:func:`clean_input`); then the design curve runs
(:func:`~brakewear.cleaning.sweep.design_curve`) with a progress bar and its
ETA, on a process pool or a dask cluster (``--dask``), its runs journalled
so that ``--resume`` continues it; then the files (:mod:`brakewear.cleaning.report`).
"""
from __future__ import annotations

import argparse
import logging
import math
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import DutyError, SceneError

logger = logging.getLogger(__name__)

__all__ = ["CleanInput", "clean_input", "add_clean_parser", "run_clean", "clean_main",
           "CLEANING_KEYS"]

#: the keys of a ``[cleaning]`` table: key -> (command-line option, kind, unit, what)
CLEANING_KEYS = {
    "geometry": ("--geometry", "str", "", "a packaged geometry name or a geometry .toml"),
    "car": ("--car", "str", "", "a packaged car name ('study') or a car .toml"),
    "speeds": ("--speeds", "list", "km/h", "the stops' start speeds"),
    "decels": ("--decels", "list", "m/s^2", "the stops' decelerations"),
    "intervals": ("--intervals", "list", "s", "the stops' spacing, start to start"),
    "stops": ("--stops", "int", "", "the most stops of a routine"),
    "samples": ("--samples", "int", "", "draws of the inputs per routine"),
    "size": ("--size", "num", "mm", "the mesh size"),
    "start": ("--start", "str", "", "'bedded' pads (default) or a 'new' pad"),
    "heat": ("--no-heat", "bool", "", "the stops' heat and thermal coning"),
    "seed": ("--seed", "int", "", "the draws' seed"),
    "targets": ("--targets", "list", "", "the probabilities whose routines are picked"),
}

_DEFAULTS = {"geometry": "floating", "car": "study", "speeds": [50.0, 80.0, 100.0],
             "decels": [0.5, 1.0, 1.5, 2.0, 3.0], "intervals": [120.0, 300.0], "stops": 20,
             "samples": 200, "size": 4.0, "start": "bedded", "heat": True, "seed": 37,
             "targets": [0.9, 0.95]}


@dataclass(frozen=True)
class CleanInput:
    """A checked ``brakewear clean`` input (the user's units: km/h, m/s^2, s, mm)."""

    geometry: str
    car: object
    car_source: str
    speeds: tuple
    decels: tuple
    intervals: tuple
    stops: int
    samples: int
    size: float
    start: str
    heat: bool
    seed: int
    targets: tuple
    source: str = "the command line"
    extra: dict = field(default_factory=dict)


def _fail(where: str, key: str, value, allowed: str):
    return SceneError(f"{where}: {key} = {value!r} is not allowed; {allowed}")


def _numbers(where, key, v, lo, hi, unit, lo_open=True) -> tuple:
    vals = v if isinstance(v, (list, tuple)) else [v]
    if not vals:
        raise _fail(where, key, v, "need at least one value")
    for x in vals:
        ok = (isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
              and (x > lo if lo_open else x >= lo) and x <= hi)
        if not ok:
            raise _fail(where, key, x, f"each value must be a number {'>' if lo_open else '>='} "
                                       f"{lo:g} and <= {hi:g} {unit}".rstrip())
    return tuple(sorted(float(x) for x in vals))


def clean_input(table: dict | None = None, source: str = "the command line") -> CleanInput:
    """Check a ``[cleaning]`` table (keys of :data:`CLEANING_KEYS`, the user's units)
    over the defaults; every error names ``source``, the key, the value and what is
    allowed.  Nothing is computed."""
    from ..geometry import load_geometry
    from .car import car_file, read_car
    from .priors import STARTS
    from .routine import INTERVAL_RANGE

    table = dict(table or {})
    unknown = sorted(set(table) - set(CLEANING_KEYS))
    if unknown:
        raise SceneError(f"{source}: cleaning.{unknown[0]}: unknown key; allowed: "
                         + ", ".join(f"{k} ({u or '-'})" for k, (_, _, u, _) in
                                     CLEANING_KEYS.items()))
    d = {**_DEFAULTS, **{k: v for k, v in table.items() if v is not None}}
    where = source
    for key in ("geometry", "car", "start"):
        if not isinstance(d[key], str):
            raise _fail(where, f"cleaning.{key}", d[key], "need a name or a file name")
    if d["start"] not in STARTS:
        raise _fail(where, "cleaning.start", d["start"], f"allowed: {', '.join(STARTS)}")
    g = load_geometry(d["geometry"])
    if g.caliper.type != "floating" or not g.caliper.fingers:
        raise _fail(where, "cleaning.geometry", d["geometry"], "need a floating caliper "
                    "(its fingers and piston hold the pads: [caliper] type = 'floating')")
    car = read_car(car_file(d["car"]))
    speeds = _numbers(where, "cleaning.speeds", d["speeds"], 0.0, 250.0, "km/h")
    decels = _numbers(where, "cleaning.decels", d["decels"], 0.0, car.tyre_mu * 9.80665,
                      "m/s^2 (the car's tyre grip)")
    intervals = _numbers(where, "cleaning.intervals", d["intervals"], INTERVAL_RANGE[0],
                         INTERVAL_RANGE[1], "s", lo_open=False)
    longest = max(speeds) / 3.6 / min(decels)
    if not min(intervals) > longest:
        raise _fail(where, "cleaning.intervals", min(intervals),
                    f"a stop from {max(speeds):g} km/h at {min(decels):g} m/s^2 lasts "
                    f"{longest:.3g} s; the spacing (start to start) must be longer")
    for key, lo, hi in (("stops", 1, 100), ("samples", 2, 100_000), ("seed", 0, 2 ** 31)):
        v = d[key]
        if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
            raise _fail(where, f"cleaning.{key}", v, f"need a whole number {lo}..{hi}")
    size = _numbers(where, "cleaning.size", d["size"], 1.5, 12.0, "mm", lo_open=False)[0]
    targets = _numbers(where, "cleaning.targets", d["targets"], 0.0, 0.999, "")
    if not isinstance(d["heat"], bool):
        raise _fail(where, "cleaning.heat", d["heat"], "need true or false")
    return CleanInput(d["geometry"], car, d["car"], speeds, decels, intervals, d["stops"],
                      d["samples"], size, d["start"], d["heat"], d["seed"], targets, source)


def read_clean_file(path: str) -> dict:
    """The ``[cleaning]`` table of a TOML file (a scene may carry one)."""
    from .car import read_toml

    p = Path(path)
    data = read_toml(p, "the cleaning file", SceneError)
    if "cleaning" not in data or not isinstance(data["cleaning"], dict):
        raise SceneError(f"{p}: no [cleaning] table (its keys: {', '.join(CLEANING_KEYS)})")
    return data["cleaning"]


def add_clean_parser(sub) -> argparse.ArgumentParser:
    """The ``clean`` sub-command's options (:data:`CLEANING_KEYS`)."""
    c = sub.add_parser(
        "clean", help="the routine that cleans a corroded rotor (docs/cleaning.md)",
        description="Which friction-only stops clean a corroded rotor, with what "
                    "probability: the design curve P(clean within N stops) over the routines "
                    "of the given ranges, each on the same draws of the uncertain inputs, the "
                    "routine with P >= each target (fewest stops, then lowest deceleration, "
                    "then lowest speed) with its 95 % interval, the pads' maps and a JSON "
                    "summary, written to --out.  FILE: a TOML file with a [cleaning] table "
                    "(the same keys); options given here replace its values.")
    c.add_argument("file", nargs="?", default=None, help="a TOML file with a [cleaning] table")
    c.add_argument("--geometry", help="geometry name or .toml (default floating)")
    c.add_argument("--car", help="car name or .toml: [vehicle], [road], [blending] "
                                 "(default study, brakewear/data/cars/study_car.toml)")
    c.add_argument("--speeds", type=float, nargs="+", help="start speeds, km/h (50 80 100)")
    c.add_argument("--decels", type=float, nargs="+",
                   help="decelerations, m/s^2 (0.5 1 1.5 2 3)")
    c.add_argument("--intervals", type=float, nargs="+",
                   help="spacing of the stops, start to start, s, 60-600 (120 300)")
    c.add_argument("--stops", type=int, help="most stops of a routine (20)")
    c.add_argument("--samples", type=int, help="draws of the inputs per routine (200)")
    c.add_argument("--size", type=float, help="mesh size, mm (4)")
    c.add_argument("--start", choices=("bedded", "new"),
                   help="pads bedded to the rotor (default) or a new pad (a scenario)")
    c.add_argument("--no-heat", dest="heat", action="store_const", const=False, default=None,
                   help="without the stops' heat and thermal coning")
    c.add_argument("--seed", type=int, help="seed of the draws (37)")
    c.add_argument("--targets", type=float, nargs="+", help="probabilities (0.9 0.95)")
    c.add_argument("--out", default="brakewear-clean", help="output folder")
    c.add_argument("--resume", action="store_true",
                   help="continue the sweep journalled in --out")
    c.add_argument("--overwrite", action="store_true", help="replace what --out holds")
    c.add_argument("--workers", type=int, default=2, help="worker processes (2)")
    c.add_argument("--dask", nargs="?", const="local", default=None, metavar="ADDRESS",
                   help="run on a dask.distributed scheduler at ADDRESS (no address: a "
                        "local cluster of --workers processes)")
    c.add_argument("--quiet", action="store_true", help="no progress bar")
    return c


def input_from_args(args) -> CleanInput:
    """The checked input of the command's arguments (a file's table under them)."""
    table, source = {}, "the command line"
    if args.file:
        table, source = read_clean_file(args.file), str(args.file)
    given = {k: getattr(args, k) for k in CLEANING_KEYS if getattr(args, k, None) is not None}
    if given and args.file:
        source = f"{args.file} with the command line's {', '.join(given)}"
    if not isinstance(args.workers, int) or args.workers < 1:
        raise DutyError(f"--workers = {args.workers!r} is not allowed; need a whole number >= 1")
    return clean_input({**table, **given}, source)


def run_clean(args) -> dict:
    """``brakewear clean``: check, sweep, write (:mod:`brakewear.cleaning.report`)."""
    from .report import check_clean_out, clean_and_report

    inp = input_from_args(args)
    out = check_clean_out(args.out, overwrite=args.overwrite, resume=args.resume)
    return clean_and_report(inp, out, dask=args.dask, workers=args.workers, quiet=args.quiet,
                            overwrite=args.overwrite)


def clean_main(args) -> int:
    """``brakewear clean`` as the command line runs it: prints the routines found and
    what was written; returns the exit code (errors are the command line's to report)."""
    s = run_clean(args)
    for t, r in s["routines"].items():
        print(f"P >= {t}: " + ("no routine in the ranges" if r is None else
                              f"{r['words']} (P = {r['P']:.3f}, 95 % interval "
                              f"{r['interval_95'][0]:.3f}..{r['interval_95'][1]:.3f}, "
                              f"{r['line_pressure_MPa']:.2f} MPa)"))
    print(f"brakewear clean: {s['runs']} routines ({s['failed']} failed), "
          f"{s['cost_per_routine_s'] or 0:.1f} s each, {s['wall_s']:.0f} s; wrote "
          f"{args.out}/ ({', '.join(s['files'][:4])}, ...)")
    return 0
