"""The checks of a wear history's inputs, made before anything touches the model."""
from __future__ import annotations

import logging
import os

import numpy as np

from ..errors import WearError
from ..interfaces.fe import FEInterface
from .nodal import check_wear_law, friction_law
from .numerics import Numerics
from .speed import LinearSpeed

logger = logging.getLogger(__name__)

__all__ = []


def check_inputs(model, omega, duration, pad_law, rotor_law, mu, numerics, interface,
                  thermal, initial_gap, checkpoint, every, resume):
    """Every input check, before anything touches the model; returns ``(mu_law, mu)``."""
    if not isinstance(numerics, Numerics):
        raise WearError(f"numerics = {numerics!r} is not a brakewear.wear.Numerics")
    if not (np.isfinite(duration) and duration > 0):
        raise WearError(f"duration = {duration!r} s is not allowed; need > 0")
    if isinstance(omega, LinearSpeed) and duration > omega.duration * (1 + 1e-12):
        raise WearError(f"duration = {duration!r} s is longer than the speed profile's "
                        f"{omega.duration!r} s")
    if resume and checkpoint is None:
        raise WearError("resume=True needs a checkpoint file")
    if resume and not os.path.exists(checkpoint):
        raise WearError(f"resume=True but the checkpoint {checkpoint} does not exist")
    if isinstance(every, bool) or int(every) != every or every < 1:
        raise WearError(f"every = {every!r} is not allowed; need a whole number >= 1")
    for name, law in (("pad_law", pad_law), ("rotor_law", rotor_law)):
        if law is not None:
            check_wear_law(name, law, thermal)
    if numerics.scheme != "explicit" and pad_law.a != 1.0:
        raise WearError(f"scheme = {numerics.scheme!r} needs a pad wear law linear in p "
                        f"(a = 1); got a = {pad_law.a}")
    if numerics.scheme == "implicit" and rotor_law is not None and rotor_law.a != 1.0:
        raise WearError(f"scheme = 'implicit' needs a rotor wear law linear in p (a = 1); "
                        f"got a = {rotor_law.a}: use scheme = 'implicit_pad' (the rotor's "
                        "wear explicit) or 'explicit'")
    if initial_gap is not None:
        initial_gap = np.asarray(initial_gap, dtype=float)
        if initial_gap.ndim != 1 or not np.all(np.isfinite(initial_gap)):
            raise WearError("initial_gap must be a finite 1-D array (m), one value per pad "
                            "friction node")
    mu_law, mu = friction_law(mu, thermal)
    if thermal is not None:
        check_thermal(model, thermal, numerics, interface)
    if numerics.update == "geometry" and interface is not None and not (
            isinstance(interface, FEInterface) and interface.model is model):
        raise WearError("update = 'geometry' rebuilds the FE interface; it needs the "
                        "FEInterface of this model (or none)")
    return mu_law, mu


def check_thermal(model, thermal, numerics, interface) -> None:
    need = ("step", "flux", "thermal_load", "face_temperature", "state_arrays", "set_speed") + (
        ("follow",) if numerics.update == "geometry" else ())
    for attr in need:
        if not hasattr(thermal, attr):
            raise WearError(f"thermal = {thermal!r} is not a ThermalModel (no {attr!r})")
    if thermal.model is not model:
        raise WearError("thermal belongs to another BrakeModel; build it with "
                        "ThermalModel(model) for this model")
    if numerics.update == "geometry" and getattr(model, "order", 1) == 2:
        raise WearError("update = 'geometry' with thermal coupling moves P1 meshes only "
                        "(the temperature of a P2 model lives on its vertices, which the "
                        "thermal model does not move); use update = 'gap' or a P1 model")
    if interface is not None and not getattr(interface, "accepts_load", False):
        raise WearError(f"thermal coupling needs an interface that takes the thermal-strain "
                        f"load; {type(interface).__name__} does not (the load would be "
                        "dropped): use the FE interface")


def at_pressure(interface, line_pressure: float):
    """``interface`` under the run's line pressure: itself, its
    ``at_line_pressure`` copy (the load scaled, nothing assembled), or an error
    where it can do neither (its own pressure would be used quietly)."""
    own = getattr(interface, "line_pressure", None)
    if own is None or own == line_pressure:
        return interface
    if hasattr(interface, "at_line_pressure"):
        return interface.at_line_pressure(line_pressure)
    raise WearError(f"the interface was built for a line pressure of {own / 1e6:g} MPa and "
                    f"the run asks for {line_pressure / 1e6:g} MPa; build the "
                    f"{type(interface).__name__} with the run's line pressure")
