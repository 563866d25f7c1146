"""The brake a cleaning routine runs on, built from a draw of its inputs.

The floating caliper of a geometry file (default ``geometry/floating.toml``)
as the full model -- both pads held as the caliper holds them (the rigid
piston in its bore, the fingers, the abutments:
:class:`~brakewear.CaliperInterface`), the elastic hat rotor -- with a draw's
brake inputs set: the load path's keys (``load_path:<section.key>``, in the
geometry file's units), the fingers' radius and footprint
(``finger_radius``, ``finger_diameter``, mm) and the friction material's
modulus (``pad_modulus``, a factor).  The inputs that move the pads'
condensation (the fingers' places, the modulus) are taken on levels
(:func:`level`), so that a sweep condenses each brake once per process
(and reads it from the disk cache after); the load-path keys change the
caliper's rows only (:meth:`~brakewear.CaliperInterface.with_load_path`).
"""
from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np

from ..errors import GeometryError

logger = logging.getLogger(__name__)

__all__ = ["cleaning_geometry", "cleaning_brake", "held_brake", "transfer_gap",
           "reduced_rotor", "level", "brake_levels",
           "PAD_MODULUS_LEVELS", "FINGER_RADIUS_LEVELS", "FINGER_DIAMETER_LEVELS"]

#: the friction material's modulus is taken on these levels (times the file's)
PAD_MODULUS_LEVELS = (0.7, 1.0, 1.4)
#: the fingers' footprint centre radius (mm) and diameter (mm) are taken on these levels
FINGER_RADIUS_LEVELS = (120.0, 126.0, 132.0)
FINGER_DIAMETER_LEVELS = (16.0, 24.0)

#: this process's brakes and reduced rotors, by what builds them
_BUILT: dict = {}
_KEEP = 4


def level(value: float, levels) -> float:
    """The level nearest ``value`` (on a logarithmic scale for positive levels)."""
    lv = np.asarray(levels, dtype=float)
    return float(lv[np.argmin(np.abs(np.log(lv / value)))])


def cleaning_geometry(name: str = "floating", pad_modulus: float = 1.0,
                      load_path: dict | None = None, fingers: dict | None = None):
    """The brake of geometry file ``name`` with ``load_path`` keys (``"section.key"``
    -> value in the file's units) and the fingers' ``radius`` and ``diameter``
    (``fingers``: mm, every finger) set, checked as the file is, and its friction
    layer's moduli times ``pad_modulus``."""
    import tomllib

    from ..geometry import geometry_file, geometry_from_dict

    path = geometry_file(name)
    d = tomllib.loads(path.read_text())
    for key, value in (load_path or {}).items():
        sec, _, field = key.partition(".")
        if not field:
            raise GeometryError(f"{path}: load path key {key!r} is not 'section.key'")
        d.setdefault(sec, {})[field] = value
    if fingers:
        rows = d.get("caliper", {}).get("fingers")
        if not rows:
            raise GeometryError(f"{path}: no [[caliper.fingers]] to place (a fixed caliper)")
        scale = 1e3 if d.get("units", {}).get("length", "mm") == "m" else 1.0
        for row in rows:
            for k, v in fingers.items():
                row[k] = v / scale
    g = geometry_from_dict(d, source=f"{path}" + (f" with {load_path}" if load_path else "")
                           + (f" fingers {fingers}" if fingers else ""))
    if pad_modulus == 1.0:
        return g
    m = g.pad.friction_material
    e = m.elastic
    stiffer = replace(m, elastic=replace(e, E_p=e.E_p * pad_modulus, E_t=e.E_t * pad_modulus,
                                         G_t=e.G_t * pad_modulus))
    return replace(g, pad=replace(g.pad, friction_material=stiffer))


def _keep(key, build):
    if key not in _BUILT:
        if len(_BUILT) >= _KEEP:
            _BUILT.pop(next(iter(_BUILT)))
        _BUILT[key] = build()
    return _BUILT[key]


def _levels(draw: dict) -> tuple[float, dict]:
    modulus = level(draw.get("pad_modulus", 1.0), PAD_MODULUS_LEVELS)
    fingers = {k: level(draw[f"finger_{k}"], lv) for k, lv in
               (("radius", FINGER_RADIUS_LEVELS), ("diameter", FINGER_DIAMETER_LEVELS))
               if f"finger_{k}" in draw}
    return modulus, fingers


