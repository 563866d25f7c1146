"""Read and check the load-path keys of a geometry file: caliper, support, rotor mount, pad shape.

:func:`brakewear.geometry.geometry_from_dict` calls these after the basic
parts are read.  Each function takes one table of the parsed TOML (in the
file's units) and returns the dataclass of :mod:`brakewear.geometry.parts`
or :mod:`brakewear.caliper.geometry` in SI units, or raises
:class:`~brakewear.errors.GeometryError` naming the file, the field, the
value in the file's units and the allowed range.  Every key is optional;
absent, the idealised brake is kept exactly (a fixed caliper, bilateral
support, the ring clamped at its inner radius, a solid ring, a backplate of
the lining's outline without chamfers or slot, solid piston footprints).

The geometric rules are those a drawing of the brake must satisfy: every
footprint (piston rim or disc, finger) lies on the backplate, radially within
its radii and along the arc inside the pad ends; the hat wall meets the
friction ring and clears the outboard pad; chamfers and the slot leave a flat
friction face between them; the lining keeps a thickness under every cut.
"""
from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Mapping
from typing import Any

from ..caliper.geometry import (
    CALIPER_TYPES,
    ROTOR_MOUNTS,
    SUPPORT_TYPES,
    CaliperGeometry,
    FingerGeometry,
    HatGeometry,
    PistonGuide,
    SupportGeometry,
    VentGeometry,
)
from .parts import LENGTH_UNITS, PadGeometry, PistonGeometry, RotorGeometry

logger = logging.getLogger(__name__)

__all__ = ["STIFFNESS_UNITS", "EXTRA_FIELDS", "SECTIONS", "LOAD_PATH_KEYS"]


#: allowed ``units.stiffness`` (N/m per unit); default "N/mm"
STIFFNESS_UNITS = {"N/m": 1.0, "N/mm": 1e3, "kN/mm": 1e6}


#: the optional load-path fields of the basic sections
EXTRA_FIELDS = {
    "units": {"stiffness"},
    "rotor": {"mount", "hat", "vents"},
    "pad": {"backplate_inner_radius", "backplate_outer_radius", "leading_chamfer",
            "trailing_chamfer", "slot_width", "slot_depth"},
    "piston": {"rim_inner_diameter", "bore_clearance", "engagement_length", "stand_out",
               "seal_position", "seal_width", "seal_height", "seal_modulus", "rim_friction",
               "bore_friction"},
}


