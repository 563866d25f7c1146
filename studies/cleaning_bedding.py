"""The bedded state: the steady state solved directly against the bedding history
(docs/cleaning.md, "The bedded state").

On one brake and interface, the pads bed from new: blocks of ordinary stops
(``stops`` stops from ``speed`` km/h at ``decel`` m/s^2, ``interval`` s apart, the
study car braking through its blending controller: the friction brakes take
what the motor does not; each application standing for ``compress`` of them;
with ``hot`` the stops' heat cones the rotor, :class:`brakewear.cleaning.heat.RotorHeat`)
run by :func:`brakewear.cleaning.bedding.bedding_history` until the first cold
stop's pressure settles, and the steady state of the same duty (its mean line
pressure and thermal coning) solved directly
(:func:`brakewear.cleaning.steady.bedded_gap`).  Compared: the
first cold stop's pressure map (L2 over the history's, area-weighted), each
face's effective radius, and the cost in contact solves.

``--brake held``: the floating caliper's pads held square (both backplate ends
held in-plane, clamped by tractions on the piston's and the fingers'
footprints; the condensed FE contact), where the steady state is ``p r``
constant: its effective radius is the band's mid radius.  ``--brake caliper``:
the pads as the caliper holds them (:class:`brakewear.CaliperInterface`),
against what the cleaning routines start from: the state the pads bed to held
square (:func:`brakewear.cleaning.brake.held_brake`), its gap under the caliper.

Run ``python studies/cleaning_bedding.py --brake held --size 8 --out docs``.
"""
from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from brakewear import MATERIALS, Numerics, WearLaw
from brakewear.cleaning import bedding as bd
from brakewear.cleaning.brake import held_brake, transfer_gap
from brakewear.cleaning.corrosion import outboard_nodes
from brakewear.cleaning.routine import TouchFaces, WarmStart
from brakewear.cleaning.steady import bedded_gap
from brakewear.duty import KMH, repeated_stops, study_car
from brakewear.wear import Run

DEFAULTS = dict(brake="held", size=8.0, stops=5, speed=80.0, decel=3.0, interval=60.0,
                compress=5.0, blocks=60, tol=0.002, direct_tol=1e-3, mu=0.4, hot=False)


def brake(kind: str, size: float):
    """``(model, interface)``: the pads held square, or as the caliper holds them."""
    from brakewear import BrakeModel, CaliperInterface, CondensedInterface, load_geometry
    from brakewear.geometry import SupportGeometry

    g = load_geometry("floating")
    if kind == "held":
        m = BrakeModel(replace(g, support=SupportGeometry()), size=size * 1e-3, layout="full",
                       rotor="elastic")
        return m, CondensedInterface(m, 1e6, 0.4)
    m = BrakeModel(g, size=size * 1e-3, rotor="elastic", piston="rigid")
    return m, CaliperInterface(m, 1e6, 0.4)


def main(out=None, **settings) -> dict:
    st = {**DEFAULTS, **settings}
    model, itf = brake(st["brake"], st["size"])
    g = model.geometry
    band, t = (g.pad.inner_radius, g.pad.outer_radius), g.rotor.thickness
    k_pad, k_iron = MATERIALS["pad_resin"].wear_k, MATERIALS["grey_cast_iron"].wear_k
    block = repeated_stops(st["stops"], st["speed"] * KMH, decel=st["decel"],
                           interval=st["interval"], dwell_speed=st["speed"] * KMH)
    states = (TouchFaces(itf, t),)
    if st["hot"]:
        from brakewear.cleaning.brake import reduced_rotor
        from brakewear.cleaning.heat import RotorHeat
        from brakewear.thermal.reduced import HAT_CONING_PER_K
        heat = RotorHeat(reduced_rotor("floating", st["size"] * 1e-3), itf, band, t,
                         HAT_CONING_PER_K)
        states = (heat, TouchFaces(itf, t))
    run = Run(model, pad_law=WearLaw(k_pad), rotor_law=WearLaw(k_iron), mu=st["mu"],
              schedule=block, vehicle=study_car(), interface=WarmStart(itf),
              numerics=Numerics(scheme="implicit", dp_tol=0.05), states=states)
    t0 = time.perf_counter()
    hist = bd.bedding_history(run, cold_line_pressure=_duty_pressure(run, itf),
                              tol=st["tol"], max_blocks=st["blocks"], compress=st["compress"],
                              thickness=t)
    t_hist = time.perf_counter() - t0
    duty = hist.extra["duty"]
    t0 = time.perf_counter()
    solver = itf if st["brake"] == "held" else held_brake({}, "floating", st["size"] * 1e-3)[1]
    direct = bedded_gap(solver, duty, mu=st["mu"], k_pad=k_pad, k_rotor=k_iron, band=band,
                        thickness=t, tol=st["direct_tol"])
    if solver is not itf:
        direct.gap = transfer_gap(direct.gap, solver, itf)
        direct.pressure = transfer_gap(direct.pressure, solver, itf)
    t_direct = time.perf_counter() - t0
    P = hist.extra["cold_line_pressure"]
    faces = bd.face_masks(itf, t)
    p_hist = bd.cold_pressure(itf, hist.gap, P, st["mu"], t, hist.pressures[-1] > 0).pressure
    p_dir = bd.cold_pressure(itf, direct.gap, P, st["mu"], t, direct.pressure > 0).pressure
    r_hist = bd.face_radii(p_hist, itf, faces)
    r_dir = bd.face_radii(p_dir, itf, faces)
    result = {"settings": st, "line_pressure_MPa": P / 1e6,
              "history": {"blocks": len(hist.changes), "applications": hist.applications,
                          "settled": hist.settled, "changes": hist.changes,
                          "radii_mm": [[r * 1e3 for r in rr] for rr in hist.radii],
                          "wall_s": t_hist},
              "direct": {"iterations": direct.iterations, "solves": direct.solves,
                         "residuals": direct.residuals, "wall_s": t_direct,
                         "extra": {k: v for k, v in direct.extra.items() if k != "changes"}},
              "l2_direct_vs_history": bd.pressure_change(p_dir, p_hist, itf.area),
              "radii_history_last10_mm": [float(np.mean([r[j] for r in hist.radii[-10:]]) * 1e3)
                                          for j in range(len(faces))],
              "radii_history_mm": [r * 1e3 for r in r_hist],
              "radii_direct_mm": [r * 1e3 for r in r_dir],
              "mid_radius_mm": 0.5e3 * sum(band),
              "maps": {"r_mm": (itf.r * 1e3).tolist(), "y_mm": (itf.x[1] * 1e3).tolist(),
                       "face": np.where(outboard_nodes(itf.x, t), "out", "in").tolist(),
                       "flat": (itf.g0 <= bd.OFF_FACE).tolist(),
                       "history_MPa": (p_hist / 1e6).tolist(),
                       "direct_MPa": (p_dir / 1e6).tolist()}}
    if out is not None:
        _write(result, Path(out), f"cleaning_bedding_{st['brake']}" + ("_hot" if st["hot"]
                                                                       else ""))
    return result


