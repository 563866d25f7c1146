"""The parts of a brake as frozen dataclasses in SI units: rotor, pad, piston, mesh settings."""
from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from ..caliper.geometry import (
    CaliperGeometry,
    HatGeometry,
    PistonGuide,
    SupportGeometry,
    VentGeometry,
)
from ..materials import Material

logger = logging.getLogger(__name__)

__all__ = [
    "RotorGeometry",
    "PadGeometry",
    "PistonGeometry",
    "MeshSettings",
    "BrakeGeometry",
    "LENGTH_UNITS",
    "ANGLE_UNITS",
    "MODULUS_UNITS",
]


LENGTH_UNITS = {"mm": 1e-3, "m": 1.0}


ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}


MODULUS_UNITS = {"Pa": 1.0, "MPa": 1e6, "GPa": 1e9}


# defaults of the optional [mesh] fields (angles in degrees, converted on load)
MESH_DEFAULTS = {
    "order": 1,
    "rotor_coarse_factor": 4.0,
    "rotor_margin": 10.0,
    "rotor_z_ratio": 3.0,
    "pad_z_ratio": 2.0,
}


#: the optional per-body [mesh] fields: None (the default) keeps the rule of
#: ``size`` -- in-plane ``size``; through the thickness the fewest layers whose
#: element at z = 0 is at most ``size / 2`` thick (friction layer, rotor half)
#: and ``ceil(backplate_thickness / size)`` layers through the backplate
MESH_BODY_KEYS = ("pad_size", "rotor_size", "friction_layers", "backplate_layers",
                  "rotor_layers")


#: allowed element layers through one layer of a body: [1, MAX_LAYERS]
MAX_LAYERS = 200


# optional thermal / wear data of custom materials come from a built-in "base"
_BASE_DEFAULT = {"isotropic": "steel", "transversely_isotropic": "pad_resin"}


@dataclass(frozen=True)
class RotorGeometry:
    """The friction ring of the rotor (SI units).

    Attributes
    ----------
    inner_radius, outer_radius : float
        Radii of the friction ring (m).
    thickness : float
        Full thickness of the ring (m); the model meshes the inboard half.
    material : Material
        Rotor material.
    mount : str
        ``"ring_clamp"`` (the ring held at its inner radius) or ``"hat"`` (the
        flange of :attr:`hat` clamped at the bolt circle), :data:`ROTOR_MOUNTS`.
    hat : HatGeometry or None
        The mounting hat (``mount = "hat"`` only).
    vents : VentGeometry or None
        Cheeks and vanes of a vented ring; None: a solid ring.
    """

    inner_radius: float
    outer_radius: float
    thickness: float
    material: Material
    mount: str = "ring_clamp"
    hat: HatGeometry | None = None
    vents: VentGeometry | None = None


@dataclass(frozen=True)
class PadGeometry:
    """An annular-sector pad: friction layer (z = 0 side) on a steel backplate.

    Attributes
    ----------
    inner_radius, outer_radius : float
        Radii of the pad outline (m).
    arc_angle : float
        Angular extent of the pad (rad), in (0, pi).
    center_angle : float
        Angle of the pad centre line (rad); 0 is the +x axis.
    friction_thickness, backplate_thickness : float
        Layer thicknesses (m); the friction layer touches the rotor.
    friction_material, backplate_material : Material
        Layer materials.
    backplate_inner_radius, backplate_outer_radius : float or None
        Radii of the backplate outline (m) where it is larger than the
        lining (a real backplate carries the piston rim and the abutment
        ears); None: the lining's radii.
    leading_chamfer, trailing_chamfer : (float, float)
        ``(length, depth)`` of the chamfer at each end of the lining (m):
        the friction face is cut back linearly from ``depth`` at the end to
        0 at ``length`` along the arc (measured at the mean radius); (0, 0):
        none.
    slot_width : float
        Tangential width of a radial slot through the lining on its centre
        line (m); 0: no slot.
    slot_depth : float or None
        Depth of the slot from the friction face (m); None: the whole lining.
    """

    inner_radius: float
    outer_radius: float
    arc_angle: float
    center_angle: float
    friction_thickness: float
    backplate_thickness: float
    friction_material: Material
    backplate_material: Material
    backplate_inner_radius: float | None = None
    backplate_outer_radius: float | None = None
    leading_chamfer: tuple[float, float] = (0.0, 0.0)
    trailing_chamfer: tuple[float, float] = (0.0, 0.0)
    slot_width: float = 0.0
    slot_depth: float | None = None

    @property
    def backplate_radii(self) -> tuple[float, float]:
        """Inner and outer radius of the backplate outline (m); the lining's
        radii unless the backplate is larger."""
        return (self.inner_radius if self.backplate_inner_radius is None
                else self.backplate_inner_radius,
                self.outer_radius if self.backplate_outer_radius is None
                else self.backplate_outer_radius)

    @property
    def thickness(self) -> float:
        """Total pad thickness, friction layer plus backplate (m)."""
        return self.friction_thickness + self.backplate_thickness

    @property
    def leading_angle(self) -> float:
        """Angle of the leading edge (rad): the rotor turns in +theta, so a rotor
        point enters under the pad at the smaller angle."""
        return self.center_angle - 0.5 * self.arc_angle

    @property
    def trailing_angle(self) -> float:
        """Angle of the trailing edge (rad), where rotor points leave the pad."""
        return self.center_angle + 0.5 * self.arc_angle

    @property
    def area(self) -> float:
        """Area of the friction face (m^2)."""
        return 0.5 * self.arc_angle * (self.outer_radius ** 2 - self.inner_radius ** 2)


