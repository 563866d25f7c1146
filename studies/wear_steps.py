"""Step convergence of the wear loop (the numbers of docs/wear.md, "Step convergence").

The default brake (realistic pad, rigid rotor, ``--size`` mm) runs in under
1 MPa, 55 rad/s, mu = 0.4, pad Archard k = 5e-15 1/Pa, from first contact.
The pad wear profile at a fixed end time ``T`` is computed with N equal
steps (``steps=N``) and compared with a fine-step reference: the Richardson
extrapolation ``2 h(2M) - h(M)`` of two fine runs (both schemes are first
order), so that the reference's own error does not flatter the finest runs.
Error = max |h_N - h_ref| / max h_ref over the pad's friction nodes.

* ``explicit`` and ``implicit`` over a short horizon ``T`` chosen so that the
  coarsest explicit step stays below the explicit stability limit (the
  largest fixed step is about 1.6 x the monotone bound: it oscillates but
  decays);
* ``implicit_long``: the implicit scheme over ten times that horizon, where
  the explicit steps would be far beyond the stability limit;
* ``control``: the automatic step control (``steps=None``) at several
  ``dp_tol``: contact solves (including rejected tries and the first solve)
  against the error, next to the fixed-step runs' solves against error.

Run ``python studies/wear_steps.py [--out DIR] [--size MM] [--quick]``;
writes ``wear_steps.json`` and ``wear_steps.csv`` into ``DIR/data`` and
``wear_steps.png`` into ``DIR/figures`` (default DIR: docs).
"""
from __future__ import annotations

import argparse
import csv
import json
import logging
import time
from pathlib import Path

import numpy as np

from brakewear.scene import BrakeModel
from brakewear.simulate import FEInterface, wear_history
from brakewear.wear import WearLaw

logger = logging.getLogger(__name__)

P_LINE, OMEGA, MU, K_PAD = 1e6, 55.0, 0.4, 5e-15


def run(model, itf, scheme: str, duration: float, steps: int | None = None,
        **kw) -> dict:
    """One history to ``duration``: the final pad wear, contact solves and time."""
    t0 = time.perf_counter()
    last, solves, n = None, 1, 0   # the first contact solve, before step 1
    for last in wear_history(model, P_LINE, OMEGA, duration, WearLaw(K_PAD), None, MU,
                             steps=steps, scheme=scheme, interface=itf, **kw):
        solves += last.contact_solves
        n += 1
    return {"pad_wear": last.pad_wear, "steps": n, "contact_solves": solves,
            "time": last.time, "run_s": time.perf_counter() - t0}


def error(h: np.ndarray, ref: np.ndarray) -> float:
    """Max-norm error of a wear profile relative to the reference's largest wear."""
    return float(np.abs(h - ref).max() / np.abs(ref).max())


def rate(dt, err) -> float:
    """Observed order: slope of log err against log dt."""
    return float(np.polyfit(np.log(dt), np.log(err), 1)[0])


def convergence(model, itf, scheme: str, duration: float, counts, ref_steps: int) -> dict:
    """Fixed-step runs with ``counts`` steps against the Richardson reference."""
    fine = run(model, itf, scheme, duration, ref_steps)
    finer = run(model, itf, scheme, duration, 2 * ref_steps)
    ref = 2.0 * finer["pad_wear"] - fine["pad_wear"]
    rows = []
    for n in counts:
        r = run(model, itf, scheme, duration, n)
        rows.append({"scheme": scheme, "duration_s": duration, "steps": n,
                     "dt_s": duration / n, "contact_solves": r["contact_solves"],
                     "error": error(r["pad_wear"], ref), "run_s": r["run_s"]})
        logger.info("%s T=%g N=%d err %.3e", scheme, duration, n, rows[-1]["error"])
    dt = [r["dt_s"] for r in rows]
    err = [r["error"] for r in rows]
    return {"scheme": scheme, "duration_s": duration, "rows": rows, "rate": rate(dt, err),
            "reference_steps": [ref_steps, 2 * ref_steps],
            "reference_error_estimate": error(finer["pad_wear"], ref),
            "max_wear_m": float(np.abs(ref).max()), "ref": ref}


def stability_bound(itf) -> float:
    """The explicit scheme's monotone step bound (the loop's Gershgorin estimate), s."""
    slope = WearLaw(K_PAD).rate(1.0, OMEGA * itf.r)
    return float(1.0 / (slope * itf.normal_stiffness / itf.area).max())


