"""One run, described once: what every runner takes (:class:`Run`).

A scene builds it (:func:`brakewear.scene.build_run`), or Python does; a
drag (:func:`~brakewear.wear.wear_history`, :func:`brakewear.output.runs.run_wear`),
a schedule (:func:`brakewear.duty.run_schedule`) and a resume
(:func:`~brakewear.wear.check_resume`) all take it, and its
:meth:`Run.settings` are what a checkpoint's fingerprint holds, the
interface model's own settings among them (for any model).

Its inputs are checked when it is made, before anything is built or solved:
the laws against their protocols (:func:`~brakewear.laws.base.check_wear_law`,
:func:`~brakewear.laws.base.friction_law`), the thermal coupling against
:class:`~brakewear.wear.coupling.ThermalCoupling`, an interface against
:class:`~brakewear.interfaces.Interface` and the capabilities the run needs
(:meth:`Run.needs`).  The interface is built once, by :meth:`Run.resolved`:
the registered model named (FE contact when none is given) at the run's
line pressure.
"""
from __future__ import annotations

import logging
from dataclasses import KW_ONLY, asdict, dataclass, replace
from typing import Any

import numpy as np

from ..errors import WearError
from ..interfaces.protocol import capability, check_interface
from ..interfaces.registry import BuildRequest, build_interface, capabilities_of, interface_model
from ..laws.base import check_wear_law, friction_law
from .coupling import check_thermal
from .limits import WearLimits
from .numerics import Numerics
from .speed import ConstantSpeed, LinearSpeed, as_speed

logger = logging.getLogger(__name__)

__all__ = ["Run"]


