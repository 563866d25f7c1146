"""The tables of a scene: units, named surfaces, interface, wear laws, thermal
coupling and output (frozen dataclasses that check their values on construction
and raise :class:`~brakewear.errors.SceneError` naming the key)."""
from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import MISSING, dataclass, field, fields
from typing import Any

from ..checks import check_bool, check_choice, check_int, check_number, check_plausible, fail
from ..interfaces.registry import interface_model, model_options

logger = logging.getLogger(__name__)

__all__ = ["InterfaceSpec", "WearSpec", "ThermalSpec", "OutputSpec", "SURFACES", "UNITS",
           "MAX_NONCONFORMITY", "FACES", "scene_keys"]


#: Units a scene file may state, per quantity: name -> factor to SI (temperatures: offset).
UNITS: dict[str, dict[str, float]] = {
    "length": {"mm": 1e-3, "m": 1.0},
    "pressure": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "bar": 1e5},
    "time": {"s": 1.0, "min": 60.0, "h": 3600.0},
    "angular_speed": {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0},
    "temperature": {"K": 0.0, "C": 273.15},   # offsets: T_K = T + offset
}


#: The named surfaces (facet sets) of each body of a :class:`~brakewear.model.BrakeModel`
#: (brakewear.mesh.pad_mesh, rotor_mesh, piston_mesh); tests compare them with the meshes.
SURFACES: dict[str, tuple[str, ...]] = {
    "pad": ("friction", "back", "piston_face", "leading", "trailing", "abutment", "inner",
            "outer", "abutment_leading", "abutment_trailing", "leading_chamfer",
            "trailing_chamfer", "slot"),
    "rotor": ("friction", "midplane", "rotor_clamp", "outer"),
    "piston": ("piston_face", "piston_back", "piston_side"),
}


#: Largest rotor coning or pad taper a scene accepts (m, either sign).
MAX_NONCONFORMITY = 1e-3

#: The friction faces a per-face value names: the inboard face (the pistons' side, z = 0)
#: and the outboard face (z = -thickness; the full model only).
FACES = ("inboard", "outboard")

# the one sliding interface the wear loop integrates
_WEAR_INTERFACE = ("pad.friction", "rotor.friction")


def _key(kind: str, default: Any = MISSING, *, law: bool = False, **kw: Any) -> Any:
    """A field of a table's dataclass that is a key of the scene file: ``kind`` is how
    the reader reads it (:mod:`brakewear.scene.reader`); ``law``: a key of the built-in
    wear law, which a registered one does not take.  The one place a built-in key of
    ``[interface]`` or ``[wear.*]`` is declared."""
    return field(default=default, metadata={"kind": kind, "law": law}, **kw)


def scene_keys(spec: type, law: bool | None = None) -> dict[str, str]:
    """The keys of a table's dataclass as a scene file gives them.

    Parameters
    ----------
    spec
        :class:`InterfaceSpec` or :class:`WearSpec`.
    law
        True: only the built-in wear law's keys; False: only the others;
        None: all.

    Returns
    -------
    dict
        Key -> how the scene reader reads it, in the order of the fields.
    """
    return {f.name: f.metadata["kind"] for f in fields(spec) if "kind" in f.metadata
            and (law is None or f.metadata["law"] == law)}


def read_law(key: str, path: str, quantity: str, outside: str):
    """The friction (``quantity = "mu"``) or wear (``"k"``) law of a map file; a bad
    file is refused naming ``key`` and the file's row and column."""
    from ..errors import InputError
    from ..laws.maps import FrictionMap, WearMap, read_map
    try:
        table = read_map(path, quantity, outside)
    except (InputError, OSError) as exc:
        raise fail(key, str(exc)) from None
    return FrictionMap(table) if quantity == "mu" else WearMap(table)


