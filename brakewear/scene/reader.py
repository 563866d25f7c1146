"""Scene files: read a TOML scene, check every table and key, convert to SI units.

:func:`load_scene` / :func:`scene_from_dict` check the whole scene -- unknown
keys (the allowed keys are listed), wrong types, unknown units, missing
tables or bodies, values out of range -- and raise
:class:`~brakewear.errors.SceneError` naming the file, the key, the value and
what is allowed, *before* anything is meshed.  The result is a frozen
:class:`~brakewear.scene.Scene` in SI units (m, Pa, s, rad/s, K).  The
packaged scenes live in the top-level ``geometry/scenes`` folder.
"""
from __future__ import annotations

import logging
import math
import sys
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from ..checks import fail, file_messages, user_units
from ..errors import GeometryError, SceneError
from ..geometry.files import geometry_dir, geometry_from_dict, load_geometry
from ..geometry.parts import MESH_BODY_KEYS
from ..interfaces.registry import interface_model, model_keys
from ..laws.base import wear_law_keys, wear_law_model
from ..parts import import_parts
from ..wear.numerics import Numerics
from .spec import Scene
from .tables import UNITS, InterfaceSpec, OutputSpec, ThermalSpec, WearSpec, scene_keys

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

logger = logging.getLogger(__name__)

__all__ = ["load_scene", "scene_from_dict", "scene_dir", "scene_file", "available_scenes"]


#: table -> key -> kind.  Kinds: a unit quantity ("length", "pressure", "time",
#: "angular_speed", "temperature"), or "str", "num", "int", "bool", "surfaces",
#: "geometry", "k", "h_conv", "partition", "signed_length" (a length of either
#: sign), "face_length" (a signed length, or a table of one per friction face).
_SCHEMA: dict[str, dict[str, str]] = {
    "units": {q: "unit" for q in UNITS},
    "scene": {"name": "str", "description": "str", "geometry": "geometry", "import": "raw"},
    "components": {"rotor": "str", "pad": "str", "piston": "str", "layout": "str"},
    "mesh": {"size": "length", "order": "int", "pad_file": "path", "rotor_file": "path",
             "piston_file": "path", "pad_size": "length", "rotor_size": "length",
             "friction_layers": "int", "backplate_layers": "int", "rotor_layers": "int"},
    "environment": {"line_pressure": "pressure", "omega": "angular_speed", "duration": "time",
                    "ambient": "temperature"},
    # the built-in keys of the tables a registered part is named in (the fields of
    # their dataclasses), and the part's own keys (:func:`_schema`)
    "interface": scene_keys(InterfaceSpec),
    "wear.pad": scene_keys(WearSpec),
    "wear.rotor": {"enabled": "bool", **scene_keys(WearSpec)},
    "thermal": {"enabled": "bool", "partition": "partition", "h_conv": "h_conv",
                "T_initial": "temperature", "T_ref": "temperature",
                "contact_conductance": "conductance", "mass": "str", "T_max": "temperature",
                "convection": "str", "emissivity": "num", "pad_rms_height": "length",
                "rotor_rms_height": "length", "pad_rms_slope": "num",
                "rotor_rms_slope": "num", "conductance_law": "str"},
    "numerics": {"scheme": "str", "update": "str", "steps": "int", "dp_tol": "num",
                 "dh_fraction": "num", "max_dh": "length", "wear_tol": "length",
                 "norm": "str", "stability": "num", "implicit_floor": "num", "tol": "num",
                 "max_halvings": "int", "max_steps": "int",
                 "memory_budget": "num"},
    "output": {"vtu_every": "int", "checkpoint_every": "int", "figures": "bool"},
    "vehicle": {"mass": "num", "front_share": "num", "tyre_radius": "length",
                "brakes_per_axle": "int", "regen_share": "num", "regen_torque_limit": "num",
                "axle": "str", "tyre_mu": "num", "regen_power_limit": "num",
                "regen_decel_limit": "num", "regen_cutoff_speed": "num",
                "regen_full_speed": "num", "inertia_factor": "num",
                "rolling_resistance": "num", "drag_area": "num", "air_density": "num",
                "drivetrain_drag": "num"},
    # checked by brakewear.duty.schedule_from_table (its own units: km/h, m/s^2, MPa, s)
    "schedule": {"stops": "raw", "speed_from": "raw", "speed_to": "raw", "deceleration": "raw",
                 "line_pressure": "raw", "interval": "raw", "dwell_speed": "raw",
                 "file": "raw", "applications": "raw"},
}


