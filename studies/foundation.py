"""Winkler (elastic-foundation) interface against FE contact on the default brake.

Run ``python studies/foundation.py [--size MM] [--out DIR]``: solves the FE
contact of the default brake (elastic rotor) at 1 MPa line pressure with
mu = 0 and 0.4, builds the Winkler interface (Johnson modulus; rigid and
foundation rotor), calibrates it (stiffness; pressure), compares, times one
Winkler solve against one FE solve, checks the sphere closed form, and
writes ``foundation_study.json``, ``foundation_profile.csv`` (docs/data) and
``foundation_pressure.png`` (docs/figures).
"""
from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from brakewear import analytic as an
from brakewear.analytic import johnson_modulus
from brakewear.interfaces import WinklerInterface, calibrate, compare, fe_lever_arm
from brakewear.model import BrakeModel
from brakewear.static import solve_contact


def sphere_check(n: int = 161) -> dict:
    """Rigid sphere on a thin constrained layer, nodal solve against the closed forms."""
    R, E, nu, h, F = 0.01, 3e9, 0.25, 1e-3, 10.0
    k = johnson_modulus(E, nu, h)
    half = 1.5 * np.sqrt(2 * R * an.winkler_sphere_approach(F, R, k))
    xs = np.linspace(-half, half, n)
    X, Y = np.meshgrid(xs, xs)
    w = np.ones(n)
    w[[0, -1]] = 0.5
    A = np.outer(w, w).ravel() * (xs[1] - xs[0]) ** 2
    xy = np.vstack([X.ravel(), Y.ravel()])
    wi = WinklerInterface(xy, A, k, (0.0, 0.0), offset=(xy ** 2).sum(axis=0) / (2 * R))
    res = wi.solve_force(F)
    r = np.hypot(*xy)
    ws = an.winkler_sphere(R, k, F=F)
    hz = an.hertz_sphere(F, R, an.effective_modulus(E, nu))
    p_nodal = an.winkler_sphere_pressure(r, R, k, res.approach)
    return {
        "R_m": R, "E_Pa": E, "nu": nu, "layer_m": h, "F_N": F, "k_Pa_per_m": k, "grid": n,
        "winkler": {"a_m": ws["a"], "delta_m": ws["delta"], "p0_Pa": ws["p0"]},
        "hertz_half_space": {"a_m": hz["a"], "delta_m": hz["delta"], "p0_Pa": hz["p0"]},
        "nodal_solve": {"delta_m": res.approach,
                        "delta_rel_error": res.approach / ws["delta"] - 1,
                        "pressure_max_rel_error_vs_closed_form_at_solved_delta":
                            float(np.abs(res.pressure - p_nodal).max() / p_nodal.max()),
                        "active_set_is_disc_r_lt_sqrt_2R_delta": bool(np.array_equal(
                            res.active, r < np.sqrt(2 * R * res.approach))),
                        "iterations": res.iterations},
        "ratio_a_winkler_over_hertz_same_load": ws["a"] / hz["a"],
        "ratio_a_same_approach": float(np.sqrt(2.0)),
    }


def time_winkler(wi: WinklerInterface, lp: float, mu: float, repeat: int = 200) -> float:
    t = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        wi.solve(lp, mu)
        t.append(time.perf_counter() - t0)
    return float(np.median(t))


def mean_radius_profile(wi, p, r_target):
    r = np.hypot(*wi.xy)
    rows = np.unique(np.round(r, 9))
    r_row = rows[np.argmin(np.abs(rows - r_target))]
    sel = np.nonzero(np.abs(r - r_row) < 1e-7)[0]
    th = np.degrees(np.arctan2(wi.xy[1, sel], wi.xy[0, sel]))
    o = np.argsort(th)
    return r_row, sel[o], th[o]