#: the load path's parameters: ``"section.key"`` -> (attribute, unit, SI per unit,
#: allowed ``(lo, hi)`` (lo exclusive where the third item is True), plausible
#: ``(lo, hi)``, what it is).  Unit ``"length"`` and ``"stiffness"`` are the
#: file's ``[units]``; the others are fixed.  A value outside the allowed range
#: is refused, one outside the plausible range is logged as a warning
#: (docs/load_path.md gives each range's source).
LOAD_PATH_KEYS = {
    "piston.bore_clearance": ("clearance", "length", None, (0.0, 1e-3, True), (0.02e-3, 0.15e-3),
                              "radial clearance between piston and bore"),
    "piston.engagement_length": ("engagement", "length", None, (0.0, 0.2, True), (10e-3, 30e-3),
                                 "length of the piston guided in the bore"),
    "piston.stand_out": ("stand_out", "length", None, (0.0, 0.1, False), (0.0, 20e-3),
                         "distance from the piston's face to the bore's mouth"),
    "piston.seal_position": ("seal_position", "length", None, (0.0, 0.2, True), (2e-3, 12e-3),
                             "distance from the bore's mouth to the seal's centre"),
    "piston.seal_width": ("seal_width", "length", None, (0.0, 20e-3, True), (2e-3, 4.5e-3),
                          "radial width of the seal's section"),
    "piston.seal_height": ("seal_height", "length", None, (0.0, 20e-3, True), (2e-3, 4.5e-3),
                           "axial height of the seal's section"),
    "piston.seal_modulus": ("seal_modulus", "MPa", 1e6, (0.0, 1e9, True), (3e6, 12e6),
                            "Young's modulus of the seal's rubber"),
    "piston.rim_friction": ("rim_friction", "", 1.0, (0.0, 1.0, False), (0.08, 0.4),
                            "friction coefficient of the piston's rim on the backplate"),
    "piston.bore_friction": ("bore_friction", "", 1.0, (0.0, 1.0, False), (0.05, 0.3),
                             "friction coefficient of the piston in its bore"),
    "support.abutment_friction": ("abutment_friction", "", 1.0, (0.0, 1.0, False), (0.08, 0.5),
                                  "friction coefficient of the backplate's ends on the "
                                  "abutments"),
    "support.spring_stiffness": ("spring_stiffness", "stiffness", None, (0.0, math.inf, True),
                                 (1e4, 1e6), "stiffness of the pad's clip (anti-rattle spring)"),
    "support.rail_stiffness": ("rail_stiffness", "stiffness", None, (0.0, math.inf, True),
                               (1e7, math.inf), "radial stiffness of the bracket's rails"),
    "caliper.bridge_tilt": ("bridge_tilt", "mrad/kN", 1e-6, (0.0, math.inf, False), (0.0, 0.3e-6),
                            "the fingers' jaw's tilt per clamp force"),
    "caliper.bore_tilt": ("bore_tilt", "mrad/kN", 1e-6, (0.0, math.inf, False), (0.0, 0.3e-6),
                          "the bore's tilt per clamp force"),
    "caliper.finger_stiffness": ("finger_stiffness", "MPa/mm", 1e9, (0.0, math.inf, True),
                                 (1e11, 1e13), "stiffness per area of the finger layer"),
}


#: the optional load-path sections
SECTIONS = ("caliper", "support")


_HAT_KEYS = {"height", "wall_radius", "wall_thickness", "flange_thickness", "bore_radius",
             "bolt_circle_radius"}
_VENT_KEYS = {"cheek_thickness", "vane_count", "vane_width"}
_FINGER_KEYS = {"diameter", "radius", "angle"}
_PISTON_KEYS = {"diameter", "rim_inner_diameter", "bore_diameter", "radius", "angle"}
#: ``[caliper]`` keys of a floating caliper's bridge
_BRIDGE_KEYS = ("bridge_tilt", "finger_stiffness", "bore_tilt")
_SUPPORT_KEYS = {"type", "clearance", "rail_stiffness", "spring_stiffness", "abutment_friction"}


def _choice(ck, value: Any, name: str, allowed) -> str:
    if not isinstance(value, str) or value not in allowed:
        raise ck.fail(name, f"{value!r} is not allowed; allowed: "
                            f"{', '.join(repr(c) for c in allowed)}")
    return value


def _nonneg_length(ck, s: Mapping, sec: str, key: str) -> float:
    v = ck.number(s, sec, key)
    if v < 0.0:
        raise ck.fail(f"{sec}.{key}", f"{v!r} {ck.unit_name['length']} is not allowed; "
                                      "it must be >= 0")
    return v * LENGTH_UNITS[ck.unit_name["length"]]


def stiffness_unit(ck, units: Mapping) -> float:
    """Set ``ck.unit_name["stiffness"]`` from ``[units] stiffness`` (default N/mm);
    returns N/m per file unit."""
    u = _choice(ck, units.get("stiffness", "N/mm"), "units.stiffness", STIFFNESS_UNITS)
    ck.unit_name["stiffness"] = u
    return STIFFNESS_UNITS[u]


# --- rotor ----------------------------------------------------------------------------------

