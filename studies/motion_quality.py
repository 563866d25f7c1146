"""Moving worn faces: cost of the geometry update and mesh quality against wear
(the numbers of docs/motion.md).

Three measurements on the default brake (:class:`brakewear.motion.brake.BrakeMotion`):

* **cost** -- :meth:`BrakeMotion.apply` with partial reassembly (only the
  elements that moved are reintegrated) against full reassembly, at one or
  more mesh sizes.  The pad is worn into a taper 0.5 -> 1.5 mm from leading
  to trailing edge (every pad friction node moves), the rotor 0.1 mm over the
  pad's radial track; steps alternate partial / full, each slightly deeper,
  and medians are reported;
* **quality** -- the smallest pad element quality
  (:func:`brakewear.motion.brake.element_quality`) with the pad worn uniformly, and
  tapered from 0 at the leading edge, to a fraction of its friction layer;
* **figure** -- the pad's mesh in the (arc length, z) plane at mid radius,
  new and worn to a taper of half the friction layer.

Run ``python studies/motion_quality.py [--sizes 2.5 6] [--repeats 3] [--out DIR]``
(sizes in mm); writes ``motion_cost.json`` and ``motion_quality.csv`` into
``DIR/data`` and ``motion_pad_section.png`` into ``DIR/figures`` (default DIR:
docs).
"""
from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

import numpy as np

from brakewear.model import BrakeModel
from brakewear.motion.brake import BrakeMotion, element_quality

FRACTIONS = (0.0, 0.25, 0.5, 0.75, 0.9, 0.95)


def _pad_angles(motion: BrakeMotion) -> np.ndarray:
    """Angle of every pad friction node, scaled to 0 (leading) .. 1 (trailing)."""
    x = motion.model.meshes["pad"].p[:, motion.followers["pad"].nodes]
    th = np.arctan2(x[1], x[0])
    return (th - th.min()) / np.ptp(th)


def measure_cost(size: float | None = None, repeats: int = 3) -> dict:
    """Median time of :meth:`BrakeMotion.apply`, partial against full reassembly.

    ``size`` is the mesh size in m (None: the geometry file's).  Both
    stiffness matrices are assembled before the first step, so the steps
    time the update alone.
    """
    model = BrakeModel(size=size)
    t0 = time.perf_counter()
    for b in model.bodies:
        model.stiffness(b)
    t_first = time.perf_counter() - t0
    motion = BrakeMotion(model)
    g = model.geometry.pad
    hp = 1e-3 * (0.5 + _pad_angles(motion))
    xr = model.meshes["rotor"].p[:, motion.followers["rotor"].nodes]
    s = (np.hypot(xr[0], xr[1]) - g.inner_radius) / (g.outer_radius - g.inner_radius)
    hr = np.where((s >= 0) & (s <= 1), 1e-4, 0.0)
    runs: dict = {"partial": [], "full": []}
    st: dict = {}
    for k in range(2 * repeats):
        mode = ("partial", "full")[k % 2]
        st = motion.apply(hp * (1 + 0.01 * k), hr * (1 + 0.01 * k), step=k + 1, reassembly=mode)
        runs[mode].append((st["reassembly_s"], st["total_s"]))
    row = {"size_m": model.geometry.mesh.size if size is None else float(size),
           "first_assembly_s": t_first, "dofs": int(model.dofs)}
    for b in motion.followers:
        row[f"{b}_moved_elements"] = st[b]["moved_elements"]
        row[f"{b}_elements"] = st[b]["elements"]
        row[f"{b}_band_depth_m"] = motion.followers[b].depth
    for mode, v in runs.items():
        a = np.median(np.array(v), axis=0)
        row[f"{mode}_reassembly_s"], row[f"{mode}_apply_s"] = float(a[0]), float(a[1])
    row["partial_over_full"] = row["partial_apply_s"] / row["full_apply_s"]
    return row


def quality_curve(fractions=FRACTIONS, size: float | None = None, taper: bool = False) -> list:
    """Smallest pad element quality worn to each fraction of the friction layer.

    Uniform wear, or with ``taper`` a wear growing linearly from 0 at the
    leading to the fraction at the trailing edge.  The quality guard is set
    near zero so that the curve is measured, not cut off.
    """
    model = BrakeModel(size=size)
    motion = BrakeMotion(model, min_quality=1e-9)
    tf = model.geometry.pad.friction_thickness
    shape = _pad_angles(motion) if taper else np.ones(motion.followers["pad"].nodes.size)
    out = []
    for f in fractions:
        st = motion.apply(f * tf * shape)
        q = element_quality(motion.model.meshes["pad"])
        out.append({"fraction": float(f), "taper": bool(taper), "min_quality": float(q.min()),
                    "moved_elements": st["pad"]["moved_elements"]})
    return out