def main(size_mm: float | None = None, out_data="docs/data", out_fig="docs/figures",
         line_pressure: float = 1e6, mu: float = 0.4, figures: bool = True) -> dict:
    model = BrakeModel("default", rotor="elastic",
                       size=None if size_mm is None else size_mm * 1e-3)
    g = model.geometry
    fe, fe_time = {}, {}
    for m in (0.0, mu):
        t0 = time.perf_counter()
        fe[m] = solve_contact(model, line_pressure, m)
        fe_time[m] = time.perf_counter() - t0   # the first includes the stiffness assembly
    # one FE solve with the stiffness already assembled (what a wear step costs)
    t0 = time.perf_counter()
    solve_contact(model, line_pressure, 0.0)
    fe_repeat = time.perf_counter() - t0
    out = {"line_pressure_Pa": line_pressure, "mu": mu, "dofs": int(model.dofs),
           "interface_nodes": int(fe[0.0].interface_nodes.size),
           "mesh_size_m": g.mesh.size if size_mm is None else size_mm * 1e-3,
           "fe_solve_s": {str(k): v for k, v in fe_time.items()},
           "fe_solve_repeat_s": fe_repeat, "sphere": sphere_check()}
    cases = {}
    for rotor in ("rigid", "foundation"):
        wi = WinklerInterface.from_model(model, rotor=rotor)
        for m in (0.0, mu):
            key = f"{rotor}_mu{m:g}"
            raw = compare(wi, fe[m])
            st = calibrate(wi, fe[m], "stiffness", model=model)  # FE lever arm if mu > 0
            cases[key] = {"johnson_modulus_Pa_per_m": float(wi.modulus.mean()),
                          "uncalibrated": raw["errors"],
                          "uncalibrated_winkler": raw["winkler"], "fe": raw["fe"],
                          "stiffness_calibrated": st.errors, "stiffness_scale": st.scale,
                          "calibrated_modulus_Pa_per_m": float(st.interface.modulus.mean()),
                          "lever_arm_m": st.interface.lever_arm}
    out["cases"] = cases
    wi = WinklerInterface.from_model(model, rotor="foundation")
    pc = calibrate(wi, fe[0.0], "pressure", model=model)
    out["pressure_calibrated_mu0"] = {"at_mu0": pc.errors,
                                      "at_mu": compare(pc.interface, fe[mu])["errors"],
                                      "load_point_shift_m": pc.interface.info["load_point_shift_m"]}
    sc = calibrate(wi, fe[0.0], "stiffness")
    out["stiffness_calibrated_mu0_at_mu"] = compare(sc.interface, fe[mu])["errors"]
    # speed: one Winkler solve (median of 200) against one FE contact solve
    tw = {str(m): time_winkler(sc.interface, line_pressure, m) for m in (0.0, mu)}
    out["winkler_solve_s"] = tw
    out["speed_ratio"] = {
        "fe_first_over_winkler": {k: fe_time[float(k)] / v for k, v in tw.items()},
        "fe_repeat_over_winkler_mu0": fe_repeat / tw["0.0"]}
    # centre-of-pressure shift by friction, FE and Winkler, and the FE's lever arm
    sh = {}
    for name, res in (("fe", fe), ("winkler", {m: sc.interface.solve(line_pressure, m)
                                              for m in (0.0, mu)})):
        if name == "fe":
            cop = {m: _cop(sc.interface, np.where(r.active, r.interface_pressure, 0)) for m, r
                   in res.items()}
        else:
            cop = {m: r.centre for m, r in res.items()}
        th = {m: np.degrees(np.arctan2(c[1], c[0])) for m, c in cop.items()}
        sh[name] = {"cop_shift_deg": float(th[mu] - th[0.0]),
                    "cop_shift_m": (cop[mu] - cop[0.0]).tolist()}
    sh["lever_arm_model_m"] = sc.interface.lever_arm
    fel = fe_lever_arm(model, fe[mu])
    sh["lever_arm_fe_abutment_m"] = fel
    rl = {m: replace(sc.interface, lever_arm=fel).solve(line_pressure, m).centre for m in (0.0, mu)}
    sh["winkler_fe_lever"] = {"cop_shift_deg": float(np.degrees(
        np.arctan2(rl[mu][1], rl[mu][0]) - np.arctan2(rl[0.0][1], rl[0.0][0])))}
    # the lever arm that would give the FE's shift: shift along y = -lever * mu
    sh["lever_arm_fe_effective_m"] = float(-sh["fe"]["cop_shift_m"][1] / mu)
    out["friction_shift"] = sh

    # the profile along the mean radius and the maps
    r_mid = 0.5 * (g.pad.inner_radius + g.pad.outer_radius)
    r_row, sel, th = mean_radius_profile(sc.interface, None, r_mid)
    prof = {"theta_deg": th}
    for m in (0.0, mu):
        pf = np.where(fe[m].active, fe[m].interface_pressure, 0.0)
        prof[f"fe_mu{m:g}_MPa"] = pf[sel] / 1e6
        prof[f"winkler_mu{m:g}_MPa"] = sc.interface.solve(line_pressure, m).pressure[sel] / 1e6
        prof[f"winkler_pcal_mu{m:g}_MPa"] = pc.interface.solve(line_pressure, m).pressure[sel] / 1e6
    out["profile_radius_m"] = float(r_row)
    if out_data is not None:
        d = Path(out_data)
        d.mkdir(parents=True, exist_ok=True)
        with open(d / "foundation_study.json", "w") as fh:
            json.dump(out, fh, indent=2, default=_jsonable)
        cols = list(prof)
        np.savetxt(d / "foundation_profile.csv", np.column_stack([prof[c] for c in cols]),
                   delimiter=",", header=",".join(cols), comments="", fmt="%.6g")
    if figures and out_fig is not None:
        _figure(Path(out_fig) / "foundation_pressure.png", sc.interface, fe, mu, prof, r_row,
                line_pressure, g)
    return out