@dataclass(frozen=True, eq=False)
class Run:
    """A wear run: the brake, how its interface is modelled, what loads it.

    Parameters
    ----------
    model
        A :class:`brakewear.model.BrakeModel` (elastic or rigid rotor).
    line_pressure, omega, duration
        A drag: Pa; rotor speed, rad/s (> 0) or a profile
        (:class:`~brakewear.wear.LinearSpeed` for a stop); s.  Not given for a
        schedule, whose applications set them.
    pad_law, rotor_law
        Wear laws of pad and rotor (``rotor_law=None``: the rotor does not
        wear), each a :class:`~brakewear.laws.base.NodeWearLaw`.
    mu
        Friction coefficient, or a friction law
        (:class:`~brakewear.laws.base.NodeFrictionLaw`) evaluated per pad node.
    numerics
        A :class:`~brakewear.wear.Numerics` (default: its defaults).
    interface
        An :class:`~brakewear.interfaces.Interface`, the name of a registered
        interface model (:func:`brakewear.interfaces.interface_models`), or
        None: FE contact (``"fe"``).
    thermal
        Thermal coupling (:class:`~brakewear.wear.coupling.ThermalCoupling`,
        e.g. :class:`brakewear.thermal.ThermalModel`), or None.
    initial_gap
        Extra gap (m) at each pad friction node before any wear.
    limits
        A :class:`~brakewear.wear.WearLimits` (None: the model's).
    schedule, vehicle
        Applications (:class:`~brakewear.duty.Stop`, ``Drag``, ``Dwell``) and
        the :class:`~brakewear.duty.Vehicle` they stop: the run of
        :func:`brakewear.duty.run_schedule` (``line_pressure``, ``omega`` and
        ``duration``, when given, are then a nominal drag: what an ``"auto"``
        interface estimates the run's cost from).
    states
        What the schedule carries from one application to the next besides the
        wear (:mod:`brakewear.duty.states`: a rust layer, the rotor's heat);
        checked by :func:`~brakewear.duty.run_schedule`.
    interface_record
        What :meth:`resolved` asked of the interface table and got
        (``"requested"``, ``"model"``, a choosing model's ``"reason"``); None
        until then.

    Raises
    ------
    WearError
        An input the run cannot take, before anything is built.
    """

    model: Any
    line_pressure: float | None = None
    omega: Any = None
    duration: float | None = None
    pad_law: Any = None
    rotor_law: Any = None
    mu: Any = 0.0
    _: KW_ONLY
    numerics: Numerics | None = None
    interface: Any = None
    thermal: Any = None
    initial_gap: np.ndarray | None = None
    limits: Any = None
    schedule: tuple = ()
    vehicle: Any = None
    states: tuple = ()
    interface_record: dict | None = None

    def __post_init__(self):
        if self.numerics is None:
            object.__setattr__(self, "numerics", Numerics())
        object.__setattr__(self, "schedule", tuple(self.schedule or ()))
        object.__setattr__(self, "states", tuple(self.states or ()))
        if self.initial_gap is not None:
            object.__setattr__(self, "initial_gap", np.asarray(self.initial_gap, dtype=float))
        _check(self)

    # ---------------------------------------------------------------- what --
    @property
    def speed(self):
        """The rotor's speed over the run (:mod:`brakewear.wear.speed`)."""
        return as_speed(self.omega)

    @property
    def mu_law(self):
        """The friction law (None: ``mu`` is a number)."""
        return friction_law(self.mu, self.thermal)[0]

    @property
    def build_mu(self) -> float:
        """The friction coefficient an interface is built with (a law's values are set
        per node before the first solve; any mu > 0 builds the sliding directions)."""
        return self.mu if self.mu_law is None else 1.0

    def needs(self) -> frozenset:
        """The capabilities the run asks of its interface
        (:data:`~brakewear.interfaces.registry.CAPABILITIES`)."""
        return frozenset(c for c, yes in (
            ("accepts_load", self.thermal is not None),
            ("follows_geometry", self.numerics.update == "geometry"),
            ("per_node_friction", self.mu_law is not None),
            ("any_line_pressure", bool(self.schedule)),
            ("implicit_rings", self.numerics.scheme == "implicit"
             and self.rotor_law is not None)) if yes)

    # ------------------------------------------------------------- resolve --
    def resolved(self, line_pressure: float | None = None, options: dict | None = None,
                 checkpoint=None) -> Run:
        """This run with its interface built, or the given interface at the run's
        line pressure; checked against the :class:`~brakewear.interfaces.Interface`
        protocol and the run's needs.  The one place a run's interface is built:
        the registered model named (FE contact when none), with its ``options``
        (its own keys), at ``line_pressure`` (default the run's; 1 MPa without
        one, a schedule's applications pose it at theirs); ``checkpoint``: that of a
        run being resumed, which keeps the interface it was run on."""
        itf, record = self.interface, self.interface_record
        p = line_pressure or self.line_pressure or 1e6
        if itf is None or isinstance(itf, str):
            itf, record = build_interface(itf or "fe", BuildRequest(
                self.model, options or {}, p, self.build_mu, self.numerics, self.needs(),
                run=self, checkpoint=checkpoint))
        elif self.line_pressure is not None and not self.schedule:
            itf = at_pressure(itf, self.line_pressure)
        check_interface(itf, self.needs())
        return self if itf is self.interface else replace(self, interface=itf,
                                                          interface_record=record)

    def at(self, **changes) -> Run:
        """This run with ``changes`` (a schedule's application: its line pressure,
        speed, duration and gap), its interface posed at the new line pressure."""
        run = replace(self, **changes)
        return run.resolved() if not isinstance(run.interface, (str, type(None))) else run

    def settings(self, limits=None) -> dict:
        """Every resolved input (a checkpoint is resumed only by a run with the same);
        the interface's own settings included (:meth:`resolved` first).  ``limits``:
        the ones the run resolved to (default: its own, else the model's)."""
        g, itf = self.model.geometry, self.interface
        if itf is None or isinstance(itf, str):
            raise WearError("Run.settings: the interface is not built; call resolved() first")
        limits = limits or self.limits or WearLimits.for_model(
            self.model, update=self.numerics.update)
        speed = self.speed
        return dict(
            geometry={k: getattr(g, k) for k in ("rotor", "pad", "piston", "mesh", "caliper",
                                                 "support", "extra_pistons")},
            rotor=self.model.rotor, piston=self.model.piston, dofs=int(self.model.dofs),
            line_pressure=self.line_pressure,
            omega=speed.omega if isinstance(speed, ConstantSpeed) else asdict(speed),
            # a longer duration extends a run under automatic step control
            duration=self.duration if self.numerics.steps is not None else None,
            pad_law=self.pad_law, rotor_law=self.rotor_law,
            mu=self.mu_law if self.mu_law is not None else float(self.mu),
            numerics=asdict(self.numerics),
            interface={"type": type(itf).__name__, **itf.settings},
            thermal=None if self.thermal is None else self.thermal.settings,
            initial_gap=self.initial_gap, limits=limits)


