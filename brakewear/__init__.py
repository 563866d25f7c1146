"""brakewear: wear of disc-brake pads and rotors by 3D finite elements.

Built on scikit-fem (assembly), pyamg (solvers), meshio (files) and pyvista
(figures).  The names below are the public API; the subpackages
(:mod:`brakewear.contact`, :mod:`brakewear.fem`, :mod:`brakewear.mesh`,
:mod:`brakewear.solvers`, ...) hold the specialist parts, each with its own
``__all__``.  A typical session::

    import brakewear as bw

    model = bw.BrakeModel("default", size=12e-3)       # mesh and materials
    res = bw.solve_contact(model, 1e6, mu=0.4)         # 1 MPa line pressure
    run = bw.Run(model, 1e6, 55.0, 60.0, bw.WearLaw(5e-15), mu=0.4,
                 numerics=bw.Numerics(steps=2))
    steps = list(bw.wear_history(run))

The names are loaded on first use, so ``import brakewear`` stays light and a
run that never asks for thermal coupling never imports it.
"""
from __future__ import annotations

import importlib
import logging

from .errors import (
    ActiveSetError,
    BenchError,
    BrakewearError,
    CondensedRangeError,
    ContactError,
    ContactLostError,
    ContactSearchError,
    ConvergenceError,
    DependencyError,
    DutyError,
    FoundationError,
    FoundationSolveError,
    GeometryError,
    IdentifiabilityError,
    InputError,
    LawError,
    MapError,
    MaterialError,
    MeshError,
    MeshFileError,
    MeshQualityError,
    MotionError,
    RoughnessError,
    SceneError,
    SolverError,
    SolverSettingsError,
    StepSizeError,
    StoredFileError,
    TemperatureLimitError,
    ThermalError,
    WearError,
    WornThroughError,
)

__version__ = "0.1.0"

#: public name -> the module that defines it (imported on first use)
_LAZY = {
    "BrakeGeometry": "geometry", "load_geometry": "geometry",
    "available_geometries": "geometry",
    "MATERIALS": "materials", "Material": "materials", "Isotropic": "materials",
    "TransverselyIsotropic": "materials", "Thermal": "materials", "get_material": "materials",
    "WearLaw": "laws.base", "FrictionLaw": "laws.base", "register_wear_law": "laws.base",
    "OptionKey": "registry",
    "TableMap": "laws.maps", "read_map": "laws.maps", "FrictionMap": "laws.maps",
    "WearMap": "laws.maps", "StribeckFriction": "laws.maps", "MildSevereWear": "laws.maps",
    "BrakeModel": "model", "StaticResult": "static", "solve_contact": "static",
    "solve_tied": "static", "static_summary": "static", "body_stresses": "static",
    "FEInterface": "interfaces", "CondensedInterface": "interfaces",
    "CaliperInterface": "caliper.interface",
    "FoundationInterface": "interfaces",
    "WinklerInterface": "interfaces", "calibrate": "interfaces",
    "Interface": "interfaces", "InterfaceSolution": "interfaces",
    "register_interface": "interfaces",
    "Run": "wear", "Numerics": "wear", "WearStep": "wear", "wear_history": "wear",
    "WearState": "wear", "StepControl": "wear", "WearLimits": "wear",
    "ConstantSpeed": "wear", "LinearSpeed": "wear",
    "Vehicle": "duty", "Stop": "duty", "Drag": "duty", "Dwell": "duty",
    "run_schedule": "duty", "read_schedule_csv": "duty", "repeated_stops": "duty",
    "register_application": "duty",
    "ThermalModel": "thermal",
    "BrakeMotion": "motion.brake",
    "Scene": "scene", "load_scene": "scene", "scene_from_dict": "scene",
    "available_scenes": "scene", "build_run": "scene",
    "run_wear": "output.runs", "run_scene": "output.runs",
    "read_mesh": "mesh", "write_mesh": "mesh",
}

__all__ = [
    "__version__",
    "BrakewearError", "InputError", "SolverError",
    "GeometryError", "MaterialError", "MeshFileError", "SceneError", "WearError", "DutyError",
    "ThermalError", "FoundationError", "LawError", "MapError", "MeshError", "ContactError",
    "MotionError", "SolverSettingsError", "BenchError", "RoughnessError", "DependencyError",
    "ConvergenceError",
    "ActiveSetError",
    "ContactLostError", "ContactSearchError", "StepSizeError", "MeshQualityError",
    "TemperatureLimitError", "FoundationSolveError", "WornThroughError", "CondensedRangeError",
    "IdentifiabilityError", "StoredFileError",
    *_LAZY,
]

logging.getLogger(__name__).addHandler(logging.NullHandler())


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'brakewear' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
