"""The default drag with thermal coupling, four ways: the cost of the laws per node
and of the geometry update.

Runs the default brake's drag (1 MPa, 55 rad/s, 90 s in fixed steps, default
thermal settings) without thermal coupling, with it, with the illustrative
friction and wear maps of :mod:`brakewear.laws.maps`, and with the geometry
update; each ``repeats`` times in one process, and reports the last
repetition's wall and CPU time, the pad face's peak temperature and the pad
wear.  ``python studies/thermal_variants.py [--size MM] [--out DIR]`` writes
``thermal_variants.json`` (DIR/data, default docs/).
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import brakewear as bw
from brakewear.laws.maps import example_map
from brakewear.wear import Run


def cases():
    P, R = bw.WearLaw(5e-15), bw.WearLaw(5e-16)
    maps = (bw.WearMap(example_map("k")), R)
    return {
        "no thermal, mu 0.4": dict(mu=0.4, update="gap", laws=(P, R), thermal=False),
        "thermal, mu 0.4": dict(mu=0.4, update="gap", laws=(P, R)),
        "thermal, friction and wear maps": dict(mu=bw.FrictionMap(example_map("mu")),
                                                update="gap", laws=maps),
        "thermal, geometry update, mu 0.4": dict(mu=0.4, update="geometry", laws=(P, R)),
    }


def main(size: float = 6e-3, duration: float = 90.0, steps: int = 30, repeats: int = 2,
         out: str | None = None) -> dict:
    model = bw.BrakeModel(size=size)
    rows = {}
    for _ in range(repeats):
        for name, c in cases().items():
            th = None if c.get("thermal") is False else bw.ThermalModel(model)
            t0, c0 = time.perf_counter(), time.process_time()
            s = list(
                bw.wear_history(
                    Run(
                        model,
                        1e6,
                        55.0,
                        duration,
                        *c["laws"],
                        mu=c["mu"],
                        thermal=th,
                        numerics=bw.Numerics(steps=steps, update=c["update"]),
                    )
                )
            )
            rows[name] = {"wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0,
                          "per_step_ms": 1e3 * (time.perf_counter() - t0) / steps,
                          "pad_T_max_C": s[-1].pad_temperature_max - 273.15,
                          "pad_wear_max_um": 1e6 * float(s[-1].pad_wear.max()),
                          "mu_effective": s[-1].mu,
                          "heat_balance_error_max": max(x.heat_balance_error for x in s)}
    result = {"size_m": size, "duration_s": duration, "steps": steps, "dofs": int(model.dofs),
              "command": "python studies/thermal_variants.py", "cases": rows}
    if out is not None:
        path = Path(out) / "data" / "thermal_variants.json"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(result, indent=2, default=float))
    return result


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=6.0, help="mesh size (mm)")
    ap.add_argument("--out", default="docs")
    a = ap.parse_args()
    r = main(size=a.size * 1e-3, out=a.out)
    for name, c in r["cases"].items():
        print(f"{name:36s} wall {c['wall_s']:6.2f} s  cpu {c['cpu_s']:6.2f} s  "
              f"{c['per_step_ms']:6.1f} ms/step  pad face {c['pad_T_max_C']:6.1f} C  "
              f"pad wear {c['pad_wear_max_um']:6.2f} um")
