"""Heat in the cleaning stops on the full model (docs/cleaning.md, "Heat in the stops").

The floating caliper of ``geometry/floating.toml`` as the full model -- both
pads as the caliper holds them (the rigid piston in its bore, the fingers, the
abutments; ``held``: their backplate ends held in-plane instead), the elastic
rotor on its hat -- runs a schedule of stops with thermal
coupling on (:class:`brakewear.thermal.ThermalModel`: the heat of every wear
step into pad and rotor, the thermal load of the temperatures in every contact
solve, so the coning the stops create enters the gap step by step; the
rotor's convection follows its speed, ``SpeedConvection.solid()``, and the
dwells between the stops cool at the speed the car drives on at).  The car is
:func:`brakewear.duty.study_car` braking with a friction share (road load and
regeneration both on).  Per stop:

* **energy**: the kinetic energy, the road load's and the motor's parts and
  the friction brakes' (they add up to 1e-10); the model's friction work
  against the demand (within the torque drift it reports); the heat into pad
  and rotor against the friction work (1e-9);
* **temperature**: the first stop's swept-band mean face temperature against
  the closed form of a stop's falling flux on a slab heated on both faces
  (:func:`slab_stop_temperature`: the half-space solution and its images),
  and the share of the rotor's heat the swept slab holds at the stop's end
  (the rest has spread beyond the band, which the slab does not);
* **coning**: the ring's and the hat's capacity-weighted mean temperatures,
  the coning of each face across the pad (:class:`brakewear.thermal.RotorConing`
  of the temperature field) against the hat's thermal-coning figure times the
  ring's mean over the hat's (:data:`brakewear.thermal.reduced.HAT_CONING_PER_K`),
  and the reduced rotor (:class:`brakewear.thermal.reduced.ReducedRotorHeat`,
  driven by each stop's ring powers) against the full model's ring and hat.

Run ``python studies/cleaning_heat.py [--stops 5] [--size 6] [--out docs]``; writes
``data/cleaning_heat.json`` and ``figures/cleaning_heat.png``.
"""
from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from brakewear import (
    MATERIALS,
    BrakeModel,
    CaliperInterface,
    FEInterface,
    Numerics,
    WearLaw,
    load_geometry,
)
from brakewear import analytic as an
from brakewear.cleaning.corrosion import nonconformity_gap
from brakewear.cleaning.routine import routine_run
from brakewear.cleaning.rust import RustLaw, RustLayer
from brakewear.duty import KMH, repeated_stops, run_schedule, study_car
from brakewear.thermal import SpeedConvection, ThermalModel
from brakewear.thermal.coning import RotorConing
from brakewear.thermal.reduced import HAT_CONING_PER_K, ReducedRotorHeat, hat_nodes

sys.path.insert(0, str(Path(__file__).resolve().parent))

DEFAULTS = dict(stops=5, speed=50.0, decel=1.0, interval=120.0, friction_share=0.5,
                size=6.0, coning=30.0, mu=0.4, steps=6, held=False)


def slab_stop_temperature(t, q0: float, t_stop: float, half: float, material,
                          images: int = 20) -> np.ndarray:
    """Face temperature rise of a slab of thickness ``2 half`` heated on both faces by a
    stop's falling flux ``q0 (1 - t/t_s)``: by symmetry a slab of ``half`` with an
    insulated mid-plane, the half-space solution (:func:`brakewear.analytic.
    stop_temperature`) plus its images at depths ``2 n half`` (Carslaw and Jaeger)."""
    th = material.thermal
    out = an.stop_temperature(0.0, t, q0, t_stop, th.kappa, th.rho, th.c)
    for n in range(1, images + 1):
        out = out + 2.0 * an.stop_temperature(2 * n * half, t, q0, t_stop, th.kappa,
                                               th.rho, th.c)
    return out


def _means(model, thermal):
    """Capacity weights of the ring's and the hat's nodes and the swept band's face nodes."""
    g = model.geometry
    x = model.meshes["rotor"].p
    r = np.hypot(x[0], x[1])
    hat = hat_nodes(model)
    m = np.asarray(thermal.heat["rotor"].M @ np.ones(r.size)).ravel()
    face = thermal.heat["rotor"].face
    rf = r[face]
    band = (rf >= g.pad.inner_radius - 1e-9) & (rf <= g.pad.outer_radius + 1e-9)
    area = thermal.rotor_area
    slab = (~hat) & (r >= g.pad.inner_radius - 1e-9) & (r <= g.pad.outer_radius + 1e-9)
    return {"ring": np.where(hat, 0.0, m) / m[~hat].sum(),
            "hat": np.where(hat, m, 0.0) / m[hat].sum(),
            "band_nodes": face[band], "band_area": area[band] / area[band].sum(),
            "slab_capacity": np.where(slab, m, 0.0), "capacity": m}


