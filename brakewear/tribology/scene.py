"""Tribometer scene files: read a TOML test, check every table and key, convert to SI.

A tribometer scene is a scene file whose ``[scene]`` table names a test kind
(``test = "reciprocating"``); :func:`brakewear.load_scene` reads it through
:func:`tribometer_from_dict` (docs/validation.md lists the tables and keys).  As for
a brake scene, the whole file is checked before anything is meshed: unknown
tables or keys (the allowed ones are listed), wrong types, units and ranges
raise a :class:`~brakewear.errors.SceneError` that names the file, the key and
the value in the file's units.
"""
from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ..checks import check_bool, check_int, check_number, fail, file_messages, shown_value
from ..errors import InputError
from ..materials import Isotropic, get_material
from ..registry import check_options
from .kinds import BodySpec, TribometerKind, tribometer_kind

logger = logging.getLogger(__name__)

__all__ = ["TribometerScene", "tribometer_from_dict", "is_tribometer", "TEST_UNITS"]

#: the units a tribometer scene may state: quantity -> unit -> factor to SI
TEST_UNITS: dict[str, dict[str, float]] = {
    "length": {"mm": 1e-3, "um": 1e-6, "m": 1.0},
    "force": {"N": 1.0, "kN": 1e3},
    "modulus": {"GPa": 1e9, "MPa": 1e6, "Pa": 1.0},
    "angular_speed": {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0},
    "frequency": {"Hz": 1.0},
}
_REQUIRED_UNITS = ("length", "force", "modulus")

_TOP = ("units", "scene", "test", "bodies", "interface", "mesh", "numerics", "validation",
        "output")
_SCHEMA = {
    "scene": ("name", "description", "test"),
    "interface": ("mu",),
    "mesh": ("size", "zone", "growth"),
    "numerics": ("wear_tol", "first_jump", "min_jump", "max_jump", "fixed_jump"),
    "validation": ("source", "note", "quantity", "measured", "tolerance", "reference",
                   "profile", "profile_of"),
    "output": ("frames", "figures"),
    "body": ("material", "E", "nu", "k", "half_width", "depth"),
}


def is_tribometer(d: Any) -> bool:
    """Whether parsed scene tables describe a tribometer test (``scene.test`` given)."""
    return isinstance(d, Mapping) and isinstance(d.get("scene"), Mapping) and \
        "test" in d["scene"]


@dataclass(frozen=True)
class TribometerScene:
    """A tribometer test, checked, in SI units.

    Attributes
    ----------
    name, description : str
    test : TribometerKind
        The kind and its keys (``scene.test``, ``[test]``).
    bodies : dict
        Body name -> :class:`~brakewear.tribology.kinds.BodySpec` (slave first).
    mu : float
    mesh : dict
        ``size`` (the contact's element size, m), ``zone`` (the half-width of the
        finely meshed contact zone, m), ``growth`` (the mesh's grading).
    numerics : dict
        The cycle jump's ``wear_tol``, ``first_jump``, ``min_jump``, ``max_jump``,
        ``fixed_jump``.
    validation : dict
        What was measured, by whom (empty: none).
    output : dict
        ``frames`` (VTU files over the run), ``figures``.
    """

    name: str
    test: TribometerKind
    bodies: dict
    mu: float
    mesh: dict
    numerics: dict
    validation: dict = field(default_factory=dict)
    output: dict = field(default_factory=lambda: {"frames": 10, "figures": True})
    description: str = ""
    source: str = "<python>"
    user_units: dict = field(default_factory=dict, compare=False, repr=False)

    #: what a runner asks to tell a tribometer test from a brake scene
    tribometer = True

    def with_options(self, **changes) -> TribometerScene:
        """A copy with ``test``, ``mesh`` or ``numerics`` keys changed (SI), e.g.
        ``scene.with_options(cycles=100, size=5e-6, wear_tol=0.05)``."""
        test, mesh, num = dict(self.test.options), dict(self.mesh), dict(self.numerics)
        for k, v in changes.items():
            for table in (test, mesh, num):
                if k in table:
                    table[k] = v
                    break
            else:
                raise fail(k, "not a key of [test], [mesh] or [numerics]")
        return replace(self, test=type(self.test)(test), mesh=mesh, numerics=num)

    def to_dict(self) -> dict:
        """The scene as a JSON record (SI units)."""
        return {"name": self.name, "description": self.description, "test": self.test.name,
                "test_keys": self.test.record(),
                "bodies": {b: s.record() for b, s in self.bodies.items()},
                "mu": self.mu, "mesh_m": self.mesh, "numerics": self.numerics,
                "validation": self.validation, "output": self.output}


