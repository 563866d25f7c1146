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
* ``implicit_100``: the implicit scheme over a hundred times the short
  horizon (hours: the realistic running-in case);
* ``control``: the automatic step control (``steps=None``) at several
  ``dp_tol`` and at several ``wear_tol`` (fractions of the reference's
  largest wear): contact solves (including rejected tries and the first
  solve) against the error, next to the fixed-step runs' solves against error.

Two errors per run: ``error`` at the end time ``T`` (against the Richardson
reference), and ``history_error``, the largest wear error at any of the
run's own step times, max_n max_i |h_n - h_ref(t_n)| / max h_ref(T), against
a reference history from the ``wear_tol`` control at a tolerance 150
times below the study's smallest (interpolated linearly in time; its own
error is estimated against a run at 4 x its tolerance).

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

from brakewear.interfaces import FEInterface
from brakewear.laws.base import WearLaw
from brakewear.model import BrakeModel
from brakewear.wear import WEAR_TOL_GROWTH, Numerics, Run, wear_history

logger = logging.getLogger(__name__)

P_LINE, OMEGA, MU, K_PAD = 1e6, 55.0, 0.4, 5e-15
#: wear_tol of the reference history, as a fraction of the largest final wear
#: (``--quick``: five times larger)
HIST_REF_TOL = 2e-6
CASES = ("explicit", "implicit", "implicit_long", "implicit_100")


def run(model, itf, scheme: str, duration: float, steps: int | None = None,
        **kw) -> dict:
    """One history to ``duration``: the final pad wear, the history (step times
    ``t`` and pad wear ``H`` per step, from t = 0), contact solves and time.
    ``kw`` are further :class:`~brakewear.Numerics` settings (``dp_tol``, ``wear_tol``)."""
    t0 = time.perf_counter()
    last, solves, n = None, 0, 0   # the first solve is counted in the first record
    t, H = [0.0], [np.zeros(itf.area.size)]
    for last in wear_history(
        Run(
            model,
            P_LINE,
            OMEGA,
            duration,
            WearLaw(K_PAD),
            None,
            MU,
            interface=itf,
            numerics=Numerics(steps=steps, scheme=scheme, **kw),
        )
    ):
        solves += last.contact_solves
        n += 1
        t.append(last.time)
        H.append(last.pad_wear.copy())
    return {"pad_wear": last.pad_wear, "steps": n, "contact_solves": solves,
            "time": last.time, "run_s": time.perf_counter() - t0,
            "t": np.array(t), "H": np.array(H)}


def history_error(r: dict, ref: dict, scale: float) -> float:
    """Largest wear error at the run's step times against the reference history
    (linear in time between its steps), relative to ``scale`` (m)."""
    R = np.stack([np.interp(r["t"], ref["t"], ref["H"][:, i])
                  for i in range(ref["H"].shape[1])], axis=1)
    return float(np.abs(r["H"] - R).max() / scale)


def error(h: np.ndarray, ref: np.ndarray) -> float:
    """Max-norm error of a wear profile relative to the reference's largest wear."""
    return float(np.abs(h - ref).max() / np.abs(ref).max())


def rate(dt, err) -> float:
    """Observed order: slope of log err against log dt."""
    return float(np.polyfit(np.log(dt), np.log(err), 1)[0])