@dataclass(frozen=True)
class InterfaceSpec:
    """The pad-rotor interface.

    Parameters
    ----------
    model
        A registered interface model
        (:func:`brakewear.interfaces.interface_models`): ``"auto"`` (default):
        the condensed interface where the run's expected steps pay for its
        condensation, FE otherwise (:func:`brakewear.interfaces.auto.choose_interface`;
        the same answer either way); ``"fe"``: node-to-surface FE contact;
        ``"winkler"``: an elastic foundation
        (:class:`brakewear.interfaces.WinklerInterface`); ``"condensed"``: the
        FE contact condensed onto the contact nodes
        (:class:`brakewear.interfaces.CondensedInterface`: the FE answer,
        gap-offset wear only); or one registered from outside
        (:func:`brakewear.interfaces.register_interface`).
    surfaces
        The two surfaces it joins, ``"body.surface"`` (see :data:`SURFACES`).
    mu
        Sliding friction coefficient (>= 0).
    options
        The model's own keys (each model declares and checks them, and
        fills in their defaults): ``method`` (FE contact discretisation,
        ``"segment"``; FE and condensed); ``winkler_modulus`` (Pa/m; None:
        Johnson's layer modulus of the friction layer) and ``winkler_rotor``
        (``"rigid"`` or ``"foundation"``: the rotor's half thickness in
        series) of the foundation.  In a scene file they are keys of the
        ``[interface]`` table.
    coning, pad_taper
        The initial non-conformity (m), each the gap it opens across the pad's
        radial extent, linear in radius (:func:`brakewear.cleaning.corrosion.nonconformity_gap`).
        On a face, positive opens the gap at the outer radius, negative at the
        inner.  ``coning`` a number ``c``: a coned rotor, whose dishing opens the
        gap at the outer radius on one face and at the inner radius on the
        other -- ``c`` on the inboard face and ``-c`` on the outboard face
        (``c > 0``: the rim dished toward the outboard side).  ``coning`` a
        table ``{inboard = a, outboard = b}`` (or a pair ``(a, b)``): each face's
        own value (full model only).  ``pad_taper``: the same radial taper on
        every pad.  Coning and taper add on each face (:meth:`Scene.initial_gap`).
    gap_file
        An initial-gap map, a CSV with columns ``r_mm``, ``theta_deg``,
        ``gap_um`` (:func:`brakewear.cleaning.corrosion.read_gap_map`), added to the
        coning and taper on every face at the node's (r, theta) (a tangential
        taper is given this way); read and checked when the scene is made.
    mu_map, map_outside
        A friction map ``mu(p, v, T)`` (CSV, :func:`brakewear.laws.maps.read_map`)
        used at each pad node instead of ``mu``; outside its grid ``"clamp"``
        (default) or ``"error"``.  Read and checked when the scene is made.
    """

    model: str = _key("str", "auto")
    surfaces: tuple[str, str] = _key("surfaces", _WEAR_INTERFACE)
    mu: float = _key("num", 0.0)
    options: Mapping[str, Any] = field(default_factory=dict)
    coning: float | Mapping[str, float] = _key("face_length", 0.0)
    pad_taper: float = _key("signed_length", 0.0)
    gap_file: str | None = _key("path", None)
    mu_map: str | None = _key("path", None)
    map_outside: str = _key("str", "clamp")

    def __post_init__(self):
        entry = interface_model(self.model)
        check_choice("interface.map_outside", self.map_outside, ("clamp", "error"))
        if (not isinstance(self.surfaces, (tuple, list)) or len(self.surfaces) != 2
                or not all(isinstance(s, str) for s in self.surfaces)):
            raise fail("interface.surfaces", f"{self.surfaces!r} is not allowed; expected two "
                                              "names \"body.surface\", e.g. "
                                              "[\"pad.friction\", \"rotor.friction\"]")
        object.__setattr__(self, "surfaces", tuple(self.surfaces))
        check_number("interface.mu", self.mu, 0.0, lo_open=False)
        check_plausible("interface.mu", self.mu)
        object.__setattr__(self, "coning", _face_lengths("interface.coning", self.coning))
        _check_nonconformity("interface.pad_taper", self.pad_taper)
        if not isinstance(self.options, Mapping):
            raise fail("interface", f"options = {self.options!r}; expected key -> value")
        object.__setattr__(self, "options", model_options(entry, self.options))

    @property
    def entry(self):
        """The registered interface model's class (:func:`~brakewear.interfaces.interface_model`
        of :attr:`model`)."""
        return interface_model(self.model)

    @property
    def per_face(self) -> bool:
        """Whether ``coning`` gives each face its own value (a table)."""
        return isinstance(self.coning, Mapping)

    def face_coning(self) -> dict[str, float]:
        """The coning on each face (m), in that face's own sense (positive opens
        the gap at the outer radius): a number ``c`` is ``c`` inboard, ``-c`` outboard."""
        if self.per_face:
            return dict(self.coning)
        return {"inboard": self.coning, "outboard": -self.coning}

    @property
    def nonconforming(self) -> bool:
        """Whether the faces start with an initial gap (coning, taper or a gap map)."""
        return (any(self.face_coning().values()) or self.pad_taper != 0.0
                or self.gap_file is not None)


