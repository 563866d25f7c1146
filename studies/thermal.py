"""Thermal verification and a brake drag (the numbers of docs/thermal.md).

* ``half_space``: a 20 mm bar of pad material heated by a constant flux at
  one end (adiabatic sides), surface temperature at t = 10 s against the
  half-space closed form; errors under refinement in space (2000 time
  steps) and in time (0.0625 mm cells).
* ``drag``: the default brake (``--size`` mm) under 1 MPa, mu = 0.4,
  omega = 50 rad/s for 10 s, heat only (pressure of the isothermal contact
  solve): pad and rotor temperatures, energy balance of every step, the
  cost of a factorisation against a reused one; with the fixed partition
  and with a contact conductance of 1e5 W/m^2 K.
* ``staggered``: the steady staggered thermoelastic iteration (contact with
  the thermal load -> q -> steady heat) on a light drag at the size-8 mm
  model: the step ratio of the settled iteration is the loop gain B/L.

Run ``python studies/thermal.py [--out DIR] [--size MM] [--no-figures]``;
writes ``thermal_half_space.csv``, ``thermal_drag.json``,
``thermal_staggered.json`` into ``DIR/data`` and ``thermal_half_space.png``,
``thermal_drag.png`` into ``DIR/figures`` (default DIR: docs).
"""
from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

import numpy as np
import skfem as fem

from brakewear import analytic as an
from brakewear import static
from brakewear.contact import solve_contact
from brakewear.fem import HeatConduction
from brakewear.materials import MATERIALS
from brakewear.model import BrakeModel
from brakewear.output.figures import label_log_axis
from brakewear.thermal import ThermalModel

PAD = MATERIALS["pad_resin"]
Q, T_PROBE, LENGTH, T_AMB = 1e5, 10.0, 0.02, 300.0


def half_space_surface(nx: int, nsteps: int) -> float:
    """Surface temperature at T_PROBE of the bar with ``nx`` cells, ``nsteps`` steps."""
    x = np.linspace(0.0, LENGTH, nx + 1)
    m = fem.MeshTet.init_tensor(x, np.array([0.0, 1e-3]), np.array([0.0, 1e-3]))
    m = m.with_boundaries({"hot": lambda X: X[0] < 1e-12})
    body = HeatConduction(m, PAD, flux_facets="hot", T_ambient=T_AMB, name="bar")
    T = np.full(body.n, T_AMB)
    F = body.flux_load(np.full(body.face.size, Q))
    for _ in range(nsteps):
        T = body.step(T, F, T_PROBE / nsteps)
    return float(T[body.face].mean())


def half_space() -> list[dict]:
    th = PAD.thermal
    exact = an.semi_infinite_surface_temperature(T_PROBE, Q, th.kappa, th.rho, th.c, T_AMB)
    rows = []
    for kind, runs in (("space", [(n, 2000) for n in (5, 10, 20, 40, 80)]),
                       ("time", [(320, n) for n in (5, 10, 20, 40, 80, 160)])):
        for nx, ns in runs:
            T = half_space_surface(nx, ns)
            rows.append({"study": kind, "h_mm": 1e3 * LENGTH / nx, "dt_s": T_PROBE / ns,
                         "T_surface_K": T, "T_exact_K": exact,
                         "rel_error": abs(T - exact) / (exact - T_AMB)})
    for kind, key in (("space", "h_mm"), ("time", "dt_s")):
        r = [x for x in rows if x["study"] == kind]
        rate = np.polyfit(np.log([x[key] for x in r[:4]]),
                          np.log([x["rel_error"] for x in r[:4]]), 1)[0]
        print(f"half-space, {kind}: rate {rate:.2f} (first four); errors "
              + ", ".join(f"{x['rel_error']:.2e}" for x in r))
    return rows


def drag(size_mm: float, duration: float = 10.0, dt: float = 0.5,
         contact_conductance: float = 0.0) -> tuple[dict, BrakeModel, ThermalModel]:
    model = BrakeModel(size=size_mm * 1e-3)
    mu, omega, p_line = 0.4, 50.0, 1e6
    res = static.solve_contact(model, p_line, mu=mu)
    t0 = time.perf_counter()
    th = ThermalModel(model, contact_conductance=contact_conductance)
    build_s = time.perf_counter() - t0
    q = th.flux(res.interface_pressure, mu, omega)
    steps, errors, times = 0, [], []
    while th.time < duration - 1e-9:
        t0 = time.perf_counter()
        th.step(q, dt)
        times.append(time.perf_counter() - t0)
        errors.append(th.heat_balance()["relative_error"])
        steps += 1
    b = th.heat_balance()
    out = {
        "size_mm": size_mm, "line_pressure_Pa": p_line, "mu": mu, "omega_rad_s": omega,
        "duration_s": duration, "dt_s": dt, "steps": steps,
        "nodes": {k: int(th.heat[k].n) for k in th.bodies},
        "contact_conductance_W_m2K": contact_conductance,
        "pad_share": th.partition, "friction_power_W": b["friction_power_W"],
        "pad_net_share_last_step": (b["bodies"]["pad"]["heat_in_W"] - b["bodies"]["pad"][
            "to_contact_W"]) / b["friction_power_W"],
        "pad_face_T_max_K": float(th.face_temperature("pad").max()),
        "pad_face_T_mean_K": float(th.face_temperature("pad").mean()),
        "rotor_face_T_max_K": float(th.face_temperature("rotor").max()),
        "max_energy_balance_error": float(max(errors)),
        "build_s": build_s, "first_step_s (factorise + solve)": times[0],
        "later_step_s (reuse)": float(np.median(times[1:])),
    }
    print(json.dumps(out, indent=1))
    return out, model, th


