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
import csv
import json
import logging
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from brakewear.mesh.surface import surface_nodes, tributary_areas
from brakewear.model import BrakeModel
from brakewear.wear import Numerics, Run, wear_history
from brakewear.thermal import ThermalModel
from brakewear.laws.base import WearLaw
from brakewear.mesh.rings import rotor_rings

logger = logging.getLogger("thermal_drag")

C0 = 273.15
PAD_LAW = WearLaw(5e-15, activation_energy=5e4, T_threshold=503.15)
ROTOR_LAW = WearLaw(5e-16)
H_C = 1e5

_FRESH = """
import json, sys, time
import brakewear
from brakewear import BrakeModel
from brakewear import FEInterface, wear_history
from brakewear import WearLaw
from brakewear.mesh.rings import rotor_rings
from brakewear import Numerics
from brakewear.wear import Run
a = json.loads(sys.argv[1])
m = BrakeModel(size=a["size"])
times, cpu = [], []
for _ in range(a["repeats"]):
    t0, c0 = time.perf_counter(), time.process_time()
    h = list(wear_history(Run(m, a["p"], a["omega"], a["duration"], WearLaw(*a["pad"]),
                              WearLaw(*a["rotor"]), mu=a["mu"],
                              numerics=Numerics(steps=a["steps"], scheme="implicit"))))
    times.append(time.perf_counter() - t0)
    cpu.append(time.process_time() - c0)
print(json.dumps({"times_s": times, "cpu_s": cpu, "thermal_imported": "brakewear.thermal" in sys.modules,
                  "package": brakewear.__file__, "pad_volume_m3": h[-1].pad_volume,
                  "rotor_volume_m3": h[-1].rotor_volume,
                  "pad_wear": h[-1].pad_wear.tolist()}))
"""


def _law_args(law: WearLaw) -> list:
    return [law.k, law.a, law.b, law.T_threshold, law.activation_energy]


def run(model: BrakeModel, thermal: bool, p_line: float, omega: float, mu: float,
        duration: float, steps: int, h_c: float = H_C):
    """One drag: (list of WearStep, ThermalModel or None, run seconds, build seconds,
    CPU seconds of this process)."""
    t0, c0 = time.perf_counter(), time.process_time()
    th = ThermalModel(model, contact_conductance=h_c) if thermal else None
    build = time.perf_counter() - t0
    hist = list(wear_history(Run(model, p_line, omega, duration, PAD_LAW, ROTOR_LAW, mu=mu, thermal=th, numerics=Numerics(steps=steps, scheme="implicit"))))
    return hist, th, time.perf_counter() - t0, build, time.process_time() - c0


def end_pressure(model, p_line: float, mu: float, hist, th=None):
    """Contact pressure of the final worn state (t = duration), with the final thermal
    load: (pressure, active) at the pad friction nodes (the last step's end state)."""
    last = hist[-1]
    return last.pressure_end, last.active_end


