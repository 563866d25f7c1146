"""A compliant caliper bridge and tapered pad wear.

Under the clamp force a floating caliper's bridge spreads and the fingers'
jaw turns about a tangential axis, away from the outboard backplate at its
inner radius (``caliper.bridge_tilt``, mrad per kN of clamp force; the
finger pressure follows :func:`brakewear.caliper.loads.jaw_pressure`).  The
outboard pad's load moves toward the bridge, the classic cause of radially
tapered outboard wear.  For ``geometry/floating.toml`` with bridge tilts from
rigid to soft:

- static contact at one line pressure (with friction): coverage, centre of
  pressure radius and peak pressure of each face (the contact problem of
  conforming faces is linear, so these do not depend on the line pressure);
- a drag at that pressure long enough to run the pads in: each pad's radial
  wear profile (area-weighted mean wear in radial bands of the lining) and
  its taper, the mean wear of the outer quarter of the lining's radial width
  less that of the inner quarter, over the face's mean wear.

Run ``python studies/bridge_tilt.py [--out DIR] [--tilts 0 0.05 0.1 0.2 0.4]
[--size MM] [--hours H]``; writes ``DIR/data/bridge_tilt.json``, ``.csv`` and
``DIR/figures/bridge_tilt.png``.
"""
from __future__ import annotations

import argparse
import csv
import json
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from brakewear import Numerics, WearLaw
from brakewear.geometry import load_geometry
from brakewear.interfaces import FEInterface
from brakewear.mesh.surface import face_nodes
from brakewear.model import BrakeModel
from brakewear.static import solve_contact
from brakewear.wear import wear_history

sys.path.insert(0, str(Path(__file__).resolve().parent))
from brakewear.wear import Run
from load_path import MESH, face_numbers, meshed  # noqa: E402  (a sibling script)

TILTS = (0.0, 0.05, 0.1, 0.2, 0.4)        # mrad per kN of clamp force
LINE_PRESSURE = 1e6                        # Pa
MU = 0.4
OMEGA = 55.0                               # rad/s: the default scene's drag
BANDS = 8                                  # radial bands of the wear profile


def tilted(geom, mrad_per_kN: float):
    """``geom`` with ``caliper.bridge_tilt`` in mrad/kN."""
    return replace(geom, caliper=replace(geom.caliper, bridge_tilt=mrad_per_kN * 1e-6))


def wear_profile(model, itf, step) -> dict:
    """Per face: the area-weighted mean pad wear (m) in :data:`BANDS` radial bands
    of the lining and the taper (outer quarter less inner quarter over the mean)."""
    g = model.geometry
    pad = model.meshes["pad"]
    x = pad.p[:, itf.pad_nodes]
    r = np.hypot(x[0], x[1])
    out = np.isin(itf.pad_nodes, face_nodes(pad, "friction_out"))
    ri, ro = g.pad.inner_radius, g.pad.outer_radius
    edges = np.linspace(ri, ro, BANDS + 1)
    rows = {}
    for face, mask in (("in", ~out), ("out", out)):
        w, a, rr = step.pad_wear[mask], itf.area[mask], r[mask]
        band = np.clip(np.searchsorted(edges, rr, side="right") - 1, 0, BANDS - 1)
        mean_band = (np.bincount(band, w * a, BANDS) / np.bincount(band, a, BANDS))
        q = 0.25 * (ro - ri)
        inner, outer = rr <= ri + q, rr >= ro - q
        mean = (w * a).sum() / a.sum()
        rows[face] = {"band_mean_um": (1e6 * mean_band).tolist(), "mean_um": 1e6 * mean,
                      "taper": ((w * a)[outer].sum() / a[outer].sum()
                                - (w * a)[inner].sum() / a[inner].sum()) / mean}
    return {"band_edges_mm": (1e3 * edges).tolist(), "faces": rows}


def run_tilt(geom, tilt: float, hours: float, steps: int) -> dict:
    """Static contact and a drag of ``hours`` of the floating brake with ``tilt``."""
    t0 = time.perf_counter()
    g = tilted(geom, tilt)
    model = BrakeModel(g, layout="full")
    res = solve_contact(model, LINE_PRESSURE, mu=MU)
    row = {"tilt_mrad_per_kN": tilt, "dofs": int(model.dofs),
           "jaw_tilt_mrad": 1e3 * g.caliper.bridge_tilt * LINE_PRESSURE * g.clamp_area,
           "static": face_numbers(model, res, LINE_PRESSURE)}
    if hours > 0:
        pad_law = WearLaw(g.pad.friction_material.wear_k)
        rotor_law = WearLaw(g.rotor.material.wear_k)
        itf = FEInterface(model, LINE_PRESSURE, MU)
        for step in wear_history(  # noqa: B007  (the last step)
            Run(
                model,
                LINE_PRESSURE,
                OMEGA,
                3600.0 * hours,
                pad_law,
                rotor_law,
                MU,
                interface=itf,
                numerics=Numerics(scheme="implicit", update="gap", steps=steps),
            )
        ):
            pass
        row["worn"] = wear_profile(model, itf, step)
    row["wall_s"] = time.perf_counter() - t0
    return row


