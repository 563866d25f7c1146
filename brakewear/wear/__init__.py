"""The wear loop: Archard wear of pad and rotor integrated in time."""


from .numerics import Numerics
from .stepper import WearStep, wear_history

__all__ = ["Numerics", "WearStep", "wear_history"]
