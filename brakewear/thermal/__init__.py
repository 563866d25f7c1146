"""Frictional heating of the brake: heat partition, temperatures of pad and rotor, thermal strain."""

from ..materials import H_CONV_DEFAULT, T_AMBIENT_DEFAULT
from .model import ThermalModel
from .partition import heat_flux, partition_effusivity
from .stability import staggered_amplification
from .strain import thermal_load_matrix, thermal_stress

__all__ = [
    "ThermalModel",
    "partition_effusivity",
    "heat_flux",
    "H_CONV_DEFAULT",
    "T_AMBIENT_DEFAULT",
    "staggered_amplification",
    "thermal_load_matrix",
    "thermal_stress",
]
