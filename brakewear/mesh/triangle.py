"""Triangles: a degree-5 quadrature, its subdivision, the six quadratic shape functions.

Shared by the dual mortar faces of quadratic contact
(:mod:`brakewear.contact.quadratic`) and by footprint loads, whose
indicator needs many points per facet (:mod:`brakewear.fem.footprint`).
"""
from __future__ import annotations

import numpy as np

__all__ = ["tri6", "subdivided_rule"]


# 7-point, degree-5 rule on a triangle (barycentric points, weights summing to one)
_A, _B = (6 - np.sqrt(15)) / 21, (6 + np.sqrt(15)) / 21
_RULE_L = np.array([[1 / 3, 1 - 2 * _A, _A, _A, 1 - 2 * _B, _B, _B],
                    [1 / 3, _A, 1 - 2 * _A, _A, _B, 1 - 2 * _B, _B],
                    [1 / 3, _A, _A, 1 - 2 * _A, _B, _B, 1 - 2 * _B]])
_RULE_W = np.array([9 / 40] + [(155 - np.sqrt(15)) / 1200] * 3 + [(155 + np.sqrt(15)) / 1200] * 3)


def tri6(lam: np.ndarray) -> np.ndarray:
    """Standard 6-node shape functions (6, ...) at barycentric points ``lam`` (3, ...)."""
    l0, l1, l2 = lam
    return np.stack([l0 * (2 * l0 - 1), l1 * (2 * l1 - 1), l2 * (2 * l2 - 1),
                     4 * l0 * l1, 4 * l1 * l2, 4 * l0 * l2])


def subdivided_rule(level: int) -> tuple[np.ndarray, np.ndarray]:
    """Barycentric points (3, nq) and weights (nq,) summing to one: the 7-point
    rule on each of the ``4**level`` congruent sub-triangles."""
    m = 2 ** level
    tris = []
    for i in range(m):
        for j in range(m - i):
            tris.append(((i, j), (i + 1, j), (i, j + 1)))
            if i + j < m - 1:
                tris.append(((i + 1, j), (i + 1, j + 1), (i, j + 1)))
    pts = []
    for tri in tris:
        c = np.array(tri, dtype=float).T / m          # (xi, eta) of the corners (2, 3)
        xy = c @ _RULE_L                              # (2, 7)
        pts.append(np.vstack([1 - xy[0] - xy[1], xy]))
    return np.hstack(pts), np.tile(_RULE_W, len(tris)) / len(tris)
