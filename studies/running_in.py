"""Running-in of the default brake under steady drag (docs/wear.md, "Running-in").

The situation of the thesis' Paper D: constant line pressure 1 MPa, rotor
speed 55 rad/s (about 60 km/h on a 0.3 m tyre), mu = 0.4, both surfaces
wearing by Archard's law with their materials' coefficients (resin pad
5e-15 1/Pa, grey iron rotor 5e-16 1/Pa; docs/references.md: orders 1e-15..1e-14
and 1e-16..1e-15).  Elastic rotor, realistic steel backplate, implicit
scheme, automatic step control (``dp_tol`` 0.1), gap-offset update.  From first contact (a
flat pad on a flat rotor) the pressure moves from the stiff regions to a
running-in state; the p r spread over the contact says how far it is from
the uniform-wear law of a rigid backing (p r = const).

Run ``python studies/running_in.py [--out DIR] [--size MM] [--duration S] [--dp-tol X]``;
writes ``running_in.json`` and ``running_in.csv`` (one row per step) into
``DIR/data`` and ``running_in_pressure.png``, ``running_in_pad_wear.png``,
``running_in_rotor_wear.png`` (pyvista, one panel per stage) and
``running_in_evolution.png`` (matplotlib) into ``DIR/figures``.
"""
from __future__ import annotations

import argparse
import csv
import json
import logging
import tempfile
import time
from pathlib import Path

import numpy as np

from brakewear import Numerics
from brakewear.analytic import uniform_wear_torque
from brakewear.interfaces import FEInterface
from brakewear.laws.base import WearLaw
from brakewear.materials import MATERIALS
from brakewear.model import BrakeModel
from brakewear.output.runs import step_figures
from brakewear.wear import Run, wear_history

logger = logging.getLogger(__name__)

P_LINE, OMEGA, MU = 1e6, 55.0, 0.4
K_PAD = MATERIALS["pad_resin"].wear_k          # 5e-15 1/Pa
K_ROTOR = MATERIALS["grey_cast_iron"].wear_k   # 5e-16 1/Pa
TITLES = {"pressure": "pad contact pressure (friction face seen from the rotor)",
          "pad_wear": "pad wear (colour range per stage)",
          "rotor_wear": "rotor wear (ring-averaged)"}


def stage_state(itf, p, act, pad_w, rot_w, t, s) -> dict:
    A, r = itf.area, itf.r
    pr = (p * r)[act]
    F = float((p * A).sum())
    g = itf.model.geometry.pad
    return {"time_s": float(t), "sliding_distance_m": float(s),
            "pressure": p.copy(), "active": act.copy(), "pad_wear": pad_w.copy(),
            "rotor_wear": rot_w.copy(),
            "pr_spread": float((pr.max() - pr.min()) / pr.mean()),
            "contact_fraction": float(A[act].sum() / A.sum()),
            "torque_ratio": float(MU * (p * A * r).sum()
                                  / uniform_wear_torque(F, MU, g.inner_radius, g.outer_radius))}


