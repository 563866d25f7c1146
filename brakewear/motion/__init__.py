"""Worn geometry: the surfaces that wear move, and the layer beneath follows.

- :mod:`~brakewear.motion.brake`: :class:`BrakeMotion`, the pad's and the
  rotor's worn faces moved along their normals and a new model state returned;
- :mod:`~brakewear.motion.follower`: the band of nodes beneath a worn face and
  how it follows the face without inverting an element.
"""
from .brake import *  # noqa: F403
from .brake import __all__ as _brake_all
from .follower import SurfaceFollower

__all__ = [*_brake_all, "SurfaceFollower"]
