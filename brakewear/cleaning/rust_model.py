"""The forward model of a dynamometer record of rust removal, with its derivatives.

Stop ``n`` of a record (contact pressure ``p_n``, sliding distance ``s_n``) can
remove ``d_n = k_r max(p_n - p_th, 0) s_n pad_share`` of oxide and removes
``min(h_n, d_n)`` of the ``h_n`` still there; its friction coefficient is
``mu_n = mu_iron (1 + (mu_factor - 1) phi_n)``, ``phi_n`` the part of the stop
that slid on rust (:mod:`brakewear.cleaning.rust_fit`).  Written with the cumulative
removal ``C_n = d_1 + ... + d_n``, the removal is ``clip(h - C_{n-1}, 0, d_n)``:
a piecewise linear function of the parameters whose kinks are where the layer
runs out at a stop's end (``h = C_n``) and where the threshold meets a stop's
pressure (``p_th = p_n``).

:func:`record_model` gives the two observables and their derivatives with
respect to the fit's coordinates :data:`COORDINATES` (``log k_r``, ``p_th``,
``log h_c``, ``mu_factor``, ``mu_iron``), in closed form.  On a kink it gives
one side's derivative (``side``: the layer's run-out and the threshold's
activation taken as if the parameters were moved up or down by an
infinitesimal amount); :func:`curvature` averages ``J^T J`` over the sides,
so that a fit that stops on a kink still has the curvature of both pieces.
"""
from __future__ import annotations

import itertools

import numpy as np

__all__ = ["COORDINATES", "record_model", "curvature"]

#: the fit's coordinates, in the order of the derivatives' columns
COORDINATES = ("k_rust", "threshold", "thickness", "mu_factor", "mu_iron")
#: fitted on their logarithms (positive, over decades)
LOG = frozenset({"k_rust", "thickness"})


def record_model(params: dict, pressure, distance, pad_share: float, side: tuple = (0, 0),
                 jac: bool = False):
    """The friction coefficient and the removed depth (m) per stop with ``params``
    (``k_rust``, ``threshold``, ``thickness``, ``mu_factor``, ``mu_iron``, SI).

    Parameters
    ----------
    params
        The parameters.
    pressure, distance
        Per stop the contact pressure (Pa) and the sliding distance (m).
    pad_share
        The share of a revolution a rotor point spends under the pad.
    side
        ``(s_h, s_p)``, each -1, 0 or +1: on a kink of the run-out (``s_h``) or of
        the threshold (``s_p``), the side whose derivative is taken (0: the
        removal of a stop that ends the layer exactly is the stop's whole
        ``d_n``, and a stop at the threshold's pressure removes nothing).
    jac
        Whether to return the derivatives too.

    Returns
    -------
    mu, removed : ndarray
        Per stop.
    J_mu, J_removed : ndarray
        Only with ``jac``: their derivatives (stops x 5) with respect to
        :data:`COORDINATES` (``d/d log k_r`` and ``d/d log h_c`` for the two
        fitted on their logarithms).
    """
    k, pth, h = params["k_rust"], params["threshold"], params["thickness"]
    f, mu_i = params["mu_factor"], params["mu_iron"]
    p, s = np.asarray(pressure, dtype=float), np.asarray(distance, dtype=float)
    s_h, s_p = side
    rel = 1e-9
    # a stop at the threshold removes oxide on its upper side only (s_p = -1: p_th just below)
    active = p > pth * (1.0 + rel * s_p) if s_p else p > pth
    a = k * pad_share * s * active
    d = a * (p - pth)
    cum = np.cumsum(d)
    prev = cum - d
    left = h - prev
    removed = np.clip(left, 0.0, d)
    # the pieces the derivatives are taken on: the stop's whole d_n (full), what was
    # left (part) or nothing; on a kink, those of the side s_h
    tol = rel * max(h, 1e-300) * s_h
    full = left >= d - tol
    part = ~full & (left > -tol)
    on_d = d > 0
    phi = np.where(on_d, np.divide(removed, d, out=np.zeros_like(d), where=on_d),
                   (left > 0).astype(float))
    mu = mu_i * (1.0 + (f - 1.0) * phi)
    if not jac:
        return mu, removed
    n = p.size
    dd = np.zeros((n, 5))
    dd[:, 0] = d                         # d d / d log k
    dd[:, 1] = -a                        # d d / d p_th
    dprev = np.cumsum(dd, axis=0) - dd
    dh = np.zeros((n, 5))
    dh[:, 2] = h                         # d h / d log h
    J_rem = np.where(full[:, None], dd, np.where(part[:, None], dh - dprev, 0.0))
    dphi = np.zeros((n, 5))
    m = part & on_d
    dphi[m] = (J_rem[m] * d[m, None] - removed[m, None] * dd[m]) / d[m, None] ** 2
    J_mu = mu_i * (f - 1.0) * dphi
    J_mu[:, 3] = mu_i * phi
    J_mu[:, 4] = 1.0 + (f - 1.0) * phi
    return mu, removed, J_mu, J_rem


