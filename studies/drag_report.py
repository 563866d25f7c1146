"""The end-state summary, the tables and the figures of ``studies/thermal_drag.py`` (the
default drag with thermal coupling off and on), from its results."""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from brakewear.mesh.surface import surface_nodes


def summary_of(hist, area, th, pad_law, p_end, act_end) -> dict:
    """The end state of one drag (wear, contact, pressures; with ``th``: temperatures and
    heat)."""
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
            "pad_face_T_max_C": float(th.face_temperature("pad").max()) - 273.15,
            "pad_face_T_mean_C": float(np.average(th.face_temperature("pad"),
                                                  weights=th.pad_area)) - 273.15,
            "rotor_face_T_max_C": float(th.face_temperature("rotor").max()) - 273.15,
            "pad_T_min_C": float(th.T["pad"].min()) - 273.15,
            "friction_power_last_W": b["friction_power_W"],
            "pad_net_share_last": pad_net / b["friction_power_W"],
            "heat_balance_error_max": max(s.heat_balance_error for s in hist),
            "pad_k_factor_max": float(np.max(pad_law.coefficient(th.face_temperature("pad"))
                                             / pad_law.k)),
        })
    return out


def write_tables(data: Path, step_rows: list, rows: list, rotor: dict) -> None:
    """``thermal_drag_steps.csv`` and ``thermal_drag_wear_profile.csv`` into ``data``."""
    for name, table in (("thermal_drag_steps.csv", step_rows),
                        ("thermal_drag_wear_profile.csv",
                         [{"surface": "pad", "r_mm": x["r_mm"], "off_um": x["pad_off_um"],
                           "on_um": x["pad_on_um"]} for x in rows]
                         + [{"surface": "rotor", "r_mm": x["r_mm"], "off_um": x["w_um"],
                             "on_um": y["w_um"]} for x, y in zip(rotor["off"], rotor["on"])])):
        keys = list(dict.fromkeys(k for row in table for k in row))
        with open(data / name, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=keys)
            w.writeheader()
            w.writerows(table)


def plot_temperatures(model, th, duration, fig_dir: Path) -> list[Path]:
    """Pad and rotor temperature after the drag, each on its friction face."""
    from brakewear.output.figures import plot_field

    paths = []
    for body, view, what in (("pad", (0.5, -0.8, -1.0), "friction face from below"),
                             ("rotor", (0.3, -0.7, 1.0), "friction face from above")):
        p = fig_dir / f"thermal_drag_T_{body}.png"
        plot_field(model.meshes[body], th.T[body] - 273.15, p,
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
    """Pad and rotor wear against the radius, thermal off and on."""
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


def plot_history(step_rows: list[dict], T_ambient_C: float, threshold_C: float,
                 path: Path) -> Path:
    """Face temperatures, contact, worn volumes and the heat balance over the drag."""
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
    ax.axhline(threshold_C, color="grey", lw=0.8, ls=":",
               label=f"pad wear threshold ({threshold_C:.0f} C)")
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
