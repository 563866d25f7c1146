"""The rotor's temperatures over a schedule of stops by a reduced model of its heat
conduction, and the thermal coning they give the gap.

A schedule of many stops heats the rotor's ring, and the ring, hotter than the
hat it hangs on, cones (docs/thermal.md, "Thermal coning of a hat rotor"):
the friction faces turn about the ring's circumference, by ``kappa_c`` across
the pad per kelvin of ring over hat.  Coning is a property of the bulk
temperatures, which change slowly; the full model's temperature field is far
more than it needs.

:class:`ReducedRotorHeat` projects the rotor's finite-element heat equation
(the :class:`~brakewear.fem.HeatConduction` of a
:class:`~brakewear.thermal.ThermalModel`: the same mesh, materials and
convective faces) onto a Krylov basis of its inputs, the heat put into each
ring of each friction face (revolution-averaged, as the full model puts it):
``V0 = A^-1 B``, ``V_k+1 = A^-1 M V_k`` (``A`` conduction plus convection at
a reference speed, ``M`` the capacity), and blocks ``(A + M / tau)^-1 B`` at
the time scales of a stop, orthonormalised in ``M``.  The reduced
system ``M_r da/dt + (K_r + s H_r) a = V^T B u`` (``s`` the convection's speed
factor) matches the full one's steady state and its slowest moments exactly;
it is integrated by implicit Euler in sub-steps (a stop's power falling
linearly with its speed, each sub-step's exact mean).  The ring's and the
hat's capacity-weighted mean temperatures follow.  The thermal coning is the
elastic rotor's own under the reduced field (:meth:`add_coning`: one solve per
basis vector, once), or ``kappa_c`` times the ring's mean over the hat's
(:meth:`coning`): the hat's figure holds for a ring of one temperature, and the
elastic rotor's is larger while a stop heats the band (docs/cleaning.md).
"""
from __future__ import annotations

import logging

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import ThermalError
from .convection import SpeedConvection, rounded
from .partition import partition_effusivity

logger = logging.getLogger(__name__)

__all__ = ["ReducedRotorHeat", "HAT_CONING_PER_K", "hat_nodes"]

#: The hat rotor's thermal coning across the pad per kelvin of ring over hat (m/K):
#: 66 um per 100 K across the 43 mm pad of geometry/floating.toml (the axisymmetric
#: P2 section model, docs/thermal.md)
HAT_CONING_PER_K = 0.66e-6