def curvature(jacobian) -> np.ndarray:
    """``J^T J`` averaged over the four sides of the kinks (:func:`record_model`'s
    ``side``); ``jacobian(side)`` gives the whitened residuals' Jacobian on a side.
    Away from a kink the four are the same."""
    H = [(lambda J: J.T @ J)(jacobian(sd)) for sd in itertools.product((-1, 1), repeat=2)]
    return sum(H) / len(H)


def screen(pressure, distance, pad_share: float, removed=None, friction=None, *,
           sigma: dict, held: dict, keep: int = 3, never: bool | None = None) -> list[dict]:
    """Starts for the fit, one per piece of the model that fits the record best.

    The model is smooth between its kinks: fix the stop ``N`` the layer runs out
    in (or none) and which pressure levels lie above the threshold, and the
    removal is linear in ``(k_r, k_r p_th, h_c)`` (each stop before ``N``
    removes ``k_r pad_share s_n (p_n - p_th)``, stop ``N`` what is left) and the
    friction linear in ``(mu_iron, mu_iron (mu_factor - 1))`` once the share of
    stop ``N`` on rust is taken from that removal.  Every piece is fitted by
    linear least squares (weighted by ``sigma``; all the stops ``N`` of one set
    of levels at once, from cumulative sums) and the best piece of each of the
    ``keep`` best run-out stops, by chi-square, is returned as a parameter dict
    (``held`` for what a piece does not give; a friction record alone gives only
    when the layer ran out: the ``k_r`` that makes ``held``'s layer run out
    then).  ``never``: True for the pieces whose layer lasts only, False for
    those where it runs out only.
    """
    p, s = np.asarray(pressure, dtype=float), np.asarray(distance, dtype=float)
    n = p.size
    a = pad_share * s
    has_r = removed is not None and np.isfinite(removed).any()
    has_f = friction is not None and np.isfinite(friction).any()
    levels = np.unique(p)
    lows = np.concatenate([[0.0], levels[:-1]]) if has_r else np.array([held["threshold"]])
    Ns = np.arange(n + 1)                  # the run-out stop; n: the layer lasts
    pick = np.ones(n + 1, dtype=bool) if never is None else (Ns == n) == bool(never)
    found = []
    for j, low in enumerate(lows):
        act = p > low
        if has_r:
            theta, chi, phi_N = _removal_pieces(a, p, act, removed, sigma["removed"], low,
                                                levels[j])
        else:
            theta, chi, phi_N = None, np.zeros(n + 1), np.full(n + 1, 0.5)
        ok = pick & (np.ones(n + 1, dtype=bool) if theta is None else np.isfinite(chi))
        ab = None
        if has_f:
            ab, chi_f = _friction_pieces(friction, sigma["friction"], phi_N)
            chi = chi + chi_f
        for N in np.flatnonzero(ok):
            found.append((float(chi[N]), int(N), j, None if theta is None else theta[N],
                          None if ab is None else ab[N], act, float(phi_N[N])))
    found.sort(key=lambda t: t[0])
    best, seen = [], set()
    for _chi, N, _j, th, ab, act, ph in found:     # the best piece of each run-out stop
        if N not in seen:
            seen.add(N)
            best.append(_piece_start(th, ab, N, n, a, p, act, held, ph))
        if len(best) == keep:
            break
    return best


