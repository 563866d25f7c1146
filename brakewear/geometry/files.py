"""Parametric brake geometry: read, check and hold a geometry/*.toml file.

A geometry file describes one brake -- rotor ring, pad (friction layer on a
steel backplate), piston and, optionally, the caliper, the pads' support and
the rotor's mount (read by :mod:`brakewear.geometry.sections`) -- in the
units named in its ``[units]`` table.
:func:`load_geometry` and :func:`geometry_from_dict` check *everything*
(unknown keys, missing fields, types, ranges, the pad on the rotor ring, the
piston on the pad, materials, units) before any mesh is built, and return a
frozen :class:`BrakeGeometry` in SI units (m, rad, Pa) whose materials are
resolved :class:`brakewear.materials.Material` objects.

Every error is a :class:`GeometryError` that names the file, the field (for
example ``pad.inner_radius``), the value and the allowed range.  The file
format is documented in docs/geometry.md.
"""
from __future__ import annotations

import importlib.resources
import logging
import math
import re
import sys
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from ..errors import GeometryError, MaterialError
from ..materials import MATERIALS, Isotropic, Material, Thermal, TransverselyIsotropic
from .parts import (
    _BASE_DEFAULT,
    ANGLE_UNITS,
    LENGTH_UNITS,
    MAX_LAYERS,
    MESH_BODY_KEYS,
    MESH_DEFAULTS,
    MODULUS_UNITS,
    BrakeGeometry,
    MeshSettings,
    PadGeometry,
    PistonGeometry,
    RotorGeometry,
)
from .sections import (
    EXTRA_FIELDS,
    SECTIONS,
    check_footprint,
    pad_shape,
    piston_guide,
    rim_inner_diameter,
    rotor_mount,
    stiffness_unit,
)
from .sections import caliper as _caliper
from .sections import support as _support

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

logger = logging.getLogger(__name__)

__all__ = [
    "load_geometry",
    "geometry_from_dict",
    "available_geometries",
    "geometry_dir",
    "geometry_file",
]


_SCHEMA: dict[str, dict[str, str]] = {
    # field -> kind: "length", "angle", "material", "int", "ratio", "unit"
    "units": {"length": "unit", "angle": "unit", "modulus": "unit"},
    "rotor": {"inner_radius": "length", "outer_radius": "length", "thickness": "length",
              "material": "material"},
    "pad": {"inner_radius": "length", "outer_radius": "length", "arc_angle": "angle",
            "center_angle": "angle", "friction_thickness": "length",
            "backplate_thickness": "length", "friction_material": "material",
            "backplate_material": "material"},
    "piston": {"diameter": "length", "radius": "length", "angle": "angle",
               "length": "length", "material": "material", "bore_diameter": "length"},
    "mesh": {"size": "length", "order": "int", "rotor_coarse_factor": "ratio",
             "rotor_margin": "angle", "rotor_z_ratio": "ratio", "pad_z_ratio": "ratio",
             "pad_size": "length", "rotor_size": "length", "friction_layers": "int",
             "backplate_layers": "int", "rotor_layers": "int"},
}


_OPTIONAL = {
    "pad": {"center_angle"},
    "piston": {"angle", "bore_diameter"},
    "mesh": {"order", "rotor_coarse_factor", "rotor_margin", "rotor_z_ratio", "pad_z_ratio",
             *MESH_BODY_KEYS},
}


_UNIT_CHOICES = {"length": LENGTH_UNITS, "angle": ANGLE_UNITS, "modulus": MODULUS_UNITS}


_ISO_KEYS = {"type", "E", "nu", "rho", "c", "kappa", "alpha", "wear_k", "base", "notes"}


_TI_KEYS = {"type", "E_p", "E_t", "nu_p", "nu_tp", "G_t", "rho", "c", "kappa", "alpha",
            "wear_k", "base", "notes"}


