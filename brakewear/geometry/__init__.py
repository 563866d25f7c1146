"""Brake geometry: the parts of a disc brake and the checked TOML files that define them.

:mod:`~brakewear.geometry.parts` holds the dataclasses (rotor, pad, piston,
mesh settings), :mod:`~brakewear.geometry.files` reads and checks geometry
files (docs: reference/geometry).
"""

from .files import (
    available_geometries,
    geometry_dir,
    geometry_file,
    geometry_from_dict,
    load_geometry,
)
from .parts import (
    ANGLE_UNITS,
    LENGTH_UNITS,
    MODULUS_UNITS,
    BrakeGeometry,
    MeshSettings,
    PadGeometry,
    PistonGeometry,
    RotorGeometry,
)

__all__ = [
    "load_geometry",
    "geometry_from_dict",
    "available_geometries",
    "geometry_dir",
    "geometry_file",
    "RotorGeometry",
    "PadGeometry",
    "PistonGeometry",
    "MeshSettings",
    "BrakeGeometry",
    "LENGTH_UNITS",
    "ANGLE_UNITS",
    "MODULUS_UNITS",
]
