"""The interface models by name: what a scene may choose, and how each is built.

A table in the style of sfepy's solver table.  An interface model is its
class (:class:`~brakewear.interfaces.Interface`), registered once with
:func:`register_interface`; the table reads everything from the class's
attributes:

* ``name`` -- what a scene's ``interface.model`` says;
* ``keys`` -- its own keys of the ``[interface]`` table
  (:class:`~brakewear.registry.OptionKey`: kind and unit for the scene
  reader, default, allowed range), checked for it;
* its **capabilities** (:data:`CAPABILITIES`: True or False class
  attributes), which the scene compares with what it asks for (thermal
  coupling, the geometry update, a friction law per node, quadratic meshes,
  a schedule) before anything is meshed, and ``why_not`` (capability -> why
  it lacks it, for the message);
* ``build(request) -> Interface`` (a class method; :class:`BuildRequest`: the
  model, the checked keys, the line pressure, mu and the numerics);
* or, instead of ``build``, ``decide(request) -> name`` (or ``(name,
  record)``, the record saying why): a choice among the others (``"auto"``:
  the condensed interface where it pays, FE contact otherwise);
* optionally ``fe_answer`` (it gives the FE contact's answer on the same
  meshes) and ``check_scene(scene)`` (the scene's demands on it, checked
  before anything is meshed).

A new model is such a class in any module (a package's, a script's, a
test's) and :func:`register_interface` (a class decorator); a scene file
then names it in ``interface.model`` (and its keys in ``[interface]``), and
nothing in the package changes (docs/extending.md).  The built-in models
register themselves in their modules: ``"fe"``
(:class:`~brakewear.interfaces.FEInterface`), ``"winkler"``
(:class:`~brakewear.interfaces.FoundationInterface`), ``"condensed"``
(:class:`~brakewear.interfaces.CondensedInterface`), ``"auto"``
(:class:`~brakewear.interfaces.auto.AutoChoice`) and ``"caliper"``
(:class:`~brakewear.caliper.interface.CaliperInterface`).
"""
from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

from ..checks import fail
from ..registry import Registry

logger = logging.getLogger(__name__)

__all__ = ["CAPABILITIES", "BuildRequest", "register_interface", "unregister_interface",
           "interface_model", "interface_models", "build_interface", "capabilities_of",
           "allowed_for", "model_keys", "lacks", "model_options"]

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



#: the table; ``fe_answer`` is checked as the capabilities are (True or False)
_TABLE = Registry("interface model", "interface.model", modules=("brakewear.caliper.interface",),
                  capabilities=CAPABILITIES + ("fe_answer",))


def register_interface(part: type[Any], *, replace: bool = False) -> type[Any]:
    """Add the interface model ``part`` to the table; usable as a class decorator.

    Parameters
    ----------
    part
        The model's class: its ``name``, ``keys``, capabilities and ``build``
        (or ``decide``) as class attributes (:mod:`~brakewear.interfaces.registry`).
    replace
        Replace a model of the same name (otherwise refused).

    Returns
    -------
    type
        ``part``.

    Raises
    ------
    SceneError
        Naming ``interface.model`` and what the class lacks or declares
        wrongly; a key it shares with another model must be read the same
        way (the same ``kind``: the scene reader reads a key before it knows
        the model).
    """
    if isinstance(part, type):
        has = [m for m in ("build", "decide") if callable(getattr(part, m, None))]
        if len(has) != 1:
            raise fail("interface.model", f"{part.__name__} has {' and '.join(has) or 'neither'}"
                                          " of build and decide; give exactly one (a class "
                                          "method)")
        for other in _TABLE.registered():
            if other.name == vars(part).get("name"):
                continue
            for k in getattr(part, "keys", ()):
                for o in other.keys:
                    if o.name == k.name and o.kind != k.kind:
                        raise fail(f"interface.{k.name}", f"read as {k.kind!r} by "
                                                          f"{part.__name__} and as {o.kind!r} "
                                                          f"by {other.name!r}")
    return _TABLE.register(part, replace=replace)


def unregister_interface(name: str) -> None:
    """Take the model ``name`` out of the table (registered for a while, by a test).

    Parameters
    ----------
    name
        A registered model's name.
    """
    _TABLE.unregister(name)


