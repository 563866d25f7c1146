"""``brakewear run`` for a tribometer scene: the output folder, a progress bar, the lines
the command prints (the command line's part; the library below it only logs)."""
from __future__ import annotations

import logging
import sys
from pathlib import Path

from ..errors import SceneError
from ..output.folder import check_new_out
from .runner import clear_tribometer_run, run_tribometer

logger = logging.getLogger(__name__)

__all__ = ["run_tribometer_file", "summary_lines"]


def run_tribometer_file(scene, out: str | Path | None = None, resume: bool = False,
                  quiet: bool = False, overwrite: bool = False) -> dict:
    """Run a checked tribometer scene into ``out`` (default ``brakewear-<name>``) with a
    progress bar on stderr in cycles (none if ``quiet``); return the summary."""
    if resume:
        raise SceneError(f"--resume: the tribometer test {scene.name!r} runs from its start "
                         "(its cycle jumps take about a minute; run it again without --resume)")
    out = Path(out) if out is not None else Path(f"brakewear-{scene.name}")
    check_new_out(out, overwrite=overwrite, resume=False, can_resume=False)
    if overwrite:
        clear_tribometer_run(out, scene)
    bar = None
    if not quiet:
        from tqdm import tqdm
        unit = scene.test.capabilities["cycle"]
        bar = tqdm(total=scene.test.cycles, unit=unit, file=sys.stderr, desc=scene.name,
                   dynamic_ncols=True, bar_format="{l_bar}{bar}| {n:.0f}/{total:.0f} "
                   + unit + "s [{elapsed}<{remaining}]")

    def progress(done, total):
        bar.update(done - bar.n)

    try:
        summary = run_tribometer(scene, out, progress=progress if bar is not None else None)
    finally:
        if bar is not None:
            bar.close()
    summary["out"] = str(out)
    return summary


def summary_lines(name: str, s: dict) -> list[str]:
    """What ``brakewear run`` prints at the end of a tribometer test."""
    lines = [f"brakewear run {name}: {s['test']}, {s['cycles']:.6g} {s['cycle']}s in "
             f"{s['jumps']} jumps ({s['cycles_simulated']} simulated), "
             f"{s['cost']['run_s']:.1f} s"]
    for body, f in s["bodies"].items():
        worn = (f"worn volume {f['worn_volume'] * 1e9:.4g} mm^3" if "worn_volume" in f
                else f"worn area {f['worn_area'] * 1e12:.4g} um^2 per unit length")
        lines.append(f"  {body}: depth max {f['depth_max'] * 1e6:.4g} um, at the centre "
                     f"{f['depth_centre'] * 1e6:.4g} um, {worn}")
    if s.get("worn_ratio") is not None and s.get("k_ratio") is not None:
        lines.append(f"  worn ratio {s['worn_ratio']:.6g} (k ratio {s['k_ratio']:.6g})")
    v = s.get("validation")
    if v:
        scale = 1e6 if v["quantity"].split(".")[1] in ("depth_max", "depth_centre",
                                                         "scar_width") else 1.0
        unit = " um" if scale == 1e6 else ""
        lines.append(f"  {v['quantity']}: computed {v['computed'] * scale:.4g}{unit}, measured "
                     f"{v['measured'] * scale:.4g}{unit} ({v['error']:+.1%}; tolerance "
                     f"{v['tolerance']:.0%}: {'met' if v['within_tolerance'] else 'NOT met'}) "
                     f"-- {v['source']}")
    lines.append(f"  wrote {s['out']}/: summary.json, history.csv, profile.csv, "
                 + ", ".join(s["files"]["series"])
                 + (f", {s['files']['figure']}" if "figure" in s["files"] else ""))
    return lines
