"""Grids of the parametric brake meshes: element sizes, graded cell counts, the ring's theta grid.

Shared by the ring and pad meshes of :mod:`brakewear.mesh.brake` and the
hat and vented rotor of :mod:`brakewear.mesh.rotor`.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import MeshError
from .structured import graded

if TYPE_CHECKING:  # imported for annotations only: geometry sits above mesh
    from ..geometry import BrakeGeometry

__all__: list[str] = []



def _n_cells(length: float, h_min: float, ratio: float) -> int:
    """Fewest cells whose geometric grading (``ratio``) has its smallest cell <= h_min."""
    n = 1
    while n < 100_000:
        x = graded(0.0, length, n, ratio, "a")
        if x[1] - x[0] <= 1.05 * h_min:
            return n
        n += 1
    raise MeshError(f"cannot grade {length} with smallest cell {h_min}")  # pragma: no cover



def _two_sided(length: float, h_end: float, h_mid: float, growth: float = 1.3) -> np.ndarray:
    """Cell boundaries on [0, length]: ``h_end`` at both ends growing by ``growth``
    per cell up to ``h_mid`` in the middle (a coarse gap between two fine zones)."""
    if h_mid <= h_end:
        n = max(1, int(np.ceil(length / h_end)))
        return np.linspace(0.0, length, n + 1)
    ramp = [h_end * growth]
    while ramp[-1] * growth < h_mid:
        ramp.append(ramp[-1] * growth)
    ramp = np.array(ramp)
    middle = length - 2.0 * ramp.sum()
    if middle < h_mid:
        # too short for full ramps: a symmetric grading with the same end cell
        n = max(2, int(np.ceil(length / (0.5 * (h_end + h_mid)))))
        return graded(0.0, length, n, h_mid / h_end if n > 2 else 1.0, "both")
    n_mid = max(1, int(round(middle / h_mid)))
    cells = np.concatenate([ramp, np.full(n_mid, middle / n_mid), ramp[::-1]])
    x = np.concatenate([[0.0], np.cumsum(cells)])
    x[-1] = length
    return x



def _check_size_order(size: float, order: int) -> tuple[float, int]:
    size = float(size)
    if not np.isfinite(size) or size <= 0.0:
        raise MeshError(f"mesh size = {size!r} is not allowed; it must be a finite number > 0 (m)")
    if isinstance(order, bool) or order not in (1, 2):
        raise MeshError(f"mesh order = {order!r} is not allowed; allowed: 1, 2")
    return size, int(order)



def _body_size(geom: BrakeGeometry, size: float | None, body: str) -> float:
    """In-plane size of ``body`` (m): its ``mesh.<body>_size``, else ``size``, else
    ``mesh.size``."""
    own = getattr(geom.mesh, f"{body}_size")
    return own if own is not None else (geom.mesh.size if size is None else size)



def _ring_theta(geom: BrakeGeometry, h: float) -> np.ndarray:
    """Closed theta grid of the rotor (last = first + 2 pi): cells of arc ``h`` at
    the pad mid radius over the pad arc plus ``mesh.rotor_margin`` on both sides,
    a graded gap growing to ``rotor_coarse_factor`` times that elsewhere."""
    ms, pad = geom.mesh, geom.pad
    r_ref = 0.5 * (pad.inner_radius + pad.outer_radius)
    span = pad.arc_angle + 2.0 * ms.rotor_margin
    th0 = pad.center_angle - 0.5 * span
    n_fine = max(2, int(np.ceil(span * r_ref / h)))
    fine = np.linspace(0.0, span, n_fine + 1)
    dth = span / n_fine
    gap = _two_sided(2 * np.pi - span, dth, ms.rotor_coarse_factor * dth)
    th = th0 + np.concatenate([fine, span + gap[1:]])
    th[-1] = th0 + 2 * np.pi
    return th