def pad_section_figure(path, fraction: float = 0.5, size: float | None = None) -> dict:
    """Draw the pad mesh at mid radius in the (arc length, z) plane, new and worn."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = BrakeModel(size=size)
    motion = BrakeMotion(model)
    g = model.geometry.pad
    motion.apply(fraction * g.friction_thickness * _pad_angles(motion))
    p0, p1 = motion.reference["pad"], motion.model.meshes["pad"].p
    r = np.hypot(p0[0], p0[1])
    radii = np.unique(np.round(r, 9))
    rk = radii[len(radii) // 2]
    sel = np.nonzero(np.abs(r - rk) < 1e-9)[0]
    ang = np.arctan2(p0[1, sel], p0[0, sel])
    ua, uz = np.unique(np.round(ang, 9)), np.unique(np.round(p0[2, sel], 9))
    ia = np.searchsorted(ua, np.round(ang, 9))
    iz = np.searchsorted(uz, np.round(p0[2, sel], 9))
    fig, axes = plt.subplots(2, 1, figsize=(9, 4.8), sharex=True)
    for ax, p, title in (
        (axes[0], p0, "new"),
        (axes[1], p1, f"worn: 0 -> {fraction:g} x friction layer, leading -> trailing"),
    ):
        S = np.full((ua.size, uz.size), np.nan)
        Z = np.full((ua.size, uz.size), np.nan)
        S[ia, iz], Z[ia, iz] = rk * ang * 1e3, p[2, sel] * 1e3
        ax.plot(S, Z, color="0.3", lw=0.6)
        ax.plot(S.T, Z.T, color="0.3", lw=0.6)
        ax.axhline(g.friction_thickness * 1e3, color="tab:red", lw=1.0, ls="--",
                   label="band bottom = backplate interface")
        ax.set_title(f"pad at r = {rk * 1e3:.1f} mm, {title}", fontsize=9)
        ax.set_ylabel("z (mm)")
        ax.set_aspect("equal")
    axes[0].legend(loc="upper right", fontsize=7)
    axes[1].set_xlabel("arc length r theta (mm), rotor enters at the left")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    q = element_quality(motion.model.meshes["pad"])
    return {"radius_m": float(rk), "fraction": fraction, "min_quality": float(q.min())}


def main(sizes=(2.5e-3, 6e-3), repeats: int = 3, out=None, quality_size: float | None = None,
         fractions=FRACTIONS) -> dict:
    """Run the three measurements; write their files under ``out`` (if given).

    ``sizes`` (m) are the cost rows' mesh sizes; ``quality_size`` the mesh
    of the quality curves and the figure (None: the geometry file's).
    """
    cost = [measure_cost(s, repeats) for s in sizes]
    quality = (quality_curve(fractions, quality_size)
               + quality_curve(fractions, quality_size, taper=True))
    res = {"cost": cost, "quality": quality, "figure": None}
    if out is not None:
        out = Path(out)
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "figures").mkdir(parents=True, exist_ok=True)
        (out / "data" / "motion_cost.json").write_text(json.dumps(cost, indent=1))
        with open(out / "data" / "motion_quality.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(quality[0]))
            w.writeheader()
            w.writerows({**r, "taper": int(r["taper"])} for r in quality)
        res["figure"] = pad_section_figure(out / "figures" / "motion_pad_section.png",
                                           size=quality_size)
    return res


def _cli(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=float, nargs="+", default=[2.5, 6.0], help="mesh sizes (mm)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default="docs", help="folder for data/ and figures/ (default docs)")
    args = ap.parse_args(argv)
    res = main([s * 1e-3 for s in args.sizes], args.repeats, args.out)
    for r in res["cost"]:
        print(f"size {r['size_m'] * 1e3:.2f} mm, {r['dofs']} DOFs: moved pad "
              f"{r['pad_moved_elements']}/{r['pad_elements']}, rotor {r['rotor_moved_elements']}/"
              f"{r['rotor_elements']} elements; apply partial {r['partial_apply_s']:.3f} s "
              f"(reassembly {r['partial_reassembly_s']:.3f}), full {r['full_apply_s']:.3f} s "
              f"(reassembly {r['full_reassembly_s']:.3f}); ratio {r['partial_over_full']:.2f}")
    for r in res["quality"]:
        print(f"{'tapered' if r['taper'] else 'uniform'} wear to {r['fraction']:.2f} of the "
              f"friction layer: min quality {r['min_quality']:.4f}")
    print(f"figure: {res['figure']}")


if __name__ == "__main__":
    _cli()
