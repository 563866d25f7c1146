"""A scene's bounds checked against each other and against the start state, before
anything is meshed.

Each table checks its own values (:mod:`brakewear.scene.tables`); the checks here
compare values across tables and with the geometry, where a value that is fine by
itself makes the run absurd or stop at its first step:

* ``thermal.T_max`` above ``environment.ambient`` and above the starting temperature
  ``thermal.T_initial`` (a face starts hotter than its plausibility bound);
* ``wear.pad.limit`` within the friction layer (beyond it the backplate would wear)
  and ``wear.rotor.limit`` within a friction face's depth (half the solid ring, a
  vented ring's cheek);
* ``interface.gap_file``: the map covers the whole pad face;
* a friction or wear map that refuses look-ups outside its grid
  (``map_outside = "error"``) covers the sliding speeds of the pad face at
  ``environment.omega`` and the starting temperature.

An interface model checks the scene's demands on itself (the condensed
interface's dense compliance against the memory budget) through its entry's
``check_scene`` (:mod:`brakewear.interfaces.registry`).

Every message names the keys and shows the values in the scene file's units.  A
``[thermal]`` value given while ``thermal.enabled = false`` is not used; it is logged
as a warning.
The schedule's own bounds (a stop's end speed below its start, dwell speeds, an
interval longer than the stop) are checked where it is read
(:func:`brakewear.duty.schedule_from_table`, :func:`brakewear.duty.check_schedule`).
"""
from __future__ import annotations

import logging
from dataclasses import fields

import numpy as np

from ..checks import check_order, fail, shown_value

logger = logging.getLogger(__name__)

__all__ = ["check_bounds", "check_thermal_bounds", "check_wear_limits", "check_gap_map",
           "check_map_ranges"]


def check_bounds(scene) -> None:
    """Every cross-check of this module on ``scene`` (a :class:`~brakewear.scene.Scene`)."""
    check_thermal_bounds(scene)
    check_wear_limits(scene)
    check_gap_map(scene)
    check_map_ranges(scene)


def check_thermal_bounds(scene) -> None:
    """``thermal.T_max`` above the ambient and the starting temperature (thermal runs)."""
    from ..thermal.model import T_MAX_DEFAULT
    th = scene.thermal
    if not th.enabled:
        unused = [f.name for f in fields(th) if f.name != "enabled"
                  and getattr(th, f.name) != f.default]
        if unused:
            logger.warning("thermal.%s is given but thermal.enabled = false: no temperature "
                           "field is computed and it is not used", unused[0])
        return
    t_max = T_MAX_DEFAULT if th.T_max is None else th.T_max
    why = ("the plausibility bound of the face temperatures: the run would stop at its "
           "first step")
    if th.T_max is None:        # the default bound: blame the start
        why = "the default thermal.T_max; " + why
    check_order("environment.ambient", scene.ambient, "thermal.T_max", t_max, "K",
                blame="thermal.T_max" if th.T_max is not None else "environment.ambient",
                why=why)
    if th.T_initial is not None:
        check_order("thermal.T_initial", th.T_initial, "thermal.T_max", t_max, "K",
                    blame="thermal.T_max" if th.T_max is not None else "thermal.T_initial",
                    why=why)


def check_wear_limits(scene) -> None:
    """``wear.pad.limit`` within the friction layer, ``wear.rotor.limit`` within the
    depth of a friction face (half a solid ring, a vented ring's cheek)."""
    g = scene.geometry
    src = f"of the geometry {g.source}"
    if scene.pad_wear.limit is not None:
        check_order("wear.pad.limit", scene.pad_wear.limit,
                    f"pad.friction_thickness {src}", g.pad.friction_thickness, "m",
                    blame="wear.pad.limit", strict=False,
                    why="the friction layer's thickness: beyond it the backplate would wear")
    if scene.rotor_wear is not None and scene.rotor_wear.limit is not None:
        ro = g.rotor
        depth, what = ((ro.vents.cheek_thickness, f"rotor.vents.cheek_thickness {src}")
                       if ro.vents is not None else
                       (0.5 * ro.thickness, f"half of rotor.thickness {src}"))
        check_order("wear.rotor.limit", scene.rotor_wear.limit, what, depth, "m",
                    blame="wear.rotor.limit", strict=False,
                    why="the depth of one friction face: beyond it the face would wear "
                        "through")