def convergence(model, itf, scheme: str, duration: float, counts, ref_steps: int,
                hist_tol: float = HIST_REF_TOL) -> dict:
    """Fixed-step runs with ``counts`` steps against the Richardson reference."""
    fine = run(model, itf, scheme, duration, ref_steps)
    finer = run(model, itf, scheme, duration, 2 * ref_steps)
    ref = 2.0 * finer["pad_wear"] - fine["pad_wear"]
    hmax = float(np.abs(ref).max())
    # the reference history: the wear_tol control far below the study's tolerances
    href = run(model, itf, scheme, duration, None, wear_tol=hist_tol * hmax)
    hchk = run(model, itf, scheme, duration, None, wear_tol=4 * hist_tol * hmax)
    rows = []
    for n in counts:
        r = run(model, itf, scheme, duration, n)
        rows.append({"scheme": scheme, "duration_s": duration, "steps": n,
                     "dt_s": duration / n, "contact_solves": r["contact_solves"],
                     "error": error(r["pad_wear"], ref),
                     "history_error": history_error(r, href, hmax), "run_s": r["run_s"]})
        logger.info("%s T=%g N=%d err %.3e hist %.3e", scheme, duration, n, rows[-1]["error"],
                    rows[-1]["history_error"])
    dt = [r["dt_s"] for r in rows]
    err = [r["error"] for r in rows]
    return {"scheme": scheme, "duration_s": duration, "rows": rows, "rate": rate(dt, err),
            "reference_steps": [ref_steps, 2 * ref_steps],
            "reference_error_estimate": error(finer["pad_wear"], ref),
            "history_reference": {"wear_tol_m": hist_tol * hmax, "steps": href["steps"],
                                  "error_estimate": history_error(hchk, href, hmax),
                                  "final_error": error(href["pad_wear"], ref)},
            "max_wear_m": hmax, "ref": ref, "href": href}


def stability_bound(itf) -> float:
    """The explicit scheme's monotone step bound (the loop's Gershgorin estimate), s."""
    slope = WearLaw(K_PAD).rate(1.0, OMEGA * itf.r)
    return float(1.0 / (slope * itf.normal_stiffness / itf.area).max())


