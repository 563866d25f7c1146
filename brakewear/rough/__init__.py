"""Rough surfaces: topographies, a half-space contact reference, the foundation model
on the same grid, and the contact conductance of rough faces (docs/rough.md).

* :class:`Topography`, its statistics (:func:`rms_height`, :func:`rms_slope`,
  :func:`radial_psd`, :func:`hurst_fit`), self-affine synthesis
  (:func:`self_affine`) and measured grids (:func:`read_topography`);
* :class:`HalfSpace`: the surface compliance (Boussinesq, Cerruti) by FFT on
  free or periodic grids; :func:`solve_normal` (constrained conjugate
  gradients) and :func:`contact_stiffness` (normal and tangential);
* :class:`FoundationBed`: the Winkler bed and brush on the same grid,
  calibrated on the smooth sphere by :func:`hertz_calibrated_bed`;
* :class:`RoughConductance`: the contact conductance ``h_c(p)`` of two rough
  faces (:mod:`brakewear.rough.conductance`).
"""
from .conductance import RoughConductance, halfspace_conductance
from .foundation import FoundationBed, FoundationContact, hertz_calibrated_bed
from .halfspace import HalfSpace, pixel_kernel
from .normal import NormalContact, solve_normal
from .reader import read_topography
from .stiffness import Stiffness, contact_stiffness
from .synthesis import self_affine, self_affine_psd
from .topography import Topography, hurst_fit, radial_psd, rms_height, rms_slope

__all__ = [
    "Topography", "rms_height", "rms_slope", "radial_psd", "hurst_fit",
    "self_affine", "self_affine_psd", "read_topography",
    "HalfSpace", "pixel_kernel", "NormalContact", "solve_normal", "Stiffness",
    "contact_stiffness", "FoundationBed", "FoundationContact", "hertz_calibrated_bed",
    "RoughConductance", "halfspace_conductance",
]
