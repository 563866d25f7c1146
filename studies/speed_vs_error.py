"""Run time against error for the modelling choices a user has.

The same running-in of the default brake (1 MPa line pressure, 55 rad/s,
mu = 0.4, Archard pad k = 5e-15 1/Pa, rotor 5e-16 1/Pa, ``duration`` s), run
with one modelling choice changed at a time, all in one process, against the
*reference*: the Richardson estimate of ``studies/mesh_convergence.py`` at the
same time (``docs/data/mesh_convergence.json``), or, with ``reference=None`` or
a file of another case, the finest mesh of ``sizes``.  The choices: mesh size;
implicit or explicit fixed steps; geometry update against gap offset; rigid
against elastic rotor; FE contact, its condensation and the Winkler foundation
(uncalibrated, or stiffness-calibrated against one FE solve, counted in the
cost); element order on the thick cylinder of ``studies/cylinder_convergence.py``.
Each non-mesh choice is also measured against the *base* model of the same mesh
(``base_size``): its own error, apart from the mesh's.

Errors, each run's fields interpolated at the reference's points
(:func:`brakewear.mesh.convergence.interpolate`): ``pad_wear_l2`` (area-weighted
relative L2 of the pad wear, the headline), ``pressure_l2`` (the same for the
pressure at the end), ``pad_wear_max``, ``pressure_max``, ``r_eff`` (relative
errors of the maxima and of ``sum(p A r) / sum(p A)``), ``rotor_wear_l2``
(relative L2 of the rotor wear profile against r).

Run ``python studies/speed_vs_error.py [--out DIR] [--quick]``; writes
``speed_vs_error.json`` and ``.csv`` (DIR/data) and ``speed_vs_error.png``
(DIR/figures).
"""
from __future__ import annotations

import argparse
import json
import logging
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from brakewear import Numerics
from brakewear.interfaces import (
    CondensedInterface,
    FEInterface,
    FoundationInterface,
    WinklerInterface,
    calibrate,
)
from brakewear.laws.base import WearLaw
from brakewear.mesh.convergence import interpolate, relative_l2
from brakewear.mesh.surface import surface_nodes
from brakewear.model import BrakeModel
from brakewear.static import solve_contact
from brakewear.wear import Run, wear_history

sys.path.insert(0, str(Path(__file__).resolve().parent))
from tradeoff_report import converged_reference, plot, table, write  # noqa: E402

logger = logging.getLogger(__name__)

PAD, ROTOR = WearLaw(5e-15), WearLaw(5e-16)
RUN = {"line_pressure": 1e6, "omega": 55.0, "mu": 0.4}


# ------------------------------------------------------------------ runs --
def run_case(size: float, duration: float, steps: int, scheme: str = "implicit",
             update: str = "gap", rotor: str = "elastic", piston: str = "traction",
             interface: str = "fe", thermal: bool = False, pad_law: WearLaw = PAD,
             rotor_law: WearLaw = ROTOR, **run) -> dict:
    """One running-in; returns the final fields and the cost (s).

    ``interface``: ``"fe"``, ``"condensed"`` (its condensation in the cost),
    ``"winkler"`` (layer modulus) or
    ``"winkler_cal"`` (stiffness-calibrated against one FE solve, counted in
    the cost).  ``run_s`` is model build + (calibration) + the wear history.
    """
    run = {**RUN, **run}
    lp, om, mu = run["line_pressure"], run["omega"], run["mu"]
    t0, c0 = time.perf_counter(), time.process_time()
    model = BrakeModel("default", size=size, rotor=rotor, piston=piston)
    kw = {}
    if interface == "fe":
        if update == "gap":
            kw["interface"] = FEInterface(model, lp, mu)
    elif interface == "condensed":     # its condensation counted in the cost (no cache)
        kw["interface"] = CondensedInterface(model, lp, mu, cache=False)
    else:
        wi = WinklerInterface.from_model(model)
        if interface == "winkler_cal":
            wi = calibrate(wi, solve_contact(model, lp, mu), "stiffness", model=model).interface
        elif interface != "winkler":
            raise ValueError(f"interface = {interface!r}; allowed: 'fe', 'condensed', "
                             "'winkler', 'winkler_cal'")
        kw["interface"] = FoundationInterface(model, wi, lp, mu)
    if thermal:
        from brakewear.thermal import ThermalModel
        kw["thermal"] = ThermalModel(model, contact_conductance=1e5)
    if "interface" not in kw:
        kw["interface"] = FEInterface(model, lp, mu)
    itf = kw["interface"]
    last, solves, solve_s = None, 0, 0.0
    for s in wear_history(
        Run(
            model,
            lp,
            om,
            duration,
            pad_law,
            rotor_law,
            mu,
            **kw,
            numerics=Numerics(steps=steps, scheme=scheme, update=update),
        )
    ):
        last = s
        solves += s.contact_solves
        solve_s += s.solve_s
    run_s, cpu_s = time.perf_counter() - t0, time.process_time() - c0
    p_end = last.pressure_end
    pad = model.meshes["pad"]
    nodes = surface_nodes(pad, "friction")
    x = pad.p[:2, nodes]
    area = itf.area if itf is not None else None
    rr = np.hypot(itf.rotor_x[0], itf.rotor_x[1])
    order = np.argsort(rr)
    out = {
        "size_m": size, "duration_s": duration, "steps": steps, "scheme": scheme,
        "update": update, "rotor": rotor, "piston": piston, "interface": interface,
        "thermal": thermal, "dofs": int(model.dofs), "pad_nodes": int(nodes.size),
        "run_s": run_s, "cpu_s": cpu_s, "solve_s": solve_s, "contact_solves": solves,
        "_xy": x, "_area": area, "_pad_wear": last.pad_wear.copy(),
        "_pressure": np.asarray(p_end, dtype=float).copy(),
        "_rotor_r": rr[order], "_rotor_wear": last.rotor_wear[order].copy(),
        "pad_wear_max_m": float(last.pad_wear.max()),
        "pressure_max_Pa": float(np.max(p_end)),
        "r_eff_m": _r_eff(p_end, area, x),
    }
    if thermal:
        out["pad_temperature_max_K"] = last.pad_temperature_max
        out["rotor_temperature_max_K"] = last.rotor_temperature_max
    return out