def _table(d: Mapping, key: str, allowed) -> dict:
    if not isinstance(d, Mapping):
        raise fail(key, f"expected a table [{key}], got {type(d).__name__}")
    unknown = sorted(set(d) - set(allowed))
    if unknown:
        raise fail(f"{key}.{unknown[0]}", f"unknown key {unknown[0]!r} in [{key}]; allowed "
                                           f"keys: {', '.join(allowed)}")
    return dict(d)


class _Reader:
    """Values of one file in SI, remembering how the file wrote them (for messages)."""

    def __init__(self, units: dict, shown: dict):
        self.units, self.shown = units, shown

    def quantity(self, key: str, value: Any, kind: str) -> Any:
        if kind in ("str", "path"):
            if not isinstance(value, str):
                raise fail(key, f"{value!r} is a {type(value).__name__}; expected a string")
            return value
        if kind == "bool":
            check_bool(key, value)
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise fail(key, f"{value!r} is a {type(value).__name__}; expected a number")
        if kind == "int":
            check_int(key, value, 0)
            return int(value)
        if kind == "num":
            return float(value)
        if kind == "line_force":
            u = self._unit(key, "force") + "/" + self._unit(key, "length")
            factor = TEST_UNITS["force"][self.units["force"]] / \
                TEST_UNITS["length"][self.units["length"]]
        else:
            u = self._unit(key, kind)
            factor = TEST_UNITS[kind][u]
        self.shown[key] = (u, factor, 0.0, value)
        return float(value) * factor

    def _unit(self, key: str, quantity: str) -> str:
        if quantity not in self.units:
            raise fail(key, f"needs units.{quantity} in [units] (allowed: "
                            f"{', '.join(repr(u) for u in TEST_UNITS[quantity])})")
        return self.units[quantity]


def _units(d: Mapping) -> dict:
    t = _table(d, "units", TEST_UNITS)
    for q in _REQUIRED_UNITS:
        if q not in t:
            raise fail(f"units.{q}", f"missing required unit {q!r} in [units]")
    for q, u in t.items():
        if u not in TEST_UNITS[q]:
            raise fail(f"units.{q}", f"{u!r} is not allowed; allowed units: "
                                      f"{', '.join(repr(c) for c in TEST_UNITS[q])}")
    return t


def _body(rd: _Reader, name: str, d: Mapping) -> BodySpec:
    key = f"bodies.{name}"
    t = _table(d, key, _SCHEMA["body"])
    for k in ("k", "half_width", "depth"):
        if k not in t:
            raise fail(f"{key}.{k}", f"missing required key {k!r} in [{key}]")
    mat = ""
    if "material" in t:
        if "E" in t or "nu" in t:
            raise fail(f"{key}.material", "give a material or E and nu, not both")
        mat = rd.quantity(f"{key}.material", t["material"], "str")
        try:
            el = get_material(mat).elastic
        except InputError as exc:
            raise fail(f"{key}.material", str(exc)) from None
        if not isinstance(el, Isotropic):
            raise fail(f"{key}.material", f"{mat!r} is not isotropic; a tribometer body "
                                           "needs an isotropic material (or E and nu)")
        E, nu = el.E, el.nu
    else:
        for k in ("E", "nu"):
            if k not in t:
                raise fail(f"{key}.{k}", f"missing required key {k!r} in [{key}] (or give "
                                          "a material)")
        E = rd.quantity(f"{key}.E", t["E"], "modulus")
        nu = rd.quantity(f"{key}.nu", t["nu"], "num")
        check_number(f"{key}.E", E, 0.0, unit="Pa")
        check_number(f"{key}.nu", nu, -1.0, 0.5)
        if nu >= 0.5:
            raise fail(f"{key}.nu", f"{nu!r} is not allowed; it must be below 0.5")
    k = rd.quantity(f"{key}.k", t["k"], "num")
    check_number(f"{key}.k", k, 0.0, 1e-9, lo_open=False, unit="1/Pa")
    hw = rd.quantity(f"{key}.half_width", t["half_width"], "length")
    depth = rd.quantity(f"{key}.depth", t["depth"], "length")
    check_number(f"{key}.half_width", hw, 0.0, unit="m")
    check_number(f"{key}.depth", depth, 0.0, unit="m")
    return BodySpec(name=name, E=E, nu=nu, k=k, half_width=hw, depth=depth, material=mat)