class ReducedRotorHeat:
    """The rotor of a :class:`~brakewear.thermal.ThermalModel` (of a model with an
    elastic rotor), reduced (see the module).

    Parameters
    ----------
    thermal
        The full thermal model whose rotor is reduced (its mesh, materials,
        convection and the rotor's share of the frictional heat).
    band
        ``(r_in, r_out)`` (m): the rings whose heat inputs span the basis (the
        pad's radial extent; default all rings of the friction faces).
    blocks
        Krylov blocks about the steady state (each as many vectors as inputs).
    fast
        Time scales ``tau`` (s) of further blocks ``(A + M / tau)^-1 B``: the
        response within a stop (the heat entering the hat near its junction).
    omega_ref
        The speed (rad/s) of the convection in ``A``.

    Attributes
    ----------
    T_ring, T_hat : float
        Capacity-weighted mean temperatures (K) of the ring and of the hat
        (:func:`hat_nodes`; the ring's without a hat).
    convection_factor : float
        A factor on the convection (1: the thermal model's; the air a wheel
        housing moves over the rotor, and radiation, shed more).
    """

    def __init__(self, thermal, band: tuple[float, float] | None = None, blocks: int = 3,
                 omega_ref: float = 40.0, fast: tuple = (10.0,)):
        if "rotor" not in thermal.bodies:
            raise ThermalError("a reduced rotor needs a thermal model of a meshed (elastic) rotor")
        heat, model = thermal.heat["rotor"], thermal.model
        self.share = 1.0 - rotor_share_partition(thermal)
        self.T_ambient = thermal.T_ambient
        law = thermal.cooling.get("rotor", (None, 0.0))
        if law[1] > 0:
            raise ThermalError("the reduced rotor is linear: give the rotor no emissivity "
                               "(radiation is linearised about the temperature)")
        self._law = law[0] if isinstance(law[0], SpeedConvection) else None
        self._h_assembled = thermal.h_assembled["rotor"]
        self.convection_factor = 1.0
        self.ring, self.radii = thermal.ring, thermal.ring_radii
        self.face_area = thermal.rotor_area
        x = model.meshes["rotor"].p
        hat = hat_nodes(model)
        m = np.asarray(heat.M @ np.ones(heat.n)).ravel()
        self._w_ring = np.where(hat, 0.0, m) / m[~hat].sum()
        self._w_hat = np.where(hat, m, 0.0) / m[hat].sum() if hat.any() else None
        self._hat = hat
        face = heat.face
        xf = x[:, face]
        self.face_of_ring = _ring_faces(model, xf, self.ring)
        lo, hi = band if band is not None else (self.radii.min(), self.radii.max())
        gaps = np.diff(np.unique(np.round(self.radii, 12)))
        h = float(gaps.max()) if gaps.size else 0.0
        # the band's rings and the next ring either side (a node between two rings
        # heats both)
        self.inputs = np.flatnonzero((self.radii >= lo - h - 1e-9) &
                                     (self.radii <= hi + h + 1e-9))
        ring_area = np.bincount(self.ring, weights=self.face_area, minlength=self.radii.size)
        # one input per ring: its power (W) spread uniformly over its area
        E = sp.csr_matrix((1.0 / ring_area[self.ring], (np.arange(face.size), self.ring)),
                          shape=(face.size, self.radii.size))
        B = (heat.S @ E[:, self.inputs]).toarray()
        #: the nodal heat input (W) of one watt into each input ring
        self.input_loads = B
        self._omega_ref = float(omega_ref)
        scale = self._convection_scale(omega_ref)
        A = (heat.K + scale * heat.H1).tocsc()
        lu = spla.splu(A)
        V = _m_orthonormal(lu.solve(B), heat.M)
        W = V
        for _ in range(blocks - 1):        # block Krylov, each block orthonormalised in M
            W = _extend(V, lu.solve(np.asarray(heat.M @ W)), heat.M)
            V = np.hstack([V, W])
        for tau in fast:                   # the response over a stop: (A + M / tau)^-1 B
            W = _extend(V, spla.splu((A + heat.M / tau).tocsc()).solve(B), heat.M)
            V = np.hstack([V, W])
        self.V = V
        self.M_r = V.T @ (heat.M @ V)
        self.K_r = V.T @ (heat.K @ V)
        self.H_r = V.T @ (heat.H1 @ V)
        self.B_r = V.T @ B
        self._wv_ring = self._w_ring @ V
        self._wv_hat = None if self._w_hat is None else self._w_hat @ V
        self.a = np.zeros(V.shape[1])
        self.time = 0.0
        self._cone = None
        self._factors: dict = {}
        logger.info("reduced rotor heat: %d inputs, basis %d of %d nodes", self.inputs.size,
                    V.shape[1], heat.n)

    # ------------------------------------------------------------------ state --
    def _convection_scale(self, omega: float) -> float:
        """The factor on the rotor's assembled convection at ``omega``: a speed-dependent
        coefficient over the one assembled, rounded as the full model rounds it."""
        law = self._law
        base = 1.0 if law is None else rounded(law.h(omega) / self._h_assembled)
        return base * self.convection_factor

    @property
    def field(self) -> np.ndarray:
        """The rotor's temperature at its nodes (K)."""
        return self.T_ambient + self.V @ self.a

    @property
    def T_ring(self) -> float:
        return float(self.T_ambient + self._wv_ring @ self.a)

    @property
    def T_hat(self) -> float:
        if self._wv_hat is None:
            return self.T_ring
        return float(self.T_ambient + self._wv_hat @ self.a)

    def state(self) -> tuple:
        """The reduced temperatures and the time, to :meth:`restore` later."""
        return self.a.copy(), self.time

    def restore(self, state: tuple) -> None:
        """Put back a :meth:`state`."""
        self.a, self.time = state[0].copy(), state[1]

    def coning(self, per_kelvin: float = HAT_CONING_PER_K) -> float:
        """The thermal coning across the pad (m) now: with :meth:`add_coning` the
        elastic rotor's own (the mean of its faces, times ``per_kelvin /
        HAT_CONING_PER_K``: a scale on it), else ``per_kelvin`` times the ring's mean
        temperature over the hat's."""
        if self._cone is not None:
            return float(np.mean(self._cone @ self.a)) * per_kelvin / HAT_CONING_PER_K
        return per_kelvin * (self.T_ring - self.T_hat)

    def add_coning(self, coning, reference: float | None = HAT_CONING_PER_K) -> None:
        """Take the coning from the elastic rotor: ``coning`` a
        :class:`~brakewear.thermal.coning.RotorConing` of the same rotor, applied to each
        basis vector once (the coning is linear in the temperature rise), so that
        :meth:`coning` is the elastic rotor's under the reduced field, radial and
        axial gradients included.  ``reference`` (m/K): scale it so that the ring
        heated evenly over a cold hat cones by ``reference`` per kelvin (the hat's
        converged figure; linear tetrahedra bend too stiffly and cone less on a
        coarse mesh); None: as it is.  The scale is kept as ``coning_scale``."""
        cols = [coning(self.T_ambient + self.V[:, j]) for j in range(self.V.shape[1])]
        faces = sorted(cols[0])
        base = coning(np.full(self.V.shape[0], self.T_ambient))
        self._cone = np.array([[c[f] - base[f] for c in cols] for f in faces])
        self.coning_scale = 1.0
        if reference is not None:
            ring = ~self._hat
            step = coning(self.T_ambient + 100.0 * ring)
            self.coning_step = float(np.mean([step[f] - base[f] for f in faces])) / 100.0
            self.coning_scale = reference / self.coning_step
        self._cone = self._cone * self.coning_scale

    # ------------------------------------------------------------------ input --
    def ring_powers(self, r, power, outboard=None, mirror: bool = False) -> np.ndarray:
        """Per input ring the power (W) of pad nodes at radii ``r`` (m) putting
        ``power`` (W, friction power of each node) into the rotor's friction faces
        (``outboard``: a mask of the nodes on the outboard face; None: all on the
        inboard face), times the rotor's share: each node's power to the two
        rings either side of its radius on its face, linearly in radius.  ``mirror``: the inboard
        nodes stand for
        both faces (a half model), their power also put into the outboard face."""
        r, power = np.asarray(r, dtype=float), np.asarray(power, dtype=float)
        out = np.zeros(r.size, dtype=bool) if outboard is None else np.asarray(outboard, bool)
        u = np.zeros(self.inputs.size)
        sides = [("in", ~out), ("out", out)] + ([("out", ~out)] if mirror else [])
        for face, mask in sides:
            idx = np.flatnonzero(self.face_of_ring[self.inputs] == face)
            if not mask.any():
                continue
            if idx.size == 0:
                raise ThermalError(f"the reduced rotor has no input ring on face {face!r}")
            order = np.argsort(self.radii[self.inputs[idx]])
            idx = idx[order]
            rr = self.radii[self.inputs[idx]]
            x = np.clip(r[mask], rr[0], rr[-1])
            j = np.clip(np.searchsorted(rr, x) - 1, 0, max(rr.size - 2, 0))
            if rr.size == 1:
                np.add.at(u, idx[j], power[mask])
                continue
            w = (x - rr[j]) / (rr[j + 1] - rr[j])        # linear in radius between rings
            np.add.at(u, idx[j], (1.0 - w) * power[mask])
            np.add.at(u, idx[j + 1], w * power[mask])
        return self.share * u

    # ----------------------------------------------------------------- march --
    def _march(self, u0: np.ndarray, u1: np.ndarray, omega0: float, omega1: float,
               duration: float, max_dt: float) -> None:
        n = max(1, int(np.ceil(duration / max_dt)))
        dt = duration / n
        for k in range(n):
            s0, s1 = k / n, (k + 1) / n
            u = u0 + (u1 - u0) * 0.5 * (s0 + s1)       # exact mean of a linear input
            w = omega0 + (omega1 - omega0) * 0.5 * (s0 + s1)
            self.a = sla.cho_solve(self._factor(dt, self._convection_scale(w)),
                                   self.M_r @ self.a / dt + self.B_r @ u)
        self.time += duration

    def _factor(self, dt: float, scale: float):
        """The Cholesky factor of ``M_r / dt + K_r + scale H_r``, kept per (dt, scale)."""
        key = (dt, scale)
        f = self._factors.get(key)
        if f is None:
            if len(self._factors) > 64:
                self._factors.clear()
            f = self._factors[key] = sla.cho_factor(self.M_r / dt + self.K_r + scale * self.H_r)
        return f

    def heat(self, u_start: np.ndarray, duration: float, omega0: float, omega1: float,
             u_end: np.ndarray | None = None, max_dt: float = 1.0) -> None:
        """A braked application: ring powers ``u_start`` (W, :meth:`ring_powers`) at its
        start falling linearly to ``u_end`` (default: in proportion to the speed,
        ``u_start omega1 / omega0``) over ``duration`` (s), the rotor slowing
        from ``omega0`` to ``omega1`` (rad/s)."""
        if not (np.isfinite(duration) and duration > 0):
            raise ThermalError(f"duration = {duration!r} s is not allowed; need > 0")
        u0 = np.asarray(u_start, dtype=float)
        u1 = u0 * (omega1 / omega0 if omega0 > 0 else 0.0) if u_end is None else u_end
        self._march(u0, np.asarray(u1, dtype=float), omega0, omega1, duration, max_dt)

    def cool(self, duration: float, omega: float = 0.0, max_dt: float = 5.0) -> None:
        """A pause of ``duration`` (s) with the rotor turning at ``omega`` (rad/s)."""
        z = np.zeros(self.inputs.size)
        self._march(z, z, omega, omega, duration, max_dt)


