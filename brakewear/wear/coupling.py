"""What the wear loop asks of thermal coupling: the :class:`ThermalCoupling` protocol.

:class:`brakewear.thermal.ThermalModel` answers it; so may any user class.
The loop checks it once, when a run starts (:func:`check_thermal`), and
needs nothing else of it.  The protocol lives with the loop, so a run that
never asks for thermal coupling never imports :mod:`brakewear.thermal`.
"""
from __future__ import annotations

import logging
from collections.abc import Mapping
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import WearError

logger = logging.getLogger(__name__)

__all__ = ["ThermalCoupling", "check_thermal"]


@runtime_checkable
class ThermalCoupling(Protocol):
    """The temperatures of a wear run, one staggered update per step.

    Attributes
    ----------
    model
        The :class:`~brakewear.model.BrakeModel` it belongs to.
    bodies : tuple of str
        The bodies with a temperature field (``"pad"``, and ``"rotor"`` when meshed).
    T : dict
        Body -> nodal temperatures (K).
    partition
        The pad's share of the frictional heat (a number or one per pad node).
    T_max, contact_conductance : float
        The plausibility bound of the face temperatures (K) and the pad-rotor
        contact conductance (W/m^2 K).
    settings : dict
        Its settings (a checkpoint is resumed only with the same).

    Methods
    -------
    The loop calls ``set_speed(omega)``, ``flux(p, mu, omega)`` (heat flux per
    pad node, W/m^2), ``step(q_pad, dt)``, ``thermal_load()`` (nodal load of the
    thermal strain, N per DOF), ``face_temperature("pad")``,
    ``rotor_temperature_under_pad()``, ``heat_balance()``, ``state_arrays()``
    and ``load_state(arrays)`` (its state in and out of a checkpoint), and with
    the geometry update ``follow(model)`` (the moved model).
    """

    model: Any
    bodies: tuple
    T: Mapping[str, np.ndarray]
    partition: Any
    T_max: float
    contact_conductance: float
    settings: dict

    def set_speed(self, omega: float) -> None: ...

    def flux(self, p: np.ndarray, mu, omega: float) -> np.ndarray: ...

    def step(self, q_pad: np.ndarray, dt: float) -> dict: ...

    def thermal_load(self) -> np.ndarray: ...

    def face_temperature(self, body: str = "pad") -> np.ndarray: ...

    def rotor_temperature_under_pad(self) -> np.ndarray: ...

    def heat_balance(self) -> dict: ...

    def state_arrays(self) -> dict: ...

    def load_state(self, arrays: Mapping[str, np.ndarray]) -> None: ...


#: the members the loop uses (``follow`` only with the geometry update)
_MEMBERS = ("step", "flux", "thermal_load", "face_temperature", "state_arrays", "set_speed",
            "load_state", "rotor_temperature_under_pad", "heat_balance", "model", "bodies",
            "T", "partition", "T_max", "contact_conductance", "settings")


def check_thermal(thermal, model, update: str) -> None:
    """Refuse a thermal coupling that lacks a member of :class:`ThermalCoupling`
    (``follow`` too when ``update == "geometry"``) or belongs to another model."""
    need = ("step", "flux", "thermal_load", "face_temperature", "state_arrays", "set_speed") + (
        ("follow",) if update == "geometry" else ()) + _MEMBERS[6:]
    for attr in need:
        if not hasattr(thermal, attr):
            raise WearError(f"thermal = {thermal!r} is not a ThermalModel (no {attr!r})")
    if thermal.model is not model:
        raise WearError("thermal belongs to another BrakeModel; build it with "
                        "ThermalModel(model) for this model")
