"""Scenes: one brake model plus what to compute, read from a TOML file or built in Python.

A scene file names the brake geometry (a packaged name, a path, or an inline
``[geometry]`` table), the **components** (rigid or elastic rotor, piston as
a traction or a body), the **interface** (FE contact or a Winkler
foundation, the surfaces it joins, friction), the **environment** (line
pressure, rotor speed, duration, ambient temperature), the **wear laws** of
pad and rotor, optional **thermal** coupling, the **numerics** of the wear
loop and the **output**.  Every number is in the unit its ``[units]`` table
states.  docs/scenes.md is the reference.

:func:`load_scene` / :func:`scene_from_dict` check the whole scene -- unknown
keys (the allowed keys are listed), wrong types, unknown units, missing
tables or bodies, an interface naming a surface the model does not have,
values out of range -- and raise :class:`SceneError` naming the file, the key,
the value and what is allowed, *before* anything is meshed.  The result is a
frozen :class:`Scene` in SI units (m, Pa, s, rad/s, K); :meth:`Scene.run`
builds the model and runs the wear history with
:func:`brakewear.history.run_wear`.

The module is named ``scenefile`` because ``brakewear.scene`` already holds
the brake model (:class:`~brakewear.scene.BrakeModel`) that a scene builds.
"""
from __future__ import annotations

import json
import logging
import math
import sys
from dataclasses import asdict, dataclass, field, fields
from os import PathLike
from pathlib import Path
from typing import Any, Callable, Mapping

from .geometry import BrakeGeometry, geometry_dir, geometry_from_dict, load_geometry
from .scene import SceneError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

logger = logging.getLogger(__name__)

__all__ = [
    "SceneError",
    "Scene",
    "Interface",
    "WearSpec",
    "Thermal",
    "Numerics",
    "Output",
    "load_scene",
    "scene_from_dict",
    "scene_dir",
    "scene_file",
    "available_scenes",
    "SURFACES",
    "UNITS",
]

#: Units a scene file may state, per quantity: name -> factor to SI (temperatures: offset).
UNITS: dict[str, dict[str, float]] = {
    "length": {"mm": 1e-3, "m": 1.0},
    "pressure": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "bar": 1e5},
    "time": {"s": 1.0, "min": 60.0, "h": 3600.0},
    "angular_speed": {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0},
    "temperature": {"K": 0.0, "C": 273.15},   # offsets: T_K = T + offset
}

#: The named surfaces (facet sets) of each body of a :class:`~brakewear.scene.BrakeModel`
#: (brakewear.mesh.pad_mesh, rotor_mesh, piston_mesh); tests compare them with the meshes.
SURFACES: dict[str, tuple[str, ...]] = {
    "pad": ("friction", "back", "piston_face", "leading", "trailing", "abutment", "inner",
            "outer"),
    "rotor": ("friction", "midplane", "rotor_clamp", "outer"),
    "piston": ("piston_face", "piston_back", "piston_side"),
}

# the one sliding interface the wear loop integrates
_WEAR_INTERFACE = ("pad.friction", "rotor.friction")


# ----------------------------------------------------------------------------
# the scene in SI units

def _fail(key: str, msg: str) -> SceneError:
    return SceneError(f"{key}: {msg}")


def _check_choice(key: str, value: Any, allowed: tuple) -> None:
    if value not in allowed:
        raise _fail(key, f"{value!r} is not allowed; allowed: "
                         f"{', '.join(repr(a) for a in allowed)}")


def _check_number(key: str, value: Any, lo: float | None = None, hi: float | None = None,
                  lo_open: bool = True, unit: str = "", allow_none: bool = False) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _fail(key, f"{value!r} is a {type(value).__name__}; expected a number")
    if not math.isfinite(value):
        raise _fail(key, f"{value!r} is not allowed; it must be a finite number")
    u = f" {unit}" if unit else ""
    if lo is not None and (value <= lo if lo_open else value < lo):
        raise _fail(key, f"{value!r}{u} is not allowed; it must be {'>' if lo_open else '>='} "
                         f"{lo:g}{u}")
    if hi is not None and value > hi:
        raise _fail(key, f"{value!r}{u} is not allowed; it must be <= {hi:g}{u}")


def _check_int(key: str, value: Any, lo: int, allow_none: bool = False) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, int):
        raise _fail(key, f"{value!r} is a {type(value).__name__}; expected a whole number")
    if value < lo:
        raise _fail(key, f"{value!r} is not allowed; it must be >= {lo}")


def _check_bool(key: str, value: Any) -> None:
    if not isinstance(value, bool):
        raise _fail(key, f"{value!r} is a {type(value).__name__}; expected true or false")


