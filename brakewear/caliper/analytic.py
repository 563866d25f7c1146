"""Closed forms of the caliper's parts: a rubber seal in its groove, a ring of springs, a
piston in its bore (the checks of :mod:`brakewear.caliper.parts`), tested on
their own.

All functions take and return SI units, and refuse (a
:class:`~brakewear.errors.GeometryError` naming the argument) moduli, lengths and
forces that are not finite and positive, and an annulus whose inner radius is not
below its outer one.
"""
from __future__ import annotations

import numpy as np

from ..checks import check_number
from ..errors import GeometryError

__all__ = [
    "bonded_ring_axial_stiffness",
    "bonded_ring_torsion_stiffness",
    "bonded_strip_compression_modulus",
    "ring_tilt_stiffness",
    "rigid_ring_liftoff_moment",
    "bore_contact_tilt",
]


def _positive(**values) -> None:
    units = {"G": "Pa", "E": "Pa", "force": "N", "axial_stiffness": "N/m"}
    for key, v in values.items():
        check_number(key, v, 0.0, unit=units.get(key, "m"), kind=GeometryError)


def _annulus(r_i: float, r_o: float) -> None:
    if not r_i < r_o:
        raise GeometryError(f"r_i = {r_i!r} m, r_o = {r_o!r} m: the annulus needs "
                            "r_i < r_o")


def bonded_ring_axial_stiffness(G: float, r_i: float, r_o: float, height: float) -> float:
    """Axial (telescopic) shear stiffness (N/m) of a rubber annulus of shear modulus
    ``G``, radii ``r_i < r_o``, axial ``height``, bonded to a rigid core and a rigid
    sleeve: ``2 pi G h / ln(r_o / r_i)`` (the antiplane shear ``u_z(r)`` of a
    bush, exact where the ends carry the shear that the rest of the ring does).

    Examples
    --------
    A thin wall of thickness ``t = r_o - r_i`` shears as a slab of area
    ``2 pi r h``: ``G 2 pi r h / t``.

    >>> k = bonded_ring_axial_stiffness(1e6, 0.0300, 0.0301, 0.01)
    >>> round(float(k) / (1e6 * 2 * np.pi * 0.03005 * 0.01 / 0.0001), 4)
    1.0
    """
    _positive(G=G, r_i=r_i, r_o=r_o, height=height)
    _annulus(r_i, r_o)
    return 2.0 * np.pi * G * height / np.log(r_o / r_i)


def bonded_ring_torsion_stiffness(G: float, r_i: float, r_o: float, height: float) -> float:
    """Torsional stiffness (N m/rad) of the same bonded annulus about its axis:
    ``4 pi G h / (1/r_i^2 - 1/r_o^2)`` (the shear stress ``T / (2 pi r^2 h)``
    integrated across the wall).

    Examples
    --------
    A thin wall: the shear force ``G theta r / t`` over ``2 pi r h`` at arm ``r``.

    >>> k = bonded_ring_torsion_stiffness(1e6, 0.0300, 0.0301, 0.01)
    >>> round(k / (1e6 * 2 * np.pi * 0.03005 ** 3 * 0.01 / 0.0001), 4)
    1.0
    """
    _positive(G=G, r_i=r_i, r_o=r_o, height=height)
    _annulus(r_i, r_o)
    return 4.0 * np.pi * G * height / (r_i ** -2 - r_o ** -2)


def bonded_strip_compression_modulus(E: float, width: float, thickness: float) -> float:
    """Apparent compression modulus (Pa) of a long rubber strip of ``width`` bonded
    (or held by friction) between two plates ``thickness`` apart: ``(4/3) E (1 +
    S^2)`` with the shape factor ``S = width / (2 thickness)`` (Gent's long-strip
    estimate for nearly incompressible rubber; an estimate within a factor of
    about 1.5 for a square seal section, which is neither bonded nor long).

    Examples
    --------
    A square section (``S = 1/2``) is 5/3 as stiff as ``E``:

    >>> round(bonded_strip_compression_modulus(3e6, 4e-3, 4e-3) / 3e6, 6)
    1.666667
    """
    _positive(E=E, width=width, thickness=thickness)
    S = width / (2.0 * thickness)
    return 4.0 / 3.0 * E * (1.0 + S * S)


def ring_tilt_stiffness(axial_stiffness: float, radius: float) -> float:
    """Tilt stiffness (N m/rad) about a diameter of a ring of axial springs of total
    stiffness ``axial_stiffness`` spread evenly at ``radius``: ``k_a r^2 / 2``.

    Examples
    --------
    Four springs of ``k_a / 4`` at 90 degrees: the two on the tilt axis carry
    nothing, the other two ``2 (k_a / 4) r^2``.

    >>> ring_tilt_stiffness(4e6, 0.02) == 2 * (4e6 / 4) * 0.02 ** 2
    True
    """
    _positive(axial_stiffness=axial_stiffness, radius=radius)
    return 0.5 * axial_stiffness * radius ** 2


def rigid_ring_liftoff_moment(force: float, radius: float) -> float:
    """The moment (N m) at which a rigid plate pressed by ``force`` onto a ring of
    equal springs at ``radius`` begins to lift off the ring: the ring's force per
    unit length is ``F/(2 pi a) (1 + 2 M cos(phi) / (F a))``, zero at its edge when
    ``M = F a / 2``.  The plate rocks on the ring's edge (all the force at one
    point) as ``M`` approaches ``F a``.

    Examples
    --------
    >>> rigid_ring_liftoff_moment(1000.0, 0.02)    # N m: half of F a
    10.0
    """
    _positive(force=force, radius=radius)
    return 0.5 * force * radius


def bore_contact_tilt(clearance: float, engagement: float) -> float:
    """The tilt (rad) at which a rigid piston in a bore of radial ``clearance``
    touches the wall at both ends of its guided length ``engagement``, free to
    shift sideways within the clearance: ``2 c / L`` (small angles); held
    centred at one end (a pivot on the axis), it touches at ``c / L``.

    Examples
    --------
    A 0.1 mm clearance over a 20 mm guide: 10 mrad.

    >>> round(bore_contact_tilt(1e-4, 0.02), 12)
    0.01
    """
    _positive(clearance=clearance, engagement=engagement)
    return 2.0 * clearance / engagement