def main(size_mm: float = 8.0, out: str | Path = "docs", quick: bool = False,
         figures: bool = True, duration: float | None = None) -> dict:
    """Run the study; returns the results (also written to ``out``).

    ``quick``: step counts 4..16 against a 64/128-step reference (for tests).
    ``duration``: the short horizon (default 1.6 x 4 x the monotone explicit bound).
    """
    out = Path(out)
    t0 = time.perf_counter()
    model = BrakeModel("default", size=size_mm * 1e-3, rotor="rigid")
    itf = FEInterface(model, P_LINE, MU)
    bound = stability_bound(itf)
    T = float(duration) if duration is not None else round(1.6 * 4 * bound, 1)
    counts = (4, 8, 16) if quick else (4, 8, 16, 32, 64)
    ref_steps = 64 if quick else 256
    res = {"settings": {"size_mm": size_mm, "dofs": int(model.dofs), "rotor": "rigid",
                        "line_pressure_Pa": P_LINE, "omega_rad_s": OMEGA, "mu": MU,
                        "k_pad": K_PAD, "pad_friction_nodes": int(itf.area.size),
                        "explicit_monotone_bound_s": bound, "duration_s": T,
                        "long_duration_s": 10 * T}}
    studies = {"explicit": convergence(model, itf, "explicit", T, counts, ref_steps),
               "implicit": convergence(model, itf, "implicit", T, counts, ref_steps),
               "implicit_long": convergence(model, itf, "implicit", 10 * T, counts, ref_steps)}
    # the automatic step control against the same references
    control = []
    for scheme, key in (("explicit", "explicit"), ("implicit", "implicit"),
                        ("implicit", "implicit_long")):
        dur = studies[key]["duration_s"]
        for tol in ((0.2, 0.05) if quick else (0.4, 0.2, 0.1, 0.05, 0.02)):
            r = run(model, itf, scheme, dur, None, dp_tol=tol)
            control.append({"scheme": scheme, "case": key, "duration_s": dur, "dp_tol": tol,
                            "steps": r["steps"], "contact_solves": r["contact_solves"],
                            "error": error(r["pad_wear"], studies[key]["ref"]),
                            "run_s": r["run_s"]})
            logger.info("control %s dp_tol=%g: %d solves, err %.3e", key, tol,
                        r["contact_solves"], control[-1]["error"])
    for s in studies.values():
        s.pop("ref")
    res.update(studies)
    res["control"] = control
    res["run_s"] = time.perf_counter() - t0
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / "wear_steps.json").write_text(json.dumps(res, indent=2))
    with open(out / "data" / "wear_steps.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "scheme", "duration_s", "control", "steps", "dt_s",
                    "contact_solves", "error"])
        for key, s in studies.items():
            for r in s["rows"]:
                w.writerow([key, r["scheme"], r["duration_s"], "fixed", r["steps"], r["dt_s"],
                            r["contact_solves"], r["error"]])
        for r in control:
            w.writerow([r["case"], r["scheme"], r["duration_s"], f"dp_tol={r['dp_tol']}",
                        r["steps"], "", r["contact_solves"], r["error"]])
    if figures:
        figure(res, out / "figures" / "wear_steps.png")
    return res


def figure(res: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    colours = {"explicit": "C0", "implicit": "C1", "implicit_long": "C2"}
    for key in ("explicit", "implicit", "implicit_long"):
        s = res[key]
        dt = [r["dt_s"] for r in s["rows"]]
        e = [r["error"] for r in s["rows"]]
        lab = f"{key.replace('_', ' ')} (T = {s['duration_s']:g} s), rate {s['rate']:.2f}"
        a.loglog(dt, e, "o-", color=colours[key], label=lab)
        b.loglog([r["contact_solves"] for r in s["rows"]], e, "o-", color=colours[key],
                 label=f"{key.replace('_', ' ')}: fixed steps")
        c = [r for r in res["control"] if r["case"] == key]
        b.loglog([r["contact_solves"] for r in c], [r["error"] for r in c], "s--",
                 color=colours[key], mfc="none", label=f"{key.replace('_', ' ')}: dp_tol control")
        for r in c:
            b.annotate(f"{r['dp_tol']:g}", (r["contact_solves"], r["error"]), fontsize=7,
                       xytext=(3, 3), textcoords="offset points", color=colours[key])
    bound = res["settings"]["explicit_monotone_bound_s"]
    a.axvline(bound, color="gray", ls=":", lw=1)
    a.text(bound, a.get_ylim()[0] * 1.5, " explicit monotone bound", color="gray", fontsize=8)
    a.set_xlabel("step dt (s)")
    a.set_ylabel("max |h - h_ref| / max h_ref (pad wear at T)")
    a.set_title("Wear profile error against the step")
    a.legend(fontsize=8, loc="upper left")
    a.grid(True, which="both", alpha=0.3)
    b.set_xlabel("contact solves (incl. rejected tries)")
    b.set_ylabel("error")
    b.set_title("Cost: fixed steps vs automatic control (labels: dp_tol)")
    b.legend(fontsize=7)
    b.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _cli(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--size", type=float, default=8.0, help="mesh size, mm (default 8)")
    ap.add_argument("--quick", action="store_true", help="fewer and shorter runs")
    ap.add_argument("--no-figures", action="store_true")
    a = ap.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    res = main(a.size, a.out, a.quick, not a.no_figures)
    for key in ("explicit", "implicit", "implicit_long"):
        s = res[key]
        logging.info("%s (T = %g s): rate %.3f, errors %s", key, s["duration_s"], s["rate"],
                     " ".join(f"{r['error']:.2e}" for r in s["rows"]))
    return 0


if __name__ == "__main__":
    raise SystemExit(_cli())
