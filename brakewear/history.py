"""A wear history on disk: VTU time series (ParaView), a CSV of per-step figures, a JSON summary.

:func:`run_wear` drives :func:`brakewear.simulate.wear_history` and writes

- ``pad.pvd`` + ``pad_NNNNN.vtu``: the pad mesh with the point fields
  ``pressure`` (Pa), ``pad_wear`` (m), ``active`` (1 in contact) on its
  friction face (zero elsewhere);
- ``rotor.pvd`` + ``rotor_NNNNN.vtu`` (elastic rotor): ``rotor_wear`` (m);
- ``history.csv``: one row per accepted step;
- ``checkpoint.npz``: the loop's state (resume with ``resume=True``);
- ``summary.json``: what a user asks first (wear, pressure, steps, cost).

ParaView opens the ``.pvd`` files as time series.  A resumed run drops the
files written after its checkpoint and continues the series, so a run
killed at any point and resumed leaves the same files as an uninterrupted
one.
"""
from __future__ import annotations

import csv
import json
import logging
import os
import re
import time
from pathlib import Path

import meshio
import numpy as np

from .simulate import FEInterface, WearStep, wear_history

logger = logging.getLogger(__name__)

__all__ = ["SeriesWriter", "run_wear", "step_figures", "ring_profile"]


class SeriesWriter:
    """A ParaView time series (``NAME.pvd`` + one VTU per written step) of one mesh."""

    def __init__(self, directory: str | os.PathLike, name: str, points: np.ndarray,
                 tets: np.ndarray, resume_step: int | None = None):
        self.dir, self.name = Path(directory), name
        self.points, self.tets = np.ascontiguousarray(points.T), np.ascontiguousarray(tets.T)
        self.entries: list[tuple[float, int]] = []
        pvd = self.dir / f"{name}.pvd"
        if resume_step is not None and pvd.exists():
            pat = re.compile(rf'timestep="([^"]+)"[^>]*file="{re.escape(name)}_(\d+)\.vtu"')
            for t, s in pat.findall(pvd.read_text()):
                if int(s) <= resume_step:
                    self.entries.append((float(t), int(s)))
            for f in self.dir.glob(f"{name}_*.vtu"):   # written after the checkpoint
                if int(f.stem.rsplit("_", 1)[1]) > resume_step:
                    f.unlink()

    def write(self, step: int, time_s: float, fields: dict) -> Path:
        path = self.dir / f"{self.name}_{step:05d}.vtu"
        meshio.Mesh(self.points, [("tetra", self.tets)],
                    point_data={k: np.asarray(v, dtype=float) for k, v in fields.items()}
                    ).write(path)
        self.entries = [e for e in self.entries if e[1] != step] + [(time_s, step)]
        rows = "\n".join(f'    <DataSet timestep="{t!r}" group="" part="0" '
                         f'file="{self.name}_{s:05d}.vtu"/>' for t, s in self.entries)
        text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n")
        tmp = self.dir / f".{self.name}.pvd.tmp"
        tmp.write_text(text)
        os.replace(tmp, self.dir / f"{self.name}.pvd")
        return path


def step_figures(s: WearStep, itf, mu: float) -> dict:
    """Per-step figures of a wear step (the rows of history.csv)."""
    p, act, A, r = s.pressure, s.active, itf.area, itf.r
    F = float((p * A).sum())
    pr = (p * r)[act]
    return {
        "step": s.step, "time_s": s.time, "dt_s": s.dt, "limit": s.limit,
        "sliding_distance_m": s.sliding_distance,
        "pad_wear_max_m": float(s.pad_wear.max()), "pad_wear_mean_m": float(
            (s.pad_wear * A).sum() / A.sum()),
        "rotor_wear_max_m": float(s.rotor_wear.max()),
        "pressure_max_Pa": float(p.max()), "contact_fraction": float(A[act].sum() / A.sum()),
        "pr_spread": float((pr.max() - pr.min()) / pr.mean()) if pr.size else float("nan"),
        "normal_force_N": F,
        "torque_Nm": float(mu * (p * A * r).sum()),
        "pad_volume_m3": s.pad_volume, "rotor_volume_m3": s.rotor_volume,
        "rejected": s.rejected, "contact_solves": s.contact_solves, "solve_s": s.solve_s,
    }


