"""A single brake stop against the closed form (docs/verification.md, last section).

* ``column``: a column of rotor (grey cast iron) or pad (resin) material,
  ``DEPTH`` diffusion lengths ``sqrt(a t_s)`` deep (semi-infinite over the stop
  and after it), adiabatic sides and bottom, heated on its top face by a stop's
  flux ``q0 (1 - t / t_s)``: :class:`~brakewear.fem.HeatConduction` (P1
  tetrahedra, implicit Euler, consistent capacity) against
  :func:`brakewear.analytic.stop_surface_temperature` at the peak (``t_s / 2``)
  and at the end of the stop, and :func:`~brakewear.analytic.stop_temperature`
  inside.  Each implicit step takes the step's mean flux, the exact integral
  of ``q`` over the step (:func:`~brakewear.analytic.stop_heat`) over ``dt``.
  Nodes graded geometrically toward the heated face (last cell ``RATIO``
  times the first); refinement doubles the cells at the same ratio.
* ``brake``: the default brake (:class:`~brakewear.model.BrakeModel`),
  :class:`~brakewear.thermal.ThermalModel` with its defaults but no
  convection, one stop of a 1500 kg car from 100 km/h under 5 MPa (the
  deceleration from the brake's torque, :class:`~brakewear.duty.Vehicle`):
  the friction work against the vehicle's energy, the mean temperature rise
  of pad and rotor against ``E / sum(m c)``, and the rotor face against the
  closed form with the revolution-averaged flux.

Run ``PYTHONPATH=. python studies/stop_temperature.py [--out docs/figures]``; writes
``stop_temperature.json`` and ``stop_temperature.png``.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import skfem as fem

from brakewear import analytic as an
from brakewear.duty import KMH, Stop, Vehicle, brake_torque, effective_radius
from brakewear.fem import HeatConduction
from brakewear.materials import MATERIALS
from brakewear.mesh.convergence import fitted_rate
from brakewear.model import BrakeModel
from brakewear.static import solve_contact
from brakewear.thermal import ThermalModel

sys.path.insert(0, str(Path(__file__).resolve().parent))
from thermal_figures import stop_figure  # noqa: E402  (a sibling script, not a package)

T_STOP = 4.0          # s: 100 km/h at 7 m/s^2
T_AMB = 293.15        # K
DEPTH = 6.0           # column depth in diffusion lengths sqrt(a t_s)
RATIO = 20.0          # last over first cell of the graded column
#: flux at the start of the stop (W/m^2): a hard stop's revolution-averaged
#: rotor flux and the pad's effusivity share (the values only scale the rise)
FLUX = {"grey_cast_iron": 1.5e6, "pad_resin": 3e5}


def diffusion_length(material: str, t: float) -> float:
    """``sqrt(a t)``, ``a = kappa / (rho c)`` (m)."""
    th = MATERIALS[material].thermal
    return float(np.sqrt(th.kappa / (th.rho * th.c) * t))


def column_axis(depth: float, cells: int, ratio: float = RATIO) -> np.ndarray:
    """Node depths 0 .. ``depth``, geometric growth, last cell ``ratio`` times the first."""
    g = ratio ** (1.0 / (cells - 1))
    return depth * (g ** np.arange(cells + 1) - 1.0) / (g ** cells - 1.0)


def column_mesh(x: np.ndarray) -> fem.MeshTet:
    """A column of one cell's section (as wide as the first cell), heated face at x = 0."""
    w = x[1]
    m = fem.MeshTet.init_tensor(x, np.array([0.0, w]), np.array([0.0, w]))
    return m.with_boundaries({"heated": lambda X: X[0] < 1e-9 * w})