def main(tilts=TILTS, mesh: dict | None = None, hours: float = 1.0, steps: int = 10,
         out: Path | None = None, figures: bool = True) -> dict:
    """Every tilt; returns the numbers (and writes them under ``out``)."""
    geom = meshed(load_geometry("floating"), dict(MESH if mesh is None else mesh))
    rows = []
    for tilt in tilts:
        rows.append(run_tilt(geom, tilt, hours, steps))
        r = rows[-1]
        print(f"tilt {tilt:g} mrad/kN: {r['dofs']} DOFs, {r['wall_s']:.1f} s")
    result = {"line_pressure_MPa": LINE_PRESSURE / 1e6, "mu": MU, "omega_rad_s": OMEGA,
              "hours": hours, "steps": steps, "mesh_m": mesh or MESH, "rows": rows}
    if out is not None:
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "bridge_tilt.json").write_text(json.dumps(result, indent=1))
        write_csv(result, out / "data" / "bridge_tilt.csv")
        if figures:
            draw(result, out / "figures" / "bridge_tilt.png")
    print_table(result)
    return result


def write_csv(result: dict, path: Path) -> None:
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["tilt_mrad_per_kN", "face", "coverage", "cop_r_mm", "peak_over_nominal",
                    "wear_mean_um", "wear_taper"])
        for r in result["rows"]:
            for face, s in r["static"].items():
                worn = r.get("worn", {}).get("faces", {}).get(face, {})
                w.writerow([r["tilt_mrad_per_kN"], face, s["coverage"], s["cop_r_mm"],
                            s["peak_over_nominal"], worn.get("mean_um"), worn.get("taper")])


def draw(result: dict, path: Path) -> Path:
    """Left: coverage and centre of pressure against the tilt; right: the worn
    pads' radial wear profiles."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = result["rows"]
    t = [r["tilt_mrad_per_kN"] for r in rows]
    fig, ax = plt.subplots(1, 2, figsize=(11, 5.0))
    for face, ls in (("in", "--"), ("out", "-")):
        ax[0].plot(t, [100 * r["static"][face]["coverage"] for r in rows], "o" + ls,
                   color="C0", label=f"coverage, {face}board")
    ax[0].set_xlabel("bridge tilt (mrad per kN of clamp force)")
    ax[0].set_ylabel("contact coverage (%)", color="C0")
    twin = ax[0].twinx()
    for face, ls in (("in", "--"), ("out", "-")):
        twin.plot(t, [r["static"][face]["cop_r_mm"] for r in rows], "s" + ls, color="C3",
                  label=f"centre of pressure, {face}board")
    twin.set_ylabel("centre of pressure radius (mm)", color="C3")
    h0, l0 = ax[0].get_legend_handles_labels()
    h1, l1 = twin.get_legend_handles_labels()
    ax[0].legend(h0 + h1, l0 + l1, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2,
                 fontsize=8)
    ax[0].set_title(f"static contact, {result['line_pressure_MPa']:g} MPa, mu {result['mu']:g}")
    if all("worn" in r for r in rows):
        e = np.array(rows[0]["worn"]["band_edges_mm"])
        mid = 0.5 * (e[1:] + e[:-1])
        for i, r in enumerate(rows):
            for face, ls in (("in", "--"), ("out", "-")):
                ax[1].plot(mid, r["worn"]["faces"][face]["band_mean_um"], ls, color=f"C{i}",
                           label=f"{r['tilt_mrad_per_kN']:g} mrad/kN, {face}"
                           if face == "out" or i == 0 else None)
        ax[1].set_xlabel("radius (mm)")
        ax[1].set_ylabel("pad wear (um), band mean")
        ax[1].set_title(f"pads after a {result['hours']:g} h drag at "
                        f"{result['omega_rad_s']:g} rad/s\n(solid: outboard, dashed: inboard)",
                        fontsize=10)
        ax[1].legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def print_table(result: dict) -> None:
    print("| bridge tilt (mrad/kN) | jaw tilt (mrad) | face | coverage | CoP r (mm) | "
          "p max / p nom | mean wear (um) | taper |")
    print("|---|---|---|---|---|---|---|---|")
    for r in result["rows"]:
        for face, s in r["static"].items():
            worn = r.get("worn", {}).get("faces", {}).get(face)
            tail = (f"{worn['mean_um']:.1f} | {worn['taper']:+.3f}" if worn else "- | -")
            print(f"| {r['tilt_mrad_per_kN']:g} | {r['jaw_tilt_mrad']:.3f} | {face} | "
                  f"{100 * s['coverage']:.1f} % | {s['cop_r_mm']:.2f} | "
                  f"{s['peak_over_nominal']:.2f} | {tail} |")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("."))
    ap.add_argument("--tilts", type=float, nargs="+", default=list(TILTS))
    ap.add_argument("--size", type=float, default=None,
                    help="pad size in mm (the rotor twice, layers as studies/load_path.py)")
    ap.add_argument("--hours", type=float, default=1.0)
    ap.add_argument("--steps", type=int, default=10)
    a = ap.parse_args()
    mesh = None
    if a.size is not None:
        s = a.size * 1e-3
        mesh = {**MESH, "size": s, "pad_size": s, "rotor_size": 2 * s}
    main(a.tilts, mesh, a.hours, a.steps, a.out)
