"""Meshes: structured tetrahedra, the parametric brake meshes with named surfaces, files."""

from .brake import (
    brake_meshes,
    component_materials,
    element_materials,
    pad_mesh,
    piston_mesh,
    rotor_mesh,
)
from .io import read_mesh, write_mesh
from .structured import (
    KUHN,
    annulus_mesh,
    cylindrical,
    graded,
    mapped_mesh,
    structured_tets,
)
from .topology import ensure_topology, facet_indices, keep_topology

__all__ = [
    "rotor_mesh",
    "pad_mesh",
    "piston_mesh",
    "brake_meshes",
    "component_materials",
    "element_materials",
    "read_mesh",
    "write_mesh",
    "graded",
    "structured_tets",
    "mapped_mesh",
    "cylindrical",
    "annulus_mesh",
    "KUHN",
    "facet_indices",
    "ensure_topology",
    "keep_topology",
]