def rotor_mount(ck, s: Mapping, rotor: RotorGeometry) -> RotorGeometry:
    """``[rotor] mount``, ``[rotor.hat]`` and ``[rotor.vents]`` added to ``rotor``."""
    mount = _choice(ck, s.get("mount", "ring_clamp"), "rotor.mount", ROTOR_MOUNTS)
    hat = None
    if mount == "hat":
        if "hat" not in s:
            raise ck.fail("rotor.hat", "rotor.mount = 'hat' needs a [rotor.hat] table with "
                                       f"{', '.join(sorted(_HAT_KEYS))}")
        hat = _hat(ck, ck.table(s["hat"], "rotor.hat"), rotor)
    elif "hat" in s:
        raise ck.fail("rotor.hat", f"a [rotor.hat] table with rotor.mount = {mount!r}; set "
                                   "rotor.mount = 'hat' to clamp the rotor by its hat")
    vents = _vents(ck, ck.table(s["vents"], "rotor.vents"), rotor) if "vents" in s else None
    return dataclasses.replace(rotor, mount=mount, hat=hat, vents=vents)


def _hat(ck, t: dict, rotor: RotorGeometry) -> HatGeometry:
    sec = "rotor.hat"
    ck.keys(t, sec, _HAT_KEYS, _HAT_KEYS)
    v = {k: ck.length(t, sec, k) for k in sorted(_HAT_KEYS)}
    L = ck.fmt_len
    ri, wr, half = rotor.inner_radius, v["wall_radius"], 0.5 * v["wall_thickness"]
    if not (wr - half < ri <= (wr + half) * (1 + 1e-12)):
        raise ck.fail(f"{sec}.wall_radius",
                      f"{L(wr)} with wall_thickness {L(2 * half)} puts the hat wall at "
                      f"[{L(wr - half)}, {L(wr + half)}], which does not meet the friction "
                      f"ring at rotor.inner_radius = {L(ri)}; allowed wall_radius: "
                      f"[{L(ri - half)}, {L(ri + half)}) (wall_radius - wall_thickness/2 < "
                      "rotor.inner_radius <= wall_radius + wall_thickness/2)")
    if v["bore_radius"] >= wr - half:
        raise ck.fail(f"{sec}.bore_radius", f"{L(v['bore_radius'])} is not allowed; allowed "
                                            f"range (0, {L(wr - half)}) (inside the hat wall)")
    if not (v["bore_radius"] < v["bolt_circle_radius"] < wr - half):
        raise ck.fail(f"{sec}.bolt_circle_radius",
                      f"{L(v['bolt_circle_radius'])} is not allowed; allowed range "
                      f"({L(v['bore_radius'])}, {L(wr - half)}) (between bore_radius and the "
                      "wall's inner surface)")
    if v["height"] <= v["flange_thickness"]:
        raise ck.fail(f"{sec}.height", f"{L(v['height'])} is not allowed; it must be > "
                                       f"flange_thickness = {L(v['flange_thickness'])}")
    return HatGeometry(**v)


def _vents(ck, t: dict, rotor: RotorGeometry) -> VentGeometry:
    sec = "rotor.vents"
    ck.keys(t, sec, _VENT_KEYS, _VENT_KEYS)
    L = ck.fmt_len
    cheek = ck.length(t, sec, "cheek_thickness")
    if 2 * cheek >= rotor.thickness:
        raise ck.fail(f"{sec}.cheek_thickness",
                      f"{L(cheek)} is not allowed; allowed range (0, {L(0.5 * rotor.thickness)}) "
                      "(two cheeks must leave a channel: 2 cheek_thickness < rotor.thickness)")
    n = t["vane_count"]
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ck.fail(f"{sec}.vane_count", f"{n!r} is not allowed; allowed: a whole number >= 1")
    width = ck.length(t, sec, "vane_width")
    room = 2 * math.pi * rotor.inner_radius
    if n * width >= room:
        raise ck.fail(
            f"{sec}.vane_width",
            f"{L(width)} is not allowed with vane_count = {n}; allowed range (0, "
            f"{L(room / n)}) (the vanes must fit around the ring's inner "
            f"circumference {L(room)}: vane_count * vane_width < 2 pi rotor.inner_radius)",
        )
    return VentGeometry(cheek, int(n), width)


# --- pad ------------------------------------------------------------------------------------

