"""How wrong is the elastic foundation on rough surfaces? A smooth sphere on a rough
plane, the Winkler bed and brush against the half-space reference (docs/rough.md).

Run ``python studies/rough_foundation.py [--grids 128 256] [--fine 512] [--seeds 5]``.

The sphere (radius R) is pressed on a self-affine rough plane by the load that
gives a Hertz contact radius ``a = L / 8`` on the smooth plane (``L`` the
grid's side; a free, zero-padded grid).  The roughness has the rms height
``sigma = ratio * delta_H`` (``delta_H = a^2 / R``, Hertz's approach), Hurst
exponent 0.8, a roll-off at ``L / 4`` and a cut-off at ``L / 32``; the same
seed gives the same surface on every grid (:func:`brakewear.rough.self_affine`).
The foundation is calibrated on the smooth case as the thesis does
(:func:`brakewear.rough.hertz_calibrated_bed`): Hertz's radius and load,
Mindlin's tangential stiffness.

For each grid, roughness and seed it solves both models at the same load and
reports the foundation's errors against the half-space: pressure (relative L2
over the grid, and the peak), real contact area, approach (from first
touch), normal tangent stiffness (the punch on the contact set) and
tangential stiffness (the stuck contact, Cerruti).  The fine grid shows how
far the reference has converged.  Writes ``rough_foundation.json`` and
``rough_foundation.csv`` (docs/data), ``rough_foundation.png`` and
``rough_foundation_maps.png`` (docs/figures).
"""
from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

import numpy as np

from brakewear import analytic as an
from brakewear.rough import (
    HalfSpace,
    Topography,
    contact_stiffness,
    hertz_calibrated_bed,
    self_affine,
    solve_normal,
)

#: The problem, in SI units (the answers are ratios; any consistent set gives the same).
PROBLEM = {"R_m": 0.01, "E_star_Pa": 1e9, "nu": 0.3, "a_hertz_m": 0.5e-3, "side_over_a": 8.0,
           "hurst": 0.8, "rolloff_over_side": 0.25, "cutoff_over_side": 1.0 / 32.0,
           "tol": 1e-8}
RATIOS = (0.0, 0.1, 0.25, 0.5, 1.0, 1.5, 2.0)
#: the foundation's calibrations on the smooth sphere: the thesis's (Hertz's radius at
#: Hertz's load) and Hertz's stiffness at Hertz's load
CALIBRATIONS = ("radius", "stiffness")
ERRORS = ("pressure_l2", "peak_pressure", "contact_area", "approach", "normal_stiffness",
          "tangential_stiffness")


def _setup():
    P = PROBLEM
    R, Es, a = P["R_m"], P["E_star_Pa"], P["a_hertz_m"]
    F = 4.0 * Es * a ** 3 / (3.0 * R)           # Hertz: a^3 = 3 F R / (4 E*)
    return R, Es, a, F, a * a / R, P["side_over_a"] * a


def _errors(ref, kn: float, kt: float, fnd, g_min: float) -> dict:
    """(foundation - half-space) / half-space; the pressure's relative L2 norm."""
    p, q = ref.pressure, fnd.pressure
    return {"pressure_l2": float(np.linalg.norm(q - p) / np.linalg.norm(p)),
            "peak_pressure": float(q.max() / p.max() - 1),
            "contact_area": fnd.area / ref.area - 1,
            "approach": (fnd.approach - g_min) / (ref.approach - g_min) - 1,
            "normal_stiffness": fnd.normal_stiffness / kn - 1,
            "tangential_stiffness": fnd.tangential_stiffness / kt - 1}


def case(n: int, ratio: float, seed: int, hs: HalfSpace, keep_fields: bool = False) -> dict:
    """Both models on one surface; the errors (foundation - half-space) / half-space."""
    P = PROBLEM
    R, Es, a, F, dH, L = _setup()
    if ratio > 0:
        t = self_affine(n, L, P["hurst"], rms_height=ratio * dH,
                        rolloff=P["rolloff_over_side"] * L, cutoff=P["cutoff_over_side"] * L,
                        seed=seed)
    else:
        t = Topography(np.zeros((n, n)), L / n, periodic=True)
    X, Y = t.coordinates()
    g0 = (X ** 2 + Y ** 2) / (2 * R) - t.heights
    g_min = float(g0.min())
    ref = solve_normal(hs, g0, load=F, tol=P["tol"])
    kn = contact_stiffness(hs, ref.contact, "normal")
    kt = contact_stiffness(hs, ref.contact, "tangential")
    beds = {m: hertz_calibrated_bed(F, R, Es, P["nu"], m) for m in CALIBRATIONS}
    t0 = time.perf_counter()
    fnd = beds["radius"].solve(g0, hs.pixel_area, F)
    t_fnd = time.perf_counter() - t0
    err = _errors(ref, kn.stiffness, kt.stiffness, fnd, g_min)
    err_k = _errors(ref, kn.stiffness, kt.stiffness,
                    beds["stiffness"].solve(g0, hs.pixel_area, F), g_min)
    p, q = ref.pressure, fnd.pressure
    out = {"n": n, "ratio": ratio, "seed": seed, "errors": err, "errors_stiffness_bed": err_k,
           "sigma_m": ratio * dH, "rms_slope": t.rms_slope(),
           "halfspace": {"area_m2": ref.area, "peak_Pa": float(p.max()),
                         "approach_from_touch_m": ref.approach - g_min,
                         "normal_stiffness_N_per_m": kn.stiffness,
                         "tangential_stiffness_N_per_m": kt.stiffness,
                         "kt_over_kn": kt.stiffness / kn.stiffness,
                         "iterations": ref.iterations,
                         "seconds": ref.seconds + kn.seconds + kt.seconds,
                         "normal_solve_s": ref.seconds},
           "foundation": {"area_m2": fnd.area, "peak_Pa": float(q.max()),
                          "approach_from_touch_m": fnd.approach - g_min,
                          "normal_stiffness_N_per_m": fnd.normal_stiffness,
                          "tangential_stiffness_N_per_m": fnd.tangential_stiffness,
                          "seconds": t_fnd}}
    if keep_fields:
        out["fields"] = {"x": X[:, 0], "y": Y[0], "p_ref": p, "p_fnd": q}
    return out