def main(size_mm: float = 8.0, out: str | Path = "docs", quick: bool = False,
         figures: bool = True, duration: float | None = None) -> dict:
    """Run the study; returns the results (also written to ``out``).

    ``quick``: step counts 4..16 against a 64/128-step reference and a reference
    history at five times the tolerance (for tests).
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
    hist = HIST_REF_TOL * (5 if quick else 1)
    res = {"settings": {"size_mm": size_mm, "dofs": int(model.dofs), "rotor": "rigid",
                        "line_pressure_Pa": P_LINE, "omega_rad_s": OMEGA, "mu": MU,
                        "k_pad": K_PAD, "pad_friction_nodes": int(itf.area.size),
                        "explicit_monotone_bound_s": bound, "duration_s": T,
                        "long_duration_s": 10 * T, "longer_duration_s": 100 * T,
                        "wear_tol_growth_max": WEAR_TOL_GROWTH}}
    studies = {
        "explicit": convergence(model, itf, "explicit", T, counts, ref_steps, hist),
        "implicit": convergence(model, itf, "implicit", T, counts, ref_steps, hist),
        "implicit_long": convergence(model, itf, "implicit", 10 * T, counts, ref_steps, hist),
        "implicit_100": convergence(model, itf, "implicit", 100 * T, counts, ref_steps, hist),
    }
    # the automatic step controls against the same references
    control = []
    dp_tols = (0.2, 0.05) if quick else (0.4, 0.2, 0.1, 0.05, 0.02)
    wear_fracs = (1e-2, 1e-3) if quick else (3e-2, 1e-2, 3e-3, 1e-3, 3e-4)
    for key in CASES:
        s = studies[key]
        dur, scheme, hmax = s["duration_s"], s["scheme"], s["max_wear_m"]
        for kw in ([{"dp_tol": t} for t in dp_tols]
                   + [{"wear_tol": f * hmax} for f in wear_fracs]):
            r = run(model, itf, scheme, dur, None, **kw)
            name, tol = next(iter(kw.items()))
            control.append({"scheme": scheme, "case": key, "duration_s": dur, "control": name,
                            "tol": tol, "wear_tol_fraction": tol / hmax
                            if name == "wear_tol" else None,
                            "steps": r["steps"], "contact_solves": r["contact_solves"],
                            "error": error(r["pad_wear"], s["ref"]),
                            "history_error": history_error(r, s["href"], hmax),
                            "run_s": r["run_s"]})
            logger.info("control %s %s=%.3g: %d solves, err %.3e, hist %.3e", key, name, tol,
                        r["contact_solves"], control[-1]["error"], control[-1]["history_error"])
    for s in studies.values():
        s.pop("ref")
        s.pop("href")
    res.update(studies)
    res["control"] = control
    res["run_s"] = time.perf_counter() - t0
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "data" / "wear_steps.json").write_text(json.dumps(res, indent=2))
    with open(out / "data" / "wear_steps.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "scheme", "duration_s", "control", "steps", "dt_s",
                    "contact_solves", "error", "history_error"])
        for key, s in studies.items():
            for r in s["rows"]:
                w.writerow([key, r["scheme"], r["duration_s"], "fixed", r["steps"], r["dt_s"],
                            r["contact_solves"], r["error"], r["history_error"]])
        for r in control:
            label = (f"dp_tol={r['tol']}" if r["control"] == "dp_tol"
                     else f"wear_tol={r['wear_tol_fraction']:g}*max_wear")
            w.writerow([r["case"], r["scheme"], r["duration_s"], label, r["steps"], "",
                        r["contact_solves"], r["error"], r["history_error"]])
    if figures:
        figure(res, out / "figures" / "wear_steps.png")
    return res


def figure(res: dict, path: Path) -> None:
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(16, 5))
    colours = {"explicit": "C0", "implicit": "C1", "implicit_long": "C2", "implicit_100": "C3"}
    for key in CASES:
        s = res[key]
        col, name = colours[key], f"{key.replace('_', ' ')} (T = {s['duration_s']:g} s)"
        dt = [r["dt_s"] for r in s["rows"]]
        a.loglog(dt, [r["error"] for r in s["rows"]], "o-", color=col,
                 label=f"{name}, rate {s['rate']:.2f}")
        for ax, err in ((b, "error"), (c, "history_error")):
            ax.loglog([r["contact_solves"] for r in s["rows"]], [r[err] for r in s["rows"]],
                      "o-", color=col, label=f"{name}: fixed" if ax is b else None)
            for ctl, mk, ls in (("dp_tol", "s", ":"), ("wear_tol", "^", "--")):
                rows = [r for r in res["control"] if r["case"] == key and r["control"] == ctl]
                ax.loglog([r["contact_solves"] for r in rows], [r[err] for r in rows], mk + ls,
                          color=col, mfc="none",
                          label=f"{key.replace('_', ' ')}: {ctl}" if ax is b else None)
    bound = res["settings"]["explicit_monotone_bound_s"]
    a.axvline(bound, color="gray", ls=":", lw=1)
    a.text(bound, a.get_ylim()[1] / 1.5, " explicit monotone bound", color="gray", fontsize=8)
    a.set_xlabel("step dt (s)")
    a.set_ylabel("max |h - h_ref| / max h_ref (pad wear at T)")
    a.set_title("Fixed steps: wear error at T against the step")
    a.legend(fontsize=7, loc="lower left")
    b.set_title("Error at the end time T against cost")
    b.set_ylabel("max_i |h_i(T) - h_ref,i(T)| / max h_ref(T)")
    b.legend(fontsize=6, ncol=2)
    c.set_title("Error over the history (every step) against cost")
    c.set_ylabel("max_n max_i |h_i(t_n) - h_ref,i(t_n)| / max h_ref(T)")
    for ax in (b, c):
        ax.set_xlabel("contact solves (incl. rejected tries and the first)")
        ax.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        lim = ax.get_xlim()
        ax.set_xticks([t for t in (3, 5, 10, 20, 50, 100, 200, 500) if lim[0] <= t <= lim[1]])
        ax.set_xlim(lim)
    for ax in (a, b, c):
        ax.grid(True, which="both", alpha=0.3)
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
    for key in CASES:
        s = res[key]
        logging.info("%s (T = %g s): rate %.3f, errors %s", key, s["duration_s"], s["rate"],
                     " ".join(f"{r['error']:.2e}" for r in s["rows"]))
    return 0


if __name__ == "__main__":
    raise SystemExit(_cli())
