"""Rotor cleaning for a stated vehicle: the lowest deceleration (and its line
pressure) whose stops wear a corrosion layer off the whole friction band.

The vehicle (default: a 1.8 t electric car, 70 % of the friction braking on
the front axle, 0.32 m tyres, regeneration off for the cleaning stops) makes
``stops`` stops from ``speed`` km/h to rest at one deceleration, ``interval``
s apart.  Every stop dissipates the same energy in the front brake (the
vehicle's kinetic energy times the brake's share), whatever the
deceleration; the deceleration sets the line pressure (through the brake's
torque, ``T = 2 mu p A_clamp r_eff``), and the line pressure sets how much
of the band the pad touches -- the pad and rotor start non-conformal (a
coning of ``coning`` um across the band).

Per deceleration: the cleaned fraction of the band's *area* after each stop
(:class:`brakewear.cleaning.corrosion.CorrodedRotor`; a ring counts as touched only
where the pad presses with at least ``threshold`` MPa), the line pressure,
the energy per face (the vehicle's demand and the model's friction work).
The answer: the lowest deceleration of the sweep that cleans within
``stops``, and its line pressure; the map of cleaned fraction against
deceleration and number of stops.

Model (``geometry = "floating"``, the default): the floating caliper of
``geometry/floating.toml`` as the full model -- both pads, the whole rotor on
its hat, elastic -- with the pads held as the caliper holds them
(``piston = "rigid"``: the rigid piston in its bore and seal, the rim, the
fingers and the abutments one-sided with friction;
:class:`brakewear.CaliperInterface`, condensed onto the contact nodes and the
caliper's rows); each rotor face has its own corrosion layer and its own
wear, the coning opens the inboard face's gap at the outer radius and the
outboard face's at the inner one (:func:`brakewear.cleaning.corrosion.nonconformity_gap`),
and the band counts as cleaned when both faces are: the answer is the worse
face's (:class:`brakewear.cleaning.corrosion.BandCriterion`).  ``load_path`` overrides
load-path keys of the geometry file (``{"support.abutment_friction": 0.4}``,
in the file's units, checked as the file is).

``geometry = "default"`` is the *idealised* brake (labelled so in the
outputs): one pad on a rigid rotor (the plane z = 0), the clamp force a
uniform traction on a 40 mm disc, both backplate ends held; its contact
solves on the FE model condensed onto the pad's contact nodes
(:class:`brakewear.CondensedInterface`; ``--interface fe`` for FE solves).
``rotor = "rigid"`` with ``geometry = "floating"`` takes its inboard pad alone
(the half model), with the piston a traction (``piston = "traction"``, which
needs ``interface = "fe"`` for its unilateral abutments) or meshed
(``"body"``).  Isothermal Archard wear (pad ``k`` of a resin pad, rotor
``k_corrosion`` on the layer and ``k`` of grey cast iron beneath), implicit
pad wear, gap-offset update (:func:`brakewear.duty.run_schedule`); every
model is condensed once and read from the cache by every run.

Run ``python studies/cleaning_stops.py [--decels 0.5 1 2 3] [--stops 20] [--out docs]``;
the sensitivity sweeps with ``--name cleaning_stops_<case>`` (:data:`SENSITIVITY`) and
their tornado chart with ``--tornado``; the probability of clean under uncertain
inputs (:data:`UNCERTAIN`) with ``--monte-carlo N``.  The runs go to a process pool
(``--workers``, default 2) or, with ``--dask ADDRESS`` (``local``: a local cluster),
to a dask.distributed cluster.
"""
from __future__ import annotations

import argparse
import csv
import json
import logging
import sys
import time
from concurrent.futures import Executor, ProcessPoolExecutor
from pathlib import Path

import numpy as np

from brakewear import (MATERIALS, BrakeModel, CondensedInterface, FEInterface, Numerics,
                       SolverError, Vehicle, WearLaw)
from brakewear.cleaning.corrosion import CorrodedRotor, nonconformity_gap, outboard_nodes
from brakewear.duty import KMH, repeated_stops, run_schedule

sys.path.insert(0, str(Path(__file__).resolve().parent))
from sweep_executor import add_executor_options, study_executor  # noqa: E402  (a sibling script)
from brakewear.wear import Run

logger = logging.getLogger("cleaning_stops")

DEFAULTS = dict(decels=(0.5, 1.0, 1.5, 2.0, 3.0, 4.0), stops=20, speed=50.0, interval=120.0,
                mass=1800.0, front_share=0.7, tyre_radius=0.32, regen_share=0.0,
                corrosion=25.0, k_corrosion=1e-12, coning=30.0, mu=0.4, threshold=0.02,
                size=4.0, dp_tol=0.05, pad_modulus=1.0, interface="condensed",
                geometry="floating", support=None, piston=None, rotor=None, load_path=None)


