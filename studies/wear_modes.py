"""Geometry update against gap offset (the numbers of docs/wear.md, "Modes").

The default brake (rigid rotor, ``--size`` mm) wears its pad under 1 MPa,
55 rad/s, mu = 0.4 with the implicit scheme, once with ``update="gap"``
(the worn depth offsets the contact gap, meshes stay) and once with
``update="geometry"`` (the worn face moves and the friction layer beneath is
compressed, :class:`brakewear.motion.brake.BrakeMotion`).  Each history is run in
segments that stop where the pad's mean worn depth is 1 %, 10 % and 50 % of
the friction layer's thickness (resumed from the loop's checkpoint, with a
freshly built model, as the loop requires); at each stop the two modes'
pressure (at the end of the last step: the checkpoint's state) and wear
profile are compared, and the worn pad mesh's smallest element quality
(:func:`brakewear.motion.brake.element_quality`) is reported.

The pad's k is 100 x a resin pad's (5e-13 1/Pa): only k times the sliding
distance sets the worn shape, so this is the same history in 1/100 of the
simulated time.

Run ``python studies/wear_modes.py [--out DIR] [--size MM]``; writes
``wear_modes.json`` into ``DIR/data`` and ``wear_modes.png`` into
``DIR/figures`` (default DIR: docs).
"""
from __future__ import annotations

import argparse
import json
import logging
import tempfile
import time
from pathlib import Path

import numpy as np

from brakewear import Numerics
from brakewear.interfaces import FEInterface
from brakewear.laws.base import WearLaw
from brakewear.model import BrakeModel
from brakewear.motion.brake import element_quality
from brakewear.wear import Run, wear_history

logger = logging.getLogger(__name__)

P_LINE, OMEGA, MU, K_PAD = 1e6, 55.0, 0.4, 5e-13
FRACTIONS = (0.01, 0.1, 0.5)


def history(update: str, size: float, fractions=FRACTIONS, dh_fraction: float = 0.25,
            dp_tol: float = 0.05, workdir: Path | None = None) -> list[dict]:
    """Run one mode to each mean-depth milestone; the state at every milestone."""
    tmp = tempfile.TemporaryDirectory() if workdir is None else None
    ck = Path(tmp.name if tmp else workdir) / f"modes_{update}.npz"
    if ck.exists():
        ck.unlink()
    law = WearLaw(K_PAD)
    model = BrakeModel("default", size=size, rotor="rigid")
    itf = FEInterface(model, P_LINE, MU)     # reference geometry: areas, radii
    A, r, v = itf.area, itf.r, OMEGA * itf.r
    tf = model.geometry.pad.friction_thickness
    sol = itf.solve(np.zeros(A.size), None)
    p = sol.pressure
    t, depth, out, steps, solves, run_s = 0.0, 0.0, [], 0, 0, 0.0
    for frac in fractions:
        target = frac * tf
        # the mean wear rate k omega sum(p r A) / sum(A) barely changes: aim with it
        for _ in range(6):
            mean_rate = float((law.rate(p, v) * A).sum() / A.sum())
            t_end = t + (target - depth) / mean_rate
            m = BrakeModel("default", size=size, rotor="rigid") if steps or update == "geometry" \
                else model
            t0 = time.perf_counter()
            last = None
            for last in wear_history(
                Run(
                    m,
                    P_LINE,
                    OMEGA,
                    t_end,
                    law,
                    None,
                    MU,
                    numerics=Numerics(
                        scheme="implicit", update=update, dh_fraction=dh_fraction, dp_tol=dp_tol
                    ),
                ),
                checkpoint=ck,
                every=10**6,
                resume=steps > 0,
            ):
                solves += last.contact_solves
            run_s += time.perf_counter() - t0
            steps = last.step
            with np.load(ck) as d:
                p, h = d["pressure"].copy(), d["pad_wear"].copy()
                act = d["active"].astype(bool)
            t = float(last.time)
            depth = float((h * A).sum() / A.sum())
            if depth >= (1 - 0.005) * target:
                break
        q = element_quality(m.meshes["pad"])
        pr = (p * r)[act]
        out.append({"fraction": frac, "target_depth_m": target, "mean_depth_m": depth,
                    "time_s": t, "sliding_distance_m": float(last.sliding_distance),
                    "steps": steps, "contact_solves": solves, "run_s": run_s,
                    "pad_min_quality": float(q.min()), "pad_inverted": int((q <= 0).sum()),
                    "pr_spread": float((pr.max() - pr.min()) / pr.mean()),
                    "contact_fraction": float(A[act].sum() / A.sum()),
                    "normal_force_N": float((p * A).sum()),
                    "pressure": p, "pad_wear": h, "r": r, "x": itf.x})
        logger.info("%s: mean depth %.4g mm (%.0f %%) at t = %.4g s, step %d, q_min %.3f",
                    update, depth * 1e3, 100 * depth / tf, t, steps, q.min())
    if tmp:
        tmp.cleanup()
    return out


