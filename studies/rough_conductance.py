"""The contact conductance of a rough interface from half-space solves, the law fitted to
them, Mikic's correlation beside it, and what both give for the default brake (docs/rough.md).

Run ``python studies/rough_conductance.py [--n 256] [--fine 512] [--seeds 3]``.

Periodic self-affine surfaces (Hurst 0.5 and 0.8, roll-off at a quarter of the
period, cut-off at four pixels) are pressed on a flat at nominal pressures
``p / (E* Sdq)`` from 1e-3 to 3e-2; at each the incremental normal stiffness
``k_n`` comes from the contact set (:func:`brakewear.rough.halfspace_conductance`)
and the conductance from Barber's analogy, ``h_c = kappa_s k_n / E*``.  The
law ``k_n = p / (gamma sigma)`` is fitted on ``HALFSPACE_FIT["range"]``; the
finer grid shows the solves have converged.  Writes
``rough_conductance.json`` and ``.csv`` (docs/data) and
``rough_conductance.png`` (docs/figures).
"""
from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

import numpy as np

from brakewear.analytic import effective_modulus, mikic_elastic_conductance
from brakewear.geometry import load_geometry
from brakewear.rough import RoughConductance, halfspace_conductance, self_affine
from brakewear.rough.conductance import HALFSPACE_FIT

E_STAR = 1e9
SURFACES = ({"hurst": 0.8, "rolloff": 0.25}, {"hurst": 0.5, "rolloff": 0.25},
            {"hurst": 0.8, "rolloff": 0.125})
#: illustrative faces of a run-in brake (rms height, areal rms slope Sdq): a turned or
#: ground grey-iron rotor and a bedded resin pad; calibrate for a real brake
BRAKE_FACES = {"pad": (3e-6, 0.2), "rotor": (1.5e-6, 0.1)}


def sweep(n: int, surface: dict, seed: int, x) -> dict:
    """One surface: ``k_n sigma / p`` (= 1/gamma) and Mikic's value at ``x = p / (E* Sdq)``."""
    L = 1e-3
    t = self_affine(n, L, surface["hurst"], rms_slope=0.1, rolloff=surface["rolloff"] * L,
                    cutoff=4 * L / 256, seed=seed)
    s, m = t.rms_height(), t.rms_slope()
    r = halfspace_conductance(t, E_STAR * m * np.asarray(x), E_STAR)
    mikic = mikic_elastic_conductance(r["p"], E_STAR, s, m / np.sqrt(np.pi), 1.0) * E_STAR
    return {"n": n, **surface, "seed": seed, "x": list(map(float, x)),
            "sigma_m": s, "sdq": m, "contact_fraction": r["contact_fraction"].tolist(),
            "kn_sigma_over_p": (r["k_n"] * s / r["p"]).tolist(),
            "mikic_kn_sigma_over_p": (mikic * s / r["p"]).tolist()}


def brake_figures() -> dict:
    """The default brake's faces (:data:`BRAKE_FACES`): h_c at 0.5-10 MPa line pressure."""
    g = load_geometry("default")
    pad, rotor = g.pad.friction_material, g.rotor.material
    Es = effective_modulus(pad.elastic.E_normal, pad.elastic.nu_normal,
                           rotor.elastic.E_normal, rotor.elastic.nu_normal)
    out = {"E_star_Pa": Es, "faces": BRAKE_FACES, "rows": []}
    for lp in (0.5e6, 1e6, 2e6, 5e6, 10e6):
        p = lp * g.clamp_area / g.pad.area
        row = {"line_pressure_MPa": lp / 1e6, "nominal_pressure_MPa": p / 1e6}
        for law in ("halfspace", "mikic"):
            rc = RoughConductance.of_faces(BRAKE_FACES["pad"], BRAKE_FACES["rotor"], Es,
                                           pad.thermal.kappa, rotor.thermal.kappa, law)
            row[f"h_c_{law}_W_m2K"] = float(rc.conductance(p))
        m = np.hypot(BRAKE_FACES["pad"][1], BRAKE_FACES["rotor"][1])
        row["p_over_Es_sdq"] = p / (Es * m)
        out["rows"].append(row)
    return out