@dataclass(frozen=True)
class Interface:
    """The pad-rotor interface.

    Parameters
    ----------
    model
        ``"fe"``: node-to-surface FE contact; ``"winkler"``: an elastic
        foundation (:class:`brakewear.foundation.WinklerInterface`).
    surfaces
        The two surfaces it joins, ``"body.surface"`` (see :data:`SURFACES`).
    mu
        Sliding friction coefficient (>= 0).
    method
        FE contact discretisation (``"segment"``; FE only).
    winkler_modulus
        Foundation modulus (Pa/m); ``None``: Johnson's layer modulus of the
        friction layer (Winkler only).
    winkler_rotor
        ``"rigid"`` or ``"foundation"`` (rotor half thickness in series; Winkler only).
    """

    model: str = "fe"
    surfaces: tuple[str, str] = _WEAR_INTERFACE
    mu: float = 0.0
    method: str = "segment"
    winkler_modulus: float | None = None
    winkler_rotor: str = "rigid"

    def __post_init__(self):
        _check_choice("interface.model", self.model, ("fe", "winkler"))
        if (not isinstance(self.surfaces, (tuple, list)) or len(self.surfaces) != 2
                or not all(isinstance(s, str) for s in self.surfaces)):
            raise _fail("interface.surfaces", f"{self.surfaces!r} is not allowed; expected two "
                                              "names \"body.surface\", e.g. "
                                              "[\"pad.friction\", \"rotor.friction\"]")
        object.__setattr__(self, "surfaces", tuple(self.surfaces))
        _check_number("interface.mu", self.mu, 0.0, lo_open=False)
        _check_choice("interface.method", self.method, ("segment",))
        _check_number("interface.winkler_modulus", self.winkler_modulus, 0.0, unit="Pa/m",
                      allow_none=True)
        _check_choice("interface.winkler_rotor", self.winkler_rotor, ("rigid", "foundation"))


@dataclass(frozen=True)
class WearSpec:
    """A wear law ``dh/dt = k(T) p^a v^b`` (see :class:`brakewear.wear.WearLaw`).

    ``k = None`` takes the material's ``wear_k`` (pad: the friction
    material, rotor: the rotor material).  ``k`` is in SI units
    (1/Pa = m^2/N for a = b = 1; in general m/s per Pa^a (m/s)^b).
    """

    k: float | None = None
    a: float = 1.0
    b: float = 1.0
    T_threshold: float = 503.15
    activation_energy: float = 0.0

    def check(self, sec: str) -> None:
        _check_number(f"{sec}.k", self.k, 0.0, unit="1/Pa", allow_none=True)
        _check_number(f"{sec}.a", self.a, 0.0)
        _check_number(f"{sec}.b", self.b, 0.0)
        _check_number(f"{sec}.T_threshold", self.T_threshold, 0.0, unit="K")
        _check_number(f"{sec}.activation_energy", self.activation_energy, 0.0, lo_open=False,
                      unit="J/mol")

    def law(self, material, sec: str):
        """The :class:`~brakewear.wear.WearLaw` (``material`` supplies a missing k)."""
        from .wear import WearLaw
        k = self.k
        if k is None:
            k = material.wear_k
            if k is None:
                raise _fail(f"{sec}.k", f"not given and material {material.name!r} has no "
                                        "wear_k; give k (1/Pa)")
        return WearLaw(k, self.a, self.b, self.T_threshold, self.activation_energy)


@dataclass(frozen=True)
class Thermal:
    """Thermal coupling (:class:`brakewear.thermal.ThermalModel` arguments, SI).

    ``T_ambient`` is the scene's ``environment.ambient``.
    """

    enabled: bool = False
    partition: str | float = "effusivity"
    h_conv: float | Mapping[str, float] = 40.0
    T_initial: float | None = None
    T_ref: float | None = None
    contact_conductance: float = 0.0
    mass: str = "consistent"

    def __post_init__(self):
        _check_bool("thermal.enabled", self.enabled)
        if isinstance(self.partition, str):
            _check_choice("thermal.partition", self.partition, ("effusivity", "effusivity_area"))
        else:
            _check_number("thermal.partition", self.partition, 0.0, 1.0, lo_open=False)
        if isinstance(self.h_conv, Mapping):
            unknown = sorted(set(self.h_conv) - {"pad", "rotor"})
            if unknown:
                raise _fail(f"thermal.h_conv.{unknown[0]}", "unknown body; allowed: pad, rotor")
            for b, h in self.h_conv.items():
                _check_number(f"thermal.h_conv.{b}", h, 0.0, lo_open=False, unit="W/m^2 K")
            object.__setattr__(self, "h_conv", dict(self.h_conv))
        else:
            _check_number("thermal.h_conv", self.h_conv, 0.0, lo_open=False, unit="W/m^2 K")
        _check_number("thermal.T_initial", self.T_initial, 0.0, unit="K", allow_none=True)
        _check_number("thermal.T_ref", self.T_ref, 0.0, unit="K", allow_none=True)
        _check_number("thermal.contact_conductance", self.contact_conductance, 0.0,
                      lo_open=False, unit="W/m^2 K")
        _check_choice("thermal.mass", self.mass, ("consistent", "lumped"))


