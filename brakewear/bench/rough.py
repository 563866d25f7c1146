"""The rough-contact benchmark (``brakewear bench rough``): the half-space solve against
tamaas and the foundation model, in one run.

Two cases per grid size ``n``:

* **periodic**: a periodic self-affine surface (Hurst 0.8, roll-off at a
  quarter of the period, cut-off at four pixels, rms slope 0.1) on a flat at
  the mean pressure ``0.01 E* Sdq`` (about 2.5 % real contact), solved from
  scratch (kernel included) by :func:`brakewear.rough.solve_normal` and, if it
  is installed, by tamaas's ``PolonskyKeerRey`` at the same tolerance; both
  single-threaded.  Reported: times, iterations, real contact areas and their
  difference, and each solution's gap error (the largest ``|g - delta|`` on
  the contact or overlap off it, over the rms height) measured the same way;
  and the time of our solve at a hundred times the tolerance, whose gap
  error is below tamaas's (so the comparison does not hang on what each
  code's tolerance means).
* **sphere**: the sphere on a rough plane of studies/rough_foundation.py
  (``sigma / delta_Hertz = 1``, free grid): the half-space normal solve
  against the foundation bed on the same grid and load (the bed's median of
  repeated solves).

Timings are wall-clock on this machine: take the ratios within one run.
"""
from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence

import numpy as np

from ..errors import BenchError
from .common import fmt

logger = logging.getLogger(__name__)

__all__ = ["ROUGH_SIZES", "run_rough_case", "bench_rough", "format_rough_table"]

ROUGH_SIZES = (256, 512)


def _gap_error(hs, g0, p, sigma: float) -> float:
    g = g0 + hs.displacement(p)
    S = p > 0
    g = g - g[S].mean()
    off = float(max(-g[~S].min(), 0.0)) if (~S).any() else 0.0
    return max(float(np.abs(g[S]).max()), off) / sigma


def _tamaas(t, Es: float, nu: float, p_mean: float, tol: float):
    """tamaas's solve of the same problem, or None if tamaas is not installed."""
    try:
        import tamaas as tm
    except ImportError:
        return None
    tm.set_log_level(tm.LogLevel.warning)
    t0 = time.perf_counter()
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, list(t.size), list(t.shape))
    model.E, model.nu = Es * (1 - nu ** 2), nu          # tamaas takes E; E* = E / (1 - nu^2)
    solver = tm.PolonskyKeerRey(model, np.ascontiguousarray(t.heights), tol)
    solver.solve(p_mean)
    seconds = time.perf_counter() - t0
    return np.array(model.traction, dtype=float).reshape(t.shape), seconds, \
        getattr(tm.TamaasInfo, "version", "?")


def run_rough_case(n: int, tol: float = 1e-8, repeats: int = 20) -> dict:
    """Both cases on an ``n x n`` grid; one row of figures."""
    from ..rough import HalfSpace, self_affine, solve_normal

    Es, nu, L = 1.0, 0.3, 1.0
    t = self_affine(n, L, 0.8, rms_slope=0.1, rolloff=L / 4, cutoff=4 * L / n, seed=0)
    p_mean = 0.01 * Es * 0.1
    t0 = time.perf_counter()
    hs = HalfSpace(t.shape, t.pixel, Es, nu, periodic=True)
    ours = solve_normal(hs, -t.heights, load=p_mean * L * L, tol=tol)
    ours_s = time.perf_counter() - t0
    sigma = t.rms_height()
    # a hundred times tighter: its gap error below tamaas's at ``tol``
    t0 = time.perf_counter()
    strict = solve_normal(HalfSpace(t.shape, t.pixel, Es, nu, periodic=True), -t.heights,
                          load=p_mean * L * L, tol=tol / 100)
    strict_s = time.perf_counter() - t0
    row = {"n": n, "tol": tol, "ours_s": ours_s, "ours_iterations": ours.iterations,
           "ours_area_fraction": ours.contact_fraction,
           "ours_gap_error": _gap_error(hs, -t.heights, ours.pressure, sigma),
           "ours_tol100_s": strict_s,
           "ours_tol100_gap_error": _gap_error(hs, -t.heights, strict.pressure, sigma)}
    tam = _tamaas(t, Es, nu, p_mean, tol)
    if tam is not None:
        p, secs, version = tam
        frac = float((p > 0).mean())
        row.update({"tamaas_version": version, "tamaas_s": secs, "tamaas_area_fraction": frac,
                    "area_difference": ours.contact_fraction / frac - 1,
                    "tamaas_gap_error": _gap_error(hs, -t.heights, p, sigma),
                    "ours_over_tamaas_time": ours_s / secs})
    row.update(_sphere_case(n, tol, repeats))
    return row