class _Checker:
    """Collects the context (file, units) for error messages."""

    def __init__(self, source: str):
        self.source = source
        self.unit_name: dict[str, str] = {}

    def fail(self, fieldname: str, msg: str) -> GeometryError:
        return GeometryError(f"{self.source}: {fieldname}: {msg}")

    def table(self, d: Any, name: str) -> dict:
        if not isinstance(d, Mapping):
            raise self.fail(name, f"expected a table, got {type(d).__name__} {d!r}")
        return dict(d)

    def keys(self, d: Mapping, name: str, allowed: set[str], required: set[str]) -> None:
        unknown = sorted(set(d) - allowed)
        if unknown:
            raise self.fail(f"{name}.{unknown[0]}",
                            f"unknown field {unknown[0]!r} in [{name}]; allowed fields: "
                            f"{', '.join(sorted(allowed))}")
        missing = sorted(required - set(d))
        if missing:
            raise self.fail(f"{name}.{missing[0]}",
                            f"missing required field {missing[0]!r} in [{name}]")

    def number(self, d: Mapping, sec: str, key: str) -> float:
        v = d[key]
        name = f"{sec}.{key}"
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise self.fail(name, f"{v!r} is a {type(v).__name__}; expected a number")
        v = float(v)
        if not math.isfinite(v):
            raise self.fail(name, f"{v!r} is not allowed; it must be a finite number")
        return v

    def positive(self, d: Mapping, sec: str, key: str) -> float:
        v = self.number(d, sec, key)
        if v <= 0.0:
            raise self.fail(f"{sec}.{key}", f"{v!r} is not allowed; it must be > 0")
        return v

    def length(self, d: Mapping, sec: str, key: str) -> float:
        return self.positive(d, sec, key) * LENGTH_UNITS[self.unit_name["length"]]

    def angle(self, d: Mapping, sec: str, key: str) -> float:
        return self.number(d, sec, key) * ANGLE_UNITS[self.unit_name["angle"]]

    def fmt_len(self, v_si: float) -> str:
        u = self.unit_name["length"]
        return f"{v_si / LENGTH_UNITS[u]:.6g} {u}"

    def fmt_ang(self, v_si: float) -> str:
        u = self.unit_name["angle"]
        return f"{v_si / ANGLE_UNITS[u]:.6g} {u}"


def geometry_dir():
    """The folder of the packaged geometry files.

    Installed, the top-level ``geometry/`` folder is the package
    ``brakewear.geometries`` (setup.cfg maps it).  Imported from a source
    checkout (e.g. ``python -m pytest`` at the repository root puts the
    source tree first on ``sys.path``) that package does not exist, and the
    files are read from ``geometry/`` beside the ``brakewear`` folder.
    """
    try:
        return importlib.resources.files("brakewear.geometries")
    except ModuleNotFoundError:
        return Path(__file__).resolve().parents[2] / "geometry"


def geometry_file(name: str = "default"):
    """The packaged geometry file of a name (a Traversable; may not exist)."""
    return geometry_dir() / f"{name}.toml"


def available_geometries() -> list[str]:
    """The names of the geometry files shipped with brakewear.

    Returns
    -------
    list of str
        Names :func:`load_geometry` takes (``"default"``, ...), sorted.
    """
    return sorted(p.name[:-5] for p in geometry_dir().iterdir() if p.name.endswith(".toml"))