@dataclass(frozen=True)
class Numerics:
    """How the wear loop integrates (:func:`brakewear.simulate.wear_history` arguments, SI).

    ``steps = None``: automatic step control (``dp_tol``, or ``wear_tol`` when
    given, ``dh_fraction`` or ``max_dh``, ``stability``); a number: that many
    equal steps.
    """

    scheme: str = "implicit"
    update: str = "gap"
    steps: int | None = None
    dp_tol: float = 0.05
    dh_fraction: float = 0.1
    max_dh: float | None = None
    wear_tol: float | None = None
    stability: float = 1.0
    tol: float = 1e-9
    max_halvings: int = 12

    def __post_init__(self):
        _check_choice("numerics.scheme", self.scheme, ("explicit", "implicit"))
        _check_choice("numerics.update", self.update, ("gap", "geometry"))
        _check_int("numerics.steps", self.steps, 1, allow_none=True)
        _check_number("numerics.dp_tol", self.dp_tol, 0.0)
        _check_number("numerics.dh_fraction", self.dh_fraction, 0.0, 1.0)
        _check_number("numerics.max_dh", self.max_dh, 0.0, unit="m", allow_none=True)
        _check_number("numerics.wear_tol", self.wear_tol, 0.0, unit="m", allow_none=True)
        _check_number("numerics.stability", self.stability, 0.0, 2.0)
        _check_number("numerics.tol", self.tol, 0.0, 1e-3)
        _check_int("numerics.max_halvings", self.max_halvings, 0)


@dataclass(frozen=True)
class Output:
    """What the run writes: VTU every ``vtu_every`` steps, a checkpoint every
    ``checkpoint_every`` steps, PNG figures at the end."""

    vtu_every: int = 10
    checkpoint_every: int = 10
    figures: bool = True

    def __post_init__(self):
        _check_int("output.vtu_every", self.vtu_every, 1)
        _check_int("output.checkpoint_every", self.checkpoint_every, 1)
        _check_bool("output.figures", self.figures)