def brake_levels(draw: dict) -> tuple:
    """The levels a draw's brake is condensed at: the modulus, the fingers' radius and
    diameter (None: the geometry file's)."""
    modulus, fingers = _levels(draw)
    return modulus, fingers.get("radius"), fingers.get("diameter")


def cleaning_brake(draw: dict, geometry: str = "floating", size: float = 4e-3):
    """``(model, interface)`` of a draw (see the module): the caliper interface of the
    draw's brake, its condensation built once per process for each level of the
    fingers and the modulus, its rows those of the draw's load path.

    Parameters
    ----------
    draw
        The inputs (:func:`brakewear.cleaning.priors.cleaning_inputs`); those absent
        take the geometry file's values.
    geometry
        A geometry file or packaged name (a floating caliper).
    size
        Mesh size (m).
    """
    from ..caliper.interface import CaliperInterface
    from ..model import BrakeModel

    modulus, fingers = _levels(draw)
    lp = {k.split(":", 1)[1]: v for k, v in draw.items() if k.startswith("load_path:")}
    key = (str(geometry), float(size), modulus, tuple(sorted(fingers.items())))

    def build():
        g = cleaning_geometry(geometry, modulus, fingers=fingers)
        model = BrakeModel(g, size=size, rotor="elastic", piston="rigid")
        return CaliperInterface(model, 1e6, 0.4)

    base = _keep(key, build)
    itf = base.with_load_path(cleaning_geometry(geometry, modulus, lp or None, fingers))
    return itf.model, itf


def held_brake(draw: dict, geometry: str = "floating", size: float = 4e-3, order: int = 1):
    """``(model, interface)`` of the draw's brake with its pads held square: both
    backplate ends held in-plane, the clamp force a traction on the piston's and the
    fingers' footprints (their places and the modulus the draw's levels), the
    condensed FE contact (:class:`~brakewear.CondensedInterface`), on meshes of
    element ``order``; one per process and level.  Where the pads bed
    (:mod:`brakewear.cleaning.steady`)."""
    from ..caliper.geometry import SupportGeometry
    from ..interfaces.condensed import CondensedInterface
    from ..model import BrakeModel

    modulus, fingers = _levels(draw)

    def build():
        g = cleaning_geometry(geometry, modulus, fingers=fingers)
        g = replace(g, support=SupportGeometry(), mesh=replace(g.mesh, order=order))
        model = BrakeModel(g, size=size, layout="full", rotor="elastic")
        return model, CondensedInterface(model, 1e6, 0.4)

    return _keep(("held", str(geometry), float(size), int(order), modulus,
                  tuple(sorted(fingers.items()))), build)


def transfer_gap(gap: np.ndarray, source, target, tol: float = 1e-9) -> np.ndarray:
    """``gap`` at the pad friction nodes of interface ``source`` read at those of
    ``target`` (the same pads meshed alike: node by node, by position)."""
    from scipy.spatial import cKDTree

    d, i = cKDTree(np.asarray(source.x).T).query(np.asarray(target.x).T)
    if d.max() > tol:
        raise GeometryError(f"the pads' friction nodes differ between the two models (a node "
                            f"{d.max() * 1e3:.3g} mm from the nearest); mesh them alike")
    return np.asarray(gap, dtype=float)[i]


def reduced_rotor(geometry: str = "floating", size: float = 4e-3, blocks: int = 3,
                  convection_factor: float = 1.0):
    """The reduced heat of the brake's hat rotor (one per process and mesh), at
    ambient, its convection times ``convection_factor``
    (:class:`~brakewear.thermal.reduced.ReducedRotorHeat` with the elastic rotor's
    coning)."""
    from ..model import BrakeModel
    from ..thermal import SpeedConvection, ThermalModel
    from ..thermal.coning import RotorConing
    from ..thermal.reduced import ReducedRotorHeat

    def build():
        g = cleaning_geometry(geometry)
        m = BrakeModel(g, size=size, layout="full", rotor="elastic")
        th = ThermalModel(m, h_conv={"pad": 40.0, "rotor": SpeedConvection.solid()})
        band = (g.pad.inner_radius, g.pad.outer_radius)
        heat = ReducedRotorHeat(th, band=band, blocks=blocks)
        heat.add_coning(RotorConing(th, band))
        return heat

    heat = _keep(("heat", str(geometry), float(size), blocks), build)
    heat.restore((np.zeros_like(heat.a), 0.0))
    heat.convection_factor = convection_factor
    return heat
