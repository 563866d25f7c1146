"""Figures of the thermal studies (``studies/thermal_coning.py``,
``studies/stop_temperature.py``), drawn from their results."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from brakewear import analytic as an
from brakewear.materials import MATERIALS
from brakewear.output.figures import label_log_axis
from brakewear.thermal.hat_cone import annulus_edge


def coning_figure(g, axi, est, hat3d, dT, path) -> None:
    """studies/thermal_coning.py: the axisymmetric section's displacement, and the
    inboard face's u_z(r) of the 3D model, the axisymmetric model and the closed forms."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    m, u, basis = axi["mesh"], axi["u"], axi["basis"]
    ur, uz = u[basis.nodal_dofs[0]], u[basis.nodal_dofs[1]]
    raw = 0.1 * g.rotor.outer_radius / max(np.abs(ur).max(), np.abs(uz).max())
    decade = 10.0 ** np.floor(np.log10(raw))
    scale = decade * max(k for k in (1, 2, 5) if k * decade <= raw)  # a round 1-2-5 factor
    fig, ax = plt.subplots(1, 2, figsize=(13, 5), width_ratios=(1.1, 1))
    tri = Triangulation(1e3 * m.p[0], 1e3 * m.p[1], m.t.T)
    ax[0].triplot(tri, color="0.8", lw=0.3)
    td = Triangulation(1e3 * (m.p[0] + scale * ur), 1e3 * (m.p[1] + scale * uz), m.t.T)
    pc = ax[0].tripcolor(td, 1e6 * uz, shading="gouraud", cmap="coolwarm")
    fig.colorbar(pc, ax=ax[0], label="u_z (um)")
    ax[0].set(aspect="equal", xlabel="r (mm)", ylabel="z (mm)",
              title=f"hat section: ring +{dT:.0f} K, hat cold\n(grey: undeformed; "
                    f"displacement x {scale:.0f})")
    ri, ro, t = g.rotor.inner_radius, g.rotor.outer_radius, g.rotor.thickness
    ax[1].plot(1e3 * hat3d["r"], 1e6 * hat3d["uz"], ".", ms=2, color="0.5",
               label=f"3D FE, P{hat3d['order']}, {hat3d['size_mm']:.0f} mm (every face node)")
    o = np.argsort(axi["r"])
    ax[1].plot(1e3 * axi["r"][o], 1e6 * axi["uz"][o], "k-", lw=1.5, label="axisymmetric FE")
    r = np.linspace(ri, ro, 50)
    alpha = g.rotor.material.thermal.alpha
    e = est["plate"]
    b = min(ri, g.rotor.hat.wall_radius - 0.5 * g.rotor.hat.wall_thickness)
    rise = annulus_edge(b, ro, g.rotor.material.elastic.nu, r)[2]
    ax[1].plot(1e3 * r, 1e6 * (e["psi"] * rise + alpha * dT * t), "C1--",
               label="closed form: annular plate on a cylindrical shell")
    e = est["rigid"]
    ax[1].plot(1e3 * r, 1e6 * (e["psi"] * (r - g.rotor.hat.wall_radius) + alpha * dT * t), "C2:",
               label="closed form: rigid-section ring on the shell")
    ax[1].set(xlabel="r (mm)", ylabel="u_z of the inboard friction face (um)",
              title=f"cone at mid band: {1e3 * hat3d['cone']:.2f} mrad (3D), "
                    f"{1e3 * axi['cone']:.2f} mrad (axisymmetric)\nring +{dT:.0f} K")
    ax[1].grid(alpha=0.3)
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)