@dataclass(frozen=True)
class Scene:
    """A brake scene in SI units: what to build and what to compute.

    Parameters
    ----------
    geometry
        A :class:`~brakewear.geometry.BrakeGeometry`, or a packaged geometry
        name / ``.toml`` path (loaded and checked at once; no meshing).
    rotor, piston
        Components: ``"elastic"`` | ``"rigid"`` rotor; ``"traction"`` | ``"body"`` piston.
    mesh_size, order
        Interface element size (m) and element order; ``None``: the geometry's.
    line_pressure, omega, duration, ambient
        Pa, rad/s, s, K: steady drag at constant line pressure and rotor speed.
    interface, pad_wear, rotor_wear, thermal, numerics, output
        The tables of the scene file; ``rotor_wear = None``: the rotor does not wear.
    name, description, source
        For messages and the summary (not compared).
    """

    geometry: BrakeGeometry | str = "default"
    duration: float = 600.0
    line_pressure: float = 1e6
    omega: float = 55.0
    ambient: float = 293.15
    rotor: str = "elastic"
    piston: str = "traction"
    mesh_size: float | None = None
    order: int | None = None
    interface: Interface = field(default_factory=Interface)
    pad_wear: WearSpec = field(default_factory=WearSpec)
    rotor_wear: WearSpec | None = field(default_factory=WearSpec)
    thermal: Thermal = field(default_factory=Thermal)
    numerics: Numerics = field(default_factory=Numerics)
    output: Output = field(default_factory=Output)
    name: str = field(default="scene", compare=False)
    description: str = field(default="", compare=False)
    source: str = field(default="<python>", compare=False)

    def __post_init__(self):
        g = self.geometry
        if isinstance(g, (str, PathLike)):
            object.__setattr__(self, "geometry", load_geometry(g))
        elif not isinstance(g, BrakeGeometry):
            raise _fail("scene.geometry", f"{g!r} is not a geometry; expected a name, a path "
                                          "or a BrakeGeometry")
        _check_choice("components.rotor", self.rotor, ("elastic", "rigid"))
        _check_choice("components.piston", self.piston, ("traction", "body"))
        _check_number("environment.line_pressure", self.line_pressure, 0.0, unit="Pa")
        _check_number("environment.omega", self.omega, 0.0, unit="rad/s")
        _check_number("environment.duration", self.duration, 0.0, unit="s")
        _check_number("environment.ambient", self.ambient, 0.0, unit="K")
        width = self.geometry.pad.outer_radius - self.geometry.pad.inner_radius
        _check_number("mesh.size", self.mesh_size, 0.0, 0.5 * width, unit="m", allow_none=True)
        _check_int("mesh.order", self.order, 1, allow_none=True)
        if self.order not in (None, 1):
            raise _fail("mesh.order", f"{self.order!r} is not allowed; a brake with a pad-rotor "
                                      "interface supports P1 meshes only: allowed 1")
        for name, cls in (("interface", Interface), ("thermal", Thermal),
                          ("numerics", Numerics), ("output", Output)):
            if not isinstance(getattr(self, name), cls):
                raise _fail(name, f"{getattr(self, name)!r} is not a {cls.__name__}")
        for sec, spec in (("wear.pad", self.pad_wear), ("wear.rotor", self.rotor_wear)):
            if spec is None and sec == "wear.rotor":
                continue
            if not isinstance(spec, WearSpec):
                raise _fail(sec, f"{spec!r} is not a WearSpec")
            spec.check(sec)
        self._check_interface()
        self._check_consistency()

    # ------------------------------------------------------------ checks --
    def _bodies(self) -> dict[str, str]:
        return {"rotor": self.rotor, "pad": "elastic", "piston": self.piston}

    def _check_interface(self) -> None:
        bodies = self._bodies()
        for s in self.interface.surfaces:
            body, _, surf = s.partition(".")
            if body not in SURFACES:
                raise _fail("interface.surfaces", f"{s!r} names no body of the scene; "
                                                  f"bodies: {', '.join(SURFACES)} "
                                                  "(write \"body.surface\")")
            if body == "piston" and bodies["piston"] != "body":
                raise _fail("interface.surfaces", f"{s!r}: the piston is not a body of this "
                                                  "scene (components.piston = 'traction')")
            if surf not in SURFACES[body]:
                raise _fail("interface.surfaces", f"{s!r}: the {body} has no surface {surf!r}; "
                                                  f"{body} surfaces: "
                                                  f"{', '.join(SURFACES[body])}")
        if tuple(sorted(self.interface.surfaces)) != _WEAR_INTERFACE:
            raise _fail("interface.surfaces",
                        f"{list(self.interface.surfaces)!r}: the wear loop's sliding interface is "
                        f"{' against '.join(_WEAR_INTERFACE)}; allowed: "
                        f"{list(_WEAR_INTERFACE)!r}")

    def _check_consistency(self) -> None:
        n = self.numerics
        if n.scheme == "implicit" and self.pad_wear.a != 1.0:
            raise _fail("wear.pad.a", f"{self.pad_wear.a!r} is not allowed with numerics.scheme "
                                      "= 'implicit' (backward Euler needs a law linear in p): "
                                      "allowed 1, or use scheme = 'explicit'")
        if n.update == "geometry" and self.interface.model != "fe":
            raise _fail("numerics.update", "'geometry' moves the FE meshes; it needs "
                                           "interface.model = 'fe'")
        if n.update == "geometry" and self.thermal.enabled:
            raise _fail("numerics.update", "'geometry' cannot be combined with thermal coupling "
                                           "(thermal.enabled = true): the thermal meshes do not "
                                           "follow the worn faces; allowed: 'gap'")
        if self.thermal.contact_conductance > 0 and self.rotor != "elastic":
            raise _fail("thermal.contact_conductance", "> 0 needs an elastic rotor "
                                                       "(components.rotor = 'elastic')")

    # -------------------------------------------------------------- build --
    def build_model(self):
        """The :class:`~brakewear.scene.BrakeModel` of the scene (this meshes)."""
        from .scene import BrakeModel
        return BrakeModel(self.geometry, piston=self.piston, size=self.mesh_size,
                          order=self.order, rotor=self.rotor)

    def wear_laws(self):
        """(pad law, rotor law or None)."""
        g = self.geometry
        pad = self.pad_wear.law(g.pad.friction_material, "wear.pad")
        rot = None if self.rotor_wear is None else self.rotor_wear.law(g.rotor.material,
                                                                        "wear.rotor")
        return pad, rot

    def to_dict(self) -> dict:
        """A JSON-ready record of the scene in SI units (written to ``scene.json``)."""
        d = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "geometry"}
        for k in ("interface", "pad_wear", "rotor_wear", "thermal", "numerics", "output"):
            d[k] = None if d[k] is None else asdict(d[k])
        d["interface"]["surfaces"] = list(d["interface"]["surfaces"])
        g = self.geometry
        d["geometry"] = {"source": str(g.source), "rotor": _geom_record(g.rotor),
                         "pad": _geom_record(g.pad), "piston": _geom_record(g.piston),
                         "mesh": asdict(g.mesh)}
        return json.loads(json.dumps(d, default=str))

    def run(self, out: str | PathLike, resume: bool = False,
            progress: Callable | None = None) -> dict:
        """Build the model and run the wear history into ``out``; return the summary.

        Writes what :func:`brakewear.history.run_wear` writes, plus
        ``scene.json`` (this scene, SI) and, with ``output.figures``, PNG
        figures.  ``resume=True`` continues from ``out/checkpoint.npz`` and
        refuses a folder written by a different scene.  ``progress`` is
        called with each :class:`~brakewear.simulate.WearStep`.
        """
        from .history import run_wear

        out = Path(out)
        record = self.to_dict()
        rec_path = out / "scene.json"
        if resume:
            ck = out / "checkpoint.npz"
            if not ck.exists():
                raise SceneError(f"--resume: {ck} does not exist (no checkpoint was written: "
                                 "run without --resume to start)")
            # outputs may change on resume, and so may the duration under automatic
            # step control (a longer one extends the run)
            ignore = {"output"} | ({"duration"} if self.numerics.steps is None else set())
            if rec_path.exists():
                old = json.loads(rec_path.read_text())
                diff = _first_difference({k: v for k, v in old.items() if k not in ignore},
                                         {k: v for k, v in record.items() if k not in ignore})
                if diff is not None:
                    raise SceneError(f"--resume: {out} holds a run of a different scene "
                                     f"({diff}); resume with the same scene or choose another "
                                     "--out")
            import numpy as np
            with np.load(ck) as d:
                t_done, step_done = float(d["time"]), int(d["step"])
            if t_done > self.duration * (1 + 1e-12):
                raise SceneError(f"--resume: the run in {out} has already reached t = "
                                 f"{t_done:.6g} s, beyond environment.duration = "
                                 f"{self.duration:.6g} s; allowed: a duration >= {t_done:.6g} s")
            if t_done >= self.duration * (1 - 1e-12):
                logger.info("run in %s already finished (step %d)", out, step_done)
                summ = out / "summary.json"
                if not summ.exists():
                    raise SceneError(f"--resume: the run in {out} has finished (step "
                                     f"{step_done}, t = {t_done:.6g} s) but its summary.json "
                                     "is missing; run again without --resume to redo it")
                s = json.loads(summ.read_text())
                s["already_finished"] = True
                return s
        out.mkdir(parents=True, exist_ok=True)
        rec_path.write_text(json.dumps(record, indent=2))
        pad_law, rotor_law = self.wear_laws()
        model = self.build_model()
        n = self.numerics
        kw: dict[str, Any] = dict(steps=n.steps, max_dh=n.max_dh, dh_fraction=n.dh_fraction,
                                  dp_tol=n.dp_tol, wear_tol=n.wear_tol,
                                  stability=n.stability, scheme=n.scheme,
                                  update=n.update, every=self.output.checkpoint_every,
                                  tol=n.tol, max_halvings=n.max_halvings)
        if self.interface.model == "winkler":
            from .foundation import WinklerInterface
            from .simulate import FoundationInterface
            winkler = WinklerInterface.from_model(model, modulus=self.interface.winkler_modulus,
                                                  rotor=self.interface.winkler_rotor)
            kw["interface"] = FoundationInterface(model, winkler, self.line_pressure,
                                                  self.interface.mu)
        if self.thermal.enabled:
            from .thermal import ThermalModel
            t = self.thermal
            kw["thermal"] = ThermalModel(model, partition=t.partition, h_conv=t.h_conv,
                                         T_ambient=self.ambient, T_ref=t.T_ref, mass=t.mass,
                                         T_initial=t.T_initial,
                                         contact_conductance=t.contact_conductance)
        summary = run_wear(model, out, self.line_pressure, self.omega, self.duration, pad_law,
                           rotor_law, self.interface.mu, vtu_every=self.output.vtu_every,
                           resume=resume, progress=progress, **kw)
        summary["scene"] = {"name": self.name, "source": self.source,
                            "interface": self.interface.model, "scheme": n.scheme,
                            "update": n.update, "mesh_size_m": model.geometry.mesh.size
                            if self.mesh_size is None else self.mesh_size}
        if self.output.figures:
            summary["figures"] = _figures(model, out, self)
        (out / "summary.json").write_text(json.dumps(summary, indent=2, default=float))
        return summary


