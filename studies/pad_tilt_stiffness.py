"""The pad's tilt stiffness as the caliper presents it: moment against tilt, inboard and outboard.

The floating caliper of ``geometry/floating.toml`` as it holds its pads
(``BrakeModel(piston="rigid")``: the rigid piston in its bore and seal, the
rim, the fingers and the abutments one-sided with friction; the full model on
the hat rotor) under a line pressure, with a coning ``c`` of the rotor: the
gap opens linearly across the band, at the outer radius on the inboard face
and at the inner radius on the outboard one (``c < 0`` the other way), so
each pad must tilt about a tangential axis to follow its face, and the
caliper resists.  Per pad and coning:

* the pad's tilt (mrad): the slope across the radius of a plane fitted to the
  displacement of its backplate's back face, positive where the pad's outer
  edge moves away from its rotor face's unconed plane (a pad that follows a
  coning ``c`` over the band's width ``w`` tilts by ``-c / w``);
* the caliper's moment on the pad (N m) about the tangential axis through
  the pad's mean radius on its friction face, in the sense of a positive
  tilt: every force the caliper puts on the pad (rim or fingers, abutments
  with their friction, rails and clip).

The slope of the moment against the tilt, negated (the caliper's moment falls
as the pad tilts: it resists), is the caliper's tilt stiffness for that pad
(kN m/rad), printed against the lining's own (``E_t / h`` times the
second moment of the face's area about that axis) and the seal's (the bonded
ring's closed form).  Over the load-path parameters' plausible ranges
(:data:`brakewear.geometry.sections.LOAD_PATH_KEYS`), one at a time at each
end of its range.

Run ``python studies/pad_tilt_stiffness.py [--out docs] [--size MM] [--pressure MPA]
[--mu 0.4] [--coning -60 -30 0 30 60]``; writes ``data/pad_tilt_stiffness.json``,
``data/pad_tilt_stiffness.csv`` and ``figures/pad_tilt_stiffness.png``.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import time
from pathlib import Path

import numpy as np

from brakewear import BrakeModel, CaliperInterface
from brakewear.cleaning.corrosion import nonconformity_gap
from brakewear.geometry import geometry_file, geometry_from_dict
from brakewear.geometry.sections import LOAD_PATH_KEYS
from brakewear.mesh.surface import face_nodes

CONING_UM = (-60.0, -30.0, -15.0, 0.0, 15.0, 30.0, 60.0)
#: the parameters varied (the keys of LOAD_PATH_KEYS); each at the ends of its plausible range
PARAMETERS = ("piston.seal_modulus", "piston.bore_clearance", "piston.engagement_length",
              "piston.stand_out", "piston.rim_friction", "piston.bore_friction",
              "support.abutment_friction", "support.spring_stiffness", "caliper.bridge_tilt",
              "caliper.bore_tilt", "caliper.finger_stiffness")


def parameter_range(key: str, units: dict) -> tuple[float, float]:
    """The plausible range of a load-path key in the geometry file's units."""
    _, unit, si, _, (lo, hi), _ = LOAD_PATH_KEYS[key]
    if unit == "length":
        si = {"mm": 1e-3, "m": 1.0}[units["length"]]
    elif unit == "stiffness":
        si = {"N/m": 1.0, "N/mm": 1e3, "kN/mm": 1e6}[units["stiffness"]]
    return lo / si, hi / si


def floating(overrides: dict | None = None):
    """The floating caliper's geometry (``geometry/floating.toml``) with some keys set
    (``"section.key"`` -> value in the file's units) and the file's units."""
    import tomllib

    d = tomllib.loads(geometry_file("floating").read_text())
    for key, value in (overrides or {}).items():
        sec, field = key.split(".")
        d.setdefault(sec, {})[field] = value
    return geometry_from_dict(d, source=f"floating.toml with {overrides or {}}"), d["units"]


