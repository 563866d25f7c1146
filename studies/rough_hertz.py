"""The half-space reference against Hertz and Mindlin on free grids (docs/rough.md).

Run ``python studies/rough_hertz.py [--grids 128 256 512]``: ContactMechanics' Hertz
test (sphere radius 20, side 5, E* 102; a load of 15 and an approach of 0.1) on each
grid, and the normal and tangential stiffness of the contact against ``2 E* a`` and
Mindlin's ``8 G a / (2 - nu)``.  Writes ``rough_hertz.json`` (docs/data).
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from brakewear import analytic as an
from brakewear.rough import HalfSpace, contact_stiffness, solve_normal

R, SIDE, ES, NU = 20.0, 5.0, 102.0, 0.3


def grid_case(n: int, tol: float = 1e-10) -> dict:
    hs = HalfSpace((n, n), SIDE / n, ES, NU)
    x = (np.arange(n) - n / 2) * SIDE / n
    X, Y = np.meshgrid(x, x, indexing="ij")
    r = np.hypot(X, Y)
    g0 = r ** 2 / (2 * R)
    load = solve_normal(hs, g0, load=15.0, tol=tol)
    disp = solve_normal(hs, g0, approach=0.1, tol=tol)
    h = an.hertz_sphere(15.0, R, ES)
    inside = r < 0.99 * h["a"]
    p_err = np.abs(load.pressure - an.hertz_sphere_pressure(r, 15.0, R, ES))[inside].max()
    kn = contact_stiffness(hs, load.contact, "normal").stiffness
    kt = contact_stiffness(hs, load.contact, "tangential").stiffness
    return {"n": n, "approach_error": load.approach / h["delta"] - 1,
            "force_error": disp.load / (4 / 3 * ES * np.sqrt(R) * 0.1 ** 1.5) - 1,
            "area_error": load.area / (np.pi * h["a"] ** 2) - 1,
            "p_error_over_E_star": float(p_err / ES),
            "iterations_load": load.iterations, "iterations_approach": disp.iterations,
            "normal_stiffness_error": kn / an.hertz_sphere_stiffness(15.0, R, ES) - 1,
            "tangential_stiffness_error": kt / an.mindlin_tangential_stiffness(h["a"], ES,
                                                                              NU) - 1,
            "kt_over_kn_error": kt / kn / (2 * (1 - NU) / (2 - NU)) - 1}


def main(grids=(128, 256, 512), out_data="docs/data", write: bool = True) -> dict:
    res = {"R": R, "side": SIDE, "E_star": ES, "nu": NU, "tol": 1e-10,
           "rows": [grid_case(n) for n in grids]}
    if write:
        Path(out_data).mkdir(parents=True, exist_ok=True)
        (Path(out_data) / "rough_hertz.json").write_text(json.dumps(res, indent=1))
    return res


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grids", type=int, nargs="+", default=[128, 256, 512])
    a = ap.parse_args()
    for row in main(a.grids)["rows"]:
        print(" ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}"
                       for k, v in row.items()))