def _summary(hist, area, th, p_end, act_end) -> dict:
    last = hist[-1]
    out = {
        "pad_volume_m3": last.pad_volume, "rotor_volume_m3": last.rotor_volume,
        "pad_archard_m3": last.pad_archard,
        "pad_wear_max_um": 1e6 * float(last.pad_wear.max()),
        "pad_wear_mean_um": 1e6 * float((last.pad_wear * area).sum() / area.sum()),
        "rotor_wear_max_um": 1e6 * float(last.rotor_wear.max()),
        "contact_fraction_first": float(hist[0].active.mean()),
        "contact_fraction_last": float(last.active.mean()),
        "contact_area_fraction_last": float(area[last.active].sum() / area.sum()),
        "peak_pressure_last_MPa": 1e-6 * float(last.pressure.max()),
        "mean_pressure_over_contact_last_MPa": 1e-6 * float(
            (last.pressure * area).sum() / max(area[last.active].sum(), 1e-300)),
        "pressure_time_s": last.time - last.dt,
        "contact_fraction_end": float(act_end.mean()),
        "contact_area_fraction_end": float(area[act_end].sum() / area.sum()),
        "peak_pressure_end_MPa": 1e-6 * float(p_end.max()),
    }
    if th is not None:
        b = th.heat_balance()
        # heat_in_W includes the conductance exchange received; to_contact_W is
        # the pad's gross outflow through it: the difference is the net heat in
        pad_net = b["bodies"]["pad"]["heat_in_W"] - b["bodies"]["pad"]["to_contact_W"]
        out.update({
            "pad_face_T_max_C": float(th.face_temperature("pad").max()) - C0,
            "pad_face_T_mean_C": float(np.average(th.face_temperature("pad"),
                                                  weights=th.pad_area)) - C0,
            "rotor_face_T_max_C": float(th.face_temperature("rotor").max()) - C0,
            "pad_T_min_C": float(th.T["pad"].min()) - C0,
            "friction_power_last_W": b["friction_power_W"],
            "pad_net_share_last": pad_net / b["friction_power_W"],
            "heat_balance_error_max": max(s.heat_balance_error for s in hist),
            "pad_k_factor_max": float(np.max(PAD_LAW.coefficient(th.face_temperature("pad"))
                                             / PAD_LAW.k)),
        })
    return out


def _per_radius(r: np.ndarray, w: np.ndarray, area: np.ndarray):
    """Radii of the node rings (the pad and rotor meshes are structured in r) and the
    area-weighted mean of ``w`` on each: (radii, means)."""
    ring, radii = rotor_rings(r, 1e-6)
    a = np.bincount(ring, weights=area)
    return radii, np.bincount(ring, weights=w * area) / a


def _fresh_process_times(size, p, omega, mu, duration, steps, repeats,
                         tree: str | Path | None = None) -> dict:
    """Time the thermal=None loop in a new interpreter, run from ``tree`` (a source
    tree of brakewear; default this one: its package is imported, not an installed one)."""
    arg = json.dumps({"size": size, "p": p, "omega": omega, "mu": mu, "duration": duration,
                      "steps": steps, "repeats": repeats, "pad": _law_args(PAD_LAW),
                      "rotor": _law_args(ROTOR_LAW)})
    tree = Path(__file__).resolve().parents[1] if tree is None else Path(tree).resolve()
    res = subprocess.run([sys.executable, "-c", _FRESH, arg], check=True, capture_output=True,
                         text=True, cwd=tree)
    return json.loads(res.stdout.strip().splitlines()[-1])


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


# ------------------------------------------------------------------ figures --
def plot_temperatures(model, th, duration, fig_dir: Path) -> list[Path]:
    from brakewear.output.figures import plot_field

    paths = []
    for body, view, what in (("pad", (0.5, -0.8, -1.0), "friction face from below"),
                             ("rotor", (0.3, -0.7, 1.0), "friction face from above")):
        p = fig_dir / f"thermal_drag_T_{body}.png"
        plot_field(model.meshes[body], th.T[body] - C0, p,
                   f"{body} temperature after the {duration:g} s drag, thermal on ({what})",
                   label=f"{body} T (C)", cmap="inferno", view=view)
        paths.append(p)
    return paths