def brake_kind(task: dict) -> tuple[str, str, str]:
    """``(piston, rotor, label)`` of a task: the floating caliper as the caliper holds
    its pads (rigid piston, elastic rotor, both faces) unless told otherwise, the
    default geometry as the idealised brake."""
    ideal = task.get("geometry", "floating") == "default"
    piston = task.get("piston") or ("traction" if ideal else "rigid")
    rotor = task.get("rotor") or ("rigid" if ideal or piston != "rigid" else "elastic")
    if ideal:
        label = "idealised brake (one pad, rigid rotor, 40 mm disc, ends held)"
    elif piston == "rigid" and rotor == "elastic":
        label = "floating caliper, both faces (rigid piston in its bore, hat rotor)"
    else:
        label = f"floating caliper, inboard pad (piston {piston}, rotor {rotor})"
    return piston, rotor, label


def run_decel(task: dict) -> dict:
    """One deceleration: ``task`` holds the settings of :func:`main` and ``decel``.

    A solver failure returns ``{"decel", "error"}``: the sweep reports it and
    leaves the deceleration out of the answer.
    """
    from threadpoolctl import threadpool_limits

    try:
        # one BLAS thread: the runs are many small problems, run side by side (two
        # workers with two OpenBLAS threads each on 2 cores ran 2-3x slower)
        with threadpool_limits(limits=1, user_api="blas"):
            return _run_decel(task)
    except SolverError as e:
        logger.warning("%g m/s^2 failed: %s", task["decel"], e)
        return {"decel": task["decel"], "error": f"{type(e).__name__}: {e}"}


def task_geometry(pad_modulus: float, name: str = "default", support: str | None = None,
              load_path: dict | None = None):
    """The brake of geometry file ``name`` (default: the default brake), its friction
    layer's moduli scaled by ``pad_modulus``; ``support = "bilateral"``: both
    backplate ends held in-plane instead of the file's support; ``load_path``:
    keys of the file set to other values (``"section.key"`` -> value in the file's
    units), checked as the file is."""
    from dataclasses import replace

    from brakewear import load_geometry
    from brakewear.geometry import SupportGeometry
    if load_path:
        import tomllib

        from brakewear.geometry import geometry_file, geometry_from_dict
        d = tomllib.loads(geometry_file(name).read_text())
        for key, value in load_path.items():
            sec, field = key.split(".")
            d.setdefault(sec, {})[field] = value
        g = geometry_from_dict(d, source=f"{name}.toml with {load_path}")
    else:
        g = load_geometry(name)
    if support is not None:
        _check("support", support, support == "bilateral", "allowed: None, 'bilateral'")
        g = replace(g, support=SupportGeometry())
    if pad_modulus == 1.0:
        return g
    m = g.pad.friction_material
    e = m.elastic
    stiffer = replace(m, elastic=replace(e, E_p=e.E_p * pad_modulus, E_t=e.E_t * pad_modulus,
                                         G_t=e.G_t * pad_modulus))
    return replace(g, pad=replace(g.pad, friction_material=stiffer))


#: this process's caliper interface of the last brake run (its condensation and model)
_BUILT: dict = {}


def task_interface(task: dict):
    """The study's model and its interface: the FE contact, or its condensation
    (the same answer; read from the cache when a run of this model made it); the
    rigid piston's caliper interface for the floating caliper."""
    from brakewear import CaliperInterface

    piston, rotor, _ = brake_kind(task)
    geometry = task_geometry(task.get("pad_modulus", 1.0), task.get("geometry", "default"),
                         task.get("support"), task.get("load_path"))
    kind = task.get("interface", "fe")
    _check("interface", kind, kind in ("fe", "condensed"), "allowed: 'fe', 'condensed'")
    if piston == "rigid":
        _check("interface", kind, kind == "condensed", "the rigid piston's load path runs on "
               "the condensed (caliper) interface: interface = 'condensed'")
        # one model and condensation per worker for every load path of this brake; each
        # run gets its own rows and solver state (CaliperInterface.with_load_path)
        key = (task.get("geometry"), task["size"], task.get("pad_modulus", 1.0),
               task.get("support"), rotor)
        if key not in _BUILT:
            base = BrakeModel(task_geometry(task.get("pad_modulus", 1.0), task.get("geometry"),
                                        task.get("support")),
                              size=task["size"] * 1e-3, rotor=rotor, piston=piston)
            _BUILT.clear()
            _BUILT[key] = CaliperInterface(base, 1e6, task["mu"])
        itf = _BUILT[key].with_load_path(geometry)
        return itf.model, itf
    model = BrakeModel(geometry, size=task["size"] * 1e-3, rotor=rotor, piston=piston)
    if kind == "condensed":
        return model, CondensedInterface(model, 1e6, task["mu"])
    return model, FEInterface(model, 1e6, task["mu"])