def _brake(st: dict):
    """``(model, interface)``: the floating caliper as it holds its pads (rigid piston,
    fingers, abutments; :class:`brakewear.CaliperInterface`), or with ``held`` both
    backplate ends held in-plane on the FE contact (no load path)."""
    if st["held"]:
        from brakewear.geometry import SupportGeometry

        g = replace(load_geometry("floating"), support=SupportGeometry())
        model = BrakeModel(g, size=st["size"] * 1e-3, layout="full", rotor="elastic")
        return model, FEInterface(model, 1e6, st["mu"])
    model = BrakeModel(load_geometry("floating"), size=st["size"] * 1e-3, rotor="elastic",
                       piston="rigid")
    return model, CaliperInterface(model, 1e6, st["mu"])


def main(out=None, **settings) -> dict:
    """The schedule with heat on; the per-stop figures (see the module)."""
    st = {**DEFAULTS, **settings}
    model, itf = _brake(st)
    g = model.geometry
    thermal = ThermalModel(model, h_conv={"pad": 40.0, "rotor": SpeedConvection.solid()})
    band = (g.pad.inner_radius, g.pad.outer_radius)
    coning, reduced = RotorConing(thermal, band), ReducedRotorHeat(thermal, band=band)
    reduced.add_coning(coning)
    w = _means(model, thermal)
    car = study_car().with_friction_share(st["friction_share"])
    v0 = st["speed"] * KMH
    sched = repeated_stops(st["stops"], v0, decel=st["decel"], interval=st["interval"],
                           dwell_speed=v0)
    gap = nonconformity_gap(itf.x, *band, g.rotor.thickness, st["coning"] * 1e-6)
    out_nodes = itf.x[2] < -0.5 * g.rotor.thickness
    rows, t0 = [], time.perf_counter()
    watch = {"t": [], "band": []}

    def on_step(rec, s, pad_w, rot_w):
        if not rows:                      # the first stop's band temperature, step by step
            T = thermal.T["rotor"]
            watch["t"].append(s.time)
            watch["band"].append(float(w["band_area"] @ T[w["band_nodes"]]) - thermal.T_ambient)
            rise = T - thermal.T_ambient      # the heat the swept slab holds, of the rotor's
            watch["slab_share"] = float(w["slab_capacity"] @ rise / (w["capacity"] @ rise))

    rust = RustLayer(itf, RustLaw(thickness=1e-3 - 1e-9), MATERIALS["grey_cast_iron"].wear_k,
                     WearLaw(MATERIALS["pad_resin"].wear_k))
    run = routine_run(model, itf, car, rust, st["mu"], sched, gap0=gap, thermal=thermal,
                      numerics=Numerics(scheme="implicit", steps=st["steps"]))
    for rec in run_schedule(run, on_step=on_step):
        if rec.kind == "stop":
            # the stop's friction power at its start, distributed as p r A of its pressure
            shape = np.maximum(rec.pressure, 0.0) * itf.r * itf.area
            power = shape / shape.sum() * 2 * (2 * rec.friction_face_J) / rec.duration
            reduced.heat(reduced.ring_powers(itf.r, power, out_nodes), rec.duration,
                         rec.omega0, rec.omega1)
        else:
            reduced.cool(rec.duration, v0 / car.tyre_radius)
        rows.append(_row(rec, thermal, coning, reduced, w, car))
    result = {"settings": st, "rows": rows, "first_stop": _first_stop(rows, watch, model, car),
              "coning_scale": reduced.coning_scale, "coning_step_per_K": reduced.coning_step,
              "run_s": time.perf_counter() - t0}
    if out is not None:
        import json
        out = Path(out)
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "cleaning_heat.json").write_text(json.dumps(result, indent=1))
        if plot is not None:
            (out / "figures").mkdir(parents=True, exist_ok=True)
            plot(result, out / "figures" / "cleaning_heat.png")
    return result


def _row(rec, thermal, coning, reduced, w, car) -> dict:
    T = thermal.T["rotor"]
    Tr, Th = float(w["ring"] @ T), float(w["hat"] @ T)
    row = {"index": rec.index, "kind": rec.kind, "duration_s": rec.duration,
           "ring_C": Tr - 273.15, "hat_C": Th - 273.15,
           "reduced_ring_C": reduced.T_ring - 273.15, "reduced_hat_C": reduced.T_hat - 273.15,
           "coning_um": {k: v * 1e6 for k, v in coning(T).items()},
           "figure_coning_um": HAT_CONING_PER_K * (Tr - Th) * 1e6,
           "mesh_figure_coning_um": reduced.coning_step * (Tr - Th) * 1e6,
           "reduced_coning_um": reduced.coning() * 1e6}
    if rec.kind == "stop":
        friction = rec.target_face_J * 2 * car.brakes_per_axle / car.axle_share
        heat = rec.heat["heat_pad_J"] + rec.heat["heat_rotor_J"]
        row.update(line_pressure_MPa=rec.line_pressure / 1e6, kinetic_J=rec.kinetic_J,
                   road_J=rec.road_net_J, regenerated_J=rec.regenerated_J, friction_J=friction,
                   closure=(rec.road_net_J + rec.regenerated_J + friction) / rec.kinetic_J - 1,
                   target_face_J=rec.target_face_J, friction_face_J=rec.friction_face_J,
                   torque_drift=rec.torque_drift,
                   model_closure=(rec.road_net_J + rec.regenerated_J + friction
                                  * (1 + rec.torque_drift)) / rec.kinetic_J - 1,
                   heat_J=heat, heat_rotor_J=rec.heat["heat_rotor_J"],
                   heat_over_friction=heat / (2 * rec.friction_face_J) - 1,
                   rotor_T_max_peak_C=rec.heat["rotor_T_max_peak_C"])
    return row


