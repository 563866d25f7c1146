"""Thermal strain: the load ``int eps(v) : C : alpha (T - T_ref) I`` and thermal stresses."""
from __future__ import annotations

import logging
from collections.abc import Mapping

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..errors import ThermalError
from ..fem.forms import scalar_element
from ..fem.heat import body_label, check_thermal, material_groups, thermal_coupling
from ..fem.stress import element_stress
from ..materials import Material

logger = logging.getLogger(__name__)

__all__ = ["thermal_load_matrix", "model_thermal_load", "thermal_load", "heated_subdomain_load",
           "thermal_stress"]


def _elastic_groups(mesh: fem.Mesh, materials, name: str) -> list[tuple[np.ndarray, Material]]:
    groups = material_groups(mesh, materials, name)
    for _, m in groups:
        if not isinstance(m, Material):
            raise ThermalError(f"body {name!r}: a thermal-strain load needs Material objects "
                               f"(elastic and thermal data), got {type(m).__name__}")
        check_thermal(m, body_label(name, m), ("alpha",))
    return groups


def thermal_load_matrix(mesh: fem.Mesh, materials, name: str = "body") -> sp.csr_matrix:
    """``G`` (3N x n_vertices): the thermal-strain load is ``G @ (T - T_ref)`` of the
    temperature ``T`` at the vertices (N nodes; a P2 mesh's temperature is linear
    on its vertices, :mod:`brakewear.thermal.quadratic`).

    Vector DOF ``3 s + i`` as in :mod:`brakewear.fem`; each material
    group contributes with its own ``C`` and ``alpha``.  On a P2 mesh the rule
    is the P2 stiffness's (degree 4 on the curved elements), so that a
    uniform warming of a free body is balanced by the stiffness to round-off.
    """
    if not isinstance(mesh, fem.MeshTet1):
        raise ThermalError(f"body {name!r}: thermal load needs a MeshTet (P1 or P2), got "
                           f"{type(mesh).__name__}")
    quad = isinstance(mesh, fem.MeshTet2)
    q, vel = (4, fem.ElementTetP2()) if quad else (1, fem.ElementTetP1())
    G = sp.csr_matrix((3 * mesh.p.shape[1], mesh.nvertices))
    for e, m in _elastic_groups(mesh, materials, name):
        sb = fem.Basis(mesh, fem.ElementTetP1(), intorder=q, elements=e)
        vb = fem.Basis(mesh, fem.ElementVector(vel), intorder=q, elements=e)
        G = G + thermal_coupling(m.voigt(), m.thermal.alpha).assemble(sb, vb)
    return G.tocsr()


def model_thermal_load(model, bodies, T: Mapping[str, np.ndarray], T_ref: float,
                       cache: dict) -> np.ndarray:
    """Thermal-strain load (3 * model.n_nodes,) in ``model``'s global numbering of the
    vertex temperatures ``T[b]`` of each body in ``bodies``; the matrices
    (:func:`thermal_load_matrix`) are kept in ``cache``."""
    f = np.zeros(3 * model.n_nodes)
    for b in bodies:
        if b not in cache:
            cache[b] = thermal_load_matrix(model.meshes[b], model.materials[b], b)
        fb = cache[b] @ (np.asarray(T[b], dtype=float) - T_ref)
        o = 3 * model.offsets[b]
        f[o:o + fb.size] = fb
    return f


def thermal_load(mesh: fem.Mesh, material, T: np.ndarray, elements=None) -> np.ndarray:
    """The load of the thermal strain ``alpha T I`` on one body of one material.

    Parameters
    ----------
    mesh
        A P1 or P2 tetrahedral mesh.
    material
        Its material (elastic and thermal data).
    T
        Temperature rise per scalar DOF (K).
    elements
        An element subset (default: all).

    Returns
    -------
    numpy.ndarray
        ``G T``, with ``G`` of :func:`brakewear.fem.heat.thermal_coupling` on the
        mesh's own elements.
    """
    el = scalar_element(mesh)
    # the library's rule: one point is exact for P1; degree 4 on the curved P2 elements
    kw = {"intorder": 1 if el.maxdeg == 1 else 4, "elements": elements}
    G = thermal_coupling(material.voigt(), material.thermal.alpha).assemble(
        fem.Basis(mesh, el, **kw), fem.Basis(mesh, fem.ElementVector(el), **kw))
    return G @ T


def heated_subdomain_load(model, body: str, subdomain: str, dT: float) -> np.ndarray:
    """The load, on every DOF of ``model``, of one subdomain of a body heated by ``dT``.

    Parameters
    ----------
    model
        A :class:`~brakewear.model.BrakeModel`.
    body
        The body (``"rotor"``, ``"pad"``).
    subdomain
        A subdomain of the body's mesh (the rotor's ``"ring"``: its friction ring,
        without the hat).
    dT
        Uniform temperature rise of the subdomain (K); the rest stays at the
        reference.

    Returns
    -------
    numpy.ndarray
        The load of the subdomain's thermal strain (:func:`thermal_load`), zero
        on the other bodies.
    """
    mesh, off = model.meshes[body], model.offsets[body]
    if subdomain not in (mesh.subdomains or {}):
        raise ThermalError(f"{body} mesh has no subdomain {subdomain!r}; it has "
                           f"{sorted(mesh.subdomains or {})}")
    groups = model.materials[body]
    if len(groups) != 1:
        raise ThermalError(f"{body}: {len(groups)} materials; a heated subdomain needs a body "
                           "of one material")
    unit = thermal_load(mesh, groups[0][1], np.ones(mesh.p.shape[1]),
                        elements=mesh.subdomains[subdomain])
    load = np.zeros(model.dofs)
    load[3 * off:3 * off + unit.size] = dT * unit
    return load


def thermal_stress(mesh: fem.Mesh, u: np.ndarray, materials, dT: np.ndarray,
                   name: str = "body") -> np.ndarray:
    """Element stresses ``C (eps(u) - alpha dT I)`` (6, n_elements), Voigt order.

    ``dT`` is the nodal temperature rise over the stress-free reference; the
    element value is its mean over the element's vertices (exact for P1
    strains, which are constant per element).
    """
    groups = _elastic_groups(mesh, materials, name)
    s = element_stress(mesh, u, groups)
    dTe = np.asarray(dT, dtype=float)[mesh.t[:4]].mean(axis=0)
    for e, m in groups:
        s[:, e] -= (m.voigt() @ np.array([1.0, 1.0, 1.0, 0, 0, 0]) * m.thermal.alpha)[:, None] \
            * dTe[None, e]
    return s
