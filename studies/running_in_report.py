"""Files and figures of the running-in studies (``studies/friction_taper.py``,
``studies/winkler_running_in.py``), drawn from their results."""
from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np


def _face_triangles(itf) -> np.ndarray:
    """The friction face's triangles (ntri, 3) in the interface's node numbering."""
    pad = itf.model.meshes["pad"]
    tri = pad.facets[:, pad.boundaries["friction"]]
    local = -np.ones(pad.nvertices, dtype=np.int64)
    local[itf.pad_nodes] = np.arange(itf.pad_nodes.size)
    return local[tri[:3]].T


def taper_figure(res: dict, path: Path) -> Path:
    """Wear along the arc, the leading/trailing difference and the centre of
    pressure over the drag, and the wear maps of the friction face, per mu."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    runs = list(res["runs"].values())
    band = res["settings"]["band"]
    fig = plt.figure(figsize=(12, 4.2 + 3.6 * ((len(runs) + 1) // 2)))
    grid = fig.add_gridspec(1 + (len(runs) + 1) // 2, 2, height_ratios=[1.15] + [1] * (
        (len(runs) + 1) // 2))
    a, b = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])
    b2 = b.twinx()
    lo, hi = min(r["profile_deg"][0] for r in runs), max(r["profile_deg"][-1] for r in runs)
    for edge in (lo, hi - band * (hi - lo)):
        a.axvspan(edge, edge + band * (hi - lo), color="0.92")
    for i, r in enumerate(runs):
        a.plot(r["profile_deg"], r["profile_um"], "o-", ms=3, color=f"C{i}",
               label=f"mu = {r['mu']:g}: taper {100 * r['taper']:+.1f} %, "
                     f"slope {r['slope_um_per_deg']:+.3f} um/deg")
        hist = r["history"]
        t = [row["time_s"] / 60 for row in hist]
        b.plot(t, [row["lead_minus_trail_um"] for row in hist], "-", color=f"C{i}",
               label=f"mu = {r['mu']:g}: lead - trail")
        b2.plot(t, [row["cop_deg"] for row in hist], "--", color=f"C{i}",
                label=f"mu = {r['mu']:g}: centre of pressure")
    a.text(lo, a.get_ylim()[1], " leading end", va="top", fontsize=9)
    a.text(hi, a.get_ylim()[1], "trailing end ", va="top", ha="right", fontsize=9)
    a.set_xlabel("angle from the pad centre line along the rotor's motion (deg)")
    a.set_ylabel("pad wear, mean over radius (um)")
    a.set_title(f"Pad wear along the arc after {res['settings']['duration_s'] / 60:.0f} min "
                f"(shaded: the {100 * band:.0f} % bands)", fontsize=10)
    a.legend(fontsize=8, loc="lower center")
    a.grid(alpha=0.3)
    b.axhline(0.0, color="k", lw=0.6)
    b.set_xlabel("time (min)")
    b.set_ylabel("leading minus trailing band wear (um), solid")
    b2.set_ylabel("centre of pressure (deg; < 0: toward leading), dashed")
    b.set_title("Taper and centre of pressure over the drag", fontsize=10)
    lines = b.get_legend_handles_labels()
    lines2 = b2.get_legend_handles_labels()
    b.legend(lines[0] + lines2[0], lines[1] + lines2[1], fontsize=8, loc="center right")
    b.grid(alpha=0.3)
    vmax = max(float(r["_fields"]["pad_wear"].max()) for r in runs) * 1e6
    vmin = min(float(r["_fields"]["pad_wear"].min()) for r in runs) * 1e6
    levels = np.linspace(vmin, vmax, 21)
    for i, r in enumerate(runs):
        ax = fig.add_subplot(grid[1 + i // 2, i % 2])
        f = r["_fields"]
        tri = Triangulation(f["xi"], f["itf"].r * 1e3, _face_triangles(f["itf"]))
        cs = ax.tricontourf(tri, f["pad_wear"] * 1e6, levels=levels, cmap="viridis")
        ax.set_title(f"pad wear (um), mu = {r['mu']:g}; rotor moves left to right",
                     fontsize=10)
        ax.set_xlabel("angle along the rotor's motion (deg); leading end at the left")
        ax.set_ylabel("radius (mm)")
        fig.colorbar(cs, ax=ax, format="%.0f")
    fig.suptitle(f"Default scene, {res['settings']['line_pressure_Pa'] / 1e6:g} MPa, "
                 f"{res['settings']['omega_rad_s']:g} rad/s, mesh "
                 f"{res['settings']['mesh_size_mm']:g} mm: friction tilts the pad toward "
                 "its leading end", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


LABELS = {"fe": "FE contact (elastic rotor)",
          "johnson": "Winkler, Johnson modulus (uncalibrated)",
          "stiffness": "Winkler, stiffness-calibrated",
          "pressure": "Winkler, pressure-calibrated (per node)"}
STYLES = {"fe": dict(color="k", marker="o", ls="-", ms=3, lw=1.6),
          "johnson": dict(color="tab:orange", marker="s", ls="--", ms=2.5, lw=1),
          "stiffness": dict(color="tab:blue", marker="^", ls="-.", ms=2.5, lw=1),
          "pressure": dict(color="tab:green", marker="v", ls=":", ms=2.5, lw=1.3)}


def speed_record(fe_solve_s: list, walls: dict, solve_s: dict) -> dict:
    """studies/winkler_running_in.py: the interface solve time of every step (s) of the
    FE run and of each Winkler run, and their ratios (medians: the machine is shared)."""
    speed = {"fe_solve_s": fe_solve_s, "fe_step_wall_s": walls["fe"],
             "fe_median_solve_s": float(np.median(fe_solve_s))}
    fs = np.array(fe_solve_s)
    for k, ws in solve_s.items():
        ws = np.array(ws)
        speed[k] = {"solve_s": ws.tolist(), "step_wall_s": walls[k],
                    "median_solve_s": float(np.median(ws)),
                    "ratio_of_medians": float(np.median(fs) / np.median(ws)),
                    "median_of_ratios": float(np.median(fs / ws)),
                    "min_ratio": float((fs / ws).min()),
                    "wall_ratio_of_medians": float(np.median(walls["fe"]) /
                                                   np.median(walls[k]))}
    return speed


def write(out: Path, res: dict, runs: dict, figures: bool, g) -> None:
    """studies/winkler_running_in.py: its JSON, fields, CSV files and (``figures``) PNGs."""
    d = out / "data"
    d.mkdir(parents=True, exist_ok=True)
    with open(d / "winkler_running_in.json", "w") as fh:
        json.dump(res, fh, indent=1, default=lambda o: o.tolist() if hasattr(o, "tolist")
                  else str(o))
    # every record's fields (to redo stages or plots without rerunning)
    arrays = {}
    for k, recs in runs.items():
        for name in ("pressure", "pad_wear", "rotor_wear"):
            arrays[f"{k}_{name}"] = np.array([getattr(s, name) for s in recs], dtype=np.float32)
        arrays[f"{k}_active"] = np.array([s.active for s in recs])
    np.savez_compressed(d / "winkler_running_in_fields.npz", **arrays)
    # per time and model
    rows = []
    sp = res["speed"]
    for k, lst in res["per_time"].items():
        for row in lst:
            j = row["j"]
            solve = sp["fe_solve_s"][j] if k == "fe" else sp[k]["solve_s"][j]
            rows.append({"model": k, **row, "solve_s_step_from_here": solve})
    keys = []
    for row in rows:
        keys += [c for c in row if c not in keys]
    with open(d / "winkler_running_in_steps.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    # stage profiles (long format)
    with open(d / "winkler_running_in_profiles.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time_s", "model", "profile", "coordinate", "value"])
        ax = res["profile_axes"]
        for st in res["stages"]:
            for k, pr in st["profiles"].items():
                for name, xs in (("pressure_mean_radius_MPa", ax["theta_deg"]),
                                 ("pad_wear_mean_radius_um", ax["theta_deg"]),
                                 ("pressure_centre_MPa", ax["centre_radius_m"]),
                                 ("pad_wear_centre_um", ax["centre_radius_m"]),
                                 ("rotor_wear_um", pr["rotor_ring_radius_m"])):
                    for x, v in zip(xs, pr[name]):
                        w.writerow([f"{st['time_s']:.6g}", k, name, f"{x:.6g}", f"{v:.6g}"])
    if figures:
        f = out / "figures"
        f.mkdir(parents=True, exist_ok=True)
        _figure_profiles(f / "winkler_running_in_pressure.png", res, "pressure", g)
        _figure_profiles(f / "winkler_running_in_wear.png", res, "wear", g)
        _figure_history(f / "winkler_running_in_history.png", res)


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _figure_profiles(path, res, what, g):
    plt = _plt()
    stages = res["stages"]
    ax_ = res["profile_axes"]
    nrow = 2 if what == "pressure" else 3
    fig, axs = plt.subplots(nrow, len(stages), figsize=(3.6 * len(stages), 3.0 * nrow + 0.6),
                            squeeze=False, sharey="row")
    lead = np.degrees(g.pad.center_angle + 0.5 * g.pad.arc_angle)
    for c, st in enumerate(stages):
        for k, pr in st["profiles"].items():
            sty = STYLES[k]
            if what == "pressure":
                axs[0, c].plot(ax_["theta_deg"], pr["pressure_mean_radius_MPa"], label=LABELS[k],
                               **sty)
                axs[1, c].plot(np.array(ax_["centre_radius_m"]) * 1e3, pr["pressure_centre_MPa"],
                               **sty)
            else:
                axs[0, c].plot(ax_["theta_deg"], pr["pad_wear_mean_radius_um"], label=LABELS[k],
                               **sty)
                axs[1, c].plot(np.array(ax_["centre_radius_m"]) * 1e3, pr["pad_wear_centre_um"],
                               **sty)
                axs[2, c].plot(np.array(pr["rotor_ring_radius_m"]) * 1e3, pr["rotor_wear_um"],
                               **{**sty, "marker": None if k == "fe" else sty["marker"]})
        t = st["time_s"]
        axs[0, c].set_title(f"t = {t:.0f} s" + (" (new pad)" if t == 0 else ""))
        axs[0, c].axvline(lead, color="0.7", lw=0.8)
        axs[0, c].set_xlabel("angle (deg), leading edge at grey line")
        axs[1, c].set_xlabel("radius (mm), pad centre line")
        if nrow == 3:
            axs[2, c].set_xlabel("radius (mm)")
            axs[2, c].set_xlim(0.98 * g.pad.inner_radius * 1e3, 1.02 * g.pad.outer_radius * 1e3)
    r_m = res["settings"]["mean_radius_profile_m"] * 1e3
    if what == "pressure":
        axs[0, 0].set_ylabel(f"pad pressure (MPa)\nat r = {r_m:.1f} mm")
        axs[1, 0].set_ylabel("pad pressure (MPa)\non the centre line")
        title = "Pad pressure during running-in: FE contact against Winkler interfaces"
    else:
        axs[0, 0].set_ylabel(f"pad wear (um)\nat r = {r_m:.1f} mm")
        axs[1, 0].set_ylabel("pad wear (um)\non the centre line")
        axs[2, 0].set_ylabel("rotor wear (um)\nring mean")
        title = "Pad and rotor wear during running-in: FE contact against Winkler interfaces"
    s = res["settings"]
    fig.suptitle(f"{title}\n{s['line_pressure_Pa'] / 1e6:g} MPa, {s['omega_rad_s']:g} rad/s, "
                 f"mu {s['mu']:g}, implicit, dt {s['dt_s']:g} s, mesh {s['size_m'] * 1e3:g} mm",
                 fontsize=10)
    h, lab = axs[0, 0].get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _figure_history(path, res):
    plt = _plt()
    fig, axs = plt.subplots(2, 4, figsize=(18, 7.5))
    pt = res["per_time"]
    for k, rows in pt.items():
        t = [r_["time_s"] for r_ in rows]
        sty = {**STYLES[k], "label": LABELS[k]}
        axs[0, 0].plot(t, [r_["pr_cv"] for r_ in rows], **sty)
        axs[0, 1].plot(t, [r_["pressure_max_MPa"] for r_ in rows], **sty)
        axs[0, 2].plot(t, [r_["contact_fraction"] for r_ in rows], **sty)
        axs[0, 3].plot(t, [r_["cop_r_mm"] for r_ in rows], **sty)
        if k != "fe":
            axs[1, 0].plot(t, [r_["pressure_l2_rel"] for r_ in rows], **sty)
            axs[1, 1].plot(t[1:], [r_["pad_wear_l2_rel"] for r_ in rows][1:], **sty)
    axs[0, 0].set_ylabel("p r spread: CV over the contact")
    axs[0, 1].set_ylabel("peak pad pressure (MPa)")
    axs[0, 2].set_ylabel("contact area fraction")
    axs[0, 3].set_ylabel("radius of the centre of pressure (mm)")
    c_inv = res["settings"]["cop_at_p_r_const"]["cop_r_mm"]
    axs[0, 3].axhline(c_inv, color="0.5", lw=0.8, ls="--")
    axs[0, 3].text(0.02, c_inv, "p r = const", color="0.4", fontsize=8, va="bottom",
                   transform=axs[0, 3].get_yaxis_transform())
    axs[1, 0].set_ylabel("pressure error, L2 relative to FE")
    axs[1, 1].set_ylabel("pad wear error, L2 relative to FE")
    sp = res["speed"]
    n = len(sp["fe_solve_s"])
    axs[1, 3].semilogy(range(1, n + 1), sp["fe_solve_s"], **{**STYLES["fe"], "label": LABELS["fe"]})
    for k in pt:
        if k != "fe":
            axs[1, 3].semilogy(range(1, n + 1), sp[k]["solve_s"],
                               **{**STYLES[k], "label": f"{LABELS[k]}: FE/Winkler "
                                  f"{sp[k]['median_of_ratios']:.0f}x"})
            if "retimed_solve_s" in sp[k]:
                axs[1, 3].semilogy(range(1, n + 1), sp[k]["retimed_solve_s"],
                                   color=STYLES[k]["color"], lw=0.8, alpha=0.5)
    axs[1, 3].set_xlabel("step")
    axs[1, 3].set_ylabel("interface solve time per step (s)")
    axs[1, 3].legend(fontsize=7)
    for k in pt:
        if k != "fe":
            rows = pt[k]
            axs[1, 2].plot([r_["time_s"] for r_ in rows][1:],
                           [r_["rotor_wear_l2_rel"] for r_ in rows][1:], **STYLES[k])
    axs[1, 2].set_ylabel("rotor wear (ring means) error, L2 rel. to FE")
    for a in list(axs.flat[:7]):
        a.set_xlabel("time (s)")
    h, lab = axs[0, 0].get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.suptitle("Running-in: FE contact against Winkler interfaces (history and cost per step)",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.05, 1, 0.97))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def replot(out: str | Path = "docs") -> None:
    """Redraw the Winkler study's figures from the JSON a run wrote (no solve)."""
    from brakewear.geometry import load_geometry
    out = Path(out)
    res = json.loads((out / "data" / "winkler_running_in.json").read_text())
    g = load_geometry("default")
    f = out / "figures"
    _figure_profiles(f / "winkler_running_in_pressure.png", res, "pressure", g)
    _figure_profiles(f / "winkler_running_in_wear.png", res, "wear", g)
    _figure_history(f / "winkler_running_in_history.png", res)
