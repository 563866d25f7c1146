"""Running-in with the Winkler interface against the FE contact: profiles, errors, speed.

Run ``python studies/winkler_running_in.py [--size MM] [--duration S] [--steps N]
[--out DIR]`` from the repository root.  The default brake (elastic rotor) at
1 MPa line pressure, 55 rad/s, mu 0.4, Archard pad k 5e-15 1/Pa and rotor
k 5e-16 1/Pa, wears through a running-in with the implicit (backward Euler)
scheme and a fixed step sequence, once with the FE contact and once with
each Winkler interface:

- ``johnson``: Johnson's layer modulus with the rotor layer in series,
  uncalibrated (geometric lever arm);
- ``stiffness``: uniform modulus scaled to the FE stiffness (FE lever arm);
- ``pressure``: per-node modulus fitted to the FE pressure (at the load and
  mu of the run), so it starts on the FE pressure.

All four runs use the same steps.  At several stages it compares the pad
pressure and pad wear (along the mean radius against angle, along the centre
line against radius), the rotor wear against radius (ring means), the
``p r`` spread, and the time of the interface solves per step (``solve_s``).
Writes ``winkler_running_in.json``, ``winkler_running_in_steps.csv`` and
``winkler_running_in_profiles.csv`` (``OUT/data``) and
``winkler_running_in_{pressure,wear,history}.png`` (``OUT/figures``).

The pressure of a :class:`~brakewear.wear.WearStep` is the one at the
start of its step and its wear the one at the end, so the runs take one step
more than ``steps`` (``duration`` is the time of the last stage): the state
at time ``t_j = j duration / steps`` is the pressure of record ``j`` and the
wear of record ``j - 1``.
"""
from __future__ import annotations

import argparse
import csv
import json
import logging
import time
from pathlib import Path

import numpy as np

from brakewear.interfaces import WinklerInterface, calibrate, compare
from brakewear.mesh.rings import ring_profile
from brakewear.model import BrakeModel
from brakewear.interfaces import FoundationInterface
from brakewear.wear import wear_history
from brakewear.laws.base import WearLaw
from brakewear import Numerics
from brakewear.static import solve_contact
from brakewear.wear import Run

logger = logging.getLogger(__name__)

VARIANTS = ("johnson", "stiffness", "pressure")
LABELS = {"fe": "FE contact (elastic rotor)",
          "johnson": "Winkler, Johnson modulus (uncalibrated)",
          "stiffness": "Winkler, stiffness-calibrated",
          "pressure": "Winkler, pressure-calibrated (per node)"}
STYLES = {"fe": dict(color="k", marker="o", ls="-", ms=3, lw=1.6),
          "johnson": dict(color="tab:orange", marker="s", ls="--", ms=2.5, lw=1),
          "stiffness": dict(color="tab:blue", marker="^", ls="-.", ms=2.5, lw=1),
          "pressure": dict(color="tab:green", marker="v", ls=":", ms=2.5, lw=1.3)}


# ------------------------------------------------------------------ helpers --

def profile_nodes(xy: np.ndarray, geometry) -> dict:
    """Node selections of the two profiles: the row of pad nodes closest to the
    mean radius (sorted by angle) and, in every row of constant radius, the node
    closest to the pad's centre line (sorted by radius)."""
    r = np.hypot(xy[0], xy[1])
    th = np.arctan2(xy[1], xy[0])
    pad = geometry.pad
    r_mid = 0.5 * (pad.inner_radius + pad.outer_radius)
    rows = np.unique(np.round(r, 7))
    r_row = rows[np.argmin(np.abs(rows - r_mid))]
    sel = np.nonzero(np.abs(r - r_row) < 1e-6)[0]
    sel = sel[np.argsort(th[sel])]
    dth = np.abs(np.angle(np.exp(1j * (th - pad.center_angle))))
    centre = []
    for rr in rows:
        on = np.nonzero(np.abs(r - rr) < 1e-6)[0]
        centre.append(on[np.argmin(dth[on])])
    centre = np.array(centre)
    centre = centre[np.argsort(r[centre])]
    return {"mean_radius_m": float(r_row), "mean": sel, "theta_deg": np.degrees(th[sel]),
            "centre": centre, "centre_radius_m": r[centre],
            "centre_dtheta_deg_max": float(np.degrees(dth[centre].max()))}