def _r_eff(p, area, xy) -> float:
    f = np.clip(p, 0, None) * area
    return float((f * np.hypot(xy[0], xy[1])).sum() / f.sum())


def errors(case: dict, ref: dict) -> dict:
    """Errors of ``case`` against ``ref`` (see the module docstring)."""
    X, A = ref["_xy"], ref["_area"]
    if case is ref:
        wear, p = ref["_pad_wear"], ref["_pressure"]
    else:
        wear = interpolate(case["_pad_wear"], case["_xy"], X)
        p = interpolate(case["_pressure"], case["_xy"], X)
    # no wear outside the radii a run has wear nodes at (an unmeshed rotor's
    # rings span the pad's radii only)
    rw = np.interp(ref["_rotor_r"], case["_rotor_r"], case["_rotor_wear"], left=0.0, right=0.0)
    rA = ref["_rotor_wear"]
    return {
        "pad_wear_l2": relative_l2(wear, ref["_pad_wear"], A),
        "pressure_l2": relative_l2(p, ref["_pressure"], A),
        "pad_wear_max": case["pad_wear_max_m"] / ref["pad_wear_max_m"] - 1.0,
        "pressure_max": case["pressure_max_Pa"] / ref["pressure_max_Pa"] - 1.0,
        "r_eff": case["r_eff_m"] / ref["r_eff_m"] - 1.0,
        "rotor_wear_l2": relative_l2(rw, rA),
    }


def element_order(ns_p1=(4, 8, 16), ns_p2=(2, 4, 8)) -> list[dict]:
    """P1 against P2 on the thick cylinder (the brake's: studies/brake_order.py)."""
    import cylinder_convergence as cyl
    rows = []
    for order, ns in ((1, ns_p1), (2, ns_p2)):
        for n in ns:
            r = cyl.solve(n, order)
            rows.append({"name": f"P{order} cylinder n={n}", "order": order, "h_m": r["h"],
                         "dofs": int(r["dofs"]), "run_s": r["time_s"],
                         "energy_error": r["energy"], "l2_error": r["l2"]})
    return rows


#: the convergence study's results, whose estimate is the default reference
CONVERGED = Path(__file__).parents[1] / "docs" / "data" / "mesh_convergence.json"


def machine_state() -> dict:
    load = os.getloadavg() if hasattr(os, "getloadavg") else (np.nan,) * 3
    return {"cpus": os.cpu_count(), "load_average_1_5_15": list(load),
            "python": platform.python_version(), "platform": platform.platform(),
            "date_utc": time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime())}


