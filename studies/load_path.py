"""The caliper's load path: how much of the rotor the pads touch, idealised against real.

Static contact of two brakes under line pressures from light to firm, with and
without friction: ``idealised`` (``geometry/default.toml``, the half model),
``floating`` (``geometry/floating.toml``: both pads, the whole rotor on its hat,
the piston's rim, the fingers, the abutments) and ``floating_hot`` (the ring
100 K warmer than the hat: it cones, and the faces no longer conform; with
conforming faces the problem is proportional and coverage does not change with
the line pressure).

For each case, pressure and friction coefficient: per friction face the
coverage, the centre of pressure, the largest pressure over the nominal one,
each pad's and (full model) the caliper's balance
(:func:`brakewear.static.pad_balance`, :func:`brakewear.static.caliper_balance`);
the half model against the full one where its assumption holds (a fixed
caliper) and where it does not (the fingers); the coverage of each face with
the ring ``dT`` warmer than the hat (:func:`hat_coverage`); the coverage at
0.5 MPa under mesh refinement with its Richardson estimate
(:func:`coverage_convergence`).  docs/load_path.md tells what each shows.

Run ``python studies/load_path.py [--out DIR] [--pressures 0.25 0.5 1 2 4] [--mu 0 0.4]
[--pad-size MM] [--levels 1 1.5 2]``: ``DIR/data/load_path.json`` and the maps
``DIR/figures/load_path_mu*.png``; ``--caliper-only``: no contact, the caliper's
balance of every full-model case (:func:`caliper_main`), ``load_path_caliper.json``.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from brakewear.geometry import CaliperGeometry, load_geometry
from brakewear.mesh.convergence import richardson
from brakewear.model import BrakeModel
from brakewear.static import caliper_balance, pad_balance, solve_contact, static_summary
from brakewear.thermal.strain import heated_subdomain_load

sys.path.insert(0, str(Path(__file__).resolve().parent))
from pressure_maps import draw_maps  # noqa: E402  (a sibling script, not a package)

PRESSURES_MPA = (0.25, 0.5, 1.0, 2.0, 4.0)
MUS = (0.0, 0.4)
#: the default scene's mesh keys (m): pad 1.5 mm, 4 + 8 layers, rotor 4.5 mm, 3 layers
MESH = {"size": 1.5e-3, "pad_size": 1.5e-3, "rotor_size": 4.5e-3, "friction_layers": 4,
        "backplate_layers": 8, "rotor_layers": 3}


def meshed(geom, mesh: dict):
    """``geom`` with the mesh keys ``mesh`` (m)."""
    return replace(geom, mesh=replace(geom.mesh, **mesh))


#: the friction ring's temperature above the hat's in the ``floating_hot`` case (K)
HOT_RING_K = 100.0


def cases(mesh: dict) -> dict:
    """name -> (geometry, layout, ring temperature rise K) of every model solved."""
    ideal = meshed(load_geometry("default"), mesh)
    flt = meshed(load_geometry("floating"), mesh)
    ring = replace(flt, rotor=replace(flt.rotor, mount="ring_clamp", hat=None))
    fixed = replace(ring, caliper=CaliperGeometry("fixed"))
    return {"idealised": (ideal, "half", 0.0), "floating": (flt, "full", 0.0),
            "floating_hot": (flt, "full", HOT_RING_K),
            "fingers_full": (ring, "full", 0.0), "fingers_half": (ring, "half", 0.0),
            "fixed_full": (fixed, "full", 0.0), "fixed_half": (fixed, "half", 0.0)}


def face_numbers(model, res, line_pressure: float) -> dict:
    """Coverage, centre of pressure, peak over nominal pressure per face."""
    g = model.geometry
    s = static_summary(model, res)
    nominal = line_pressure * g.clamp_area / g.pad.area
    out = {}
    for face, f in s["faces"].items():
        th = f["centre_of_pressure_theta_deg"] - math.degrees(g.pad.center_angle)
        out[face] = {"coverage": f["coverage"], "cop_r_mm": f["centre_of_pressure_r_m"] * 1e3,
                     "cop_theta_deg": th, "peak_over_nominal": f["pressure_max_Pa"] / nominal,
                     "normal_force_N": f["normal_force_N"]}
    return out


def pressure_field(model, res) -> dict:
    """Nodal pressure on each friction face with its (x, y) and the face's facets
    (for the maps)."""
    pad = model.meshes["pad"]
    faces = {"in": "friction_in", "out": "friction_out"} if model.full else {"in": "friction"}
    p = np.zeros(pad.p.shape[1])
    p[res.interface_nodes] = res.interface_pressure
    return {k: {"facets": pad.facets[:, pad.boundaries[f]], "p": p, "xy": pad.p[:2]}
            for k, f in faces.items()}


def solve_case(geom, layout: str, pressures, mus, dT: float = 0.0,
               fields: bool = False) -> dict:
    """Contact at every pressure and mu (the ring ``dT`` warmer than the hat);
    the model is built once."""
    t0 = time.perf_counter()
    model = BrakeModel(geom, layout=layout)
    load = None if dT == 0.0 else heated_subdomain_load(model, "rotor", "ring", dT)
    rows, maps = [], {}
    for mu in mus:
        for p_mpa in pressures:
            p = p_mpa * 1e6
            # a thermal load is large against the clamp force: a tighter solve keeps
            # each pad's balance, relative to the clamp force, below 1e-8
            res = solve_contact(model, p, mu=mu, tol=1e-10 if load is None else 1e-12,
                                      load=load)
            bal = pad_balance(model, res, p)
            rows.append({"line_pressure_MPa": p_mpa, "mu": mu,
                         "faces": face_numbers(model, res, p),
                         "balance": {k: max(v["force"], v["moment"]) for k, v in bal.items()
                                     if k != "caliper"},
                         "caliper": bal.get("caliper")})
            if fields:
                maps[(mu, p_mpa)] = pressure_field(model, res)
    return {"layout": model.layout, "dofs": int(model.dofs), "rows": rows,
            "wall_s": time.perf_counter() - t0, "maps": maps}


def caliper_rows(geom, pressures) -> list:
    """The caliper's balance (:func:`brakewear.static.caliper_balance`) of the
    full model of ``geom`` at every pressure (MPa): the clamp loads alone
    decide it, so no contact is solved and it is cheap on any mesh."""
    model = BrakeModel(geom, layout="full")
    return [{"line_pressure_MPa": p, **caliper_balance(model, p * 1e6)} for p in pressures]


def half_differences(full: dict, half: dict) -> list:
    """Relative differences of the full model's faces from the half model's one."""
    out = []
    for rf, rh in zip(full["rows"], half["rows"]):
        h = rh["faces"]["in"]
        d = {"line_pressure_MPa": rf["line_pressure_MPa"], "mu": rf["mu"]}
        for face, f in rf["faces"].items():
            d[face] = {k: abs(f[k] - h[k]) / abs(h[k]) for k in
                       ("coverage", "cop_r_mm", "peak_over_nominal")}
        out.append(d)
    return out


#: the cases drawn in the pressure maps, and their rows (case, face, label)
MAPPED = ("idealised", "floating", "floating_hot")
MAP_ROWS = (("idealised", "in", "idealised (half model)"),
            ("floating", "in", "floating: inboard (piston rim)"),
            ("floating", "out", "floating: outboard (fingers)"),
            ("floating_hot", "in", f"floating, ring +{HOT_RING_K:g} K: inboard"),
            ("floating_hot", "out", f"floating, ring +{HOT_RING_K:g} K: outboard"))


def hat_coverage(geom, dTs=(0.0, 100.0, 200.0), line_pressure: float = 1e6,
                 mu: float = 0.4) -> list:
    """Coverage and centre of pressure of both faces with the friction ring
    ``dT`` (K) warmer than the hat (the ring's elements heated uniformly)."""
    model = BrakeModel(geom, layout="full")
    rows = []
    for dT in dTs:
        load = None if dT == 0.0 else heated_subdomain_load(model, "rotor", "ring", dT)
        res = solve_contact(model, line_pressure, mu=mu, tol=1e-12, load=load)
        rows.append({"dT_K": dT, "faces": face_numbers(model, res, line_pressure)})
    return rows


#: refinement levels of the coverage study: pad size 6 mm / n, n lining and
#: 2 n backplate layers, rotor 12 mm / n with n layers per half
def level_mesh(n: float) -> dict:
    """The mesh keys (m) of refinement level ``n``."""
    return {"size": 6e-3 / n, "pad_size": 6e-3 / n, "rotor_size": 12e-3 / n,
            "friction_layers": max(1, round(2 * n)), "backplate_layers": max(1, round(2 * n)),
            "rotor_layers": max(1, round(n))}


def coverage_convergence(levels=(1.0, 1.5, 2.0), line_pressure: float = 0.5e6,
                         mus=MUS) -> dict:
    """Coverage of both faces of the floating brake at ``line_pressure`` on
    meshes refined by the levels (element sizes ``1 / level`` relative): per
    face and mu the values, the observed rate and the Richardson estimate of
    the three finest (:func:`brakewear.mesh.convergence.richardson`)."""
    geom = load_geometry("floating")
    runs = []
    for n in levels:
        r = solve_case(meshed(geom, level_mesh(n)), "full", [line_pressure / 1e6], mus)
        runs.append({"level": n, "dofs": r["dofs"], "wall_s": r["wall_s"], "rows": r["rows"]})
        print(f"level {n:g}: {r['dofs']} DOFs, {r['wall_s']:.1f} s")
    return analyse_coverage({"levels": list(levels), "runs": runs})


def analyse_coverage(cc: dict) -> dict:
    """Rates and estimates of a :func:`coverage_convergence` record (coverage and
    centre-of-pressure radius of each face and mu)."""
    lv = cc["levels"]
    ratios = [b / a for a, b in zip(lv[:-1], lv[1:])]
    cc["estimate"] = {}
    for k, mu in enumerate(r["mu"] for r in cc["runs"][0]["rows"]):
        for face in ("in", "out"):
            for q in ("coverage", "cop_r_mm"):
                vals = [run["rows"][k]["faces"][face][q] for run in cc["runs"]]
                cc["estimate"][f"{q}_mu{mu:g}_{face}"] = {"values": vals,
                                                          **richardson(vals, ratios)}
    return cc


def main(pressures=PRESSURES_MPA, mus=MUS, mesh: dict | None = None, out: Path | None = None,
         figures: bool = True, levels=(1.0, 1.5, 2.0), dTs=(0.0, 100.0, 200.0)) -> dict:
    """Solve every case; returns the numbers (and writes them under ``out``)."""
    mesh = dict(MESH if mesh is None else mesh)
    runs = {}
    for name, (geom, layout, dT) in cases(mesh).items():
        runs[name] = solve_case(geom, layout, pressures, mus, dT,
                                fields=figures and name in MAPPED)
        runs[name]["geometry"] = geom
        print(f"{name}: {runs[name]['layout']}, {runs[name]['dofs']} DOFs, "
              f"{runs[name]['wall_s']:.1f} s")
    result = {"mesh_m": mesh, "pressures_MPa": list(pressures), "mu": list(mus),
              "cases": {k: {kk: v[kk] for kk in ("layout", "dofs", "rows", "wall_s")}
                        for k, v in runs.items()},
              "half_where_it_holds": half_differences(runs["fixed_full"], runs["fixed_half"]),
              "half_where_it_does_not": half_differences(runs["fingers_full"],
                                                         runs["fingers_half"]),
              "hat_coverage": hat_coverage(runs["floating"]["geometry"], dTs),
              "coverage_convergence": coverage_convergence(levels) if levels else None}
    if out is not None:
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "load_path.json").write_text(json.dumps(result, indent=1))
        if figures:
            for mu in mus:
                draw_maps(runs, MAP_ROWS, mu, pressures,
                          out / "figures" / f"load_path_mu{mu:g}.png")
    print_table(result)
    return result


