"""The brake's temperatures: pad and rotor heated by friction (:class:`ThermalModel`).

The pad (friction layer and backplate) and the rotor (if elastic) each get a
temperature field (:class:`~brakewear.fem.HeatConduction`); the pad's share
of ``q = mu p v`` enters the pad at its friction nodes, the rotor's share is
spread over whole rings of the rotor's friction face (the revolution average
of :mod:`brakewear.mesh.rings`), free surfaces convect, and the thermal-strain
load enters the elasticity in the :class:`~brakewear.model.BrakeModel`'s
global numbering.  Temperatures are in kelvin; the equations, the partition
formula and the stability of the staggered coupling are in the thermal
explanation page of the docs.
"""
from __future__ import annotations

import inspect
import logging
from collections import OrderedDict
from collections.abc import Mapping, Sequence

import numpy as np
import scipy.sparse as sp

from ..checks import check_order
from ..errors import ThermalError
from ..fem.heat import THERMAL_FIELDS, HeatConduction, body_label, check_thermal
from ..materials import H_CONV_DEFAULT, T_AMBIENT_DEFAULT
from ..mesh.rings import face_rings, rotor_wear_rate
from ..mesh.topology import ensure_topology
from .convection import SpeedConvection, radiation_coefficient, rounded
from .partition import heat_flux, partition_effusivity
from .strain import model_thermal_load, thermal_stress

logger = logging.getLogger(__name__)

__all__ = ["ThermalModel", "T_MAX_DEFAULT", "H_CONTACT_DEFAULT"]

#: Default plausibility bound of face temperatures (K): 900 C.
T_MAX_DEFAULT = 1173.15

#: Default contact conductance between pad and meshed rotor (W/m^2 K): large enough
#: that the pad face follows the rotor ring under it (a sliding interface has one
#: temperature), inside the 1e4 - 1e6 range of pad-disc interface conductances
#: (docs/thermal.md, "A heat partition that cannot run away by default").
H_CONTACT_DEFAULT = 1e5