def main(size_mm: float = 4.0, duration: float = 14400.0, out: str | Path = "docs",
         stages=(0.0, 0.03, 0.15, 1.0), figures: bool = True, dp_tol: float = 0.1) -> dict:
    """Run the running-in; returns the numbers (also written to ``out``).

    ``stages``: fractions of ``duration`` at which the fields are kept (the
    first accepted step at or after each; 0 is first contact, 1 the end).
    """
    out = Path(out)
    t0 = time.perf_counter()
    model = BrakeModel("default", size=size_mm * 1e-3, rotor="elastic")
    itf = FEInterface(model, P_LINE, MU)
    r_mean = 0.5 * (model.geometry.pad.inner_radius + model.geometry.pad.outer_radius)
    setup_s = time.perf_counter() - t0
    rows, kept = [], []
    targets = sorted(stages)
    prev = (np.zeros(itf.area.size), np.zeros(itf.rotor_area.size), 0.0)
    last = None
    for last in wear_history(
        Run(
            model,
            P_LINE,
            OMEGA,
            duration,
            WearLaw(K_PAD),
            WearLaw(K_ROTOR),
            MU,
            interface=itf,
            numerics=Numerics(scheme="implicit", dp_tol=dp_tol),
        )
    ):
        row = step_figures(last, itf, MU)
        # the record's pressure is the one at the start of its step
        row["start_time_s"] = prev[2]
        row["start_sliding_distance_m"] = OMEGA * r_mean * prev[2]
        row["torque_ratio"] = stage_state(itf, last.pressure, last.active, prev[0], prev[1],
                                          prev[2], 0.0)["torque_ratio"]
        rows.append(row)
        while targets and targets[0] < 1.0 and prev[2] >= targets[0] * duration * (1 - 1e-9):
            kept.append(stage_state(itf, last.pressure, last.active, prev[0], prev[1],
                                    prev[2], OMEGA * r_mean * prev[2]))
            targets.pop(0)
        prev = (last.pad_wear, last.rotor_wear, last.time)
        logger.info("step %d t = %.4g s (%s): p r spread %.4f, contact %.3f", last.step,
                    last.time, last.limit, row["pr_spread"], row["contact_fraction"])
    loop_s = time.perf_counter() - t0 - setup_s
    # the end state: the contact of the worn surfaces
    sol = itf.solve(last.pad_wear + itf.W @ last.rotor_wear, last.active)
    p, act = sol.pressure, sol.active
    kept.append(stage_state(itf, p, act, last.pad_wear, last.rotor_wear, last.time,
                            OMEGA * r_mean * last.time))
    total_s = time.perf_counter() - t0
    A = itf.area
    res = {"settings": {"size_mm": size_mm, "dofs": int(model.dofs), "rotor": "elastic",
                        "line_pressure_Pa": P_LINE, "omega_rad_s": OMEGA, "mu": MU,
                        "k_pad": K_PAD, "k_rotor": K_ROTOR, "scheme": "implicit",
                        "dp_tol": dp_tol, "duration_s": duration,
                        "clamp_force_N": float((kept[-1]["pressure"] * A).sum())},
           "steps": last.step, "contact_solves": int(sum(r["contact_solves"] for r in rows)) + 2,
           "rejected": int(sum(r["rejected"] for r in rows)),
           "pad_volume_m3": last.pad_volume, "pad_archard_m3": last.pad_archard,
           "rotor_volume_m3": last.rotor_volume, "rotor_archard_m3": last.rotor_archard,
           "pad_wear_max_m": float(last.pad_wear.max()),
           "pad_wear_mean_m": float((last.pad_wear * A).sum() / A.sum()),
           "rotor_wear_max_m": float(last.rotor_wear.max()),
           "setup_s": setup_s, "loop_s": loop_s, "run_s": total_s,
           "stages": [{k: v for k, v in st.items()
                       if k not in ("pressure", "active", "pad_wear", "rotor_wear")}
                      for st in kept]}
    line = _centre_line(itf)
    res["centre_line"] = {"r_m": itf.r[line].tolist(),
                          "pressure_Pa": [st["pressure"][line].tolist() for st in kept],
                          "pad_wear_m": [st["pad_wear"][line].tolist() for st in kept]}
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / "running_in.json").write_text(json.dumps(res, indent=2))
    with open(out / "data" / "running_in.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    if figures:
        evolution_figure(itf, rows, kept, out / "figures" / "running_in_evolution.png")
        field_figures(model, itf, kept, out / "figures")
    return res


def _centre_line(itf) -> np.ndarray:
    th = np.degrees(np.arctan2(itf.x[1], itf.x[0]))
    # one column of nodes: the angle closest to the centre line, with its sign
    line = np.nonzero(np.isclose(th, th[np.argmin(np.abs(th))], atol=0.05))[0]
    return line[np.argsort(itf.r[line])]


def evolution_figure(itf, rows: list[dict], kept: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    line = _centre_line(itf)
    r = itf.r[line] * 1e3
    for i, st in enumerate(kept):
        a.plot(r, st["pressure"][line] / 1e6, "o-", ms=3, color=f"C{i}",
               label=f"{st['sliding_distance_m'] / 1e3:.3g} km ({st['time_s']:.0f} s)")
    st = kept[-1]
    g = itf.model.geometry.pad
    from brakewear.analytic import uniform_wear_pressure
    F = float((st["pressure"] * itf.area).sum())
    a.plot(r, uniform_wear_pressure(itf.r[line], F, g.arc_angle, g.inner_radius,
                                    g.outer_radius) / 1e6, "k--",
           label="p r = const (rigid backing)")
    a.set_xlabel("r (mm), pad centre line")
    a.set_ylabel("contact pressure (MPa)")
    a.set_title("Pressure along the pad's centre line")
    a.legend(fontsize=8)
    a.grid(alpha=0.3)
    s = np.array([row["start_sliding_distance_m"] for row in rows]) / 1e3
    b.plot(s, [row["pr_spread"] for row in rows], "-", label="p r spread (max-min)/mean")
    b.plot(s, [row["contact_fraction"] for row in rows], "-", label="contact fraction")
    b.plot(s, [row["torque_ratio"] for row in rows], "-",
           label="torque / (mu F (ri+ro)/2)")
    b.set_xscale("symlog", linthresh=1.0)
    b.set_xlim(left=0)
    b.set_xlabel("sliding distance at the mean radius (km; log above 1 km)")
    b.set_title("Running-in")
    b.set_ylim(bottom=0)
    b.legend(fontsize=8)
    b.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def field_figures(model, itf, kept: list[dict], outdir: Path) -> list[Path]:
    """Pyvista pictures of pad pressure, pad and rotor wear, one panel per stage."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from brakewear.output.figures import plot_field

    pad, rotor = model.meshes["pad"], model.meshes["rotor"]
    fields = {
        "pressure": ("p (MPa)", pad, itf.pad_nodes, "pressure", 1e-6, (0, -0.3, -1)),
        "pad_wear": ("h pad (um)", pad, itf.pad_nodes, "pad_wear", 1e6, (0, -0.3, -1)),
        "rotor_wear": ("h rotor (um)", rotor, itf.rotor_nodes, "rotor_wear", 1e6,
                       (0, -0.3, 1)),
    }
    paths = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, (label, mesh, nodes, key, scale, view) in fields.items():
            hi = max(float(st[key].max()) * scale for st in kept)
            pngs = []
            for i, st in enumerate(kept):
                if name != "pressure" and st["time_s"] == 0.0:
                    continue      # nothing worn yet
                vals = np.zeros(mesh.nvertices)
                vals[nodes] = st[key] * scale
                title = (f"{st['sliding_distance_m'] / 1e3:.3g} km, t = {st['time_s']:.0f} s")
                clim = (0.0, hi if name != "pad_wear" else float(vals.max()))
                pngs.append(plot_field(mesh, vals, Path(tmp) / f"{name}_{i}.png", title,
                                       label=label, clim=clim, facets="friction", view=view,
                                       window_size=(900, 700)))
            fig, axes = plt.subplots(1, len(pngs), figsize=(4.2 * len(pngs), 3.6))
            for ax, png in zip(np.atleast_1d(axes), pngs):
                ax.imshow(plt.imread(png))
                ax.axis("off")
            fig.suptitle(f"Running-in, 1 MPa, 55 rad/s, mu 0.4: {TITLES[name]}")
            fig.tight_layout()
            path = outdir / f"running_in_{name}.png"
            fig.savefig(path, dpi=110)
            plt.close(fig)
            paths.append(path)
    return paths


def _cli(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--size", type=float, default=4.0, help="mesh size, mm (default 4)")
    ap.add_argument("--duration", type=float, default=14400.0, help="drag, s (default 14400)")
    ap.add_argument("--dp-tol", type=float, default=0.1, dest="dp_tol",
                    help="step control: largest pressure change per step (default 0.1)")
    ap.add_argument("--no-figures", action="store_true")
    a = ap.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    logging.getLogger("brakewear").setLevel(logging.WARNING)
    res = main(a.size, a.duration, a.out, figures=not a.no_figures, dp_tol=a.dp_tol)
    logging.info("%d steps, %d contact solves, %.0f s; final p r spread %.4f, torque ratio %.4f",
                 res["steps"], res["contact_solves"], res["run_s"],
                 res["stages"][-1]["pr_spread"], res["stages"][-1]["torque_ratio"])
    return 0


if __name__ == "__main__":
    raise SystemExit(_cli())
