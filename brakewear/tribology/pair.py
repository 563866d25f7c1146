"""The contact of a test's two condensed bodies: pairing, compliance, gap, forces.

The slave body (below, its face at heights ``z_A``) keeps its face nodes in the
contact's frame; the master (above, its face at heights ``z_B``) is met at the
points above them, shifted by the master's rigid ``offset`` (the reciprocating
stroke; zero where the master passes through the contact with the same shape
at every instant -- a disc, a ring).  At an offset the pairing is the master
face's linear interpolation ``Pi`` at ``x - offset`` (the face's projection
along the normal: the faces' slopes are small where they touch), and::

    C = C_A + Pi C_B Pi^T,     g0 = z_B(x - offset) + Pi h_B - z_A + h_A,

``h_A``, ``h_B`` the worn depths of the faces (the wear offsets the gap; the
meshes stay, which holds while the depths are far below the contact's width).
A contact force ``f`` on the master at the slave nodes displaces the slave's
face by ``-C_A f`` and the master's by ``C_B Pi^T f``.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..errors import ContactSearchError
from .bodies import Body, face_interpolation

logger = logging.getLogger(__name__)

__all__ = ["ContactPair"]


@dataclass
class ContactPair:
    """Slave and master bodies of a test and their pairing.

    Attributes
    ----------
    slave, master : Body
    tris : ndarray or None
        (3, nt) the master face's triangles in its face numbering (3D).
    """

    slave: Body
    master: Body
    tris: np.ndarray | None = None
    _cache: dict = field(default_factory=dict, repr=False)

    @property
    def dim(self) -> int:
        return self.slave.dim

    @property
    def lateral(self) -> np.ndarray:
        """(dim - 1, m) the slave face nodes' lateral coordinates."""
        return self.slave.x[:-1]

    def interpolation(self, offset=0.0) -> sp.csr_matrix:
        """(m, n_master) the master face at the slave nodes, the master shifted by
        ``offset`` (m, along x)."""
        key = ("pi", float(offset))
        if key not in self._cache:
            lat = self.lateral.copy()
            lat[0] = lat[0] - offset
            if self.dim == 2:
                Pi = face_interpolation(self.master.x[0], lat[0])
            else:
                Pi = face_interpolation(self.master.x[:2], lat, self.tris)
            self._cache[key] = Pi
        return self._cache[key]

    def check_reach(self, offset, touching: np.ndarray) -> None:
        """Refuse a contact that reaches the edge of the meshed contact zone."""
        Pi = self.interpolation(offset)
        outside = np.asarray(Pi.sum(axis=1)).ravel() < 1 - 1e-9
        rim = self._rim()
        bad = touching & (outside | rim)
        if np.any(bad):
            x = self.lateral[:, bad]
            raise ContactSearchError(
                f"the contact reached the edge of the finely meshed zone (at x = "
                f"{x[0].min() * 1e3:.4g} .. {x[0].max() * 1e3:.4g} mm, offset "
                f"{float(offset) * 1e3:.4g} mm): give a larger mesh.zone")

    def _rim(self) -> np.ndarray:
        if "rim" not in self._cache:
            if self.slave.whole_face:
                rim = np.zeros(self.slave.face.size, bool)
            elif self.dim == 2:
                rim = np.zeros(self.slave.face.size, bool)
                rim[[0, -1]] = True
            else:
                r = np.hypot(*self.lateral)
                h = np.sqrt(np.median(self.slave.area))
                rim = r > r.max() - 1.5 * h
            self._cache["rim"] = rim
        return self._cache["rim"]

    def compliance(self, offset=0.0) -> np.ndarray:
        """(m d, m d) the relative compliance at ``offset`` (cached per offset)."""
        key = ("C", float(offset))
        if key not in self._cache:
            d = self.dim
            E = sp.kron(self.interpolation(offset), sp.identity(d), format="csr")
            CB = self.master.compliance
            self._cache[key] = self.slave.compliance + np.asarray(E @ (E @ CB).T).T
        return self._cache[key]

    def gap(self, offset=0.0, h_slave=None, h_master=None) -> np.ndarray:
        """(m,) the normal gap before the forces (m), with the worn depths."""
        Pi = self.interpolation(offset)
        g = Pi @ self.master.x[-1] - self.slave.x[-1]
        if h_slave is not None:
            g = g + h_slave
        if h_master is not None:
            g = g + Pi @ h_master
        return g

    def displacements(self, forces: np.ndarray, offset=0.0) -> tuple[np.ndarray, np.ndarray]:
        """The faces' displacements ((m, d) slave, (n_master, d) master; m) under the
        forces ``forces`` ((m, d), N) on the master at the slave nodes."""
        d = self.dim
        f = np.asarray(forces, dtype=float)
        uA = -(self.slave.compliance @ f.ravel()).reshape(-1, d)
        fB = self.interpolation(offset).T @ f
        uB = (self.master.compliance @ np.asarray(fB).ravel()).reshape(-1, d)
        return uA, uB

    def master_forces(self, forces: np.ndarray, offset=0.0) -> np.ndarray:
        """(n_master, d) the forces ``forces`` (at the slave nodes) on the master's
        face nodes (the pairing's transpose: the total is kept)."""
        return np.asarray(self.interpolation(offset).T @ np.asarray(forces, dtype=float))

    def relative_tangential(self, uA: np.ndarray, uB: np.ndarray, offset=0.0) -> np.ndarray:
        """(m, d - 1) the master's tangential displacement relative to the slave's at the
        points paired at ``offset``."""
        return (self.interpolation(offset) @ uB)[:, :-1] - uA[:, :-1]