def _check_nonconformity(key: str, value) -> None:
    # tens of um in service; a millimetre is a pad that bears on one edge
    check_number(key, value, -MAX_NONCONFORMITY, MAX_NONCONFORMITY, lo_open=False, unit="m")


def _face_lengths(key: str, value):
    """A checked signed length, or a dict face -> signed length of a table or pair."""
    if isinstance(value, (tuple, list)):
        if len(value) != len(FACES):
            raise fail(key, f"{value!r} is not allowed; expected a number or a pair "
                            "(inboard, outboard)")
        value = dict(zip(FACES, value))
    if not isinstance(value, Mapping):
        _check_nonconformity(key, value)
        return value
    unknown = sorted(set(value) - set(FACES))
    missing = [f for f in FACES if f not in value]
    if unknown or missing:
        what = (f"unknown key(s) {', '.join(map(repr, unknown))}" if unknown else
                f"missing key(s) {', '.join(map(repr, missing))}")
        raise fail(key, f"{what}; a table per face needs exactly the keys "
                        f"{', '.join(FACES)} (a length each, in the file's length unit)")
    for f in FACES:
        _check_nonconformity(f"{key}.{f}", value[f])
    return {f: value[f] for f in FACES}


@dataclass(frozen=True)
class WearSpec:
    """A wear law ``dh/dt = k(T) p^a v^b`` (see :class:`brakewear.laws.base.WearLaw`).

    ``k = None`` takes the material's ``wear_k`` (pad: the friction
    material, rotor: the rotor material).  ``k`` is in SI units
    (1/Pa = m^2/N for a = b = 1; in general m/s per Pa^a (m/s)^b).
    ``limit`` (m) is the wear depth at which the run ends
    (:mod:`brakewear.wear.limits`; None: the friction layer's thickness for
    the pad, :data:`~brakewear.wear.limits.ROTOR_LIMIT` for the rotor).
    ``k_map`` is a measured map of the specific wear rate ``k(p, v, T)``
    (CSV, :func:`brakewear.laws.maps.read_map`; Archard: ``a = b = 1``) used
    instead of ``k`` and its temperature law; ``map_outside`` is ``"clamp"``
    or ``"error"`` outside its grid.  ``model`` names a registered wear law
    (:func:`brakewear.laws.base.register_wear_law`) instead: it is built from its
    own keys, ``options`` (in a scene file, keys of the same table), and the
    surface's material, and takes none of the keys above but ``limit``.
    """

    k: float | None = _key("k", None, law=True)
    a: float = _key("num", 1.0, law=True)
    b: float = _key("num", 1.0, law=True)
    T_threshold: float = _key("temperature", 503.15, law=True)
    activation_energy: float = _key("num", 0.0, law=True)
    limit: float | None = _key("length", None)
    k_map: str | None = _key("path", None, law=True)
    map_outside: str = _key("str", "clamp", law=True)
    model: str | None = _key("str", None)
    options: Mapping[str, Any] = field(default_factory=dict)

    def check(self, sec: str) -> None:
        if self.model is not None:
            self._check_registered(sec)
            return
        if self.options:
            raise fail(f"{sec}.{next(iter(self.options))}", "is a key of a registered wear "
                                                             f"law; name the law ({sec}.model)")
        check_choice(f"{sec}.map_outside", self.map_outside, ("clamp", "error"))
        if self.k_map is not None and (self.k is not None or self.a != 1.0 or self.b != 1.0
                                       or self.activation_energy != 0.0):
            raise fail(f"{sec}.k_map", "a wear map gives k(p, v, T) of the Archard law: it "
                                       "cannot be combined with k, a, b or activation_energy")
        check_number(f"{sec}.k", self.k, 0.0, unit="1/Pa", allow_none=True)
        check_number(f"{sec}.a", self.a, 0.0)
        check_number(f"{sec}.b", self.b, 0.0)
        check_number(f"{sec}.T_threshold", self.T_threshold, 0.0, unit="K")
        check_number(f"{sec}.activation_energy", self.activation_energy, 0.0, lo_open=False,
                      unit="J/mol")
        check_number(f"{sec}.limit", self.limit, 0.0, unit="m", allow_none=True)
        check_plausible(f"{sec}.T_threshold", self.T_threshold, "T_threshold")

    def _check_registered(self, sec: str) -> None:
        """A registered law: its own keys checked, none of the built-in law's given."""
        from ..laws.base import wear_law_model, wear_law_options
        entry = wear_law_model(self.model, f"{sec}.model")
        law = scene_keys(WearSpec, law=True)
        builtin = {f.name: f.default for f in fields(self) if f.name in law}
        own = ", ".join(k.name for k in getattr(entry, "keys", ())) or "none"
        for key, default in builtin.items():
            if getattr(self, key) != default:
                raise fail(f"{sec}.{key}", f"{getattr(self, key)!r} is not allowed with "
                                           f"{sec}.model = {self.model!r} (it builds itself "
                                           f"from its own keys: {own})")
        check_number(f"{sec}.limit", self.limit, 0.0, unit="m", allow_none=True)
        if not isinstance(self.options, Mapping):
            raise fail(sec, f"options = {self.options!r}; expected key -> value")
        object.__setattr__(self, "options", wear_law_options(entry, self.options, sec))

    def law(self, material, sec: str, geometry_source: str = "<python>"):
        """The :class:`~brakewear.laws.base.WearLaw` (``material`` supplies a missing k), the
        :class:`~brakewear.laws.maps.WearMap` of ``k_map``, or the registered ``model``."""
        from ..laws.base import WearLaw, wear_law_model
        if self.model is not None:
            return wear_law_model(self.model, f"{sec}.model").build(self.options, material)
        if self.k_map is not None:
            return read_law(f"{sec}.k_map", self.k_map, "k", self.map_outside)
        k = self.k
        if k is None:
            k = material.wear_k
            if k is None or k <= 0:
                has = "has no wear_k" if k is None else f"has wear_k = {k!r} (it would not wear)"
                raise fail(f"{sec}.k", f"\"material\" takes the wear coefficient of material "
                                        f"{material.name!r} (materials.{material.name} of "
                                        f"the geometry {geometry_source}), which {has}; give "
                                        "k > 0 (1/Pa) here or wear_k > 0 in the material")
        return WearLaw(k, self.a, self.b, self.T_threshold, self.activation_energy)


