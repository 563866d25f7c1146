"""The rust law calibrated on a dynamometer record (docs/cleaning.md, "The rust law").

Reads a record (``--record``, default the packaged *synthetic* one,
``brakewear/data/dyno/synthetic_rust_record.csv``), fits the rust law's
parameters with their 95 % intervals (:func:`brakewear.cleaning.rust_fit.calibrate`)
and draws the record against the fit.  ``--make-synthetic`` writes the
synthetic record first: the forward model with known parameters (:data:`TRUTH`),
30 stops cycling through 0.15, 0.3, 0.6 and 1.0 MPa of contact pressure, 35 m
of sliding at the pad's mean radius each (a stop from 50 km/h on a 0.32 m
tyre), a 55 degree pad, measured with noise (friction 0.01, removed depth
0.2 um).

Run ``python studies/rust_calibration.py [--make-synthetic] [--out docs]``; writes
``data/rust_calibration.json`` and ``figures/rust_calibration.png``.

``--coverage N`` fits ``N`` seeded synthetic records of each kind in :data:`KINDS`
(:func:`coverage`): parameters drawn from the priors' central 95 %, designs of
20-40 stops at 3-5 pressure levels, noise 0.005-0.02 in friction and 0.1-0.4 um
in depth.  The ordinary kinds must be fitted with intervals that cover the known
values at their stated 95 %; the degenerate ones must be refused, naming the
parameters they do not constrain (:data:`REFUSE`).  Writes
``data/rust_coverage.json``.
"""
from __future__ import annotations

import argparse
import json
from importlib import resources
from pathlib import Path

import numpy as np

from brakewear.cleaning.rust import RUST_PRIORS, RustLaw
from brakewear.cleaning.rust_fit import (
    DynoRecord,
    calibrate,
    predict_record,
    read_dyno_record,
    synthetic_record,
    write_dyno_record,
)
from brakewear.errors import IdentifiabilityError

#: the synthetic record's known parameters (SI units) and its design
TRUTH = dict(thickness=25e-6, k_rust=1.2e-12, threshold=0.06e6, mu_factor=1.15, mu_iron=0.40)
PAD_ARC_DEG = 55.0
PRESSURES_MPA = (0.15, 0.3, 0.6, 1.0)
STOPS, DISTANCE_M, SEED = 30, 35.0, 37


#: the kinds of synthetic record :func:`coverage` draws: the two ordinary ones (the layer
#: wears through between a fifth and three quarters of the way, with and without the
#: friction measured) and four that do not identify the whole law
KINDS = ("ordinary", "removal_only", "below", "lasting", "friction_only", "one_pressure")
#: what a record of each degenerate kind must be refused for (the default fit)
REFUSE = {"below": {"k_rust", "threshold", "thickness", "mu_factor", "mu_iron"},
          "lasting": {"thickness", "mu_factor", "mu_iron"},
          "friction_only": {"threshold"}, "one_pressure": {"threshold"}}
_DRAWN = ("thickness", "k_rust", "threshold", "mu_factor")


