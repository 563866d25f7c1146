"""The caliper, the pad support and the rotor mount as frozen dataclasses (SI units).

These are the parts of a brake that carry the load between the hydraulic
pressure and the friction faces, the ones a brake engineer checks first:

- :class:`CaliperGeometry`: a *floating* caliper (piston(s) on the inboard
  pad, fingers on the outboard pad, the caliper sliding on its pins so that
  the finger force equals the piston force) or a *fixed* caliper (opposed
  pistons of the same size and position on both sides);
- :class:`FingerGeometry`: one finger footprint on the outboard backplate;
- :class:`SupportGeometry`: how the bracket holds each pad in its plane --
  ``"bilateral"`` (both backplate ends held, the idealisation that blocks any
  tilt and can pull), ``"push"`` (the trailing abutment bears, the leading one
  has a clearance) or ``"pull"`` (the leading hook bears, the trailing end has
  a clearance); unilateral abutments add radial rails and an anti-rattle
  spring so the pad is held where no abutment bears;
- :class:`PistonGuide`: how the caliper holds its piston -- the bore's radial
  clearance and guided length, the square-section seal (its section and the
  rubber's modulus), the friction at the piston's rim and in the bore --
  which decides how far the inboard pad may tilt (the rigid piston of
  :mod:`brakewear.caliper.rows`);
- :class:`HatGeometry` and :class:`VentGeometry`: the rotor's mounting hat
  (flange clamped at the bolt circle, a cylindrical wall, the friction ring)
  and a vented ring (two cheeks joined by radial vanes).

Absent from a geometry file they default to the idealised brake: a fixed
caliper with the one piston of ``[piston]`` on each side, bilateral support,
the ring clamped at its inner radius, a solid ring.  For that brake the half
model (one pad, the rotor's inboard half, a mirror plane) is exact.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "FingerGeometry",
    "PistonGuide",
    "CaliperGeometry",
    "SupportGeometry",
    "HatGeometry",
    "VentGeometry",
    "CALIPER_TYPES",
    "SUPPORT_TYPES",
    "ROTOR_MOUNTS",
]


#: allowed ``caliper.type``
CALIPER_TYPES = ("fixed", "floating")

#: allowed ``support.type``
SUPPORT_TYPES = ("bilateral", "push", "pull")

#: allowed ``rotor.mount``
ROTOR_MOUNTS = ("ring_clamp", "hat")


@dataclass(frozen=True)
class FingerGeometry:
    """One caliper finger bearing on the back of the outboard pad.

    Attributes
    ----------
    diameter : float
        Diameter of the (circular) footprint on the backplate (m).
    radius : float
        Radial position of the footprint centre (m).
    angle : float
        Angular position of the footprint centre relative to the pad centre
        line (rad), positive toward the trailing edge.
    """

    diameter: float
    radius: float
    angle: float

    @property
    def area(self) -> float:
        """Footprint area (m^2)."""
        return 0.25 * math.pi * self.diameter ** 2


@dataclass(frozen=True)
class CaliperGeometry:
    """How the clamp force reaches the two pads.

    Attributes
    ----------
    type : str
        ``"fixed"``: the pistons of :attr:`BrakeGeometry.pistons` press both
        pads, mirrored through the rotor's mid-plane; ``"floating"``: they
        press the inboard pad and the :attr:`fingers` the outboard pad with
        the same total force (the caliper slides on its pins).
    fingers : tuple of FingerGeometry
        Finger footprints on the outboard pad (floating calipers only); with
        a rigid bridge the clamp force is shared in proportion to their areas.
    bridge_tilt : float
        Compliance of the caliper bridge (rad/N, floating calipers only): under
        a clamp force ``F`` the bridge spreads and the fingers' jaw turns by
        ``bridge_tilt x F`` about a tangential axis, away from the pad at its
        inner radius (the bridge reaches over the rotor's outer edge).  0: a
        rigid bridge.
    finger_stiffness : float
        Normal stiffness per unit area (Pa/m) of the layer between the jaw and
        the backplate (a shim, the local compliance of finger and plate): with
        a tilted jaw the finger pressure is ``finger_stiffness x`` the jaw's
        local approach (:func:`brakewear.caliper.loads.jaw_pressure`).
    bore_tilt : float
        The same compliance on the inboard side (rad/N, floating calipers
        only): under ``F`` the housing's bore turns by ``bore_tilt x F`` about
        a tangential axis through the centre of the bore's mouth, its deep end
        moving outward (the housing opens at the inner radius); it turns the
        seal's groove and the bore wall that guide the rigid piston.
    """

    type: str = "fixed"
    fingers: tuple[FingerGeometry, ...] = ()
    bridge_tilt: float = 0.0
    finger_stiffness: float = 1e12
    bore_tilt: float = 0.0

    @property
    def symmetric(self) -> bool:
        """Whether both pads get the same load (the half model's assumption)."""
        return self.type == "fixed"


@dataclass(frozen=True)
class SupportGeometry:
    """How the bracket holds each pad in its plane.

    Attributes
    ----------
    type : str
        ``"bilateral"``, ``"push"`` or ``"pull"`` (:data:`SUPPORT_TYPES`).
    clearance : float
        Tangential clearance (m) between the non-bearing pad end and the
        bracket (push: the leading end; pull: the trailing end).
    rail_stiffness : float
        Radial stiffness of the rails the backplate ends rest on (N/m per
        abutment face); a stiff steel bracket by default.
    spring_stiffness : float
        Tangential stiffness of the anti-rattle spring (N/m): it holds the
        pad where no abutment bears (no friction, or before the clearance
        closes) and is small enough not to carry a braking drag: the pad's
        clip.
    abutment_friction : float
        Coulomb friction coefficient between the backplate's ends and the
        bracket's abutments: the ends slide there along the rotor axis, and
        the friction holds the pad against tilting in proportion to the drag
        the abutment carries (the rigid-piston load path,
        :mod:`brakewear.caliper.rows`; the FE interface's stops are
        frictionless).
    """

    type: str = "bilateral"
    clearance: float = 0.0
    rail_stiffness: float = 1e9
    spring_stiffness: float = 1e5
    abutment_friction: float = 0.0

    @property
    def bearing_end(self) -> str | None:
        """``"trailing"`` (push), ``"leading"`` (pull) or None (bilateral)."""
        return {"push": "trailing", "pull": "leading"}.get(self.type)


@dataclass(frozen=True)
class PistonGuide:
    """How the caliper's housing holds its piston (SI units).

    The piston stands on the backplate; ``stand_out`` from it the bore's
    mouth begins, and the piston is guided over ``engagement`` from there.
    A square-section seal sits in a groove of the bore ``seal_position`` from
    the mouth (to its centre); it grips the piston and holds it elastically,
    softly in tilt.  The bore wall holds the piston only once the radial
    ``clearance`` is taken up.

    Attributes
    ----------
    clearance : float
        Radial clearance between piston and bore (m, one side).
    engagement : float
        Guided length of the piston in the bore (m).
    stand_out : float
        Distance from the piston's face (on the backplate) to the bore's mouth (m).
    seal_position : float
        Distance from the bore's mouth to the seal's centre (m).
    seal_width, seal_height : float
        The seal's section: radial width and axial height (m).
    seal_modulus : float
        Young's modulus of the seal's rubber (Pa).
    rim_friction : float
        Coulomb friction coefficient between the piston's rim and the backplate.
    bore_friction : float
        Coulomb friction coefficient between the piston and the bore wall.
    """

    clearance: float = 0.08e-3
    engagement: float = 20e-3
    stand_out: float = 5e-3
    seal_position: float = 5e-3
    seal_width: float = 3e-3
    seal_height: float = 3e-3
    seal_modulus: float = 6e6
    rim_friction: float = 0.15
    bore_friction: float = 0.15


@dataclass(frozen=True)
class HatGeometry:
    """The rotor's mounting hat, on the outboard side of the friction ring.

    The hat wall is a cylinder of mid radius :attr:`wall_radius` from the
    ring's outboard face (``z = -rotor.thickness``) to the flange; the
    flange is an annular plate from :attr:`bore_radius` to the wall, whose
    mounting face (``z = -rotor.thickness - height``) is clamped by the hub
    and the wheel out to :attr:`bolt_circle_radius`.

    Attributes
    ----------
    height : float
        Axial distance from the ring's outboard face to the mounting face (m).
    wall_radius, wall_thickness : float
        Mid radius and thickness of the cylindrical hat wall (m); the wall's
        outer surface meets the ring at ``rotor.inner_radius``.
    flange_thickness : float
        Axial thickness of the flange (m).
    bore_radius : float
        Radius of the centre bore (m).
    bolt_circle_radius : float
        Radius out to which the mounting face is clamped (m).
    """

    height: float
    wall_radius: float
    wall_thickness: float
    flange_thickness: float
    bore_radius: float
    bolt_circle_radius: float


@dataclass(frozen=True)
class VentGeometry:
    """A vented friction ring: two cheeks joined by straight radial vanes.

    Attributes
    ----------
    cheek_thickness : float
        Axial thickness of each cheek (m); the channel between them is
        ``rotor.thickness - 2 cheek_thickness`` high.
    vane_count : int
        Number of vanes around the ring.
    vane_width : float
        Tangential width of a vane (m), constant along the radius.
    """

    cheek_thickness: float
    vane_count: int
    vane_width: float