def load_geometry(path_or_name: str | PathLike = "default") -> BrakeGeometry:
    """Load and check a brake geometry file.

    Parameters
    ----------
    path_or_name
        A packaged geometry name (``"default"`` loads
        ``brakewear/geometries/default.toml``) or the path of a TOML file.
        A string containing a path separator or ending in ``.toml`` is a path.

    Returns
    -------
    BrakeGeometry
        The checked geometry in SI units.

    Raises
    ------
    GeometryError
        Unreadable file, TOML syntax error or any invalid field.
    """
    s = str(path_or_name)
    is_path = isinstance(path_or_name, PathLike) or "/" in s or "\\" in s or s.endswith(".toml")
    if is_path:
        path = Path(path_or_name)
        source = str(path)
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise GeometryError(f"{source}: cannot read geometry file ({exc})") from None
    else:
        res = geometry_file(s)
        source = f"brakewear.geometries/{s}.toml"
        if not res.is_file():
            raise GeometryError(
                f"unknown geometry name {s!r}; packaged geometries: "
                f"{', '.join(available_geometries())} (or give the path of a .toml file)")
        data = res.read_bytes()
    try:
        d = tomllib.loads(data.decode("utf-8-sig"))     # a BOM (Windows editors) is fine
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise GeometryError(f"{source}: not a valid TOML file: {exc}") from None
    geom = geometry_from_dict(d, source=source)
    logger.info("loaded brake geometry from %s", source)
    return geom


def geometry_from_dict(d: Mapping[str, Any], source: str = "<dict>") -> BrakeGeometry:
    """Check a geometry given as nested dicts (the parsed TOML) and convert it to SI.

    Parameters
    ----------
    d
        Tables ``units``, ``rotor``, ``pad``, ``piston``, ``mesh`` and optional
        ``materials``, ``caliper`` and ``support`` (the load-path keys are read
        by :mod:`brakewear.geometry.sections`); see docs/geometry.md.
    source
        Name used in error messages (the file path when loading a file).

    Returns
    -------
    BrakeGeometry

    Raises
    ------
    GeometryError
        Naming ``source``, the field, the value and the allowed range.
    """
    ck = _Checker(source)
    d = ck.table(d, "<top level>")
    allowed = set(_SCHEMA) | {"materials", *SECTIONS}
    unknown = sorted(set(d) - allowed)
    if unknown:
        raise ck.fail(unknown[0], f"unknown section [{unknown[0]}]; allowed sections: "
                                  f"{', '.join(sorted(allowed))}")
    for sec in _SCHEMA:
        if sec not in d:
            raise ck.fail(sec, f"missing required section [{sec}]")
    secs = {sec: ck.table(d[sec], sec) for sec in _SCHEMA}
    for sec, fields in _SCHEMA.items():
        ck.keys(secs[sec], sec, set(fields) | EXTRA_FIELDS.get(sec, set()),
                set(fields) - _OPTIONAL.get(sec, set()))

    # units first: every other number depends on them
    for key, choices in _UNIT_CHOICES.items():
        u = secs["units"][key]
        if not isinstance(u, str) or u not in choices:
            raise ck.fail(f"units.{key}", f"{u!r} is not allowed; allowed units: "
                                          f"{', '.join(repr(c) for c in choices)}")
        ck.unit_name[key] = u
    stiffness_unit(ck, secs["units"])

    materials = _materials(ck, d.get("materials", {}))

    def material(sec: str, key: str) -> Material:
        name = secs[sec][key]
        if not isinstance(name, str):
            raise ck.fail(f"{sec}.{key}", f"{name!r} is a {type(name).__name__}; expected a "
                                          "material name (string)")
        if name not in materials:
            raise ck.fail(f"{sec}.{key}", f"unknown material {name!r}; known materials: "
                                          f"{', '.join(sorted(materials))}")
        return materials[name]

    rotor = rotor_mount(ck, secs["rotor"], _rotor(ck, secs["rotor"], material))
    pad = pad_shape(ck, secs["pad"], _pad(ck, secs["pad"], rotor, material), rotor)
    piston = _piston(ck, secs["piston"], pad, material)
    caliper, extra = _caliper(ck, d, pad, piston)
    support = _support(ck, d)
    mesh = _mesh(ck, secs["mesh"], pad)
    return BrakeGeometry(rotor=rotor, pad=pad, piston=piston, mesh=mesh, caliper=caliper,
                         support=support, extra_pistons=extra, materials=materials,
                         source=source, units=dict(ck.unit_name))


