"""The thermal coning of a rotor's friction faces under a temperature field.

The rotor alone (its mesh and materials in a :class:`~brakewear.model.BrakeModel`),
held at its ``rotor_clamp`` face (the hat's mounting face to the bolt circle),
under the load of its thermal strain (the same ``G (T - T_ref)`` the contact
solves take, :meth:`brakewear.thermal.ThermalModel.thermal_load`).  On each
friction face the axial displacement is averaged ring by ring; the coning
across the pad is the change of the gap it opens from the pad's inner to its
outer radius, in the sense of :func:`brakewear.cleaning.corrosion.nonconformity_gap`'s
``coning`` (positive: the inboard face's gap opens at the outer radius and the
outboard face's at the inner one).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse.linalg as spla

from ..errors import ThermalError
from ..fem import apply_dirichlet, assemble_stiffness, boundary_dofs

__all__ = ["RotorConing"]


class RotorConing:
    """Coning of the rotor of ``thermal``'s model under its temperatures.

    Parameters
    ----------
    thermal
        A :class:`~brakewear.thermal.ThermalModel` of a model with an elastic rotor.
    band
        ``(r_in, r_out)`` (m): the pad's radial extent, across which the coning is taken.
    """

    def __init__(self, thermal, band: tuple[float, float]):
        model = thermal.model
        if model.rotor != "elastic" or "rotor" not in thermal.bodies:
            raise ThermalError("rotor coning needs a model with an elastic (meshed) rotor")
        mesh = model.meshes["rotor"]
        if "rotor_clamp" not in mesh.boundaries:
            raise ThermalError("the rotor mesh has no 'rotor_clamp' face to hold it by")
        self.thermal, self.band = thermal, band
        K, _ = assemble_stiffness(mesh, model.materials["rotor"])
        self.fixed = boundary_dofs(mesh, "rotor_clamp")
        Kd, _ = apply_dirichlet(K.tocsr(), np.zeros(K.shape[0]), self.fixed)
        self._lu = spla.splu(Kd.tocsc())
        n0 = 3 * model.offsets["rotor"]
        self._dofs = slice(n0, n0 + 3 * mesh.p.shape[1])
        heat = thermal.heat["rotor"]
        face, x = heat.face, mesh.p[:, heat.face]
        self.face_nodes = face
        self.ring, self.radii = thermal.ring, thermal.ring_radii
        t = model.geometry.rotor.thickness
        n = self.radii.size
        z = np.bincount(self.ring, weights=x[2], minlength=n) / np.bincount(self.ring,
                                                                            minlength=n)
        self.ring_face = np.where(z < -0.5 * t, "out", "in") if model.full else \
            np.full(n, "in")

    def displacement(self, T_rotor: np.ndarray) -> np.ndarray:
        """The rotor's displacement (3 per node, m) under the temperatures ``T_rotor`` (K)."""
        T_pad = np.full(self.thermal.heat["pad"].n, self.thermal.T_ref)
        f = self.thermal.thermal_load({"rotor": np.asarray(T_rotor, dtype=float),
                                       "pad": T_pad})[self._dofs]
        f = f.copy()
        f[self.fixed] = 0.0
        return self._lu.solve(f)

    def __call__(self, T_rotor: np.ndarray) -> dict:
        """Per face (``"in"``, ``"out"``) the coning across the band (m)."""
        u = self.displacement(T_rotor)
        uz = u[2::3][self.face_nodes]
        n = self.radii.size
        ring_uz = np.bincount(self.ring, weights=uz, minlength=n) / np.bincount(self.ring,
                                                                                minlength=n)
        out = {}
        for f in ("in", "out"):
            idx = np.flatnonzero(self.ring_face == f)
            if idx.size < 2:
                continue
            idx = idx[np.argsort(self.radii[idx])]
            at = np.interp(self.band, self.radii[idx], ring_uz[idx])
            # the gap opens as the inboard face moves to -z, the outboard face to +z;
            # in the coning's sense (docs/duty.md) both are -(u_z(out) - u_z(in))
            out[f] = float(-(at[1] - at[0]))
        return out