@dataclass(frozen=True)
class ThermalSpec:
    """Thermal coupling (:class:`brakewear.thermal.ThermalModel` arguments, SI).

    ``T_ambient`` is the scene's ``environment.ambient``; ``T_max`` (K) the
    plausibility bound of face temperatures (None: 900 C).  ``partition =
    "auto"`` and ``contact_conductance = None`` (the defaults) resolve by the
    rotor: a meshed rotor gets the effusivity share and a contact conductance
    of 1e5 W/m^2 K, a rigid one the area-weighted effusivity share and none
    (:class:`~brakewear.thermal.ThermalModel`).  ``convection = "solid"`` or
    ``"vented"`` makes the rotor's coefficient follow its speed
    (:meth:`brakewear.thermal.SpeedConvection.solid`, ``.vented``; the pad keeps
    ``h_conv``); ``emissivity`` adds radiation from the convective faces.

    ``contact_conductance = "rough"`` derives the conductance from the faces'
    roughness (:class:`brakewear.rough.RoughConductance`): ``pad_rms_height``
    and ``rotor_rms_height`` (m), with ``conductance_law = "halfspace"``
    (None, the default: the law fitted to the half-space solves) or ``"mikic"`` (which
    also needs ``pad_rms_slope`` and ``rotor_rms_slope``, the areal rms
    slopes Sdq), evaluated at the nominal pressure, the clamp force over the
    pad's friction face (:meth:`conductance`).  Not with a [schedule], whose
    pressure changes from application to application.
    """

    enabled: bool = False
    partition: str | float = "auto"
    h_conv: float | Mapping[str, float] = 40.0
    T_initial: float | None = None
    T_ref: float | None = None
    contact_conductance: float | None = None
    mass: str = "consistent"
    T_max: float | None = None
    convection: str = "constant"
    emissivity: float | None = None
    pad_rms_height: float | None = None
    pad_rms_slope: float | None = None
    rotor_rms_height: float | None = None
    rotor_rms_slope: float | None = None
    conductance_law: str | None = None

    def __post_init__(self):
        check_bool("thermal.enabled", self.enabled)
        if isinstance(self.partition, str):
            check_choice("thermal.partition", self.partition,
                         ("auto", "effusivity", "effusivity_area"))
        else:
            check_number("thermal.partition", self.partition, 0.0, 1.0, lo_open=False)
        if isinstance(self.h_conv, Mapping):
            unknown = sorted(set(self.h_conv) - {"pad", "rotor"})
            if unknown:
                raise fail(f"thermal.h_conv.{unknown[0]}", "unknown body; allowed: pad, rotor")
            for b, h in self.h_conv.items():
                check_number(f"thermal.h_conv.{b}", h, 0.0, lo_open=False, unit="W/m^2 K")
            object.__setattr__(self, "h_conv", dict(self.h_conv))
        else:
            check_number("thermal.h_conv", self.h_conv, 0.0, lo_open=False, unit="W/m^2 K")
        check_number("thermal.T_initial", self.T_initial, 0.0, unit="K", allow_none=True)
        check_number("thermal.T_ref", self.T_ref, 0.0, unit="K", allow_none=True)
        check_plausible("thermal.T_initial", self.T_initial)
        check_plausible("thermal.T_ref", self.T_ref)
        if isinstance(self.contact_conductance, str):
            check_choice("thermal.contact_conductance", self.contact_conductance, ("rough",))
        else:
            check_number("thermal.contact_conductance", self.contact_conductance, 0.0,
                         lo_open=False, unit="W/m^2 K", allow_none=True)
        self._check_roughness()
        check_choice("thermal.mass", self.mass, ("consistent", "lumped"))
        check_number("thermal.T_max", self.T_max, 0.0, unit="K", allow_none=True)
        check_choice("thermal.convection", self.convection, ("constant", "solid", "vented"))
        if self.convection != "constant" and isinstance(self.h_conv, Mapping) \
                and "rotor" in self.h_conv:
            raise fail("thermal.h_conv.rotor", f"is not allowed with thermal.convection = "
                                                f"{self.convection!r}, which sets the rotor's "
                                                "coefficient from its speed")
        check_number("thermal.emissivity", self.emissivity, 0.0, 1.0, lo_open=False,
                     allow_none=True)


    @property
    def rough(self) -> bool:
        """Whether the contact conductance comes from the faces' roughness."""
        return self.contact_conductance == "rough"

    def _check_roughness(self) -> None:
        keys = ("pad_rms_height", "rotor_rms_height", "pad_rms_slope", "rotor_rms_slope")
        # None: "halfspace"; a run's record without these keys reads the same
        if self.conductance_law is not None:
            check_choice("thermal.conductance_law", self.conductance_law,
                         ("halfspace", "mikic"))
        if not self.rough:
            given = [k for k in keys if getattr(self, k) is not None]
            if given or self.conductance_law is not None:
                k = given[0] if given else "conductance_law"
                raise fail(f"thermal.{k}", "is used only with contact_conductance = \"rough\" "
                                           "(the conductance from the faces' roughness)")
            return
        law = self.conductance_law or "halfspace"
        need = keys[:2] + (keys[2:] if law == "mikic" else ())
        for k in need:
            if getattr(self, k) is None:
                raise fail(f"thermal.{k}", f"missing: contact_conductance = \"rough\" with "
                                           f"conductance_law = {law!r} needs "
                                           f"{', '.join(need)}")
        for k in keys[:2]:
            # the rms height of a brake face is microns; a millimetre is a wavy face
            check_number(f"thermal.{k}", getattr(self, k), 0.0, 1e-3, unit="m")
        for k in keys[2:]:
            check_number(f"thermal.{k}", getattr(self, k), 0.0, 2.0, allow_none=True)

    def rough_law(self, geometry):
        """The :class:`~brakewear.rough.RoughConductance` of the pad and rotor faces of
        ``geometry`` (their materials give ``E*`` and the conductivities)."""
        from ..analytic import effective_modulus
        from ..rough.conductance import RoughConductance
        pad, rotor = geometry.pad.friction_material, geometry.rotor.material
        Es = effective_modulus(pad.elastic.E_normal, pad.elastic.nu_normal,
                               rotor.elastic.E_normal, rotor.elastic.nu_normal)
        return RoughConductance.of_faces(
            (self.pad_rms_height, self.pad_rms_slope),
            (self.rotor_rms_height, self.rotor_rms_slope), Es, pad.thermal.kappa,
            rotor.thermal.kappa, self.conductance_law or "halfspace")

    def conductance(self, geometry, line_pressure: float | None) -> float | None:
        """The ``contact_conductance`` argument of :class:`~brakewear.thermal.ThermalModel`:
        the number given, or (``"rough"``) the rough law at the nominal pressure
        ``line_pressure * clamp_area / pad area`` (W/m^2 K)."""
        if not self.rough:
            return self.contact_conductance
        p = line_pressure * geometry.clamp_area / geometry.pad.area
        h = float(self.rough_law(geometry).conductance(p))
        logger.info("contact conductance from the roughness (%s law): %.4g W/m^2 K at the "
                    "nominal pressure %.4g MPa", self.conductance_law or "halfspace", h,
                    p / 1e6)
        return h

    def convection_law(self):
        """The ``h_conv`` argument of :class:`~brakewear.thermal.ThermalModel`: the
        scene's coefficients, the rotor's following its speed unless ``"constant"``."""
        if self.convection == "constant":
            return self.h_conv
        from ..thermal.convection import SpeedConvection
        pad = self.h_conv.get("pad", 40.0) if isinstance(self.h_conv, Mapping) else self.h_conv
        law = SpeedConvection.solid() if self.convection == "solid" else SpeedConvection.vented()
        return {"pad": pad, "rotor": law}


@dataclass(frozen=True)
class OutputSpec:
    """What the run writes: VTU every ``vtu_every`` steps, a checkpoint every
    ``checkpoint_every`` steps, PNG figures at the end."""

    vtu_every: int = 10
    checkpoint_every: int = 10
    figures: bool = True

    def __post_init__(self):
        check_int("output.vtu_every", self.vtu_every, 1)
        check_int("output.checkpoint_every", self.checkpoint_every, 1)
        check_bool("output.figures", self.figures)