def plot_pressure(model, panels, path: Path) -> Path:
    """Pad friction-face pressure maps side by side, one colour scale, seen from the rotor."""
    from brakewear.output.figures import facets_to_pyvista, offscreen_pyvista

    pv = offscreen_pyvista()
    pad = model.meshes["pad"]
    nodes = surface_nodes(pad, "friction")
    facets = pad.boundaries["friction"]
    used = np.unique(pad.facets[:, facets])
    vmax = max(float(p.max()) for _, p in panels) * 1e-6
    pl = pv.Plotter(off_screen=True, window_size=[560 * len(panels) + 140, 760],
                    shape=(1, len(panels)), border=False)
    for i, (title, p) in enumerate(panels):
        vals = np.zeros(pad.p.shape[1])
        vals[nodes] = 1e-6 * p
        surf = facets_to_pyvista(pad, facets)
        surf.point_data["p (MPa)"] = vals[used]
        pl.subplot(0, i)
        pl.add_mesh(surf, scalars="p (MPa)", cmap="viridis", clim=(0.0, vmax),
                    show_edges=True, edge_color=(0.6, 0.6, 0.6), line_width=0.3,
                    show_scalar_bar=(i == len(panels) - 1),
                    scalar_bar_args={"title": "p (MPa)", "color": "black", "fmt": "%.1f",
                                     "vertical": True, "position_x": 0.82, "position_y": 0.2,
                                     "height": 0.6, "width": 0.1})
        pl.add_text(title, position="upper_edge", font_size=10, color="black")
        if i == 0:
            pl.add_text("pad friction face seen from the rotor: inner radius on the right",
                        position="lower_left", font_size=11, color="black")
        b = np.array(surf.bounds)
        c = 0.5 * (b[0::2] + b[1::2])
        d = 2.3 * max(b[1] - b[0], b[3] - b[2])
        if i == len(panels) - 1:   # keep the colour bar off the pad
            c = c - np.array([0.3 * (b[1] - b[0]), 0.0, 0.0])  # screen right is -x
        pl.camera.focal_point = tuple(c)
        pl.camera.position = (c[0], c[1], c[2] - d)
        pl.camera.up = (0.0, 1.0, 0.0)
        pl.set_background("white")
    pl.screenshot(str(path))
    pl.close()
    return path