def pad_shape(ck, s: Mapping, pad: PadGeometry, rotor: RotorGeometry) -> PadGeometry:
    """Backplate radii, chamfers and slot of ``[pad]`` added to ``pad``."""
    L = ck.fmt_len
    bri = ck.length(s, "pad", "backplate_inner_radius") if "backplate_inner_radius" in s else None
    bro = ck.length(s, "pad", "backplate_outer_radius") if "backplate_outer_radius" in s else None
    if bri is not None and bri > pad.inner_radius:
        raise ck.fail("pad.backplate_inner_radius",
                      f"{L(bri)} is not allowed; allowed range (0, {L(pad.inner_radius)}] "
                      "(the backplate carries the whole lining: <= pad.inner_radius)")
    if bro is not None and bro < pad.outer_radius:
        raise ck.fail("pad.backplate_outer_radius",
                      f"{L(bro)} is not allowed; it must be >= pad.outer_radius = "
                      f"{L(pad.outer_radius)} (the backplate carries the whole lining)")
    if rotor.hat is not None:
        wall = rotor.hat.wall_radius + 0.5 * rotor.hat.wall_thickness
        low = pad.inner_radius if bri is None else bri
        if low < wall * (1 - 1e-12):
            key = "pad.inner_radius" if bri is None else "pad.backplate_inner_radius"
            raise ck.fail(key, f"{L(low)} is not allowed with the hat mount; it must be >= "
                               f"{L(wall)} (the outboard pad must clear the hat wall, "
                               "whose outer surface is at rotor.hat.wall_radius + "
                               "wall_thickness/2)")
    r_mean = 0.5 * (pad.inner_radius + pad.outer_radius)
    lead = _chamfer(ck, s, "leading_chamfer", pad)
    trail = _chamfer(ck, s, "trailing_chamfer", pad)
    if lead[0] + trail[0] >= pad.arc_angle * r_mean:
        raise ck.fail("pad.trailing_chamfer" if trail[0] else "pad.leading_chamfer",
                      f"chamfer lengths {L(lead[0])} + {L(trail[0])} are not allowed; their "
                      f"sum must be < the arc length at the mean radius, "
                      f"{L(pad.arc_angle * r_mean)}")
    width, depth = _slot(ck, s, pad, lead, trail)
    return dataclasses.replace(pad, backplate_inner_radius=bri, backplate_outer_radius=bro,
                               leading_chamfer=lead, trailing_chamfer=trail, slot_width=width,
                               slot_depth=depth)


def _chamfer(ck, s: Mapping, key: str, pad: PadGeometry) -> tuple[float, float]:
    name = f"pad.{key}"
    if key not in s:
        return (0.0, 0.0)
    v = s[key]
    if not isinstance(v, (list, tuple)) or len(v) != 2:
        raise ck.fail(name, f"{v!r} is not allowed; expected [length, depth] in "
                            f"{ck.unit_name['length']}")
    length, depth = (_nonneg_length(ck, {key: x}, "pad", key) for x in v)
    L = ck.fmt_len
    if (length == 0.0) != (depth == 0.0):
        raise ck.fail(name, f"[{L(length)}, {L(depth)}] is not allowed; both > 0 for a "
                            "chamfer, or [0, 0] for none")
    if depth >= pad.friction_thickness:
        raise ck.fail(name, f"depth {L(depth)} is not allowed; allowed range [0, "
                            f"{L(pad.friction_thickness)}) (< pad.friction_thickness: the "
                            "lining keeps a thickness at the pad end)")
    return (length, depth)


