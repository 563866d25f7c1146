"""The fidelity ladder: the same running-in at four levels of modelling.

The running-in of ``studies/speed_vs_error.py`` (default brake, 1 MPa line
pressure, 55 rad/s, mu = 0.4, Archard pad k = 5e-15 1/Pa, rotor 5e-16 1/Pa,
implicit Euler with ``steps`` equal steps, gap offset) at one mesh size, run
at four levels, each adding one thing to the one before:

1. ``rigid rotor``   -- the rotor is the plane z = 0 (nothing meshed);
2. ``elastic rotor`` -- the rotor's inboard half meshed, clamped at its hat;
3. ``piston body``   -- the piston meshed and tied to the backplate, hydraulic
   pressure on its back (instead of a uniform traction on its footprint);
4. ``thermal``       -- staggered heat conduction in pad and rotor (frictional
   heat partitioned by effusivity, contact conductance 1e5 W/m^2K), thermal
   strain in the contact; the wear law has no temperature dependence here,
   so the difference is the thermal distortion alone.

For each level: the cost (model build + wear history, s, all in one
process) and the difference of its results from the level below and from
the top level (the same metrics as the speed-vs-error study: relative L2 of
pad wear and pressure at the top level's pad nodes, effective radius,
rotor wear profile).

Run ``python studies/fidelity.py [--out DIR] [--quick]``; writes
``fidelity.json`` (DIR/data) and ``fidelity.png`` (DIR/figures).
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import logging
import time
from pathlib import Path

import numpy as np

from brakewear.laws.base import WearLaw

logger = logging.getLogger(__name__)


def _sve():
    path = Path(__file__).with_name("speed_vs_error.py")
    spec = importlib.util.spec_from_file_location("speed_vs_error", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


LEVELS = [
    ("rigid rotor", {"rotor": "rigid"}),
    ("elastic rotor", {}),
    ("piston body", {"piston": "body"}),
    ("thermal", {"piston": "body", "thermal": True}),
]


def main(size: float = 8e-3, steps: int = 16, duration: float = 120.0, wear_scale: float = 10.0,
         out: str | Path | None = "docs", figures: bool = True, repeats: int = 1,
         **run) -> dict:
    """Run the four levels in this process; returns (and writes under ``out``) the results.

    ``repeats`` > 1 runs the ladder that many times (levels interleaved, so
    that a change of machine load hits all of them) and reports the median
    wall and CPU times; the results are those of the first pass (the runs
    are deterministic).  ``wear_scale`` multiplies both wear coefficients:
    a gap-offset run depends on ``k t`` only, so ``k x 10`` over ``t / 10``
    gives the same wear with a tenth of the frictional heat.
    """
    sve = _sve()
    pad, rotor = (WearLaw(sve.PAD.k * wear_scale), WearLaw(sve.ROTOR.k * wear_scale))
    state0 = sve.machine_state()
    t_all = time.perf_counter()
    res, times = [], {n: [] for n, _ in LEVELS}
    for rep in range(repeats):
        for name, kw in LEVELS:
            logger.info("running %s (pass %d)", name, rep + 1)
            r = sve.run_case(size, duration, steps, **kw, pad_law=pad, rotor_law=rotor, **run)
            times[name].append((r["run_s"], r["cpu_s"]))
            if rep == 0:
                res.append({"name": name, **r})
    for r in res:
        t = np.array(times[r["name"]])
        r["run_s"], r["cpu_s"] = float(np.median(t[:, 0])), float(np.median(t[:, 1]))
        r["run_s_all"], r["cpu_s_all"] = t[:, 0].tolist(), t[:, 1].tolist()
    top = res[-1]
    for i, r in enumerate(res):
        r["difference_vs_top"] = sve.errors(r, top)
        r["difference_vs_previous"] = sve.errors(r, res[i - 1]) if i else None
        r["cost_ratio_vs_elastic"] = r["run_s"] / res[1]["run_s"]
    result = {
        "case": {"geometry": "default", "size_m": size, "steps": steps, "scheme": "implicit",
                 "repeats": repeats, "wear_scale": wear_scale,
                 "duration_s": duration, **sve.RUN, **run, "pad_law_k": pad.k,
                 "rotor_law_k": rotor.k, "contact_conductance": 1e5},
        "levels": [{k: v for k, v in r.items() if not k.startswith("_")} for r in res],
        "profiles": _profiles(res),
        "machine_before": state0, "machine_after": sve.machine_state(),
        "total_s": time.perf_counter() - t_all, "command": "python studies/fidelity.py",
    }
    if out is not None:
        out = Path(out)
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "fidelity.json").write_text(json.dumps(result, indent=2, default=float))
        if figures:
            (out / "figures").mkdir(parents=True, exist_ok=True)
            plot(result, out / "figures" / "fidelity.png")
    return result


def _profiles(res: list[dict]) -> dict:
    """Pad wear and pressure against radius: area-weighted means over each ring of
    pad nodes of equal radius (the pad meshes are structured in r), and the nodes."""
    out = {}
    for r in res:
        rr = np.hypot(*r["_xy"])
        rows, k = np.unique(np.round(rr, 5), return_inverse=True)
        A = r["_area"]
        w = np.bincount(k, A)
        out[r["name"]] = {
            "row_r_m": (np.bincount(k, A * rr) / w).tolist(),
            "pad_wear_m": (np.bincount(k, A * r["_pad_wear"]) / w).tolist(),
            "pressure_Pa": (np.bincount(k, A * r["_pressure"]) / w).tolist(),
            "nodes_r_m": rr.tolist(), "nodes_pad_wear_m": r["_pad_wear"].tolist(),
            "rotor_r_m": r["_rotor_r"].tolist(), "rotor_wear_m": r["_rotor_wear"].tolist()}
    return out


def plot(result: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    lv = result["levels"]
    names = [r["name"] for r in lv]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.8))
    x = np.arange(len(lv))
    bars = ax[0].bar(x, [r["run_s"] for r in lv], color=["C3", "C0", "C2", "C1"])
    for b, r in zip(bars, lv):
        ax[0].annotate(f"{r['run_s']:.1f} s wall\n{r.get('cpu_s', np.nan):.1f} s CPU\n"
                       f"{r['dofs']} DOFs",
                       (b.get_x() + b.get_width() / 2, b.get_height()), ha="center",
                       va="bottom", fontsize=8)
    ax[0].set_xticks(x, names, fontsize=8)
    ax[0].set_ylabel("run time (s, build + wear history)")
    ax[0].set_title("cost of each level", fontsize=10)
    ax[0].margins(y=0.2)
    w = 0.38
    d_prev = [100 * r["difference_vs_previous"]["pad_wear_l2"]
              if r["difference_vs_previous"] else np.nan for r in lv]
    d_top = [100 * r["difference_vs_top"]["pad_wear_l2"] for r in lv]
    b1 = ax[1].bar(x - w / 2, d_prev, w, label="vs the level below")
    b2 = ax[1].bar(x + w / 2, d_top, w, label="vs the top level (thermal)")
    for bb in (b1, b2):
        for b in bb:
            if not np.isfinite(b.get_height()):
                continue
            ax[1].annotate(f"{b.get_height():.1f}", (b.get_x() + b.get_width() / 2,
                                                    b.get_height()), ha="center",
                           va="bottom", fontsize=8)
    ax[1].set_xticks(x, names, fontsize=8)
    ax[1].set_ylabel("pad wear difference (relative L2, %)")
    ax[1].set_title("what each level changes", fontsize=10)
    ax[1].legend(fontsize=8)
    pr = result["profiles"]
    for n, c in zip(names, ["C3", "C0", "C2", "C1"]):
        ax[2].plot(1e3 * np.asarray(pr[n]["row_r_m"]), 1e6 * np.asarray(pr[n]["pad_wear_m"]),
                   "--" if n == "rigid rotor" else "-", color=c, lw=2.5 if n == "rigid rotor"
                   else 1.5, label=f"{n} (mean per ring of nodes)", zorder=3)
        if "nodes_r_m" in pr[n]:
            ax[2].plot(1e3 * np.asarray(pr[n]["nodes_r_m"]),
                       1e6 * np.asarray(pr[n]["nodes_pad_wear_m"]), ".", color=c, ms=3,
                       alpha=0.5)
    ax[2].set_xlabel("radius (mm)")
    ax[2].set_ylabel("pad wear (um): dots nodes, lines ring means")
    c = result["case"]
    ax[2].set_title(f"pad wear after {c['duration_s']:g} s, size {c['size_m'] * 1e3:g} mm",
                    fontsize=10)
    ax[2].legend(fontsize=8)
    ax[2].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def table(result: dict) -> str:
    lines = ["| level | DOFs | wall s | CPU s | wall / elastic | pad wear diff vs below | "
             "vs top | pressure diff vs top | r_eff vs top | rotor wear vs top |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in result["levels"]:
        p, t = r["difference_vs_previous"], r["difference_vs_top"]
        lines.append(f"| {r['name']} | {r['dofs']} | {r['run_s']:.1f} | "
                     f"{r.get('cpu_s', float('nan')):.1f} | "
                     f"{r['cost_ratio_vs_elastic']:.2f} | "
                     + (f"{p['pad_wear_l2']:.2%}" if p else "-")
                     + f" | {t['pad_wear_l2']:.2%} | {t['pressure_l2']:.2%} | "
                     f"{t['r_eff']:+.2%} | {t['rotor_wear_l2']:.2%} |")
    return "\n".join(lines)


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs", help="writes OUT/data and OUT/figures")
    ap.add_argument("--quick", action="store_true", help="tiny settings (a smoke run)")
    ap.add_argument("--size", type=float, default=8e-3, help="mesh size (m)")
    ap.add_argument("--steps", type=int, default=16)
    ap.add_argument("--duration", type=float, default=120.0)
    ap.add_argument("--repeats", type=int, default=3, help="median of this many passes")
    ap.add_argument("--replot", metavar="JSON", help="only redraw the figure from a JSON")
    a = ap.parse_args(argv)
    if a.replot:
        res = json.loads(Path(a.replot).read_text())
        (Path(a.out) / "figures").mkdir(parents=True, exist_ok=True)
        plot(res, Path(a.out) / "figures" / "fidelity.png")
        print(table(res))
        return res
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(name)s %(message)s")
    logger.setLevel(logging.INFO)
    kw = (dict(size=1.5e-2, steps=2, repeats=1) if a.quick
          else dict(size=a.size, steps=a.steps, repeats=a.repeats))
    res = main(out=a.out, duration=a.duration, **kw)
    print(table(res))
    return res


if __name__ == "__main__":
    _cli()