def print_table(result: dict) -> None:
    """The table of docs/geometry.md, "The load path"."""
    print("| case | face | p (MPa) | mu | coverage | CoP r (mm) | CoP theta (deg) | "
          "p max / p nom | balance | caliper |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in MAPPED:
        for r in result["cases"][name]["rows"]:
            cal = "" if r["caliper"] is None else f"{r['caliper']['force']:.1e}"
            for face, f in r["faces"].items():
                print(f"| {name} | {face} | {r['line_pressure_MPa']:g} | {r['mu']:g} | "
                      f"{100 * f['coverage']:.1f} % | {f['cop_r_mm']:.2f} | "
                      f"{f['cop_theta_deg']:+.2f} | {f['peak_over_nominal']:.2f} | "
                      f"{r['balance'][face]:.1e} | {cal} |")
    for key in ("half_where_it_holds", "half_where_it_does_not"):
        worst = max(max(d[f][q] for f in ("in", "out") for q in d[f]) for d in result[key])
        print(f"{key}: largest relative difference {100 * worst:.2f} %")
    for key, e in ((result.get("coverage_convergence") or {}).get("estimate") or {}).items():
        est = "not asymptotic" if e["estimate"] is None else \
            f"rate {e['rate']:.2f}, estimate {e['estimate']:.4g}"
        print(f"{key}: {' '.join(f'{v:.4g}' for v in e['values'])}; {est}")


def caliper_main(pressures=PRESSURES_MPA, mesh: dict | None = None,
                 out: Path | None = None) -> dict:
    """The caliper's balance of every full-model case at every pressure (no
    contact solves; :func:`caliper_rows`); writes ``out/data/load_path_caliper.json``."""
    mesh = dict(MESH if mesh is None else mesh)
    result = {"mesh_m": mesh, "pressures_MPa": list(pressures),
              "cases": {name: caliper_rows(geom, pressures)
                        for name, (geom, layout, _) in cases(mesh).items()
                        if layout == "full" and name != "floating_hot"}}
    for name, rows in result["cases"].items():
        for r in rows:
            print(f"{name} {r['line_pressure_MPa']:g} MPa: inboard {r['inboard_force_N']:.6g} N, "
                  f"outboard {r['outboard_force_N']:.6g} N, residual {r['force']:.1e}, "
                  f"pin moment {', '.join(f'{m:+.4g}' for m in r['pin_moment_Nm'])} N m")
    if out is not None:
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "load_path_caliper.json").write_text(json.dumps(result, indent=1))
    return result


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", type=Path, default=Path("docs"))
    ap.add_argument("--pressures", type=float, nargs="+", default=list(PRESSURES_MPA))
    ap.add_argument("--mu", type=float, nargs="+", default=list(MUS))
    ap.add_argument("--pad-size", type=float, default=None, help="pad element size (mm)")
    ap.add_argument("--levels", type=float, nargs="*", default=[1.0, 1.5, 2.0],
                    help="refinement levels of the coverage study (none: skip it)")
    ap.add_argument("--caliper-only", action="store_true",
                    help="only the caliper's balance (no contact solves): "
                         "DIR/data/load_path_caliper.json")
    a = ap.parse_args()
    mesh = dict(MESH)
    if a.pad_size:
        mesh.update(size=a.pad_size * 1e-3, pad_size=a.pad_size * 1e-3)
    if a.caliper_only:
        caliper_main(a.pressures, mesh, a.out)
    else:
        main(a.pressures, a.mu, mesh, a.out, levels=tuple(a.levels))
