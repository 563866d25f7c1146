"""The cycle jump converged (the numbers of docs/validation.md, "Cycles without
simulating every one").

The fretting test of McColl, Ding and Leen (the packaged scene ``mccoll_fretting``)
is run to its 18 000 cycles with

* fixed jumps of ``N`` cycles per wear update (``numerics.fixed_jump``), over a
  range of ``N``: the flat's scar depth at its centre converges as ``N`` falls,
  first order (each increment books ``N`` times its wear before the next is
  solved); its limit is estimated by Richardson extrapolation of the two
  smallest jumps, ``2 h(N) - h(2N)``;
* the error-controlled jump (``numerics.wear_tol``) at several tolerances:
  the depth against the cycles simulated, beside the fixed jumps';
* (``--sizes``, ``--increments``) the contact mesh's element size and the
  stroke's increments per cycle at the default tolerance.

``python studies/cycle_jump.py [--out DIR] [--quick]`` writes
``cycle_jump.json`` into ``DIR/data`` and ``cycle_jump.png`` into
``DIR/figures`` (default DIR: docs); ``--quick`` runs a 2000-cycle test on a
coarse mesh (for the test suite).
"""
from __future__ import annotations

import argparse
import json
import logging
import tempfile
from pathlib import Path

from brakewear.scene import load_scene
from brakewear.tribology import run_tribometer

logger = logging.getLogger(__name__)

FIXED = (10, 20, 50, 100, 200, 500, 1000, 2000)
TOLS = (0.005, 0.01, 0.02, 0.05, 0.1)


def run(scene, **changes) -> dict:
    """One run of ``scene`` with ``changes`` (keys of [test], [mesh], [numerics], SI)."""
    sc = scene.with_options(**changes)
    with tempfile.TemporaryDirectory() as tmp:
        s = run_tribometer(sc, tmp, figures=False)
    f = s["bodies"]["flat"]
    return {**{k: v for k, v in changes.items()}, "depth_centre_m": f["depth_centre"],
            "depth_max_m": f["depth_max"], "worn_ratio": s["worn_ratio"],
            "cycles_simulated": s["cycles_simulated"], "jumps": s["jumps"],
            "run_s": s["cost"]["run_s"]}


def main(out: str | Path | None = "docs", quick: bool = False, fixed=FIXED, tols=TOLS,
         sizes=(), increments=()) -> dict:
    """Run the study; write its data and figure under ``out`` (None: nothing written)."""
    scene = load_scene("mccoll_fretting")
    base = {}
    if quick:
        base = {"cycles": 2000.0, "size": 1e-5}
        fixed, tols = (20, 50, 200), (0.02, 0.1)
    data = {"scene": scene.name, "base": base, "fixed": [], "controlled": [], "sizes": [],
            "increments": []}
    for N in fixed:
        data["fixed"].append(run(scene, fixed_jump=True, first_jump=float(N), **base))
        logger.info("fixed jump %d: %s", N, data["fixed"][-1])
    for tol in tols:
        data["controlled"].append(run(scene, wear_tol=tol, **base))
    for h in sizes:
        data["sizes"].append(run(scene, **{**base, "size": h}))
    for n in increments:
        data["increments"].append(run(scene, increments=int(n), **base))
    d = sorted(data["fixed"], key=lambda r: r["first_jump"])
    if len(d) >= 2 and d[1]["first_jump"] == 2 * d[0]["first_jump"]:
        data["richardson_depth_centre_m"] = 2 * d[0]["depth_centre_m"] - d[1]["depth_centre_m"]
    else:
        data["richardson_depth_centre_m"] = d[0]["depth_centre_m"]
    if out is not None:
        out = Path(out)
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "cycle_jump.json").write_text(json.dumps(data, indent=2))
        (out / "figures").mkdir(parents=True, exist_ok=True)
        draw(data, out / "figures" / "cycle_jump.png")
    return data


def draw(data: dict, path: Path) -> Path:
    """Left: the centre depth against the jump; right: its error against the cycles
    simulated, fixed jumps and the error-controlled jump."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ref = data["richardson_depth_centre_m"]
    fixed = sorted(data["fixed"], key=lambda r: r["first_jump"])
    ctrl = data["controlled"]
    fig, (a, b) = plt.subplots(1, 2, figsize=(10.0, 4.0))
    N = [r["first_jump"] for r in fixed]
    a.semilogx(N, [r["depth_centre_m"] * 1e6 for r in fixed], "o-", label="fixed jump of N cycles")
    a.axhline(ref * 1e6, color="k", ls=":", label=f"extrapolated to N -> 0: {ref * 1e6:.3f} um")
    a.set_xlabel("cycles per wear update N")
    a.set_ylabel("flat's scar depth at its centre (um)")
    a.set_title(f"{data['scene']}: the depth converges in N")
    a.legend(fontsize=8)
    def err(r):
        return max(abs(r["depth_centre_m"] / ref - 1.0), 1e-6)

    b.loglog([r["cycles_simulated"] for r in fixed], [err(r) for r in fixed], "o-",
             label="fixed jumps")
    b.loglog([r["cycles_simulated"] for r in ctrl], [err(r) for r in ctrl], "s-",
             label="error-controlled jumps")
    for r in ctrl:
        b.annotate(f"tol {r['wear_tol']:g}", (r["cycles_simulated"], err(r)), fontsize=7,
                   xytext=(4, 4), textcoords="offset points")
    b.set_xlabel("cycles simulated")
    b.set_ylabel("relative error of the centre depth")
    b.set_title("cost against error")
    b.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--sizes", type=float, nargs="*", default=(1e-5, 5e-6, 2.5e-6),
                    help="contact element sizes (m) at the default tolerance")
    ap.add_argument("--increments", type=int, nargs="*", default=(12, 20, 40))
    args = ap.parse_args()
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    res = main(args.out, args.quick, sizes=() if args.quick else args.sizes,
               increments=() if args.quick else args.increments)
    for key in ("fixed", "controlled", "sizes", "increments"):
        for r in res[key]:
            print(key, {k: (float(f"{v:.5g}") if isinstance(v, float) else v)
                        for k, v in r.items()})
    print("Richardson centre depth", res["richardson_depth_centre_m"])