_REQUIRED_TABLES = ("units", "scene", "components", "environment", "wear")


_REQUIRED_KEYS = {
    "units": set(UNITS),
    "components": {"rotor", "pad"},
    "environment": {"line_pressure", "omega", "duration"},
    "vehicle": {"mass"},
}


_TOP = ("units", "scene", "geometry", "components", "mesh", "environment", "interface", "wear",
        "thermal", "numerics", "output", "vehicle", "schedule")

# what a [schedule] replaces: its applications set the loads and the durations
_SCHEDULED = {"line_pressure", "omega", "duration"}


def _schema(table: str) -> dict[str, str]:
    """The keys of ``table`` and their kinds; ``[interface]`` and ``[wear.*]`` hold
    those of every registered part too (the named part refuses the others' keys)."""
    if table == "interface":
        return {**_SCHEMA[table], **model_keys()}
    if table.startswith("wear."):
        return {**_SCHEMA[table], **wear_law_keys()}
    return _SCHEMA[table]


def _part(table: str, tab: Mapping[str, Any]):
    """The registered part ``tab`` names (``interface.model``, ``wear.pad.model``), checked
    before its keys: an unknown name is named as such, not through a key of its own;
    None for a built-in wear law."""
    if table == "interface":
        return interface_model(tab.get("model", InterfaceSpec.model))
    if "model" in tab:
        return wear_law_model(tab["model"], f"{table}.model")
    return None


def _imports(d: Any, base: Path | None) -> tuple[str, ...]:
    """Import the modules of ``[scene] import`` (a user's parts), before any table is read."""
    sc = d.get("scene") if isinstance(d, Mapping) else None
    names = sc.get("import") if isinstance(sc, Mapping) else None
    if names is None:
        return ()
    if isinstance(names, str):
        names = [names]
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        raise fail("scene.import", f"{names!r} is not allowed; need a list of module names or "
                                   ".py files, e.g. [\"my_parts\"]")
    import_parts(names, "scene.import", base)
    return tuple(names)


def scene_dir():
    """The folder of the packaged scene files.

    In a source checkout: ``geometry/scenes`` beside the ``brakewear`` folder
    (looked at first, so that a checkout never reads the scenes of another
    installed copy); installed: ``brakewear.geometries/scenes`` (setup.cfg
    ships them as package data).
    """
    here = Path(__file__).resolve().parents[2] / "geometry" / "scenes"
    if here.is_dir():
        return here
    return geometry_dir() / "scenes"


def scene_file(name: str = "default"):
    """The packaged scene file of a name (a Traversable; may not exist)."""
    return scene_dir() / f"{name}.toml"


def available_scenes() -> list[str]:
    """The names of the scene files shipped with brakewear.

    Returns
    -------
    list of str
        Names :func:`load_scene` takes (``"default"``, ...), sorted.
    """
    return sorted(p.name[:-5] for p in scene_dir().iterdir() if p.name.endswith(".toml"))


def load_scene(path_or_name: str | PathLike = "default") -> Scene:
    """Load and check a scene file (nothing is meshed).

    Parameters
    ----------
    path_or_name
        A packaged scene name (``"default"``) or the path of a TOML file; a
        string with a path separator or ending in ``.toml`` is a path.

    Returns
    -------
    Scene
        The checked scene, in SI units.

    Raises
    ------
    SceneError
        Naming the file, the key, the value and what is allowed.
    GeometryError
        From the scene's geometry (naming its file and field).
    """
    s = str(path_or_name)
    if isinstance(path_or_name, PathLike) or "/" in s or "\\" in s or s.endswith(".toml"):
        path = Path(path_or_name)
        source, base = str(path), path.parent
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise SceneError(f"{source}: cannot read scene file ({exc})") from None
    else:
        res = scene_file(s)
        source, base = f"brakewear scene {s!r}", None
        if not res.is_file():
            raise SceneError(f"unknown scene name {s!r}; packaged scenes: "
                             f"{', '.join(available_scenes())} (or give the path of a .toml file)")
        data = res.read_bytes()
    try:
        d = tomllib.loads(data.decode("utf-8-sig"))     # a BOM (Windows editors) is fine
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise SceneError(f"{source}: not a valid TOML file: {exc}") from None
    from ..tribology.scene import is_tribometer, tribometer_from_dict
    if is_tribometer(d):  # a tribometer test (docs/validation.md)
        return tribometer_from_dict(d, source=source, base=base or Path(str(scene_dir())))
    scene = scene_from_dict(d, source=source, base=base)
    logger.info("loaded scene %r from %s", scene.name, source)
    return scene