class ThermalModel:
    """Temperatures of the brake's pad and rotor, driven by frictional heat.

    Parameters
    ----------
    model
        A :class:`brakewear.model.BrakeModel` (of order 2: the temperature is
        a linear field on its vertices,
        :class:`~brakewear.thermal.quadratic.QuadraticThermal`).  The pad
        (friction layer and backplate) always gets a temperature field; the
        rotor only if it is elastic (meshed).  The piston is not heated (its temperature stays at
        ``T_ref``: no thermal strain).
    partition
        ``"auto"`` (default: ``"effusivity"`` with a meshed rotor, whose
        contact conductance then sets the net share; ``"effusivity_area"``
        with a rigid one, where no heat can flow back),
        ``"effusivity"`` (:func:`partition_effusivity`),
        ``"effusivity_area"`` (the revolution-averaged variant) or a number in
        [0, 1]: the share of ``q`` that enters the pad.  The rest enters the
        rotor (with a rigid rotor it leaves the model; reported as
        ``rotor_unmodelled_W`` by :meth:`heat_balance`).
    h_conv
        Convection coefficient (W/m^2 K): one number for all free faces or
        ``{"pad": h, "rotor": h}``; a :class:`~brakewear.thermal.SpeedConvection`
        in place of a number follows the rotor's speed (:meth:`set_speed`).
    T_ambient, T_ref
        Ambient temperature (K) and stress-free reference (default ambient).
    convection_facets
        Free faces per body; default: pad ``back, leading, trailing, inner,
        outer`` (all but the friction face); rotor ``friction, outer,
        rotor_clamp`` (the friction face sheds heat for the part of each
        revolution it is not under the pad, which is 85 % of it for a 55 deg
        pad; the midplane is a symmetry plane: insulated).
    mass
        ``"consistent"`` or ``"lumped"`` capacity matrix.
    T_initial
        Initial temperature (K), default ``T_ambient``.
    contact_conductance
        ``h_c`` (W/m^2 K; None, the default: :data:`H_CONTACT_DEFAULT` with a
        meshed rotor, 0 with a rigid one; 0: off).  Besides its share of ``q``, each
        pad friction node exchanges ``h_c A_i (T_pad,i - T_ring,i)`` with the
        rotor, ``T_ring,i`` the area-weighted mean temperature of the rotor
        rings under it (the revolution average again); the rotor receives
        it spread over those rings.  Solved monolithically in each step
        (through the ring means, a few dense unknowns: see :meth:`_coupled`),
        so a large ``h_c`` drives the pad face toward the rotor's ring
        temperature and the effective partition follows.  Needs an elastic
        (meshed) rotor.
    emissivity
        Radiation from the convective faces: an emissivity in [0, 1] or one per
        body (None: none), linearised about each body's mean face temperature
        at the start of each step (:func:`~brakewear.thermal.radiation_coefficient`).
    T_max
        Plausibility bound of the face temperatures (K, default
        :data:`T_MAX_DEFAULT`, 900 C): a wear step that leaves a pad or
        rotor face hotter ends the run with
        :class:`~brakewear.errors.TemperatureLimitError` (the binder of a
        resin-bonded pad decomposes over about 300-450 C, docs/references.md,
        and the pad fades far below this; a hotter face
        means a heat partition or a duty the model does not describe).
        None: the default.
    """

    PAD_FACETS = ("back", "leading", "trailing", "inner", "outer")

    def __new__(cls, model=None, *args, **kwargs):
        # a model of P2 tetrahedra: the temperature on its vertices (thermal.quadratic)
        if cls is ThermalModel and getattr(model, "order", 1) == 2:
            from .quadratic import QuadraticThermal, linear_twin
            return QuadraticThermal(model, ThermalModel(linear_twin(model), *args, **kwargs))
        return super().__new__(cls)
    ROTOR_FACETS = ("friction", "outer", "rotor_clamp")

    def __init__(self, model, partition: str | float = "auto",
                 h_conv: float | Mapping[str, float] = H_CONV_DEFAULT,
                 T_ambient: float = T_AMBIENT_DEFAULT, T_ref: float | None = None,
                 convection_facets: Mapping[str, Sequence[str]] | None = None,
                 mass: str = "consistent", T_initial: float | None = None,
                 contact_conductance: float | None = None, T_max: float | None = None,
                 emissivity: float | Mapping[str, float] | None = None):
        self.model = model
        self.bodies = tuple(b for b in ("rotor", "pad") if b in model.bodies)
        partition, contact_conductance = _resolve_defaults("rotor" in self.bodies, partition,
                                                           contact_conductance)
        #: the constructor's settings, defaults resolved (a run's checkpoint fingerprints them)
        self.settings = {"partition": partition, "h_conv": h_conv, "T_ambient": T_ambient,
                         "T_ref": T_ref, "convection_facets": convection_facets, "mass": mass,
                         "T_initial": T_initial, "contact_conductance": contact_conductance,
                         "emissivity": emissivity}
        if "pad" not in self.bodies:
            raise ThermalError("the brake model has no pad body")
        # ---- input checks first (nothing is assembled before they pass)
        for b in self.bodies:
            for _, m in model.materials[b]:
                check_thermal(m, body_label(b, m), THERMAL_FIELDS)
        g = model.geometry
        rotor_mat = (self._face_material("rotor") if "rotor" in self.bodies
                     else g.rotor.material)
        if "rotor" not in self.bodies:
            check_thermal(rotor_mat, body_label("rotor", rotor_mat))
        pad_mat = self._face_material("pad")
        gamma = _resolve_partition(partition, pad_mat, rotor_mat, g.pad.arc_angle)
        self.partition = gamma
        hs, self.cooling = _convection(h_conv, emissivity, self.bodies)
        self.h_assembled, self.omega = hs, None
        h_c = contact_conductance
        if not (isinstance(h_c, (int, float, np.floating)) and np.isfinite(h_c) and h_c >= 0):
            raise ThermalError(f"contact_conductance = {h_c!r} W/m^2 K is not allowed; need a "
                               "number >= 0")
        if h_c > 0 and "rotor" not in self.bodies:
            raise ThermalError("contact_conductance > 0 needs an elastic (meshed) rotor; this "
                               f"model's rotor is {model.rotor!r}")
        self.contact_conductance = float(h_c)
        T_max = T_MAX_DEFAULT if T_max is None else T_max
        if not (isinstance(T_max, (int, float, np.floating)) and not isinstance(T_max, bool)
                and np.isfinite(T_max) and T_max > 0):
            raise ThermalError(f"T_max = {T_max!r} K is not allowed; need a temperature > 0 K")
        #: plausibility bound of face temperatures (K); not fingerprinted: it changes no
        #: result, only where a run stops
        self.T_max = float(T_max)
        facets = {"pad": self.PAD_FACETS, "rotor": self.ROTOR_FACETS}
        facets.update(dict(convection_facets or {}))
        self.T_ambient = float(T_ambient)
        _check_start(self.T_max, self.T_ambient, T_initial)
        self.T_ref = self.T_ambient if T_ref is None else float(T_ref)
        if not (np.isfinite(self.T_ref) and self.T_ref > 0):
            raise ThermalError(f"T_ref = {T_ref!r} K is not allowed; need > 0 K")
        # ---- assembly (once)
        self.heat = {b: HeatConduction(model.meshes[b], model.materials[b], "friction",
                                       {f: hs.get(b, H_CONV_DEFAULT) for f in facets[b]},
                                       T_ambient, mass=mass, name=b,
                                       contact_conductance=h_c if b == "pad" else 0.0)
                     for b in self.bodies}
        pad = model.meshes["pad"]
        self.pad_nodes = self.heat["pad"].face
        self.pad_area = self.heat["pad"].face_area
        x = pad.p[:, self.pad_nodes]
        self.pad_radius = np.hypot(x[0], x[1])
        if "rotor" in self.bodies:
            rotor = model.meshes["rotor"]
            face = self.heat["rotor"].face
            pair = model.contact_pair(0.0)
            self.coupling = pair.coupling[:, face + model.offsets["rotor"]].tocsr()
            self.ring, self.ring_radii = face_rings(model, rotor.p[:, face])
            self.rotor_area = self.heat["rotor"].face_area
            if h_c > 0:
                n_ring = int(self.ring.max()) + 1
                E = sp.csr_matrix((np.ones(face.size), (np.arange(face.size), self.ring)),
                                  shape=(face.size, n_ring))
                ring_area = np.bincount(self.ring, weights=self.rotor_area)
                # V: ring means seen by each pad node (rows sum to 1); U: a ring's
                # power spread uniformly over its area (columns sum to 1); the ring
                # mean temperature is U^T T_rotor
                self._V = np.asarray((self.coupling @ E).todense())
                self._U = np.asarray((self.heat["rotor"].S @ E
                                      @ sp.diags(1.0 / ring_area)).todense())
                self._DV = np.zeros((self.heat["pad"].n, n_ring))
                self._DV[self.pad_nodes] = (h_c * self.pad_area)[:, None] * self._V
                self._influence: OrderedDict = OrderedDict()
        self._G: dict[str, sp.csr_matrix] = {}
        T0 = self.T_ambient if T_initial is None else float(T_initial)
        self.T = {b: np.full(self.heat[b].n, T0) for b in self.bodies}
        self.time = 0.0
        self._last: dict | None = None
        logger.info("thermal model: bodies %s, pad share %.4f, %s nodes", self.bodies, gamma,
                    {b: self.heat[b].n for b in self.bodies})

    def _face_material(self, body: str):
        """The material of the elements on the body's friction face (must be one)."""
        mesh = self.model.meshes[body]
        ensure_topology(mesh)
        elems = mesh.f2t[0, mesh.boundaries["friction"]]
        found = [m for e, m in self.model.materials[body] if np.isin(elems, e).any()]
        if len(found) != 1:
            raise ThermalError(f"body {body!r}: the friction face touches {len(found)} materials; "
                               "the heat partition needs exactly one")
        return found[0]

    # ----------------------------------------------------------- fluxes --
    def flux(self, p: np.ndarray, mu, omega: float) -> np.ndarray:
        """``q = mu p omega r`` at the pad's friction nodes (W/m^2)."""
        if not (np.isfinite(omega) and omega >= 0):
            raise ThermalError(f"omega = {omega!r} rad/s is not allowed; need >= 0")
        return heat_flux(p, omega * self.pad_radius, mu)

    def _loads(self, q_pad: np.ndarray) -> tuple[dict, dict]:
        q = np.asarray(q_pad, dtype=float)
        if q.shape != self.pad_nodes.shape:
            raise ThermalError(f"q_pad has shape {q.shape}; need {self.pad_nodes.shape} (one "
                               "value per pad friction node, order of surface_nodes(pad, "
                               "'friction'))")
        if not np.all(np.isfinite(q)) or np.any(q < 0):
            raise ThermalError(f"q_pad must be finite and >= 0 (friction heats); min {q.min()!r}")
        power = float(q @ self.pad_area)
        F = {"pad": self.heat["pad"].flux_load(self.partition * q)}
        figures = {"friction_power_W": power, "rotor_unmodelled_W": 0.0}
        rotor_power = (1.0 - self.partition) * q * self.pad_area
        if "rotor" in self.bodies:
            q_rot = rotor_wear_rate(rotor_power, self.coupling, self.ring, self.rotor_area)
            F["rotor"] = self.heat["rotor"].flux_load(q_rot)
        else:
            figures["rotor_unmodelled_W"] = float(rotor_power.sum())
        return F, figures

    # ----------------------------------------------------------- solves --
    def _solve(self, q_pad: np.ndarray, dt: float | None) -> dict:
        if any(eps > 0 for _, eps in self.cooling.values()):
            self._update_cooling()          # radiation about this step's start
        F, figs = self._loads(q_pad)
        old = self.T
        figs["friction_in"] = {b: float(np.sum(F[b])) for b in self.bodies}
        figs["exchange_W"] = 0.0
        if self.contact_conductance == 0.0:
            self.T = {b: self.heat[b].solve(dt, self.heat[b].rhs(old[b], F[b], dt))
                      for b in self.bodies}
        else:
            self.T, F, figs["exchange_W"] = self._coupled(old, F, dt)
        self._last = {"F": F, "old": old, "dt": dt, **figs}
        return self.T

    def _coupled(self, old: dict, F: dict, dt: float | None):
        """Pad and rotor coupled through the contact conductance, solved exactly.

        The coupling acts only through the ring means ``tau = U^T T_rotor``
        and the ring exchange powers ``g = h_c V^T A (T_pad,face - V tau)``:
        with the influence columns ``Z_p = A_p^-1 (h_c A V)`` and
        ``Z_r = A_r^-1 U`` (cached per ``dt``), the uncoupled solutions plus
        ``Z_p tau`` and ``Z_r g`` solve the monolithic system, and ``tau``
        comes from a dense n_ring x n_ring system.
        """
        pad, rot = self.heat["pad"], self.heat["rotor"]
        key = (None if dt is None else float(dt), pad.h_scale, rot.h_scale)
        if key not in self._influence:
            Zp = pad.solve(dt, self._DV)
            Zr = rot.solve(dt, self._U)
            DVf = self._DV[self.pad_nodes]
            G = DVf.T @ Zp[self.pad_nodes] - DVf.T @ self._V
            self._influence[key] = (Zp, Zr, self._U.T @ Zr, G)
            if len(self._influence) > HeatConduction.cache_size:
                self._influence.popitem(last=False)
        Zp, Zr, R, G = self._influence[key]
        Tp = pad.solve(dt, pad.rhs(old["pad"], F["pad"], dt))
        Tr = rot.solve(dt, rot.rhs(old["rotor"], F["rotor"], dt))
        g0 = self._DV[self.pad_nodes].T @ Tp[self.pad_nodes]
        tau0 = self._U.T @ Tr
        tau = np.linalg.solve(np.eye(R.shape[0]) - R @ G, tau0 + R @ g0)
        g = g0 + G @ tau
        T = {"pad": Tp + Zp @ tau, "rotor": Tr + Zr @ g}
        Ftot = {"pad": F["pad"] + self._DV @ tau, "rotor": F["rotor"] + self._U @ g}
        return T, Ftot, float(g.sum())

    def step(self, q_pad: np.ndarray, dt: float) -> dict:
        """Advance all bodies by one implicit-Euler step ``dt`` (s) under ``q_pad``
        (W/m^2 at the pad's friction nodes); returns the new temperatures."""
        if not (np.isfinite(dt) and dt > 0):
            raise ThermalError(f"dt = {dt!r} s is not allowed; need dt > 0")
        self._solve(q_pad, dt)
        self.time += dt
        return self.T

    def steady(self, q_pad: np.ndarray) -> dict:
        """Steady temperatures under ``q_pad`` (needs convection)."""
        return self._solve(q_pad, None)

    def heat_balance(self) -> dict:
        """Energy figures of the last solve (W).

        ``heat_into_bodies_W`` counts the friction heat only;
        ``exchange_pad_to_rotor_W`` is the net contact-conductance flow
        (the bodies' ``heat_in_W`` include it, their ``to_contact_W`` is
        the pad's gross outflow ``sum h_c A_i T_i``).  ``partition_error``: the
        absolute difference of the heat into the bodies (plus a rigid rotor's
        share) and the friction power, over the friction power (the flux
        mapping, incl. the rotor's revolution average).  ``bodies[b]['relative_error']``: heat
        in vs stored + convected (the solve).  ``relative_error``: the
        largest of them.
        """
        if self._last is None:
            raise ThermalError("heat_balance: no thermal solve yet")
        L = self._last
        bodies = {b: self.heat[b].balance(L["old"][b], self.T[b], L["F"][b], L["dt"])
                  for b in self.bodies}
        into = sum(L["friction_in"].values())
        P = L["friction_power_W"]
        perr = abs(into + L["rotor_unmodelled_W"] - P) / max(P, 1e-300) if P > 0 else 0.0
        return {"friction_power_W": P, "heat_into_bodies_W": into,
                "rotor_unmodelled_W": L["rotor_unmodelled_W"], "partition_error": perr,
                "exchange_pad_to_rotor_W": L["exchange_W"], "bodies": bodies,
                "relative_error": max([perr] + [v["relative_error"] for v in bodies.values()])}

    # ----------------------------------------------------------- state --
    def set_speed(self, omega: float) -> None:
        """The rotor speed (rad/s) of the next steps: the speed-dependent convection
        coefficients (:class:`~brakewear.thermal.SpeedConvection`) follow it."""
        if not (np.isfinite(omega) and omega >= 0):
            raise ThermalError(f"rotor speed {omega!r} rad/s is not allowed; need >= 0")
        self.omega = float(omega)
        self._update_cooling()

    def _update_cooling(self) -> None:
        """Each cooled body's coefficient: convection at the speed (``h_ref`` before
        any :meth:`set_speed`) plus radiation linearised about the mean temperature of
        its convective faces, rounded to 2^(1/8) (:mod:`brakewear.thermal.convection`)."""
        for b, (base, eps) in self.cooling.items():
            h = base if not isinstance(base, SpeedConvection) else (
                base.h_ref if self.omega is None else base.h(self.omega))
            if eps > 0:
                heat = self.heat[b]
                w = np.asarray(heat.H1.sum(axis=1)).ravel()        # convective areas x h
                Ts = float(w @ self.T[b] / w.sum())
                h += radiation_coefficient(eps, Ts, self.T_ambient)
            self.heat[b].set_convection_scale(rounded(h / self.h_assembled[b]))

    def follow(self, model) -> None:
        """Move onto ``model``, the same brake with moved (worn) faces
        (:class:`~brakewear.motion.brake.BrakeMotion`: the same nodes, new
        coordinates): everything assembled again on the moved meshes with the
        same settings, the temperatures carried on the nodes, which move with
        the faces.  In place, so every holder of this model sees the moved one."""
        state, omega = self.state_arrays(), self.omega
        self.__init__(model, T_max=self.T_max, **self.settings)
        self.load_state(state)
        if omega is not None:
            self.set_speed(omega)

    def state_arrays(self) -> dict:
        """The thermal state for a checkpoint: ``T_<body>`` arrays and ``thermal_time``."""
        return {**{f"T_{b}": self.T[b].copy() for b in self.bodies},
                "thermal_time": float(self.time)}

    def load_state(self, arrays: Mapping[str, np.ndarray]) -> None:
        """Restore :meth:`state_arrays` (e.g. from an ``.npz``); checks the sizes."""
        for b in self.bodies:
            key = f"T_{b}"
            if key not in arrays:
                raise ThermalError(f"thermal state: {key!r} is missing; keys: {sorted(arrays)}")
            T = np.asarray(arrays[key], dtype=float)
            if T.shape != (self.heat[b].n,) or not np.all(np.isfinite(T)) or np.any(T <= 0):
                raise ThermalError(f"thermal state: {key!r} has shape {T.shape}; need "
                                   f"({self.heat[b].n},) finite temperatures > 0 K")
            self.T[b] = T.copy()
        self.time = float(np.asarray(arrays.get("thermal_time", 0.0)))
        self._last = None

    # ------------------------------------------------------ temperatures --
    def face_temperature(self, body: str = "pad") -> np.ndarray:
        """Temperature (K) at the friction-face nodes of ``body`` (sorted node order)."""
        if body not in self.bodies:
            raise ThermalError(f"body = {body!r} has no temperature field; thermal bodies: "
                               f"{self.bodies}")
        return self.T[body][self.heat[body].face]

    def rotor_temperature_under_pad(self) -> np.ndarray:
        """Rotor surface temperature seen by each pad friction node (K), for the
        rotor's ``k(T)``; the ambient if the rotor is rigid."""
        if "rotor" not in self.bodies:
            return np.full(self.pad_nodes.size, self.T_ambient)
        return self.coupling @ self.face_temperature("rotor")

    def thermal_load(self, T: Mapping[str, np.ndarray] | None = None) -> np.ndarray:
        """Thermal-strain load (3 * model.n_nodes,) in the model's global numbering.

        ``int eps(v) : C : alpha (T - T_ref) I`` per body (the form of
        :func:`brakewear.fem.thermal_strain_form`); zero on bodies
        without a temperature field.  Add it to the mechanical load:
        ``f = cs.f + cs.P.T @ thermal.thermal_load()`` for a contact system.
        """
        return model_thermal_load(self.model, self.bodies, self.T if T is None else T,
                                  self.T_ref, self._G)

    def stresses(self, u: Mapping[str, np.ndarray]) -> dict:
        """Element stresses ``C (eps - alpha dT I)`` per thermal body (6, n_elements)."""
        return {b: thermal_stress(self.model.meshes[b], u[b], self.model.materials[b],
                                  self.T[b] - self.T_ref, b) for b in self.bodies}


