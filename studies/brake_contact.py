"""Pad-rotor contact pressure of the default brake, without and with friction.

The pad is pressed on the rotor by the line pressure (traction over the
piston footprint); the rotor turns in +theta, so friction drags the pad
toward its trailing end, where the abutment holds it.  Friction tilts the
pad and moves the centre of pressure toward the leading edge (the end where
rotor material enters under the pad, the smaller angle here).

Run ``python studies/brake_contact.py [--out DIR] [--pressure MPa] [--mu MU]``:
prints the numbers and writes ``brake_contact.json`` and two PNG pressure
maps (seen from the rotor, same colour scale).
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from brakewear.model import BrakeModel
from brakewear.static import solve_contact


def centre_of_pressure(model: BrakeModel, res) -> tuple[float, float]:
    """(radius m, angle deg) of the normal-force centroid on the pad face."""
    x = model.meshes["pad"].p[:, res.interface_nodes]
    fz = res.interface_force[2]
    r = float((fz * np.hypot(x[0], x[1])).sum() / fz.sum())
    th = float(np.degrees((fz * np.arctan2(x[1], x[0])).sum() / fz.sum()))
    return r, th


def main(line_pressure_mpa: float = 1.0, mu: float = 0.4, size_mm: float | None = None,
         rotor: str = "elastic", out: str | Path | None = None, figures: bool = True) -> dict:
    model = BrakeModel("default", rotor=rotor,
                       size=None if size_mm is None else size_mm * 1e-3)
    g = model.geometry
    runs = {}
    for label, m in (("frictionless", 0.0), ("friction", mu)):
        res = solve_contact(model, line_pressure_mpa * 1e6, mu=m)
        r, th = centre_of_pressure(model, res)
        runs[label] = {
            "mu": m, "res": res, "cop_r_m": r, "cop_theta_deg": th,
            "contact_fraction": float(res.active.mean()),
            "p_max_Pa": float(res.interface_pressure.max()),
            "normal_force_N": float(res.normal_force),
            "friction_force_N": float(np.linalg.norm(res.interface_force[:2], axis=0).sum()
                                      if m > 0 else 0.0),
            "active_set_iterations": res.info["active_set_iterations"],
            "linear_iterations": res.info["linear_iterations"], "time_s": res.info["total_s"],
        }
    shift_deg = runs["friction"]["cop_theta_deg"] - runs["frictionless"]["cop_theta_deg"]
    r_mean = runs["friction"]["cop_r_m"]
    leading = np.degrees(g.pad.leading_angle)
    result = {
        "line_pressure_MPa": line_pressure_mpa, "mu": mu, "rotor": rotor,
        "dofs": int(model.dofs), "clamp_force_N": runs["frictionless"]["res"].clamp_force,
        "leading_edge_deg": float(leading),
        "cop_shift_deg": float(shift_deg),
        "cop_shift_mm": float(np.radians(shift_deg) * r_mean * 1e3),
        "cop_shift_toward_leading_edge": bool(np.sign(shift_deg) == np.sign(leading - np.degrees(
            g.pad.center_angle))),
        **{f"{k}_{key}": v for k, run in runs.items() for key, v in run.items() if key != "res"},
    }
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        with open(out / "brake_contact.json", "w") as fh:
            json.dump(
                result, fh, indent=2, default=lambda o: o.item() if hasattr(o, "item") else str(o)
            )
        if figures:
            from brakewear.output.figures import plot_field
            pad = model.meshes["pad"]
            vmax = max(run["p_max_Pa"] for run in runs.values()) / 1e6
            for label, run in runs.items():
                p = np.zeros(pad.nvertices)
                p[run["res"].interface_nodes] = run["res"].interface_pressure / 1e6
                plot_field(pad, p, out / f"brake_contact_{label}.png",
                           f"Pad contact pressure, {label} (mu = {run['mu']:g}), "
                           f"{line_pressure_mpa:g} MPa line; rotor turns toward +y",
                           label="pressure (MPa)", cmap="inferno", clim=(0.0, vmax),
                           facets="friction", view=(0.0, 0.0, -1.0))
    return result


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--pressure", type=float, default=1.0, help="line pressure, MPa")
    ap.add_argument("--mu", type=float, default=0.4)
    ap.add_argument("--rotor", choices=("elastic", "rigid"), default="elastic")
    ap.add_argument("--size", type=float, default=None, help="mesh size at the interface, mm")
    a = ap.parse_args()
    res = main(a.pressure, a.mu, a.size, a.rotor, a.out)
    for k, v in res.items():
        print(f"{k:40s} {v}")