def _first_stop(rows, watch, model, car) -> dict:
    """The first stop's band-mean face temperature against the slab's closed form
    (the rotor's share of the face's mean flux over the swept band)."""
    g = model.geometry
    r0 = rows[0]
    t_s = r0["duration_s"]
    band_area = np.pi * (g.pad.outer_radius ** 2 - g.pad.inner_radius ** 2)
    share = r0["heat_rotor_J"] / r0["heat_J"]          # the rotor's net share in the stop
    q0 = 2 * r0["heat_J"] * share / 2 / t_s / band_area  # per face, W/m^2, at the start
    t = np.array(watch["t"])
    fe = np.array(watch["band"])
    closed = slab_stop_temperature(t, q0, t_s, 0.5 * g.rotor.thickness, g.rotor.material)
    return {"t_s": t.tolist(), "fe_band_rise_K": fe.tolist(), "closed_form_K": closed.tolist(),
            "ratio_at_end": float(fe[-1] / closed[-1]),
            "slab_heat_share_at_end": watch["slab_share"],
            "ratio_max": float(fe.max() / closed.max()), "q0_W_m2": q0, "rotor_share": share}


def plot(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = result["rows"]
    t = np.cumsum([0.0] + [r["duration_s"] for r in rows])[1:]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    for key, lab, st in (("ring_C", "ring (FE)", "o-"), ("hat_C", "hat (FE)", "s-"),
                         ("reduced_ring_C", "ring (reduced)", "x--"),
                         ("reduced_hat_C", "hat (reduced)", "+--")):
        ax[0].plot(t, [r[key] for r in rows], st, label=lab)
    ax[0].set(xlabel="time (s)", ylabel="capacity-weighted mean (C)",
              title="rotor temperatures, end of each stop and dwell")
    ax[0].legend(fontsize=8)
    for f, mk in (("in", "o-"), ("out", "s-")):
        ax[1].plot(t, [r["coning_um"].get(f, np.nan) for r in rows], mk,
                   label=f"FE field, {f}board face")
    ax[1].plot(t, [r["figure_coning_um"] for r in rows], "k--",
               label="0.66 um/K x (ring - hat)")
    ax[1].plot(t, [r["mesh_figure_coning_um"] for r in rows], "k:",
               label="this mesh's even step x (ring - hat)")
    ax[1].plot(t, [r["reduced_coning_um"] for r in rows], "x-",
               label="reduced rotor, scaled to the figure")
    ax[1].set(xlabel="time (s)", ylabel="thermal coning across the pad (um)",
              title="coning the stops create")
    ax[1].legend(fontsize=8)
    fs = result["first_stop"]
    ax[2].plot(fs["t_s"], fs["fe_band_rise_K"], "o-", label="FE, swept band mean")
    ax[2].plot(fs["t_s"], fs["closed_form_K"], "k--", label="slab closed form")
    ax[2].set(xlabel="time in the first stop (s)", ylabel="face temperature rise (K)",
              title="first stop against the closed form")
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for k, v in DEFAULTS.items():
        if isinstance(v, bool):
            ap.add_argument(f"--{k.replace('_', '-')}", dest=k, action="store_true")
        else:
            ap.add_argument(f"--{k.replace('_', '-')}", dest=k, type=type(v), default=v)
    ap.add_argument("--out", default=None)
    a = vars(ap.parse_args(argv))
    out = a.pop("out")
    r = main(out, **a)
    for row in r["rows"]:
        if row["kind"] == "stop":
            print(f"stop {row['index']}: {row['line_pressure_MPa']:.2f} MPa, closure "
                  f"{row['closure']:.1e}, drift {row['torque_drift']:.2e}, heat/friction - 1 "
                  f"{row['heat_over_friction']:.1e}, ring {row['ring_C']:.1f} C hat "
                  f"{row['hat_C']:.1f} C, coning {row['coning_um']} um (figure "
                  f"{row['figure_coning_um']:.2f})")
    print(f"first stop: FE/closed form at its end {r['first_stop']['ratio_at_end']:.3f}, the "
          f"swept slab holds {r['first_stop']['slab_heat_share_at_end']:.3f} of the heat; "
          f"{r['run_s']:.0f} s")
    return r


if __name__ == "__main__":
    _cli()