def stop_figure(res: dict, path: Path) -> Path:
    """studies/stop_temperature.py: the column against the closed form, convergence, the
    brake's stop."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 3, figsize=(15, 8.5))
    t_stop, t_amb = res["settings"]["t_stop_s"], res["settings"]["T_ambient_K"]
    for (name, run), color in zip(res["column"].items(), ("C0", "C3")):
        th = MATERIALS[name].thermal
        t = np.linspace(0, t_stop * (1 + res["settings"]["after"]), 400)
        exact = an.stop_surface_temperature(t, run["q0_W_m2"], t_stop, th.kappa, th.rho, th.c)
        ax[0, 0].plot(t, exact, color=color, label=f"{name}: closed form")
        ax[0, 0].plot(run["t_s"], np.subtract(run["T_surface_K"], t_amb), "o", ms=3.5,
                      color=color, mfc="none", label=f"{name}: FE")
    ax[0, 0].axvline(t_stop / 2, color="0.6", lw=0.8, ls=":")
    ax[0, 0].axvline(t_stop, color="0.6", lw=0.8, ls=":")
    ax[0, 0].set(xlabel="t (s)", ylabel="surface rise (K)",
                 title=f"column, {res['settings']['cells']} cells, "
                       f"{res['settings']['steps']} steps per stop")
    ax[0, 0].legend(fontsize=8)
    run = res["column"]["grey_cast_iron"]
    th = MATERIALS["grey_cast_iron"].thermal
    for (key, prof), color in zip(run["profiles"].items(), ("C1", "C2")):
        x = np.linspace(0, max(prof["x_m"]) / 2, 300)
        exact = an.stop_temperature(x, prof["t_s"], run["q0_W_m2"], t_stop, th.kappa, th.rho,
                                    th.c)
        ax[0, 1].plot(1e3 * x, exact, color=color, label=f"t = {prof['t_s']:g} s ({key})")
        ax[0, 1].plot(1e3 * np.array(prof["x_m"]), np.subtract(prof["T_K"], t_amb), "o",
                      color=color, mfc="none")
    ax[0, 1].set(xlim=(0, 1e3 * max(prof["x_m"]) / 2), xlabel="depth (mm)", ylabel="rise (K)",
                 title="grey cast iron inside: closed form (lines), FE nodes")
    ax[0, 1].legend(fontsize=8)
    _plot_brake(ax[0, 2], res["brake"][-1])
    for a, study, unit, slope in ((ax[1, 0], res["space"], "first cell / sqrt(a t_s)", 2),
                                  (ax[1, 1], res["time"], "dt (s)", 1)):
        for key, mark in (("peak", "o-"), ("end", "s-")):
            a.loglog(study["h"], study[key], mark,
                     label=f"t = t_s{' / 2' if key == 'peak' else ''}: rate "
                           f"{study['rate_' + key]:.2f}")
        h = np.array(study["h"])
        a.loglog(h, study["end"][0] * (h / h[0]) ** slope, "k:", lw=0.8, label=f"slope {slope}")
        label_log_axis(a.xaxis, h)
        a.set(xlabel=unit, ylabel="relative error of the surface rise",
              title=f"{study['kind']}: " + (f"{study['fixed']} steps (Richardson in dt)"
                                            if study["kind"] == "space"
                                            else f"{study['fixed']} cells"))
        a.legend(fontsize=8)
    _plot_bulk(ax[1, 2], res["brake"][-1])
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _plot_brake(a, b: dict) -> None:
    th = MATERIALS["grey_cast_iron"].thermal
    t = np.linspace(0, b["t_stop_s"], 200)
    a.plot(t, an.stop_surface_temperature(t, b["rotor_flux0_W_m2"], b["t_stop_s"], th.kappa,
                                          th.rho, th.c), "k", label="half-space, mean ring flux")
    h, T0 = b["history"], b["T_ambient_K"]
    ts = [0] + [x["t_s"] for x in h]
    a.plot(ts, [0] + [x["ring_mean_K"] - T0 for x in h], "o-", ms=3.5,
           label="FE rotor face, mean over the swept ring")
    a.plot(ts, [0] + [x["face_max_K"] - T0 for x in h], "s-", ms=3.5, label="FE rotor face, max")
    a.axhline(b["rotor_bulk_rise_K"], color="0.5", ls="--", lw=0.8,
              label="rotor bulk rise at the end")
    a.set(xlabel="t (s)", ylabel="rise (K)",
          title=f"default brake, {1e3 * b['size_m']:g} mm mesh: rotor face over the stop")
    a.legend(fontsize=8)


def _plot_bulk(a, b: dict) -> None:
    h = b["history"]
    mc = sum(b["mc_J_K"].values())
    ts = [0] + [x["t_s"] for x in h]
    a.plot(ts, [0] + [x["work_J"] / mc for x in h], "k", label="friction work / sum(m c)")
    a.plot(ts, [0] + [x["stored_J"] / mc for x in h], "o", mfc="none",
           label="FE: capacity-weighted mean rise")
    a.set(xlabel="t (s)", ylabel="rise (K)",
          title=f"pad + rotor, no convection: bulk rise {b['bulk_rise_K']:.2f} K")
    a.legend(fontsize=8)