def _check(run: Run) -> None:
    """Every input check, before anything touches the model."""
    numerics = run.numerics
    if not isinstance(numerics, Numerics):
        raise WearError(f"numerics = {numerics!r} is not a brakewear.wear.Numerics")
    if not run.schedule:
        _check_drag(run)
    for name, law in (("pad_law", run.pad_law), ("rotor_law", run.rotor_law)):
        if law is not None or name == "pad_law":
            check_wear_law(name, law, run.thermal)
    for surface, law in (("pad", run.pad_law), ("rotor", run.rotor_law)):
        why = None if law is None else numerics.refuses_law(surface, law.a)
        if why:
            raise WearError(f"{why}; got a = {law.a}")
    gap = run.initial_gap
    if gap is not None and (gap.ndim != 1 or not np.all(np.isfinite(gap))):
        raise WearError("initial_gap must be a finite 1-D array (m), one value per pad "
                        "friction node")
    friction_law(run.mu, run.thermal)
    if run.thermal is not None:
        check_thermal(run.thermal, run.model, numerics.update)
        if not _can(run.interface, "accepts_load"):
            raise WearError(
                f"thermal coupling needs an interface that takes the thermal-strain "
                f"load; {_name(run.interface)} does not (the load would be dropped): "
                "use the FE interface")
    if numerics.update == "geometry":
        _check_geometry(run)


def _check_drag(run: Run) -> None:
    duration = run.duration
    if duration is None or not (np.isfinite(duration) and duration > 0):
        raise WearError(f"duration = {duration!r} s is not allowed; need > 0")
    speed = as_speed(run.omega)
    if isinstance(speed, LinearSpeed) and duration > speed.duration * (1 + 1e-12):
        raise WearError(f"duration = {duration!r} s is longer than the speed profile's "
                        f"{speed.duration!r} s")


def _check_geometry(run: Run) -> None:
    model, itf = run.model, run.interface
    if run.thermal is not None and getattr(model, "order", 1) == 2:
        raise WearError("update = 'geometry' with thermal coupling moves P1 meshes only "
                        "(the temperature of a P2 model lives on its vertices, which the "
                        "thermal model does not move); use update = 'gap' or a P1 model")
    if itf is not None and not (_can(itf, "follows_geometry") and (
            isinstance(itf, str) or getattr(itf, "model", None) is model)):
        raise WearError("update = 'geometry' rebuilds the interface on the moved meshes; it "
                        "needs an interface of this model that follows them "
                        "(follows_geometry, as the FEInterface of this model; or none)")


def _can(itf, cap: str) -> bool:
    """Whether ``itf`` (an interface, a registered name or None: FE) has ``cap``."""
    if itf is None or isinstance(itf, str):
        return cap in capabilities_of(interface_model(itf or "fe"))
    return capability(itf, cap)


def _name(itf) -> str:
    return repr(itf) if isinstance(itf, str) else type(itf).__name__


def at_pressure(interface, line_pressure: float):
    """``interface`` under the run's line pressure: itself, its
    ``at_line_pressure`` copy (the load scaled, nothing assembled), or an error
    where it can do neither (its own pressure would be used quietly)."""
    own = getattr(interface, "line_pressure", None)
    if own is None or own == line_pressure:
        return interface
    if capability(interface, "any_line_pressure"):
        return interface.at_line_pressure(line_pressure)
    raise WearError(f"the interface was built for a line pressure of {own / 1e6:g} MPa and "
                    f"the run asks for {line_pressure / 1e6:g} MPa; build the "
                    f"{type(interface).__name__} with the run's line pressure")
