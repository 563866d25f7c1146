"""A tribometer run on disk: ParaView series of both bodies, CSVs, a JSON summary, a figure.

:func:`write_run` writes, into the run's folder,

- ``<body>.pvd`` + ``<body>_NNNNN.vtu`` for each body: its mesh (triangles in
  plane strain, tetrahedra in 3D) with ``wear`` (m) on its contact face,
  ``pressure`` (Pa, the slave's face) and ``displacement`` (m) under the
  frame's contact forces -- a ParaView time series in cycles;
- ``history.csv``: one row per cycle jump;
- ``profile.csv``: the worn profiles of both faces at the end;
- ``summary.json`` and ``scene.json``;
- ``profile.png``: the worn profiles against the measured ones
  (``output.figures``).
"""
from __future__ import annotations

import csv
import json
import logging
import os
from pathlib import Path

import numpy as np

from ..mesh.series import SeriesWriter

logger = logging.getLogger(__name__)

__all__ = ["FrameWriter", "write_csv", "write_json", "profile_figure", "RUN_FILES"]

#: the files a tribometer run writes besides its bodies' series (for --overwrite)
RUN_FILES = ("summary.json", "scene.json", "history.csv", "profile.csv", "profile.png")


def write_csv(path: Path, rows: list[dict]) -> None:
    tmp = path.with_name("." + path.name + ".tmp")
    with open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, path)


def write_json(path: Path, data: dict) -> None:
    tmp = path.with_name("." + path.name + ".tmp")
    tmp.write_text(json.dumps(data, indent=2, default=float))
    os.replace(tmp, path)


class FrameWriter:
    """The two bodies' ParaView series."""

    def __init__(self, out: Path, pair):
        self.pair = pair
        self.series = {}
        for body in (pair.slave, pair.master):
            p = body.mesh.p
            pts = np.vstack([p, np.zeros((3 - p.shape[0], p.shape[1]))])
            self.series[body.name] = SeriesWriter(out, body.name, pts, body.mesh.t)
        self.count = 0

    def write(self, cycles: float, depths: dict, pressure: np.ndarray, forces, offset) -> None:
        """One frame at ``cycles``: the depths of both faces, the slave's pressure, the
        displacement under ``forces`` (N, on the master at the slave nodes)."""
        pair = self.pair
        self.count += 1
        fm = pair.master_forces(forces, offset) if forces is not None else None
        for body, f, p in ((pair.slave, None if forces is None else -forces, pressure),
                           (pair.master, fm, None)):
            n = body.mesh.nvertices
            fields = {}
            w = np.zeros(n)
            w[body.face] = depths[body.name]
            fields["wear"] = w
            if p is not None:
                pr = np.zeros(n)
                pr[body.face] = p
                fields["pressure"] = pr
            if f is not None:
                u = body.displacement(f)
                fields["displacement"] = np.hstack([u, np.zeros((n, 3 - u.shape[1]))])
            self.series[body.name].write(self.count, float(cycles), fields)


def profile_figure(path: Path, scene, profiles: dict, summary: dict,
                   closed: dict | None = None) -> Path:
    """The worn profiles of both faces (µm against mm) with the measured figure and
    profile (its spread where there are several tests) and the closed form."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9.6, 4.2))
    styles = ("-", "--")
    for (name, (x, h)), ls in zip(profiles.items(), styles):
        sign = -1.0 if name == scene.test.bodies[0] else 1.0
        ax.plot(np.asarray(x) * 1e3, sign * np.asarray(h) * 1e6, ls, lw=1.6,
                label=f"{name}, computed" + (" (drawn below 0)" if sign < 0 else ""))
    v = scene.validation
    if v:
        body, _, what = v["quantity"].partition(".")
        sign = -1.0 if body == scene.test.bodies[0] else 1.0
        if what.startswith("depth"):
            m = v["measured"]
            ax.axhspan(sign * m * (1 - v["tolerance"]) * 1e6, sign * m * (1 + v["tolerance"])
                       * 1e6, color="0.92", zorder=0,
                       label=f"measured {what.replace('_', ' ')} ± {v['tolerance']:.0%}")
            ax.plot([0.0], [sign * m * 1e6], "ko", label=f"measured: {m * 1e6:.3g} um")
            for i, (ref, val) in enumerate(v.get("reference", {}).items()):
                ax.plot([0.0], [sign * val * 1e6], "s^v"[i % 3], mfc="none", ms=8,
                        label=f"{ref.replace('_', ' ')}: {val * 1e6:.3g} um")
        if "profile" in v and "measured_profile" in summary:
            mp = summary["measured_profile"]
            sign = -1.0 if v.get("profile_of") == scene.test.bodies[0] else 1.0
            xm = np.asarray(mp["x_m"]) * 1e3
            if "depth_min_m" in mp:
                ax.fill_between(xm, sign * np.asarray(mp["depth_min_m"]) * 1e6,
                                sign * np.asarray(mp["depth_max_m"]) * 1e6, color="0.7",
                                alpha=0.5, lw=0, label="measured, the tests' spread")
            ax.plot(xm, sign * np.asarray(mp["depth_m"]) * 1e6, "k.", ms=4,
                    label="measured profile" + (" (mean)" if "depth_min_m" in mp else ""))
    if closed is not None:
        x, h = closed["profile"]
        sign = -1.0 if closed["body"] == scene.test.bodies[0] else 1.0
        ax.plot(np.asarray(x) * 1e3, sign * np.asarray(h) * 1e6, "k:", lw=1.4,
                label=f"closed form: {closed['name']}")
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xlabel("position across the scar (mm)")
    ax.set_ylabel("worn depth (um)")
    ax.set_title(f"{scene.name}: worn profiles after {summary['cycles']:.6g} "
                 f"{scene.test.capabilities['cycle']}s")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
