"""Running-in with the Winkler interface against the FE contact: profiles, errors, speed.

The default brake (elastic rotor) at 1 MPa, 55 rad/s, mu 0.4, Archard pad k
5e-15 1/Pa and rotor 5e-16 1/Pa, run in with implicit equal steps once with the
FE contact and once with each Winkler interface: ``johnson`` (Johnson's layer
modulus, the rotor layer in series, uncalibrated), ``stiffness`` (a uniform
modulus scaled to the FE stiffness), ``pressure`` (a modulus per node fitted to
the FE pressure).  At several stages it compares the pad pressure and wear (along
the mean radius and the centre line), the rotor's ring-mean wear, the ``p r``
spread and the interface solve time per step.  Run ``python
studies/winkler_running_in.py [--size MM] [--duration S] [--steps N] [--out DIR]``:
``OUT/data/winkler_running_in*.{json,csv}``, ``OUT/figures/winkler_running_in_*.png``.

The pressure of a :class:`~brakewear.wear.WearStep` is the one at the
start of its step and its wear the one at the end, so the runs take one step
more than ``steps`` (``duration`` is the time of the last stage): the state
at time ``t_j = j duration / steps`` is the pressure of record ``j`` and the
wear of record ``j - 1``.
"""
from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

import numpy as np

from brakewear import Numerics
from brakewear.interfaces import (
    FEInterface,
    FoundationInterface,
    WinklerInterface,
    calibrate,
    compare,
)
from brakewear.laws.base import WearLaw
from brakewear.mesh.convergence import pad_profiles, relative_l2
from brakewear.mesh.rings import ring_profile
from brakewear.model import BrakeModel
from brakewear.static import solve_contact
from brakewear.wear import Run, wear_history
from brakewear.wear.records import pr_spread

sys.path.insert(0, str(Path(__file__).resolve().parent))
from running_in_report import replot, speed_record, write  # noqa: E402  (a sibling script)

logger = logging.getLogger(__name__)

VARIANTS = ("johnson", "stiffness", "pressure")
#: the differences of a state without wear yet
NONE = {"max_abs": 0.0, "max_rel": float("nan"), "l2_rel": float("nan")}


def field_errors(a: np.ndarray, ref: np.ndarray, area: np.ndarray) -> dict:
    """Max and area-weighted L2 difference of ``a`` against ``ref`` (absolute and
    relative to max |ref| / the L2 norm of ref)."""
    d, mref = float(np.abs(a - ref).max()), float(np.abs(ref).max())
    return {"max_abs": d, "max_rel": d / mref if mref > 0 else float("nan"),
            "l2_rel": relative_l2(a, ref, area)}


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
    num = Numerics(steps=steps + 1, scheme="implicit")
    for s in wear_history(Run(model, lp, omega, duration * (steps + 1) / steps, pad_law,
                              rotor_law, mu, **kw, numerics=num)):
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
    itfs["fe"] = FEInterface(model, line_pressure, mu)
    runs["fe"], walls["fe"] = run(model, itfs["fe"], line_pressure, omega, duration, steps,
                                  pad_law, rotor_law, mu)
    for k, wi in winkler.items():
        itfs[k] = FoundationInterface(model, wi, line_pressure, mu)
        runs[k], walls[k] = run(model, itfs[k], line_pressure, omega, duration, steps, pad_law,
                                rotor_law, mu)

    A = itfs["fe"].area
    r = itfs["fe"].r
    prof = pad_profiles(itfs["fe"].x[:2], g)
    F = line_pressure * g.piston.hydraulic_area
    times = [duration * j / steps for j in range(steps + 1)]
    stages = stage_indices(steps, n_stages)

    # rotor wear against radius: FE rings (rotor face nodes) and Winkler rings (pad radii)
    rf = ring_profile(itfs["fe"])[0]
    in_pad = (rf >= g.pad.inner_radius - 1e-9) & (rf <= g.pad.outer_radius + 1e-9)

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
        rr_fe, rv_fe = ring_profile(itfs["fe"], rwf)
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
                ew = field_errors(w, wf, A) if j > 0 else NONE
                rr, rv = ring_profile(itfs[k], rw)
                rv_i = np.interp(rr_fe[in_pad], rr, rv)
                er = field_errors(rv_i, rv_fe[in_pad], np.ones(int(in_pad.sum()))) if j > 0 \
                    else NONE
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

    speed = speed_record([s.solve_s for s in runs["fe"]], walls,
                         {k: [s.solve_s for s in runs[k]] for k in winkler})
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
            rr, rv = ring_profile(itfs[k], rw)
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
        write(Path(out), result, runs, figures, g)
    result["records"] = runs
    return result


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
