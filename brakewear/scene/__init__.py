"""Scenes: one brake model plus what to compute, from a TOML file or from Python."""

from .reader import available_scenes, load_scene, scene_dir, scene_file, scene_from_dict
from .spec import (
    SURFACES,
    UNITS,
    InterfaceSpec,
    OutputSpec,
    Scene,
    ThermalSpec,
    WearSpec,
)

__all__ = [
    "load_scene",
    "scene_from_dict",
    "scene_dir",
    "scene_file",
    "available_scenes",
    "Scene",
    "InterfaceSpec",
    "WearSpec",
    "ThermalSpec",
    "OutputSpec",
    "SURFACES",
    "UNITS",
]
