"""Convergence under refinement: observed orders, Richardson estimates, fitted rates.

A quantity ``f`` computed on a sequence of meshes (or steps) refined by the
ratios ``r = h_k / h_(k+1)`` approaches its converged value ``f0`` as
``f = f0 + c h^p`` once the sequence is in its asymptotic range.  From three
successive values the observed order is ``p = log((f1 - f2) / (f2 - f3)) /
log(r)`` (unequal ratios: the fixed point of Celik et al., J. Fluids Eng. 130,
2008, eq. 3), and the Richardson estimate of the converged value is
``f0 = f3 + (f3 - f2) / (r^p - 1)``.  A sequence whose differences change sign
is not in its asymptotic range and has no estimate.

Fields computed on different meshes are compared on one grid:
:func:`pad_grid` lays cell-centred points over a pad face, :func:`interpolate`
takes each mesh's nodal values there, :func:`radial_profile` reduces a rotor
face to its ring means; :func:`pad_profiles` picks a pad's nodes along its mean
radius and its centre line.  :func:`field_richardson` then takes the order from
the (weighted) L2 norms of the differences and the estimate point by point.
:func:`fitted_rate` is the least-squares slope of ``log(err)`` against
``log(h)`` when the errors themselves are known.

>>> f = [3.0 + 0.7 * h ** 2 for h in (1 / 2, 1 / 3, 1 / 4.5)]
>>> est = richardson(f, (1.5, 1.5))
>>> round(est["rate"], 9), round(est["estimate"], 12)
(2.0, 3.0)
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

__all__ = ["observed_rate", "richardson", "field_richardson", "settle", "estimate",
           "fitted_rate", "relative_l2", "pad_grid", "pad_profiles", "interpolate",
           "radial_profile"]


def observed_rate(f: Sequence[float], r: Sequence[float]) -> float:
    """Observed order of convergence of three values.

    Parameters
    ----------
    f
        Three values, coarse to fine.
    r
        The two refinement ratios ``(h1 / h2, h2 / h3)``.

    Returns
    -------
    float
        The order ``p``; nan where the differences vanish or change sign.
    """
    e21, e32 = f[0] - f[1], f[1] - f[2]
    if e32 == 0 or e21 == 0 or e21 / e32 <= 0:
        return float("nan")
    r21, r32 = r
    p = math.log(e21 / e32) / math.log(r32)
    for _ in range(100):        # p = (log(e21 / e32) + q(p)) / log(r32)
        if p <= 0:
            break
        q = math.log((r32 ** p - 1.0) / (r21 ** p - 1.0))
        p_new = (math.log(e21 / e32) + q) / math.log(r32)
        if abs(p_new - p) < 1e-12:
            p = p_new
            break
        p = p_new
    return float(p)


def richardson(f: Sequence[float], r: Sequence[float]) -> dict:
    """Richardson estimate of the converged value of a scalar sequence.

    Parameters
    ----------
    f
        Three or more values, coarse to fine.
    r
        The refinement ratios between successive values (one fewer than ``f``).

    Returns
    -------
    dict
        ``rate`` (from the three finest values), ``estimate`` (None where the
        rate is not positive), ``errors`` (each value's relative error from the
        estimate), ``asymptotic`` and ``estimate_rate1`` (the estimate at rate 1,
        a measure of its uncertainty while the rate has not settled).
    """
    f = tuple(float(v) for v in f)
    p = observed_rate(f[-3:], r[-2:])
    if not (np.isfinite(p) and p > 0):
        return {"rate": p, "estimate": None, "errors": [None] * len(f), "asymptotic": False}
    f0 = f[-1] + (f[-1] - f[-2]) / (r[-1] ** p - 1.0)
    return {"rate": p, "estimate": f0, "errors": [v / f0 - 1.0 for v in f], "asymptotic": True,
            "estimate_rate1": f[-1] + (f[-1] - f[-2]) / (r[-1] - 1.0)}


def _norm(a: np.ndarray, w: np.ndarray) -> float:
    return float(np.sqrt((w * a ** 2).sum()))


def field_richardson(fields: Sequence[np.ndarray], weights: np.ndarray,
                     r: Sequence[float]) -> dict:
    """Richardson estimate of a field given on one grid for every level.

    Parameters
    ----------
    fields
        Three or more arrays of the same shape, coarse to fine.
    weights
        Quadrature weights of the grid points (areas, lengths).
    r
        The refinement ratios between successive fields.

    Returns
    -------
    dict
        ``rate`` (from the L2 norms of the two finest differences), ``field``
        (the estimate point by point; None where the rate is not positive),
        ``errors`` (each field's relative L2 distance from it), ``asymptotic``
        (the differences shrink), ``differences`` and ``shift_rate1`` (how far,
        relative L2, the estimate at rate 1 lies from it).
    """
    w = np.asarray(weights, dtype=float)
    f1, f2, f3 = (np.asarray(a, dtype=float) for a in fields[-3:])
    d21, d32 = _norm(f2 - f1, w), _norm(f3 - f2, w)
    p = observed_rate((0.0, d21, d21 + d32), r[-2:]) if d21 > 0 and d32 > 0 else float("nan")
    if not (np.isfinite(p) and p > 0):
        return {"rate": p, "field": None, "errors": [None] * len(fields), "asymptotic": False,
                "differences": [d21, d32]}
    f0 = f3 + (f3 - f2) / (r[-1] ** p - 1.0)
    n0 = _norm(f0, w)
    return {"rate": p, "field": f0,
            "errors": [_norm(np.asarray(a) - f0, w) / n0 for a in fields],
            "asymptotic": d32 < d21, "differences": [d21, d32],
            "shift_rate1": d32 * abs(1.0 / (r[-1] - 1.0) - 1.0 / (r[-1] ** p - 1.0)) / n0}


def settle(est: dict) -> dict:
    """Withdraw an estimate whose rate has not settled (in place; returned too).

    Parameters
    ----------
    est
        A result of :func:`richardson` or :func:`field_richardson` with
        ``rates``: the observed rate of every successive triple.

    Returns
    -------
    dict
        ``est``, without its estimate and errors where the rate of the triple
        before the finest was not positive (one positive rate after a sign
        change is not a trend) or the last rate is below 0.5 (the estimate
        would lie many last differences away).
    """
    rates = est.get("rates", [])
    if len(rates) >= 2 and not (rates[-2] > 0 and rates[-1] >= 0.5):
        est.update(asymptotic=False, errors=[None] * len(est["errors"]))
        est["estimate" if "estimate" in est else "field"] = None
    return est


def estimate(values: Sequence, r: Sequence[float], weights: np.ndarray | None = None) -> dict:
    """The Richardson estimate of a sequence, withdrawn unless its rate has settled.

    Parameters
    ----------
    values
        Three or more scalars, or fields on one grid, coarse to fine.
    r
        The refinement ratios between successive values.
    weights
        The grid's quadrature weights for fields; None for scalars.

    Returns
    -------
    dict
        :func:`richardson`'s (scalars) or :func:`field_richardson`'s (fields)
        result from the three finest values, with ``rates``: the observed rate
        of every successive triple, and :func:`settle` applied.
    """
    def one(vals, ratios):
        return richardson(vals, ratios) if weights is None else \
            field_richardson(vals, weights, ratios)

    est = one(values, r)
    est["rates"] = [one(values[i:i + 3], r[i:i + 2])["rate"] for i in range(len(values) - 2)]
    return settle(est)


def fitted_rate(h: Sequence[float], err: Sequence[float]) -> float:
    """Least-squares slope of ``log(err)`` against ``log(h)``.

    Parameters
    ----------
    h
        Mesh sizes or steps (two or more).
    err
        The errors at them (positive).

    Returns
    -------
    float
        The observed order.

    >>> round(fitted_rate([0.1, 0.05, 0.025], [2e-2, 5e-3, 1.25e-3]), 12)
    2.0
    """
    return float(np.polyfit(np.log(np.asarray(h, float)), np.log(np.asarray(err, float)), 1)[0])


def relative_l2(a: np.ndarray, ref: np.ndarray, weights: np.ndarray | None = None) -> float:
    """Weighted relative L2 distance ``||a - ref|| / ||ref||``.

    Parameters
    ----------
    a, ref
        Values at the same points.
    weights
        Quadrature weights (default 1).

    Returns
    -------
    float
        The distance; nan where ``ref`` vanishes.
    """
    ref = np.asarray(ref, dtype=float)
    w = np.ones_like(ref) if weights is None else np.asarray(weights, dtype=float)
    n = _norm(ref, w)
    return _norm(np.asarray(a, dtype=float) - ref, w) / n if n > 0 else float("nan")


def pad_grid(geometry, n_r: int = 24, n_t: int = 40) -> dict:
    """Cell-centred polar points over a pad face, to compare fields of different meshes.

    Parameters
    ----------
    geometry
        A brake geometry (its ``pad``: radii, leading angle, arc angle).
    n_r, n_t
        Cells in radius and in angle.

    Returns
    -------
    dict
        ``xy`` (2, n_r n_t) points (m) with their ``area``; ``r`` the radii of
        the rows with their widths ``r_weight``; ``theta`` the angles of the
        columns and ``arc_xy`` the points of the arc at the mid radius.
    """
    pad = geometry.pad
    dr = (pad.outer_radius - pad.inner_radius) / n_r
    dt = pad.arc_angle / n_t
    r = pad.inner_radius + dr * (np.arange(n_r) + 0.5)
    t = pad.leading_angle + dt * (np.arange(n_t) + 0.5)
    R, T = np.meshgrid(r, t, indexing="ij")
    r_mid = 0.5 * (pad.inner_radius + pad.outer_radius)
    return {"xy": np.vstack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel()]),
            "area": (R * dr * dt).ravel(), "r": r, "r_weight": np.full(n_r, dr),
            "theta": t, "arc_xy": r_mid * np.vstack([np.cos(t), np.sin(t)])}


def pad_profiles(xy: np.ndarray, geometry) -> dict:
    """Pad friction nodes along the two profiles a pad field is read on.

    Parameters
    ----------
    xy
        (2, n) coordinates of the pad's friction nodes (m), on a mesh structured
        in radius (rows of nodes of one radius, to 0.1 um).
    geometry
        The brake geometry (its pad's radii and centre angle).

    Returns
    -------
    dict
        ``mean`` (the row of nodes closest to the mean radius, by angle) with its
        ``mean_radius_m`` and ``theta_deg``; ``centre`` (in every row, the node
        closest to the pad's centre line, by radius) with ``centre_radius_m`` and
        ``centre_dtheta_deg_max``, the largest angle of those nodes off the line.
    """
    r = np.hypot(xy[0], xy[1])
    th = np.arctan2(xy[1], xy[0])
    pad = geometry.pad
    r_mid = 0.5 * (pad.inner_radius + pad.outer_radius)
    rows = np.unique(np.round(r, 7))
    r_row = rows[np.argmin(np.abs(rows - r_mid))]
    sel = np.nonzero(np.abs(r - r_row) < 1e-6)[0]
    sel = sel[np.argsort(th[sel])]
    dth = np.abs(np.angle(np.exp(1j * (th - pad.center_angle))))
    centre = []
    for rr in rows:
        on = np.nonzero(np.abs(r - rr) < 1e-6)[0]
        centre.append(on[np.argmin(dth[on])])
    centre = np.array(centre)
    centre = centre[np.argsort(r[centre])]
    return {"mean_radius_m": float(r_row), "mean": sel, "theta_deg": np.degrees(th[sel]),
            "centre": centre, "centre_radius_m": r[centre],
            "centre_dtheta_deg_max": float(np.degrees(dth[centre].max()))}


def interpolate(values: np.ndarray, xy: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Scattered values in the plane, linearly interpolated at other points.

    Parameters
    ----------
    values
        Values at the points ``xy`` (2, n).
    xy
        Where they are given.
    target
        Where they are wanted (2, m).

    Returns
    -------
    numpy.ndarray
        (m,) values: linear on a Delaunay triangulation of ``xy``, the nearest
        value outside its hull.
    """
    from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator

    lin = LinearNDInterpolator(xy.T, values)(target.T)
    miss = np.isnan(lin)
    if miss.any():
        lin[miss] = NearestNDInterpolator(xy.T, values)(target.T[miss])
    return lin


def radial_profile(x: np.ndarray, values: np.ndarray, r_grid: np.ndarray) -> np.ndarray:
    """Ring means of nodal values against radius, interpolated at ``r_grid``.

    Parameters
    ----------
    x
        Node coordinates (2 or 3, n); the radius is taken in (x, y).
    values
        A value per node.
    r_grid
        Radii to interpolate the ring means at.

    Returns
    -------
    numpy.ndarray
        The mean over every ring of nodes of equal radius (to 1 nm), linearly
        interpolated at ``r_grid``.
    """
    rr = np.round(np.hypot(x[0], x[1]), 9)
    radii, inv = np.unique(rr, return_inverse=True)
    mean = np.bincount(inv, values) / np.bincount(inv)
    return np.interp(r_grid, radii, mean)