def scene_from_dict(d: Mapping[str, Any], source: str = "<dict>",
                    base: str | PathLike | None = None) -> Scene:
    """Check a scene given as nested dicts (the parsed TOML) and convert it to SI.

    Parameters
    ----------
    d
        The tables of docs/scenes.md.
    source
        Name used in messages (the file path when loading a file).
    base
        Folder that relative geometry paths are relative to (the scene
        file's folder); default the working directory.

    Returns
    -------
    Scene
        The checked scene, in SI units.
    """
    with file_messages(source, {}):         # every message about the file names it
        return _parse(d, source, None if base is None else Path(base))


def _tables(d: Any) -> dict[str, dict]:
    """The checked tables of a scene: no unknown table or key, none missing."""
    if not isinstance(d, Mapping):
        raise fail("<top level>", f"expected tables, got {type(d).__name__}")
    unknown = sorted(set(d) - set(_TOP))
    if unknown:
        raise fail(unknown[0], f"unknown table [{unknown[0]}]; allowed tables: "
                                f"{', '.join(_TOP)}")
    for t in _REQUIRED_TABLES:
        if t not in d:
            raise fail(t, f"missing required table [{t}]")
    tables: dict[str, dict] = {}
    for t in _TOP:
        if t in d and t not in ("wear", "geometry"):
            tables[t] = _table(d[t], t)
    wear = _table(d["wear"], "wear")
    bad = sorted(set(wear) - {"pad", "rotor"})
    if bad:
        raise fail(f"wear.{bad[0]}", f"unknown table [wear.{bad[0]}]; allowed: [wear.pad], "
                                      "[wear.rotor]")
    if "pad" not in wear:
        raise fail("wear.pad", "missing required table [wear.pad] (the pad always wears)")
    for b in ("pad", "rotor"):
        if b in wear:
            tables[f"wear.{b}"] = _table(wear[b], f"wear.{b}")
    for t, tab in tables.items():
        allowed = _schema(t)
        part = _part(t, tab) if t == "interface" or t.startswith("wear.") else None
        unknown = sorted(set(tab) - set(allowed))
        if unknown:
            own = [k.name for k in getattr(part, "keys", ())]
            raise fail(f"{t}.{unknown[0]}", f"unknown key {unknown[0]!r} in [{t}]; allowed "
                                             f"keys: {', '.join([*_SCHEMA[t], *own])}")
        required = _REQUIRED_KEYS.get(t, set())
        if t == "environment" and "schedule" in d:
            given = sorted(_SCHEDULED & set(tab))
            if given:
                raise fail(f"environment.{given[0]}", "is set by the [schedule]'s applications; "
                                                       "remove it (allowed with a schedule: "
                                                       "ambient)")
            required = required - _SCHEDULED
        for k in sorted(required - set(tab)):
            what = "body" if t == "components" else "key"
            raise fail(f"{t}.{k}", f"missing required {what} {k!r} in [{t}]" + (
                "; a brake scene needs a pad and a rotor" if t == "components" else ""))
    return tables


def _units(tables: dict) -> dict[str, str]:
    """The [units] table, checked."""
    units = {}
    for q, choices in UNITS.items():
        u = tables["units"][q]
        if not isinstance(u, str) or u not in choices:
            raise fail(f"units.{q}", f"{u!r} is not allowed; allowed units: "
                                      f"{', '.join(repr(c) for c in choices)}")
        units[q] = u
    return units