def _pad_corners(pad) -> tuple[np.ndarray, np.ndarray]:
    """Radii and angles (rad) of the corners and edge midpoints of the pad's friction
    face (an annular sector: a map that covers them covers the face)."""
    r = np.array([pad.inner_radius, 0.5 * (pad.inner_radius + pad.outer_radius),
                  pad.outer_radius])
    th = np.array([pad.leading_angle, pad.center_angle, pad.trailing_angle])
    rr, tt = np.meshgrid(r, th)
    return rr.ravel(), tt.ravel()


def check_gap_map(scene) -> None:
    """The initial-gap map (``interface.gap_file``) covers the whole pad face (a scene
    with its own pad mesh file is checked on its nodes when the run starts)."""
    points = scene.gap_points
    if points is None or "pad" in scene.mesh_files:
        return
    from scipy.interpolate import LinearNDInterpolator
    r, th = _pad_corners(scene.geometry.pad)
    r_m = float(points[:, 0].mean())
    f = LinearNDInterpolator(np.c_[points[:, 0], r_m * points[:, 1]], points[:, 2])
    # a hair inside the face: the map's edge may lie exactly on the pad's
    shrink = 1.0 - 1e-9
    rc = r.mean() + shrink * (r - r.mean())
    tc = th.mean() + shrink * (th - th.mean())
    out = ~np.isfinite(f(np.c_[rc, r_m * tc]))
    if out.any():
        i = int(np.flatnonzero(out)[0])
        deg = np.degrees
        raise fail("interface.gap_file",
                   f"{scene.interface.gap_file!r}: the map covers r "
                   f"{points[:, 0].min() * 1e3:.4g} to {points[:, 0].max() * 1e3:.4g} mm, "
                   f"theta {deg(points[:, 1].min()):.4g} to {deg(points[:, 1].max()):.4g} deg; "
                   f"the pad face spans r {r.min() * 1e3:.4g} to {r.max() * 1e3:.4g} mm, theta "
                   f"{deg(th.min()):.4g} to {deg(th.max()):.4g} deg (its point r = "
                   f"{r[i] * 1e3:.4g} mm, theta = {deg(th[i]):.4g} deg lies outside); the map "
                   "must cover the whole pad face")


def check_map_ranges(scene) -> None:
    """A map with ``map_outside = "error"`` covers the start: the sliding speeds of the
    pad face at ``environment.omega`` (a drag) and the starting temperature."""
    itf, th = scene.interface, scene.thermal
    maps = [("interface", "mu_map", itf.map_outside, itf.mu_map)]
    for sec, spec in (("wear.pad", scene.pad_wear), ("wear.rotor", scene.rotor_wear)):
        if spec is not None:
            maps.append((sec, "k_map", spec.map_outside, spec.k_map))
    laws = dict(zip(("interface", "wear.pad", "wear.rotor"),
                    (scene.friction(), *scene.wear_laws())))
    pad = scene.geometry.pad
    T0 = th.T_initial if th.T_initial is not None else scene.ambient
    for sec, key, outside, path in maps:
        table = getattr(laws[sec], "table", None)
        if path is None or outside != "error" or table is None:
            continue
        starts = {"T": ([T0], "thermal.T_initial" if th.T_initial is not None
                        else "environment.ambient", "K")} if th.enabled else {}
        if not scene.schedule:
            v = [scene.omega * pad.inner_radius, scene.omega * pad.outer_radius]
            starts["v"] = (v, "environment.omega", "rad/s")
        for axis, (values, start_key, unit) in starts.items():
            what = table.beyond(axis, values)
            if what is None:
                continue
            given = shown_value(start_key, scene.omega if axis == "v" else T0, unit)
            where = (f"the sliding speeds of the pad face (r {pad.inner_radius * 1e3:.4g} to "
                     f"{pad.outer_radius * 1e3:.4g} mm) at {start_key} = {given}"
                     if axis == "v" else f"the starting temperature {start_key} = {given}")
            raise fail(f"{sec}.{key}", f"{path!r}: {where}: {what}; extend the map, or set "
                                       f"{sec}.map_outside = 'clamp' to take its edge values")
