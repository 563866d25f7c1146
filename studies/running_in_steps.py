"""Steps and time error of the default scene's running-in on several meshes (docs/wear.md).

The default scene (``geometry/scenes/default.toml``: one hour of drag at
1 MPa, 55 rad/s, mu 0.4, pad and rotor wearing, FE interface, gap offset) is
run with its ``mesh.size`` set to each of ``--sizes`` (mm; its other mesh
keys kept) and with each of ``--runs``, a numerics override per run:
``steps=60`` (equal steps), ``dp_tol=0.05``, ``wear_tol=3e-8`` (m),
``scheme=implicit_pad``, ``norm=l2`` (the step control's measure; a
step-controlled run is stored with the norm it ran with), or several joined
by ``+``; the scene's own numerics
are 60 equal steps, so a step control needs ``steps=none`` with it
(``steps=none+wear_tol=3e-8``, ``steps=none+scheme=implicit_pad``: the
automatic control, ``dp_tol = 0.05``, with the rotor's rings explicit).
Each run records its steps, contact solves, what limited its steps, CPU and
wall time, and the answer at the end time: the largest and the mean pad
wear, the largest contact pressure and the p r spread (max - min over mean,
nodes in contact), all of the end-of-step state.  Per size, a reference from
two equal-step runs, ``--ref`` and twice as many, by Richardson extrapolation
(backward Euler is first order): ``2 x(2M) - x(M)``.  Errors are relative to
it.

Each run is one JSON line in ``DIR/data/running_in_steps.jsonl``, and a run
already there (same size, settings and duration) is read back rather than
run again, so a sweep can be extended, interrupted and resumed.  Writes
``running_in_steps.json`` (every run with its errors) and the figure
``DIR/figures/running_in_steps.png`` (steps against mesh size per control,
and the p r spread's error against steps).

``python studies/running_in_steps.py --sizes 6 3 1.5 --runs steps=60
steps=none+wear_tol=1e-8+norm=l2 steps=none+dp_tol=0.05+norm=max --ref 64 --out docs``
(docs/wear.md gives the full list); ``main(...)`` returns the rows.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import logging
import time
from collections import Counter
from pathlib import Path

import numpy as np

from brakewear.wear import Run

logger = logging.getLogger(__name__)

KEYS = ("pad_max_um", "pad_mean_um", "p_max_MPa", "pr_spread")


def parse_run(text: str) -> dict:
    """``"steps=60+scheme=implicit"`` -> ``{"steps": 60, "scheme": "implicit"}``."""
    out = {}
    for part in text.split("+"):
        key, _, value = part.partition("=")
        if key not in ("steps", "dp_tol", "wear_tol", "scheme", "norm"):
            raise ValueError(f"run {text!r}: {key!r} is not one of steps, dp_tol, wear_tol, "
                             "scheme, norm")
        if value.lower() == "none":
            out[key] = None
        else:
            out[key] = int(value) if key == "steps" else value if key in ("scheme", "norm") \
                else float(value)
    return out


def run_one(size_mm: float, settings: dict, duration: float | None = None,
            resolution: bool = True) -> dict:
    """One run of the default scene at ``size_mm`` with the numerics ``settings``
    (``resolution=False``: without the scene's per-body mesh keys, the geometry's rule)."""
    from brakewear.interfaces import FEInterface
    from brakewear.scene import load_scene
    from brakewear.wear import wear_history

    sc = dataclasses.replace(load_scene("default"), mesh_size=size_mm * 1e-3)
    if not resolution:
        sc = dataclasses.replace(sc, resolution={})
    num = dataclasses.replace(sc.numerics, **settings)
    T = sc.duration if duration is None else duration
    pad_law, rotor_law = sc.wear_laws()
    t0, c0 = time.perf_counter(), time.process_time()
    model = sc.build_model()
    itf = FEInterface(model, sc.line_pressure, sc.interface.mu, num.tol)
    limits, solves, last = Counter(), 0, None
    for last in wear_history(
        Run(
            model,
            sc.line_pressure,
            sc.omega,
            T,
            pad_law,
            rotor_law,
            sc.interface.mu,
            numerics=num,
            interface=itf,
        )
    ):
        limits[last.limit] += 1
        solves += last.contact_solves
    A, r = itf.area, itf.r
    p, act = last.pressure_end, last.active_end
    pr = (p * r)[act]
    return {"size_mm": size_mm, "settings": settings, "duration_s": T,
            **({} if resolution else {"resolution": False}), "dofs": int(model.dofs),
            "steps": last.step, "contact_solves": solves, "limits": dict(limits),
            "pad_max_um": float(last.pad_wear.max() * 1e6),
            "pad_mean_um": float((last.pad_wear * A).sum() / A.sum() * 1e6),
            "p_max_MPa": float(p.max() / 1e6), "pr_spread": float(np.ptp(pr) / pr.mean()),
            "rotor_volume_error": abs(last.rotor_volume - last.rotor_archard)
            / last.rotor_archard,
            "cpu_s": time.process_time() - c0, "wall_s": time.perf_counter() - t0}


def _key(row: dict) -> str:
    return json.dumps([row["size_mm"], row["settings"], row["duration_s"],
                       row.get("resolution", True)], sort_keys=True)


def main(sizes=(6.0, 3.0, 1.5), runs=("steps=60",), ref: int = 128, out="docs",
         duration: float | None = None, figure: bool = True,
         cached: bool = False, resolution: bool = True) -> list[dict]:
    """Run (or read back) every size x run and the references; returns the rows with
    their errors against the size's reference (``cached``: only the runs already
    in the file, none computed; ``resolution=False``: the meshes without the
    scene's per-body keys, for quick checks)."""
    out = Path(out)
    (out / "data").mkdir(parents=True, exist_ok=True)
    cache_path = out / "data" / "running_in_steps.jsonl"
    cache = {}
    if cache_path.exists():
        for line in cache_path.read_text().splitlines():
            row = json.loads(line)
            cache[_key(row)] = row
    T = duration if duration is not None else _scene_duration()

    def get(size, settings):
        settings = _resolved(settings)
        k = _key({"size_mm": size, "settings": settings, "duration_s": T,
                  "resolution": resolution})
        if k not in cache:
            if cached:
                return None
            logger.info("size %g mm, %s", size, settings)
            cache[k] = run_one(size, settings, T, resolution)
            with open(cache_path, "a") as f:
                f.write(json.dumps(cache[k]) + "\n")
        return cache[k]

    rows = []
    for size in sizes:
        coarse, fine = get(size, {"steps": ref}), get(size, {"steps": 2 * ref})
        if coarse is None or fine is None:
            continue
        reference = {k: 2 * fine[k] - coarse[k] for k in KEYS}
        for text in runs:
            got = get(size, parse_run(text))
            if got is None:
                continue
            row = dict(got, run=text, reference=reference)
            row["errors"] = {k: row[k] / reference[k] - 1 for k in KEYS}
            rows.append(row)
    (out / "data" / "running_in_steps.json").write_text(json.dumps(rows, indent=1))
    if figure:
        _figure(rows, out / "figures" / "running_in_steps.png")
    return rows