def figure(rows: list[dict], gamma: float, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    styles = {}
    for r in rows:
        key = (r["n"], r["hurst"], r["rolloff"])
        c = styles.setdefault(key, f"C{len(styles)}")
        label = (f"half-space {r['n']}$^2$, H {r['hurst']}, roll-off L/{1 / r['rolloff']:.0f}"
                 if r["seed"] == 0 else None)
        ax.plot(r["x"], r["kn_sigma_over_p"], "o-", color=c, ms=3, lw=0.8, label=label)
    r0 = rows[0]
    ax.plot(r0["x"], r0["mikic_kn_sigma_over_p"], "k--", label="Mikic (1974), elastic")
    lo, hi = HALFSPACE_FIT["range"]
    ax.plot([lo, hi], [1 / gamma] * 2, "r-", lw=2.5, alpha=0.6,
            label=rf"fit $k_n = p / (\gamma \sigma)$, $\gamma$ = {gamma:.3f}")
    ax.set_xscale("log")
    ax.set_xlabel(r"nominal pressure $p / (E^* \, S_{dq})$")
    ax.set_ylabel(r"$k_n \sigma / p$  ($= h_c \sigma E^* / (\kappa_s p)$)")
    ax.set_title("Normal stiffness (and conductance) of a rough interface", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(n: int = 256, fine: int | None = 512, seeds: int = 3, points: int = 7,
         out_data="docs/data", out_fig="docs/figures", write: bool = True,
         progress=print) -> dict:
    """Run the sweeps and the fit; returns ``{"rows", "gamma", "brake", ...}``."""
    t0 = time.perf_counter()
    x = np.logspace(-3, np.log10(3e-2), points)
    rows = []
    for surface in SURFACES:
        for seed in range(seeds):
            rows.append(sweep(n, surface, seed, x))
            if progress:
                progress(f"  {n}^2 {surface} seed {seed}: k_n sigma / p = "
                         + " ".join(f"{v:.2f}" for v in rows[-1]["kn_sigma_over_p"]))
    if fine:
        rows.append(sweep(fine, SURFACES[0], 0, x))
    lo, hi = HALFSPACE_FIT["range"]
    sel = (x >= lo * (1 - 1e-9)) & (x <= hi * (1 + 1e-9))
    base = [r for r in rows if r["n"] == n]
    vals = np.array([np.array(r["kn_sigma_over_p"])[sel] for r in base])
    gamma = float(1.0 / vals.mean())
    per_surface = {f"H{s['hurst']}_rolloff{s['rolloff']}": float(1.0 / np.mean(
        [np.array(r["kn_sigma_over_p"])[sel] for r in base
         if r["hurst"] == s["hurst"] and r["rolloff"] == s["rolloff"]])) for s in SURFACES}
    conv = None
    if fine:
        a = np.array(rows[-1]["kn_sigma_over_p"])
        b = np.array(rows[0]["kn_sigma_over_p"])
        conv = {"fine": fine, "max_rel_difference": float(np.max(np.abs(b / a - 1)))}
    mik = np.array(rows[0]["mikic_kn_sigma_over_p"])[sel]
    res = {"E_star_Pa": E_STAR, "x": x.tolist(), "rows": rows, "gamma": gamma,
           "gamma_per_surface": per_surface,
           "spread_in_range": {"min": float(vals.min() * gamma - 1),
                               "max": float(vals.max() * gamma - 1)},
           "gamma_used": HALFSPACE_FIT["gamma"], "fit_range": [lo, hi],
           "mikic_over_fit_in_range": [float(mik.min() * gamma), float(mik.max() * gamma)],
           "grid_convergence": conv, "brake": brake_figures(),
           "seconds": time.perf_counter() - t0}
    if write:
        d, f = Path(out_data), Path(out_fig)
        d.mkdir(parents=True, exist_ok=True)
        f.mkdir(parents=True, exist_ok=True)
        (d / "rough_conductance.json").write_text(json.dumps(res, indent=1))
        with open(d / "rough_conductance.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["n", "hurst", "rolloff_over_side", "seed", "p_over_Es_sdq",
                        "contact_fraction", "kn_sigma_over_p", "mikic_kn_sigma_over_p"])
            for r in rows:
                for i, xi in enumerate(r["x"]):
                    w.writerow([r["n"], r["hurst"], r["rolloff"], r["seed"], xi,
                                r["contact_fraction"][i], r["kn_sigma_over_p"][i],
                                r["mikic_kn_sigma_over_p"][i]])
        figure(rows, gamma, f / "rough_conductance.png")
    return res


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--fine", type=int, default=512, help="finer grid (0: none)")
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args()
    r = main(args.n, args.fine or None, args.seeds)
    print(f"gamma = {r['gamma']:.4f} (per surface {r['gamma_per_surface']}), spread "
          f"{r['spread_in_range']}, Mikic/fit {r['mikic_over_fit_in_range']}, grid "
          f"{r['grid_convergence']}, {r['seconds']:.0f} s")
    for row in r["brake"]["rows"]:
        print(row)