@dataclass(frozen=True)
class PistonGeometry:
    """A solid cylindrical piston pressing on the back of the pad.

    Attributes
    ----------
    diameter : float
        Diameter of the footprint on the backplate, which is also the diameter
        of the meshed cylinder (m).
    radius : float
        Radial position of the piston axis (m).
    angle : float
        Angular position of the piston axis *relative to the pad centre line*
        (rad); positive towards the trailing edge.
    length : float
        Length of the meshed cylinder along z (m).
    material : Material
        Piston material.
    bore_diameter : float
        Hydraulic bore diameter (m), which converts line pressure to clamp
        force (:attr:`hydraulic_area`); defaults to ``diameter``.
    rim_inner_diameter : float or None
        Inner diameter of the piston's annular rim (m): a real piston is a
        cup and bears on the backplate through its rim, between this
        diameter and :attr:`diameter`; None: a solid disc footprint.
    guide : PistonGuide
        How the housing holds the piston: bore clearance, seal, friction
        (the rigid piston's load path).
    """

    diameter: float
    radius: float
    angle: float
    length: float
    material: Material
    bore_diameter: float
    rim_inner_diameter: float | None = None
    guide: PistonGuide = PistonGuide()

    @property
    def footprint_area(self) -> float:
        """Area of the footprint on the backplate (m^2): the annular rim
        between :attr:`rim_inner_diameter` and :attr:`diameter`, or the disc."""
        inner = self.rim_inner_diameter or 0.0
        return 0.25 * math.pi * (self.diameter ** 2 - inner ** 2)

    @property
    def hydraulic_area(self) -> float:
        """Area that the line pressure acts on (m^2): pi bore_diameter^2 / 4."""
        return 0.25 * math.pi * self.bore_diameter ** 2


@dataclass(frozen=True)
class MeshSettings:
    """Mesh controls (SI units).

    Attributes
    ----------
    size : float
        Target in-plane element size at the friction interface (m).
    order : int
        Geometric and element order, 1 (P1) or 2 (isoparametric P2).
    rotor_coarse_factor : float
        Rotor element size away from the pad arc, as a multiple of ``size``.
    rotor_margin : float
        Angle (rad) added on both sides of the pad arc over which the rotor is
        meshed at the fine size.
    rotor_z_ratio, pad_z_ratio : float
        Largest over smallest element thickness through the rotor half and the
        friction layer; the smallest elements touch the friction interface.
    pad_size, rotor_size : float or None
        In-plane element size (m) of the pad and of the rotor under the pad;
        None: ``size``.
    friction_layers, backplate_layers, rotor_layers : int or None
        Element layers through the pad's friction layer (graded toward the
        friction face by ``pad_z_ratio``), the backplate (uniform) and the
        rotor half (graded toward the friction face by ``rotor_z_ratio``);
        None: the rule of ``size`` (:data:`MESH_BODY_KEYS`).
    """

    size: float
    order: int = 1
    rotor_coarse_factor: float = MESH_DEFAULTS["rotor_coarse_factor"]
    rotor_margin: float = math.radians(MESH_DEFAULTS["rotor_margin"])
    rotor_z_ratio: float = MESH_DEFAULTS["rotor_z_ratio"]
    pad_z_ratio: float = MESH_DEFAULTS["pad_z_ratio"]
    pad_size: float | None = None
    rotor_size: float | None = None
    friction_layers: int | None = None
    backplate_layers: int | None = None
    rotor_layers: int | None = None


@dataclass(frozen=True)
class BrakeGeometry:
    """A checked brake geometry in SI units.

    Parameters
    ----------
    rotor, pad, piston, mesh
        The components and the mesh controls.
    caliper, support
        The caliper (fixed or floating, fingers) and the pads' support in the
        bracket (:mod:`brakewear.caliper.geometry`).
    extra_pistons
        Further pistons of a multi-piston caliper beside :attr:`piston`
        (same side; a fixed caliper mirrors all of them).
    materials : dict
        Every material the file can name: the built-ins plus its
        ``[materials.NAME]`` tables.
    source : str
        Where the geometry came from (file path or ``"<dict>"``).
    units : dict
        The ``[units]`` table of the file (for messages and write-back).
    """

    rotor: RotorGeometry
    pad: PadGeometry
    piston: PistonGeometry
    mesh: MeshSettings
    caliper: CaliperGeometry = CaliperGeometry()
    support: SupportGeometry = SupportGeometry()
    extra_pistons: tuple[PistonGeometry, ...] = ()
    materials: Mapping[str, Material] = field(compare=False, repr=False, default_factory=dict)
    source: str = field(default="<dict>", compare=False)
    units: Mapping[str, str] = field(default_factory=dict, compare=False)

    @property
    def pistons(self) -> tuple[PistonGeometry, ...]:
        """Every piston on one side: :attr:`piston` and :attr:`extra_pistons`."""
        return (self.piston, *self.extra_pistons)

    @property
    def clamp_area(self) -> float:
        """Hydraulic area of one side's pistons (m^2): line pressure times this
        is the clamp force on each pad."""
        return sum(p.hydraulic_area for p in self.pistons)

    @property
    def piston_center(self) -> tuple[float, float]:
        """Cartesian (x, y) of the piston axis (m)."""
        ang = self.pad.center_angle + self.piston.angle
        return (self.piston.radius * math.cos(ang), self.piston.radius * math.sin(ang))
