"""The bedded state solved directly: the steady state of Archard wear under a duty.

In the steady state the gap no longer changes but by the rigid motion the
load path lets each pad make: its closing rate -- the pad's wear ``k_pad p
omega r`` plus the rotor rings' under each node -- is uniform on each face's
flat friction face where the load path holds the pad square (``p r``
constant), and affine along a tilt the load path leaves free (the pad tilts
as it wears; its pressure's moment is the one the load path's statics give).

:func:`bedded_gap` finds the gap on the interface's own contact solves
(faces touching, :func:`~brakewear.cleaning.bedding.gauged`), at the duty's
mean load (exact for a brake linear in the load; the bedding history tells
how far a caliper's row states take it).  Each iteration is one contact
solve: the rate's departure from its steady form, over the pad's wear per
pascal ``kappa = k_pad omega r``, is a pressure correction ``dp`` (which
keeps each face's force); the gap steps by the interface's own normal
compliance times ``dp`` -- an explicit wear step at its stability limit, in
which the stiff, local modes settle at once -- and Anderson acceleration
mixes the iterates, which settles the pad's soft modes (its bending and
tilting on the load path) in a few dozen solves instead of the hundreds of
applications a bedding takes.  A mixed gap the load path cannot carry (a
solver error) restarts the mixing from the last gap.
"""
from __future__ import annotations

import logging

import numpy as np

from ..errors import ConvergenceError, SolverError, WearError
from ..mesh.rings import rotor_wear_rate
from .bedding import BeddedState, BeddingDuty, coning_gap_of, face_masks, gauged, pressure_change

logger = logging.getLogger(__name__)

__all__ = ["bedded_gap", "closing_rate"]


def closing_rate(itf, p: np.ndarray, omega: float, k_pad: float,
                 k_rotor: float) -> np.ndarray:
    """The gap's closing rate per pad node (m/s): the pad's wear and the rotor rings'."""
    v = omega * itf.r
    rate = k_pad * np.maximum(p, 0.0) * v
    if k_rotor > 0:
        q = k_rotor * np.maximum(p, 0.0) * v * itf.area
        rate = rate + itf.W @ rotor_wear_rate(q, itf.W, itf.ring, itf.rotor_area)
    return rate


class _Anderson:
    """Anderson mixing (type II, depth ``m``) of a fixed-point iteration ``x <- x + f``."""

    def __init__(self, m: int):
        self.m, self.X, self.F = m, [], []

    def __call__(self, x: np.ndarray, f: np.ndarray) -> np.ndarray:
        self.X.append(x.copy())
        self.F.append(f.copy())
        if len(self.X) > self.m + 1:
            self.X.pop(0)
            self.F.pop(0)
        if len(self.X) < 2 or self.m == 0:
            return x + f
        dX = np.diff(np.array(self.X), axis=0).T
        dF = np.diff(np.array(self.F), axis=0).T
        gamma = np.linalg.lstsq(dF, f, rcond=None)[0]
        return x + f - (dX + dF) @ gamma


class _Faces:
    """Each face's flat nodes, its tilt modes (on every node of the face) and the
    split of a rate into its affine part and the rest."""

    def __init__(self, itf, thickness):
        self.itf = itf
        self.all, self.flat = face_masks(itf, thickness), face_masks(itf, thickness, True)
        n = itf.area.size
        self.modes = []                  # (face, column of the basis) -> gap shape
        self.basis = []
        for m_all, m in zip(self.all, self.flat):
            xi = itf.r - itf.r[m].mean()
            eta = itf.x[1] - itf.x[1][m].mean()
            cols = []
            for c in (xi, eta):
                c = c / np.abs(c[m]).max()
                self.modes.append(np.where(m_all, c, 0.0))
                cols.append(c[m])
            self.basis.append(np.array([np.ones(m.sum())] + cols).T)
        self.n = n

    def split(self, rate, kappa) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(rest, tilt, mean)``: the rate's departure from its affine fit over ``kappa``
        (Pa), each face's two tilt coefficients over its mean, and the means."""
        rest, tilt, mean = np.zeros(self.n), [], []
        for m, Phi in zip(self.flat, self.basis):
            w = self.itf.area[m] / kappa[m]
            alpha = np.linalg.solve(Phi.T @ (w[:, None] * Phi), Phi.T @ (w * rate[m]))
            rest[m] = (rate[m] - Phi @ alpha) / kappa[m]
            tilt += [alpha[1] / alpha[0], alpha[2] / alpha[0]]
            mean.append(alpha[0])
        return rest, np.array(tilt), np.array(mean)

    def tilt_pressure(self, tilt, mean, kappa, held) -> np.ndarray:
        """The pressure correction (Pa) of the held tilts' rate."""
        out = np.zeros(self.n)
        for k, (f, c) in enumerate((f, c) for f in range(len(self.flat)) for c in (1, 2)):
            if held[k]:
                m = self.flat[f]
                out[m] += tilt[k] * mean[f] * self.basis[f][:, c] / kappa[m]
        return out


