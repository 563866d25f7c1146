"""The caliper's load path on a brake model's meshes: clamp loads and pad supports.

The clamp force ``F = line_pressure x clamp_area`` (the hydraulic area of one
side's pistons) reaches the pads' backs through each piston's footprint (the
annular rim between ``rim_inner_diameter`` and ``diameter``, or the disc),
integrated mesh-independently (:func:`~brakewear.fem.footprint.footprint_load`),
each carrying ``line_pressure x`` its own bore area.  The half and the full
model integrate the same footprint with the same rule, so a pad gets the same
nodal loads in both (the half model equals the full one where its assumption
holds).  In the full model a fixed caliper presses the outboard pad with the
mirrored pistons, a floating one with its fingers, which share ``F`` in
proportion to their footprint areas (the caliper slides on its pins, so the
finger force balances the piston force).  A compliant bridge
(``caliper.bridge_tilt > 0``) turns the fingers' jaw under the clamp force,
so the finger pressure varies across the footprints (:func:`jaw_pressure`).

Supports of the pads in the bracket: ``"bilateral"`` holds the backplate's
end faces in-plane (Dirichlet); push and pull supports are unilateral
abutments (:mod:`brakewear.contact.supports`).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..errors import SceneError
from ..fem.boundary import assemble_traction, boundary_dofs
from ..fem.footprint import annulus, footprint_load
from ..mesh.surface import is_quadratic, tributary_areas

logger = logging.getLogger(__name__)

__all__ = ["clamp_loads", "pad_support_dofs", "footprints", "uniform_traction",
           "half_model_holds", "resolve_layout", "jaw_pressure", "JawPressure"]


def half_model_holds(geometry) -> bool:
    """Whether one pad and the rotor's inboard half with a mirror plane model the
    brake exactly: both pads get the same load (a fixed caliper) and the rotor
    is symmetric about its mid-plane (no hat)."""
    return geometry.caliper.symmetric and geometry.rotor.mount == "ring_clamp"


def resolve_layout(geometry, layout: str, rotor: str = "elastic", strict: bool = False) -> str:
    """``"half"`` or ``"full"`` for a model layout (``"auto"``: half where
    :func:`half_model_holds` or the rotor is rigid, else full).  ``strict``:
    refuse a layout the model cannot build, warn of a half model whose
    assumption does not hold."""
    if layout not in ("auto", "half", "full"):
        raise SceneError(f"layout = {layout!r} is not allowed; allowed: 'auto', 'half', 'full'")
    holds = half_model_holds(geometry)
    if layout == "auto":
        layout = "half" if holds or rotor == "rigid" else "full"
    if strict and layout == "full" and rotor == "rigid":
        raise SceneError("layout = 'full' needs rotor = 'elastic': a rigid rotor is the "
                         "plane z = 0, with no second friction face")
    if strict and layout == "half" and not holds:
        logger.warning("half model of an unsymmetric brake (%s caliper, rotor mount %s): "
                       "the outboard pad is taken to carry the inboard pad's load",
                       geometry.caliper.type, geometry.rotor.mount)
    return layout


def _center(geometry, radius: float, angle: float) -> tuple[float, float]:
    a = geometry.pad.center_angle + angle
    return radius * math.cos(a), radius * math.sin(a)


def footprints(geometry, side: str) -> list[tuple[tuple[float, float], float, float, float]]:
    """``(centre (x, y), inner radius, outer radius, share of F)`` of each footprint
    on the ``"in"`` (pistons) or ``"out"`` side (mirrored pistons or fingers)."""
    cal = geometry.caliper
    if side == "out" and cal.type == "floating":
        total = sum(f.area for f in cal.fingers)
        return [(_center(geometry, f.radius, f.angle), 0.0, 0.5 * f.diameter, f.area / total)
                for f in cal.fingers]
    A = geometry.clamp_area
    return [(_center(geometry, p.radius, p.angle), 0.5 * (p.rim_inner_diameter or 0.0),
             0.5 * p.diameter, p.hydraulic_area / A) for p in geometry.pistons]


@dataclass(frozen=True)
class JawPressure:
    """The finger pressure of a tilted caliper jaw on the outboard backplate:
    ``p(x) = k max(0, delta + theta (e . x))``, ``e`` the unit radial vector of
    the pad's centre line (the jaw turns about a tangential axis).

    Attributes
    ----------
    stiffness : float
        ``k``, the finger layer's normal stiffness per unit area (Pa/m).
    delta : float
        The jaw's approach at the rotor axis (m), from the force balance.
    theta : float
        The jaw's tilt (rad): ``bridge_tilt x F``.
    direction : tuple of float
        ``e`` (x, y).
    forces : tuple of float
        Each finger's force (N), summing to ``F``.
    """

    stiffness: float
    delta: float
    theta: float
    direction: tuple[float, float]
    forces: tuple[float, ...]

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Pressure (Pa) at points ``x (3, n)`` if they lie under a finger."""
        s = self.direction[0] * x[0] + self.direction[1] * x[1]
        return self.stiffness * np.maximum(self.delta + self.theta * s, 0.0)


