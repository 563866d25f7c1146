"""The validation table of docs/validation.md: the packaged tribometer scenes as they are.

Runs ``mccoll_fretting``, ``cruzado_block_on_ring`` and ``pin_on_disc_cap``
(the same runs as ``brakewear run NAME``), and writes

* ``DIR/data/validation.json``: per scene the measured and computed figures,
  the closed form's where the test has one, the worn ratio against the k
  ratio, the cycles simulated and the wall time (with the load average);
* ``DIR/figures/validation_NAME.png``: the run's profile figure (the worn
  profiles against the measured one and the closed form).

``python studies/validation.py [--out DIR] [--scenes NAME ...]`` (default DIR: docs).
"""
from __future__ import annotations

import argparse
import json
import logging
import os
import shutil
import tempfile
from pathlib import Path

from brakewear.scene import load_scene
from brakewear.tribology import run_tribometer

logger = logging.getLogger(__name__)

SCENES = ("mccoll_fretting", "cruzado_block_on_ring", "pin_on_disc_cap")


def run(name: str, figures: Path | None = None) -> dict:
    """One packaged scene as it is; its figure copied to ``figures/validation_NAME.png``."""
    scene = load_scene(name)
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        s = run_tribometer(scene, tmp, figures=figures is not None)
        if figures is not None:
            figures.mkdir(parents=True, exist_ok=True)
            shutil.copy(Path(tmp) / "profile.png", figures / f"validation_{name}.png")
    s.pop("measured_profile", None)
    if "profile" in s["validation"]:  # the packaged file by its name, not this machine's path
        s["validation"]["profile"] = Path(s["validation"]["profile"]).name
    return {"scene": name, "test": s["test"], "cycles": s["cycles"], "cycle": s["cycle"],
            "cycles_simulated": s["cycles_simulated"], "jumps": s["jumps"],
            "wall_s": s["cost"]["run_s"], "cpu_s": s["cost"]["cpu_s"],
            "build_s": s["cost"]["build_s"],
            "load_average_at_start": load, "bodies": s["bodies"],
            "worn_ratio": s["worn_ratio"], "k_ratio": s["k_ratio"],
            "validation": s["validation"], "closed_form": s.get("closed_form"),
            "face_nodes": s["mesh"]["face_nodes"]}


def main(out: str | Path | None = "docs", scenes=SCENES) -> list[dict]:
    """Run the scenes; write the table's data and figures under ``out`` (None: nothing)."""
    figs = None if out is None else Path(out) / "figures"
    rows = [run(name, figs) for name in scenes]
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / "validation.json").write_text(json.dumps(rows, indent=2))
    return rows


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs")
    ap.add_argument("--scenes", nargs="*", default=SCENES)
    args = ap.parse_args()
    logging.basicConfig(level=logging.WARNING)
    for r in main(args.out, args.scenes):
        v = r["validation"]
        line = f"{r['scene']}: {r['cycles']:.6g} {r['cycle']}s, {r['cycles_simulated']} " \
               f"simulated, {r['wall_s']:.1f} s wall, {r['cpu_s']:.1f} s CPU (load " \
               f"{r['load_average_at_start']:.1f})"
        if v:
            line += (f"; {v['quantity']} computed {v['computed']:.4g}, measured "
                     f"{v['measured']:.4g} ({v['error']:+.1%})")
        if r["closed_form"]:
            line += "; closed form: " + ", ".join(
                f"{k} {f['error']:+.2%}" for k, f in r["closed_form"]["figures"].items())
        print(line)
