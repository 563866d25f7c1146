"""The kinds of tribometer test, registered by name: one class each, carrying its
name, its keys and its capabilities.

A test kind reads its own ``[test]`` table (its :attr:`TribometerKind.keys`, checked
with their units and ranges), builds the two condensed bodies of the test
(:meth:`TribometerKind.build`) and simulates one cycle -- one stroke back and forth,
one revolution -- at the current worn geometry standing for ``N`` cycles
(:meth:`TribometerKind.advance`), returning the wear of each body per cycle.  The cycle jump
(:mod:`brakewear.tribology.jump`) does the rest, the same for every kind.

The registry reads a kind from its class alone (:func:`register_tribometer`); a
scene's ``scene.test`` names it.  The built-in kinds: ``"reciprocating"``
(:mod:`~brakewear.tribology.reciprocating`), ``"pin_on_disc"`` and
``"block_on_ring"`` (:mod:`~brakewear.tribology.sliding`).
"""
from __future__ import annotations

import logging
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from ..registry import OptionKey, Registry

logger = logging.getLogger(__name__)

__all__ = ["TribometerKind", "CycleResult", "register_tribometer", "tribometer_kind",
           "tribometer_kinds"]

_TESTS = Registry("tribometer test", "scene.test", members=("bodies", "capabilities"))


@dataclass
class CycleResult:
    """One simulated cycle at a worn geometry.

    Attributes
    ----------
    rates : dict
        Body name -> (n,) wear depth per cycle at its face nodes (m).
    pressure : ndarray
        (m,) contact pressure at the slave face nodes at the cycle's end (Pa).
    slip : ndarray
        (m,) the slip of the slave face nodes over the cycle (m).
    figures : dict
        Scalars of the cycle (peak pressure, contact width, tangential force,
        Newton iterations).
    carry : Any
        What the next cycle starts from (the last solve).
    forces : ndarray
        (m, d) the contact forces on the master at the cycle's end (N).
    offset : float
        The master's offset at the cycle's end (m).
    """

    rates: dict
    pressure: np.ndarray
    slip: np.ndarray
    figures: dict
    carry: Any = None
    forces: np.ndarray | None = None
    offset: float = 0.0


class TribometerKind(ABC):
    """A kind of test: subclass it, give the class attributes, register it.

    Attributes
    ----------
    name : str
        As ``scene.test`` names it.
    keys : tuple of OptionKey
        Its ``[test]`` table.
    bodies : tuple of str
        The slave's and the master's names (``[bodies.NAME]`` tables).
    capabilities : dict
        ``dimension`` (2: plane strain, 3), ``slip`` (``"solved"``: stick and slip
        from Coulomb's law; ``"sliding"``: gross sliding), ``cycle``
        (``"cycle"``, ``"revolution"``).
    """

    name: ClassVar[str] = ""
    keys: ClassVar[tuple[OptionKey, ...]] = ()
    bodies: ClassVar[tuple[str, str]] = ("", "")
    capabilities: ClassVar[dict] = {}

    def __init__(self, options: dict):
        self.options = dict(options)

    def __getattr__(self, key: str):
        try:
            return self.__dict__["options"][key]
        except KeyError:
            raise AttributeError(key) from None

    def __eq__(self, other) -> bool:
        return type(self) is type(other) and self.options == other.options

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.options!r})"

    # what a kind answers -------------------------------------------------
    @property
    @abstractmethod
    def cycles(self) -> float:
        """How many cycles the test runs."""

    @property
    @abstractmethod
    def cycle_time(self) -> float:
        """Seconds per cycle (for the record)."""

    def check(self, scene) -> None:  # noqa: B027  (an optional hook)
        """Cross-checks of the kind's keys with the rest of the scene (SceneError)."""

    @abstractmethod
    def build(self, scene):
        """The :class:`~brakewear.tribology.pair.ContactPair` of the scene's bodies."""

    @abstractmethod
    def start(self, scene, pair) -> CycleResult:
        """The loaded state the first cycle starts from (no wear)."""

    @abstractmethod
    def advance(self, scene, pair, depths: dict, last: CycleResult, jump: float) -> CycleResult:
        """One simulated cycle from ``last`` at the worn ``depths`` (body name -> (n,)
        m) standing for ``jump`` cycles; its ``rates`` are the jump's mean wear per
        cycle (m) of each body's face nodes."""

    @abstractmethod
    def profiles(self, pair, depths: dict) -> dict:
        """Body name -> (coordinate (m), depth (m)) of its worn profile's section."""

    def closed_form(self, scene) -> dict | None:
        """The rigid-body limit the test's worn shape approaches, where there is one:
        ``body``, ``name``, figures of :func:`~brakewear.tribology.runner.worn_figures`
        (m, m^2, m^3) and ``profile`` ((x, depth), m); None where there is none."""
        return None

    def record(self) -> dict:
        """The kind's keys, SI, for scene.json."""
        return {k: (v.tolist() if isinstance(v, np.ndarray) else v)
                for k, v in self.options.items()}


def register_tribometer(cls: type[TribometerKind], *,
                        replace: bool = False) -> type[TribometerKind]:
    """Register a test kind by its class (its ``name``, ``keys``, ``bodies`` and
    ``capabilities`` are read from it); usable as a class decorator."""
    return _TESTS.register(cls, replace=replace)


def tribometer_kind(name: str) -> type[TribometerKind]:
    """The registered kind ``name`` (a SceneError naming ``scene.test`` and the kinds;
    the built-in kinds register themselves when :mod:`brakewear.tribology` is imported)."""
    return _TESTS.get(name)


def tribometer_kinds() -> tuple[str, ...]:
    """The names of the registered kinds."""
    return _TESTS.names()


@dataclass(frozen=True)
class BodySpec:
    """A body of a test: its material, its wear coefficient and the extent meshed."""

    name: str
    E: float
    nu: float
    k: float
    half_width: float
    depth: float
    material: str = ""
    extra: dict = field(default_factory=dict)

    @property
    def elastic(self):
        """The body's :class:`~brakewear.materials.Isotropic` law."""
        from ..materials import Isotropic
        return Isotropic(self.E, self.nu, name=self.material or self.name)

    def record(self) -> dict:
        return {"E_Pa": self.E, "nu": self.nu, "k_per_Pa": self.k,
                "half_width_m": self.half_width, "depth_m": self.depth,
                "material": self.material, **self.extra}
