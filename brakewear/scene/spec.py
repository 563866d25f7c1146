"""Scenes: one brake model plus what to compute, in SI units.

A scene names the brake geometry, the **components** (rigid or elastic rotor, piston as
a traction or a body), the **interface** (FE contact or a Winkler foundation, the
surfaces it joins, friction), the **environment** (line pressure, rotor speed, duration,
ambient temperature), the **wear laws** of pad and rotor, optional **thermal** coupling,
the **numerics** of the wear loop and the **output**. :class:`Scene` and its tables
check their values on construction and raise :class:`~brakewear.errors.SceneError`
naming the key; files are read by :mod:`brakewear.scene.reader` and run by
:func:`brakewear.output.runs.run_scene`.
"""
from __future__ import annotations

import json
import logging
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields, replace
from os import PathLike
from typing import Any

from ..checks import (
    check_choice,
    check_int,
    check_number,
    check_plausible,
    fail,
    shown_value,
    user_scale,
    user_unit,
)
from ..geometry.files import load_geometry
from ..geometry.parts import MAX_LAYERS, MESH_BODY_KEYS, BrakeGeometry
from ..interfaces.registry import allowed_for, capabilities_of, lacks
from ..wear.numerics import Numerics
from .bounds import check_bounds
from .tables import (
    _WEAR_INTERFACE,
    SURFACES,
    InterfaceSpec,
    OutputSpec,
    ThermalSpec,
    WearSpec,
)

logger = logging.getLogger(__name__)