def _cop(wi, p):
    fz = wi.area * p
    return (wi.xy * fz).sum(axis=1) / fz.sum()


def _jsonable(o):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if hasattr(o, "item"):
        return o.item()
    return str(o)


def _figure(path, wi, fe, mu, prof, r_row, lp, g):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(2, 2, figsize=(11, 8.5))
    for j, m in enumerate((0.0, mu)):
        a = ax[0, j]
        a.plot(prof["theta_deg"], prof[f"fe_mu{m:g}_MPa"], "o-", ms=3, label="FE contact")
        a.plot(prof["theta_deg"], prof[f"winkler_mu{m:g}_MPa"], "s--", ms=3,
               label="Winkler, uniform modulus (any k)")
        a.plot(prof["theta_deg"], prof[f"winkler_pcal_mu{m:g}_MPa"], "^:", ms=3,
               label="Winkler, per-node k fitted to FE at mu = 0")
        a.axvline(np.degrees(g.pad.leading_angle), color="0.6", lw=0.8)
        a.text(np.degrees(g.pad.leading_angle) + 0.5, 0.02, "leading edge", color="0.4",
               fontsize=8, transform=a.get_xaxis_transform())
        a.set_xlabel("angle theta (deg); rotor turns toward +theta")
        a.set_ylabel("contact pressure (MPa)")
        a.set_title(f"along r = {r_row * 1e3:.1f} mm, mu = {m:g}")
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    pf = np.where(fe[mu].active, fe[mu].interface_pressure, 0.0) / 1e6
    pw = wi.solve(lp, mu).pressure / 1e6
    vmax = max(pf.max(), pw.max())
    for j, (p, name) in enumerate(((pf, "FE contact"), (pw, "Winkler"))):
        a = ax[1, j]
        sc = a.scatter(wi.xy[1] * 1e3, wi.xy[0] * 1e3, c=p, s=max(3.0, 1600.0 / wi.n),
                       cmap="inferno", vmin=0, vmax=vmax)
        a.set_aspect("equal")
        a.set_xlabel("y (mm), rotor velocity +y")
        a.set_ylabel("x (mm), radial at the pad centre")
        a.set_title(f"{name}, mu = {mu:g} (open nodes: 0)")
        fig.colorbar(sc, ax=a, label="pressure (MPa)", shrink=0.8)
    fig.suptitle(f"Default brake, {lp / 1e6:g} MPa line pressure: FE contact vs Winkler "
                 "interface (maps: uniform modulus)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=None, help="mesh size at the interface, mm")
    ap.add_argument("--out-data", default="docs/data")
    ap.add_argument("--out-fig", default="docs/figures")
    ap.add_argument("--mu", type=float, default=0.4)
    a = ap.parse_args()
    res = main(a.size, a.out_data, a.out_fig, mu=a.mu)
    print(json.dumps({k: v for k, v in res.items() if k != "cases"}, indent=1,
                     default=_jsonable))
    for k, v in res["cases"].items():
        print(k, {e: round(x, 4) for e, x in v["stiffness_calibrated"].items()})
