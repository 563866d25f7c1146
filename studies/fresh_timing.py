"""The thermal=None wear loop of ``studies/thermal_drag.py`` timed in a new interpreter:
that it never imports ``brakewear.thermal``, and (with another source tree of
brakewear) how its time and wear compare with this process's run."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

_FRESH = """
import json, sys, time
import brakewear
from brakewear import BrakeModel
from brakewear import FEInterface, wear_history
from brakewear import WearLaw
from brakewear.mesh.rings import rotor_rings
from brakewear import Numerics
from brakewear.wear import Run
a = json.loads(sys.argv[1])
m = BrakeModel(size=a["size"])
times, cpu = [], []
for _ in range(a["repeats"]):
    t0, c0 = time.perf_counter(), time.process_time()
    h = list(wear_history(Run(m, a["p"], a["omega"], a["duration"], WearLaw(*a["pad"]),
                              WearLaw(*a["rotor"]), mu=a["mu"],
                              numerics=Numerics(steps=a["steps"], scheme="implicit"))))
    times.append(time.perf_counter() - t0)
    cpu.append(time.process_time() - c0)
print(json.dumps({"times_s": times, "cpu_s": cpu,
                  "thermal_imported": "brakewear.thermal" in sys.modules,
                  "package": brakewear.__file__, "pad_volume_m3": h[-1].pad_volume,
                  "rotor_volume_m3": h[-1].rotor_volume,
                  "pad_wear": h[-1].pad_wear.tolist()}))
"""


def law_args(law) -> list:
    """A wear law's constructor arguments (k, a, b, T_threshold, activation_energy)."""
    return [law.k, law.a, law.b, law.T_threshold, law.activation_energy]


def fresh_process_times(size, p, omega, mu, duration, steps, repeats, pad_law, rotor_law,
                        tree: str | Path | None = None) -> dict:
    """Time the thermal=None loop in a new interpreter, run from ``tree`` (a source
    tree of brakewear; default this one: its package is imported, not an installed one)."""
    arg = json.dumps({"size": size, "p": p, "omega": omega, "mu": mu, "duration": duration,
                      "steps": steps, "repeats": repeats, "pad": law_args(pad_law),
                      "rotor": law_args(rotor_law)})
    tree = Path(__file__).resolve().parents[1] if tree is None else Path(tree).resolve()
    res = subprocess.run([sys.executable, "-c", _FRESH, arg], check=True, capture_output=True,
                         text=True, cwd=tree)
    return json.loads(res.stdout.strip().splitlines()[-1])


def external_timing(key: str, tree, pad_wear, off_median: float, *args) -> dict:
    """The thermal=None run timed in a new interpreter (``tree``: another source tree, or
    None: this one), checked and compared with this process's run."""
    r = fresh_process_times(*args, tree=tree)
    if tree is None and r["thermal_imported"]:
        raise RuntimeError("a thermal=None run imported brakewear.thermal")
    if tree is not None and not str(r["package"]).startswith(str(Path(tree).resolve())):
        raise RuntimeError(f"baseline run imported {r['package']}, not {tree}")
    k = "off_fresh_process" if key == "fresh_process" else "off_baseline"
    c = "cpu_off_fresh_process" if key == "fresh_process" else "cpu_off_baseline"
    p = "fresh" if key == "fresh_process" else "baseline"
    out = {f"{k}_s": r["times_s"], f"{k}_median_s": float(np.median(r["times_s"])),
           f"{c}_s": r["cpu_s"], f"{c}_median_s": float(np.median(r["cpu_s"])),
           f"{p}_over_in_process_off": float(np.median(r["times_s"])) / off_median,
           f"{p}_pad_wear_max_diff_m": float(np.abs(np.asarray(r["pad_wear"])
                                                     - pad_wear).max())}
    if tree is None:
        out["fresh_process_imported_thermal"] = r["thermal_imported"]
    return out