def _rotor(ck: _Checker, s: dict, material) -> RotorGeometry:
    ri = ck.length(s, "rotor", "inner_radius")
    ro = ck.length(s, "rotor", "outer_radius")
    if ri >= ro:
        raise ck.fail("rotor.inner_radius",
                      f"{ck.fmt_len(ri)} is not allowed; it must be < rotor.outer_radius "
                      f"= {ck.fmt_len(ro)}")
    t = ck.length(s, "rotor", "thickness")
    return RotorGeometry(ri, ro, t, material("rotor", "material"))


def _pad(ck: _Checker, s: dict, rotor: RotorGeometry, material) -> PadGeometry:
    ri = ck.length(s, "pad", "inner_radius")
    ro = ck.length(s, "pad", "outer_radius")
    if ri >= ro:
        raise ck.fail("pad.inner_radius", f"{ck.fmt_len(ri)} is not allowed; it must be < "
                                          f"pad.outer_radius = {ck.fmt_len(ro)}")
    ring = f"[{ck.fmt_len(rotor.inner_radius)}, {ck.fmt_len(rotor.outer_radius)}]"
    eps = 1e-12 * rotor.outer_radius
    for key, v in (("inner_radius", ri), ("outer_radius", ro)):
        if not (rotor.inner_radius - eps <= v <= rotor.outer_radius + eps):
            raise ck.fail(f"pad.{key}",
                          f"{ck.fmt_len(v)} lies outside the rotor friction ring; allowed "
                          f"range [rotor.inner_radius, rotor.outer_radius] = {ring}")
    arc = ck.angle(s, "pad", "arc_angle")
    if not (0.0 < arc < math.pi):
        raise ck.fail("pad.arc_angle", f"{ck.fmt_ang(arc)} is not allowed; allowed range "
                                       f"(0, {ck.fmt_ang(math.pi)}) exclusive")
    center = ck.angle(s, "pad", "center_angle") if "center_angle" in s else 0.0
    tf = ck.length(s, "pad", "friction_thickness")
    tb = ck.length(s, "pad", "backplate_thickness")
    return PadGeometry(ri, ro, arc, center, tf, tb, material("pad", "friction_material"),
                       material("pad", "backplate_material"))


def _piston(ck: _Checker, s: dict, pad: PadGeometry, material) -> PistonGeometry:
    dia = ck.length(s, "piston", "diameter")
    rc = ck.length(s, "piston", "radius")
    ang = ck.angle(s, "piston", "angle") if "angle" in s else 0.0
    length = ck.length(s, "piston", "length")
    bore = ck.length(s, "piston", "bore_diameter") if "bore_diameter" in s else dia
    rim = rim_inner_diameter(ck, s, "piston", dia)
    check_footprint(ck, "piston", dia, rc, ang, pad)
    return PistonGeometry(dia, rc, ang, length, material("piston", "material"), bore, rim,
                          piston_guide(ck, s))


def _mesh(ck: _Checker, s: dict, pad: PadGeometry) -> MeshSettings:
    size = ck.length(s, "mesh", "size")
    width = pad.outer_radius - pad.inner_radius
    if size > 0.5 * width:
        raise ck.fail("mesh.size", f"{ck.fmt_len(size)} is too coarse; allowed range (0, "
                                   f"{ck.fmt_len(0.5 * width)}] (half the radial pad width)")
    order = s.get("order", MESH_DEFAULTS["order"])
    if isinstance(order, bool) or order not in (1, 2):
        raise ck.fail("mesh.order", f"{order!r} is not allowed; allowed: 1, 2")
    kw: dict[str, float] = {}
    for key in ("rotor_coarse_factor", "rotor_z_ratio", "pad_z_ratio"):
        if key in s:
            v = ck.number(s, "mesh", key)
            if v < 1.0:
                raise ck.fail(f"mesh.{key}", f"{v!r} is not allowed; it must be >= 1")
            kw[key] = v
    if "rotor_margin" in s:
        m = ck.angle(s, "mesh", "rotor_margin")
        hi = 0.5 * (2 * math.pi - pad.arc_angle) - 1e-6
        if not (0.0 <= m < hi):
            raise ck.fail("mesh.rotor_margin", f"{ck.fmt_ang(m)} is not allowed; allowed "
                                               f"range [0, {ck.fmt_ang(hi)})")
        kw["rotor_margin"] = m
    for key in ("pad_size", "rotor_size"):
        if key in s:
            v = ck.length(s, "mesh", key)
            if v > 0.5 * width:
                raise ck.fail(f"mesh.{key}", f"{ck.fmt_len(v)} is too coarse; allowed range (0, "
                                             f"{ck.fmt_len(0.5 * width)}] (half the radial pad "
                                             "width)")
            kw[key] = v
    for key in ("friction_layers", "backplate_layers", "rotor_layers"):
        if key in s:
            v = s[key]
            if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= MAX_LAYERS:
                raise ck.fail(f"mesh.{key}", f"{v!r} is not allowed; allowed: a whole number "
                                             f"of element layers in [1, {MAX_LAYERS}]")
            kw[key] = int(v)
    return MeshSettings(size=size, order=int(order), **kw)