def _slot(ck, s: Mapping, pad: PadGeometry, lead, trail) -> tuple[float, float | None]:
    L = ck.fmt_len
    width = _nonneg_length(ck, s, "pad", "slot_width") if "slot_width" in s else 0.0
    if width > 0.0:
        # the slot's walls are parallel to the centre line; at the inner radius
        # they must stay clear of the pad ends and of the chamfer starts
        r_mean = 0.5 * (pad.inner_radius + pad.outer_radius)
        room = min(0.5 * pad.arc_angle - c[0] / r_mean for c in (lead, trail))
        w_max = 2.0 * pad.inner_radius * math.sin(room)
        if width >= w_max:
            raise ck.fail("pad.slot_width",
                          f"{L(width)} is not allowed; allowed range [0, {L(w_max)}) (the "
                          "slot must lie between the chamfer starts at pad.inner_radius)")
    if "slot_depth" not in s:
        return width, None
    if width == 0.0:
        raise ck.fail("pad.slot_depth", "is given without a slot; set pad.slot_width > 0")
    depth = ck.length(s, "pad", "slot_depth")
    if depth > pad.friction_thickness:
        raise ck.fail("pad.slot_depth", f"{L(depth)} is not allowed; allowed range (0, "
                                        f"{L(pad.friction_thickness)}] (at most "
                                        "pad.friction_thickness)")
    return width, depth


# --- footprints on the backplate ------------------------------------------------------------

def check_footprint(ck, name: str, dia: float, rc: float, ang: float, pad: PadGeometry) -> None:
    """Refuse a circular footprint (``name.diameter`` at ``name.radius``,
    ``name.angle``) that does not lie on the backplate."""
    L, A = ck.fmt_len, ck.fmt_ang
    a = 0.5 * dia
    bri, bro = pad.backplate_radii
    tol = 1e-9 * bro
    where = ("pad.backplate_inner_radius, pad.backplate_outer_radius"
             if pad.backplate_inner_radius or pad.backplate_outer_radius else
             "the pad radii: the backplate has the lining's outline")
    if rc - a < bri - tol or rc + a > bro + tol:
        lo, hi = bri + a, bro - a
        allowed = (f"[{L(lo)}, {L(hi)}]" if lo <= hi else
                   f"none: the diameter {L(dia)} exceeds the radial backplate width {L(bro - bri)}")
        raise ck.fail(f"{name}.radius",
                      f"{L(rc)} with {name}.diameter = {L(dia)} puts the footprint "
                      f"[{L(rc - a)}, {L(rc + a)}] outside the backplate radii [{L(bri)}, "
                      f"{L(bro)}] ({where}); allowed {name}.radius: {allowed}")
    # along the arc: the distance from the centre to each pad end (a line
    # through the rotor axis) must be at least the footprint radius
    half = 0.5 * pad.arc_angle
    room = half - abs(ang)
    dist = rc * math.sin(room) if room > 0 else -1.0
    if room <= 0 or dist < a - tol:
        ang_max = max(half - math.asin(min(1.0, a / rc)), 0.0)
        raise ck.fail(f"{name}.angle",
                      f"{A(ang)} puts the footprint (diameter {L(dia)}) across a pad end: "
                      f"distance to the pad end {L(max(dist, 0.0))} < footprint radius {L(a)}; "
                      f"allowed |{name}.angle| <= {A(ang_max)} at {name}.radius = {L(rc)}")


def rim_inner_diameter(ck, s: Mapping, sec: str, dia: float) -> float | None:
    """``rim_inner_diameter`` of a piston table: in (0, diameter), or None."""
    if "rim_inner_diameter" not in s:
        return None
    v = ck.length(s, sec, "rim_inner_diameter")
    if v >= dia:
        raise ck.fail(f"{sec}.rim_inner_diameter",
                      f"{ck.fmt_len(v)} is not allowed; allowed range (0, {ck.fmt_len(dia)}) "
                      f"(< {sec}.diameter, the rim's outer diameter)")
    return v