def _run_decel(task: dict) -> dict:
    t0 = time.perf_counter()
    model, itf = task_interface(task)
    g = model.geometry
    r_in, r_out = g.pad.inner_radius, g.pad.outer_radius
    rotor = CorrodedRotor(itf, r_in, r_out, task["corrosion"] * 1e-6, task["k_corrosion"],
                          MATERIALS["grey_cast_iron"].wear_k, task["threshold"] * 1e6)
    judge = rotor.criterion
    car = Vehicle(mass=task["mass"], front_share=task["front_share"],
                  tyre_radius=task["tyre_radius"], regen_share=task["regen_share"])
    sched = repeated_stops(task["stops"], task["speed"] * KMH, decel=task["decel"],
                           interval=task["interval"])
    touched: list = []

    def on_step(rec, step, pad_wear, rotor_wear):
        rotor.update(rotor_wear)

    rows = []
    num = Numerics(scheme="implicit", max_dh=task["corrosion"] * 1e-7, dp_tol=task["dp_tol"])
    for rec in run_schedule(Run(model, pad_law=WearLaw(MATERIALS["pad_resin"].wear_k), rotor_law=rotor.law, mu=task["mu"], schedule=sched, vehicle=car, numerics=num, interface=itf, initial_gap=nonconformity_gap(itf.x, r_in, r_out,
                                                          g.rotor.thickness,
                                                          task["coning"] * 1e-6)), on_step=on_step):
        if rec.kind != "stop":
            continue
        faces = judge.touched_fractions(rec.pressure)
        touched.append(min(faces.values()))
        if len(touched) == 1:
            first = rec.pressure.copy()
        cleaned = judge.cleaned_fractions(rec.rotor_wear)
        rows.append({"stop": len(rows) + 1, "line_pressure_MPa": rec.line_pressure / 1e6,
                     "r_eff_mm": rec.r_eff * 1e3, "duration_s": rec.duration,
                     "target_face_kJ": rec.target_face_J / 1e3,
                     "friction_face_kJ": rec.friction_face_J / 1e3,
                     "touched_fraction": touched[-1],
                     "cleaned_fraction": min(cleaned.values()),
                     "touched_faces": faces, "cleaned_faces": cleaned,
                     "pad_volume_mm3": rec.pad_volume_m3 * 1e9,
                     "rotor_volume_mm3": rec.rotor_volume_m3 * 1e9, "steps": rec.steps})
        if rows[-1]["cleaned_fraction"] >= 1.0:
            break
    clean = next((r["stop"] for r in rows if r["cleaned_fraction"] >= 1.0), None)
    return {"decel": task["decel"], "line_pressure_MPa": rows[0]["line_pressure_MPa"],
            # the pads' contact at the end of the first and the last stop (maps)
            "pad_x_mm": (itf.x[0] * 1e3).tolist(), "pad_y_mm": (itf.x[1] * 1e3).tolist(),
            "pad_face": ["out" if o else "in" for o in outboard_nodes(itf.x,
                                                                       g.rotor.thickness)],
            "pressure_first_MPa": (first / 1e6).tolist(),
            "pressure_last_MPa": (rec.pressure / 1e6).tolist(),
            "stops_to_clean": clean, "rows": rows,
            "ring_radius_mm": (rotor.radii * 1e3).tolist(), "ring_face": judge.face.tolist(),
            "ring_wear_um": (rotor.ring_means(rec.rotor_wear) * 1e6).tolist(),
            "run_s": time.perf_counter() - t0}


def _check(name, value, ok, allowed):
    if not ok:
        raise ValueError(f"{name} = {value!r} is not allowed; {allowed}")


def main(decels=DEFAULTS["decels"], stops: int = DEFAULTS["stops"], out=None,
         executor: Executor | None = None, figures: bool = True, name: str = "cleaning_stops",
         **settings) -> dict:
    """Sweep decelerations (m/s^2); the answer and the map.  ``settings`` override
    :data:`DEFAULTS` (speed km/h, interval s, mass kg, corrosion um,
    k_corrosion 1/Pa, coning um, threshold MPa, size mm, ...).  ``name``
    names the files written to ``out`` (``data/<name>.json``,
    ``data/<name>_map.csv``, ``figures/<name>_map.png``)."""
    unknown = set(settings) - set(DEFAULTS) - {"brake"}
    _check("settings", sorted(unknown), not unknown, f"allowed: {', '.join(DEFAULTS)}")
    st = {**DEFAULTS, **settings, "decels": sorted(float(a) for a in decels), "stops": stops}
    _check("stops", stops, isinstance(stops, int) and stops >= 1, "need a whole number >= 1")
    support = task_geometry(1.0, st["geometry"], st["support"], st["load_path"]).support.type
    piston, _, label = brake_kind(st)
    _check("interface", st["interface"], st["interface"] != "condensed" or support == "bilateral"
           or piston == "rigid",
           f"the condensed interface needs a bilateral pad support or the rigid piston, and "
           f"geometry {st['geometry']!r} has a {support!r} one: use interface = 'fe'")
    st["brake"] = label
    Vehicle(mass=st["mass"], front_share=st["front_share"], tyre_radius=st["tyre_radius"],
            regen_share=st["regen_share"]).check_deceleration(max(st["decels"]))
    t0 = time.perf_counter()
    tasks = [dict(st, decel=a) for a in st["decels"]]
    runs = _map_runs(tasks, executor)
    failed = [r for r in runs if "error" in r]
    runs = [r for r in runs if "error" not in r]
    lowest = next((r for r in runs if r["stops_to_clean"] is not None), None)
    result = {"settings": st, "runs": runs, "failed_runs": failed,
              # a failed deceleration below the answer could have cleaned: an upper bound
              "failed_below_answer": bool(lowest is not None and any(
                  f["decel"] < lowest["decel"] for f in failed)),
              "lowest_cleaning_decel": None if lowest is None else lowest["decel"],
              "its_line_pressure_MPa": None if lowest is None else lowest["line_pressure_MPa"],
              "its_stops": None if lowest is None else lowest["stops_to_clean"],
              "monotone": _monotone(runs), "wall_s": time.perf_counter() - t0}
    if out is not None:
        write_outputs(result, Path(out), figures, name)
    return result


