"""Rotor cleaning: the lowest line pressure that wears a corrosion layer off the whole swept band.

Cleaning means the pad sweeps every radius of the rotor's swept band (the
pad's radial extent, 95-138 mm on the default brake) and, for a corrosion
layer of thickness ``h_c``, wears through it everywhere.  The pad and rotor
start *non-conformal* at the cleaning pressure: a rotor coning (or a radial
pad taper: in the gap-offset model both are an extra gap linear in radius)
and/or the worn state left by running in at another line pressure.  At a low
line pressure the pad's elastic deflection cannot close that gap: the pad
touches only part of the band.  Repeated applications wear the touched part
(the corrosion layer wears fast) and bring more of the band into contact --
but only by as much as the layer is thick: once the touched radii are worn
down to bare iron (200 x more wear resistant than the rust, in the default
parameters) the contact stops spreading.  A pressure cleans the band when its
deflection plus the corrosion layer's wear closes the gap everywhere, within
the given number of applications.

Model (stated choices, see docs/cleaning.md):

- the default brake, rigid rotor (the plane z = 0; the rotor's wear is
  revolution-averaged on rings at the pad-node radii), pad + backplate
  elastic, clamp force as a traction on the piston footprint; mesh 4 mm;
- two-surface Archard wear (:func:`brakewear.wear_history`,
  implicit pad wear): pad ``k = 5e-15 1/Pa`` (``pad_resin``); rotor
  ``k_corrosion`` (default 1e-12 1/Pa) while a ring still carries corrosion,
  ``k = 5e-16 1/Pa`` (``grey_cast_iron``) once worn through;
- an application: a light stop from 50 km/h on a 0.3 m tyre (omega 45 rad/s
  falling to 0 in 5 s) -- with Archard wear and a speed-independent pressure
  it wears exactly as a 2.5 s drag at 45 rad/s, which is what is simulated.

The contact solves run on the FE model condensed onto the pad's contact
nodes (:class:`brakewear.CondensedInterface`, the FE answer), condensed once
before the sweep starts and read from the cache by every task;
``--interface fe`` runs FE contact solves instead.

Run ``python studies/cleaning_pressure.py --help``.  The sweep runs one
pressure per task on any ``concurrent.futures.Executor``: a process pool by
default; ``--dask ADDRESS`` (or ``main(executor=Client(...).get_executor())``)
runs it on a dask.distributed cluster (dask is optional, imported only then).
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

from brakewear.materials import MATERIALS
from brakewear.model import BrakeModel
from brakewear.interfaces import CondensedInterface, FEInterface
from brakewear.wear import wear_history
from brakewear.laws.base import WearLaw
from brakewear.cleaning.corrosion import LayeredWearLaw
from brakewear import Numerics

sys.path.insert(0, str(Path(__file__).resolve().parent))
from sweep_executor import add_executor_options, study_executor  # noqa: E402  (a sibling script)
from brakewear.wear import Run

logger = logging.getLogger("cleaning_pressure")

K_PAD = MATERIALS["pad_resin"].wear_k
K_IRON = MATERIALS["grey_cast_iron"].wear_k
#: Default wear coefficient of the corrosion layer (1/Pa), an assumption: a
#: 25 um layer goes in ~25 light stops at 1 MPa (see docs/cleaning.md).
K_CORROSION = 1e-12

DEFAULTS = dict(pressures=(0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0), corrosion=25.0, coning=30.0,
                applications=20, running_in=None, running_in_seconds=3000.0,
                k_corrosion=K_CORROSION, omega=45.0, app_seconds=2.5, mu=0.4, size=4.0,
                rotor="rigid", dp_tol=0.05, interface="condensed", contact_tol=1e-9)


class CleaningError(ValueError):
    """Invalid input to the cleaning study (names the parameter, value and what is allowed)."""


# ------------------------------------------------------------------ geometry of the band --
def band_rings(itf, r_in: float, r_out: float) -> tuple[np.ndarray, np.ndarray]:
    """(ring radii, radial width of each ring inside the swept band [r_in, r_out])."""
    r = np.hypot(itf.rotor_x[0], itf.rotor_x[1])
    radii = np.bincount(itf.ring, weights=r) / np.bincount(itf.ring)
    edges = np.concatenate([[radii[0]], 0.5 * (radii[1:] + radii[:-1]), [radii[-1]]])
    lo, hi = np.clip(edges[:-1], r_in, r_out), np.clip(edges[1:], r_in, r_out)
    return radii, hi - lo


def touched_rings(itf, pressure: np.ndarray, active: np.ndarray) -> np.ndarray:
    """Which rotor rings the pad touches (a contact node with p > 0 over them)."""
    load = np.asarray(itf.W.T @ (pressure * itf.area * (active & (pressure > 0))))
    return np.bincount(itf.ring, weights=load.ravel(), minlength=itf.ring.max() + 1) > 0


def ring_means(itf, values: np.ndarray) -> np.ndarray:
    """Ring means of a field on the rotor's wear nodes (the rotor's wear against radius)."""
    return np.bincount(itf.ring, weights=values) / np.bincount(itf.ring)


def coning_gap(r: np.ndarray, r_in: float, r_out: float, coning: float) -> np.ndarray:
    """Gap (m) of a rotor coning (or radial pad taper) of ``coning`` m across the band:
    zero at ``r_in``, ``coning`` at ``r_out`` (negative: the outer radius stands proud)."""
    g = coning * (r - r_in) / (r_out - r_in)
    return g - g.min()


def uniform_bound(settings: dict, pressure: float) -> float:
    """Fewest applications that can wear the layer off the band at ``pressure`` (MPa).

    The worn volume per application is ``k_c F Theta r_F`` (clamp force ``F``,
    rotor angle ``Theta = omega t_app``, force centroid radius ``r_F``, here
    the piston radius); removing the layer takes ``h_c pi (r_o^2 - r_i^2)``.
    Equality needs a rotor wear uniform across the band.
    """
    from brakewear.geometry import load_geometry

    g = load_geometry("default")
    r_in, r_out = g.pad.inner_radius, g.pad.outer_radius
    F = pressure * 1e6 * g.piston.hydraulic_area
    theta = settings["omega"] * settings["app_seconds"]
    return (settings["corrosion"] * 1e-6 * np.pi * (r_out ** 2 - r_in ** 2)
            / (settings["k_corrosion"] * F * theta * g.piston.radius))


# ----------------------------------------------------------------------------- worker --
def _model(task: dict) -> BrakeModel:
    return BrakeModel("default", rotor=task["rotor"], size=task["size"] * 1e-3)


def _interface(task: dict, line_pressure: float):
    """The task's model and its contact interface at ``line_pressure`` (Pa): FE
    contact solves, or their condensation (the same answer; read from the cache
    when a run of this model made it)."""
    model = _model(task)
    tol = task.get("contact_tol", DEFAULTS["contact_tol"])
    if task.get("interface", "fe") == "condensed":
        return model, CondensedInterface(model, line_pressure, task["mu"], tol)
    return model, FEInterface(model, line_pressure, task["mu"], tol)


def running_in_gap(task: dict, model: BrakeModel | None = None, itf=None) -> np.ndarray:
    """Worn state (m, per pad friction node) after running in at ``task['running_in']``
    MPa; on ``model`` and its interface ``itf`` when given (any line pressure)."""
    p_run = task["running_in"] * 1e6
    if itf is None:
        model, itf = _interface(task, p_run)
    itf = itf.at_line_pressure(p_run)
    last = None
    for last in wear_history(Run(model, p_run, task["omega"], task["running_in_seconds"], WearLaw(K_PAD), WearLaw(K_IRON), task["mu"], interface=itf, numerics=Numerics(scheme="implicit"))):
        pass
    return last.pad_wear + itf.W @ last.rotor_wear


def run_pressure(task: dict) -> dict:
    """One line pressure of the sweep (a picklable, module-level task).

    ``task`` holds the settings of :func:`main` in SI-free engineering units
    plus ``pressure`` (MPa) and ``initial_gap`` (m per pad friction node, or
    None: computed here from the coning).  Returns plain numbers and lists;
    a contact or step-control failure returns ``{"pressure_MPa", "error"}``
    (the sweep reports it and leaves the pressure out of the answer).
    """
    from threadpoolctl import threadpool_limits

    from brakewear.errors import ActiveSetError
    from brakewear.errors import StepSizeError

    try:
        # one BLAS thread: the condensed runs are small dense problems run side by side
        with threadpool_limits(limits=1, user_api="blas"):
            return _run_pressure(task)
    except (ActiveSetError, StepSizeError) as e:
        logger.warning("%g MPa failed: %s", task["pressure"], e)
        return {"pressure_MPa": task["pressure"], "error": f"{type(e).__name__}: {e}"}


def _run_pressure(task: dict) -> dict:
    t0 = time.perf_counter()
    p_line = task["pressure"] * 1e6
    model, itf = _interface(task, p_line)
    g = model.geometry
    r_in, r_out = g.pad.inner_radius, g.pad.outer_radius
    gap0 = (coning_gap(itf.r, r_in, r_out, task["coning"] * 1e-6) if task["initial_gap"] is None
            else np.asarray(task["initial_gap"], dtype=float))
    h_c = task["corrosion"] * 1e-6
    radii, width = band_rings(itf, r_in, r_out)
    band = width > 0
    span = width.sum()
    k_c = task["k_corrosion"]
    factor_rot = np.ones(itf.rotor_area.size)
    rotor_law = LayeredWearLaw(k_c, factor=np.asarray(itf.W @ factor_rot, dtype=float).copy())
    t_app = task["app_seconds"]
    duration = task["applications"] * t_app
    hist = {"applications": [0.0], "coverage": [], "cleaned": [0.0],
            "ring_wear": [np.zeros(radii.size)]}
    first = last = None
    for s in wear_history(Run(model, p_line, task["omega"], duration, WearLaw(K_PAD), rotor_law, task["mu"], interface=itf, initial_gap=gap0, numerics=Numerics(scheme="implicit", max_dh=h_c / 10.0, dp_tol=task["dp_tol"]))):
        first = first or s
        last = s
        # the layer under each ring: corrosion until worn through, then iron
        worn_through = s.rotor_wear >= h_c
        factor_rot[:] = np.where(worn_through, K_IRON / k_c, 1.0)
        rotor_law.factor[:] = itf.W @ factor_rot
        ring_w = ring_means(itf, s.rotor_wear)
        hist["coverage"].append(float(width[touched_rings(itf, s.pressure, s.active)].sum()
                                      / span))
        hist["applications"].append(s.time / t_app)
        hist["cleaned"].append(float(width[ring_w >= h_c].sum() / span))
        hist["ring_wear"].append(ring_w)
        if hist["cleaned"][-1] >= 1.0 - 1e-12:
            break
    # the contact state the run ends in (the records hold the start-of-step pressure)
    sol = itf.solve(gap0 + last.pad_wear + itf.W @ last.rotor_wear, last.active)
    p_end, act_end = sol.pressure, sol.active
    hist["coverage"].append(float(width[touched_rings(itf, p_end, act_end)].sum() / span))
    ring_w = np.array(hist["ring_wear"])          # (records, rings)
    apps = np.array(hist["applications"])
    # applications at which each band ring wears through (linear in time within a step)
    through = np.full(radii.size, np.nan)
    for j in np.flatnonzero(band):
        k = np.flatnonzero(ring_w[:, j] >= h_c)
        if k.size:
            i = k[0]
            w0, w1 = ring_w[i - 1, j], ring_w[i, j]
            through[j] = apps[i - 1] + (apps[i] - apps[i - 1]) * (h_c - w0) / (w1 - w0)
    cleaned = bool(np.all(np.isfinite(through[band])))
    n_clean = float(np.nanmax(through[band])) if cleaned else None
    r_mean = 0.5 * (r_in + r_out)
    return {
        "pressure_MPa": task["pressure"],
        "clamp_force_N": p_line * g.piston.hydraulic_area,
        "coverage_start": hist["coverage"][0], "coverage_end": hist["coverage"][-1],
        "cleaned_fraction_end": hist["cleaned"][-1],
        "cleaned": cleaned,
        "applications_to_clean": n_clean,
        "sliding_distance_to_clean_m": (None if n_clean is None else
                                        n_clean * t_app * task["omega"] * r_mean),
        "applications_run": float(apps[-1]),
        "ring_radius_m": radii.tolist(), "ring_width_m": width.tolist(),
        "rotor_wear_m": ring_w[-1].tolist(),
        "wear_through_applications": [None if not np.isfinite(x) else float(x)
                                      for x in through],
        "history": {"applications": apps.tolist(),
                    "coverage": hist["coverage"][:-1],
                    "cleaned_fraction": hist["cleaned"]},
        "pad_x_m": itf.x[0].tolist(), "pad_y_m": itf.x[1].tolist(),
        "pressure_start_Pa": first.pressure.tolist(), "pressure_end_Pa": p_end.tolist(),
        "initial_gap_m": gap0.tolist(),
        "pad_volume_m3": last.pad_volume, "rotor_volume_m3": last.rotor_volume,
        "pad_archard_m3": last.pad_archard, "rotor_archard_m3": last.rotor_archard,
        "pad_wear_max_m": float(last.pad_wear.max()),
        "steps": last.step, "run_s": time.perf_counter() - t0,
    }


# ------------------------------------------------------------------------------- main --
def _check(name, value, ok, allowed):
    if not ok:
        raise CleaningError(f"{name} = {value!r} is not allowed; {allowed}")


def main(pressures=DEFAULTS["pressures"], corrosion: float = DEFAULTS["corrosion"],
         coning: float = DEFAULTS["coning"], applications: int = DEFAULTS["applications"],
         executor: Executor | None = None, size: float = DEFAULTS["size"],
         out: str | Path | None = None, *, running_in: float | None = None,
         running_in_seconds: float = DEFAULTS["running_in_seconds"],
         k_corrosion: float = K_CORROSION, omega: float = DEFAULTS["omega"],
         app_seconds: float = DEFAULTS["app_seconds"], mu: float = DEFAULTS["mu"],
         rotor: str = "rigid", dp_tol: float = DEFAULTS["dp_tol"], name: str = "cleaning",
         figures: bool = True, interface: str = DEFAULTS["interface"],
         contact_tol: float = DEFAULTS["contact_tol"]) -> dict:
    """Sweep line pressures; report coverage, applications to clean, lowest cleaning pressure.

    Parameters
    ----------
    pressures
        Line pressures (MPa, > 0) of the sweep.
    corrosion
        Corrosion layer thickness (um, > 0).
    coning
        Initial non-conformity (um): gap linear in radius across the band,
        zero at the pad's inner radius (negative: zero at the outer radius).
    applications
        Applications within which the band must be clean (whole number >= 1);
        each run stops when the band is clean or after this many.
    executor
        Any ``concurrent.futures.Executor`` (one task per pressure); default a
        ``ProcessPoolExecutor(max_workers=2)`` made and shut down here.  A
        ``dask.distributed.Client(...).get_executor()`` runs on a cluster.
    size
        Mesh size at the interface (mm).
    out
        Folder: writes ``data/{name}_*.json|csv`` and (``figures``)
        ``figures/{name}_*.png`` under it; None writes nothing.
    running_in, running_in_seconds
        Line pressure (MPa) and duration (s, at ``omega``) of a running-in
        whose worn state is added to the coning (None: no running-in).
    k_corrosion, omega, app_seconds, mu, rotor
        Corrosion wear coefficient (1/Pa), drag speed (rad/s) and duration
        (s) of one application, friction coefficient, ``"rigid"`` or
        ``"elastic"`` rotor.
    dp_tol
        Step control of the wear loop: largest relative pressure change per step.
    interface
        ``"condensed"``: the FE model condensed onto the pad's contact nodes,
        once, here, before any task runs (the tasks read it from the cache);
        ``"fe"``: FE contact solves.  The same answer.
    contact_tol
        Relative tolerance of the contact solves (the FE solves' iterations).

    Returns
    -------
    dict
        ``settings``, ``runs`` (one dict per pressure, ascending), and the
        answer: ``lowest_cleaning_pressure_MPa`` (None if none cleans),
        ``highest_failing_below_MPa``, ``monotone``.
    """
    try:
        pressures = [float(p) for p in pressures]
    except (TypeError, ValueError):
        raise CleaningError(f"pressures = {pressures!r} is not allowed; need a list of "
                            "line pressures in MPa") from None
    _check("pressures", pressures, len(pressures) > 0, "need at least one line pressure (MPa)")
    for p in pressures:
        _check("pressure", p, np.isfinite(p) and p > 0, "line pressures must be > 0 MPa")
    _check("pressures", pressures, len(set(pressures)) == len(pressures), "need distinct values")
    _check("corrosion", corrosion, np.isfinite(corrosion) and corrosion > 0,
           "the corrosion thickness must be > 0 um")
    _check("coning", coning, np.isfinite(coning), "need a finite coning (um)")
    _check("applications", applications, int(applications) == applications and applications >= 1,
           "need a whole number >= 1")
    _check("size", size, np.isfinite(size) and size > 0, "need a mesh size > 0 mm")
    _check("k_corrosion", k_corrosion, np.isfinite(k_corrosion) and k_corrosion > 0,
           "need a wear coefficient > 0 (1/Pa)")
    _check("omega", omega, np.isfinite(omega) and omega > 0, "need a rotor speed > 0 rad/s")
    _check("app_seconds", app_seconds, np.isfinite(app_seconds) and app_seconds > 0,
           "need an application duration > 0 s")
    _check("mu", mu, np.isfinite(mu) and mu >= 0, "need a friction coefficient >= 0")
    _check("dp_tol", dp_tol, np.isfinite(dp_tol) and dp_tol > 0, "need > 0")
    _check("contact_tol", contact_tol, np.isfinite(contact_tol) and 0 < contact_tol < 1,
           "need 0 < contact_tol < 1")
    _check("rotor", rotor, rotor in ("rigid", "elastic"), "allowed: 'rigid', 'elastic'")
    _check("interface", interface, interface in ("fe", "condensed"),
           "allowed: 'fe', 'condensed'")
    _check("running_in", running_in, running_in is None or (np.isfinite(running_in)
                                                            and running_in > 0),
           "need None or a line pressure > 0 MPa")
    _check("running_in_seconds", running_in_seconds,
           np.isfinite(running_in_seconds) and running_in_seconds > 0, "need > 0 s")
    t0 = time.perf_counter()
    settings = dict(pressures=sorted(pressures), corrosion=float(corrosion), coning=float(coning),
                    applications=int(applications), running_in=running_in,
                    running_in_seconds=float(running_in_seconds), k_corrosion=float(k_corrosion),
                    omega=float(omega), app_seconds=float(app_seconds), mu=float(mu),
                    size=float(size), rotor=rotor, dp_tol=float(dp_tol), k_pad=K_PAD,
                    k_iron=K_IRON, interface=interface, contact_tol=float(contact_tol))
    base = {k: settings[k] for k in ("corrosion", "coning", "applications", "k_corrosion",
                                     "omega", "app_seconds", "mu", "size", "rotor", "dp_tol",
                                     "running_in", "running_in_seconds", "interface",
                                     "contact_tol")}
    gap0 = None
    if running_in is not None or interface == "condensed":
        # a condensation is made here, once: the tasks read it from the cache
        model, itf = _interface(base, 1e6)
    if running_in is not None:
        g = model.geometry
        gap0 = running_in_gap(base, model, itf) + coning_gap(
            itf.r, g.pad.inner_radius, g.pad.outer_radius, coning * 1e-6)
    tasks = [dict(base, pressure=p, initial_gap=None if gap0 is None else gap0.tolist())
             for p in settings["pressures"]]
    own = executor is None
    if own:
        executor = ProcessPoolExecutor(max_workers=2)
    try:
        futures = [executor.submit(run_pressure, t) for t in tasks]
        runs = [f.result() for f in futures]
    finally:
        if own:
            executor.shutdown()
    failed = [r for r in runs if "error" in r]
    runs = [r for r in runs if "error" not in r]
    if not runs:
        raise RuntimeError(f"every pressure of the sweep failed: {failed}")
    for r in runs:
        r["applications_lower_bound"] = uniform_bound(settings, r["pressure_MPa"])
    ok = [r["cleaned"] and r["applications_to_clean"] <= applications for r in runs]
    lowest = next((r["pressure_MPa"] for r, c in zip(runs, ok) if c), None)
    failing_below = [r["pressure_MPa"] for r, c in zip(runs, ok)
                     if not c and lowest is not None and r["pressure_MPa"] < lowest]
    result = {"settings": settings, "runs": runs, "failed_runs": failed,
              "lowest_cleaning_pressure_MPa": lowest,
              "highest_failing_below_MPa": max(failing_below) if failing_below else None,
              "monotone": bool(lowest is None or all(ok[[r["pressure_MPa"] for r in runs]
                                                          .index(lowest):])),
              # a failed pressure below the answer could have cleaned: the answer is an upper bound
              "failed_below_answer": bool(lowest is not None and any(
                  f["pressure_MPa"] < lowest for f in failed)),
              "wall_s": time.perf_counter() - t0}
    if failed:
        logger.warning("pressures that failed (left out of the answer): %s",
                       [f["pressure_MPa"] for f in failed])
    logger.info("lowest cleaning pressure %s MPa (%.1f s)", lowest, result["wall_s"])
    if out is not None:
        write_outputs(result, Path(out), name, figures)
    return result


# ---------------------------------------------------------------------------- outputs --
def write_outputs(result: dict, out: Path, name: str = "cleaning", figures: bool = True) -> None:
    """``data/{name}_sweep.json|csv``, ``data/{name}_rotor_wear.csv``,
    ``data/{name}_history.csv``, ``data/{name}_pressure_maps.csv`` and the figures."""
    data, figs = out / "data", out / "figures"
    data.mkdir(parents=True, exist_ok=True)
    runs = result["runs"]
    slim = {k: v for k, v in result.items() if k != "runs"}
    slim["runs"] = [{k: v for k, v in r.items()
                     if k not in ("pad_x_m", "pad_y_m", "pressure_start_Pa", "pressure_end_Pa",
                                  "initial_gap_m")} for r in runs]
    (data / f"{name}_sweep.json").write_text(json.dumps(slim, indent=1))
    cols = ["pressure_MPa", "clamp_force_N", "coverage_start", "coverage_end",
            "cleaned_fraction_end", "cleaned", "applications_to_clean",
            "sliding_distance_to_clean_m", "applications_run", "pad_wear_max_m", "steps", "run_s"]
    with open(data / f"{name}_sweep.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for r in runs:
            w.writerow(["" if r[c] is None else r[c] for c in cols])
    with open(data / f"{name}_rotor_wear.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["radius_m", "band_width_m"] + [f"wear_m_{r['pressure_MPa']:g}MPa"
                                                   for r in runs])
        for j, rad in enumerate(runs[0]["ring_radius_m"]):
            w.writerow([rad, runs[0]["ring_width_m"][j]] + [r["rotor_wear_m"][j] for r in runs])
    with open(data / f"{name}_history.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["pressure_MPa", "applications", "coverage", "cleaned_fraction"])
        for r in runs:
            h = r["history"]
            # coverage[k] is the contact during step k (from applications[k] on); the
            # last row is the state the run ends in
            cov = list(h["coverage"]) + [r["coverage_end"]]
            for a, c, f in zip(h["applications"], cov, h["cleaned_fraction"]):
                w.writerow([r["pressure_MPa"], a, c, f])
    with open(data / f"{name}_pressure_maps.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["pressure_MPa", "x_m", "y_m", "initial_gap_m", "p_start_Pa", "p_end_Pa"])
        for r in runs:
            for row in zip(r["pad_x_m"], r["pad_y_m"], r["initial_gap_m"],
                           r["pressure_start_Pa"], r["pressure_end_Pa"]):
                w.writerow([r["pressure_MPa"], *row])
    if figures:
        figs.mkdir(parents=True, exist_ok=True)
        plot_coverage(result, figs / f"{name}_coverage.png")
        plot_rotor_wear(result, figs / f"{name}_rotor_wear.png")
        plot_pressure_maps(result, figs / f"{name}_pressure_maps.png")
        plot_history(result, figs / f"{name}_history.png")


def load_result(out: str | Path, name: str = "cleaning") -> dict:
    """A sweep written by :func:`write_outputs`, read back (the pressure maps from their CSV)."""
    out = Path(out)
    result = json.loads((out / "data" / f"{name}_sweep.json").read_text())
    maps: dict = {}
    with open(out / "data" / f"{name}_pressure_maps.csv", newline="") as fh:
        for row in csv.DictReader(fh):
            m = maps.setdefault(float(row["pressure_MPa"]), {k: [] for k in (
                "pad_x_m", "pad_y_m", "initial_gap_m", "pressure_start_Pa", "pressure_end_Pa")})
            for k, c in (("pad_x_m", "x_m"), ("pad_y_m", "y_m"), ("initial_gap_m", "initial_gap_m"),
                         ("pressure_start_Pa", "p_start_Pa"), ("pressure_end_Pa", "p_end_Pa")):
                m[k].append(float(row[c]))
    for r in result["runs"]:
        r.update(maps[r["pressure_MPa"]])
    return result


def _title(st: dict) -> str:
    ri = "" if st["running_in"] is None else f", run in at {st['running_in']:g} MPa"
    return (f"corrosion {st['corrosion']:g} um, coning {st['coning']:g} um{ri}, "
            f"k_corr {st['k_corrosion']:.0e}/Pa, N = {st['applications']}")


def plot_coverage(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs, st = result["runs"], result["settings"]
    p = np.array([r["pressure_MPa"] for r in runs])
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.3))
    a1.plot(p, [r["coverage_start"] for r in runs], "o-", label="touched, 1st application")
    a1.plot(p, [r["coverage_end"] for r in runs], "s--", label="touched, end of run")
    a1.plot(p, [r["cleaned_fraction_end"] for r in runs], "^:", label="worn through, end of run")
    a1.set_xlabel("line pressure (MPa)")
    a1.set_ylabel("fraction of the swept band's radial extent")
    a1.set_ylim(-0.03, 1.05)
    a1.grid(alpha=0.3)
    a1.legend(fontsize=8, loc="lower right")
    n = [r["applications_to_clean"] for r in runs]
    cl = [(pi, ni) for pi, ni in zip(p, n) if ni is not None]
    if cl:
        a2.semilogy(*zip(*cl), "o-", label="applications to wear through everywhere")
    fail = [pi for pi, ni in zip(p, n) if ni is None]
    if fail:
        a2.semilogy(fail, [st["applications"]] * len(fail), "x", color="C3", ms=9,
                    label=f"not clean after {st['applications']} applications")
    pp = np.linspace(p.min(), p.max(), 100)
    a2.semilogy(pp, [uniform_bound(st, x) for x in pp], color="0.5", lw=1,
                label="lower bound: uniform wear across the band")
    a2.axhline(st["applications"], color="k", ls="--", lw=1, label="N (criterion)")
    if result["lowest_cleaning_pressure_MPa"] is not None:
        a2.axvline(result["lowest_cleaning_pressure_MPa"], color="C2", ls=":",
                   label=f"lowest cleaning pressure {result['lowest_cleaning_pressure_MPa']:g} MPa")
    a2.set_xlabel("line pressure (MPa)")
    a2.set_ylabel("applications (5 s stops from 50 km/h)")
    a2.grid(alpha=0.3, which="both")
    a2.legend(fontsize=8)
    fig.suptitle("Rotor cleaning, default brake: " + _title(st), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_rotor_wear(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs, st = result["runs"], result["settings"]
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    cmap = plt.get_cmap("viridis")
    for i, r in enumerate(runs):
        rad = np.array(r["ring_radius_m"]) * 1e3
        band = np.array(r["ring_width_m"]) > 0
        state = (f"clean after {r['applications_to_clean']:.1f}" if r["cleaned"]
                 else f"not clean after {r['applications_run']:.0f}")
        ax.plot(rad[band], np.array(r["rotor_wear_m"])[band] * 1e6, "o-", ms=3,
                color=cmap(i / max(len(runs) - 1, 1)),
                label=f"{r['pressure_MPa']:g} MPa ({state})")
    ax.axhline(st["corrosion"], color="C3", ls="--",
               label=f"corrosion layer {st['corrosion']:g} um")
    ax.set_xlabel("radius (mm)")
    ax.set_ylabel("rotor wear at end of run (um)")
    ax.set_title("Rotor wear across the swept band: " + _title(st), fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, title="line pressure (applications)", title_fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_history(result: dict, path: Path) -> None:
    """Touched and worn-through fractions of the band against applications, per pressure."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs, st = result["runs"], result["settings"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.3), sharex=True)
    cmap = plt.get_cmap("viridis")
    for i, r in enumerate(runs):
        h, c = r["history"], cmap(i / max(len(runs) - 1, 1))
        apps = np.array(h["applications"])
        # coverage[k] holds during step k (from apps[k] to apps[k + 1])
        a1.step(apps, list(h["coverage"]) + [r["coverage_end"]], where="post", color=c,
                label=f"{r['pressure_MPa']:g} MPa")
        a2.plot(apps, h["cleaned_fraction"], color=c, label=f"{r['pressure_MPa']:g} MPa")
    a1.set_ylabel("touched fraction of the band")
    a2.set_ylabel("worn-through fraction of the band")
    for a in (a1, a2):
        a.axvline(st["applications"], color="k", ls="--", lw=1)
        a.set_xlabel("applications")
        a.set_ylim(-0.03, 1.05)
        a.grid(alpha=0.3)
    a2.legend(fontsize=8, title="line pressure", title_fontsize=8)
    fig.suptitle("Cleaning history: " + _title(st), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_pressure_maps(result: dict, path: Path, count: int = 3) -> None:
    """Pad pressure at the first application and at the end of the run, for the lowest,
    a middle and the highest pressure of the sweep (seen from the rotor)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs, st = result["runs"], result["settings"]
    pick = sorted({0, len(runs) // 2, len(runs) - 1})[:count]
    fig, axes = plt.subplots(2, len(pick), figsize=(3.3 * len(pick), 7.4), squeeze=False)
    for j, i in enumerate(pick):
        r = runs[i]
        x, y = np.array(r["pad_x_m"]) * 1e3, np.array(r["pad_y_m"]) * 1e3
        vmax = max(max(r["pressure_start_Pa"]), max(r["pressure_end_Pa"])) / 1e6
        for k, (key, when) in enumerate((("pressure_start_Pa", "1st application"),
                                         ("pressure_end_Pa", "end of run"))):
            ax = axes[k, j]
            pv = np.array(r[key]) / 1e6
            sc = ax.scatter(x, y, c=pv, s=14, cmap="inferno", vmin=0, vmax=vmax)
            ax.scatter(x[pv <= 0], y[pv <= 0], s=14, facecolors="none", edgecolors="0.6",
                       lw=0.5)
            ax.set_aspect("equal")
            ax.set_title(f"{r['pressure_MPa']:g} MPa line, {when}", fontsize=9)
            ax.set_xlabel("x (mm)")
            ax.set_ylabel("y (mm), rotor turns toward +y")
            fig.colorbar(sc, ax=ax, label="pad pressure (MPa)", shrink=0.8)
    fig.suptitle("Pad contact pressure (open circles: no contact): " + _title(st), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# -------------------------------------------------------------------------------- CLI --
def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        description=__doc__.splitlines()[0],
        epilog="Example: python studies/cleaning_pressure.py --pressures 0.5 1 2 4 "
               "--corrosion 25 --coning 30 --applications 20 --out docs")
    d = DEFAULTS
    ap.add_argument("--pressures", type=float, nargs="+", default=list(d["pressures"]),
                    help="line pressures, MPa (default %(default)s)")
    ap.add_argument("--corrosion", type=float, default=d["corrosion"],
                    help="corrosion layer thickness, um (default %(default)s)")
    ap.add_argument("--coning", type=float, default=d["coning"],
                    help="initial coning / radial taper across the band, um (default %(default)s)")
    ap.add_argument("--applications", type=int, default=d["applications"],
                    help="applications within which the band must be clean (default %(default)s)")
    ap.add_argument("--running-in", type=float, default=None,
                    help="run in at this line pressure (MPa) first (default: no running-in)")
    ap.add_argument("--running-in-seconds", type=float, default=d["running_in_seconds"])
    ap.add_argument("--k-corrosion", type=float, default=K_CORROSION,
                    help="wear coefficient of the corrosion layer, 1/Pa (default %(default)s)")
    ap.add_argument("--omega", type=float, default=d["omega"], help="rad/s (default %(default)s)")
    ap.add_argument("--app-seconds", type=float, default=d["app_seconds"],
                    help="drag seconds per application at omega (default %(default)s)")
    ap.add_argument("--mu", type=float, default=d["mu"])
    ap.add_argument("--size", type=float, default=d["size"], help="mesh size, mm")
    ap.add_argument("--dp-tol", type=float, default=d["dp_tol"],
                    help="largest relative pressure change per wear step (default %(default)s)")
    ap.add_argument("--contact-tol", type=float, default=d["contact_tol"],
                    help="relative tolerance of the contact solves (default %(default)s)")
    ap.add_argument("--rotor", choices=("rigid", "elastic"), default="rigid")
    ap.add_argument("--interface", choices=("fe", "condensed"), default=d["interface"],
                    help="FE contact solves, or the FE model condensed onto the pad's contact "
                         "nodes once (the same answer, much faster; the default)")
    add_executor_options(ap)
    ap.add_argument("--name", default="cleaning", help="prefix of the output files")
    ap.add_argument("--out", default="docs", help="writes OUT/data and OUT/figures")
    ap.add_argument("--no-figures", action="store_true")
    ap.add_argument("--replot", action="store_true",
                    help="no computation: rewrite the CSVs and redraw the figures from "
                         "OUT/data/NAME_sweep.json and NAME_pressure_maps.csv")
    return ap


def cli(argv=None) -> dict:
    a = _parser().parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(name)s %(message)s")
    logger.setLevel(logging.INFO)
    if a.replot:
        res = load_result(a.out, a.name)
        write_outputs(res, Path(a.out), a.name, figures=not a.no_figures)
        return res
    with study_executor(a.dask, a.workers) as executor:
        res = main(a.pressures, a.corrosion, a.coning, a.applications, executor, a.size, a.out,
                   running_in=a.running_in, running_in_seconds=a.running_in_seconds,
                   k_corrosion=a.k_corrosion, omega=a.omega, app_seconds=a.app_seconds,
                   mu=a.mu, rotor=a.rotor, dp_tol=a.dp_tol, name=a.name, figures=not a.no_figures,
                   interface=a.interface, contact_tol=a.contact_tol)
    for r in res["runs"]:
        n = r["applications_to_clean"]
        logger.info("%5.2f MPa: touched %.2f -> %.2f of the band, worn through %.2f, %s "
                    "(%d steps, %.0f s)", r["pressure_MPa"], r["coverage_start"],
                    r["coverage_end"], r["cleaned_fraction_end"],
                    f"clean after {n:.1f} applications" if n is not None else "not clean",
                    r["steps"], r["run_s"])
    logger.info("lowest line pressure that cleans within %d applications: %s MPa",
                res["settings"]["applications"], res["lowest_cleaning_pressure_MPa"])
    return res


if __name__ == "__main__":
    cli()