def _no_overlap(ck, names: list[str], parts: list) -> None:
    """Refuse two footprints (``(diameter, radius, angle)``, named ``names``) that overlap."""
    for j, (dj, rj, aj) in enumerate(parts):
        for i, (di, ri, ai) in enumerate(parts[:j]):
            gap = math.sqrt(max(ri * ri + rj * rj - 2 * ri * rj * math.cos(ai - aj), 0.0))
            if gap < 0.5 * (di + dj) * (1 - 1e-9):
                raise ck.fail(names[j],
                              f"footprint (diameter {ck.fmt_len(dj)}) overlaps {names[i]}: "
                              f"centres {ck.fmt_len(gap)} apart, allowed >= "
                              f"{ck.fmt_len(0.5 * (di + dj))} (half the sum of the diameters)")


# --- caliper and support --------------------------------------------------------------------

def caliper(ck, d: Mapping, pad: PadGeometry, piston: PistonGeometry
            ) -> tuple[CaliperGeometry, tuple[PistonGeometry, ...]]:
    """``[caliper] type``, ``[[caliper.fingers]]`` and ``[[caliper.pistons]]``."""
    if "caliper" not in d:
        return CaliperGeometry(), ()
    s = ck.table(d["caliper"], "caliper")
    ck.keys(s, "caliper", {"type", "fingers", "pistons", *_BRIDGE_KEYS}, {"type"})
    kind = _choice(ck, s["type"], "caliper.type", CALIPER_TYPES)
    bridge = _bridge(ck, s, kind)
    rows = _rows(ck, s, "fingers")
    if kind == "fixed" and rows:
        raise ck.fail("caliper.fingers", f"{len(rows)} finger(s) on a fixed caliper; a fixed "
                                         "caliper has pistons on both sides (remove "
                                         "[[caliper.fingers]] or set caliper.type = 'floating')")
    if kind == "floating" and not rows:
        raise ck.fail("caliper.fingers", "a floating caliper needs at least one "
                                         "[[caliper.fingers]] table (diameter, radius, angle)")
    fingers = []
    for i, t in enumerate(rows):
        name = f"caliper.fingers[{i}]"
        ck.keys(t, name, _FINGER_KEYS, _FINGER_KEYS)
        f = FingerGeometry(ck.length(t, name, "diameter"), ck.length(t, name, "radius"),
                           ck.angle(t, name, "angle"))
        check_footprint(ck, name, f.diameter, f.radius, f.angle, pad)
        fingers.append(f)
    _no_overlap(ck, [f"caliper.fingers[{i}]" for i in range(len(fingers))],
                [(f.diameter, f.radius, f.angle) for f in fingers])
    extra = []
    for i, t in enumerate(_rows(ck, s, "pistons")):
        name = f"caliper.pistons[{i}]"
        ck.keys(t, name, _PISTON_KEYS, {"diameter", "radius"})
        dia = ck.length(t, name, "diameter")
        rc = ck.length(t, name, "radius")
        ang = ck.angle(t, name, "angle") if "angle" in t else 0.0
        bore = ck.length(t, name, "bore_diameter") if "bore_diameter" in t else dia
        check_footprint(ck, name, dia, rc, ang, pad)
        extra.append(PistonGeometry(dia, rc, ang, piston.length, piston.material, bore,
                                    rim_inner_diameter(ck, t, name, dia)))
    _no_overlap(ck, ["piston", *(f"caliper.pistons[{i}]" for i in range(len(extra)))],
                [(p.diameter, p.radius, p.angle) for p in (piston, *extra)])
    return CaliperGeometry(kind, tuple(fingers), **bridge), tuple(extra)