def _duty_pressure(run, itf) -> float:
    """The line pressure of the block's first stop on a flat pad (the cold stop's)."""
    from brakewear.duty import run_schedule

    first = replace(run, schedule=run.schedule[:1], pad_law=WearLaw(1e-30), rotor_law=None,
                    states=())
    (rec,) = run_schedule(first)
    return rec.line_pressure


def _write(result: dict, out: Path, name: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    (out / "data" / f"{name}.json").write_text(json.dumps(result, indent=1))
    m = result["maps"]
    r, face, flat = np.array(m["r_mm"]), np.array(m["face"]), np.array(m["flat"])
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.4))
    for f, mk in (("in", "o"), ("out", "s")):
        sel = (face == f) & flat
        if sel.any():
            ax.plot(r[sel], np.array(m["history_MPa"])[sel] * r[sel], mk, ms=3, alpha=0.6,
                    label=f"{f}board, history")
            ax.plot(r[sel], np.array(m["direct_MPa"])[sel] * r[sel], "+", ms=5,
                    label=f"{f}board, direct")
    ax.set(xlabel="radius (mm)", ylabel="p r (MPa mm), first cold stop",
           title=f"L2 direct vs history {result['l2_direct_vs_history']:.3f}")
    ax.legend(fontsize=8)
    rr = np.array(result["history"]["radii_mm"])
    for j in range(rr.shape[1]):
        bx.plot(np.arange(rr.shape[0]), rr[:, j], "o-", ms=3, label=f"face {j}, history")
        bx.axhline(result["radii_direct_mm"][j], ls="--", color=f"C{j}",
                   label=f"face {j}, direct")
    bx.axhline(result["mid_radius_mm"], color="k", lw=0.6, label="mid radius (p r const)")
    bx.set(xlabel="block", ylabel="effective radius (mm)",
           title=f"history: {result['history']['applications']} applications x "
                 f"{result['settings']['compress']:g}; direct: {result['direct']['solves']} "
                 "solves")
    bx.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "figures" / f"{name}.png", dpi=110)
    plt.close(fig)


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--brake", choices=("held", "caliper"), default=DEFAULTS["brake"])
    for k in ("size", "compress", "tol", "direct_tol", "speed", "decel", "interval"):
        ap.add_argument(f"--{k.replace('_', '-')}", dest=k, type=float, default=DEFAULTS[k])
    ap.add_argument("--blocks", type=int, default=DEFAULTS["blocks"])
    ap.add_argument("--hot", action="store_true", help="the stops' heat cones the rotor")
    ap.add_argument("--out", default=None)
    a = vars(ap.parse_args(argv))
    r = main(a.pop("out"), **a)
    print(f"history: {r['history']['applications']} applications ({r['history']['wall_s']:.0f} "
          f"s), settled {r['history']['settled']}; direct: {r['direct']['solves']} solves "
          f"({r['direct']['wall_s']:.1f} s); L2 {r['l2_direct_vs_history']:.4f}; radii "
          f"history {r['radii_history_mm']} direct {r['radii_direct_mm']} mm")
    return r


if __name__ == "__main__":
    _cli()