def field_errors(a: np.ndarray, ref: np.ndarray, area: np.ndarray) -> dict:
    """Max and area-weighted L2 difference of ``a`` against ``ref`` (absolute and
    relative to max |ref| / the L2 norm of ref)."""
    d = a - ref
    nref = float(np.sqrt((area * ref ** 2).sum()))
    mref = float(np.abs(ref).max())
    return {"max_abs": float(np.abs(d).max()),
            "max_rel": float(np.abs(d).max() / mref) if mref > 0 else float("nan"),
            "l2_rel": float(np.sqrt((area * d ** 2).sum()) / nref) if nref > 0 else float("nan")}


def pr_spread(p: np.ndarray, r: np.ndarray, active: np.ndarray, area: np.ndarray) -> dict:
    """Spread of ``p r`` over the nodes in contact: (max - min) / mean, and the
    area-weighted coefficient of variation (steady-state running-in has p r ~ const)."""
    pr, A = (p * r)[active], area[active]
    m = float((A * pr).sum() / A.sum())
    return {"range_over_mean": float((pr.max() - pr.min()) / m),
            "cv": float(np.sqrt((A * (pr - m) ** 2).sum() / A.sum()) / m)}


def stage_indices(steps: int, n: int = 4) -> list[int]:
    """``n`` stage indices j in 0..steps (time j duration / steps), start and end included,
    denser early (the running-in is fastest at the start)."""
    if steps < 1:
        raise ValueError(f"steps = {steps!r}; need >= 1")
    q = np.linspace(0.0, 1.0, n) ** 1.6 * steps
    return sorted({int(round(x)) for x in q})


def run(model, itf, lp, omega, duration, steps, pad_law, rotor_law, mu):
    """One wear history with ``steps + 1`` equal steps of ``duration / steps``; the records
    and the wall time per step."""
    recs, wall = [], []
    t0 = time.perf_counter()
    kw = {} if itf is None else {"interface": itf}
    for s in wear_history(Run(model, lp, omega, duration * (steps + 1) / steps, pad_law, rotor_law, mu, **kw, numerics=Numerics(steps=steps + 1, scheme="implicit"))):
        t1 = time.perf_counter()
        logger.info("%s step %d: t = %.0f s, interface solve %.4g s, step %.4g s",
                    type(itf).__name__, s.step, s.time, s.solve_s, t1 - t0)
        recs.append(s)
        wall.append(t1 - t0)
        t0 = t1
    return recs, wall


def state(recs, j):
    """(pressure, active, pad wear, rotor wear) at time t_j."""
    p, act = recs[j].pressure, recs[j].active
    if j == 0:
        return p, act, np.zeros_like(recs[0].pad_wear), np.zeros_like(recs[0].rotor_wear)
    return p, act, recs[j - 1].pad_wear, recs[j - 1].rotor_wear


# --------------------------------------------------------------------- main --