def pad_tilt_and_moment(model, itf, gap, line_pressure: float, mu: float) -> dict:
    """Per pad: its tilt (rad, outer edge off its face positive) and the caliper's
    moment on it (N m, in the tilt's sense) of one solve with the gap ``gap``."""
    from brakewear.caliper.static import solve_caliper

    res = solve_caliper(model, line_pressure, mu, interface=itf, offset=gap)
    g = model.geometry
    pad = model.meshes["pad"]
    a0 = g.pad.center_angle
    e = np.array([math.cos(a0), math.sin(a0), 0.0])
    t = np.array([-math.sin(a0), math.cos(a0), 0.0])
    u = res["u"]["pad"].reshape(-1, 3)
    F = res["support_force"].reshape(-1, 3)
    r_m = 0.5 * (g.pad.inner_radius + g.pad.outer_radius)
    out = {}
    for side, sigma, z0 in (("in", 1.0, 0.0), ("out", -1.0, -g.rotor.thickness)):
        back = face_nodes(pad, f"back_{side}")
        s = pad.p[:, back].T @ e
        A = np.c_[np.ones(back.size), s, pad.p[:, back].T @ t]
        slope = np.linalg.lstsq(A, u[back, 2], rcond=None)[0][1]
        mask = (pad.p[2] > -0.5 * g.rotor.thickness) == (side == "in")
        x0 = r_m * e + z0 * np.array([0.0, 0.0, 1.0])
        m_t = np.cross(pad.p[:, mask].T - x0, F[mask]).sum(axis=0) @ t
        out[side] = {"tilt": float(sigma * slope), "moment": float(-sigma * m_t)}
    return out


def sweep(itf, coning_um, line_pressure: float, mu: float) -> dict:
    """Tilt and moment of each pad at each coning."""
    model = itf.model
    g = model.geometry
    rows = {"in": [], "out": []}
    for c in coning_um:
        gap = nonconformity_gap(itf.x, g.pad.inner_radius, g.pad.outer_radius,
                                g.rotor.thickness, c * 1e-6)
        tm = pad_tilt_and_moment(model, itf, gap, line_pressure, mu)
        for side in rows:
            # each face's own coning: the outboard face opens the other way
            rows[side].append({"coning_um": c, "face_coning_um": c if side == "in" else -c,
                               "tilt_mrad": 1e3 * tm[side]["tilt"],
                               "moment_Nm": tm[side]["moment"]})
    width = g.pad.outer_radius - g.pad.inner_radius
    for side, r in rows.items():
        x = np.array([v["tilt_mrad"] for v in r]) * 1e-3
        y = np.array([v["moment_Nm"] for v in r])
        c = np.array([v["face_coning_um"] for v in r]) * 1e-6
        # the caliper resists: its moment falls as the tilt grows
        k = -float(np.polyfit(x, y, 1)[0]) if np.ptp(x) > 0 else float("nan")
        # how much of its face's coning the pad follows by tilting (1: all of it)
        follows = -float(np.polyfit(c / width, x, 1)[0]) if np.ptp(c) > 0 else float("nan")
        rows[side] = {"points": r, "stiffness_kNm_per_rad": k / 1e3, "follows": follows,
                      "moment_range_Nm": float(np.ptp(y))}
    return rows


def lining_tilt_stiffness(g) -> float:
    """``E_t / h`` times the second moment of the friction face about the tangential axis
    through its mean radius (N m/rad): the lining's own tilt stiffness, a Winkler estimate."""
    p = g.pad
    ri, ro, th = p.inner_radius, p.outer_radius, p.arc_angle
    r_m = 0.5 * (ri + ro)
    rr = np.linspace(ri, ro, 2001)
    w = th * rr          # the sector's width at r (arc), integrated over r
    integrand = w * (rr - r_m) ** 2
    I = float(np.sum(0.5 * (integrand[1:] + integrand[:-1]) * np.diff(rr)))
    return p.friction_material.elastic.E_t / p.friction_thickness * I


def main(size: float = 6.0, pressure: float = 1.0, mu: float = 0.4,
         coning: tuple = CONING_UM, parameters: tuple = PARAMETERS, out=None) -> dict:
    """Moment against tilt of both pads, nominal and at each end of each parameter's range."""
    from brakewear.caliper.parts import seal_springs

    t0 = time.perf_counter()
    p = pressure * 1e6
    g, units = floating()
    model = BrakeModel(g, size=size * 1e-3, piston="rigid")
    base = CaliperInterface(model, p, mu)
    seal = seal_springs(g.piston.guide, 0.5 * g.piston.diameter)
    cases = {"nominal": {"overrides": {}, **sweep(base, coning, p, mu)}}
    for key in parameters:
        for end, value in zip(("low", "high"), parameter_range(key, units)):
            gk, _ = floating({key: value})
            itf = base.with_load_path(gk)
            cases[f"{key} {end}"] = {"overrides": {key: value}, **sweep(itf, coning, p, mu)}
    result = {"settings": {"size_mm": size, "pressure_MPa": pressure, "mu": mu,
                           "coning_um": list(coning)},
              "lining_tilt_stiffness_kNm_per_rad": lining_tilt_stiffness(g) / 1e3,
              "seal_tilt_stiffness_kNm_per_rad": seal["tilt"] / 1e3,
              "coning_tilt_mrad_30um": 30e-3 / (g.pad.outer_radius - g.pad.inner_radius),
              "cases": cases, "wall_s": time.perf_counter() - t0}
    if out is not None:
        write(result, Path(out))
    return result