def summarise(rows: list[dict], key: str = "errors") -> list[dict]:
    """Mean, standard deviation, min and max over the seeds, per grid and roughness, of the
    errors under ``key`` (``"errors"``: the thesis's calibration; ``"errors_stiffness_bed"``)."""
    out = []
    for n in sorted({r["n"] for r in rows}):
        for ratio in sorted({r["ratio"] for r in rows if r["n"] == n}):
            sel = [r for r in rows if r["n"] == n and r["ratio"] == ratio]
            row = {"n": n, "ratio": ratio, "seeds": len(sel)}
            for e in ERRORS:
                v = np.array([r[key][e] for r in sel])
                row.update({f"{e}_mean": float(v.mean()), f"{e}_std": float(v.std()),
                            f"{e}_min": float(v.min()), f"{e}_max": float(v.max())})
            out.append(row)
    return out


def convergence(rows: list[dict], fine: int | None) -> list[dict]:
    """The reference's figures on each grid relative to the finest, per roughness (seed mean
    of the relative differences, same surfaces)."""
    if not fine:
        return []
    keys = ("area_m2", "peak_Pa", "approach_from_touch_m", "normal_stiffness_N_per_m",
            "tangential_stiffness_N_per_m")
    by = {(r["n"], r["ratio"], r["seed"]): r for r in rows}
    out = []
    for (n, ratio, seed) in sorted(by):
        if n == fine or (fine, ratio, seed) not in by:
            continue
        f, c = by[(fine, ratio, seed)]["halfspace"], by[(n, ratio, seed)]["halfspace"]
        out.append({"n": n, "fine": fine, "ratio": ratio, "seed": seed,
                    **{k: c[k] / f[k] - 1 for k in keys}})
    agg = []
    for n in sorted({o["n"] for o in out}):
        for ratio in sorted({o["ratio"] for o in out if o["n"] == n}):
            sel = [o for o in out if o["n"] == n and o["ratio"] == ratio]
            agg.append({"n": n, "fine": fine, "ratio": ratio, "seeds": len(sel),
                        **{k: float(np.mean([abs(o[k]) for o in sel])) for k in keys}})
    return agg