def compare(gap: list[dict], geo: list[dict]) -> list[dict]:
    rows = []
    for a, b in zip(gap, geo):
        rows.append({
            "fraction": a["fraction"],
            "mean_depth_gap_m": a["mean_depth_m"], "mean_depth_geometry_m": b["mean_depth_m"],
            "pressure_diff": float(np.abs(b["pressure"] - a["pressure"]).max()
                                   / a["pressure"].max()),
            "wear_diff": float(np.abs(b["pad_wear"] - a["pad_wear"]).max()
                               / a["pad_wear"].max()),
            "max_pressure_gap_Pa": float(a["pressure"].max()),
            "max_pressure_geometry_Pa": float(b["pressure"].max()),
            "pr_spread_gap": a["pr_spread"], "pr_spread_geometry": b["pr_spread"],
            "contact_fraction_gap": a["contact_fraction"],
            "contact_fraction_geometry": b["contact_fraction"],
            "force_gap_N": a["normal_force_N"], "force_geometry_N": b["normal_force_N"],
            "pad_min_quality_geometry": b["pad_min_quality"],
            "pad_inverted_geometry": b["pad_inverted"],
            "steps_gap": a["steps"], "steps_geometry": b["steps"],
            "solves_gap": a["contact_solves"], "solves_geometry": b["contact_solves"],
            "run_s_gap": a["run_s"], "run_s_geometry": b["run_s"]})
    return rows


def main(size_mm: float = 10.0, out: str | Path = "docs", fractions=FRACTIONS,
         dh_fraction: float = 0.25, figures: bool = True) -> dict:
    """Run both modes to the milestones; returns (and writes) the comparison."""
    out = Path(out)
    t0 = time.perf_counter()
    size = size_mm * 1e-3
    gap = history("gap", size, fractions, dh_fraction)
    geo = history("geometry", size, fractions, dh_fraction)
    ref = BrakeModel("default", size=size, rotor="rigid")
    res = {"settings": {"size_mm": size_mm, "dofs": int(ref.dofs), "rotor": "rigid",
                        "line_pressure_Pa": P_LINE, "omega_rad_s": OMEGA, "mu": MU,
                        "k_pad": K_PAD, "scheme": "implicit", "dh_fraction": dh_fraction,
                        "friction_thickness_m": ref.geometry.pad.friction_thickness,
                        "pad_initial_min_quality": float(element_quality(ref.meshes["pad"]).min())},
           "rows": compare(gap, geo),
           "profiles": {m: [{k: np.asarray(s[k]).tolist() for k in ("pressure", "pad_wear")}
                            | {"fraction": s["fraction"]} for s in st]
                        for m, st in (("gap", gap), ("geometry", geo))},
           "r_m": gap[0]["r"].tolist(), "x_m": gap[0]["x"].tolist()}
    res["run_s"] = time.perf_counter() - t0
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / "wear_modes.json").write_text(json.dumps(res, indent=1))
    if figures:
        figure(res, out / "figures" / "wear_modes.png")
    return res


def figure(res: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    x = np.asarray(res["x_m"])
    r = np.asarray(res["r_m"])
    th = np.degrees(np.arctan2(x[1], x[0]))
    # the column of nodes closest to the centre line
    line = np.nonzero(np.isclose(np.abs(th), np.abs(th).min(), atol=0.5))[0]
    line = line[np.argsort(r[line])]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for i, frac in enumerate([row["fraction"] for row in res["rows"]]):
        for mode, ls in (("gap", "--"), ("geometry", "-")):
            prof = res["profiles"][mode][i]
            p = np.asarray(prof["pressure"])[line] / 1e6
            h = np.asarray(prof["pad_wear"])[line] * 1e3
            axes[0].plot(r[line] * 1e3, p, ls, color=f"C{i}",
                         label=f"{100 * frac:g} % layer, {mode}")
            axes[1].plot(r[line] * 1e3, h / h.mean() if h.mean() > 0 else h, ls,
                         color=f"C{i}", label=f"{100 * frac:g} % layer, {mode}")
    axes[0].set_xlabel("r (mm), pad centre line")
    axes[0].set_ylabel("contact pressure (MPa)")
    axes[0].set_title("Pressure: gap offset (--) vs geometry update (-)")
    axes[1].set_xlabel("r (mm), pad centre line")
    axes[1].set_ylabel("pad wear / its mean on the line")
    axes[1].set_title("Wear profile (normalised)")
    for a in axes:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _cli(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--size", type=float, default=10.0, help="mesh size, mm (default 10)")
    ap.add_argument("--dh-fraction", type=float, default=0.25, dest="dh_fraction")
    ap.add_argument("--no-figures", action="store_true")
    a = ap.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    res = main(a.size, a.out, dh_fraction=a.dh_fraction, figures=not a.no_figures)
    for row in res["rows"]:
        logging.info("%g %% layer: pressure diff %.3g, wear diff %.3g, q_min %.3f",
                     100 * row["fraction"], row["pressure_diff"], row["wear_diff"],
                     row["pad_min_quality_geometry"])
    return 0


if __name__ == "__main__":
    raise SystemExit(_cli())