def _resolved(settings: dict) -> dict:
    """``settings`` with the step control's norm named when the run is step-controlled
    (the default's, :class:`~brakewear.Numerics`), so that a stored run keeps the
    norm it was run with."""
    from brakewear import Numerics

    if settings.get("steps", 0) is not None or "norm" in settings:
        return settings
    return {**settings, "norm": Numerics().norm}


def _scene_duration() -> float:
    from brakewear.scene import load_scene

    return load_scene("default").duration


def _figure(rows, path: Path) -> None:
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    path.parent.mkdir(parents=True, exist_ok=True)
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 5))
    for run in dict.fromkeys(r["run"] for r in rows):
        sel = sorted((r for r in rows if r["run"] == run), key=lambda r: r["size_mm"])
        label = run.replace("steps=none+", "step control: ").replace("steps=", "equal steps: ")
        a.plot([r["size_mm"] for r in sel], [r["steps"] for r in sel], "o-", label=label)
        b.plot([r["steps"] for r in sel], [100 * abs(r["errors"]["pr_spread"]) for r in sel],
               "o", label=label)
        for r in sel:
            b.annotate(f"{r['size_mm']:g} mm", (r["steps"], 100 * abs(r["errors"]["pr_spread"])),
                       fontsize=7)
    a.set(xlabel="mesh size (mm)", ylabel="steps", xscale="log", yscale="log",
          title="steps of the one-hour running-in")
    b.set(xlabel="steps", ylabel="|error of the p r spread at the end| (%)", xscale="log",
          yscale="log", title="against the equal-step Richardson reference")
    for axis in (a.xaxis, a.yaxis, b.xaxis, b.yaxis):
        axis.set_major_formatter(ScalarFormatter())
    for axis in (a.yaxis, b.yaxis):
        axis.set_minor_formatter(ScalarFormatter())
    for axis in (a.xaxis, b.xaxis):
        axis.set_minor_formatter(NullFormatter())
    a.set_xticks(sorted({r["size_mm"] for r in rows}))
    lo, hi = min(r["steps"] for r in rows), max(r["steps"] for r in rows)
    b.set_xticks([n for n in (10, 20, 50, 100, 200, 500, 1000, 2000) if lo / 2 <= n <= 2 * hi])
    b.axhline(0.5, color="grey", ls=":")
    handles, labels = a.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7)
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _cli() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=float, nargs="+", default=[6.0, 3.0, 1.5])
    ap.add_argument("--runs", nargs="+", default=["steps=60"])
    ap.add_argument("--ref", type=int, default=128, help="equal steps of the coarser reference")
    ap.add_argument("--duration", type=float, default=None, help="s (default: the scene's)")
    ap.add_argument("--out", default="docs")
    ap.add_argument("--cached", action="store_true",
                    help="only the runs already in DIR/data/running_in_steps.jsonl")
    a = ap.parse_args()
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    rows = main(a.sizes, a.runs, a.ref, a.out, a.duration, cached=a.cached)
    print(f"{'size':>5} {'run':>28} {'steps':>5} {'solves':>6} {'cpu s':>7} "
          + " ".join(f"{k:>12}" for k in KEYS))
    for r in rows:
        print(f"{r['size_mm']:5g} {r['run']:>28} {r['steps']:5d} {r['contact_solves']:6d} "
              f"{r['cpu_s']:7.1f} " + " ".join(f"{100 * r['errors'][k]:+11.2f}%" for k in KEYS))


if __name__ == "__main__":
    _cli()