def _disc_force(k: float, a: float, A: float, B: float) -> float:
    """``k`` times the integral of ``max(0, A + B u)`` over a disc of radius ``a``,
    ``u`` the coordinate along the tilt scaled by ``a`` (``B >= 0``)."""
    if B <= 0.0:
        return k * math.pi * a * a * max(A, 0.0)

    def G(u: float) -> float:   # antiderivative of 2 sqrt(1 - u^2) (A + B u)
        r = math.sqrt(max(1.0 - u * u, 0.0))
        return A * (u * r + math.asin(u)) - 2.0 * B * r ** 3 / 3.0
    u0 = min(max(-A / B, -1.0), 1.0)
    return k * a * a * (G(1.0) - G(u0))


def jaw_pressure(geometry, F: float) -> JawPressure:
    """The finger pressure of a floating caliper's jaw under the clamp force ``F``
    (N): the jaw, rigid, turned by ``theta = caliper.bridge_tilt x F`` so that it
    leaves the backplate at the inner radius, pressing through a layer of
    stiffness ``caliper.finger_stiffness``; its approach ``delta`` is the one
    whose finger forces (over the exact circular footprints, in closed form)
    sum to ``F``.  ``theta = 0``: a uniform pressure, each finger's force in
    proportion to its area."""
    cal = geometry.caliper
    if not (cal.bridge_tilt >= 0.0 and cal.finger_stiffness > 0.0 and cal.fingers):
        raise SceneError(f"caliper: bridge_tilt = {cal.bridge_tilt!r} rad/N (need >= 0), "
                         f"finger_stiffness = {cal.finger_stiffness!r} Pa/m (need > 0) and "
                         f"{len(cal.fingers)} finger(s) (need >= 1) do not make a jaw")
    k, theta = cal.finger_stiffness, cal.bridge_tilt * F
    a0 = geometry.pad.center_angle
    e = (math.cos(a0), math.sin(a0))
    discs = [(0.5 * f.diameter, f.radius * math.cos(f.angle)) for f in cal.fingers]

    def forces(delta: float) -> list[float]:
        return [_disc_force(k, a, delta + theta * s, theta * a) for a, s in discs]
    area = sum(math.pi * a * a for a, _ in discs)
    lo = -theta * max(s + a for a, s in discs)                  # no finger touches
    hi = 1.01 * F / (k * area) - theta * min(s - a for a, s in discs)  # pressed > F/A
    if theta == 0.0 or F <= 0.0:
        delta = F / (k * area)
    else:
        delta = brentq(lambda d: sum(forces(d)) - F, lo, hi, xtol=1e-14 * (hi - lo),
                       rtol=4 * np.finfo(float).eps)
    return JawPressure(k, delta, theta, e, tuple(forces(delta)))


def uniform_traction(mesh, facets: str, F: float) -> np.ndarray:
    """Nodal loads of a uniform traction of total ``F`` (N) toward -z on ``facets``."""
    if is_quadratic(mesh):
        # curved (isoparametric) facets: the area the traction is integrated over
        area = -assemble_traction(mesh, facets, (0.0, 0.0, -1.0))[2::3].sum()
    else:
        area = tributary_areas(mesh, facets).sum()
    return assemble_traction(mesh, facets, (0.0, 0.0, -F / area))


def clamp_loads(geometry, pad_mesh, line_pressure: float, full: bool,
                sides: tuple[str, ...] = ("in", "out")) -> np.ndarray:
    """Nodal loads (DOF ``3 node + i`` of ``pad_mesh``) of the clamp force on the
    pads' backs: the inboard pad (side ``"in"``) pressed toward -z, the
    outboard one (``"out"``, full model only) toward +z, each with
    ``F = line_pressure x clamp_area``."""
    F = line_pressure * geometry.clamp_area
    f = np.zeros(3 * pad_mesh.p.shape[1])
    todo = [s for s in (("in", "back_in" if full else "back", -1.0), ("out", "back_out", 1.0))
            if s[0] in sides and (full or s[0] == "in")]
    for side, facets, sign in todo:
        if side == "out" and geometry.caliper.bridge_tilt > 0.0:
            f += _jaw_load(geometry, pad_mesh, facets, F)
            continue
        for c, ri, ro, share in footprints(geometry, side):
            f += footprint_load(pad_mesh, facets, annulus(c, ri, ro), F * share,
                                direction=(0.0, 0.0, sign))
    return f


def _jaw_load(geometry, pad_mesh, facets: str, F: float) -> np.ndarray:
    """Nodal loads of a tilted jaw's fingers (:func:`jaw_pressure`) toward +z."""
    jaw = jaw_pressure(geometry, F)
    f = np.zeros(3 * pad_mesh.p.shape[1])
    for (c, ri, ro, _), Fi in zip(footprints(geometry, "out"), jaw.forces):
        if Fi > 1e-9 * F:     # a finger the jaw has lifted off carries nothing
            disc = annulus(c, ri, ro)
            f += footprint_load(pad_mesh, facets, lambda x, d=disc: d(x) * jaw(x), Fi,
                                direction=(0.0, 0.0, 1.0))
    logger.debug("jaw tilt %.3g mrad, finger forces %s N", 1e3 * jaw.theta,
                 ", ".join(f"{x:.4g}" for x in jaw.forces))
    return f


def pad_support_dofs(geometry, pad_mesh) -> np.ndarray:
    """Supported DOFs (pad numbering) of a bilateral support: the backplate's end
    faces held in-plane; none for push and pull supports (their abutments are
    contact pairs)."""
    if geometry.support.type != "bilateral":
        return np.zeros(0, dtype=np.int64)
    return boundary_dofs(pad_mesh, "abutment", [0, 1])