def draw_record(kind: str, seed: int):
    """A synthetic record of ``kind`` (:data:`KINDS`): ``(truth, record, pad_share)``.

    ``below``: every stop under the threshold; ``lasting``: a layer 1.5-4 times
    what the record can remove; ``friction_only``: no removal column;
    ``one_pressure``: every stop at one pressure."""
    rng = np.random.default_rng(seed)
    while True:
        u = rng.uniform(0.025, 0.975, len(_DRAWN))
        truth = {k: float(RUST_PRIORS[k].sample(u[i])) for i, k in enumerate(_DRAWN)}
        truth["mu_iron"] = float(rng.uniform(0.3, 0.5))
        share = float(rng.uniform(40.0, 70.0)) / 360.0
        stops, n_lv = int(rng.integers(20, 41)), int(rng.integers(3, 6))
        levels = np.sort(rng.uniform(0.12, 1.5, n_lv)) * 1e6
        if kind == "below":
            levels = np.sort(rng.uniform(0.2, 0.95, n_lv)) * truth["threshold"]
        if kind == "one_pressure":
            levels = levels[-1:]
        p = np.resize(levels, stops) if rng.random() < 0.5 else rng.choice(levels, stops)
        s = np.full(stops, rng.uniform(20.0, 50.0))
        noise = rng.uniform(0.005, 0.02), rng.uniform(0.1, 0.4) * 1e-6
        cum = np.cumsum(truth["k_rust"] * np.maximum(p - truth["threshold"], 0) * s * share)
        if kind == "lasting":
            truth["thickness"] = float(cum[-1] * rng.uniform(1.5, 4.0))
            if truth["thickness"] > 1e-3:
                continue
        run_out = int(np.searchsorted(cum, truth["thickness"]))
        if kind not in ("below", "lasting") and not 6 <= run_out <= 0.75 * stops:
            continue
        law = RustLaw(**{k: truth[k] for k in _DRAWN})
        rec = synthetic_record(law, truth["mu_iron"], p, s, share, noise_friction=noise[0],
                               noise_removed=noise[1], seed=seed + 7)
        if kind == "removal_only":
            rec = DynoRecord(rec.pressure, rec.distance, None, rec.removed, "synthetic")
        if kind == "friction_only":
            rec = DynoRecord(rec.pressure, rec.distance, rec.friction, None, "synthetic")
        return truth, rec, share


def coverage(per_kind: int | dict = 40, seed: int = 0) -> dict:
    """Fit ``per_kind`` records of each kind (a dict: per kind); per kind the records,
    the accepted fits, the refusals (the parameters named -> count) and, per
    parameter, how many 95 % intervals held the known value."""
    counts = per_kind if isinstance(per_kind, dict) else dict.fromkeys(KINDS, per_kind)
    table = {}
    for kind, n in counts.items():
        row = {"records": n, "accepted": 0, "refused": {}, "covered": {}, "fitted": {}}
        for i in range(n):
            truth, rec, share = draw_record(kind, seed + 100_000 * KINDS.index(kind) + i)
            try:
                cal = calibrate(rec, share)
            except IdentifiabilityError as e:
                key = ", ".join(sorted(e.parameters))
                row["refused"][key] = row["refused"].get(key, 0) + 1
                continue
            row["accepted"] += 1
            for k in cal.names:
                lo, hi = cal.interval_95[k]
                row["fitted"][k] = row["fitted"].get(k, 0) + 1
                row["covered"][k] = row["covered"].get(k, 0) + int(lo <= truth[k] <= hi)
        table[kind] = row
    return table


def packaged_record() -> Path:
    """The packaged synthetic record's path."""
    return Path(str(resources.files("brakewear") / "data" / "dyno" /
                    "synthetic_rust_record.csv"))


def make_synthetic(path: Path) -> Path:
    """Write the synthetic record (see the module) to ``path``."""
    law = RustLaw(**{k: v for k, v in TRUTH.items() if k != "mu_iron"})
    p = np.resize(np.array(PRESSURES_MPA) * 1e6, STOPS)
    rec = synthetic_record(law, TRUTH["mu_iron"], p, np.full(STOPS, DISTANCE_M),
                           PAD_ARC_DEG / 360.0, seed=SEED)
    header = (
        f"SYNTHETIC dynamometer record, not a measurement: made by "
        f"studies/rust_calibration.py --make-synthetic\n"
        f"(brakewear.cleaning.rust_fit.synthetic_record, seed {SEED}) with the known parameters "
        f"thickness 25 um, k_rust 1.2e-12 1/Pa,\nthreshold 0.06 MPa, mu_factor 1.15, "
        f"mu_iron 0.40; a {PAD_ARC_DEG:g} degree pad; noise: friction 0.01, "
        f"removed depth 0.2 um."
    )
    return write_dyno_record(path, rec, header)