def _geom_record(obj) -> dict:
    return {k: (v.name if hasattr(v, "elastic") else v) for k, v in vars(obj).items()}


def _first_difference(a: Any, b: Any, path: str = "") -> str | None:
    """The first key where two JSON records differ (None if equal)."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k in ("name", "description", "source"):
                continue
            d = _first_difference(a.get(k), b.get(k), f"{path}.{k}" if path else k)
            if d is not None:
                return d
        return None
    if isinstance(a, float) and isinstance(b, float) and math.isclose(a, b, rel_tol=1e-12):
        return None
    if a == b:
        return None
    top, _, rest = path.partition(".")
    key = _RECORD_KEYS.get(top, top) + (f".{rest}" if rest else "")
    return f"{key}: {a!r} then, {b!r} now"


# Scene field -> scene-file key, for messages about scene.json records
_RECORD_KEYS = {"duration": "environment.duration", "line_pressure": "environment.line_pressure",
                "omega": "environment.omega", "ambient": "environment.ambient",
                "rotor": "components.rotor", "piston": "components.piston",
                "mesh_size": "mesh.size", "order": "mesh.order", "pad_wear": "wear.pad",
                "rotor_wear": "wear.rotor", "geometry": "geometry"}


def _figures(model, out: Path, scene: Scene) -> list[str]:
    """Final pad wear and pressure on the friction face; wear and pressure histories."""
    import csv

    import meshio
    import numpy as np

    from .figures import plot_field

    files = []
    pvd = out / "pad.pvd"
    last = sorted(out.glob("pad_*.vtu"))
    if pvd.exists() and last:
        m = meshio.read(last[-1])
        pad = model.meshes["pad"]
        for fld, png, scale, label, cmap in (
                ("pad_wear", "pad_wear.png", 1e6, "pad wear (um)", "viridis"),
                ("pressure", "pad_pressure.png", 1e-6, "pressure (MPa)", "inferno")):
            files.append(str(plot_field(
                pad, m.point_data[fld] * scale, out / png,
                f"{scene.name}: {label}, last step", label=label, cmap=cmap,
                facets="friction", view=(0.0, 0.0, -1.0))))
    with open(out / "history.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    if rows:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        t = np.array([0.0] + [float(r["time_s"]) for r in rows])
        t_start = np.array([float(r["time_s"]) - float(r["dt_s"]) for r in rows])
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        for key, label in (("pad_wear_max_m", "pad, max"), ("pad_wear_mean_m", "pad, mean"),
                           ("rotor_wear_max_m", "rotor, max")):
            ax[0].plot(t, [0.0] + [1e6 * float(r[key]) for r in rows], label=label)
        ax[0].set(xlabel="time (s)", ylabel="wear depth (um)", title="wear")
        ax[0].legend()
        ax[1].plot(t_start, [1e-6 * float(r["pressure_max_Pa"]) for r in rows], marker=".")
        ax[1].set(xlabel="time (s)", ylabel="max contact pressure (MPa)",
                  title="pressure at the start of each step")
        fig.suptitle(f"{scene.name}: {scene.line_pressure / 1e6:g} MPa, "
                     f"{scene.omega:g} rad/s, mu {scene.interface.mu:g}")
        fig.tight_layout()
        path = out / "history.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        files.append(str(path))
    return files


# ----------------------------------------------------------------------------
# reading a scene file

#: table -> key -> kind.  Kinds: a unit quantity ("length", "pressure", "time",
#: "angular_speed", "temperature"), or "str", "num", "int", "bool", "surfaces",
#: "geometry", "k", "h_conv", "partition".
_SCHEMA: dict[str, dict[str, str]] = {
    "units": {q: "unit" for q in UNITS},
    "scene": {"name": "str", "description": "str", "geometry": "geometry"},
    "components": {"rotor": "str", "pad": "str", "piston": "str"},
    "mesh": {"size": "length", "order": "int"},
    "environment": {"line_pressure": "pressure", "omega": "angular_speed", "duration": "time",
                    "ambient": "temperature"},
    "interface": {"model": "str", "surfaces": "surfaces", "mu": "num", "method": "str",
                  "winkler_modulus": "num", "winkler_rotor": "str"},
    "wear.pad": {"k": "k", "a": "num", "b": "num", "T_threshold": "temperature",
                 "activation_energy": "num"},
    "wear.rotor": {"enabled": "bool", "k": "k", "a": "num", "b": "num",
                   "T_threshold": "temperature", "activation_energy": "num"},
    "thermal": {"enabled": "bool", "partition": "partition", "h_conv": "h_conv",
                "T_initial": "temperature", "T_ref": "temperature",
                "contact_conductance": "num", "mass": "str"},
    "numerics": {"scheme": "str", "update": "str", "steps": "int", "dp_tol": "num",
                 "dh_fraction": "num", "max_dh": "length", "wear_tol": "length",
                 "stability": "num", "tol": "num", "max_halvings": "int"},
    "output": {"vtu_every": "int", "checkpoint_every": "int", "figures": "bool"},
}
_REQUIRED_TABLES = ("units", "scene", "components", "environment", "wear")
_REQUIRED_KEYS = {
    "units": set(UNITS),
    "components": {"rotor", "pad"},
    "environment": {"line_pressure", "omega", "duration"},
}
_TOP = ("units", "scene", "geometry", "components", "mesh", "environment", "interface", "wear",
        "thermal", "numerics", "output")


def scene_dir():
    """The folder of the packaged scene files.

    In a source checkout: ``geometry/scenes`` beside the ``brakewear`` folder
    (looked at first, so that a checkout never reads the scenes of another
    installed copy); installed: ``brakewear.geometries/scenes`` (setup.cfg
    ships them as package data).
    """
    here = Path(__file__).resolve().parent.parent / "geometry" / "scenes"
    if here.is_dir():
        return here
    return geometry_dir() / "scenes"


def scene_file(name: str = "default"):
    """The packaged scene file of a name (a Traversable; may not exist)."""
    return scene_dir() / f"{name}.toml"


def available_scenes() -> list[str]:
    """Names of the scene files shipped with brakewear."""
    return sorted(p.name[:-5] for p in scene_dir().iterdir() if p.name.endswith(".toml"))


def load_scene(path_or_name: str | PathLike = "default") -> Scene:
    """Load and check a scene file (nothing is meshed).

    Parameters
    ----------
    path_or_name
        A packaged scene name (``"default"``) or the path of a TOML file; a
        string with a path separator or ending in ``.toml`` is a path.

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
        d = tomllib.loads(data.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise SceneError(f"{source}: not a valid TOML file: {exc}") from None
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
    """
    try:
        return _parse(d, source, None if base is None else Path(base))
    except SceneError as exc:
        raise SceneError(f"{source}: {exc}") from None


def _parse(d: Any, source: str, base: Path | None) -> Scene:
    if not isinstance(d, Mapping):
        raise _fail("<top level>", f"expected tables, got {type(d).__name__}")
    unknown = sorted(set(d) - set(_TOP))
    if unknown:
        raise _fail(unknown[0], f"unknown table [{unknown[0]}]; allowed tables: "
                                f"{', '.join(_TOP)}")
    for t in _REQUIRED_TABLES:
        if t not in d:
            raise _fail(t, f"missing required table [{t}]")
    tables: dict[str, dict] = {}
    for t in _TOP:
        if t in d and t not in ("wear", "geometry"):
            tables[t] = _table(d[t], t)
    wear = _table(d["wear"], "wear")
    bad = sorted(set(wear) - {"pad", "rotor"})
    if bad:
        raise _fail(f"wear.{bad[0]}", f"unknown table [wear.{bad[0]}]; allowed: [wear.pad], "
                                      "[wear.rotor]")
    if "pad" not in wear:
        raise _fail("wear.pad", "missing required table [wear.pad] (the pad always wears)")
    for b in ("pad", "rotor"):
        if b in wear:
            tables[f"wear.{b}"] = _table(wear[b], f"wear.{b}")
    for t, tab in tables.items():
        allowed = _SCHEMA[t]
        unknown = sorted(set(tab) - set(allowed))
        if unknown:
            raise _fail(f"{t}.{unknown[0]}", f"unknown key {unknown[0]!r} in [{t}]; allowed "
                                             f"keys: {', '.join(allowed)}")
        for k in sorted(_REQUIRED_KEYS.get(t, set()) - set(tab)):
            what = "body" if t == "components" else "key"
            raise _fail(f"{t}.{k}", f"missing required {what} {k!r} in [{t}]" + (
                "; a brake scene needs a pad and a rotor" if t == "components" else ""))

    units = {}
    for q, choices in UNITS.items():
        u = tables["units"][q]
        if not isinstance(u, str) or u not in choices:
            raise _fail(f"units.{q}", f"{u!r} is not allowed; allowed units: "
                                      f"{', '.join(repr(c) for c in choices)}")
        units[q] = u

    def val(t: str, k: str, default: Any = None) -> Any:
        tab = tables.get(t, {})
        if k not in tab:
            return default
        return _convert(f"{t}.{k}", tab[k], _SCHEMA[t][k], units)

    # geometry: inline table, name or path
    sc = tables["scene"]
    if "geometry" in d:
        if "geometry" in sc:
            raise _fail("scene.geometry", "given twice: as scene.geometry and as a [geometry] "
                                          "table; keep one")
        geometry = geometry_from_dict(_table(d["geometry"], "geometry"),
                                      source=f"{source}: [geometry]")
    else:
        g = sc.get("geometry", "default")
        if not isinstance(g, str):
            raise _fail("scene.geometry", f"{g!r} is a {type(g).__name__}; expected a geometry "
                                          "name or a .toml path (or a [geometry] table)")
        is_path = "/" in g or "\\" in g or g.endswith(".toml")
        if is_path and base is not None and not Path(g).is_absolute():
            g = str(base / g)
        geometry = load_geometry(g)

    comps = tables["components"]
    for k in comps:
        _convert(f"components.{k}", comps[k], "str", units)
    if comps["pad"] != "elastic":
        raise _fail("components.pad", f"{comps['pad']!r} is not allowed; allowed: 'elastic' "
                                      "(the pad is always meshed)")

    iface = tables.get("interface", {})
    ikw = {k: val("interface", k) for k in iface}
    if "surfaces" in ikw:
        ikw["surfaces"] = tuple(ikw["surfaces"])
    interface = Interface(**ikw)

    def wear_spec(b: str) -> WearSpec | None:
        t = f"wear.{b}"
        if t not in tables:
            return None
        tab = dict(tables[t])
        if b == "rotor" and not val(t, "enabled", True):
            return None
        tab.pop("enabled", None)
        return WearSpec(**{k: val(t, k) for k in tab})

    thermal = Thermal(**{k: val("thermal", k) for k in tables.get("thermal", {})})
    numerics = Numerics(**{k: val("numerics", k) for k in tables.get("numerics", {})})
    output = Output(**{k: val("output", k) for k in tables.get("output", {})})
    env = {k: val("environment", k) for k in tables["environment"]}
    name = val("scene", "name", Path(source).stem if source.endswith(".toml") else source)
    return Scene(geometry=geometry, rotor=comps["rotor"],
                 piston=comps.get("piston", "traction"),
                 mesh_size=val("mesh", "size"), order=val("mesh", "order"),
                 interface=interface, pad_wear=wear_spec("pad"), rotor_wear=wear_spec("rotor"),
                 thermal=thermal, numerics=numerics, output=output, name=name,
                 description=val("scene", "description", ""), source=source, **env)


def _table(v: Any, name: str) -> dict:
    if not isinstance(v, Mapping):
        raise _fail(name, f"expected a table [{name}], got {type(v).__name__} {v!r}")
    return dict(v)


def _convert(key: str, v: Any, kind: str, units: Mapping[str, str]) -> Any:
    """Type-check one value and convert it to SI."""
    def number() -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise _fail(key, f"{v!r} is a {type(v).__name__}; expected a number")
        if not math.isfinite(v):
            raise _fail(key, f"{v!r} is not allowed; it must be a finite number")
        return float(v)

    if kind in ("str", "geometry"):
        if not isinstance(v, str):
            raise _fail(key, f"{v!r} is a {type(v).__name__}; expected a string")
        return v
    if kind == "bool":
        if not isinstance(v, bool):
            raise _fail(key, f"{v!r} is a {type(v).__name__}; expected true or false")
        return v
    if kind == "int":
        if isinstance(v, bool) or not isinstance(v, int):
            raise _fail(key, f"{v!r} is a {type(v).__name__}; expected a whole number")
        return v
    if kind == "num":
        return number()
    if kind == "k":
        if v == "material":
            return None
        if isinstance(v, str):
            raise _fail(key, f"{v!r} is not allowed; expected a number (1/Pa) or \"material\"")
        return number()
    if kind == "partition":
        return v if isinstance(v, str) else number()
    if kind == "h_conv":
        if isinstance(v, Mapping):
            return {b: _convert(f"{key}.{b}", h, "num", units) for b, h in v.items()}
        return number()
    if kind == "surfaces":
        if not isinstance(v, list) or not all(isinstance(s, str) for s in v):
            raise _fail(key, f"{v!r} is not allowed; expected a list of two strings "
                             "\"body.surface\"")
        return v
    if kind in UNITS:
        x = number()
        u = units[kind]
        if kind == "temperature":
            return x + UNITS[kind][u]
        if x <= 0:
            raise _fail(key, f"{x!r} {u} is not allowed; it must be > 0 {u}")
        return x * UNITS[kind][u]
    raise AssertionError(kind)  # pragma: no cover
