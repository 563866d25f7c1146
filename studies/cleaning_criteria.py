"""When is a rotor clean?  Every candidate criterion under mesh refinement and element
order (docs/cleaning.md, "A criterion that converges").

One routine (``stops`` friction-only stops from ``speed`` km/h at ``decel`` m/s^2,
``interval`` s apart, the inputs at their priors' medians, heat on) runs to
its end on each mesh of ``cases`` -- the floating caliper from its pads bedded
(P1: its rows are built on linear meshes), and its pads held square from a new
pad against the median coning on P1 and P2 meshes (the element order's
effect: the bedded state of a quadratic face is not solved to the tolerance
of a linear one) -- and every candidate criterion of
:mod:`brakewear.cleaning.criteria` is read after each stop.  The table: each criterion's value after
``table_stop`` stops per mesh, and its relative change between the two finest
meshes of each brake.

Run ``python studies/cleaning_criteria.py --out docs`` (about an hour on two busy
cores; ``--cases caliper:8 caliper:6`` for fewer).
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from brakewear.cleaning.car import packaged_car
from brakewear.cleaning.criteria import CRITERIA
from brakewear.cleaning.priors import cleaning_inputs, medians
from brakewear.cleaning.routine import Routine
from brakewear.cleaning.sample import RoutineSettings, run_routine
from brakewear.duty import KMH

DEFAULTS = dict(stops=5, speed=80.0, decel=1.5, interval=120.0, table_stop=2,
                cases=("caliper:8", "caliper:6", "caliper:4", "caliper:3", "held:8:1:new",
                       "held:6:1:new", "held:4:1:new", "held:8:2:new", "held:6:2:new"))


def parse_case(case: str) -> tuple[str, float, int, str]:
    """``"brake:size_mm[:order[:start]]"`` -> (brake, size in m, order, start)."""
    parts = case.split(":")
    return (parts[0], float(parts[1]) * 1e-3, int(parts[2]) if len(parts) > 2 else 1,
            parts[3] if len(parts) > 3 else "bedded")


def main(out=None, **settings) -> dict:
    st = {**DEFAULTS, **settings}
    routine = Routine(st["stops"], st["speed"] * KMH, st["decel"], st["interval"])
    rows = {}
    for case in st["cases"]:
        brake, size, order, start = parse_case(case)
        t0 = time.perf_counter()
        res = run_routine(medians(cleaning_inputs(start)), routine, packaged_car(),
                          RoutineSettings(brake=brake, size=size, order=order, start=start,
                                          run_to_end=True))
        rows[case] = {"values": {c: res["criteria"].get(c, {}).get("values", [])
                                 for c in CRITERIA},
                      "stops_to_meet": {c: res["criteria"].get(c, {}).get("stops_to_meet")
                                        for c in CRITERIA},
                      "error": res.get("error"), "start": res.get("start"),
                      "wall_s": time.perf_counter() - t0}
        print(f"{case}: {rows[case]['wall_s']:.0f} s", {c: [round(x, 4) for x in v]
                                                       for c, v in rows[case]["values"].items()},
              flush=True)
    result = {"settings": st, "cases": rows, "table": table(rows, st["table_stop"])}
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / "cleaning_criteria.json").write_text(json.dumps(result, indent=1))
    return result


def table(rows: dict, stop: int) -> dict:
    """Each criterion's value after ``stop`` stops per case, and per brake and order its
    relative change between its two finest meshes."""
    out = {c: {"values": {}, "change": {}} for c in CRITERIA}
    groups: dict = {}
    for case, r in rows.items():
        brake, size, order, start = parse_case(case)
        groups.setdefault((brake, order, start), []).append((size, case))
        for c in CRITERIA:
            v = r["values"][c]
            out[c]["values"][case] = v[stop - 1] if len(v) >= stop else None
    for (brake, order, start), cases in groups.items():
        cases.sort()
        if len(cases) < 2:
            continue
        (_, fine), (_, next_) = cases[0], cases[1]
        for c in CRITERIA:
            a, b = out[c]["values"][fine], out[c]["values"][next_]
            key = f"{brake} P{order} {start}: {next_.split(':')[1]} -> {fine.split(':')[1]} mm"
            out[c]["change"][key] = (None if a is None or b is None or max(abs(a), abs(b)) == 0
                                     else abs(a - b) / max(abs(a), abs(b)))
    return out


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", nargs="+", default=list(DEFAULTS["cases"]))
    for k in ("stops", "table_stop"):
        ap.add_argument(f"--{k.replace('_', '-')}", dest=k, type=int, default=DEFAULTS[k])
    for k in ("speed", "decel", "interval"):
        ap.add_argument(f"--{k}", type=float, default=DEFAULTS[k])
    ap.add_argument("--out", default=None)
    a = vars(ap.parse_args(argv))
    out = a.pop("out")
    r = main(out, **a)
    for c, t in r["table"].items():
        print(f"{c:16s}", {k: None if v is None else round(v, 4) for k, v in t["values"].items()},
              {k: None if v is None else round(v, 4) for k, v in t["change"].items()})
    return r


if __name__ == "__main__":
    _cli()