def hat_nodes(model) -> np.ndarray:
    """Mask of the rotor's nodes on the hat alone: not on an element of the ring (the
    mesh's ``ring`` subdomain, the neck over the hat wall included; without one, the
    nodes inside the friction ring's inner radius)."""
    mesh = model.meshes["rotor"]
    sub = getattr(mesh, "subdomains", None) or {}
    if "ring" in sub:
        hat = np.ones(mesh.p.shape[1], dtype=bool)
        hat[np.unique(mesh.t[:, sub["ring"]])] = False
        return hat
    return np.hypot(mesh.p[0], mesh.p[1]) < model.geometry.rotor.inner_radius * (1 - 1e-9)


def rotor_share_partition(thermal) -> float:
    """The pad's share of the frictional heat the reduced rotor takes: the thermal
    model's own, or with a contact conductance (whose net share comes out of the
    temperatures) the revolution-averaged effusivity share it lands near
    (docs/thermal.md)."""
    if thermal.contact_conductance == 0.0:
        return float(thermal.partition)
    g = thermal.model.geometry
    return float(partition_effusivity(g.pad.friction_material, g.rotor.material,
                                      g.pad.arc_angle / (2 * np.pi)))


def _ring_faces(model, x: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Each ring's face, ``"in"`` or ``"out"`` (the full model's outboard face is
    at ``z = -thickness``)."""
    n = int(ring.max()) + 1
    z = np.bincount(ring, weights=x[2], minlength=n) / np.bincount(ring, minlength=n)
    t = model.geometry.rotor.thickness
    return np.where(z < -0.5 * t, "out", "in") if getattr(model, "full", False) else \
        np.full(n, "in")


def _extend(V: np.ndarray, W: np.ndarray, M) -> np.ndarray:
    """``W`` made M-orthogonal to ``V`` (twice, for round-off) and M-orthonormal."""
    for _ in range(2):
        W = W - V @ (V.T @ (M @ W))
    return _m_orthonormal(W, M)


def _m_orthonormal(V: np.ndarray, M) -> np.ndarray:
    """An ``M``-orthonormal basis of the columns of ``V`` (dropping dependent ones)."""
    V = V / np.sqrt(np.einsum("ij,ij->j", V, M @ V))      # unit columns first
    G = V.T @ (M @ V)
    w, Q = np.linalg.eigh(0.5 * (G + G.T))
    keep = w > 1e-10 * w.max()
    return V @ (Q[:, keep] / np.sqrt(w[keep]))