def tribometer_from_dict(d: Mapping, source: str = "<dict>", base: Path | None = None
                   ) -> TribometerScene:
    """Check a tribometer scene given as nested dicts (the parsed TOML) and convert
    it to SI (:class:`TribometerScene`); errors name ``source`` and the key."""
    shown: dict[str, tuple] = {}
    with file_messages(source, shown):
        sc = _parse(d, shown, base)
    return replace(sc, source=source, user_units=dict(shown))


def _parse(d: Mapping, shown: dict, base: Path | None) -> TribometerScene:
    unknown = sorted(set(d) - set(_TOP))
    if unknown:
        raise fail(unknown[0], f"unknown table [{unknown[0]}]; allowed tables of a tribometer "
                                f"scene: {', '.join(_TOP)}")
    for t in ("units", "scene", "test", "bodies", "interface", "mesh"):
        if t not in d:
            raise fail(t, f"missing required table [{t}]")
    rd = _Reader(_units(d["units"]), shown)
    scene = _table(d["scene"], "scene", _SCHEMA["scene"])
    kind_cls = tribometer_kind(rd.quantity("scene.test", scene["test"], "str"))
    name = rd.quantity("scene.name", scene.get("name", kind_cls.name), "str")
    # the kind's own keys, read in the file's units, then checked by the kind
    keys = {k.name: k for k in kind_cls.keys}
    raw = _table(d["test"], "test", keys)
    given = {k: rd.quantity(f"test.{k}", v, keys[k].kind) for k, v in raw.items()}
    for k in kind_cls.keys:
        if k.default is None and not k.allow_none and k.name not in given:
            raise fail(f"test.{k.name}", f"missing required key {k.name!r} in [test] (a "
                                          f"{kind_cls.name} test)")
    test = kind_cls(check_options(kind_cls.keys, given, "test", f"scene.test = "
                                  f"{kind_cls.name!r}"))
    bodies_t = d["bodies"]
    if not isinstance(bodies_t, Mapping):
        raise fail("bodies", "expected tables [bodies.NAME]")
    want = kind_cls.bodies
    extra = sorted(set(bodies_t) - set(want))
    if extra:
        raise fail(f"bodies.{extra[0]}", f"unknown body {extra[0]!r}; a {kind_cls.name} test "
                                          f"has the bodies {', '.join(want)}")
    for b in want:
        if b not in bodies_t:
            raise fail(f"bodies.{b}", f"missing required table [bodies.{b}]")
    bodies = {b: _body(rd, b, bodies_t[b]) for b in want}
    iface = _table(d["interface"], "interface", _SCHEMA["interface"])
    if "mu" not in iface:
        raise fail("interface.mu", "missing required key 'mu' in [interface]")
    mu = rd.quantity("interface.mu", iface["mu"], "num")
    check_number("interface.mu", mu, 0.0, 2.0, lo_open=False)
    mesh = _mesh(rd, d["mesh"], bodies)
    numerics = _numerics(rd, d.get("numerics", {}), kind_cls)
    validation = _validation(rd, d.get("validation", {}), base)
    out = _table(d.get("output", {}), "output", _SCHEMA["output"])
    output = {"frames": rd.quantity("output.frames", out.get("frames", 10), "int"),
              "figures": rd.quantity("output.figures", out.get("figures", True), "bool")}
    check_int("output.frames", output["frames"], 2)
    sc = TribometerScene(name=name, test=test, bodies=bodies, mu=mu, mesh=mesh,
                         numerics=numerics, validation=validation, output=output,
                         description=rd.quantity("scene.description",
                                                 scene.get("description", ""), "str"))
    test.check(sc)
    return sc