def figure(summary: list[dict], summary_k: list[dict], path: Path) -> None:
    import matplotlib.pyplot as plt

    titles = {"pressure_l2": "pressure, relative L2 error", "peak_pressure": "peak pressure",
              "contact_area": "real contact area", "approach": "approach from first touch",
              "normal_stiffness": "normal stiffness", "tangential_stiffness":
              "tangential stiffness"}
    fig, axes = plt.subplots(2, 3, figsize=(12, 7), sharex=True)
    grids = sorted({s["n"] for s in summary})
    for ax, e in zip(axes.ravel(), ERRORS):
        for n, c in zip(grids, ("C0", "C1", "C2", "C3")):
            sel = [s for s in summary if s["n"] == n]
            x = [s["ratio"] for s in sel]
            ax.plot(x, [100 * s[f"{e}_mean"] for s in sel], "o-", color=c, ms=3,
                    label=f"{n}$^2$ (mean, band: min-max of {sel[-1]['seeds']} seeds)")
            ax.fill_between(x, [100 * s[f"{e}_min"] for s in sel],
                            [100 * s[f"{e}_max"] for s in sel], color=c, alpha=0.2)
        if e in ("normal_stiffness", "tangential_stiffness"):
            sel = [s for s in summary_k if s["n"] == grids[-1]]
            x = [s["ratio"] for s in sel]
            ax.plot(x, [100 * s[f"{e}_mean"] for s in sel], "s--", color="C3", ms=3,
                    label=f"bed calibrated on the stiffness, {grids[-1]}$^2$")
            ax.fill_between(x, [100 * s[f"{e}_min"] for s in sel],
                            [100 * s[f"{e}_max"] for s in sel], color="C3", alpha=0.15)
            ax.legend(fontsize=7)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_title(titles[e], fontsize=10)
        ax.set_ylabel("foundation error (%)")
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel(r"roughness $\sigma / \delta_{Hertz}$")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("Winkler bed and brush calibrated on the smooth sphere (Hertz's radius and "
                 "load) against the half-space, sphere on a rough plane", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def maps_figure(cases: list[dict], path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(cases), figsize=(3.2 * len(cases), 6.2))
    a = PROBLEM["a_hertz_m"]
    for j, c in enumerate(cases):
        f = c["fields"]
        vmax = max(f["p_ref"].max(), f["p_fnd"].max()) / 1e6
        ext = [f["y"][0] / a, f["y"][-1] / a, f["x"][-1] / a, f["x"][0] / a]
        for i, (key, name) in enumerate((("p_ref", "half-space"), ("p_fnd", "foundation"))):
            ax = axes[i, j]
            im = ax.imshow(f[key] / 1e6, extent=ext, cmap="viridis", vmin=0, vmax=vmax)
            ax.set_xlim(-3, 3)
            ax.set_ylim(-3, 3)
            ax.set_title(rf"{name}, $\sigma/\delta_H$ = {c['ratio']:g}", fontsize=9)
            ax.set_xlabel("y / a")
            ax.set_ylabel("x / a")
            fig.colorbar(im, ax=ax, shrink=0.8, label="p (MPa)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def write_csv(summary: list[dict], path: Path) -> None:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(summary[0]))
        w.writeheader()
        w.writerows(summary)


def main(grids=(128, 256), fine: int | None = 512, ratios=RATIOS, seeds: int = 5,
         fine_seeds: int | None = None, out_data="docs/data", out_fig="docs/figures",
         write: bool = True, progress=print) -> dict:
    """Run the study; returns ``{"problem", "rows", "summary", "convergence", ...}``."""
    R, Es, a, F, dH, L = _setup()
    grids = tuple(grids)
    all_grids = grids + ((fine,) if fine and fine not in grids else ())
    rows, t0 = [], time.perf_counter()
    for n in all_grids:
        hs = HalfSpace((n, n), L / n, Es, PROBLEM["nu"])
        ns = seeds if n != fine or fine_seeds is None else fine_seeds
        for ratio in ratios:
            for seed in (range(ns) if ratio > 0 else [0]):
                rows.append(case(n, ratio, seed, hs))
                if progress:
                    r = rows[-1]
                    progress(f"  {n}^2 sigma/delta_H {ratio:g} seed {seed}: "
                             + ", ".join(f"{k} {100 * v:+.1f} %" for k, v in
                                         r["errors"].items())
                             + f" ({r['halfspace']['seconds']:.1f} s)")
    summary = summarise([r for r in rows if r["n"] in grids])
    result = {"problem": {**PROBLEM, "load_N": F, "delta_hertz_m": dH, "side_m": L,
                          "closed_form": an.winkler_hertz_match(F, R, Es)["ratio"]},
              "grids": list(grids), "fine": fine, "seeds": seeds, "ratios": list(ratios),
              "rows": rows, "summary": summary,
              "summary_stiffness_bed": summarise([r for r in rows if r["n"] in grids],
                                                 "errors_stiffness_bed"),
              "fine_summary": summarise([r for r in rows if r["n"] == fine]) if fine else [],
              "convergence": convergence(rows, fine),
              "seconds": time.perf_counter() - t0}
    if write:
        d, fdir = Path(out_data), Path(out_fig)
        d.mkdir(parents=True, exist_ok=True)
        fdir.mkdir(parents=True, exist_ok=True)
        (d / "rough_foundation.json").write_text(json.dumps(result, indent=1))
        write_csv(summary, d / "rough_foundation.csv")
        figure(summary, result["summary_stiffness_bed"], fdir / "rough_foundation.png")
        n = max(grids)
        hs = HalfSpace((n, n), L / n, Es, PROBLEM["nu"])
        maps_figure([case(n, r, 0, hs, keep_fields=True) for r in (0.0, 0.5, 2.0)],
                    fdir / "rough_foundation_maps.png")
    return result


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grids", type=int, nargs="+", default=[128, 256])
    ap.add_argument("--fine", type=int, default=512, help="finest grid (0: none)")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--fine-seeds", type=int, default=None, dest="fine_seeds")
    ap.add_argument("--out", default="docs/data")
    ap.add_argument("--fig", default="docs/figures")
    args = ap.parse_args()
    res = main(args.grids, args.fine or None, RATIOS, args.seeds, args.fine_seeds, args.out,
               args.fig)
    print(f"done in {res['seconds']:.0f} s")
    for s in res["summary"]:
        print(f"{s['n']}^2 sigma/delta_H {s['ratio']:g}: " + ", ".join(
            f"{e} {100 * s[e + '_mean']:+.1f} +- {100 * s[e + '_std']:.1f} %" for e in ERRORS))