def load_path_value(ck, s: Mapping, sec: str, key: str) -> float:
    """A key of :data:`LOAD_PATH_KEYS` in SI: refused outside its allowed range
    (in the file's units), a warning outside its plausible range."""
    name = f"{sec}.{key}"
    _, unit, si, (lo, hi, lo_open), (p_lo, p_hi), what = LOAD_PATH_KEYS[name]
    v = ck.number(s, sec, key)
    shown = unit
    if unit in ("length", "stiffness"):
        shown = ck.unit_name[unit]
        si = LENGTH_UNITS[shown] if unit == "length" else STIFFNESS_UNITS[shown]
    x = v * si
    u = f" {shown}" if shown else ""
    if x < lo or (lo_open and x == lo) or x > hi:
        bound = f"{'>' if lo_open else '>='} {lo / si:.6g}{u}" + (
            f" and <= {hi / si:.6g}{u}" if math.isfinite(hi) else "")
        raise ck.fail(name, f"{v!r}{u} is not allowed ({what}); it must be {bound}")
    if not p_lo <= x <= p_hi:
        side = f"below {p_lo / si:.6g}{u}" if x < p_lo else f"above {p_hi / si:.6g}{u}"
        logger.warning("%s: %s = %r%s is unusual (%s; %s: docs/load_path.md gives the "
                       "range and its source); check the value and its unit", ck.source, name,
                       v, u, side, what)
    return x


def piston_guide(ck, s: Mapping) -> PistonGuide:
    """The ``[piston]`` keys of the piston's guide (bore, seal, friction) in SI,
    each checked alone and against the others."""
    kw = {}
    for name, (attr, *_rest) in LOAD_PATH_KEYS.items():
        sec, key = name.split(".")
        if sec == "piston" and key in s:
            kw[attr] = load_path_value(ck, s, sec, key)
    g = PistonGuide(**kw)
    L = ck.fmt_len
    if g.seal_height >= g.engagement:
        raise ck.fail("piston.seal_height", f"{L(g.seal_height)} is not allowed; it must be < "
                                            f"piston.engagement_length = {L(g.engagement)}")
    lo, hi = 0.5 * g.seal_height, g.engagement - 0.5 * g.seal_height
    if not lo <= g.seal_position <= hi:
        raise ck.fail("piston.seal_position", f"{L(g.seal_position)} is not allowed; allowed "
                                              f"range [{L(lo)}, {L(hi)}] (the seal lies in the "
                                              "guided length)")
    if g.clearance >= g.seal_width:
        raise ck.fail("piston.bore_clearance", f"{L(g.clearance)} is not allowed; it must be < "
                                               f"piston.seal_width = {L(g.seal_width)} (the "
                                               "seal closes the clearance)")
    return g


def _bridge(ck, s: Mapping, kind: str) -> dict[str, float]:
    """The bridge keys of ``[caliper]`` (:data:`_BRIDGE_KEYS`) in SI."""
    out = {}
    for key in _BRIDGE_KEYS:
        if key not in s:
            continue
        if kind != "floating":
            raise ck.fail(f"caliper.{key}", f"is given with caliper.type = {kind!r}; the bridge "
                                            "and its fingers belong to a floating caliper")
        out[key] = load_path_value(ck, s, "caliper", key)
    return out


def _rows(ck, s: Mapping, key: str) -> list[dict]:
    v = s.get(key, [])
    if not isinstance(v, list):
        raise ck.fail(f"caliper.{key}", f"expected an array of tables ([[caliper.{key}]]), got "
                                        f"{type(v).__name__} {v!r}")
    return [ck.table(t, f"caliper.{key}[{i}]") for i, t in enumerate(v)]


def support(ck, d: Mapping) -> SupportGeometry:
    """``[support] type clearance rail_stiffness spring_stiffness abutment_friction``."""
    if "support" not in d:
        return SupportGeometry()
    s = ck.table(d["support"], "support")
    ck.keys(s, "support", _SUPPORT_KEYS, {"type"})
    kind = _choice(ck, s["type"], "support.type", SUPPORT_TYPES)
    clearance = _nonneg_length(ck, s, "support", "clearance") if "clearance" in s else 0.0
    if kind == "bilateral" and clearance > 0.0:
        raise ck.fail("support.clearance", f"{ck.fmt_len(clearance)} is not allowed with "
                                           "support.type = 'bilateral' (both ends held); "
                                           "allowed: 0, or type 'push' / 'pull'")
    kw = {key: load_path_value(ck, s, "support", key)
          for key in ("rail_stiffness", "spring_stiffness", "abutment_friction") if key in s}
    return SupportGeometry(kind, clearance, **kw)