def _removal_pieces(a, p, act, removed, sigma: float, low: float, high: float):
    """Per run-out stop ``N`` (0..n; n: none) the least-squares ``(k_r, k_r p_th, h_c)``
    of the removal with the stops above ``low`` removing, its chi-square (inf where
    ``k_r <= 0`` or ``p_th`` would be above ``high``) and the share of stop N on rust."""
    n = p.size
    m = np.isfinite(removed)
    w = m / sigma ** 2
    r = np.where(m, removed, 0.0)
    x = np.column_stack([a * p * act, -a * act, np.zeros(n)])       # rows before N
    P = np.concatenate([[0.0], np.cumsum(x[:, 0])])                   # sums over m < N
    Q = np.concatenate([[0.0], np.cumsum(x[:, 1])])
    y = np.column_stack([-P, -Q, np.ones(n + 1)])                     # row N
    wN = np.concatenate([w, [0.0]])
    rN = np.concatenate([r, [0.0]])
    outer = np.concatenate([np.zeros((1, 3, 3)),
                            np.cumsum(w[:, None, None] * x[:, :, None] * x[:, None, :], 0)])
    M = outer + wN[:, None, None] * y[:, :, None] * y[:, None, :]
    b = np.concatenate([np.zeros((1, 3)), np.cumsum((w * r)[:, None] * x, 0)]) \
        + (wN * rN)[:, None] * y
    M[n, 2, 2] = 1.0                       # no stop runs the layer out: h_c is not seen
    theta = _solve_batched(M, b)
    floor = theta[:, 1] < low * theta[:, 0]
    if floor.any():                        # p_th held at the piece's floor
        T = np.array([[1.0, 0.0], [low, 0.0], [0.0, 1.0]])
        M2 = np.einsum("ki,nkl,lj->nij", T, M, T)
        b2 = b @ T
        th2 = _solve_batched(M2, b2) @ T.T
        theta[floor] = th2[floor]
    rw = float(np.sum(w * r ** 2))
    chi = rw - 2 * np.einsum("ni,ni->n", theta, b) + np.einsum("ni,nij,nj->n", theta, M, theta)
    chi[n] += theta[n, 2] ** 2             # the placeholder row of h_c
    bad = ~(theta[:, 0] > 0) | (theta[:, 1] >= high * theta[:, 0]) | \
        ((np.arange(n + 1) < n) & ~(theta[:, 2] > 0))
    chi[bad] = np.inf
    d_N = a * (theta[:n, 0] * p - theta[:n, 1]) * act
    r_N = np.einsum("ni,ni->n", y[:n], theta[:n])
    phi = np.ones(n + 1)
    phi[:n] = np.where(d_N > 0, np.clip(r_N / np.where(d_N > 0, d_N, 1.0), 0.0, 1.0), 1.0)
    return theta, chi, phi


def _friction_pieces(friction, sigma: float, phi_N):
    """Per run-out stop ``N`` the least-squares ``(mu_iron, mu_iron (mu_factor - 1))``
    of the friction (on rust before N, on iron after, ``phi_N`` of stop N) and its
    chi-square."""
    n = friction.size
    m = np.isfinite(friction)
    w = m / sigma ** 2
    f = np.where(m, friction, 0.0)
    cw = np.concatenate([[0.0], np.cumsum(w)])            # sums over the stops before N
    cf = np.concatenate([[0.0], np.cumsum(w * f)])
    wN = np.concatenate([w, [0.0]])
    fN = np.concatenate([f, [0.0]])
    S1, Sf, Sff = cw[-1], cf[-1], float(np.sum(w * f ** 2))
    Sp = cw + wN * phi_N                                    # sum of w phi
    Spp = cw + wN * phi_N ** 2
    Sfp = cf + wN * fN * phi_N
    G = np.stack([np.stack([np.full(n + 1, S1), Sp], -1), np.stack([Sp, Spp], -1)], -2)
    c = np.stack([np.full(n + 1, Sf), Sfp], -1)
    ab = _solve_batched(G, c)
    chi = Sff - 2 * np.einsum("ni,ni->n", ab, c) + np.einsum("ni,nij,nj->n", ab, G, ab)
    return ab, chi


def _solve_batched(M, b):
    """``M x = b`` per leading index, scaled to a unit diagonal first (the unknowns
    differ by decades); a singular system gives its least-norm answer."""
    dg = np.einsum("nii->ni", M)
    D = np.where(dg > 0, 1.0 / np.sqrt(np.where(dg > 0, dg, 1.0)), 1.0)
    Ms = M * D[:, :, None] * D[:, None, :]
    z = np.einsum("nij,nj->ni", np.linalg.pinv(Ms, hermitian=True), b * D)
    return z * D


def _piece_start(theta, ab, N, n, a, p, act, held, phi_N) -> dict:
    """A piece's least-squares values as parameters (see :func:`screen`)."""
    x = dict(held)
    if theta is not None:
        u, c, h = theta
        x["k_rust"], x["threshold"] = float(u), float(max(c / u, 0.0))
        removable = float(np.sum(a * np.maximum(p - x["threshold"], 0.0))) * u
        x["thickness"] = float(h) if N < n else max(2.0 * removable, float(held["thickness"]))
    else:                           # the k_r that makes the held layer run out in stop N
        dk = a * np.maximum(p - held["threshold"], 0.0) * act
        within = float(dk[:N].sum() + (phi_N * dk[N] if N < n else dk.sum()))
        if within > 0:
            x["k_rust"] = float(held["thickness"] / within) * (1.0 if N < n else 0.5)
    if ab is not None and ab[0] > 0:
        x["mu_iron"], x["mu_factor"] = float(ab[0]), float(1.0 + ab[1] / ab[0])
    return x