def _scene_geometry(d: Any, tables: dict, source: str, base: Path | None):
    """The brake geometry: an inline [geometry] table, a name or a path."""
    sc = tables["scene"]
    if "geometry" in d:
        if "geometry" in sc:
            raise fail("scene.geometry", "given twice: as scene.geometry and as a [geometry] "
                                          "table; keep one")
        geometry = geometry_from_dict(_table(d["geometry"], "geometry"),
                                      source=f"{source}: [geometry]")
    else:
        g = sc.get("geometry", "default")
        if not isinstance(g, str):
            raise fail("scene.geometry", f"{g!r} is a {type(g).__name__}; expected a geometry "
                                          "name or a .toml path (or a [geometry] table)")
        is_path = "/" in g or "\\" in g or g.endswith(".toml")
        if is_path and base is not None and not Path(g).is_absolute():
            g = str(base / g)
        try:
            geometry = load_geometry(g)
        except GeometryError as exc:
            raise GeometryError(f"{source}: scene.geometry = {sc['geometry']!r}: {exc}"
                                if "geometry" in sc else f"{source}: {exc}") from None
    return geometry


def _parse(d: Any, source: str, base: Path | None) -> Scene:
    _imports(d, base)
    tables = _tables(d)
    units = _units(tables)

    shown = _units_shown(units)      # key -> (unit, factor, offset, value as written)

    def val(t: str, k: str, default: Any = None) -> Any:
        tab = tables.get(t, {})
        if k not in tab:
            return default
        kind = _schema(t)[k]
        out = _convert(f"{t}.{k}", tab[k], kind, units)
        if kind == "face_length" and isinstance(tab[k], Mapping):
            u = units["length"]
            shown.update({f"{t}.{k}.{f}": (u, UNITS["length"][u], 0.0, x)
                          for f, x in tab[k].items()})
            return out
        if kind in ("signed_length", "face_length"):
            kind = "length"
        if kind in UNITS:
            u = units[kind]
            shown[f"{t}.{k}"] = ((u, 1.0, UNITS[kind][u], tab[k]) if kind == "temperature"
                                 else (u, UNITS[kind][u], 0.0, tab[k]))
        return out

    geometry = _scene_geometry(d, tables, source, base)

    comps = tables["components"]
    for k in comps:
        _convert(f"components.{k}", comps[k], "str", units)
    if comps["pad"] != "elastic":
        raise fail("components.pad", f"{comps['pad']!r} is not allowed; allowed: 'elastic' "
                                      "(the pad is always meshed)")

    iface = tables.get("interface", {})
    ikw = {k: val("interface", k) for k in iface}
    for key in ("gap_file", "mu_map"):
        if key in ikw and base is not None and not Path(ikw[key]).is_absolute():
            ikw[key] = str(base / ikw[key])                 # relative to the scene file
    if "surfaces" in ikw:
        ikw["surfaces"] = tuple(ikw["surfaces"])
    # the chosen model's own keys (each model checks its own)
    ikw = {k: v for k, v in ikw.items() if k in _SCHEMA["interface"]} | {
        "options": {k: v for k, v in ikw.items() if k not in _SCHEMA["interface"]}}

    def wear_spec(b: str) -> WearSpec | None:
        t = f"wear.{b}"
        if t not in tables:
            return None
        tab = dict(tables[t])
        if b == "rotor" and not val(t, "enabled", True):
            return None
        tab.pop("enabled", None)
        kw = {k: val(t, k) for k in tab}
        if "k_map" in kw and base is not None and not Path(kw["k_map"]).is_absolute():
            kw["k_map"] = str(base / kw["k_map"])           # relative to the scene file
        # a registered law's own keys (each law checks its own)
        kw = {k: v for k, v in kw.items() if k in _SCHEMA[t]} | {
            "options": {k: v for k, v in kw.items() if k not in _SCHEMA[t]}}
        return WearSpec(**kw)

    with user_units(shown):
        interface = InterfaceSpec(**ikw)
        thermal = ThermalSpec(**{k: val("thermal", k) for k in tables.get("thermal", {})})
        numerics = Numerics(**{k: val("numerics", k) for k in tables.get("numerics", {})})
        output = OutputSpec(**{k: val("output", k) for k in tables.get("output", {})})
        env = {k: val("environment", k) for k in tables["environment"]}
        name = val("scene", "name", Path(source).stem if source.endswith(".toml") else source)
        pad_wear, rotor_wear = wear_spec("pad"), wear_spec("rotor")
        mesh_size = val("mesh", "size")
        mesh_files = {}
        for k in ("pad_file", "rotor_file", "piston_file"):
            f = val("mesh", k)
            if f is not None:       # relative to the scene file's folder
                mesh_files[k[:-5]] = str(base / f) if base is not None and not \
                    Path(f).is_absolute() else f
        resolution = {k: val("mesh", k) for k in tables.get("mesh", {})
                      if k in MESH_BODY_KEYS}
        duty = _duty(tables, val, source, base)
        return Scene(geometry=geometry, rotor=comps["rotor"],
                     piston=comps.get("piston", "traction"),
                     layout=comps.get("layout", "auto"),
                     mesh_size=mesh_size, order=val("mesh", "order"), mesh_files=mesh_files,
                     resolution=resolution,
                     interface=interface, pad_wear=pad_wear, rotor_wear=rotor_wear,
                     thermal=thermal, numerics=numerics, output=output, name=name,
                     description=val("scene", "description", ""), source=source,
                     user_units=shown, **duty, **env)