def _map_runs(tasks: list, executor: Executor | None) -> list:
    """:func:`run_decel` of every task on ``executor`` (default: two processes)."""
    if tasks and tasks[0].get("interface") == "condensed" and run_decel.__module__ == __name__:
        task_interface(tasks[0])    # condensed once here: the workers read it from the cache
    own = executor is None
    executor = ProcessPoolExecutor(max_workers=2) if own else executor
    try:
        return list(executor.map(run_decel, tasks))
    finally:
        if own:
            executor.shutdown()


def _monotone(runs) -> bool:
    """Whether every deceleration above a cleaning one cleans too."""
    ok = [r["stops_to_clean"] is not None for r in runs]
    return all(ok[ok.index(True):]) if True in ok else True


def cleaned_map(result: dict) -> np.ndarray:
    """Cleaned fraction after each stop (rows) at each deceleration (columns);
    a run that cleaned early stays at 1."""
    n = result["settings"]["stops"]
    M = np.ones((n, len(result["runs"])))
    for j, r in enumerate(result["runs"]):
        f = [row["cleaned_fraction"] for row in r["rows"]]
        M[:len(f), j] = f
        if r["stops_to_clean"] is None:
            M[len(f):, j] = f[-1]
    return M


def write_outputs(result: dict, out: Path, figures: bool = True,
                  name: str = "cleaning_stops") -> None:
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / f"{name}.json").write_text(json.dumps(result, indent=1))
    with open(out / "data" / f"{name}_map.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["stop"] + [f"decel_{r['decel']:g}" for r in result["runs"]])
        for i, row in enumerate(cleaned_map(result)):
            w.writerow([i + 1] + [f"{x:.6f}" for x in row])
    if figures:
        (out / "figures").mkdir(parents=True, exist_ok=True)
        plot_map(result, out / "figures" / f"{name}_map.png")
        if all("pressure_first_MPa" in r for r in result["runs"]):
            plot_contact_maps(result, out / "figures" / f"{name}_contact.png")


def plot_map(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    st, runs = result["settings"], result["runs"]
    M = cleaned_map(result)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    x = np.arange(len(runs))
    im = ax.imshow(M * 100, origin="lower", aspect="auto", cmap="viridis", vmin=0, vmax=100,
                   extent=(-0.5, len(runs) - 0.5, 0.5, st["stops"] + 0.5))
    ax.set_xticks(x, [f"{r['decel']:g}\n{r['line_pressure_MPa']:.2f}" for r in runs],
                  fontsize=8 if len(runs) <= 7 else 7)
    ax.set_xlabel("deceleration (m/s^2) and its line pressure (MPa)")
    ax.set_ylabel("stops")
    ax.yaxis.get_major_locator().set_params(integer=True)
    worse = ", the worse face" if "cleaned_faces" in runs[0]["rows"][0] and len(
        runs[0]["rows"][0]["cleaned_faces"]) > 1 else ""
    ax.set_title(f"cleaned share of the friction band's area (%){worse}", fontsize=10)
    fig.colorbar(im, ax=ax)
    for r in runs:
        f = [row["touched_fraction"] for row in r["rows"]]
        bx.plot(np.arange(1, len(f) + 1), np.array(f) * 100, marker=".",
                label=f"{r['decel']:g} m/s^2")
    bx.set_xlabel("stop")
    bx.xaxis.get_major_locator().set_params(integer=True)
    bx.set_ylabel(f"band area touched at >= {st['threshold']:g} MPa (%){worse}")
    bx.set_ylim(0, 105)
    bx.legend(fontsize=7)
    fig.suptitle(f"{st['mass']:g} kg, {st['front_share']:.0%} front, {st['tyre_radius']:g} m "
                 f"tyres; stops from {st['speed']:g} km/h; corrosion {st['corrosion']:g} um, "
                 f"coning {st['coning']:g} um, mu {st['mu']:g}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


#: the sensitivity sweeps: parameter -> (its default, the low and the high variant,
#: each (value, file name of the sweep in data/))
SENSITIVITY = {
    "corrosion (um)": (25.0, (10.0, "cleaning_stops_corr10"), (50.0, "cleaning_stops_corr50")),
    "k_corrosion (1/Pa)": (1e-12, (5e-13, "cleaning_stops_kc05"), (2e-12, "cleaning_stops_kc2")),
    "coning (um)": (30.0, (15.0, "cleaning_stops_coning15"), (50.0, "cleaning_stops_coning50")),
    "mu": (0.4, (0.3, "cleaning_stops_mu03"), (0.5, "cleaning_stops_mu05")),
    "pad modulus (x resin's)": (1.0, (0.5, "cleaning_stops_E05"), (2.0, "cleaning_stops_E2")),
    "stop speed (km/h)": (50.0, (None, None), (80.0, "cleaning_stops_v80")),
}


def stops_at(result: dict, decel: float) -> float:
    """Stops to clean at ``decel`` (inf: not within the sweep's stops; nan: not run)."""
    r = next((r for r in result["runs"] if r["decel"] == decel), None)
    if r is None:
        return float("nan")
    return float("inf") if r["stops_to_clean"] is None else float(r["stops_to_clean"])


def sensitivity(data: Path, decel: float = 1.5, base: str = "cleaning_stops") -> list[dict]:
    """One row per parameter of :data:`SENSITIVITY` whose sweeps are in ``data``: the
    stops to clean at ``decel`` and the lowest cleaning deceleration, low and high."""
    ref = json.loads((data / f"{base}.json").read_text())
    rows = []
    for name, (default, *variants) in SENSITIVITY.items():
        row = {"parameter": name, "default": default,
               "base_stops": stops_at(ref, decel), "base_lowest": ref["lowest_cleaning_decel"]}
        for side, (value, fname) in zip(("low", "high"), variants):
            f = data / f"{fname}.json" if fname else None
            res = json.loads(f.read_text()) if f is not None and f.exists() else None
            row[side] = value if res is not None else None
            row[f"{side}_stops"] = stops_at(res, decel) if res is not None else float("nan")
            row[f"{side}_lowest"] = res["lowest_cleaning_decel"] if res is not None else None
        rows.append(row)
    return rows


def plot_tornado(rows: list[dict], decel: float, stops: int, path: Path) -> None:
    """Stops to clean at ``decel`` for each parameter's low and high value (bars from
    the default's count); a run that does not clean within ``stops`` is drawn at
    ``stops + 1`` and marked."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 0.6 * len(rows) + 1.5))
    base = rows[0]["base_stops"]
    for i, r in enumerate(rows):
        for side, color in (("low", "tab:blue"), ("high", "tab:red")):
            v = r[f"{side}_stops"]
            if not np.isnan(v):
                w = min(v, stops + 1) - base
                ax.barh(i, w, left=base, color=color, alpha=0.8,
                        label=f"{side} value" if i == 0 else None)
                # a value that does not move the count: its label above (low) or below
                ax.annotate(f"{r[side]:g}" + ("" if np.isfinite(v) else f" (> {stops})"),
                            (base + w, i), xytext=(4 if w >= 0 else -4,
                                                   0 if w else (7 if side == "low" else -7)),
                            textcoords="offset points", va="center", fontsize=8,
                            ha="left" if w >= 0 else "right")
    ax.axvline(base, color="k", lw=1)
    ax.set_yticks(range(len(rows)), [f"{r['parameter']}\n(default {r['default']:g})"
                                     for r in rows], fontsize=8)
    ax.set_xlabel(f"stops to clean at {decel:g} m/s^2 (default: {base:g})")
    ax.set_xlim(0, stops + 5)
    ax.legend(fontsize=8, loc="lower right")
    ax.invert_yaxis()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def write_sensitivity(out: Path, decel: float = 1.5, stops: int = DEFAULTS["stops"]) -> list:
    """The tornado of the sweeps in ``out/data``: CSV and PNG."""
    rows = sensitivity(out / "data", decel)
    with open(out / "data" / "cleaning_stops_sensitivity.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    plot_tornado(rows, decel, stops, out / "figures" / "cleaning_stops_tornado.png")
    return rows


#: the Monte Carlo's input distributions, in the study's units: name -> (kind, a, b);
#: "lognormal": median a, standard deviation b of the logarithm; "uniform": a..b;
#: "normal": mean a, standard deviation b
UNCERTAIN = {
    "corrosion": ("lognormal", 25.0, 0.3),        # um: days to weeks of standing
    "k_corrosion": ("lognormal", 1e-12, 0.5),     # 1/Pa: the least known input
    "coning": ("uniform", 15.0, 45.0),            # um
    "mu": ("normal", 0.4, 0.03),
}


def sample_inputs(n: int, seed: int = 20091, dists: dict = UNCERTAIN) -> list[dict]:
    """``n`` draws of the uncertain inputs (a NumPy generator seeded with ``seed``)."""
    rng = np.random.default_rng(seed)
    cols = {}
    for name, (kind, a, b) in dists.items():
        if kind == "lognormal":
            cols[name] = a * np.exp(b * rng.standard_normal(n))
        elif kind == "uniform":
            cols[name] = rng.uniform(a, b, n)
        elif kind == "normal":
            cols[name] = rng.normal(a, b, n)
        else:
            raise ValueError(f"{name}: unknown distribution {kind!r}; allowed: lognormal, "
                             "uniform, normal")
    return [{k: float(v[i]) for k, v in cols.items()} for i in range(n)]


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score interval (95 % by default) of a probability seen k times in n."""
    if n == 0:
        return 0.0, 1.0
    p = k / n
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return max(0.0, c - h), min(1.0, c + h)


def probability_of_clean(decel: float, n: int = 24, seed: int = 20091,
                         stops: int = DEFAULTS["stops"], executor: Executor | None = None,
                         out=None, dists: dict = UNCERTAIN, **settings) -> dict:
    """Monte Carlo: the probability that ``stops`` stops at ``decel`` clean the band
    when the inputs of ``dists`` are uncertain (the rest from :data:`DEFAULTS` and
    ``settings``); each sample is one :func:`run_decel` on ``executor`` (a
    ``ProcessPoolExecutor(2)`` by default; a dask client's ``get_executor()`` for
    large samples).  A sample whose solve failed counts as not cleaned and is
    reported.  Writes ``data/cleaning_stops_mc.json`` to ``out``."""
    unknown = set(settings) - set(DEFAULTS)
    _check("settings", sorted(unknown), not unknown, f"allowed: {', '.join(DEFAULTS)}")
    _check("n", n, isinstance(n, int) and n >= 1, "need a whole number of samples >= 1")
    st = {**DEFAULTS, **settings, "stops": stops}
    samples = sample_inputs(n, seed, dists)
    tasks = [dict(st, **x, decel=decel) for x in samples]
    t0 = time.perf_counter()
    runs = _map_runs(tasks, executor)
    rows = [{**x, "stops_to_clean": r.get("stops_to_clean"), "error": r.get("error"),
             "cleaned_fraction": r["rows"][-1]["cleaned_fraction"] if "rows" in r else None,
             "run_s": r.get("run_s")} for x, r in zip(samples, runs)]
    k = sum(r["stops_to_clean"] is not None for r in rows)
    times = [r["run_s"] for r in rows if r["run_s"] is not None]
    result = {"decel": decel, "stops": stops, "samples": n, "seed": seed,
              "distributions": {k_: list(v) for k_, v in dists.items()},
              "settings": {k_: v for k_, v in st.items() if k_ not in dists},
              "cleaned": k, "probability": k / n, "interval_95": list(wilson(k, n)),
              "failed": sum(r["error"] is not None for r in rows),
              "cost_per_sample_s": float(np.mean(times)) if times else None,
              "wall_s": time.perf_counter() - t0, "rows": rows}
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / "cleaning_stops_mc.json").write_text(json.dumps(result, indent=1))
    return result


#: the load-path keys whose plausible ranges the spread covers, one at a time
LOAD_PATH_SPREAD = ("piston.seal_modulus", "piston.bore_clearance", "piston.engagement_length",
                    "piston.stand_out", "piston.rim_friction", "piston.bore_friction",
                    "support.abutment_friction", "support.spring_stiffness",
                    "caliper.bridge_tilt", "caliper.bore_tilt", "caliper.finger_stiffness")


def load_path_cases(keys=LOAD_PATH_SPREAD, geometry: str = "floating") -> dict:
    """name -> load-path overrides: the nominal brake and each key at each end of its
    plausible range (:data:`brakewear.geometry.sections.LOAD_PATH_KEYS`), in the
    geometry file's units."""
    import tomllib

    from brakewear.geometry import geometry_file
    from brakewear.geometry.sections import LOAD_PATH_KEYS, STIFFNESS_UNITS
    units = tomllib.loads(geometry_file(geometry).read_text())["units"]
    cases = {"nominal": {}}
    for key in keys:
        _, unit, si, _, (lo, hi), _ = LOAD_PATH_KEYS[key]
        if unit == "length":
            si = {"mm": 1e-3, "m": 1.0}[units["length"]]
        elif unit == "stiffness":
            si = STIFFNESS_UNITS[units.get("stiffness", "N/mm")]
        for end, v in (("low", lo), ("high", hi)):
            cases[f"{key} {end}"] = {key: float(v / si)}
    return cases


def load_path_spread(decels=(0.5, 1.0, 2.0, 3.0), stops: int = DEFAULTS["stops"],
                     executor: Executor | None = None, out=None, keys=LOAD_PATH_SPREAD,
                     name: str = "cleaning_stops_load_path", **settings) -> dict:
    """The floating caliper's answer over the load path's own uncertainty: the sweep
    of ``decels`` for the nominal brake and for each of ``keys`` at each end of its
    plausible range (:func:`load_path_cases`), one at a time.  Per case the lowest
    cleaning deceleration and, per deceleration, the cleaned share of each face after
    the last stop.  Writes ``data/<name>.json`` to ``out``."""
    st = {**DEFAULTS, **settings, "stops": stops}
    cases = load_path_cases(keys)
    tasks = [dict(st, load_path=lp or None, decel=a, case=case)
             for case, lp in cases.items() for a in sorted(decels)]
    t0 = time.perf_counter()
    runs = _map_runs(tasks, executor)
    result = {"settings": {k: v for k, v in st.items() if k != "decels"},
              "decels": sorted(decels), "cases": {}}
    for (case, lp), i in zip(cases.items(), range(0, len(tasks), len(decels))):
        rr = runs[i:i + len(decels)]
        ok = [r for r in rr if "error" not in r]
        low = next((r for r in ok if r["stops_to_clean"] is not None), None)
        result["cases"][case] = {
            "overrides": lp, "failed": [r for r in rr if "error" in r],
            "lowest_cleaning_decel": None if low is None else low["decel"],
            "its_stops": None if low is None else low["stops_to_clean"],
            "cleaned_faces": {str(r["decel"]): r["rows"][-1]["cleaned_faces"] for r in ok},
            "stops_run": {str(r["decel"]): r["rows"][-1]["stop"] for r in ok},
            "line_pressure_MPa": {str(r["decel"]): r["line_pressure_MPa"] for r in ok},
            "run_s": [r.get("run_s") for r in ok]}
    result["wall_s"] = time.perf_counter() - t0
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / f"{name}.json").write_text(json.dumps(result, indent=1))
    return result


def plot_contact_maps(result: dict, path: Path, decels=None) -> None:
    """The pad faces seen from their rotor faces at the end of the first and the last
    stop, for up to four decelerations: one dot per friction node coloured by
    pressure, open where it is below the touch threshold; the band's edges dashed.
    Both faces of the full model in their own rows (inboard, then outboard)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = result["runs"]
    if decels is None:
        idx = np.unique(np.linspace(0, len(runs) - 1, min(4, len(runs))).round().astype(int))
        runs = [runs[i] for i in idx]
    else:
        runs = [r for r in runs if r["decel"] in decels]
    thr = result["settings"]["threshold"]
    vmax = max(max(r["pressure_first_MPa"] + r["pressure_last_MPa"]) for r in runs)
    faces = sorted(set(runs[0].get("pad_face", ["in"])), key=("in", "out").index)
    fig, axes = plt.subplots(2 * len(faces), len(runs),
                             figsize=(2.6 * len(runs) + 1.2, 3.0 * 2 * len(faces)),
                             squeeze=False, layout="constrained")
    for j, r in enumerate(runs):
        x, y = np.array(r["pad_x_mm"]), np.array(r["pad_y_mm"])
        face = np.array(r.get("pad_face", ["in"] * x.size))
        for f, fc in enumerate(faces):
            m = face == fc
            label = "" if len(faces) == 1 else {"in": "inboard face, ", "out": "outboard face, "}[fc]
            for i, (key, when) in enumerate((("pressure_first_MPa", "stop 1"),
                                             ("pressure_last_MPa",
                                              f"stop {r['rows'][-1]['stop']}"))):
                ax, p = axes[2 * f + i, j], np.array(r[key])[m]
                on = p >= thr
                sc = ax.scatter(x[m][on], y[m][on], c=p[on], s=9, cmap="inferno", vmin=0,
                                vmax=vmax)
                ax.scatter(x[m][~on], y[m][~on], s=9, facecolors="none", edgecolors="0.6",
                           lw=0.5)
                for rad in (min(np.hypot(x, y)), max(np.hypot(x, y))):
                    t = np.linspace(np.arctan2(y, x).min(), np.arctan2(y, x).max(), 50)
                    ax.plot(rad * np.cos(t), rad * np.sin(t), "k--", lw=0.5)
                ax.set_aspect("equal")
                ax.set_xticks([])
                ax.set_yticks([])
                ax.set_title(f"{r['decel']:g} m/s^2, {r['line_pressure_MPa']:.2f} MPa\n"
                             f"{label}{when}", fontsize=8)
    fig.colorbar(sc, ax=axes, shrink=0.6, label="contact pressure (MPa)")
    fig.suptitle(f"pad faces seen from the rotor (radius to the right); open: below {thr:g} MPa",
                 fontsize=9)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--decels", type=float, nargs="+", default=list(DEFAULTS["decels"]))
    ap.add_argument("--stops", type=int, default=DEFAULTS["stops"])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--name", default="cleaning_stops", help="names the files written")
    ap.add_argument("--no-figures", dest="figures", action="store_false")
    for k in ("speed", "interval", "mass", "front_share", "regen_share", "corrosion",
              "k_corrosion", "coning", "mu", "threshold", "size", "pad_modulus"):
        ap.add_argument(f"--{k.replace('_', '-')}", dest=k, type=float, default=DEFAULTS[k])
    ap.add_argument("--geometry", default=DEFAULTS["geometry"],
                    help="geometry file or packaged name ('floating', the default: the floating "
                         "caliper as it holds its pads, both faces; 'default': the idealised "
                         "brake, one pad on a rigid rotor)")
    ap.add_argument("--piston", choices=("rigid", "traction", "body"), default=DEFAULTS["piston"],
                    help="the rigid piston in its bore (the floating caliper's default), the "
                         "clamp force as a traction on the piston footprint (the pad free to "
                         "tilt on it), or the piston meshed, tied and guided by its bore")
    ap.add_argument("--rotor", choices=("elastic", "rigid"), default=DEFAULTS["rotor"],
                    help="the rotor elastic on its hat (both faces; the rigid piston's default) "
                         "or rigid (the inboard pad alone)")
    ap.add_argument("--load-path", dest="load_path", nargs="+", default=None,
                    metavar="SECTION.KEY=VALUE",
                    help="load-path keys of the geometry file set to other values, in its "
                         "units (e.g. support.abutment_friction=0.4 piston.seal_modulus=3)")
    ap.add_argument("--support", choices=("bilateral",), default=None,
                    help="hold both backplate ends in-plane instead of the geometry's support")
    ap.add_argument("--interface", choices=("fe", "condensed"), default=DEFAULTS["interface"],
                    help="FE contact solves, or the FE model condensed onto the pad's contact "
                         "nodes once (the same answer, much faster; the default)")
    ap.add_argument("--tornado", action="store_true",
                    help="only draw the sensitivity (tornado) chart of the sweeps in OUT/data")
    ap.add_argument("--load-path-spread", action="store_true",
                    help="the floating caliper's answer for each load-path key at each end of "
                         "its plausible range, one at a time (at --decels)")
    ap.add_argument("--monte-carlo", type=int, default=0, metavar="N",
                    help="only the probability of clean at the first of --decels, N samples "
                         "of the inputs in UNCERTAIN")
    add_executor_options(ap)
    a = vars(ap.parse_args(argv))
    if a["load_path"]:
        a["load_path"] = {k: float(v) for k, v in (x.split("=", 1) for x in a["load_path"])}
    mc, where = a.pop("monte_carlo"), (a.pop("dask"), a.pop("workers"))
    spread = a.pop("load_path_spread")
    if a.pop("tornado"):
        for r in write_sensitivity(Path(a["out"])):
            print(r)
        return {}
    with study_executor(*where) as executor:
        if spread:
            return _run_spread(a, executor)
        return _run_cli(a, mc, executor)


def _run_spread(a: dict, executor: Executor) -> dict:
    """The command line's load-path spread; prints a line per case."""
    name = a.pop("name")
    r = load_path_spread(a.pop("decels"), a.pop("stops"), executor=executor, out=a.pop("out"),
                         name="cleaning_stops_load_path" if name == "cleaning_stops" else name,
                         **{k: v for k, v in a.items() if k in DEFAULTS})
    for name, c in r["cases"].items():
        worst = {d: min(f.values()) for d, f in c["cleaned_faces"].items()}
        print(f"{name:34s} lowest {c['lowest_cleaning_decel']} m/s^2; cleaned (worse face) "
              + ", ".join(f"{d}: {v:.2f}" for d, v in worst.items()))
    return r


def _run_cli(a: dict, mc: int, executor: Executor) -> dict:
    """The command line's Monte Carlo (``mc`` samples) or sweep on ``executor``; prints."""
    if mc:
        r = probability_of_clean(a["decels"][0], mc, stops=a["stops"], out=a["out"],
                                 executor=executor,
                                 **{k: a[k] for k in DEFAULTS if k in a and k not in UNCERTAIN
                                    and k not in ("decels", "stops")})
        lo, hi = r["interval_95"]
        print(f"{r['decel']:g} m/s^2, {r['stops']} stops: cleaned in {r['cleaned']} of "
              f"{r['samples']} samples, P = {r['probability']:.2f} (95 % interval {lo:.2f}.."
              f"{hi:.2f}); {r['failed']} failed; {r['cost_per_sample_s']:.0f} s per sample, "
              f"{r['wall_s']:.0f} s")
        return r
    res = main(a.pop("decels"), a.pop("stops"), a.pop("out"), executor=executor, **a)
    for r in res["runs"]:
        last = r["rows"][-1]
        print(f"{r['decel']:4.2f} m/s^2  {r['line_pressure_MPa']:5.2f} MPa  stops to clean "
              f"{r['stops_to_clean']}  cleaned {last['cleaned_fraction']:.1%} after "
              f"{last['stop']}  ({r['run_s']:.0f} s)")
    for f in res["failed_runs"]:
        print(f"{f['decel']:4.2f} m/s^2  failed: {f['error']}")
    print(f"lowest cleaning deceleration: {res['lowest_cleaning_decel']} m/s^2 "
          f"({res['its_line_pressure_MPa']} MPa, {res['its_stops']} stops); {res['wall_s']:.0f} s")
    return res


if __name__ == "__main__":
    logging.basicConfig(level=logging.WARNING)
    _cli()
