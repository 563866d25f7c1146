"""Thermal coning of the rotor: the free plate's dish and the hat rotor's cone (docs/thermal.md).

Two elastic problems, each checked against an independent estimate:

(a) **Free plate, temperature linear through the thickness.**  The whole
    friction ring (no clamp; rigid-body modes removed by a statically
    determinate 3-2-1 support) with ``T = dT (z + t/2) / t``.  The thermal
    strain ``alpha T I`` is then linear in the coordinates, hence compatible:
    the ring bends without stress into a spherical dish of curvature
    ``kappa = alpha dT / t`` (``u_z = -kappa r^2 / 2`` plus a rigid motion).
    The 3D FE curvature and the stress left in it converge to that.

(b) **Hat rotor, ring heated, hat cold.**  The friction ring (with the neck
    over the wall) is heated uniformly by ``dT``, the hat stays at the
    reference temperature (the end of a short hard stop: the heat has not
    yet reached the hat), the flange's mounting face is clamped out to the
    bolt circle.  The ring grows radially by ``alpha dT r``; the cold wall
    holds its outboard inner corner back, so the ring's section rotates:
    the ring cones.  Compared with (1) an axisymmetric P2 FE model of the
    same section (forms of this module) and (2) the closed form of
    :func:`~brakewear.thermal.hat_cone.hat_cone_estimate` (rigid-section ring on a Timoshenko
    cylindrical
    shell clamped at the flange).  The temperature is element-wise (ring
    elements ``dT``, hat elements 0), so the step at the junction is exact on
    every mesh.

Cone angle = ``d u_z / d r`` of the inboard friction face at the friction
band's mid radius; run-out = ``u_z`` of the inboard face at the outer radius
(the mounting face is held, so it is the axial run-out against the hub).

Thermal strain enters the elastic solve as in :mod:`brakewear.thermal.strain`:
the load is ``G dT`` with ``G`` the matrix of
:func:`brakewear.fem.heat.thermal_coupling` (assembled on P2 bases, or on an
element subset, here).

Run ``python studies/thermal_coning.py [--out DIR] [--sizes MM ...]
[--order N] [--no-figures]``; writes ``DIR/data/thermal_coning.json`` and
``DIR/figures/thermal_coning.png``.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import skfem as fem

from brakewear.caliper.geometry import HatGeometry
from brakewear.fem import apply_dirichlet, assemble_stiffness, boundary_dofs, scalar_element
from brakewear.geometry import load_geometry
from brakewear.mesh import full_rotor_mesh, rotor_mesh
from brakewear.mesh.convergence import fitted_rate
from brakewear.solvers.amg import amg_solver
from brakewear.thermal.hat_cone import (
    axisymmetric_cone,
    face_cone,
    hat_cone_estimate,
    plate_curvature,
)
from brakewear.thermal.strain import thermal_load, thermal_stress

sys.path.insert(0, str(Path(__file__).resolve().parent))
from thermal_figures import coning_figure  # noqa: E402  (a sibling script, not a package)

logger = logging.getLogger("thermal_coning")

#: A hat for the default 300 mm rotor (m): 45 mm deep, 6 mm wall whose outer
#: surface is the ring's inner radius, 7 mm flange, 66 mm bore, clamped out
#: to the 114.3 mm bolt circle (radius 57 mm).
HAT = HatGeometry(height=0.045, wall_radius=0.087, wall_thickness=0.006, flange_thickness=0.007,
                  bore_radius=0.033, bolt_circle_radius=0.057)
DT = 100.0  # K; every result is linear in dT and reported per 100 K


def hat_geometry(base=None):
    """The default geometry with :data:`HAT` and ``mount = "hat"``."""
    g = load_geometry("default") if base is None else base
    return replace(g, rotor=replace(g.rotor, mount="hat", hat=HAT))


# ---------------------------------------------------------------- closed forms

# ------------------------------------------------------- axisymmetric FE model

# ------------------------------------------------------------------- 3D solves

def _solve(K, f, fixed, coords, tol=1e-10) -> tuple[np.ndarray, dict]:
    Kd, fd = apply_dirichlet(K, f, fixed)
    solver = amg_solver(Kd, coords=coords, fixed=fixed, tol=tol)
    u = solver.solve(fd)
    return u, {"iterations": int(solver.info.iterations), "dofs": int(K.shape[0]),
               "relative_residual": float(solver.info.relative_residual)}


def _three_two_one(coords: np.ndarray, ri: float, t: float) -> np.ndarray:
    """DOFs of a statically determinate support: all three at the node nearest
    ``(ri, 0, -t/2)``, y and z at the one nearest ``(-ri, 0, -t/2)``, z at the
    one nearest ``(0, ri, -t/2)``."""
    def near(x, y):
        return int(np.argmin(np.sum((coords - np.array([[x], [y], [-0.5 * t]])) ** 2, axis=0)))
    a, b, c = near(ri, 0.0), near(-ri, 0.0), near(0.0, ri)
    return np.array([3 * a, 3 * a + 1, 3 * a + 2, 3 * b + 1, 3 * b + 2, 3 * c + 2])


def free_plate(size: float, order: int, dT: float = DT, geom=None) -> dict:
    """(a): the whole ring, ``T = dT (z + t/2) / t``, 3-2-1 support.

    Returns the FE curvature (from a least-squares fit of ``u_z`` at every
    node to ``a + b x + c y + d r^2 + e z^2``: ``kappa = -2 d``), the closed
    form, the largest von Mises stress over ``E alpha dT / (1 - nu)`` and the
    largest reaction over the load (zero: the load is self-equilibrated).
    """
    g = load_geometry("default") if geom is None else geom
    mat, t = g.rotor.material, g.rotor.thickness
    m = rotor_mesh(g, size=size, order=order, full=True)
    X = fem.Basis(m, scalar_element(m), intorder=1).doflocs
    T = dT * (X[2] + 0.5 * t) / t
    K, _ = assemble_stiffness(m, mat)
    f = thermal_load(m, mat, T)
    fixed = _three_two_one(X, g.rotor.inner_radius, t)
    u, info = _solve(K, f, fixed, X)
    reaction = np.abs((K @ u - f)[fixed]).max() / np.abs(f).max()
    uz = u[2::3]
    A = np.column_stack([np.ones(X.shape[1]), X[0], X[1], X[0] ** 2 + X[1] ** 2, X[2] ** 2])
    coef = np.linalg.lstsq(A, uz, rcond=None)[0]
    kappa = plate_curvature(mat.thermal.alpha, dT, t)
    s = thermal_stress(m, u, mat, T, name="rotor")
    vm = np.sqrt(0.5 * ((s[0] - s[1]) ** 2 + (s[1] - s[2]) ** 2 + (s[2] - s[0]) ** 2)
                 + 3 * (s[3] ** 2 + s[4] ** 2 + s[5] ** 2))
    scale = mat.elastic.E * mat.thermal.alpha * dT / (1 - mat.elastic.nu)
    return {"size_mm": 1e3 * size, "order": order, "kappa_fe": float(-2 * coef[3]),
            "kappa": kappa, "kappa_error": float(abs(-2 * coef[3] / kappa - 1)),
            "stress_ratio": float(vm.max() / scale), "reaction_ratio": float(reaction),
            "h_z_mm": 1e3 * float(np.diff(np.unique(np.round(m.p[2], 12))).max()), **info}


def hat_cone(size: float, order: int, dT: float = DT, hat_size: float | None = None,
             geom=None) -> dict:
    """(b): the hat rotor, ring elements heated by ``dT``, hat cold, mounting
    face clamped to the bolt circle.  Cone angle and run-out of the inboard
    face (:func:`~brakewear.thermal.hat_cone.face_cone`) and the face's ``u_z(r)``."""
    g = hat_geometry() if geom is None else geom
    mat = g.rotor.material
    m = full_rotor_mesh(g, size=size, order=order, hat_size=size if hat_size is None else hat_size)
    X = fem.Basis(m, scalar_element(m), intorder=1).doflocs
    K, _ = assemble_stiffness(m, mat)
    f = thermal_load(m, mat, np.full(X.shape[1], dT), elements=m.subdomains["ring"])
    fixed = boundary_dofs(m, "rotor_clamp")
    u, info = _solve(K, f, fixed, X)
    face = np.abs(X[2]) < 1e-9 * g.rotor.outer_radius
    out = face_cone(g, np.hypot(X[0, face], X[1, face]), u[2::3][face])
    out.update(size_mm=1e3 * size, order=order, **info)
    return out


