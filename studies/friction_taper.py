"""Friction tilts the pad: the leading/trailing taper of the worn pad (docs/wear.md).

The default scene (``geometry/scenes/default.toml``: the default brake, 1 MPa
line pressure, 55 rad/s, one hour of drag, both surfaces wearing, elastic
rotor, its 6 mm mesh and its numerics) is run once per friction coefficient,
everything else the same.  Sliding friction drags the friction face (z = 0)
along the rotor's motion; the abutment holds the pad at its backplate, higher
up.  The couple of the two tips the pad toward the end where rotor material
enters under it (the leading end), which then carries more pressure and wears
more: the worn pad is tapered from leading to trailing.

The numbers, for each mu: ``taper`` (leading minus trailing band wear over the
mean; a band is the outer ``band`` of the arc at each end) and the difference in
um; ``slope_um_per_deg`` (area-weighted slope of the wear against the angle
along the rotor's motion; < 0: the leading end worn more); the centre of
pressure at first contact and worn (``cop_*``, from the pad's centre line along
the motion); the abutment reaction's lever above the friction face
(:func:`brakewear.interfaces.fe_lever_arm`) and the centre-of-pressure shift
statics gives, ``-lever mu <cos theta>``; ``archard_error``, the worn volume
against :func:`brakewear.wear.records.archard_volumes`.

Which end leads follows from the pair's drag direction (the rotor's surface
velocity, ``BrakeModel.contact_pair(...).drag``): in the default brake the
rotor turns in +theta, so the leading end is the one at the smaller angle.

Run ``python studies/friction_taper.py [--out DIR] [--size MM] [--steps N]
[--mu 0 0.4] [--no-figures]``; writes ``friction_taper.json`` and
``friction_taper.png`` into ``DIR`` (default ``docs/figures``).
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from brakewear.interfaces import FEInterface, fe_lever_arm
from brakewear.scene import load_scene
from brakewear.wear import Run, wear_history
from brakewear.wear.records import archard_volumes

sys.path.insert(0, str(Path(__file__).resolve().parent))
from running_in_report import taper_figure  # noqa: E402  (a sibling script, not a package)

BAND = 0.15     # fraction of the arc at each end that makes a band


def rotor_sense(model) -> int:
    """+1 if the rotor's surface moves in +theta under the pad, -1 if in -theta.

    Taken from the contact pair's drag directions (the rotor's velocity at the
    pad's friction nodes), so it follows the model rather than a convention.
    """
    pair = model.contact_pair(1.0)
    x = model.coordinates()[:, pair.slave]
    e_theta = np.vstack([-x[1], x[0]]) / np.hypot(x[0], x[1])
    return 1 if float((pair.drag[:2] * e_theta).sum()) > 0 else -1


def along_motion(itf, sense: int) -> np.ndarray:
    """Angle (deg) of each pad friction node from the pad's centre line, positive
    along the rotor's motion: the leading end is negative, the trailing positive."""
    c = itf.model.geometry.pad.center_angle
    th = np.arctan2(itf.x[1], itf.x[0]) - c
    return sense * np.degrees(np.arctan2(np.sin(th), np.cos(th)))


def profile_numbers(xi: np.ndarray, area: np.ndarray, h: np.ndarray,
                    band: float = BAND) -> dict:
    """Taper, band means and slope of a pad wear field ``h`` (m).

    Parameters
    ----------
    xi
        Angle of each node along the rotor's motion (deg; leading end < 0).
    area
        Nodal areas (m^2): the weights of every mean and of the fit.
    h
        Pad wear per node (m).
    band
        Fraction of the arc at each end over which the band means are taken.

    Returns
    -------
    dict
        ``mean_um``, ``lead_um``, ``trail_um``, ``lead_minus_trail_um``,
        ``taper`` (the difference over the mean) and ``slope_um_per_deg``.
    """
    lo, hi = xi.min(), xi.max()
    tol = 1e-9 * (hi - lo)
    lead = xi <= lo + band * (hi - lo) + tol
    trail = xi >= hi - band * (hi - lo) - tol
    mean = float((h * area).sum() / area.sum())
    hl = float((h * area)[lead].sum() / area[lead].sum())
    ht = float((h * area)[trail].sum() / area[trail].sum())
    slope = np.polyfit(xi, h, 1, w=np.sqrt(area))[0]
    return {"mean_um": mean * 1e6, "lead_um": hl * 1e6, "trail_um": ht * 1e6,
            "lead_minus_trail_um": (hl - ht) * 1e6, "taper": (hl - ht) / mean,
            "slope_um_per_deg": float(slope) * 1e6}


def centre_of_pressure(itf, xi: np.ndarray, p: np.ndarray) -> dict:
    """Circumferential centre of pressure: angle along the rotor's motion (deg),
    the same as an arc length at its radius (mm), and its radius (mm)."""
    f = p * itf.area
    deg = float((f * xi).sum() / f.sum())
    r = float((f * itf.r).sum() / f.sum())
    return {"deg": deg, "mm": np.radians(deg) * r * 1e3, "r_mm": r * 1e3}


