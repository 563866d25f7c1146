"""The interface models by name: what a scene may choose, and how each is built.

A table in the style of sfepy's solver table: each interface model is
registered once, under its name, with

* its own keys of a scene's ``[interface]`` table
  (:class:`~brakewear.registry.OptionKey`: kind and unit for the scene
  reader, default, allowed range), which it checks itself;
* its **capabilities** (:data:`CAPABILITIES`), which the scene compares
  with what it asks for (thermal coupling, the geometry update, a friction
  law per node, quadratic meshes, a schedule) before anything is meshed;
* a builder, ``build(request) -> Interface`` (:class:`BuildRequest`: the
  model, the checked keys, the line pressure, mu and the numerics);
* or, instead of a builder, a decision ``decide(request) -> name`` (or
  ``(name, record)``, the record saying why): a choice among the others
  (``"auto"``: the condensed interface where it pays, FE contact otherwise).

A new model is a class answering :class:`~brakewear.interfaces.Interface`
and one call of :func:`register_interface`, in any module (a package's, a
script's, a test's); a scene file then names it in ``interface.model`` (and
its keys in ``[interface]``), and nothing in the package changes
(docs/extending.md).  The built-in models register themselves in their
modules: ``"fe"`` (:class:`~brakewear.interfaces.FEInterface`),
``"winkler"`` (:class:`~brakewear.interfaces.FoundationInterface`),
``"condensed"`` (:class:`~brakewear.interfaces.CondensedInterface`).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Mapping

from ..checks import fail
from ..registry import OptionKey, Registry, check_options

logger = logging.getLogger(__name__)

__all__ = ["CAPABILITIES", "InterfaceModel", "BuildRequest", "register_interface",
           "unregister_interface", "interface_model", "interface_models", "build_interface",
           "capabilities_of", "allowed_for", "model_keys"]

#: What an interface model may be able to do, each a class attribute of the model
#: (True or False) that the wear loop and the scene read:
#: ``accepts_load`` -- a nodal load (thermal strain) enters its solves;
#: ``follows_geometry`` -- :meth:`rebuilt` on a moved model (update = "geometry");
#: ``per_node_friction`` -- a friction coefficient per pad node (a friction law);
#: ``quadratic`` -- quadratic (P2) meshes;
#: ``any_line_pressure`` -- :meth:`at_line_pressure` (a schedule's applications);
#: ``implicit_rings`` -- its solve takes a :class:`~brakewear.interfaces.StepCompliance`
#: with rings and solves the rotor's ring wear of the step with the pressure
#: (``numerics.scheme = "implicit"`` with a rotor that wears).
CAPABILITIES = ("accepts_load", "follows_geometry", "per_node_friction", "quadratic",
                "any_line_pressure", "implicit_rings")


@dataclass(frozen=True)
class BuildRequest:
    """What a builder (or a decision) of an interface model is given.

    Attributes
    ----------
    model
        The :class:`~brakewear.model.BrakeModel`.
    options
        The model's own keys, checked, with their defaults (SI).
    line_pressure
        Pa, the run's (a schedule's first).
    mu
        The friction coefficient to build with (a friction law's values are
        set per node before the first solve; any mu > 0 builds the sliding
        directions).
    numerics
        The run's :class:`~brakewear.wear.Numerics` (``tol``, ``update``,
        ``memory_budget``).
    needs
        The capabilities the run asks for (:data:`CAPABILITIES`).
    run
        The :class:`~brakewear.wear.Run` being resolved (its speed, duration,
        laws, thermal coupling, schedule: what a decision may weigh), or None.
    checkpoint
        The checkpoint of a run being resumed (a decision keeps the interface
        it was run on), or None.
    built
        Interfaces a decision built to decide, by model name, for the chosen
        model's builder to use (the ``"auto"`` choice's FE interface, which the
        condensed interface condenses); a decision fills it.
    """

    model: Any
    options: Mapping[str, Any]
    line_pressure: float
    mu: float
    numerics: Any
    needs: frozenset = frozenset()
    run: Any = None
    checkpoint: Any = None
    built: dict = field(default_factory=dict)


@dataclass(frozen=True)
class InterfaceModel:
    """One entry of the table: a named interface model.

    Parameters
    ----------
    name
        What a scene's ``interface.model`` says.
    build
        ``build(request: BuildRequest) -> Interface``, or ``(Interface, record)``
        where it chose among others: ``record`` says which and why (``"model"``,
        ``"reason"``; ``summary.json``'s ``interface``).
    keys
        Its own keys of the ``[interface]`` table (:class:`~brakewear.registry.OptionKey`).
    capabilities
        What it can do (a subset of :data:`CAPABILITIES`); a model class's
        are :func:`capabilities_of` it.
    decide
        Instead of ``build``: ``decide(request) -> name`` of the model to build,
        or ``(name, record)`` with the reasons (``summary.json``'s
        ``interface``).
    why_not
        Capability -> why this model lacks it (ends the scene's message).
    fe_answer
        Whether it gives the FE contact's answer on the same meshes (to its
        solvers' tolerance), so the FE meshes' measured convergence rates it
        (:func:`brakewear.scene.accuracy.mesh_accuracy`); ``why_not["fe_answer"]``
        says why not.
    check_scene
        ``check_scene(scene)``: the scene's demands on this model checked before
        anything is meshed (the condensed interface's memory), raising a
        :class:`~brakewear.errors.SceneError` naming the key.
    summary
        One line for messages and the documentation.
    """

    name: str
    build: Callable[[BuildRequest], Any] | None = None
    keys: tuple[OptionKey, ...] = ()
    capabilities: frozenset = frozenset()
    decide: Callable[[BuildRequest], str] | None = None
    why_not: Mapping[str, str] = field(default_factory=dict)
    fe_answer: bool = False
    check_scene: Callable[[Any], None] | None = None
    summary: str = ""

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise fail("interface.model", f"{self.name!r} is not allowed as a model name; "
                                          "need a name like 'fe' (letters, digits, _)")
        if (self.build is None) == (self.decide is None):
            raise fail(f"interface.model = {self.name!r}", "give exactly one of build and "
                                                          "decide")
        unknown = sorted(set(self.capabilities) - set(CAPABILITIES))
        if unknown:
            raise fail(f"interface.model = {self.name!r}", f"unknown capability "
                                                          f"{unknown[0]!r}; known: "
                                                          f"{', '.join(CAPABILITIES)}")
        object.__setattr__(self, "capabilities", frozenset(self.capabilities))
        object.__setattr__(self, "keys", tuple(self.keys))

    def lacks(self, capability: str) -> str:
        """Why this model lacks ``capability`` (for a scene's message)."""
        return self.why_not.get(capability, f"interface.model = {self.name!r} does not "
                                            f"declare {capability}")

    def options(self, given: Mapping[str, Any]) -> dict[str, Any]:
        """``given`` (this model's keys) checked, with the defaults of the others."""
        others: dict[str, list[str]] = {}
        for m in _TABLE:
            for k in m.keys:
                others.setdefault(k.name, []).append(f"interface.model = {m.name!r}")
        return check_options(self.keys, given, "interface", f"interface.model = {self.name!r}",
                             others)


_TABLE = Registry("interface model", "interface.model", modules=("brakewear.caliper.interface",))


def register_interface(entry: InterfaceModel, *, replace: bool = False) -> InterfaceModel:
    """Add ``entry`` to the table (``replace=True``: over one of the same name).

    A key it shares with another model must be read the same way (the same
    ``kind``): the scene reader reads a key before it knows the model."""
    if not isinstance(entry, InterfaceModel):
        raise fail("interface.model", f"{entry!r} is not an InterfaceModel")
    for other in _TABLE.registered():
        if other.name == entry.name:
            continue
        for k in entry.keys:
            for o in other.keys:
                if o.name == k.name and o.kind != k.kind:
                    raise fail(f"interface.{k.name}", f"read as {k.kind!r} by {entry.name!r} "
                                                      f"and as {o.kind!r} by {other.name!r}")
    return _TABLE.register(entry.name, entry, replace)


def unregister_interface(name: str) -> None:
    """Take the model ``name`` out of the table (registered for a while, by a test)."""
    _TABLE.unregister(name)


def interface_models() -> tuple[str, ...]:
    """The registered names, in the order of registration."""
    return _TABLE.names()


def interface_model(name: str) -> InterfaceModel:
    """The entry of ``name`` (a :class:`~brakewear.errors.SceneError` naming
    ``interface.model`` and the allowed names if there is none)."""
    return _TABLE.get(name)


def allowed_for(capability: str) -> tuple[str, ...]:
    """The registered names whose models have ``capability``."""
    return tuple(m.name for m in _TABLE if capability in m.capabilities)


def model_keys() -> dict[str, str]:
    """Every registered model's keys: name -> kind (for the scene reader)."""
    return {k.name: k.kind for m in _TABLE for k in m.keys}


def capabilities_of(cls) -> frozenset:
    """The capabilities an interface class declares (its true class attributes)."""
    return frozenset(c for c in CAPABILITIES if getattr(cls, c, False) is True)


def build_interface(name: str, request: BuildRequest) -> tuple[Any, dict]:
    """The interface of the registered model ``name`` for ``request`` (its options
    checked) and the record of what was asked and built (``{"requested": name,
    "model": ...}``, with a choosing builder's reasons): a decision's choice is
    followed until a model builds."""
    seen, why = [], {}
    entry = interface_model(name)
    request = replace(request, options=entry.options(request.options), built={})
    while entry.decide is not None:
        seen.append(entry.name)
        chosen = entry.decide(request)
        if isinstance(chosen, tuple):
            chosen, why = chosen[0], {**why, **chosen[1]}
        if chosen in seen:
            raise fail("interface.model", f"{' -> '.join(seen + [chosen])}: the decisions "
                                          "go round in a circle")
        entry = interface_model(chosen)
        own = {k.name for k in entry.keys}
        request = replace(request, options=entry.options(
            {k: v for k, v in request.options.items() if k in own}))
        logger.info("interface.model = %r chose %r", seen[-1], entry.name)
    built = entry.build(request)
    itf, record = built if isinstance(built, tuple) else (built, {"model": entry.name})
    logger.debug("interface %r built: %s", entry.name, type(itf).__name__)
    return itf, {"requested": name, **record, **why}