# ------------------------------------------------------------------- the study

def _axisymmetric_reference(g, dT: float, sizes) -> tuple[dict, dict]:
    """The section model on halving sizes; the finest run and the Richardson
    extrapolation of its cone and run-out."""
    runs = [axisymmetric_cone(g, dT, h) for h in sizes]
    c = [r["cone"] for r in runs]
    rate = 1.0
    if len(c) >= 3:
        rate = float(np.log2(abs((c[-3] - c[-2]) / (c[-2] - c[-1]))))
    q = 2.0 ** rate - 1.0
    ref = {"cone": c[-1] + (c[-1] - c[-2]) / q, "cones": c, "rate": rate,
           "runout": runs[-1]["runout"] + (runs[-1]["runout"] - runs[-2]["runout"]) / q}
    print(f"axisymmetric: cone {', '.join(f'{1e3 * x:.4f}' for x in c)} mrad at "
          f"{', '.join(f'{1e3 * h:g}' for h in sizes)} mm (rate {rate:.2f}) -> "
          f"{1e3 * ref['cone']:.4f} mrad")
    return runs[-1], ref


def main(out: str | Path | None = "docs", plate_sizes=(0.016, 0.012, 0.008),
         hat_sizes=(0.012, 0.008, 0.006), hat_size_ratio: float = 0.5, order: int = 2,
         axi_sizes=(2e-3, 1e-3, 5e-4), dT: float = DT, figures: bool = True) -> dict:
    """Run (a) and (b); return the numbers (per ``dT``; ``dT`` = 100 K by default).

    Parameters
    ----------
    out
        Folder: writes ``out/data/thermal_coning.json`` and
        ``out/figures/thermal_coning.png``; None: nothing is written.
    plate_sizes, hat_sizes
        In-plane mesh sizes (m) of the free ring (a) and of the hat rotor (b).
    hat_size_ratio
        Size in the hat's section over the ring's size (b).
    order
        Element order of the 3D meshes.
    axi_sizes
        Element sizes (m) of the axisymmetric section model, halving: the
        finest run, extrapolated (Richardson, with the observed rate from
        three sizes, else rate 1), is the reference of (b).
    """
    t0 = time.perf_counter()
    plate = [free_plate(s, order, dT) for s in plate_sizes]
    for p in plate:
        print(f"(a) size {p['size_mm']:4.1f} mm P{order}: {p['dofs']:6d} DOFs, kappa "
              f"{p['kappa_fe']:.5f} / {p['kappa']:.5f} 1/m (error {100 * p['kappa_error']:.3f} %), "
              f"max von Mises {100 * p['stress_ratio']:.2f} % of E alpha dT/(1-nu)")
    g = hat_geometry()
    axi, ref = _axisymmetric_reference(g, dT, axi_sizes)
    est = {k: hat_cone_estimate(g, dT, k) for k in ("plate", "rigid")}
    hat = [hat_cone(s, order, dT, hat_size=hat_size_ratio * s) for s in hat_sizes]
    for h in hat:
        h["diff_vs_axisymmetric"] = h["cone"] / ref["cone"] - 1
        print(f"(b) size {h['size_mm']:4.1f} mm P{order}: {h['dofs']:6d} DOFs, cone "
              f"{1e3 * h['cone']:.4f} mrad, run-out {1e6 * h['runout']:.2f} um "
              f"({100 * h['diff_vs_axisymmetric']:+.2f} % vs axisymmetric)")
    ext = None
    if len(hat) >= 2:  # Richardson with rate 1 (the section's corner limits both models to it)
        h1, h2 = hat[-2], hat[-1]
        ext = h2["cone"] + (h2["cone"] - h1["cone"]) / (h1["size_mm"] / h2["size_mm"] - 1.0)
        print(f"(b) 3D extrapolated (rate 1): {1e3 * ext:.4f} mrad "
              f"({100 * (ext / ref['cone'] - 1):+.2f} % vs axisymmetric)")
    per = 100.0 / dT
    res = {
        "settings": {"dT_K": dT, "order": order, "axi_sizes_mm": [1e3 * h for h in axi_sizes],
                     "hat_size_ratio": hat_size_ratio,
                     "hat_mm": {k: 1e3 * getattr(HAT, k) for k in HAT.__dataclass_fields__}},
        "plate": plate,
        "plate_rate": fitted_rate([p["size_mm"] for p in plate], [p["kappa_error"] for p in plate]),
        "axisymmetric": {"cone_mrad": 1e3 * ref["cone"], "runout_um": 1e6 * ref["runout"],
                         "finest_cone_mrad": 1e3 * axi["cone"], "dofs": axi["dofs"],
                         "runs_cone_mrad": [1e3 * c for c in ref["cones"]], "rate": ref["rate"],
                         "richardson_change": ref["cone"] / axi["cone"] - 1},
        "estimate": {k: {"cone_mrad": 1e3 * e["cone"], "edge_rotation_mrad": 1e3 * e["psi"],
                         "runout_um": 1e6 * e["runout"], "beta_L": e["beta_L"],
                         "diff_vs_axisymmetric": e["cone"] / ref["cone"] - 1,
                         "runout_diff_vs_axisymmetric": e["runout"] / ref["runout"] - 1}
                     for k, e in est.items()},
        "hat": [{k: v for k, v in h.items() if k not in ("r", "uz")} for h in hat],
        "hat_extrapolated": None if ext is None else {
            "cone_mrad": 1e3 * ext, "diff_vs_axisymmetric": ext / ref["cone"] - 1},
        "per_100K": {"cone_mrad": 1e3 * hat[-1]["cone"] * per,
                     "runout_um": 1e6 * hat[-1]["runout"] * per,
                     "cone_mrad_axisymmetric": 1e3 * ref["cone"] * per,
                     "runout_um_axisymmetric": 1e6 * ref["runout"] * per},
    }
    res["total_s"] = time.perf_counter() - t0
    p100 = res["per_100K"]
    print(f"per 100 K: cone {p100['cone_mrad']:.3f} mrad, run-out at the outer radius "
          f"{p100['runout_um']:.1f} um (axisymmetric {p100['cone_mrad_axisymmetric']:.3f} mrad, "
          f"{p100['runout_um_axisymmetric']:.1f} um); closed form (plate ring) "
          f"{res['estimate']['plate']['cone_mrad'] * per:.3f} mrad "
          f"({100 * res['estimate']['plate']['diff_vs_axisymmetric']:+.1f} %)")
    if out is not None:
        out = Path(out)
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "thermal_coning.json").write_text(json.dumps(res, indent=1) + "\n")
        if figures:
            (out / "figures").mkdir(parents=True, exist_ok=True)
            coning_figure(g, axi, est, hat[-1], dT, out / "figures" / "thermal_coning.png")
    return res


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description="Thermal coning: free plate and hat rotor")
    ap.add_argument("--out", default="docs", help="folder of data/ and figures/")
    ap.add_argument("--sizes", type=float, nargs="+", default=[12.0, 8.0, 6.0],
                    help="hat rotor mesh sizes (mm)")
    ap.add_argument("--order", type=int, default=2)
    ap.add_argument("--no-figures", action="store_true")
    a = ap.parse_args()
    logging.basicConfig(level=logging.WARNING)
    main(a.out, hat_sizes=tuple(1e-3 * s for s in a.sizes), order=a.order,
         figures=not a.no_figures)