def interface_models() -> tuple[str, ...]:
    """The registered names, in the order of registration.

    Returns
    -------
    tuple of str
        The names a scene's ``interface.model`` may give.
    """
    return _TABLE.names()


def interface_model(name: str) -> type[Any]:
    """The class registered as ``name``.

    Parameters
    ----------
    name
        What ``interface.model`` says.

    Returns
    -------
    type
        The model's class.

    Raises
    ------
    SceneError
        Naming ``interface.model`` and the registered names if there is none.
    """
    return _TABLE.get(name)


def capabilities_of(cls: type[Any]) -> frozenset:
    """The capabilities an interface class declares (its class attributes that are True).

    Parameters
    ----------
    cls
        An interface class (registered or not).

    Returns
    -------
    frozenset
        Names of :data:`CAPABILITIES`.
    """
    return frozenset(c for c in CAPABILITIES if getattr(cls, c, False) is True)


def lacks(cls: type[Any], capability: str) -> str:
    """Why the model ``cls`` lacks ``capability`` (the end of a scene's message).

    Parameters
    ----------
    cls
        A registered model's class.
    capability
        A name of :data:`CAPABILITIES` (or ``"fe_answer"``).

    Returns
    -------
    str
        Its ``why_not[capability]``, or that it does not declare it.
    """
    return (getattr(cls, "why_not", None) or {}).get(
        capability, f"interface.model = {cls.name!r} does not declare {capability}")


def allowed_for(capability: str) -> tuple[str, ...]:
    """The registered names whose models have ``capability``.

    Parameters
    ----------
    capability
        A name of :data:`CAPABILITIES`.

    Returns
    -------
    tuple of str
        Model names, in the order of registration.
    """
    return tuple(m.name for m in _TABLE if capability in capabilities_of(m))


def model_keys() -> dict[str, str]:
    """Every registered model's keys and how the scene reader reads each.

    Returns
    -------
    dict
        Key -> kind (:class:`~brakewear.registry.OptionKey`).
    """
    return _TABLE.key_kinds()


def model_options(cls: type[Any], given: Mapping[str, Any]) -> dict[str, Any]:
    """``given`` (the model's keys of ``[interface]``) checked, with the defaults of the others.

    Parameters
    ----------
    cls
        A registered model's class.
    given
        Key -> value (SI).

    Returns
    -------
    dict
        Every key of the model -> its value.

    Raises
    ------
    SceneError
        Naming the key (and the model it belongs to, if another).
    """
    return _TABLE.options(cls, given, "interface")


def build_interface(name: str, request: BuildRequest) -> tuple[Any, dict]:
    """The interface of the registered model ``name`` for ``request``, and its record.

    A decision's choice is followed until a model builds.

    Parameters
    ----------
    name
        What ``interface.model`` says.
    request
        What the model is built for (its ``options`` are checked here).

    Returns
    -------
    interface
        The built interface.
    record : dict
        What was asked and built (``{"requested": name, "model": ...}``, with a
        choosing model's reasons).
    """
    seen: list[str] = []
    why: dict = {}
    entry = interface_model(name)
    request = replace(request, options=model_options(entry, request.options), built={})
    while callable(getattr(entry, "decide", None)):
        seen.append(entry.name)
        chosen = entry.decide(request)
        if isinstance(chosen, tuple):
            chosen, why = chosen[0], {**why, **chosen[1]}
        if chosen in seen:
            raise fail("interface.model", f"{' -> '.join(seen + [chosen])}: the decisions "
                                          "go round in a circle")
        entry = interface_model(chosen)
        own = {k.name for k in getattr(entry, "keys", ())}
        request = replace(request, options=model_options(
            entry, {k: v for k, v in request.options.items() if k in own}))
        logger.info("interface.model = %r chose %r", seen[-1], entry.name)
    built = entry.build(request)
    itf, record = built if isinstance(built, tuple) else (built, {"model": entry.name})
    logger.debug("interface %r built: %s", entry.name, type(itf).__name__)
    return itf, {"requested": name, **record, **why}
