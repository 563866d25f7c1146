"""Finite-element building blocks: forms, fast assembly, boundary conditions, stresses, heat.

Form factories in scikit-fem style (:mod:`~brakewear.fem.forms`), the chunked
elasticity assembly tested against them (:mod:`~brakewear.fem.assembly`),
Dirichlet conditions and tractions (:mod:`~brakewear.fem.boundary`), stress
recovery (:mod:`~brakewear.fem.stress`) and transient heat conduction of one
body (:mod:`~brakewear.fem.heat`).
"""

from .assembly import BlockPattern, assemble_stiffness, stiffness_update
from .boundary import (
    apply_dirichlet,
    assemble_pressure,
    assemble_traction,
    boundary_dofs,
)
from .forms import (
    elasticity_form,
    lame_parameters,
    pressure_form,
    scalar_element,
    thermal_strain_form,
    traction_form,
    voigt_strain,
)
from .heat import (
    HeatConduction,
    capacity,
    conduction,
    convection,
    surface_flux,
    thermal_coupling,
)
from .stress import element_stress, nodal_stress, von_mises

__all__ = [
    "BlockPattern",
    "assemble_stiffness",
    "stiffness_update",
    "assemble_traction",
    "assemble_pressure",
    "boundary_dofs",
    "apply_dirichlet",
    "lame_parameters",
    "scalar_element",
    "voigt_strain",
    "elasticity_form",
    "thermal_strain_form",
    "traction_form",
    "pressure_form",
    "conduction",
    "capacity",
    "convection",
    "surface_flux",
    "thermal_coupling",
    "HeatConduction",
    "element_stress",
    "nodal_stress",
    "von_mises",
]
