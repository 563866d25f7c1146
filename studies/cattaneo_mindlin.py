"""Stick and slip against Cattaneo-Mindlin (the figure and table of docs/validation.md,
"Frictional contact with stick and slip").

Two bodies of one material (E = 200 GPa, nu = 0.3, mu = 0.5) are meshed as a block
and its mirror image, condensed onto their contact faces
(:mod:`brakewear.tribology.bodies`), loaded by a normal load with the initial gap
of a cylinder (plane strain: R = 10 mm, 200 kN/m) or a sphere (R = 5 mm, 10 N),
then by a tangential load Q below mu P (:func:`brakewear.contact.friction.solve_friction`).
Compared with the closed forms of :mod:`brakewear.analytic.tribometer`: the
shear traction and the stick zone, and what the slip adds to the tangential
approach (the approach minus the approach with mu = 1e6, all stuck).

``python studies/cattaneo_mindlin.py [--out DIR]`` writes
``cattaneo_mindlin.json`` into ``DIR/data`` and ``cattaneo_mindlin.png`` into
``DIR/figures`` (default DIR: docs).
"""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

import brakewear.analytic as an
from brakewear.contact.friction import STICK, solve_friction
from brakewear.materials import Isotropic
from brakewear.solvers.threads import blas_threads
from brakewear.tribology.bodies import block, mirrored

E, NU, MU = 200e9, 0.3, 0.5
ES = E / (2 * (1 - NU ** 2))
RATIOS = (0.3, 0.6, 0.9)


def pair(dim: int, a: float, per_a: float, extent: float):
    """A block of one material and its mirror, condensed; the relative compliance."""
    with blas_threads(1):
        A = block("flat", Isotropic(E, NU), extent * a, extent * a, 1.3 * a, a / per_a, dim,
                  below=True)
    return A, A.compliance + mirrored(A, "counterface").compliance


def loaded(C, g0, P, Q, mu, k):
    with blas_threads(1):
        n = solve_friction(C, g0, mu, P, shift=np.zeros(k))
        return solve_friction(C, g0, mu, P, Q=[Q] + [0.0] * (k - 1), w_prev=n.w, start=n)


def cylinder(per_a: float = 24) -> dict:
    P, R = 2e5, 0.01
    a = an.hertz_cylinder(P, R, ES)["a"]
    A, C = pair(2, a, per_a, 30)
    x = A.x[0]
    g0 = x ** 2 / (2 * R)
    out = {"a_m": a, "x_m": x.tolist(), "ratios": []}
    for ratio in RATIOS:
        Q = ratio * MU * P
        s = loaded(C, g0, P, Q, MU, 1)
        stuck = loaded(C, g0, P, Q, 1e6, 1)
        cm = an.cattaneo_mindlin_cylinder(P, Q, MU, R, ES)
        out["ratios"].append({
            "ratio": ratio, "q_Pa": (-s.tangential[:, 0] / A.area).tolist(),
            "q_closed_Pa": an.cattaneo_mindlin_cylinder_traction(x, P, Q, MU, R, ES).tolist(),
            "c_over_a": float(np.sum(A.area[s.state == STICK]) / 2 / a),
            "c_over_a_closed": cm["c"] / cm["a"],
            "slip_compliance_m": float(s.shift[0] - stuck.shift[0]),
            "slip_compliance_closed_m": an.cattaneo_mindlin_cylinder_slip_compliance(
                P, Q, MU, R, ES)})
    return out


def sphere(per_a: float = 10) -> dict:
    F, R = 10.0, 0.005
    a = an.hertz_sphere(F, R, ES)["a"]
    A, C = pair(3, a, per_a, 12)
    g0 = (A.x[0] ** 2 + A.x[1] ** 2) / (2 * R)
    out = {"a_m": a, "face_nodes": int(A.face.size), "ratios": []}
    for ratio in RATIOS:
        Q = ratio * MU * F
        s = loaded(C, g0, F, Q, MU, 2)
        stuck = loaded(C, g0, F, Q, 1e6, 2)
        cm = an.cattaneo_mindlin_sphere(F, Q, MU, R, ES)
        d = an.cattaneo_mindlin_sphere_displacement(F, Q, MU, R, E, NU, E, NU)
        out["ratios"].append({
            "ratio": ratio,
            "c_over_a": math.sqrt(np.sum(A.area[s.state == STICK]) / math.pi) / a,
            "c_over_a_closed": cm["c"] / cm["a"],
            "approach_m": float(s.shift[0]), "approach_closed_m": d["delta"],
            "slip_compliance_m": float(s.shift[0] - stuck.shift[0]),
            "slip_compliance_closed_m": d["slip"]})
    return out


def main(out: str | Path | None = "docs", per_a_cylinder: float = 24,
         per_a_sphere: float = 10) -> dict:
    data = {"cylinder": cylinder(per_a_cylinder), "sphere": sphere(per_a_sphere)}
    if out is not None:
        out = Path(out)
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "cattaneo_mindlin.json").write_text(json.dumps(data, indent=1))
        (out / "figures").mkdir(parents=True, exist_ok=True)
        draw(data, out / "figures" / "cattaneo_mindlin.png")
    return data


def draw(data: dict, path: Path) -> Path:
    """Left: the cylinder's shear traction, FE (markers) and closed form (lines); right:
    the stick zone and the slip's share of the approach against Q / mu P."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(10.0, 4.0))
    cyl = data["cylinder"]
    x = np.asarray(cyl["x_m"]) / cyl["a_m"]
    for r, c in zip(cyl["ratios"], ("C0", "C1", "C2")):
        a.plot(x, np.asarray(r["q_closed_Pa"]) / 1e6, "-", color=c,
               label=f"Q / mu P = {r['ratio']:g}, closed form")
        a.plot(x, np.asarray(r["q_Pa"]) / 1e6, "o", ms=3, color=c, label="FE")
    a.set_xlim(-1.2, 1.2)
    a.set_xlabel("x / a")
    a.set_ylabel("shear traction (MPa)")
    a.set_title("cylinder (plane strain): shear traction")
    a.legend(fontsize=7)
    fine = np.linspace(0.0, 0.999, 200)
    closed = {"cylinder": np.sqrt(1 - fine), "sphere": (1 - fine) ** (1 / 3)}
    for key, mark in (("cylinder", "o"), ("sphere", "s")):
        rs = data[key]["ratios"]
        q = [r["ratio"] for r in rs]
        b.plot(fine, closed[key], "-", color="C0" if key == "cylinder" else "C1",
               label=f"{key}: c / a, closed form")
        b.plot(q, [r["c_over_a"] for r in rs], mark, color="C0" if key == "cylinder"
               else "C1", label=f"{key}: c / a, FE")
        b.plot(q, [r["slip_compliance_m"] / r["slip_compliance_closed_m"] for r in rs],
               mark, mfc="none", color="k", label=f"{key}: slip's approach, FE / closed")
    b.axhline(1.0, color="0.6", lw=0.6)
    b.set_xlabel("Q / mu P")
    b.set_ylabel("c / a; FE / closed form")
    b.set_title("stick zone and the slip's approach")
    b.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs")
    args = ap.parse_args()
    res = main(args.out)
    for key in ("cylinder", "sphere"):
        for r in res[key]["ratios"]:
            print(key, r["ratio"], "c/a", round(r["c_over_a"], 4), "closed",
                  round(r["c_over_a_closed"], 4), "slip approach FE/closed",
                  round(r["slip_compliance_m"] / r["slip_compliance_closed_m"], 4))