def cases(sizes, base_size, ref_steps, implicit_steps, explicit_steps,
          finest_is_reference: bool = True) -> list[dict]:
    """The runs: (name, group, settings).  The last of ``sizes`` is the finest mesh
    (the reference if ``finest_is_reference``)."""
    mm = lambda s: f"{s * 1e3:g} mm"    # noqa: E731
    out = [{"name": f"mesh {mm(s)}", "group": "mesh size",
            "kw": {"size": s, "steps": ref_steps}} for s in sizes]
    if finest_is_reference:
        out[-1]["name"] += " (reference)"
    b = {"size": base_size}
    out += [{"name": f"implicit {n} steps", "group": "wear step",
             "kw": {**b, "steps": n}} for n in implicit_steps]
    out += [{"name": f"explicit {n} steps", "group": "wear step",
             "kw": {**b, "steps": n, "scheme": "explicit"}} for n in explicit_steps]
    out += [
        {"name": "geometry update", "group": "geometry update",
         "kw": {**b, "steps": ref_steps, "update": "geometry"}},
        {"name": "rigid rotor", "group": "rotor", "kw": {**b, "steps": ref_steps,
                                                          "rotor": "rigid"}},
        {"name": "condensed FE", "group": "interface",
         "kw": {**b, "steps": ref_steps, "interface": "condensed"}},
        {"name": "Winkler (layer modulus)", "group": "interface",
         "kw": {**b, "steps": ref_steps, "interface": "winkler"}},
        {"name": "Winkler (stiffness-calibrated)", "group": "interface",
         "kw": {**b, "steps": ref_steps, "interface": "winkler_cal"}},
    ]
    return out


def main(sizes=(12e-3, 8e-3, 6e-3, 5e-3, 4e-3), base_size: float = 8e-3, ref_steps: int = 16,
         implicit_steps=(2, 4, 8, 32), explicit_steps=(16, 64), duration: float = 1200.0,
         out: str | Path | None = "docs", figures: bool = True, order_study: bool = True,
         reference: str | Path | None = CONVERGED, **run) -> dict:
    """Run all cases in this process; returns the results (and writes them under ``out``).

    ``sizes`` must contain ``base_size``; its last entry is the finest mesh, the
    cost reference (``time_ratio``, ``cpu_ratio``) and, when ``reference`` (the
    convergence study's JSON) is None or of another case, the error reference.
    """
    sizes = tuple(sizes)
    if base_size not in sizes:
        raise ValueError(f"base_size = {base_size!r} must be one of sizes = {sizes!r}")
    state0 = machine_state()
    t_all = time.perf_counter()
    conv = (None if reference is None else
            converged_reference(reference, duration, ref_steps, {**RUN, **run}))
    todo = cases(sizes, base_size, ref_steps, implicit_steps, explicit_steps, conv is None)
    res = []
    for c in todo:
        logger.info("running %s", c["name"])
        try:
            r = run_case(duration=duration, **c["kw"], **run)
        except Exception as e:   # a choice that fails is a result too (e.g. explicit blow-up)
            logger.warning("%s failed: %s", c["name"], e)
            r = {"failed": f"{type(e).__name__}: {e}"}
        res.append({"name": c["name"], "group": c["group"], **r})
    finest = res[len(sizes) - 1]
    ref = finest if conv is None else conv
    base = res[sizes.index(base_size)]
    for r in res:
        if "failed" in r:
            r["error"], r["error_vs_base"] = None, None
            continue
        r["error"] = errors(r, ref)
        r["error_vs_base"] = errors(r, base) if r["group"] != "mesh size" else None
        r["time_ratio"] = r["run_s"] / finest["run_s"]
        r["cpu_ratio"] = r["cpu_s"] / finest["cpu_s"]
    result = {
        "case": {"geometry": "default", "duration_s": duration, **RUN, **run,
                 "pad_law_k": PAD.k, "rotor_law_k": ROTOR.k, "reference": ref["name"],
                 "finest": finest["name"], "base": base["name"], "ref_steps": ref_steps},
        "runs": [{k: v for k, v in r.items() if not k.startswith("_")} for r in res],
        "element_order": element_order() if order_study else [],
        "machine_before": state0, "machine_after": machine_state(),
        "total_s": time.perf_counter() - t_all,
        "command": "python studies/speed_vs_error.py",
    }
    if out is not None:
        write(result, Path(out), figures)
    return result


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs", help="writes OUT/data and OUT/figures")
    ap.add_argument("--quick", action="store_true", help="tiny settings (a smoke run)")
    ap.add_argument("--duration", type=float, default=1200.0)
    ap.add_argument("--replot", metavar="JSON", help="only redraw the figure from a JSON")
    a = ap.parse_args(argv)
    if a.replot:
        res = json.loads(Path(a.replot).read_text())
        (Path(a.out) / "figures").mkdir(parents=True, exist_ok=True)
        plot(res, Path(a.out) / "figures" / "speed_vs_error.png")
        print(table(res))
        return res
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(name)s %(message)s")
    logger.setLevel(logging.INFO)
    kw = dict(sizes=(1.5e-2, 1.2e-2), base_size=1.5e-2, ref_steps=2, implicit_steps=(1,),
              explicit_steps=(2,)) if a.quick else {}
    res = main(out=a.out, duration=a.duration, **kw)
    print(table(res))
    return res


if __name__ == "__main__":
    _cli()