# the constructor's parameters are __init__'s (__new__ only hands a P2 model on)
ThermalModel.__signature__ = inspect.signature(ThermalModel.__init__).replace(  # type: ignore
    parameters=list(inspect.signature(ThermalModel.__init__).parameters.values())[1:])


def _convection(h_conv, emissivity, bodies) -> tuple[dict, dict]:
    """``({body: h assembled}, {body: (convection, emissivity)})`` of the ``h_conv``
    and ``emissivity`` arguments (each a value or one per body): the second holds the
    bodies whose coefficient changes from step to step (a SpeedConvection, radiation)."""
    hs = dict(h_conv) if isinstance(h_conv, Mapping) else {b: h_conv for b in bodies}
    es = dict(emissivity) if isinstance(emissivity, Mapping) else {
        b: emissivity for b in bodies}
    for key, d in (("h_conv", hs), ("emissivity", es)):
        unknown = sorted(set(d) - set(bodies))
        if unknown:
            raise ThermalError(f"{key}: body {unknown[0]!r} is not a thermal body; allowed: "
                               f"{', '.join(bodies)}")
    cooling = {}
    for b in bodies:
        h, eps = hs.get(b, H_CONV_DEFAULT), es.get(b)
        eps = 0.0 if eps is None else eps
        if not (isinstance(eps, (int, float, np.floating)) and 0.0 <= eps <= 1.0):
            raise ThermalError(f"body {b!r}: emissivity = {eps!r} is not allowed; need a "
                               "number in [0, 1] (grey cast iron about 0.4-0.6 when oxidised)")
        if isinstance(h, SpeedConvection):
            cooling[b], hs[b] = (h, float(eps)), h.h_ref
        elif not (isinstance(h, (int, float, np.floating)) and np.isfinite(h) and h >= 0):
            raise ThermalError(f"body {b!r}: h_conv = {h!r} W/m^2 K is not allowed; need a "
                               "number >= 0 or a SpeedConvection")
        elif eps > 0:
            cooling[b] = (float(h), float(eps))
            hs[b] = h if h > 0 else 1.0          # assembled once, then scaled
    return hs, cooling