def arc_profile(xi: np.ndarray, area: np.ndarray, h: np.ndarray) -> tuple[list, list]:
    """Wear along the arc averaged over radius: one area-weighted mean per column
    of nodes at one angle (the pad mesh is structured in r and theta)."""
    cols, inv = np.unique(np.round(xi, 6), return_inverse=True)
    w = np.bincount(inv, area)
    return cols.tolist(), (np.bincount(inv, h * area) / w).tolist()


def lever_arm(itf, sol) -> float:
    """Height (m) of the abutment reaction's line of action above the friction face,
    for an interface solution (needs friction)."""
    model = itf.model
    u = itf.cs.P @ sol.u
    off, n = model.offsets["pad"], model.meshes["pad"].nvertices
    fe = SimpleNamespace(u={"pad": u[3 * off:3 * (off + n)]}, clamp_force=itf.cs.clamp_force)
    return fe_lever_arm(model, fe)


def run(model, scene, mu: float, numerics, duration: float, sense: int,
        band: float = BAND) -> dict:
    """One running-in of ``scene`` on ``model`` with friction ``mu``: its numbers
    and fields (see the module docstring)."""
    t0 = time.perf_counter()
    itf = FEInterface(model, scene.line_pressure, mu, numerics.tol)
    pad_law, rotor_law = scene.wear_laws()
    xi = along_motion(itf, sense)
    history, rows = [], []
    for s in wear_history(Run(model, scene.line_pressure, scene.omega, duration, pad_law,
                              rotor_law, mu, numerics=numerics, interface=itf)):
        history.append(s)
        prof = profile_numbers(xi, itf.area, s.pad_wear, band)
        rows.append({"time_s": s.time, "mean_um": prof["mean_um"],
                     "lead_minus_trail_um": prof["lead_minus_trail_um"],
                     "cop_deg": centre_of_pressure(itf, xi, s.pressure_end)["deg"]})
    last = history[-1]
    first = history[0]
    rows.insert(0, {"time_s": 0.0, "mean_um": 0.0, "lead_minus_trail_um": 0.0,
                    "cop_deg": centre_of_pressure(itf, xi, first.pressure)["deg"]})
    # the worn state at the end: the contact of the worn surfaces
    end = itf.solve(last.pad_wear + itf.W @ last.rotor_wear, last.active_end)
    pad_arch, rot_arch = archard_volumes(itf, history, pad_law, rotor_law, scene.omega,
                                         numerics.scheme)
    out = {"mu": mu, "steps": last.step,
           "contact_solves": int(sum(s.contact_solves for s in history)),
           **profile_numbers(xi, itf.area, last.pad_wear, band),
           **{f"cop_start_{k}": v for k, v in centre_of_pressure(itf, xi, first.pressure).items()},
           **{f"cop_end_{k}": v for k, v in centre_of_pressure(itf, xi, end.pressure).items()},
           "pad_volume_m3": last.pad_volume, "pad_archard_m3": pad_arch,
           "rotor_volume_m3": last.rotor_volume, "rotor_archard_m3": rot_arch,
           "pad_archard_error": abs(last.pad_volume - pad_arch) / pad_arch,
           "rotor_archard_error": (abs(last.rotor_volume - rot_arch) / rot_arch
                                   if rot_arch > 0 else 0.0),
           "rotor_wear_mean_um": float((last.rotor_wear * itf.rotor_area).sum()
                                       / itf.rotor_area.sum()) * 1e6,
           "history": rows}
    if mu > 0:
        start = itf.solve(np.zeros(itf.area.size), first.active)
        f = first.pressure * itf.area
        cos = float((f * np.cos(np.radians(xi))).sum() / f.sum())
        out["lever_start_mm"] = lever_arm(itf, start) * 1e3
        out["lever_end_mm"] = lever_arm(itf, end) * 1e3
        out["statics_shift_mm"] = -out["lever_start_mm"] * mu * cos
    out["profile_deg"], out["profile_um"] = arc_profile(xi, itf.area, last.pad_wear * 1e6)
    out["run_s"] = time.perf_counter() - t0
    out["_fields"] = {"itf": itf, "xi": xi, "pad_wear": last.pad_wear}
    return out