def run_column(material: str = "grey_cast_iron", cells: int = 10, steps: int = 32,
               t_stop: float = T_STOP, after: float = 0.0, ratio: float = RATIO,
               depth: float = DEPTH, history: bool = False) -> dict:
    """The column over one stop (``steps`` implicit-Euler steps) and ``after`` stops more.

    Returns, at the peak ``t_s / 2`` and at ``t_s`` (``probes``), the surface
    temperature (mean of the heated face's nodes) and the closed form, their
    relative difference in the rise (``errors``), the largest spread of the
    face's nodes over the rise, the first cell in diffusion lengths, and with
    ``history`` the surface temperature of every step and the depth profiles
    at both probe times.
    """
    if steps % 2:
        raise ValueError(f"steps = {steps}: need an even number (t_s / 2 is a probe)")
    mat = MATERIALS[material]
    th, q0 = mat.thermal, FLUX[material]
    delta = diffusion_length(material, t_stop)
    x = column_axis(depth * delta, cells, ratio)
    body = HeatConduction(column_mesh(x), mat, flux_facets="heated", T_ambient=T_AMB,
                          name=f"column ({material})", reuse="exact")
    on_axis = np.flatnonzero((body.mesh.p[1] == 0) & (body.mesh.p[2] == 0))
    on_axis = on_axis[np.argsort(body.mesh.p[0, on_axis])]
    dt = t_stop / steps
    T = np.full(body.n, T_AMB)
    ones = np.ones(body.face.size)
    names = {steps // 2: "peak", steps: "end"}
    out = {"material": material, "cells": cells, "steps": steps, "dt_s": dt,
           "h_over_delta": float(x[1] / delta), "q0_W_m2": q0, "probes": {}, "errors": {},
           "face_spread": 0.0, "t_s": [0.0], "T_surface_K": [T_AMB], "profiles": {}}
    for k in range(steps + int(round(after * steps))):
        # the step's mean flux: the exact integral of q over the step, over dt
        q_mean = an.stop_heat(k * dt, (k + 1) * dt, q0, t_stop) / dt
        T = body.step(T, body.flux_load(q_mean * ones), dt)
        t, face = (k + 1) * dt, T[body.face]
        if history:
            out["t_s"].append(t)
            out["T_surface_K"].append(float(face.mean()))
        if k + 1 in names:
            exact = float(an.stop_surface_temperature(t, q0, t_stop, th.kappa, th.rho, th.c,
                                                      T_AMB))
            out["probes"][names[k + 1]] = {"t_s": t, "T_K": float(face.mean()), "exact_K": exact}
            out["errors"][names[k + 1]] = relative_error(face.mean(), exact)
            out["face_spread"] = max(out["face_spread"], float(np.ptp(face) / (exact - T_AMB)))
            if history:
                out["profiles"][names[k + 1]] = {"t_s": t, "x_m": body.mesh.p[0, on_axis].tolist(),
                                                 "T_K": T[on_axis].tolist()}
    return out


def relative_error(T: float, exact: float) -> float:
    """``|T - exact|`` over the closed form's rise ``exact - T_AMB``."""
    return float(abs(T - exact) / (exact - T_AMB))


def convergence(kind: str, levels, fixed: int, material: str = "grey_cast_iron") -> dict:
    """Errors under refinement in space (``levels`` = cells) or in time (``levels`` =
    steps per stop), with the fitted rates.

    In space ``fixed`` is the number of steps, and each level runs ``fixed / 2``
    and ``fixed`` steps: ``2 T(dt) - T(2 dt)`` (Richardson) removes the
    implicit-Euler error, first order in ``dt``, which would otherwise floor the
    error at ``t_s`` (where ``dT/dt`` is largest).  In time ``fixed`` is the
    number of cells.
    """
    errors = {"peak": [], "end": []}
    h = []
    for n in levels:
        if kind == "space":
            fine = run_column(material, cells=n, steps=fixed)
            coarse = run_column(material, cells=n, steps=fixed // 2)
            h.append(fine["h_over_delta"])
            for key, pr in fine["probes"].items():
                extrapolated = 2.0 * pr["T_K"] - coarse["probes"][key]["T_K"]
                errors[key].append(relative_error(extrapolated, pr["exact_K"]))
        else:
            run = run_column(material, cells=fixed, steps=n)
            h.append(run["dt_s"])
            for key in errors:
                errors[key].append(run["errors"][key])
    return {"kind": kind, "material": material, "fixed": fixed, "levels": list(levels),
            "h": h, **errors, "rate_peak": fitted_rate(h, errors["peak"]),
            "rate_end": fitted_rate(h, errors["end"])}


def brake_stop(size: float = 12e-3, steps: int = 16, line_pressure: float = 5e6,
               mu: float = 0.4, v0: float = 100 * KMH, mass: float = 1500.0) -> dict:
    """One stop of the default brake, heat only (the isothermal contact pressure of
    ``line_pressure``), no convection: energies, the mean rise and the rotor face.

    Each step takes the mean speed of the step (its midpoint: the speed falls
    linearly), so the friction work is exact.  ``sum(m c)`` is the capacity
    of the meshed bodies (``1^T M 1``); the geometry's is reported beside it.
    """
    model = BrakeModel(size=size)
    g = model.geometry
    p = solve_contact(model, line_pressure, mu=mu).interface_pressure
    th = ThermalModel(model, h_conv=0.0)
    torque = brake_torque(line_pressure, mu, g.piston.hydraulic_area,
                          effective_radius(p, th.pad_area, th.pad_radius))
    vehicle, stop = Vehicle(mass=mass), Stop(v0, line_pressure=line_pressure)
    decel = vehicle.deceleration(torque)
    t_stop, omega0 = stop.v0 / decel, vehicle.rotor_speed(stop.v0)
    rotor_face = th.heat["rotor"].face
    r = np.hypot(*model.meshes["rotor"].p[:2, rotor_face])
    swept = (r > g.pad.inner_radius - 1e-9) & (r < g.pad.outer_radius + 1e-9)
    A = th.heat["rotor"].face_area * swept
    dt, work, hist = t_stop / steps, 0.0, []
    for k in range(steps):
        th.step(th.flux(p, mu, omega0 * (1.0 - (k + 0.5) / steps)), dt)
        work += th.heat_balance()["friction_power_W"] * dt
        Tf = th.face_temperature("rotor")
        stored = sum(float((th.heat[b].M @ (th.T[b] - th.T_ambient)).sum()) for b in th.bodies)
        hist.append({"t_s": (k + 1) * dt, "ring_mean_K": float(A @ Tf / A.sum()),
                     "face_max_K": float(Tf.max()), "work_J": work, "stored_J": stored})
    T0 = th.T_ambient
    stored = {b: float((th.heat[b].M @ (th.T[b] - T0)).sum()) for b in th.bodies}
    mc = {b: float(th.heat[b].M.sum()) for b in th.bodies}
    ring = g.rotor.outer_radius ** 2 - g.rotor.inner_radius ** 2
    th_r, th_p, th_b = (g.rotor.material.thermal, g.pad.friction_material.thermal,
                        g.pad.backplate_material.thermal)
    mc_geometry = (np.pi * ring * g.rotor.thickness / 2 * th_r.rho * th_r.c + g.pad.area * (
        g.pad.friction_thickness * th_p.rho * th_p.c
        + g.pad.backplate_thickness * th_b.rho * th_b.c))
    # the rotor's net share, spread over the swept ring: its mean flux density
    A_swept = np.pi * (g.pad.outer_radius ** 2 - g.pad.inner_radius ** 2)
    q_rotor = stored["rotor"] / work * (2.0 * work / t_stop) / A_swept
    closed = an.stop_peak_temperature(q_rotor, t_stop, th_r.kappa, th_r.rho, th_r.c)
    peak = max(hist, key=lambda h: h["ring_mean_K"])
    half = g.rotor.thickness / 2
    slab_bulk = an.bulk_temperature_rise(stored["rotor"], A_swept * half * th_r.rho, th_r.c)
    return {
        "size_m": size,
        "steps": steps,
        "T_ambient_K": T0,
        "line_pressure_Pa": line_pressure,
        "mu": mu,
        "v0_m_s": v0,
        "mass_kg": mass,
        "torque_Nm": torque,
        "decel_m_s2": decel,
        "t_stop_s": t_stop,
        "omega0_rad_s": omega0,
        "friction_work_J": work,
        "vehicle_face_J": vehicle.stop_energy(v0, 0.0, decel)["face_J"],
        "stored_J": stored,
        "mc_J_K": mc,
        "mc_geometry_J_K": float(mc_geometry),
        "mean_rise_K": sum(stored.values()) / sum(mc.values()),
        "bulk_rise_K": an.bulk_temperature_rise(work, 1.0, sum(mc.values())),
        "bulk_rise_geometry_K": an.bulk_temperature_rise(work, 1.0, mc_geometry),
        "rotor_share": stored["rotor"] / work,
        "rotor_flux0_W_m2": q_rotor,
        "rotor_bulk_rise_K": stored["rotor"] / mc["rotor"],
        "swept_slab_bulk_rise_K": slab_bulk,
        "closed_form_peak_rise_K": closed,
        "ring_mean_peak_rise_K": peak["ring_mean_K"] - T0,
        "ring_mean_peak_time_s": peak["t_s"],
        "face_max_rise_K": max(h["face_max_K"] for h in hist) - T0,
        "history": hist,
    }


def main(cells: int = 10, steps: int = 32, after: float = 0.5,
         space_levels=(10, 20, 40, 80, 160), space_steps: int = 4096,
         time_levels=(8, 16, 32, 64, 128, 256), time_cells: int = 640,
         brake_sizes=(12e-3, 6e-3), brake_steps: int = 16,
         out: str | Path | None = "docs/figures", figures: bool = True) -> dict:
    """Run the column (both materials), its convergence and the brake's stop; write
    ``stop_temperature.json`` (and ``.png`` with ``figures``) into ``out`` (None:
    nothing written).  Returns the results."""
    res = {"settings": {"t_stop_s": T_STOP, "T_ambient_K": T_AMB, "depth_diffusion_lengths":
                        DEPTH, "cell_ratio": RATIO, "cells": cells, "steps": steps,
                        "after": after, "flux_W_m2": FLUX},
           "column": {m: run_column(m, cells, steps, after=after, history=True) for m in FLUX},
           "space": convergence("space", space_levels, space_steps),
           "time": convergence("time", time_levels, time_cells),
           "brake": [brake_stop(size, brake_steps) for size in brake_sizes]}
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "stop_temperature.json").write_text(json.dumps(res, indent=1) + "\n")
        if figures:
            stop_figure(res, out / "stop_temperature.png")
    return res


def _report(res: dict) -> None:
    for name, run in res["column"].items():
        print(f"column {name}: h/delta {run['h_over_delta']:.3f}, dt {run['dt_s']:g} s, "
              f"error peak {run['errors']['peak']:.2e}, end {run['errors']['end']:.2e}")
    for key in ("space", "time"):
        s = res[key]
        print(f"{key}: levels {s['levels']}, rate peak {s['rate_peak']:.2f}, end "
              f"{s['rate_end']:.2f}")
        for h, p, e in zip(s["h"], s["peak"], s["end"]):
            print(f"  {h:10.4g}  peak {p:.2e}  end {e:.2e}")
    for b in res["brake"]:
        print(f"brake {1e3 * b['size_m']:g} mm: t_s {b['t_stop_s']:.3f} s, work "
              f"{b['friction_work_J']:.1f} J (vehicle {b['vehicle_face_J']:.1f}), mean rise "
              f"{b['mean_rise_K']:.4f} K = E/sum(mc) {b['bulk_rise_K']:.4f} K; rotor ring peak "
              f"{b['ring_mean_peak_rise_K']:.1f} K vs closed form "
              f"{b['closed_form_peak_rise_K']:.1f} K, face max {b['face_max_rise_K']:.1f} K")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--no-figures", action="store_true")
    a = ap.parse_args()
    _report(main(out=a.out, figures=not a.no_figures))