def _mesh(rd: _Reader, d: Mapping, bodies: dict) -> dict:
    t = _table(d, "mesh", _SCHEMA["mesh"])
    for k in ("size", "zone"):
        if k not in t:
            raise fail(f"mesh.{k}", f"missing required key {k!r} in [mesh]")
    size = rd.quantity("mesh.size", t["size"], "length")
    zone = rd.quantity("mesh.zone", t["zone"], "length")
    growth = rd.quantity("mesh.growth", t.get("growth", 0.35), "num")
    check_number("mesh.size", size, 0.0, unit="m")
    check_number("mesh.zone", zone, 0.0, unit="m")
    check_number("mesh.growth", growth, 0.05, 1.0)
    z = shown_value("mesh.zone", zone, "m")
    if zone < 4 * size:
        raise fail("mesh.zone", f"{z} is not allowed; the contact zone needs at least four "
                                f"elements: mesh.zone >= 4 mesh.size = "
                                f"{shown_value('mesh.size', 4 * size, 'm')}")
    for b in bodies.values():
        if zone > b.half_width:
            hw = shown_value(f"bodies.{b.name}.half_width", b.half_width, "m")
            raise fail("mesh.zone", f"{z} is not allowed; it must fit in the {b.name}: at "
                                    f"most bodies.{b.name}.half_width = {hw}")
    if zone / size > 400:
        raise fail("mesh.size", f"{shown_value('mesh.size', size, 'm')} is not allowed: "
                                f"{zone / size:.0f} elements across the contact zone; at most 400")
    return {"size": size, "zone": zone, "growth": growth}


def _numerics(rd: _Reader, d: Mapping, kind_cls) -> dict:
    t = _table(d, "numerics", _SCHEMA["numerics"])
    per_cycle = kind_cls.capabilities.get("cycle") == "cycle"
    out = {"wear_tol": 0.02, "first_jump": 1.0, "min_jump": 1.0 if per_cycle else 1e-3,
           "max_jump": 1e9, "fixed_jump": False}
    for k, v in t.items():
        out[k] = rd.quantity(f"numerics.{k}", v, "bool" if k == "fixed_jump" else "num")
    check_number("numerics.wear_tol", out["wear_tol"], 0.0, 0.5)
    check_number("numerics.min_jump", out["min_jump"], 0.0)
    check_number("numerics.first_jump", out["first_jump"], 0.0)
    check_number("numerics.max_jump", out["max_jump"], 0.0)
    if out["max_jump"] < out["min_jump"]:
        raise fail("numerics.max_jump", f"{out['max_jump']!r} is not allowed; it must be at "
                                         f"least numerics.min_jump = {out['min_jump']!r}")
    return out


#: the figures a [validation] may compare: their dimension in lengths
QUANTITIES = {"depth_max": 1, "depth_centre": 1, "scar_width": 1, "worn_area": 2,
              "worn_volume": 3}


def _validation(rd: _Reader, d: Mapping, base: Path | None) -> dict:
    t = _table(d, "validation", _SCHEMA["validation"])
    if not t:
        return {}
    for k in ("source", "quantity", "measured"):
        if k not in t:
            raise fail(f"validation.{k}", f"missing required key {k!r} in [validation]")
    q = rd.quantity("validation.quantity", t["quantity"], "str")
    body, _, what = q.partition(".")
    if what not in QUANTITIES:
        raise fail("validation.quantity", f"{q!r} is not allowed; need BODY.FIGURE with a "
                                           f"figure of {', '.join(QUANTITIES)}")
    power = QUANTITIES[what]
    length = TEST_UNITS["length"][rd.units["length"]]

    def measured(key, value):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise fail(key, f"{value!r} is a {type(value).__name__}; expected a number")
        rd.shown[key] = (f"{rd.units['length']}^{power}" if power > 1 else rd.units["length"],
                         length ** power, 0.0, value)
        return float(value) * length ** power

    out = {"source": rd.quantity("validation.source", t["source"], "str"),
           "quantity": q, "measured": measured("validation.measured", t["measured"]),
           "tolerance": rd.quantity("validation.tolerance", t.get("tolerance", 0.1), "num"),
           "note": rd.quantity("validation.note", t.get("note", ""), "str")}
    ref = t.get("reference", {})
    if not isinstance(ref, Mapping):
        raise fail("validation.reference", "expected a table of name = value")
    out["reference"] = {k: measured(f"validation.reference.{k}", v) for k, v in ref.items()}
    if "profile" in t:
        p = rd.quantity("validation.profile", t["profile"], "path")
        out["profile"] = str(base / p) if base is not None and not Path(p).is_absolute() else p
        out["profile_of"] = rd.quantity("validation.profile_of", t.get("profile_of", body),
                                        "str")
    check_number("validation.tolerance", out["tolerance"], 0.0, 1.0)
    return out