def plot_wear(rows: list[dict], pad_pts: dict, path: Path, duration: float) -> Path:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    r = np.array([x["r_mm"] for x in rows])
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    ax = axes[0]
    for key, colour, label in (("off", "tab:blue", "thermal off"), ("on", "tab:red", "thermal on")):
        rr, w = pad_pts[key]
        ax.plot(rr, w, ".", color=colour, alpha=0.25, ms=4)
        ax.plot(r, [x[f"pad_{key}_um"] for x in rows], "o-", color=colour,
                label=f"{label} (mean per radius; dots: nodes)")
    ax.set_xlabel("radius (mm)")
    ax.set_ylabel("pad wear (um)")
    ax.set_title(f"pad wear after the {duration:g} s drag")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax = axes[1]
    for key, colour, label in (("off", "tab:blue", "thermal off"), ("on", "tab:red", "thermal on")):
        rr = np.array([x["r_mm"] for x in pad_pts[f"rotor_{key}"]])
        ax.plot(rr, [x["w_um"] for x in pad_pts[f"rotor_{key}"]], "s-", color=colour,
                label=label)
    ax.set_xlabel("radius (mm)")
    ax.set_ylabel("rotor wear (um, revolution average)")
    ax.set_title("rotor wear per ring")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_history(step_rows: list[dict], T_ambient_C: float, path: Path) -> Path:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = {k: [x for x in step_rows if x["run"] == k] for k in ("off", "on")}
    on = runs["on"]
    t = [0.0] + [x["time_s"] for x in on]
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
    ax = axes[0, 0]
    ax.plot(t, [T_ambient_C] + [x["pad_face_T_max_C"] for x in on], "r-", label="pad face max")
    ax.plot(t, [T_ambient_C] + [x["rotor_face_T_max_C"] for x in on], "k--",
            label="rotor face max")
    ax.axhline(PAD_LAW.T_threshold - C0, color="grey", lw=0.8, ls=":",
               label="pad wear threshold (230 C)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("temperature (C)")
    ax.set_title("thermal on: face temperatures")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[0, 1]
    for key, style in (("off", "b.-"), ("on", "r.-")):
        rows = runs[key]
        ax.plot([x["time_s"] - x["dt_s"] for x in rows],
                [100 * x["contact_fraction"] for x in rows], style, label=f"thermal {key}")
    ax.set_ylim(0, 105)
    ax.set_xlabel("time (s, start of step)")
    ax.set_ylabel("pad friction nodes in contact (%)")
    ax.set_title("contact")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[1, 0]
    for key, style in (("off", "b.-"), ("on", "r.-")):
        rows = runs[key]
        ax.plot([0.0] + [x["time_s"] for x in rows],
                [0.0] + [1e9 * x["pad_volume_m3"] for x in rows], style,
                label=f"pad, thermal {key}")
        ax.plot([0.0] + [x["time_s"] for x in rows],
                [0.0] + [1e10 * x["rotor_volume_m3"] for x in rows], style[0] + "--",
                label=f"rotor x 10, thermal {key}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("worn volume (mm^3)")
    ax.set_title("worn volume")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[1, 1]
    ax.semilogy([x["time_s"] for x in on], [max(x["heat_balance_error"], 1e-17) for x in on],
                "o-", ms=3, label="thermal on")
    ax.axhline(1e-8, color="r", lw=0.8, ls=":", label="1e-8 (test bound)")
    ax.set_ylim(1e-17, 1e-6)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("|heat in - friction power| / power")
    ax.set_title("heat balance per step")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


# --------------------------------------------------------------------- main --
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
    if fresh_process:
        fresh = _fresh_process_times(size, line_pressure, omega, mu, duration, steps, repeats)
        if fresh["thermal_imported"]:
            raise RuntimeError("a thermal=None run imported brakewear.thermal")
        timing["off_fresh_process_s"] = fresh["times_s"]
        timing["off_fresh_process_median_s"] = float(np.median(fresh["times_s"]))
        timing["cpu_off_fresh_process_s"] = fresh["cpu_s"]
        timing["cpu_off_fresh_process_median_s"] = float(np.median(fresh["cpu_s"]))
        timing["fresh_process_imported_thermal"] = fresh["thermal_imported"]
        timing["fresh_over_in_process_off"] = timing["off_fresh_process_median_s"] / med["off"]
        timing["fresh_pad_wear_max_diff_m"] = float(np.abs(
            np.asarray(fresh["pad_wear"]) - off[-1].pad_wear).max())
    if baseline is not None:
        base = _fresh_process_times(size, line_pressure, omega, mu, duration, steps, repeats,
                                    tree=baseline)
        if not str(base["package"]).startswith(str(Path(baseline).resolve())):
            raise RuntimeError(f"baseline run imported {base['package']}, not {baseline}")
        timing["off_baseline_s"] = base["times_s"]
        timing["off_baseline_median_s"] = float(np.median(base["times_s"]))
        timing["cpu_off_baseline_s"] = base["cpu_s"]
        timing["cpu_off_baseline_median_s"] = float(np.median(base["cpu_s"]))
        timing["baseline_over_in_process_off"] = timing["off_baseline_median_s"] / med["off"]
        timing["baseline_pad_wear_max_diff_m"] = float(np.abs(
            np.asarray(base["pad_wear"]) - off[-1].pad_wear).max())

    ends = {"off": end_pressure(model, line_pressure, mu, off),
            "on": end_pressure(model, line_pressure, mu, on, th)}
    summary = {"off": _summary(off, area, None, *ends["off"]),
               "on": _summary(on, area, th, *ends["on"])}
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
                                          "activation_energy_J_mol"), _law_args(PAD_LAW))),
                     "rotor_law": dict(zip(("k", "a", "b", "T_threshold_K",
                                            "activation_energy_J_mol"), _law_args(ROTOR_LAW))),
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
    for name, table in (("thermal_drag_steps.csv", step_rows),
                        ("thermal_drag_wear_profile.csv",
                         [{"surface": "pad", "r_mm": x["r_mm"], "off_um": x["pad_off_um"],
                           "on_um": x["pad_on_um"]} for x in rows]
                         + [{"surface": "rotor", "r_mm": x["r_mm"], "off_um": x["w_um"],
                             "on_um": y["w_um"]} for x, y in zip(rotor["off"], rotor["on"])])):
        keys = list(dict.fromkeys(k for row in table for k in row))
        with open(out / "data" / name, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=keys)
            w.writeheader()
            w.writerows(table)
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