def _resolve_defaults(meshed: bool, partition, contact_conductance):
    """``partition = "auto"`` and ``contact_conductance = None`` by the rotor: a
    meshed one takes the effusivity share and :data:`H_CONTACT_DEFAULT`, a rigid
    one (no heat can flow back) the area-weighted share and no conductance."""
    if isinstance(partition, str) and partition == "auto":
        partition = "effusivity" if meshed else "effusivity_area"
    if contact_conductance is None:
        contact_conductance = H_CONTACT_DEFAULT if meshed else 0.0
    return partition, contact_conductance


def _check_start(T_max: float, T_ambient: float, T_initial: float | None) -> None:
    """A face may not start beyond its plausibility bound ``T_max``."""
    for key, T in (("T_ambient", T_ambient), ("T_initial", T_initial)):
        if T is not None:
            check_order(key, float(T), "T_max", T_max, "K", kind=ThermalError,
                        why="the plausibility bound of the face temperatures")


def _resolve_partition(partition, pad_mat, rotor_mat, arc_angle: float) -> float:
    """The share of the frictional heat that enters the pad: by the effusivities
    (``"effusivity"``), weighted by the pad's share of the swept ring
    (``"effusivity_area"``), or a number in [0, 1]."""
    if isinstance(partition, str):
        if partition == "effusivity":
            gamma = partition_effusivity(pad_mat, rotor_mat)
        elif partition == "effusivity_area":
            ratio = arc_angle / (2 * np.pi)  # pad area / swept ring area
            gamma = partition_effusivity(pad_mat, rotor_mat, ratio)
        else:
            raise ThermalError(f"partition = {partition!r} is not allowed; allowed: 'auto', "
                               "'effusivity', 'effusivity_area' or a number in [0, 1]")
    else:
        try:
            gamma = float(partition)
        except (TypeError, ValueError):
            raise ThermalError(
                f"partition = {partition!r} is not allowed; allowed: 'auto', 'effusivity', "
                "'effusivity_area' or a number in [0, 1]") from None
        if not (np.isfinite(gamma) and 0.0 <= gamma <= 1.0):
            raise ThermalError(f"partition = {partition!r} (share of the heat into the pad) "
                               "is not allowed; it must lie in [0, 1]")
    return gamma