def main(size: float | None = None, duration: float = 1500.0, steps: int = 15,
         out: str | Path | None = "docs", line_pressure: float = 1e6, omega: float = 55.0,
         mu: float = 0.4, k_pad: float = 5e-15, k_rotor: float = 5e-16, n_stages: int = 4,
         variants=VARIANTS, figures: bool = True, retime: int = 3) -> dict:
    """Run the comparison; returns everything written to the JSON (plus ``records``).

    Parameters
    ----------
    size
        Mesh size (m); default the geometry file's (2.5 mm).
    duration, steps
        Time of the last stage (s) and the number of equal steps to it.
    out
        Root of ``data/`` and ``figures/`` (None: write nothing).
    retime
        Repeats of each Winkler run after the FE run, timed again (the median per step
        goes in ``speed[variant]["retimed_*"]``); 0 skips it.
    """
    for name, v in (("duration", duration), ("line_pressure", line_pressure),
                    ("omega", omega), ("k_pad", k_pad), ("k_rotor", k_rotor)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v!r} is not allowed; need > 0")
    if int(steps) != steps or steps < 1:
        raise ValueError(f"steps = {steps!r} is not allowed; need a whole number >= 1")
    bad = [v for v in variants if v not in VARIANTS]
    if bad:
        raise ValueError(f"variants {bad} not allowed; allowed: {VARIANTS}")
    pad_law, rotor_law = WearLaw(k_pad), WearLaw(k_rotor)
    t0 = time.perf_counter()
    model = BrakeModel("default", rotor="elastic", size=size)
    g = model.geometry
    build_s = time.perf_counter() - t0
    logger.info("model: %d DOFs (%.1f s)", model.dofs, build_s)
    t0 = time.perf_counter()
    fe_static = solve_contact(model, line_pressure, mu)
    static_s = time.perf_counter() - t0

    # the Winkler interfaces
    winkler, calib = {}, {}
    if "johnson" in variants:
        wj = WinklerInterface.from_model(model, rotor="foundation")
        winkler["johnson"] = wj
        calib["johnson"] = {"errors": compare(wj, fe_static)["errors"], "scale": 1.0}
    base = WinklerInterface.from_model(model, rotor="rigid")
    for match in ("stiffness", "pressure"):
        if match in variants:
            rep = calibrate(base, fe_static, match, model=model)
            winkler[match] = rep.interface
            calib[match] = {"errors": rep.errors, "scale": rep.scale}
    for k, wi in winkler.items():
        calib[k].update({"modulus_mean_Pa_per_m": float(np.average(wi.modulus, weights=wi.area)),
                         "modulus_min_Pa_per_m": float(wi.modulus.min()),
                         "modulus_max_Pa_per_m": float(wi.modulus.max()),
                         "lever_arm_m": float(wi.lever_arm)})

    # the runs
    runs, walls, itfs = {}, {}, {}
    logger.info("FE run: %d steps", steps + 1)
    from brakewear.interfaces import FEInterface
    itfs["fe"] = FEInterface(model, line_pressure, mu)
    runs["fe"], walls["fe"] = run(model, itfs["fe"], line_pressure, omega, duration, steps,
                                  pad_law, rotor_law, mu)
    for k, wi in winkler.items():
        itfs[k] = FoundationInterface(model, wi, line_pressure, mu)
        runs[k], walls[k] = run(model, itfs[k], line_pressure, omega, duration, steps, pad_law,
                                rotor_law, mu)

    A = itfs["fe"].area
    r = itfs["fe"].r
    prof = profile_nodes(itfs["fe"].x[:2], g)
    F = line_pressure * g.piston.hydraulic_area
    times = [duration * j / steps for j in range(steps + 1)]
    stages = stage_indices(steps, n_stages)

    # rotor wear against radius: FE rings (rotor face nodes) and Winkler rings (pad radii)
    rf = ring_profile(itfs["fe"])[0]
    in_pad = (rf >= g.pad.inner_radius - 1e-9) & (rf <= g.pad.outer_radius + 1e-9)

    def rotor_profile(key, rw):
        return ring_profile(itfs[key], rw)

    xy = itfs["fe"].x[:2]

    def cop(p):
        fz = A * p
        c = (xy * fz).sum(axis=1) / fz.sum()
        return {"cop_r_mm": float(np.hypot(c[0], c[1]) * 1e3),
                "cop_theta_deg": float(np.degrees(np.arctan2(c[1], c[0])))}

    # where the centre of pressure would be at p r = const (uniform wear rate)
    c_inv = cop(1.0 / r)

    # per-time figures of every run, and errors against the FE
    per_time = {k: [] for k in runs}
    for j in range(steps + 1):
        pf, af, wf, rwf = state(runs["fe"], j)
        rr_fe, rv_fe = rotor_profile("fe", rwf)
        for k in runs:
            p, act, w, rw = state(runs[k], j)
            row = {"j": j, "time_s": times[j], "force_N": float((A * p).sum()),
                   "force_rel_error": float((A * p).sum() / F - 1.0),
                   "pressure_max_MPa": float(p.max() / 1e6),
                   "contact_fraction": float(A[act].sum() / A.sum()),
                   "pad_wear_max_um": float(w.max() * 1e6),
                   "pad_wear_mean_um": float((A * w).sum() / A.sum() * 1e6),
                   **cop(p),
                   **{f"pr_{n}": v for n, v in pr_spread(p, r, act, A).items()}}
            if k != "fe":
                ep = field_errors(p, pf, A)
                ew = field_errors(w, wf, A) if j > 0 else {"max_abs": 0.0, "max_rel": float("nan"),
                                                           "l2_rel": float("nan")}
                rr, rv = rotor_profile(k, rw)
                rv_i = np.interp(rr_fe[in_pad], rr, rv)
                er = field_errors(rv_i, rv_fe[in_pad], np.ones(int(in_pad.sum()))) if j > 0 \
                    else {"max_abs": 0.0, "max_rel": float("nan"), "l2_rel": float("nan")}
                row.update({"pressure_max_abs_diff_MPa": ep["max_abs"] / 1e6,
                            "pressure_max_rel_diff": ep["max_rel"],
                            "pressure_l2_rel": ep["l2_rel"],
                            "pad_wear_max_abs_diff_um": ew["max_abs"] * 1e6,
                            "pad_wear_max_rel_diff": ew["max_rel"],
                            "pad_wear_l2_rel": ew["l2_rel"],
                            "rotor_wear_max_abs_diff_um": er["max_abs"] * 1e6,
                            "rotor_wear_max_rel_diff": er["max_rel"],
                            "rotor_wear_l2_rel": er["l2_rel"]})
            per_time[k].append(row)

    # speed per step: the interface solves of each step (solve_s); steps 1..steps
    speed = {"fe_solve_s": [s.solve_s for s in runs["fe"]],
             "fe_step_wall_s": walls["fe"]}
    for k in winkler:
        ws = np.array([s.solve_s for s in runs[k]])
        fs = np.array(speed["fe_solve_s"])
        speed[k] = {"solve_s": ws.tolist(), "step_wall_s": walls[k],
                    "median_solve_s": float(np.median(ws)),
                    "ratio_of_medians": float(np.median(fs) / np.median(ws)),
                    "median_of_ratios": float(np.median(fs / ws)),
                    "min_ratio": float((fs / ws).min()),
                    "wall_ratio_of_medians": float(np.median(walls["fe"]) /
                                                   np.median(walls[k]))}
    speed["fe_median_solve_s"] = float(np.median(speed["fe_solve_s"]))
    # the Winkler runs again (cheap), to see how much of their step time is noise
    # of the shared machine: per step, the median over the repeats
    for k in winkler:
        rep = [[s.solve_s for s in run(model, itfs[k], line_pressure, omega, duration, steps,
                                       pad_law, rotor_law, mu)[0]] for _ in range(retime)]
        if rep:
            med = np.median(np.array(rep), axis=0)
            fs = np.array(speed["fe_solve_s"])
            speed[k].update({"retimed_repeats": retime, "retimed_solve_s": med.tolist(),
                             "retimed_median_solve_s": float(np.median(med)),
                             "retimed_median_of_ratios": float(np.median(fs / med))})

    # stage profiles
    stage_data = []
    for j in stages:
        st = {"j": j, "time_s": times[j], "profiles": {}}
        for k in runs:
            p, act, w, rw = state(runs[k], j)
            rr, rv = rotor_profile(k, rw)
            st["profiles"][k] = {
                "pressure_mean_radius_MPa": (p[prof["mean"]] / 1e6).tolist(),
                "pressure_centre_MPa": (p[prof["centre"]] / 1e6).tolist(),
                "pad_wear_mean_radius_um": (w[prof["mean"]] * 1e6).tolist(),
                "pad_wear_centre_um": (w[prof["centre"]] * 1e6).tolist(),
                "rotor_ring_radius_m": rr.tolist(), "rotor_wear_um": (rv * 1e6).tolist()}
            st[k] = per_time[k][j]
        stage_data.append(st)

    result = {
        "settings": {"size_m": g.mesh.size if size is None else size, "dofs": int(model.dofs),
                     "pad_friction_nodes": int(A.size), "line_pressure_Pa": line_pressure,
                     "clamp_force_N": F, "omega_rad_s": omega, "mu": mu, "k_pad": k_pad,
                     "k_rotor": k_rotor, "scheme": "implicit", "steps": steps,
                     "dt_s": duration / steps, "duration_s": duration,
                     "records_per_run": steps + 1, "stages_j": stages,
                     "stage_times_s": [times[j] for j in stages],
                     "mean_radius_profile_m": prof["mean_radius_m"],
                     "centre_line_max_angle_off_deg": prof["centre_dtheta_deg_max"],
                     "build_s": build_s, "fe_static_solve_s": static_s,
                     "cop_at_p_r_const": c_inv,
                     "load_point_r_mm": float(np.hypot(*base.load_point) * 1e3)},
        "calibration": calib,
        "per_time": per_time, "stages": stage_data, "speed": speed,
        "profile_axes": {"theta_deg": prof["theta_deg"].tolist(),
                         "centre_radius_m": prof["centre_radius_m"].tolist(),
                         "fe_rotor_ring_radius_m": rf.tolist()},
    }
    if out is not None:
        _write(Path(out), result, runs, figures, g)
    result["records"] = runs
    return result


