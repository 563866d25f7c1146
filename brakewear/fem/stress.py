"""Stresses from displacements: element stresses, nodal averages, von Mises."""
from __future__ import annotations

import logging

import numpy as np
import skfem as fem

from .assembly import _as_groups
from .forms import scalar_element

logger = logging.getLogger(__name__)

__all__ = ["element_stress", "nodal_stress", "von_mises"]


def element_stress(mesh: fem.Mesh, u: np.ndarray, materials) -> np.ndarray:
    """Stress at each element's quadrature-point average, Voigt order (6, nelements)."""
    elem = scalar_element(mesh)
    out = np.zeros((6, mesh.nelements))
    for elems, C in _as_groups(mesh, materials):
        idx = np.arange(mesh.nelements) if elems is None else elems
        basis = fem.Basis(mesh, elem, intorder=1 if elem.maxdeg == 1 else 2, elements=idx)
        nb = len(basis.basis)
        G = np.stack([basis.basis[a][0].grad for a in range(nb)])  # (nb, 3, ne, nq)
        ue = u[3 * basis.element_dofs[:, None, :] + np.arange(3)[None, :, None]]  # (nb, 3, ne)
        H = np.einsum("ajeq,aie->ijeq", G, ue)  # du_i/dx_j
        eps = np.stack([H[0, 0], H[1, 1], H[2, 2], H[1, 2] + H[2, 1], H[0, 2] + H[2, 0],
                        H[0, 1] + H[1, 0]])
        w = basis.dx / basis.dx.sum(axis=1, keepdims=True)
        out[:, idx] = C @ (eps * w[None]).sum(axis=2)
    return out


def nodal_stress(mesh: fem.Mesh, sigma_e: np.ndarray) -> np.ndarray:
    """Volume-weighted average of element stresses at the mesh vertices (6, nvertices)."""
    vol = fem.Basis(
        mesh,
        fem.ElementTetP1() if not isinstance(mesh, fem.MeshTet2) else fem.ElementTetP2(),
        intorder=1,
    ).dx.sum(axis=1)
    t = mesh.t[:4]
    num = np.zeros((6, mesh.nvertices))
    den = np.zeros(mesh.nvertices)
    for a in range(4):
        np.add.at(den, t[a], vol)
        for k in range(6):
            np.add.at(num[k], t[a], vol * sigma_e[k])
    return num / np.maximum(den, 1e-300)


def von_mises(s: np.ndarray) -> np.ndarray:
    """Von Mises equivalent stress of Voigt stresses (6, ...)."""
    return np.sqrt(0.5 * ((s[0] - s[1]) ** 2 + (s[1] - s[2]) ** 2 + (s[2] - s[0]) ** 2)
                   + 3.0 * (s[3] ** 2 + s[4] ** 2 + s[5] ** 2))