def write(result: dict, out: Path) -> None:
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    (out / "data" / "pad_tilt_stiffness.json").write_text(json.dumps(result, indent=1))
    with open(out / "data" / "pad_tilt_stiffness.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "pad", "face_coning_um", "tilt_mrad", "moment_Nm",
                    "stiffness_kNm_per_rad", "follows"])
        for name, c in result["cases"].items():
            for side in ("in", "out"):
                for v in c[side]["points"]:
                    w.writerow([name, side, v["face_coning_um"], f"{v['tilt_mrad']:.6g}",
                                f"{v['moment_Nm']:.6g}", f"{c[side]['stiffness_kNm_per_rad']:.6g}",
                                f"{c[side]['follows']:.6g}"])
    plot(result, out / "figures" / "pad_tilt_stiffness.png")


def plot(result: dict, path: Path) -> None:
    """Moment against tilt for each pad: the nominal caliper bold, every parameter's
    ends thin (labelled where they leave the nominal curve by more than 10 %)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for ax, side, title in zip(axes, ("in", "out"), ("inboard pad (piston)",
                                                     "outboard pad (fingers)")):
        nom = result["cases"]["nominal"][side]
        k0 = nom["stiffness_kNm_per_rad"]
        for name, c in result["cases"].items():
            pts = c[side]["points"]
            x = [v["tilt_mrad"] for v in pts]
            y = [v["moment_Nm"] for v in pts]
            k = c[side]["stiffness_kNm_per_rad"]
            if name == "nominal":
                ax.plot(x, y, "k-o", lw=2.5, ms=4, zorder=5, label=f"nominal: {k:.3g} kN m/rad")
            elif abs(k - k0) > 0.1 * max(abs(k0), 1e-3):
                ax.plot(x, y, "-", lw=1, marker=".", label=f"{name}: {k:.3g}")
            else:
                ax.plot(x, y, "-", lw=0.6, color="0.7")
        ax.set_xlabel("pad tilt (mrad; > 0: outer edge away from the unconed face)")
        ax.set_ylabel("caliper's moment on the pad (N m, in the tilt's sense)")
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    s = result["settings"]
    fig.suptitle(f"floating caliper, {s['pressure_MPa']:g} MPa, mu {s['mu']:g}, coning "
                 f"{min(s['coning_um']):g}..{max(s['coning_um']):g} um; lining's own tilt "
                 f"stiffness {result['lining_tilt_stiffness_kNm_per_rad']:.0f} kN m/rad, seal's "
                 f"{result['seal_tilt_stiffness_kNm_per_rad']:.2f}; grey: within 10 % of nominal",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--size", type=float, default=6.0, help="mesh size (mm)")
    ap.add_argument("--pressure", type=float, default=1.0, help="line pressure (MPa)")
    ap.add_argument("--mu", type=float, default=0.4)
    ap.add_argument("--coning", type=float, nargs="+", default=list(CONING_UM), help="um")
    a = ap.parse_args(argv)
    res = main(a.size, a.pressure, a.mu, tuple(a.coning), out=a.out)
    for name, c in res["cases"].items():
        print(f"{name:34s} in {c['in']['stiffness_kNm_per_rad']:9.3g}  out "
              f"{c['out']['stiffness_kNm_per_rad']:9.3g} kN m/rad; follows in "
              f"{c['in']['follows']:.3f} out {c['out']['follows']:.3f}")
    print(f"lining {res['lining_tilt_stiffness_kNm_per_rad']:.0f} kN m/rad, seal "
          f"{res['seal_tilt_stiffness_kNm_per_rad']:.3f} kN m/rad; {res['wall_s']:.0f} s")
    return res


if __name__ == "__main__":
    _cli()