# ------------------------------------------------------------------ output --

def _jsonable(o):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if hasattr(o, "item"):
        return o.item()
    return str(o)


def _write(out: Path, res: dict, runs: dict, figures: bool, g) -> None:
    d = out / "data"
    d.mkdir(parents=True, exist_ok=True)
    with open(d / "winkler_running_in.json", "w") as fh:
        json.dump(res, fh, indent=1, default=_jsonable)
    # every record's fields (to redo stages or plots without rerunning)
    arrays = {}
    for k, recs in runs.items():
        for name in ("pressure", "pad_wear", "rotor_wear"):
            arrays[f"{k}_{name}"] = np.array([getattr(s, name) for s in recs], dtype=np.float32)
        arrays[f"{k}_active"] = np.array([s.active for s in recs])
    np.savez_compressed(d / "winkler_running_in_fields.npz", **arrays)
    # per time and model
    rows = []
    sp = res["speed"]
    for k, lst in res["per_time"].items():
        for row in lst:
            j = row["j"]
            solve = sp["fe_solve_s"][j] if k == "fe" else sp[k]["solve_s"][j]
            rows.append({"model": k, **row, "solve_s_step_from_here": solve})
    keys = []
    for row in rows:
        keys += [c for c in row if c not in keys]
    with open(d / "winkler_running_in_steps.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    # stage profiles (long format)
    with open(d / "winkler_running_in_profiles.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time_s", "model", "profile", "coordinate", "value"])
        ax = res["profile_axes"]
        for st in res["stages"]:
            for k, pr in st["profiles"].items():
                for name, xs in (("pressure_mean_radius_MPa", ax["theta_deg"]),
                                 ("pad_wear_mean_radius_um", ax["theta_deg"]),
                                 ("pressure_centre_MPa", ax["centre_radius_m"]),
                                 ("pad_wear_centre_um", ax["centre_radius_m"]),
                                 ("rotor_wear_um", pr["rotor_ring_radius_m"])):
                    for x, v in zip(xs, pr[name]):
                        w.writerow([f"{st['time_s']:.6g}", k, name, f"{x:.6g}", f"{v:.6g}"])
    if figures:
        f = out / "figures"
        f.mkdir(parents=True, exist_ok=True)
        _figure_profiles(f / "winkler_running_in_pressure.png", res, "pressure", g)
        _figure_profiles(f / "winkler_running_in_wear.png", res, "wear", g)
        _figure_history(f / "winkler_running_in_history.png", res)


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _figure_profiles(path, res, what, g):
    plt = _plt()
    stages = res["stages"]
    ax_ = res["profile_axes"]
    nrow = 2 if what == "pressure" else 3
    fig, axs = plt.subplots(nrow, len(stages), figsize=(3.6 * len(stages), 3.0 * nrow + 0.6),
                            squeeze=False, sharey="row")
    lead = np.degrees(g.pad.center_angle + 0.5 * g.pad.arc_angle)
    for c, st in enumerate(stages):
        for k, pr in st["profiles"].items():
            sty = STYLES[k]
            if what == "pressure":
                axs[0, c].plot(ax_["theta_deg"], pr["pressure_mean_radius_MPa"], label=LABELS[k],
                               **sty)
                axs[1, c].plot(np.array(ax_["centre_radius_m"]) * 1e3, pr["pressure_centre_MPa"],
                               **sty)
            else:
                axs[0, c].plot(ax_["theta_deg"], pr["pad_wear_mean_radius_um"], label=LABELS[k],
                               **sty)
                axs[1, c].plot(np.array(ax_["centre_radius_m"]) * 1e3, pr["pad_wear_centre_um"],
                               **sty)
                axs[2, c].plot(np.array(pr["rotor_ring_radius_m"]) * 1e3, pr["rotor_wear_um"],
                               **{**sty, "marker": None if k == "fe" else sty["marker"]})
        t = st["time_s"]
        axs[0, c].set_title(f"t = {t:.0f} s" + (" (new pad)" if t == 0 else ""))
        axs[0, c].axvline(lead, color="0.7", lw=0.8)
        axs[0, c].set_xlabel("angle (deg), leading edge at grey line")
        axs[1, c].set_xlabel("radius (mm), pad centre line")
        if nrow == 3:
            axs[2, c].set_xlabel("radius (mm)")
            axs[2, c].set_xlim(0.98 * g.pad.inner_radius * 1e3, 1.02 * g.pad.outer_radius * 1e3)
    r_m = res["settings"]["mean_radius_profile_m"] * 1e3
    if what == "pressure":
        axs[0, 0].set_ylabel(f"pad pressure (MPa)\nat r = {r_m:.1f} mm")
        axs[1, 0].set_ylabel("pad pressure (MPa)\non the centre line")
        title = "Pad pressure during running-in: FE contact against Winkler interfaces"
    else:
        axs[0, 0].set_ylabel(f"pad wear (um)\nat r = {r_m:.1f} mm")
        axs[1, 0].set_ylabel("pad wear (um)\non the centre line")
        axs[2, 0].set_ylabel("rotor wear (um)\nring mean")
        title = "Pad and rotor wear during running-in: FE contact against Winkler interfaces"
    s = res["settings"]
    fig.suptitle(f"{title}\n{s['line_pressure_Pa'] / 1e6:g} MPa, {s['omega_rad_s']:g} rad/s, "
                 f"mu {s['mu']:g}, implicit, dt {s['dt_s']:g} s, mesh {s['size_m'] * 1e3:g} mm",
                 fontsize=10)
    h, lab = axs[0, 0].get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _figure_history(path, res):
    plt = _plt()
    fig, axs = plt.subplots(2, 4, figsize=(18, 7.5))
    pt = res["per_time"]
    for k, rows in pt.items():
        t = [r_["time_s"] for r_ in rows]
        sty = {**STYLES[k], "label": LABELS[k]}
        axs[0, 0].plot(t, [r_["pr_cv"] for r_ in rows], **sty)
        axs[0, 1].plot(t, [r_["pressure_max_MPa"] for r_ in rows], **sty)
        axs[0, 2].plot(t, [r_["contact_fraction"] for r_ in rows], **sty)
        axs[0, 3].plot(t, [r_["cop_r_mm"] for r_ in rows], **sty)
        if k != "fe":
            axs[1, 0].plot(t, [r_["pressure_l2_rel"] for r_ in rows], **sty)
            axs[1, 1].plot(t[1:], [r_["pad_wear_l2_rel"] for r_ in rows][1:], **sty)
    axs[0, 0].set_ylabel("p r spread: CV over the contact")
    axs[0, 1].set_ylabel("peak pad pressure (MPa)")
    axs[0, 2].set_ylabel("contact area fraction")
    axs[0, 3].set_ylabel("radius of the centre of pressure (mm)")
    c_inv = res["settings"]["cop_at_p_r_const"]["cop_r_mm"]
    axs[0, 3].axhline(c_inv, color="0.5", lw=0.8, ls="--")
    axs[0, 3].text(0.02, c_inv, "p r = const", color="0.4", fontsize=8, va="bottom",
                   transform=axs[0, 3].get_yaxis_transform())
    axs[1, 0].set_ylabel("pressure error, L2 relative to FE")
    axs[1, 1].set_ylabel("pad wear error, L2 relative to FE")
    sp = res["speed"]
    n = len(sp["fe_solve_s"])
    axs[1, 3].semilogy(range(1, n + 1), sp["fe_solve_s"], **{**STYLES["fe"], "label": LABELS["fe"]})
    for k in pt:
        if k != "fe":
            axs[1, 3].semilogy(range(1, n + 1), sp[k]["solve_s"],
                               **{**STYLES[k], "label": f"{LABELS[k]}: FE/Winkler "
                                  f"{sp[k]['median_of_ratios']:.0f}x"})
            if "retimed_solve_s" in sp[k]:
                axs[1, 3].semilogy(range(1, n + 1), sp[k]["retimed_solve_s"],
                                   color=STYLES[k]["color"], lw=0.8, alpha=0.5)
    axs[1, 3].set_xlabel("step")
    axs[1, 3].set_ylabel("interface solve time per step (s)")
    axs[1, 3].legend(fontsize=7)
    for k in pt:
        if k != "fe":
            rows = pt[k]
            axs[1, 2].plot([r_["time_s"] for r_ in rows][1:],
                           [r_["rotor_wear_l2_rel"] for r_ in rows][1:], **STYLES[k])
    axs[1, 2].set_ylabel("rotor wear (ring means) error, L2 rel. to FE")
    for a in list(axs.flat[:7]):
        a.set_xlabel("time (s)")
    h, lab = axs[0, 0].get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.suptitle("Running-in: FE contact against Winkler interfaces (history and cost per step)",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.05, 1, 0.97))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def replot(out: str | Path = "docs") -> None:
    """Redraw the figures from the JSON a run wrote (no solve)."""
    from brakewear.geometry import load_geometry
    out = Path(out)
    res = json.loads((out / "data" / "winkler_running_in.json").read_text())
    g = load_geometry("default")
    f = out / "figures"
    _figure_profiles(f / "winkler_running_in_pressure.png", res, "pressure", g)
    _figure_profiles(f / "winkler_running_in_wear.png", res, "wear", g)
    _figure_history(f / "winkler_running_in_history.png", res)


def _cli(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", type=float, default=None, help="mesh size in mm (default 2.5)")
    ap.add_argument("--duration", type=float, default=1500.0, help="time of the last stage (s)")
    ap.add_argument("--steps", type=int, default=15, help="equal steps to the last stage")
    ap.add_argument("--out", default="docs", help="root of data/ and figures/")
    ap.add_argument("--retime", type=int, default=3,
                    help="repeats of the Winkler runs, timed again (0: none)")
    ap.add_argument("--replot", action="store_true",
                    help="only redraw the figures from OUT/data/winkler_running_in.json")
    a = ap.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s %(message)s")
    if a.replot:
        replot(a.out)
        return
    res = main(size=None if a.size is None else a.size * 1e-3, duration=a.duration,
               steps=a.steps, out=a.out, retime=a.retime)
    for k in VARIANTS:
        if k in res["speed"]:
            logger.info("%s: FE/Winkler per step %.0fx (median of ratios)", k,
                        res["speed"][k]["median_of_ratios"])


if __name__ == "__main__":
    _cli()
