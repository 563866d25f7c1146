"""The default drag scene with thermal coupling off and on (docs/thermal_drag.md).

A downhill drag of the default brake: line pressure 1 MPa, rotor speed
55 rad/s (60 km/h on a 0.3 m tyre), mu = 0.4, for 90 s, run twice on the same
mesh with the same fixed steps and ``scheme="implicit"``:

* **off**: ``thermal=None`` (isothermal; the wear coefficient stays at its
  base value);
* **on**: ``thermal=ThermalModel(model, contact_conductance=1e5)``: frictional
  heat, the thermal-strain load in the contact, ``k(T)`` of the pad.

Pad wear law: Archard ``k = 5e-15 1/Pa`` up to 230 C (``T_threshold =
503.15 K``), above it ``k exp(E/R (1/T_threshold - 1/T))`` with ``E = 50
kJ/mol`` (x4.3 at 300 C, x10 at 350 C; the steep rise of resin-bonded pads
above ~230 C, Liu and Rhee).  Rotor (cast iron): ``k = 5e-16 1/Pa``, no
temperature dependence.

Why a contact conductance: a sliding interface has one temperature on both
sides.  The fixed effusivity partition (14 % of the heat into the pad) holds
for the instant of first contact only; over a drag it keeps feeding the pad
although the rotor face under it is cooler, and the pad face runs away
(800-4000 C within 30 s at this load, the contact collapsing onto a few
nodes).  ``h_c = 1e5 W/m^2 K`` ties the pad face to the rotor's ring
temperature (the revolution average), so the share of the heat each body
takes follows from their temperatures (the steady-sliding limit of the
partition) instead of being imposed.  Fixed steps, because the conductance
path computes its influence columns once per distinct ``dt``.

Outputs (``DIR`` default ``docs``): ``DIR/data/thermal_drag_scene.json``
(everything), ``DIR/data/thermal_drag_steps.csv`` (per step, both runs),
``DIR/data/thermal_drag_wear_profile.csv`` (wear along the radius), and
``DIR/figures/thermal_drag_{T_pad,T_rotor,pressure,wear,history}.png``.

Timing: the two runs alternate ``repeats`` times in this process (medians
reported; the thermal-on time includes building the ``ThermalModel``), and the
thermal-off run is repeated in a fresh interpreter that never imports
``brakewear.thermal`` (checked), to show that the import and the optional
coupling leave the non-thermal loop's run time unchanged.

Run ``python studies/thermal_drag.py [--out DIR] [--size MM] [--duration S]
[--steps N] [--repeats N] [--no-figures]``.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

import numpy as np

from brakewear.laws.base import WearLaw
from brakewear.mesh.rings import rotor_rings
from brakewear.mesh.surface import surface_nodes, tributary_areas
from brakewear.model import BrakeModel
from brakewear.thermal import ThermalModel
from brakewear.wear import Numerics, Run, wear_history

sys.path.insert(0, str(Path(__file__).resolve().parent))
from drag_report import (  # noqa: E402  (sibling scripts, not a package)
    plot_history,
    plot_pressure,
    plot_temperatures,
    plot_wear,
    summary_of,
    write_tables,
)
from fresh_timing import external_timing, law_args  # noqa: E402

logger = logging.getLogger("thermal_drag")

C0 = 273.15
PAD_LAW = WearLaw(5e-15, activation_energy=5e4, T_threshold=503.15)
ROTOR_LAW = WearLaw(5e-16)
H_C = 1e5

def run(model: BrakeModel, thermal: bool, p_line: float, omega: float, mu: float,
        duration: float, steps: int, h_c: float = H_C):
    """One drag: (list of WearStep, ThermalModel or None, run seconds, build seconds,
    CPU seconds of this process)."""
    t0, c0 = time.perf_counter(), time.process_time()
    th = ThermalModel(model, contact_conductance=h_c) if thermal else None
    build = time.perf_counter() - t0
    num = Numerics(steps=steps, scheme="implicit")
    hist = list(wear_history(Run(model, p_line, omega, duration, PAD_LAW, ROTOR_LAW, mu=mu,
                                 thermal=th, numerics=num)))
    return hist, th, time.perf_counter() - t0, build, time.process_time() - c0


def _per_radius(r: np.ndarray, w: np.ndarray, area: np.ndarray):
    """Radii of the node rings (the pad and rotor meshes are structured in r) and the
    area-weighted mean of ``w`` on each: (radii, means)."""
    ring, radii = rotor_rings(r, 1e-6)
    a = np.bincount(ring, weights=area)
    return radii, np.bincount(ring, weights=w * area) / a


def fixed_partition(size: float = 6e-3, duration: float = 30.0, steps: int = 10,
                    line_pressure: float = 1e6, omega: float = 55.0, mu: float = 0.4) -> dict:
    """The same drag with the fixed partition alone (``contact_conductance = 0``): why
    the main runs use a conductance.  Per step: pad and rotor face maxima, contact."""
    model = BrakeModel(size=size)
    rows = {}
    for h_c in (0.0, H_C):
        hist = run(model, True, line_pressure, omega, mu, duration, steps, h_c=h_c)[0]
        rows[f"h_c={h_c:g}"] = [{"time_s": s.time, "pad_face_T_max_C": s.pad_temperature_max - C0,
                                 "rotor_face_T_max_C": s.rotor_temperature_max - C0,
                                 "contact_fraction_start": float(s.active.mean()),
                                 "heat_balance_error": s.heat_balance_error} for s in hist]
    return {"size_m": size, "duration_s": duration, "steps": steps,
            "line_pressure_Pa": line_pressure, "omega_rad_s": omega, "mu": mu, "runs": rows}


def main(size: float = 6e-3, duration: float = 90.0, steps: int = 30,
         out: str | Path | None = "docs", line_pressure: float = 1e6, omega: float = 55.0,
         mu: float = 0.4, repeats: int = 3, figures: bool = True,
         fresh_process: bool = True, baseline: str | Path | None = None) -> dict:
    """Run the drag with thermal off and on; write data and figures under ``out``.

    Returns the results dict (also written to ``out/data/thermal_drag_scene.json``;
    ``out=None`` writes nothing).  ``fresh_process``: also time the thermal=None run in
    a new interpreter that never imports ``brakewear.thermal``.  ``baseline``: another
    brakewear source tree (a ``git archive`` of another version): the same
    thermal=None run is timed there too and its wear compared with this one's.
    """
    if int(repeats) != repeats or repeats < 1:
        raise ValueError(f"repeats = {repeats!r} is not allowed; need a whole number >= 1")
    model = BrakeModel(size=size)
    pad = model.meshes["pad"]
    nodes = surface_nodes(pad, "friction")
    area = tributary_areas(pad, "friction", nodes)
    r_pad = np.hypot(pad.p[0, nodes], pad.p[1, nodes])

    times = {"off": [], "on": []}
    cpu = {"off": [], "on": []}
    solve = {"off": [], "on": []}
    build = []
    results = {}
    for i in range(repeats):          # alternate, so that a slow spell hits both
        for key in ("off", "on"):
            hist, th, sec, b, c = run(model, key == "on", line_pressure, omega, mu, duration,
                                      steps)
            times[key].append(sec)
            cpu[key].append(c)
            solve[key].append(float(sum(s.solve_s for s in hist)))
            if key == "on":
                build.append(b)
            if key in results:        # the runs are deterministic: check it
                assert np.array_equal(results[key][0][-1].pad_wear, hist[-1].pad_wear)
            results[key] = (hist, th)
            logger.info("run %s %d: %.2f s", key, i, sec)
    (off, _), (on, th) = results["off"], results["on"]
    med = {k: float(np.median(v)) for k, v in times.items()}
    timing = {"repeats": repeats, "off_s": times["off"], "on_s": times["on"],
              "thermal_build_s": build, "off_median_s": med["off"], "on_median_s": med["on"],
              "thermal_cost_ratio": med["on"] / med["off"],
              "cpu_off_s": cpu["off"], "cpu_on_s": cpu["on"],
              "cpu_off_median_s": float(np.median(cpu["off"])),
              "cpu_on_median_s": float(np.median(cpu["on"])),
              "thermal_cost_ratio_cpu": float(np.median(cpu["on"]) / np.median(cpu["off"])),
              "contact_solve_s_off": solve["off"], "contact_solve_s_on": solve["on"],
              # wall time outside the contact solves: heat steps, thermal loads, bookkeeping
              "outside_solves_off_s": [t - s for t, s in zip(times["off"], solve["off"])],
              "outside_solves_on_s": [t - s for t, s in zip(times["on"], solve["on"])]}
    for key, tree in (("fresh_process", None if fresh_process else False),
                      ("baseline", baseline if baseline is not None else False)):
        if tree is not False:
            timing.update(external_timing(key, tree, off[-1].pad_wear, med["off"], size,
                                          line_pressure, omega, mu, duration, steps, repeats,
                                          PAD_LAW, ROTOR_LAW))

    # the worn state at t = duration: the last step's end pressure
    ends = {k: (h[-1].pressure_end, h[-1].active_end) for k, h in (("off", off), ("on", on))}
    summary = {"off": summary_of(off, area, None, PAD_LAW, *ends["off"]),
               "on": summary_of(on, area, th, PAD_LAW, *ends["on"])}
    if len(off) >= 2:
        # the implicit step wore the pad with its end pressure: p = dh / (dt k v)
        eps = off[-1].dt * PAD_LAW.rate(1.0, omega * r_pad)
        p_inc = (off[-1].pad_wear - off[-2].pad_wear) / eps
        summary["off"]["end_pressure_vs_last_wear_increment"] = float(
            np.abs(p_inc - ends["off"][0]).max() / ends["off"][0].max())
    summary["on_over_off"] = {k: summary["on"][k] / summary["off"][k] for k in (
        "pad_volume_m3", "rotor_volume_m3", "pad_wear_max_um", "pad_wear_mean_um",
        "rotor_wear_max_um", "peak_pressure_last_MPa", "peak_pressure_end_MPa")}

    # wear along the radius: area-weighted mean per ring of nodes (pad), per ring (rotor)
    rotor_mesh = model.meshes["rotor"]
    rnodes = surface_nodes(rotor_mesh, "friction")
    r_rot = np.hypot(rotor_mesh.p[0, rnodes], rotor_mesh.p[1, rnodes])
    a_rot = tributary_areas(rotor_mesh, "friction", rnodes)
    prof = {}
    for key, h in (("off", off), ("on", on)):
        prof[key] = _per_radius(r_pad, h[-1].pad_wear, area)
        prof["rotor_" + key] = _per_radius(r_rot, h[-1].rotor_wear, a_rot)
    rows = [{"r_mm": 1e3 * r, "pad_off_um": 1e6 * a, "pad_on_um": 1e6 * b}
            for r, a, b in zip(prof["off"][0], prof["off"][1], prof["on"][1])]
    rotor = {k: [{"r_mm": 1e3 * r, "w_um": 1e6 * w} for r, w in zip(*prof["rotor_" + k])]
             for k in ("off", "on")}

    step_rows = []
    for key, h in (("off", off), ("on", on)):
        for s in h:
            step_rows.append({
                "run": key, "step": s.step, "time_s": s.time, "dt_s": s.dt,
                "contact_fraction": float(s.active.mean()),
                "peak_pressure_MPa": 1e-6 * float(s.pressure.max()),
                "pad_volume_m3": s.pad_volume, "rotor_volume_m3": s.rotor_volume,
                "pad_face_T_max_C": s.pad_temperature_max - C0,
                "rotor_face_T_max_C": s.rotor_temperature_max - C0,
                "heat_balance_error": s.heat_balance_error, "solve_s": s.solve_s})

    res = {
        "settings": {"size_m": size, "line_pressure_Pa": line_pressure, "omega_rad_s": omega,
                     "mu": mu, "duration_s": duration, "steps": steps, "dt_s": duration / steps,
                     "scheme": "implicit", "contact_conductance_W_m2K": H_C,
                     "partition": "effusivity", "pad_share_partition": th.partition,
                     "h_conv_W_m2K": 40.0, "T_ambient_C": th.T_ambient - C0,
                     "pad_law": dict(zip(("k", "a", "b", "T_threshold_K",
                                          "activation_energy_J_mol"), law_args(PAD_LAW))),
                     "rotor_law": dict(zip(("k", "a", "b", "T_threshold_K",
                                            "activation_energy_J_mol"), law_args(ROTOR_LAW))),
                     "pad_friction_nodes": int(nodes.size),
                     "nodes": {b: int(m.p.shape[1]) for b, m in model.meshes.items()}},
        "summary": summary, "timing": timing,
        "wear_profile": {"pad": rows, "rotor_off": rotor["off"], "rotor_on": rotor["on"]},
        "steps": step_rows,
        "heat_balance_error_max": float(max(s.heat_balance_error for s in on)),
        "end_pressure_MPa": {k: (1e-6 * v[0]).tolist() for k, v in ends.items()},
        "pad_friction_radius_mm": (1e3 * r_pad).tolist(),
    }
    if out is None:
        return res
    out = Path(out)
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    (out / "data" / "thermal_drag_scene.json").write_text(json.dumps(res, indent=1) + "\n")
    write_tables(out / "data", step_rows, rows, rotor)
    if figures:
        fig = out / "figures"
        res["figures"] = [str(p) for p in plot_temperatures(model, th, duration, fig)]
        res["figures"].append(str(plot_pressure(model, [
            ("start (t = 0), both runs", off[0].pressure),
            (f"thermal off, end (t = {duration:g} s)", ends["off"][0]),
            (f"thermal on, end (t = {duration:g} s)", ends["on"][0])],
            fig / "thermal_drag_pressure.png")))
        pts = {"off": (1e3 * r_pad, 1e6 * off[-1].pad_wear),
               "on": (1e3 * r_pad, 1e6 * on[-1].pad_wear),
               "rotor_off": rotor["off"], "rotor_on": rotor["on"]}
        res["figures"].append(str(plot_wear(rows, pts, fig / "thermal_drag_wear.png", duration)))
        res["figures"].append(str(plot_history(step_rows, th.T_ambient - C0,
                                               PAD_LAW.T_threshold - C0,
                                               fig / "thermal_drag_history.png")))
    return res


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--size", type=float, default=6.0, help="mesh size (mm)")
    ap.add_argument("--duration", type=float, default=90.0, help="drag duration (s)")
    ap.add_argument("--steps", type=int, default=30, help="fixed wear steps")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs of each")
    ap.add_argument("--no-figures", action="store_true")
    ap.add_argument("--baseline", default=None,
                    help="another brakewear source tree (e.g. a git archive of another "
                         "version): time its thermal=None run and compare its wear")
    ap.add_argument("--fixed-partition", action="store_true",
                    help="only run the 30 s drag with contact_conductance 0 and 1e5 and write "
                         "DIR/data/thermal_drag_fixed_partition.json")
    a = ap.parse_args()
    logging.basicConfig(level=logging.WARNING, format="%(message)s")
    logger.setLevel(logging.INFO)
    if a.fixed_partition:
        fp = fixed_partition(a.size * 1e-3)
        Path(a.out, "data").mkdir(parents=True, exist_ok=True)
        Path(a.out, "data", "thermal_drag_fixed_partition.json").write_text(
            json.dumps(fp, indent=1) + "\n")
        for k, rows in fp["runs"].items():
            print(k, [(round(x["time_s"]), round(x["pad_face_T_max_C"]),
                       round(x["rotor_face_T_max_C"]), round(x["contact_fraction_start"], 2))
                      for x in rows])
        sys.exit(0)
    r = main(a.size * 1e-3, a.duration, a.steps, a.out, repeats=a.repeats,
             figures=not a.no_figures, baseline=a.baseline)
    print(json.dumps({"summary": r["summary"], "timing": r["timing"],
                      "heat_balance_error_max": r["heat_balance_error_max"]}, indent=1))