def main(size: float | None = None, steps: int | None = None,
         mu_values: tuple[float, ...] = (0.0, 0.4), band: float = BAND,
         duration: float | None = None, out: str | Path | None = None,
         figures: bool = True, scene: str = "default") -> dict:
    """Run the scene once per friction coefficient; return the numbers.

    Parameters
    ----------
    size
        Mesh size (mm); None: the scene's (6 mm for the default scene).
    steps
        Equal steps; None: the scene's (60).
    mu_values
        Friction coefficients, one running-in each (same mesh, loads, laws).
    band
        Fraction of the arc at each end over which the taper's means are taken.
    duration
        Drag (s); None: the scene's (one hour).
    out
        Folder for ``friction_taper.json`` and ``friction_taper.png``; None:
        nothing is written.
    figures
        Write the PNG (with ``out``).
    scene
        A packaged scene name or a scene file.

    Returns
    -------
    dict
        ``settings``, ``leading_end`` (which end leads and why), ``runs`` (one
        dict per mu, keyed ``"mu=<value>"``) and, with mu = 0 among the runs,
        the friction's ``cop_shift_start_mm`` and ``cop_shift_end_mm``.
    """
    t0 = time.perf_counter()
    sc = load_scene(scene)
    if size is not None:
        sc = dataclasses.replace(sc, mesh_size=size * 1e-3)
    numerics = sc.numerics if steps is None else dataclasses.replace(sc.numerics, steps=steps)
    duration = sc.duration if duration is None else duration
    model = sc.build_model()
    sense = rotor_sense(model)
    g = model.geometry.pad
    lead = np.degrees(g.center_angle - sense * 0.5 * g.arc_angle)
    runs = {f"mu={mu:g}": run(model, sc, mu, numerics, duration, sense, band)
            for mu in mu_values}
    res = {"settings": {"scene": sc.name, "mesh_size_mm": (sc.mesh_size or
                                                            model.geometry.mesh.size) * 1e3,
                        "dofs": int(model.dofs), "line_pressure_Pa": sc.line_pressure,
                        "omega_rad_s": sc.omega, "duration_s": duration,
                        "steps": steps, "scheme": numerics.scheme, "dp_tol": numerics.dp_tol,
                        "band": band, "mu_values": list(mu_values)},
           "leading_end": {"rotor_sense": sense, "leading_edge_deg": float(lead),
                           "why": "the rotor's surface moves in "
                                  f"{'+' if sense > 0 else '-'}theta under the pad (the pair's "
                                  "drag), so rotor material enters under the pad at "
                                  f"theta = {lead:.1f} deg"},
           "runs": runs}
    if "mu=0" in runs:
        for mu_key, r in runs.items():
            if mu_key != "mu=0":
                r["cop_shift_start_mm"] = r["cop_start_mm"] - runs["mu=0"]["cop_start_mm"]
                r["cop_shift_end_mm"] = r["cop_end_mm"] - runs["mu=0"]["cop_end_mm"]
    res["run_s"] = time.perf_counter() - t0
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        if figures:
            res["figure"] = str(taper_figure(res, out / "friction_taper.png"))
        (out / "friction_taper.json").write_text(json.dumps(_public(res), indent=1))
    return res


def _public(res: dict) -> dict:
    """``res`` without the fields kept for the figure, plus the nodal maps in mm and um."""
    runs = {}
    for k, r in res["runs"].items():
        f = r["_fields"]
        runs[k] = {**{q: v for q, v in r.items() if q != "_fields"},
                   "nodes": {"x_mm": (f["itf"].x[0] * 1e3).round(4).tolist(),
                             "y_mm": (f["itf"].x[1] * 1e3).round(4).tolist(),
                             "pad_wear_um": (f["pad_wear"] * 1e6).round(5).tolist()}}
    return {**res, "runs": runs}


def _cli(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--size", type=float, default=None, help="mesh size, mm (default: the "
                                                              "scene's, 6)")
    ap.add_argument("--steps", type=int, default=None, help="equal steps (default: the "
                                                             "scene's, 60)")
    ap.add_argument("--duration", type=float, default=None, help="drag, s (default: the "
                                                                   "scene's, 3600)")
    ap.add_argument("--mu", type=float, nargs="+", default=[0.0, 0.4])
    ap.add_argument("--band", type=float, default=BAND)
    ap.add_argument("--no-figures", action="store_true")
    a = ap.parse_args(argv)
    res = main(a.size, a.steps, tuple(a.mu), a.band, a.duration, out=a.out,
               figures=not a.no_figures)
    s = res["settings"]
    print(f"{s['scene']} scene, mesh {s['mesh_size_mm']:g} mm ({s['dofs']} DOFs), "
          f"{s['duration_s']:g} s; {res['leading_end']['why']}; bands: outer "
          f"{100 * s['band']:.0f} % of the arc")
    print(f"{'mu':>5} {'steps':>5} {'mean um':>8} {'lead-trail um':>13} {'taper %':>8} "
          f"{'slope um/deg':>12} {'CoP start deg':>13} {'CoP end deg':>11} {'Archard err':>11}")
    for r in res["runs"].values():
        err = max(r["pad_archard_error"], r["rotor_archard_error"])
        print(f"{r['mu']:5g} {r['steps']:5d} {r['mean_um']:8.2f} {r['lead_minus_trail_um']:13.2f} "
              f"{100 * r['taper']:8.2f} {r['slope_um_per_deg']:12.4f} "
              f"{r['cop_start_deg']:13.3f} {r['cop_end_deg']:11.3f} {err:11.1e}")
    print(f"{res['run_s']:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(_cli())
