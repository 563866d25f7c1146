"""How the wear loop integrates: the numerics shared by Python calls and scene files."""
from __future__ import annotations

import logging
from dataclasses import dataclass

from ..checks import check_choice, check_int, check_number

logger = logging.getLogger(__name__)

__all__ = ["Numerics"]


@dataclass(frozen=True)
class Numerics:
    """How the wear loop integrates (:func:`brakewear.wear.wear_history` arguments, SI).

    ``steps = None``: automatic step control (``dp_tol``, or ``wear_tol`` when
    given, ``dh_fraction`` or ``max_dh``, ``stability``); a number: that many
    equal steps.  ``memory_budget`` (GB) caps the model size a scene may ask
    for (None: ``BRAKEWEAR_MEMORY_GB`` or the machine's available memory).
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
    memory_budget: float | None = None

    def __post_init__(self):
        check_choice("numerics.scheme", self.scheme, ("explicit", "implicit"))
        check_choice("numerics.update", self.update, ("gap", "geometry"))
        check_int("numerics.steps", self.steps, 1, allow_none=True)
        check_number("numerics.dp_tol", self.dp_tol, 0.0)
        check_number("numerics.dh_fraction", self.dh_fraction, 0.0, 1.0)
        check_number("numerics.max_dh", self.max_dh, 0.0, unit="m", allow_none=True)
        check_number("numerics.wear_tol", self.wear_tol, 0.0, unit="m", allow_none=True)
        check_number("numerics.stability", self.stability, 0.0, 2.0)
        check_number("numerics.tol", self.tol, 0.0, 1e-3)
        check_int("numerics.max_halvings", self.max_halvings, 0)
        check_number("numerics.memory_budget", self.memory_budget, 0.0, unit="GB",
                     allow_none=True)
