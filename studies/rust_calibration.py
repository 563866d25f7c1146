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
"""
from __future__ import annotations

import argparse
import json
from importlib import resources
from pathlib import Path

import numpy as np

from brakewear.cleaning.rust import RustLaw
from brakewear.cleaning.rust_fit import (calibrate, predict_record, read_dyno_record, synthetic_record,
                                write_dyno_record)

#: the synthetic record's known parameters (SI units) and its design
TRUTH = dict(thickness=25e-6, k_rust=1.2e-12, threshold=0.06e6, mu_factor=1.15, mu_iron=0.40)
PAD_ARC_DEG = 55.0
PRESSURES_MPA = (0.15, 0.3, 0.6, 1.0)
STOPS, DISTANCE_M, SEED = 30, 35.0, 37


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
    header = (f"SYNTHETIC dynamometer record, not a measurement: made by "
              f"studies/rust_calibration.py --make-synthetic\n"
              f"(brakewear.cleaning.rust_fit.synthetic_record, seed {SEED}) with the known parameters "
              f"thickness 25 um, k_rust 1.2e-12 1/Pa,\nthreshold 0.06 MPa, mu_factor 1.15, "
              f"mu_iron 0.40; a {PAD_ARC_DEG:g} degree pad; noise: friction 0.01, "
              f"removed depth 0.2 um.")
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
              "noise": cal.noise, "fixed": cal.fixed,
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


def _cli(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--record", default=None, help="a dynamometer record CSV (default: the "
                                                   "packaged synthetic one)")
    ap.add_argument("--pad-arc", type=float, default=PAD_ARC_DEG, help="the pad's arc (deg)")
    ap.add_argument("--make-synthetic", action="store_true",
                    help="write the packaged synthetic record first")
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
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