_FIELD_IN_MSG = re.compile(r"^[^:]*:\s*(\w+)\s*=")


def _materials(ck: _Checker, tables: Any) -> dict[str, Material]:
    """Built-in materials plus the file's ``[materials.NAME]`` tables."""
    out = dict(MATERIALS)
    tables = ck.table(tables, "materials")
    E_unit = MODULUS_UNITS[ck.unit_name["modulus"]]
    for name, t in tables.items():
        sec = f"materials.{name}"
        t = ck.table(t, sec)
        if name in MATERIALS:
            raise ck.fail(sec, f"{name!r} is a built-in material and cannot be redefined; "
                               "choose another name")
        kind = t.get("type")
        if kind not in ("isotropic", "transversely_isotropic"):
            raise ck.fail(f"{sec}.type", f"{kind!r} is not allowed; allowed: 'isotropic', "
                                         "'transversely_isotropic'")
        if kind == "isotropic":
            ck.keys(t, sec, _ISO_KEYS, {"type", "E", "nu"})
            mods, ratios = ("E",), ("nu",)
        else:
            ck.keys(t, sec, _TI_KEYS, {"type", "E_p", "E_t", "nu_p", "nu_tp", "G_t"})
            mods, ratios = ("E_p", "E_t", "G_t"), ("nu_p", "nu_tp")
        # positivity of moduli and the Poisson ranges are checked by the
        # materials classes; here only the type (number, finite) is checked
        args = {k: ck.number(t, sec, k) * E_unit for k in mods}
        args.update({k: ck.number(t, sec, k) for k in ratios})
        base_name = t.get("base", _BASE_DEFAULT[kind])
        if base_name not in MATERIALS:
            raise ck.fail(f"{sec}.base", f"unknown material {base_name!r}; allowed: "
                                         f"{', '.join(sorted(MATERIALS))}")
        base = MATERIALS[base_name]
        th = {}
        for k in ("rho", "c", "kappa", "alpha"):
            th[k] = ck.positive(t, sec, k) if k in t else getattr(base.thermal, k)
        if "wear_k" in t:
            wear_k = ck.number(t, sec, "wear_k")
            if wear_k < 0:
                raise ck.fail(f"{sec}.wear_k", f"{wear_k!r} is not allowed; it must be >= 0")
        else:
            wear_k = base.wear_k
        try:
            elastic = (Isotropic(name=name, **args) if kind == "isotropic"
                       else TransverselyIsotropic(name=name, **args))
        except MaterialError as exc:
            m = _FIELD_IN_MSG.match(str(exc))
            where = f"{sec}.{m.group(1)}" if m else sec
            raise GeometryError(f"{ck.source}: {where}: {exc}") from None
        notes = t.get("notes", f"custom ({kind}, thermal data from {base_name} unless given)")
        out[name] = Material(name, elastic, Thermal(**th), wear_k=wear_k, notes=str(notes))
    return out
