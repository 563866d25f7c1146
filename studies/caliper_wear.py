"""What a brake engineer reads off the pads of a floating caliper, from the caliper's load path.

A drag on ``geometry/floating.toml`` held as the caliper holds its pads
(``BrakeModel(piston="rigid")``: the rigid piston in its bore and seal, the
rim, the fingers and the push bracket's abutments one-sided with Coulomb
friction; the full model on the hat rotor; :class:`brakewear.CaliperInterface`)
at one line pressure, long enough to run the pads in, with the materials' wear
coefficients.  Per pad:

* the worn volume and the mean wear: which pad wears more, and by how much;
* the radial taper, the mean wear of the outer quarter of the lining's radial
  width less that of the inner quarter, over the face's mean wear;
* the circumferential taper, the mean wear of the leading quarter of the arc
  less that of the trailing quarter, over the mean (> 0: the leading edge
  wears more);
* the normal force each face carries, against the clamp force: what the
  caliper's own friction takes (the abutments' along the axis, the bore's);

with the caliper's rows' forces at the start (rim, fingers, abutments, their
friction) that explain them.  ``abutment_friction`` sets the bracket's
friction (0: frictionless abutments, the mechanism switched off).

Run ``python studies/caliper_wear.py [--out DIR] [--size MM] [--hours H]
[--abutment-friction 0 0.2]``; writes ``DIR/data/caliper_wear.json``.
"""
from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from brakewear import CaliperInterface, Numerics, WearLaw
from brakewear.geometry import load_geometry
from brakewear.mesh.surface import face_nodes
from brakewear.model import BrakeModel
from brakewear.wear import Run, wear_history

LINE_PRESSURE = 1e6                        # Pa
MU = 0.4
OMEGA = 55.0                               # rad/s: the default scene's drag


def _quarter_taper(w, a, coord, lo, hi) -> float:
    """(mean over the upper quarter of ``coord`` less the lower quarter) over the mean."""
    q = 0.25 * (hi - lo)
    low, high = coord <= lo + q, coord >= hi - q
    mean = (w * a).sum() / a.sum()
    return float(((w * a)[high].sum() / a[high].sum() - (w * a)[low].sum() / a[low].sum())
                 / mean)


def pad_wear(model, itf, step) -> dict:
    """Per pad: worn volume (mm^3), mean wear (um), radial and circumferential taper."""
    g = model.geometry
    pad = model.meshes["pad"]
    x = pad.p[:, itf.pad_nodes]
    r = np.hypot(x[0], x[1])
    th = np.arctan2(x[1], x[0]) - g.pad.center_angle
    out = np.isin(itf.pad_nodes, face_nodes(pad, "friction_out"))
    half = 0.5 * g.pad.arc_angle
    rows = {}
    for face, mask in (("in", ~out), ("out", out)):
        w, a = step.pad_wear[mask], itf.area[mask]
        rows[face] = {"volume_mm3": float((w * a).sum() * 1e9),
                      "mean_um": float((w * a).sum() / a.sum() * 1e6),
                      "radial_taper": _quarter_taper(w, a, r[mask], g.pad.inner_radius,
                                                     g.pad.outer_radius),
                      # leading end at -half: the leading quarter is the low one
                      "leading_taper": -_quarter_taper(w, a, th[mask], -half, half)}
    return rows


def rows_at_start(itf, sol) -> dict:
    """The caliper's rows' forces of a solve, summed per family (N): normal and friction."""
    cal = sol.info["caliper"]
    rows = itf.rows
    out = {}
    for k, grp in enumerate(rows.group):
        out[grp] = out.get(grp, 0.0) + float(cal["force"][k])
    return out


def run(abutment_friction: float, size: float, hours: float) -> dict:
    g = load_geometry("floating")
    g = replace(g, support=replace(g.support, abutment_friction=abutment_friction))
    model = BrakeModel(g, size=size * 1e-3, piston="rigid")
    itf = CaliperInterface(model, LINE_PRESSURE, MU)
    n = itf.area.size
    first = itf.solve(np.zeros(n), None, mu=MU)
    F = LINE_PRESSURE * g.clamp_area
    out = np.isin(itf.pad_nodes, face_nodes(model.meshes["pad"], "friction_out"))
    force = {face: float((first.pressure * itf.area)[m].sum()) for face, m in
             (("in", ~out), ("out", out))}
    pad = g.pad.friction_material.wear_k
    rotor = g.rotor.material.wear_k
    last = None
    for last in wear_history(  # noqa: B007  (the last step)
        Run(
            model,
            LINE_PRESSURE,
            OMEGA,
            3600.0 * hours,
            WearLaw(pad),
            WearLaw(rotor),
            MU,
            interface=itf,
            numerics=Numerics(steps=10, scheme="implicit"),
        )
    ):
        pass
    return {"abutment_friction": abutment_friction, "clamp_force_N": F,
            "face_force_N": force, "face_force_share": {k: v / F for k, v in force.items()},
            "rows_N": rows_at_start(itf, first), "pads": pad_wear(model, itf, last)}


def main(frictions=(0.0, 0.2), size: float = 6.0, hours: float = 1.0, out=None) -> dict:
    """The drag for each abutment friction coefficient (see the module)."""
    t0 = time.perf_counter()
    result = {"settings": {"line_pressure_MPa": LINE_PRESSURE / 1e6, "mu": MU,
                           "omega_rad_s": OMEGA, "hours": hours, "size_mm": size},
              "runs": [run(f, size, hours) for f in frictions]}
    result["wall_s"] = time.perf_counter() - t0
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / "caliper_wear.json").write_text(json.dumps(result, indent=1))
    return result


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--size", type=float, default=6.0, help="mesh size (mm)")
    ap.add_argument("--hours", type=float, default=1.0)
    ap.add_argument("--abutment-friction", type=float, nargs="+", default=[0.0, 0.2])
    a = ap.parse_args(argv)
    res = main(tuple(a.abutment_friction), a.size, a.hours, a.out)
    for r in res["runs"]:
        p = r["pads"]
        print(f"abutment friction {r['abutment_friction']:g}: volume in {p['in']['volume_mm3']:.1f}"
              f" out {p['out']['volume_mm3']:.1f} mm^3; radial taper in "
              f"{p['in']['radial_taper']:+.2f} out {p['out']['radial_taper']:+.2f}; leading "
              f"taper in {p['in']['leading_taper']:+.2f} out {p['out']['leading_taper']:+.2f}; "
              f"face force share in {r['face_force_share']['in']:.3f} out "
              f"{r['face_force_share']['out']:.3f}")
    print(f"{res['wall_s']:.0f} s")
    return res


if __name__ == "__main__":
    _cli()