def main(record=None, out=None, pad_arc_deg: float = PAD_ARC_DEG) -> dict:
    """Fit the record (default: the packaged synthetic one); the fit as a dict, and
    the JSON and figure written to ``out``."""
    path = packaged_record() if record is None else Path(record)
    rec = read_dyno_record(path)
    share = pad_arc_deg / 360.0
    cal = calibrate(rec, share)
    result = {"record": path.name, "pad_arc_deg": pad_arc_deg, "stops": rec.stops,
              "values": cal.values, "sd": cal.sd, "interval_95": cal.interval_95,
              "names": list(cal.names), "correlation": cal.correlation.tolist(),
              "noise": cal.noise, "fixed": cal.fixed, "evidence": cal.evidence,
              "truth": TRUTH if record is None else None}
    if out is not None:
        out = Path(out)
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "rust_calibration.json").write_text(json.dumps(result, indent=1))
        (out / "figures").mkdir(parents=True, exist_ok=True)
        plot(rec, cal, share, out / "figures" / "rust_calibration.png")
    return result


def plot(rec, cal, share: float, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mu, rem = predict_record({**cal.fixed, **cal.values}, rec.pressure, rec.distance, share)
    n = np.arange(1, rec.stops + 1)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4))
    if rec.removed is not None:
        ax.plot(n, rec.removed * 1e6, "o", label="record")
        ax.plot(n, rem * 1e6, "-", label="fit")
    ax.set(xlabel="stop", ylabel="oxide removed in the stop (um)",
           title="removal: k_r max(p - p_th, 0) s until the layer is gone")
    ax.legend(fontsize=8)
    if rec.friction is not None:
        bx.plot(n, rec.friction, "o", label="record")
        bx.plot(n, mu, "-", label="fit")
    bx.set(xlabel="stop", ylabel="friction coefficient", title="friction on rust, then iron")
    bx.legend(fontsize=8)
    txt = "\n".join(f"{k}: {v:.3g} [{lo:.3g}, {hi:.3g}]"
                    for k, v in cal.values.items() for lo, hi in [cal.interval_95[k]])
    bx.text(0.98, 0.5, txt, transform=bx.transAxes, ha="right", fontsize=7, family="monospace")
    fig.suptitle(f"{Path(rec.source).name}: fit with 95 % intervals", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def print_coverage(table: dict) -> None:
    """The coverage table as Markdown rows."""
    print("| kind | records | fitted | refused (parameters named: records) | 95 % intervals "
          "holding the known value |")
    print("|---|---|---|---|---|")
    for kind, r in table.items():
        ref = "; ".join(f"{k}: {n}" for k, n in r["refused"].items()) or "-"
        cov = ", ".join(f"{k} {r['covered'][k]}/{r['fitted'][k]} "
                        f"({100 * r['covered'][k] / r['fitted'][k]:.1f} %)"
                        for k in r["fitted"]) or "-"
        print(f"| {kind} | {r['records']} | {r['accepted']} | {ref} | {cov} |")


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--record", default=None, help="a dynamometer record CSV (default: the "
                                                   "packaged synthetic one)")
    ap.add_argument("--pad-arc", type=float, default=PAD_ARC_DEG, help="the pad's arc (deg)")
    ap.add_argument("--make-synthetic", action="store_true",
                    help="write the packaged synthetic record first")
    ap.add_argument("--out", default=None)
    ap.add_argument("--coverage", type=int, default=0, metavar="N",
                    help="fit N synthetic records of each kind and print the coverage")
    a = ap.parse_args(argv)
    if a.coverage:
        table = coverage(a.coverage)
        print_coverage(table)
        if a.out is not None:
            (Path(a.out) / "data").mkdir(parents=True, exist_ok=True)
            (Path(a.out) / "data" / "rust_coverage.json").write_text(json.dumps(table, indent=1))
        return table
    if a.make_synthetic:
        print("wrote", make_synthetic(packaged_record()))
    r = main(a.record, a.out, a.pad_arc)
    for k, v in r["values"].items():
        lo, hi = r["interval_95"][k]
        print(f"{k:10s} {v:.4g}  95 % [{lo:.4g}, {hi:.4g}]"
              + (f"  (known: {r['truth'][k]:.4g})" if r["truth"] else ""))
    return r


if __name__ == "__main__":
    _cli()
