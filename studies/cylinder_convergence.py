"""Convergence of the 3D elasticity solve against the thick-walled cylinder.

A quarter ring a < r < b under internal pressure, solved in 3D with plane
strain imposed (u_z = 0 on both faces) and symmetry on the two cut faces, is
compared with Lamé's closed form (brakewear.analytic).  P2 meshes are
isoparametric, so the curved faces do not limit the rate.

Run ``python studies/cylinder_convergence.py [--out DIR]``: prints the table
and writes ``cylinder_convergence.csv`` and ``.png`` (error against h).
"""
from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np
import skfem as fem

from brakewear.analytic import thick_cylinder_displacement
from brakewear.fem import (
    apply_dirichlet,
    assemble_pressure,
    assemble_stiffness,
    boundary_dofs,
    scalar_element,
)
from brakewear.materials import Isotropic
from brakewear.mesh import annulus_mesh
from brakewear.output.figures import label_log_axis
from brakewear.solvers import amg_solver

# rotor-like ring: radii of a friction ring, cast-iron stiffness, 10 MPa inside
A_IN, B_OUT, P_IN = 0.09, 0.15, 10e6
MATERIAL = Isotropic(E=110e9, nu=0.27, name="cast_iron")


def solve(n: int, order: int = 1, tol: float = 1e-11) -> dict:
    """Solve on a mesh with ``n`` radial cells (3 n around the quarter); return errors."""
    h = (B_OUT - A_IN) / n
    m = annulus_mesh(A_IN, B_OUT, h, n, 3 * n, 1, angle=np.pi / 2, order=order)
    t0 = time.perf_counter()
    K, _ = assemble_stiffness(m, MATERIAL)
    f = assemble_pressure(m, "inner", P_IN)
    fixed = np.unique(np.concatenate([
        boundary_dofs(m, "top", [2]), boundary_dofs(m, "bottom", [2]),
        boundary_dofs(m, "theta0", [1]), boundary_dofs(m, "theta1", [0]),
    ]))
    Kd, fd = apply_dirichlet(K, f, fixed)
    elem = scalar_element(m)
    basis = fem.Basis(m, fem.ElementVector(elem), intorder=2 * elem.maxdeg + 2)
    solver = amg_solver(Kd, coords=basis.doflocs[:, ::3], fixed=fixed, tol=tol)
    u = solver.solve(fd)
    dt = time.perf_counter() - t0
    l2, en = errors(basis, u)
    return {"n": n, "order": order, "h": h, "dofs": u.size, "l2": l2, "energy": en,
            "iterations": solver.info.iterations, "time_s": dt}


def errors(basis: fem.CellBasis, u: np.ndarray) -> tuple[float, float]:
    """Relative L2 displacement error and relative energy-norm error."""
    E, nu = MATERIAL.E, MATERIAL.nu
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    uh = basis.interpolate(u)

    def exact(x):
        r = np.hypot(x[0], x[1])
        ur = thick_cylinder_displacement(r, A_IN, B_OUT, P_IN, E, nu)
        # d u_r / d r by the closed form's derivative
        from brakewear.analytic import thick_cylinder_coefficients
        Ac, Bc = thick_cylinder_coefficients(A_IN, B_OUT, P_IN)
        dur = (1 + nu) / E * ((1 - 2 * nu) * Ac - Bc / r ** 2)
        c, s = x[0] / r, x[1] / r
        uvec = np.array([ur * c, ur * s, 0 * r])
        err, ett = dur, ur / r
        eps = np.zeros((3, 3) + r.shape)
        eps[0, 0] = err * c * c + ett * s * s
        eps[1, 1] = err * s * s + ett * c * c
        eps[0, 1] = eps[1, 0] = (err - ett) * c * s
        return uvec, eps

    def energy(e):
        tr = e[0, 0] + e[1, 1] + e[2, 2]
        return lam * tr ** 2 + 2 * mu * np.einsum("ij...,ij...->...", e, e)

    @fem.Functional
    def l2_err(w):
        ue, _ = exact(w.x)
        return sum((w["uh"][i] - ue[i]) ** 2 for i in range(3))

    @fem.Functional
    def l2_ref(w):
        ue, _ = exact(w.x)
        return sum(ue[i] ** 2 for i in range(3))

    @fem.Functional
    def en_err(w):
        _, ee = exact(w.x)
        g = w["uh"].grad
        eh = 0.5 * (g + np.swapaxes(g, 0, 1))
        return energy(eh - ee)

    @fem.Functional
    def en_ref(w):
        _, ee = exact(w.x)
        return energy(ee)

    l2 = np.sqrt(l2_err.assemble(basis, uh=uh) / l2_ref.assemble(basis))
    en = np.sqrt(en_err.assemble(basis, uh=uh) / en_ref.assemble(basis))
    return float(l2), float(en)


def rate(h, e) -> float:
    """Observed rate: slope of log(error) against log(h)."""
    return float(np.polyfit(np.log(h), np.log(e), 1)[0])


def main(ns_p1=(2, 4, 8, 16), ns_p2=(1, 2, 4, 8), out: str | Path | None = None) -> dict:
    rows = [solve(n, 1) for n in ns_p1] + [solve(n, 2) for n in ns_p2]
    result = {"rows": rows}
    for order in (1, 2):
        r = [x for x in rows if x["order"] == order]
        h = [x["h"] for x in r]
        result[f"p{order}_l2_rate"] = rate(h, [x["l2"] for x in r])
        result[f"p{order}_energy_rate"] = rate(h, [x["energy"] for x in r])
        result[f"p{order}_finest"] = r[-1]
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        with open(out / "cylinder_convergence.csv", "w", newline="") as fh:
            wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
            wr.writeheader()
            wr.writerows(rows)
        _plot(result, out / "cylinder_convergence.png")
    return result


def _plot(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.5))
    for order, mk in ((1, "o"), (2, "s")):
        r = [x for x in result["rows"] if x["order"] == order]
        h = np.array([x["h"] for x in r]) * 1e3
        ax.loglog(h, [x["l2"] for x in r], mk + "-",
                  label=f"P{order} L2 (rate {result[f'p{order}_l2_rate']:.2f})")
        ax.loglog(h, [x["energy"] for x in r], mk + "--",
                  label=f"P{order} energy (rate {result[f'p{order}_energy_rate']:.2f})")
    label_log_axis(ax.xaxis, sorted({x["h"] * 1e3 for x in result["rows"]}))
    ax.set_xlabel("radial element size h (mm)")
    ax.set_ylabel("relative error")
    ax.set_title("Thick-walled cylinder, 3D plane strain: error vs h")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures")
    args = ap.parse_args()
    res = main(out=args.out)
    print(f"{'order':>5} {'n':>3} {'dofs':>7} {'L2 err':>10} {'energy err':>10} {'it':>4} {'s':>6}")
    for x in res["rows"]:
        print(f"{x['order']:>5} {x['n']:>3} {x['dofs']:>7} {x['l2']:>10.3e} {x['energy']:>10.3e} "
              f"{x['iterations']:>4} {x['time_s']:>6.2f}")
    for o in (1, 2):
        print(
            f"P{o}: L2 rate {res[f'p{o}_l2_rate']:.2f}, energy rate {res[f'p{o}_energy_rate']:.2f}"
        )