__all__ = ["Scene", "first_difference"]


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
    layout
        ``"auto"`` | ``"half"`` | ``"full"``: one pad and the rotor's half, or both
        pads and the whole rotor (:class:`~brakewear.model.BrakeModel`).
    mesh_size, order
        Interface element size (m) and element order; ``None``: the geometry's.
    mesh_files
        Your own meshes: body (``"pad"``, ``"rotor"``, ``"piston"``) -> mesh
        file with the named groups of :data:`brakewear.mesh.io.MESH_GROUPS`
        (scene keys ``mesh.pad_file``, ...); read and checked at once.
    resolution
        Per-body mesh resolution, overriding the geometry's ``[mesh]``:
        ``pad_size``, ``rotor_size`` (m), ``friction_layers``,
        ``backplate_layers``, ``rotor_layers`` (element layers; see
        :class:`~brakewear.geometry.MeshSettings`); they take precedence over
        ``mesh_size`` for their body.  ``geometry`` stays as given;
        :attr:`meshed_geometry` is the geometry the model is meshed from.
    line_pressure, omega, duration, ambient
        Pa, rad/s, s, K: steady drag at constant line pressure and rotor speed.
    interface, pad_wear, rotor_wear, thermal, numerics, output
        The tables of the scene file; ``rotor_wear = None``: the rotor does not wear.
    vehicle, schedule
        A :class:`~brakewear.duty.Vehicle` and a schedule of applications
        (:class:`~brakewear.duty.Stop`, ``Drag``, ``Dwell``; scene tables
        ``[vehicle]`` and ``[schedule]``): the run is the schedule
        (:func:`brakewear.duty.run_schedule`) instead of one drag at
        ``line_pressure`` and ``omega`` for ``duration``.
    name, description, source
        For messages and the summary (not compared).
    user_units
        Key -> ``(unit, factor, offset, value as written)`` of the values a scene
        file gave in its own units (set by the reader, not compared): messages
        about them, at a resume too, show them in those units.
    """

    geometry: BrakeGeometry | str = "default"
    duration: float = 600.0
    line_pressure: float = 1e6
    omega: float = 55.0
    ambient: float = 293.15
    rotor: str = "elastic"
    piston: str = "traction"
    layout: str = "auto"
    mesh_size: float | None = None
    order: int | None = None
    mesh_files: Mapping[str, str] = field(default_factory=dict)
    resolution: Mapping[str, float] = field(default_factory=dict)
    interface: InterfaceSpec = field(default_factory=InterfaceSpec)
    pad_wear: WearSpec = field(default_factory=WearSpec)
    rotor_wear: WearSpec | None = field(default_factory=WearSpec)
    thermal: ThermalSpec = field(default_factory=ThermalSpec)
    numerics: Numerics = field(default_factory=Numerics)
    output: OutputSpec = field(default_factory=OutputSpec)
    vehicle: Any = None
    schedule: tuple = ()
    name: str = field(default="scene", compare=False)
    description: str = field(default="", compare=False)
    source: str = field(default="<python>", compare=False)
    user_units: Mapping[str, tuple] = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self):
        g = self.geometry
        if isinstance(g, (str, PathLike)):
            object.__setattr__(self, "geometry", load_geometry(g))
        elif not isinstance(g, BrakeGeometry):
            raise fail("scene.geometry", f"{g!r} is not a geometry; expected a name, a path "
                                          "or a BrakeGeometry")
        check_choice("components.rotor", self.rotor, ("elastic", "rigid"))
        check_choice("components.piston", self.piston, ("traction", "body"))
        check_choice("components.layout", self.layout, ("auto", "half", "full"))
        if self.layout == "full" and self.rotor == "rigid":
            raise fail("components.layout", "'full' is not allowed with components.rotor = "
                                             "'rigid' (a plane has one friction face); allowed "
                                             "with a rigid rotor: 'auto', 'half'")
        check_number("environment.line_pressure", self.line_pressure, 0.0, unit="Pa")
        check_number("environment.omega", self.omega, 0.0, unit="rad/s")
        check_number("environment.duration", self.duration, 0.0, unit="s")
        check_number("environment.ambient", self.ambient, 0.0, unit="K")
        for key, value in (("environment.line_pressure", self.line_pressure),
                           ("environment.omega", self.omega),
                           ("environment.ambient", self.ambient)):
            check_plausible(key, value)
        if self.mesh_size is not None:
            check_number("mesh.size", self.mesh_size, 0.0, unit="m")
        check_int("mesh.order", self.order, 1, allow_none=True)
        self._check_resolution()
        if self.order is not None:
            check_choice("mesh.order", self.order, (1, 2))
        for name, cls in (("interface", InterfaceSpec), ("thermal", ThermalSpec),
                          ("numerics", Numerics), ("output", OutputSpec)):
            if not isinstance(getattr(self, name), cls):
                raise fail(name, f"{getattr(self, name)!r} is not a {cls.__name__}")
        for sec, spec in (("wear.pad", self.pad_wear), ("wear.rotor", self.rotor_wear)):
            if spec is None and sec == "wear.rotor":
                continue
            if not isinstance(spec, WearSpec):
                raise fail(sec, f"{spec!r} is not a WearSpec")
            spec.check(sec)
        self._check_order()
        self._check_interface()
        self._check_gap_file()
        self._check_consistency()
        self._check_laws()
        check_bounds(self)
        nodes = self._check_mesh_files()
        # last: the model must fit the memory (no meshing: an estimate from the geometry)
        from ..caliper.loads import resolve_layout
        from ..mesh.estimate import check_model_size
        check_model_size(self.meshed_geometry, self.mesh_size, self.rotor, self.piston,
                         nodes=nodes,
                         full=resolve_layout(self.geometry, self.layout, self.rotor) == "full",
                         key="mesh.size" if self.mesh_size is not None else
                         f"mesh.size of the geometry {self.geometry.source}",
                         unit=user_unit("mesh.size") or ("m" if self.mesh_size else "mm"),
                         user_value=shown_value("mesh.size", self.mesh_size, "m")
                         if user_unit("mesh.size") else None,
                         budget_gb=self.numerics.memory_budget)
        check = getattr(self.interface.entry, "check_scene", None)
        if check is not None:                   # the interface model's own (its size)
            check(self)

    # ------------------------------------------------------------ checks --
    @property
    def meshed_geometry(self) -> BrakeGeometry:
        """The geometry with the scene's per-body mesh keys (``resolution``) set."""
        g = self.geometry
        return replace(g, mesh=replace(g.mesh, **self.resolution)) if self.resolution else g

    def _check_order(self) -> None:
        """Quadratic (P2) meshes run FE contact or its condensation, with either
        wear update; the elastic foundation is refused by name."""
        order = self.geometry.mesh.order if self.order is None else self.order
        if order == 2 and self.numerics.update == "geometry" and self.thermal.enabled:
            raise fail("numerics.update", "update = 'geometry' and thermal.enabled = true "
                                          "with mesh.order = 2 is not supported (the "
                                          "thermal model of a P2 mesh does not move); use "
                                          "numerics.update = 'gap', or mesh.order = 1")
        if order == 2 and not self._can("quadratic"):
            why = lacks(self.interface.entry, "quadratic")
            raise fail("interface.model", f"interface.model = {self.interface.model!r} with "
                                          "mesh.order = 2 is not supported (quadratic meshes: "
                                          f"{why}); use interface.model = "
                                          f"{_models('quadratic')}, or mesh.order = 1")

    def _can(self, capability: str) -> bool:
        """Whether the scene's interface model has ``capability`` (its class declares it)."""
        return capability in capabilities_of(self.interface.entry)

    def _check_resolution(self) -> None:
        """Check the per-body mesh keys (names, types, ranges)."""
        if not isinstance(self.resolution, Mapping):
            raise fail("mesh", f"resolution = {self.resolution!r}; expected key -> value")
        res = dict(self.resolution)
        object.__setattr__(self, "resolution", res)
        pad = self.geometry.pad
        half_width = 0.5 * (pad.outer_radius - pad.inner_radius)
        for key, v in res.items():
            if key not in MESH_BODY_KEYS:
                raise fail(f"mesh.{key}", f"unknown key {key!r}; allowed per-body mesh keys: "
                                          f"{', '.join(MESH_BODY_KEYS)}")
            if key.endswith("_size"):
                check_number(f"mesh.{key}", v, 0.0, half_width, unit="m")
            elif isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= MAX_LAYERS:
                raise fail(f"mesh.{key}", f"{v!r} is not allowed; allowed: a whole number "
                                              f"of element layers in [1, {MAX_LAYERS}]")

    def _check_mesh_files(self) -> dict[str, int]:
        """Read the user's mesh files (groups checked); their node counts."""
        from ..errors import MeshFileError
        from ..mesh.io import read_body_mesh
        if not isinstance(self.mesh_files, Mapping):
            raise fail("mesh", f"mesh_files = {self.mesh_files!r}; expected body -> file")
        object.__setattr__(self, "mesh_files", {b: str(f) for b, f in self.mesh_files.items()})
        meshed = {"pad", "rotor"} if self.rotor == "elastic" else {"pad"}
        if self.piston == "body":
            meshed.add("piston")
        nodes = {}
        for body, path in self.mesh_files.items():
            if body not in meshed:
                raise fail(f"mesh.{body}_file", f"{path!r}: the {body} is not a meshed body of "
                                                 f"this scene; meshed: {', '.join(sorted(meshed))}")
            try:
                nodes[body] = read_body_mesh(path, body, self.piston).nvertices
            except MeshFileError as exc:
                raise fail(f"mesh.{body}_file", str(exc)) from None
        return nodes

    def _bodies(self) -> dict[str, str]:
        return {"rotor": self.rotor, "pad": "elastic", "piston": self.piston}

    def _check_interface(self) -> None:
        bodies = self._bodies()
        for s in self.interface.surfaces:
            body, _, surf = s.partition(".")
            if body not in SURFACES:
                raise fail("interface.surfaces", f"{s!r} names no body of the scene; "
                                                  f"bodies: {', '.join(SURFACES)} "
                                                  "(write \"body.surface\")")
            if body == "piston" and bodies["piston"] != "body":
                raise fail("interface.surfaces", f"{s!r}: the piston is not a body of this "
                                                  "scene (components.piston = 'traction')")
            if surf not in SURFACES[body]:
                raise fail("interface.surfaces", f"{s!r}: the {body} has no surface {surf!r}; "
                                                  f"{body} surfaces: "
                                                  f"{', '.join(SURFACES[body])}")
        if self.interface.per_face:
            from ..caliper.loads import resolve_layout
            if resolve_layout(self.geometry, self.layout, self.rotor) == "half":
                raise fail("interface.coning", "a table per face needs both faces: "
                                               "components.layout = 'full' (the half model "
                                               "has the inboard face only; give a number, "
                                               "that face's coning)")
        if tuple(sorted(self.interface.surfaces)) != _WEAR_INTERFACE:
            raise fail("interface.surfaces",
                        f"{list(self.interface.surfaces)!r}: the wear loop's sliding interface is "
                        f"{' against '.join(_WEAR_INTERFACE)}; allowed: "
                        f"{list(_WEAR_INTERFACE)!r}")

    def _check_consistency(self) -> None:
        n = self.numerics
        for surface, law in zip(("pad", "rotor"), self.wear_laws()):
            why = None if law is None else n.refuses_law(surface, law.a)
            if why:
                raise fail(f"wear.{surface}.a", f"{law.a!r} is not allowed: {why}")
        for cap, key, asked, what in (
                ("follows_geometry", "numerics.update", n.update == "geometry",
                 "'geometry' moves the FE meshes; it"),
                ("accepts_load", "thermal.enabled", self.thermal.enabled, "true"),
                ("implicit_rings", "numerics.scheme", n.scheme == "implicit"
                 and self.rotor_wear is not None, "'implicit' (the rotor's rings worn with "
                 "the pad's end pressure; 'implicit_pad': explicit rings)")):
            if asked and not self._can(cap):
                raise fail(key, f"{what} needs interface.model = {_models(cap)}: "
                                f"{lacks(self.interface.entry, cap)}")
        self._check_duty()
        if self.thermal.convection != "constant" and self.rotor != "elastic":
            raise fail("thermal.convection", f"{self.thermal.convection!r} is the convection "
                                             "of a meshed rotor; it needs components.rotor = "
                                             "'elastic'")
        hc = self.thermal.contact_conductance
        if (self.thermal.rough or (hc or 0.0) > 0) and self.rotor != "elastic":
            raise fail("thermal.contact_conductance", f"{hc!r} (> 0) needs an elastic rotor "
                                                       "(components.rotor = 'elastic')")
        if self.thermal.rough and self.schedule:
            raise fail("thermal.contact_conductance", "\"rough\" is evaluated at one nominal "
                                                       "pressure; a [schedule] changes it per "
                                                       "application: give a number (W/m^2 K)")

    def _check_gap_file(self) -> None:
        from ..cleaning.corrosion import read_gap_map
        from ..errors import InputError
        f = self.interface.gap_file
        if f is None:
            return
        if not isinstance(f, (str, PathLike)):
            raise fail("interface.gap_file", f"{f!r} is not a file name")
        try:
            object.__setattr__(self, "_gap_points", read_gap_map(f))
        except InputError as exc:
            raise fail("interface.gap_file", str(exc)) from None

    def _check_duty(self) -> None:
        from ..duty import Vehicle, application_kinds, check_schedule, is_application
        if not self.schedule:
            if self.vehicle is not None:
                raise fail("vehicle", "a [vehicle] is used by a [schedule] of stops; add one or "
                                      "remove the vehicle")
            return
        object.__setattr__(self, "schedule", tuple(self.schedule))
        if self.vehicle is not None and not isinstance(self.vehicle, Vehicle):
            raise fail("vehicle", f"{self.vehicle!r} is not a brakewear.duty.Vehicle")
        if self.numerics.update != "gap":
            raise fail("numerics.update", "a [schedule] runs in gap-offset mode, which "
                                           "carries the wear from one application to the "
                                           "next; allowed: 'gap'")
        if not self._can("any_line_pressure"):
            why = lacks(self.interface.entry, "any_line_pressure")
            allowed = ", ".join(map(repr, allowed_for("any_line_pressure")))
            raise fail("interface.model", "a [schedule] needs an interface that solves at "
                                           "each application's line pressure (its torque "
                                           f"equation uses the contact's pressure field; {why}); "
                                           f"allowed: {allowed}")
        for i, a in enumerate(self.schedule):
            if not is_application(a):
                raise fail("schedule", f"application {i}: {a!r} is not an application; "
                                       f"registered kinds: {', '.join(application_kinds())}")
        if any(a.needs_vehicle for a in self.schedule) and self.vehicle is None:
            raise fail("vehicle", "missing: the [schedule]'s stops need a [vehicle] table "
                                  "(mass, front_share, tyre_radius, ...)")
        for i, a in enumerate(self.schedule):
            a.check_scene(self.vehicle, i)
        if self.interface.mu <= 0:
            raise fail("interface.mu", f"{self.interface.mu!r}: a [schedule] turns brake "
                                        "torque into line pressure through mu; need mu > 0")
        check_schedule(self.schedule, self.vehicle, mu=self.interface.mu,
                       geometry=self.geometry)

    # -------------------------------------------------------------- build --
    def build_model(self):
        """The :class:`~brakewear.model.BrakeModel` of the scene (this meshes)."""
        from ..model import BrakeModel
        return BrakeModel(self.meshed_geometry, piston=self.piston, size=self.mesh_size,
                          order=self.order, rotor=self.rotor, meshes=dict(self.mesh_files),
                          memory_budget=self.numerics.memory_budget, layout=self.layout)

    def build_run(self, model=None, checkpoint=None):
        """The :class:`~brakewear.wear.Run` of the scene (:func:`brakewear.scene.build_run`;
        this meshes unless ``model`` is given; ``checkpoint``: of a run being resumed)."""
        from .build import build_run
        return build_run(self, model, checkpoint)

    def initial_gap(self, x):
        """The initial gap (m) at pad friction nodes at ``x`` (3, n; m) from the
        interface's coning and pad taper on each face
        (:func:`~brakewear.cleaning.corrosion.nonconformity_gap`) and its gap map; None if
        there is none."""
        from ..cleaning.corrosion import map_gap, nonconformity_gap
        itf = self.interface
        if not itf.nonconforming:
            return None
        geo = self.geometry
        g = nonconformity_gap(x, geo.pad.inner_radius, geo.pad.outer_radius,
                              geo.rotor.thickness, itf.face_coning(), itf.pad_taper)
        if itf.gap_file is not None:
            g = g + map_gap(self._gap_points, x,
                            f"{self.source}: interface.gap_file = {itf.gap_file!r}")
        return g

    @property
    def gap_points(self):
        """The points ``(n, 3)`` (r, theta, gap; m, rad, m) of ``interface.gap_file``, read
        when the scene was made; None without a gap map."""
        return getattr(self, "_gap_points", None)

    def friction(self):
        """The friction of the interface: ``interface.mu``, or the map of
        ``interface.mu_map`` (a :class:`~brakewear.laws.maps.FrictionMap`, read once)."""
        itf = self.interface
        if itf.mu_map is None:
            return itf.mu
        if getattr(self, "_friction_map", None) is None:
            from .tables import read_law
            object.__setattr__(self, "_friction_map",
                               read_law("interface.mu_map", itf.mu_map, "mu", itf.map_outside))
        return self._friction_map

    def build_mu(self) -> float:
        """The friction coefficient an interface is built with (a map's values are set
        per node before the first solve; any mu > 0 builds the sliding directions)."""
        return self.interface.mu if self.interface.mu_map is None else 1.0

    def _check_laws(self) -> None:
        """Read the laws (maps included) and refuse the combinations they cannot run in."""
        laws = {"interface.mu_map": self.friction(), "wear.pad.k_map": self.wear_laws()[0],
                "wear.rotor.k_map": self.wear_laws()[1]}
        for key, law in laws.items():
            if getattr(law, "needs_temperature", False) and hasattr(law, "table") \
                    and not self.thermal.enabled:
                raise fail(key, "the map varies with temperature (a T column); it needs "
                                "thermal.enabled = true, or a map without a T column")
        if self.interface.mu_map is not None:
            if not self._can("per_node_friction"):
                why = lacks(self.interface.entry, "per_node_friction")
                raise fail("interface.mu_map", "a friction map per node needs interface.model "
                                               f"= {_models('per_node_friction')} ({why})")
            if self.schedule:
                raise fail("interface.mu_map", "a [schedule] turns torque into line pressure "
                                               "through one mu; give interface.mu instead")

    def wear_laws(self):
        """(pad law, rotor law or None)."""
        g = self.geometry
        pad = self.pad_wear.law(g.pad.friction_material, "wear.pad", g.source)
        rot = None if self.rotor_wear is None else self.rotor_wear.law(g.rotor.material,
                                                                        "wear.rotor", g.source)
        return pad, rot

    def to_dict(self) -> dict:
        """A JSON-ready record of the scene in SI units (written to ``scene.json``)."""
        d = {f.name: getattr(self, f.name) for f in fields(self)
             if f.name not in ("geometry", "vehicle", "schedule", "user_units")}
        if self.schedule:
            d["vehicle"] = None if self.vehicle is None else {
                k: v for k, v in asdict(self.vehicle).items() if k != "source"}
            d["schedule"] = [{"kind": a.name,
                              **{k: v for k, v in asdict(a).items() if k != "source"}}
                             for a in self.schedule]
        for k in ("interface", "pad_wear", "rotor_wear", "thermal", "numerics", "output"):
            d[k] = None if d[k] is None else asdict(d[k])
        d["interface"]["surfaces"] = list(d["interface"]["surfaces"])
        for k in ("mesh_files", "resolution"):
            if not d[k]:
                del d[k]
        g = self.geometry
        d["geometry"] = {"source": str(g.source), "rotor": _geom_record(g.rotor),
                         "pad": _geom_record(g.pad), "piston": _geom_record(g.piston),
                         "mesh": asdict(g.mesh), "caliper": asdict(g.caliper),
                         "support": asdict(g.support),
                         "extra_pistons": [_geom_record(p) for p in g.extra_pistons]}
        return json.loads(json.dumps(d, default=str))