def _duty(tables: dict, val, source: str, base: Path | None) -> dict:
    """``vehicle`` and ``schedule`` of the scene's [vehicle] and [schedule] tables."""
    from ..duty import Vehicle
    from ..duty.schedule import schedule_from_table
    out = {}
    if "vehicle" in tables:
        out["vehicle"] = Vehicle(**{k: val("vehicle", k) for k in tables["vehicle"]},
                                 source=source)
    if "schedule" in tables:
        out["schedule"] = tuple(schedule_from_table(tables["schedule"], source, base))
    return out


def _table(v: Any, name: str) -> dict:
    if not isinstance(v, Mapping):
        raise fail(name, f"expected a table [{name}], got {type(v).__name__} {v!r}")
    return dict(v)


def _units_shown(units: Mapping[str, str]) -> dict[str, tuple]:
    """The ``[units]`` table as entries ``units.<quantity>`` of the messages' unit map:
    what a message about a computed value speaks (:func:`brakewear.checks.shown_in`)."""
    return {f"units.{q}": ((u, 1.0, UNITS[q][u], None) if q == "temperature"
                           else (u, UNITS[q][u], 0.0, None))
            for q, u in units.items() if q in UNITS and u in UNITS[q]}


def _convert(key: str, v: Any, kind: str, units: Mapping[str, str]) -> Any:
    """Type-check one value and convert it to SI."""
    def number() -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise fail(key, f"{v!r} is a {type(v).__name__}; expected a number")
        if not math.isfinite(v):
            raise fail(key, f"{v!r} is not allowed; it must be a finite number")
        return float(v)

    if kind == "raw":
        return v
    if kind in ("str", "geometry", "path"):
        if not isinstance(v, str):
            raise fail(key, f"{v!r} is a {type(v).__name__}; expected a string")
        return v
    if kind == "bool":
        if not isinstance(v, bool):
            raise fail(key, f"{v!r} is a {type(v).__name__}; expected true or false")
        return v
    if kind == "int":
        if isinstance(v, bool) or not isinstance(v, int):
            raise fail(key, f"{v!r} is a {type(v).__name__}; expected a whole number")
        return v
    if kind == "num":
        return number()
    if kind == "k":
        if v == "material":
            return None
        if isinstance(v, str):
            raise fail(key, f"{v!r} is not allowed; expected a number (1/Pa) or \"material\"")
        return number()
    if kind in ("partition", "conductance"):      # a number or a word
        return v if isinstance(v, str) else number()
    if kind == "h_conv":
        if isinstance(v, Mapping):
            return {b: _convert(f"{key}.{b}", h, "num", units) for b, h in v.items()}
        return number()
    if kind == "surfaces":
        if not isinstance(v, list) or not all(isinstance(s, str) for s in v):
            raise fail(key, f"{v!r} is not allowed; expected a list of two strings "
                             "\"body.surface\"")
        return v
    if kind == "signed_length":        # a length of either sign (a gap's direction)
        return number() * UNITS["length"][units["length"]]
    if kind == "face_length":          # one signed length, or a table of one per face
        if isinstance(v, Mapping):
            return {f: _convert(f"{key}.{f}", x, "signed_length", units) for f, x in v.items()}
        return _convert(key, v, "signed_length", units)
    if kind in UNITS:
        x = number()
        u = units[kind]
        if kind == "temperature":
            return x + UNITS[kind][u]
        if x <= 0:
            raise fail(key, f"{x!r} {u} is not allowed; it must be > 0 {u}")
        return x * UNITS[kind][u]
    raise AssertionError(kind)  # pragma: no cover