def bedded_gap(itf, duty: BeddingDuty, *, mu: float, k_pad: float, k_rotor: float = 0.0,
               band: tuple[float, float], thickness: float | None = None,
               gap0: np.ndarray | None = None, tol: float = 5e-3, max_iter: int = 120,
               depth: int = 8, free_tilts: bool = False) -> BeddedState:
    """The bedded state of ``itf`` under ``duty`` (see the module).

    Parameters
    ----------
    itf
        The interface (its ``solve``, ``at_line_pressure``, ``normal_stiffness``).
    duty
        The :class:`~brakewear.cleaning.bedding.BeddingDuty` (its weighted mean is solved).
    mu
        The friction coefficient.
    k_pad, k_rotor
        The wear coefficients (1/Pa) of pad and rotor (their ratio shapes the state).
    band, thickness
        The friction band (m) and the rotor's thickness (m; None: one face).
    gap0
        The gap to start from (default: none, a new pad).
    tol
        The largest departure of the rate from its steady form, as a pressure
        correction over the pressure (L2, area-weighted).
    max_iter, depth
        Iterations (one contact solve each) and the Anderson mixing depth.
    free_tilts
        The load path leaves the pads' tilts free: the rate is uniform up to them.

    Returns
    -------
    BeddedState
        ``extra["tilt_rate"]``: each face's radial and circumferential tilt of the
        closing rate over its mean at the end.

    Raises
    ------
    ConvergenceError
        When the residual is above ``tol`` after ``max_iter`` iterations.
    """
    if not (k_pad > 0 and k_rotor >= 0):
        raise WearError(f"k_pad = {k_pad!r}, k_rotor = {k_rotor!r}: need k_pad > 0, k_rotor >= 0")
    case = duty.mean()
    solver = itf.at_line_pressure(case.line_pressure[0])
    fc = _Faces(itf, thickness)
    thermal = coning_gap_of(itf, band, thickness, case.coning[0])
    compliance = itf.area / np.asarray(itf.normal_stiffness, dtype=float)     # m/Pa
    kappa = k_pad * duty.omega * itf.r
    held = np.full(2 * len(fc.flat), not free_tilts)
    g = gauged(np.zeros(itf.area.size) if gap0 is None else np.asarray(gap0, float), fc.all)
    sol = solver.solve(gauged(g + thermal, fc.all), None, mu=mu)
    p, active, solves = sol.pressure, sol.active, 1
    mix, residuals, restarts = _Anderson(depth), [], 0
    for it in range(1, max_iter + 1):
        rest, tilt, mean = fc.split(closing_rate(itf, p, duty.omega, k_pad, k_rotor), kappa)
        dp = rest + fc.tilt_pressure(tilt, mean, kappa, held)
        res = pressure_change(p - dp, p, itf.area)
        residuals.append(res)
        logger.debug("bedded gap: iteration %d, residual %.3e", it, res)
        if res <= tol:
            return BeddedState(gauged(g, fc.all), p, it, solves, residuals, duty,
                               {"tilt_rate": tilt.tolist(), "restarts": restarts})
        trial = gauged(mix(g, compliance * dp), fc.all)
        try:
            sol = solver.solve(gauged(trial + thermal, fc.all), active, mu=mu)
        except SolverError:
            # the mixed gap asks more of the load path than it gives: mix afresh from here
            mix, restarts = _Anderson(depth), restarts + 1
            trial = gauged(g + compliance * dp, fc.all)
            sol = solver.solve(gauged(trial + thermal, fc.all), active, mu=mu)
            solves += 1
        solves += 1
        g, p, active = trial, sol.pressure, sol.active
    raise ConvergenceError(f"the bedded state did not settle in {max_iter} iterations "
                           f"({solves} contact solves): the rate departs from its steady "
                           f"form by {residuals[-1]:.2e} of the pressure (tolerance {tol:.0e})",
                           figures={"iterations": max_iter, "residual": residuals[-1],
                                    "solves": solves})