def staggered(omega: float, iterations: int = 14) -> dict:
    model = BrakeModel(size=8e-3)
    th = ThermalModel(model, contact_conductance=0.0)
    mu, p_line = 0.4, 5e5
    cs = model.contact_system(p_line, mu)
    changes, active, n_active = [], None, []
    for _ in range(iterations):
        f = cs.f + cs.P.T @ th.thermal_load()
        res = solve_contact(cs.K, f, cs.fixed, cs.coords, [cs.pair], initial_active=active)
        active = res.active
        n_active.append(int(active[0].sum()))
        old = th.T["pad"].copy()
        th.steady(th.flux(res.pressure[0], mu, omega))
        changes.append(float(np.abs(th.T["pad"] - old).max()))
    ratios = [b / a for a, b in zip(changes[:-1], changes[1:])]
    out = {"omega_rad_s": omega, "line_pressure_Pa": p_line, "mu": mu,
           "max_change_K": changes, "ratio": ratios, "active_nodes": n_active,
           "pad_T_max_K": float(th.T["pad"].max())}
    print(f"staggered steady, omega {omega}: last ratios {np.round(ratios[-3:], 3)}, "
          f"active {n_active[-1]} of {active[0].size}, pad max {out['pad_T_max_K']:.1f} K")
    return out


def plot_half_space(rows: list[dict], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, kind, key, label, slope in ((axes[0], "space", "h_mm", "cell size h (mm)", 2),
                                        (axes[1], "time", "dt_s", "time step dt (s)", 1)):
        r = [x for x in rows if x["study"] == kind]
        x = np.array([v[key] for v in r])
        e = np.array([v["rel_error"] for v in r])
        ax.loglog(x, e, "o-", label="FE (P1, implicit Euler)")
        ax.loglog(x, e[0] * (x / x[0]) ** slope, "k--", lw=0.8, label=f"slope {slope}")
        ax.axhline(0.02, color="r", lw=0.8, ls=":", label="2 %")
        ax.set_xlabel(label)
        ax.set_ylabel("relative error of the surface temperature rise")
        ax.grid(True, which="both", alpha=0.3)
        label_log_axis(ax.xaxis, x)
        ax.legend()
    axes[0].set_title("space (2000 steps)")
    axes[1].set_title("time (0.0625 mm cells)")
    fig.suptitle("Half-space under constant flux, t = 10 s (pad material)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_drag(model: BrakeModel, th: ThermalModel, path: Path) -> None:
    """Rotor and pad surface temperatures after the drag, each on its own scale,
    both seen from the pad's side (+z), the pad's friction face from below."""
    from brakewear.output.figures import facets_to_pyvista, offscreen_pyvista

    pv = offscreen_pyvista()
    pl = pv.Plotter(off_screen=True, window_size=[1400, 760], shape=(1, 2))
    for i, (body, title) in enumerate((("rotor", "rotor friction face (inboard half)"),
                                       ("pad", "pad friction face, seen from the rotor"))):
        m = model.meshes[body]
        facets = m.boundaries["friction"]
        surf = facets_to_pyvista(m, facets)
        used = np.unique(m.facets[:, facets])
        label = f"{body} T (C)"
        surf.point_data[label] = th.T[body][used] - 273.15
        pl.subplot(0, i)
        pl.add_mesh(surf, scalars=label, cmap="inferno",
                    scalar_bar_args={"title": label, "color": "black", "fmt": "%.0f",
                                     "vertical": True, "position_x": 0.84, "position_y": 0.2})
        pl.add_text(title, position="upper_edge", font_size=11, color="black")
        b = np.array(surf.bounds)
        c = 0.5 * (b[0::2] + b[1::2])
        d = 2.6 * max(b[1] - b[0], b[3] - b[2])
        if body == "rotor":  # keep the colour bar off the ring
            c = c + np.array([0.12 * (b[1] - b[0]), 0.0, 0.0])
        pl.camera.focal_point = tuple(c)
        pl.camera.position = (c[0], c[1], c[2] + d if body == "rotor" else c[2] - d)
        pl.camera.up = (0.0, 1.0, 0.0)
        pl.set_background("white")
    pl.screenshot(str(path))
    pl.close()


def main(out: str | Path = "docs", size_mm: float = 4.0, figures: bool = True) -> dict:
    out = Path(out)
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    rows = half_space()
    with open(out / "data" / "thermal_half_space.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    d, model, th = drag(size_mm)
    d_hc, _, _ = drag(size_mm, contact_conductance=1e5)
    (out / "data" / "thermal_drag.json").write_text(json.dumps(
        {"fixed partition": d, "contact conductance 1e5": d_hc}, indent=1) + "\n")
    st = {"light drag": staggered(1.0), "twice the speed": staggered(2.0, 30)}
    (out / "data" / "thermal_staggered.json").write_text(json.dumps(st, indent=1) + "\n")
    if figures:
        plot_half_space(rows, out / "figures" / "thermal_half_space.png")
        plot_drag(model, th, out / "figures" / "thermal_drag.png")
    return {"half_space": rows, "drag": d, "staggered": st}


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--size", type=float, default=4.0, help="mesh size of the drag (mm)")
    ap.add_argument("--no-figures", action="store_true")
    a = ap.parse_args()
    main(a.out, a.size, not a.no_figures)