def _sphere_case(n: int, tol: float, repeats: int) -> dict:
    """Half-space against foundation: sphere on a rough plane, sigma = delta_Hertz."""
    from ..rough import HalfSpace, hertz_calibrated_bed, self_affine, solve_normal

    R, Es, nu, a = 0.01, 1e9, 0.3, 0.5e-3
    F, L = 4 * Es * a ** 3 / (3 * R), 8 * a
    t = self_affine(n, L, 0.8, rms_height=a * a / R, rolloff=L / 4, cutoff=L / 32, seed=0)
    X, Y = t.coordinates()
    g0 = (X ** 2 + Y ** 2) / (2 * R) - t.heights
    t0 = time.perf_counter()
    hs = HalfSpace(t.shape, t.pixel, Es, nu)
    ref = solve_normal(hs, g0, load=F, tol=tol)
    hs_s = time.perf_counter() - t0
    bed = hertz_calibrated_bed(F, R, Es, nu)
    times = []
    for _ in range(repeats):
        t1 = time.perf_counter()
        bed.solve(g0, hs.pixel_area, F)
        times.append(time.perf_counter() - t1)
    f_s = float(np.median(times))
    return {"sphere_halfspace_s": hs_s, "sphere_iterations": ref.iterations,
            "sphere_foundation_s": f_s, "halfspace_over_foundation": hs_s / f_s}


def bench_rough(sizes: Sequence[int] = ROUGH_SIZES, tol: float = 1e-8,
                progress: Callable[[dict], None] | None = None) -> list[dict]:
    """:func:`run_rough_case` for each grid size (after a small warm-up case)."""
    run_rough_case(64, tol, repeats=2)        # imports and first calls, outside the timings
    rows = []
    for n in sizes:
        if int(n) != n or n < 64:
            raise BenchError(f"size {n!r} is not allowed; need a whole number of pixels >= 64")
        rows.append(run_rough_case(int(n), tol))
        if progress:
            progress(rows[-1])
    return rows


def format_rough_table(rows: list[dict]) -> str:
    """The rows as a text table."""
    head = ("| grid | ours (s) | tamaas (s) | ours / tamaas | ours at tol/100 (s) | area ours | "
            "area tamaas | area diff | gap error ours / tol/100 / tamaas | sphere half-space "
            "(s) | foundation (s) | ratio |")
    lines = [head, "|" + "---|" * 12]
    for r in rows:
        lines.append(
            f"| {r['n']}^2 | {r['ours_s']:.3f} | {fmt(r.get('tamaas_s'), '.3f')} | "
            f"{fmt(r.get('ours_over_tamaas_time'), '.2f')} | {r['ours_tol100_s']:.3f} | "
            f"{r['ours_area_fraction']:.5f} | "
            f"{fmt(r.get('tamaas_area_fraction'), '.5f')} | "
            f"{fmt(None if 'area_difference' not in r else 100 * r['area_difference'], '+.3f')}"
            f" % | {r['ours_gap_error']:.1e} / {r['ours_tol100_gap_error']:.1e} / "
            f"{fmt(r.get('tamaas_gap_error'), '.1e')} | "
            f"{r['sphere_halfspace_s']:.3f} | {r['sphere_foundation_s']:.2e} | "
            f"{r['halfspace_over_foundation']:.0f} |")
    return "\n".join(lines)