def _models(capability: str) -> str:
    """The registered interface models with ``capability``: ``'fe' or 'condensed'``."""
    return " or ".join(map(repr, allowed_for(capability))) or "(none registered)"


def _geom_record(obj) -> dict:
    return {k: (v.name if hasattr(v, "elastic") else v) for k, v in vars(obj).items()}


def first_difference(a: Any, b: Any, path: str = "") -> str | None:
    """The first key where two JSON records differ (None if equal)."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k in ("name", "description", "source"):
                continue
            d = first_difference(a.get(k), b.get(k), f"{path}.{k}" if path else k)
            if d is not None:
                return d
        return None
    if isinstance(a, float) and isinstance(b, float) and math.isclose(a, b, rel_tol=1e-12):
        return None
    if a == b:
        return None
    top, _, rest = path.partition(".")
    key = _RECORD_KEYS.get(top, top) + (f".{rest}" if rest else "")
    a, b = ((shown_value(key, v, "") if user_scale(key) and isinstance(v, (int, float))
             else repr(v)) for v in (a, b))
    return f"{key}: {a} then, {b} now"


# Scene field -> scene-file key, for messages about scene.json records
_RECORD_KEYS = {"duration": "environment.duration", "line_pressure": "environment.line_pressure",
                "omega": "environment.omega", "ambient": "environment.ambient",
                "rotor": "components.rotor", "piston": "components.piston",
                "layout": "components.layout",
                "mesh_size": "mesh.size", "order": "mesh.order", "mesh_files": "mesh",
                "resolution": "mesh", "pad_wear": "wear.pad", "rotor_wear": "wear.rotor",
                "geometry": "geometry"}