def run_wear(model, out: str | os.PathLike, line_pressure: float, omega: float,
             duration: float, pad_law, rotor_law=None, mu: float = 0.0, *,
             vtu_every: int = 10, resume: bool = False, progress=None, **kwargs) -> dict:
    """Run a wear history and write it to ``out`` (see the module docstring).

    ``kwargs`` go to :func:`~brakewear.simulate.wear_history` (``steps``,
    ``max_dh``, ``dp_tol``, ``every``, ...).  ``progress`` is called with each
    :class:`WearStep` (e.g. to advance a progress bar).  Returns the summary.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    itf = kwargs.pop("interface", None) or FEInterface(model, line_pressure, mu,
                                                       kwargs.pop("tol", 1e-9))
    ck = out / "checkpoint.npz"
    start = None
    if resume:
        if not ck.exists():
            from .wear import WearError
            raise WearError(f"resume=True but {ck} does not exist")
        with np.load(ck) as d:
            start = int(d["step"])
    pad = model.meshes["pad"]
    pad_series = SeriesWriter(out, "pad", pad.p, pad.t, start)
    rot_series = (SeriesWriter(out, "rotor", model.meshes["rotor"].p, model.meshes["rotor"].t,
                               start)
                  if model.rotor == "elastic" and itf.rotor_nodes is not None else None)
    csv_path = out / "history.csv"
    rows = []
    if resume and csv_path.exists():
        with open(csv_path, newline="") as fh:
            rows = [r for r in csv.DictReader(fh) if int(r["step"]) <= start]
    n_pad = pad.nvertices
    last = None
    setup_s = time.perf_counter() - t0
    for s in wear_history(model, line_pressure, omega, duration, pad_law, rotor_law, mu,
                          checkpoint=ck, resume=resume, interface=itf, **kwargs):
        rows.append(step_figures(s, itf, mu))
        final = s.time >= duration * (1 - 1e-12)
        if s.step % vtu_every == 0 or s.step == 1 or final:
            fields = {}
            for name, val in (("pressure", s.pressure), ("pad_wear", s.pad_wear),
                              ("active", s.active.astype(float))):
                a = np.zeros(n_pad)
                a[itf.pad_nodes] = val
                fields[name] = a
            pad_series.write(s.step, s.time, fields)
            if rot_series is not None:
                a = np.zeros(model.meshes["rotor"].nvertices)
                a[itf.rotor_nodes] = s.rotor_wear
                rot_series.write(s.step, s.time, {"rotor_wear": a})
        _write_csv(csv_path, rows)
        if progress is not None:
            progress(s)
        last = s
    if last is None:
        raise RuntimeError("the wear history produced no step (was the run already finished?)")
    total_s = time.perf_counter() - t0
    summary = {
        "line_pressure_Pa": line_pressure, "omega_rad_s": omega, "duration_s": duration,
        "mu": mu, "rotor": model.rotor, "dofs": int(model.dofs),
        "pad_law": vars(pad_law), "rotor_law": None if rotor_law is None else vars(rotor_law),
        "steps": last.step, "final": rows[-1],
        "contact_solves": int(sum(int(r["contact_solves"]) for r in rows)),
        "rejected": int(sum(int(r["rejected"]) for r in rows)),
        "pad_archard_m3": last.pad_archard, "rotor_archard_m3": last.rotor_archard,
        "rotor_wear_profile": dict(zip(("r_m", "wear_m"), (
            a.tolist() for a in ring_profile(itf, last.rotor_wear)))),
        "run_s": total_s, "setup_s": setup_s, "resumed_from_step": start,
        "files": {"pad": "pad.pvd", "rotor": "rotor.pvd" if rot_series else None,
                  "history": "history.csv", "checkpoint": "checkpoint.npz"},
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=float))
    return summary


def ring_profile(itf, values: np.ndarray | None = None):
    """Rotor wear nodes grouped by ring: (ring radii, ring means of ``values``).

    ``itf`` is the wear loop's interface (``rotor_x``, ``ring``); ``values`` one
    number per rotor wear node (e.g. ``WearStep.rotor_wear``); None gives the
    radii only (second item None).
    """
    n = np.bincount(itf.ring)
    r = np.bincount(itf.ring, weights=np.hypot(itf.rotor_x[0], itf.rotor_x[1])) / n
    return r, None if values is None else np.bincount(itf.ring, weights=values) / n


def _write_csv(path: Path, rows: list) -> None:
    tmp = path.with_name("." + path.name + ".tmp")
    with open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, path)
