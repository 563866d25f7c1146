"""Frictional heating, heat conduction in pad and rotor, thermal strain load.

The pieces, from the bottom up:

* Form factories in scikit-fem style: :func:`conduction` (``kappa grad T .
  grad v``), :func:`capacity` (``rho c T v``), :func:`convection` (facet,
  ``h T v``) and :func:`surface_flux` (facet, ``q v`` with the flux ``q``
  given at the nodes and interpolated linearly).
* :class:`HeatConduction` -- one meshed body: the matrices assembled once,
  steady and implicit-Euler solves with a cached sparse factorisation per
  time step, an energy balance of every solve.
* :func:`partition_effusivity` -- the share of the frictional heat that
  enters the pad.
* :class:`ThermalModel` -- the brake: pad (friction layer and backplate) and
  rotor (if elastic), the pad's share of ``q = mu p v`` entering the pad at
  its friction nodes, the rotor's share spread over whole rings of the
  rotor's friction face (a revolution average, the same as the rotor's wear
  in :func:`brakewear.wear.rotor_wear_rate`), convection on free surfaces,
  and the thermal-strain load on the elasticity in the
  :class:`~brakewear.scene.BrakeModel`'s global numbering.

Temperatures are in kelvin.  The equations as implemented, the partition
formula and the stability of the staggered thermal-wear coupling are in
docs/thermal.md.
"""
from __future__ import annotations

import logging
from collections import OrderedDict
from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem as fem
from skfem.helpers import dot, grad

from .contact import surface_nodes, tributary_areas
from .elasticity import element_stress, voigt_strain
from .materials import Material, Thermal
from .mesh import _ensure_topology
from .wear import rotor_rings, rotor_wear_rate

logger = logging.getLogger(__name__)

__all__ = [
    "ThermalError",
    "conduction",
    "capacity",
    "convection",
    "surface_flux",
    "thermal_coupling",
    "partition_effusivity",
    "heat_flux",
    "FrictionLaw",
    "HeatConduction",
    "ThermalModel",
    "thermal_load_matrix",
    "thermal_stress",
    "staggered_amplification",
    "H_CONV_DEFAULT",
    "T_AMBIENT_DEFAULT",
]

#: Default convection coefficient on free surfaces (W/m^2 K).  A solid rotor
#: turning at 50-100 rad/s sees roughly 20-100 W/m^2 K (forced convection of a
#: rotating disc); 40 is a moderate value for a light drag.  Calibrate it.
H_CONV_DEFAULT = 40.0
#: Default ambient (and stress-free reference) temperature, 20 C in kelvin.
T_AMBIENT_DEFAULT = 293.15

_THERMAL_FIELDS = ("rho", "c", "kappa", "alpha")


class ThermalError(ValueError):
    """Invalid thermal input; the message names the body, the field and the value."""


# ------------------------------------------------------------------ forms ---

def conduction(kappa: float | None = None) -> fem.BilinearForm:
    """``kappa grad T . grad v``; ``kappa=None`` reads ``w['kappa']``."""

    @fem.BilinearForm
    def form(u, v, w):
        k = w["kappa"] if kappa is None else kappa
        return k * dot(grad(u), grad(v))

    return form


def capacity(rho_c: float | None = None) -> fem.BilinearForm:
    """``rho c T v`` (volumetric heat capacity, J/m^3 K); ``None`` reads ``w['rho_c']``."""

    @fem.BilinearForm
    def form(u, v, w):
        rc = w["rho_c"] if rho_c is None else rho_c
        return rc * u * v

    return form


def convection(h: float) -> fem.BilinearForm:
    """Facet form ``h T v`` of convection to ambient (W/m^2 K); the ambient
    part ``h T_amb v`` is :func:`surface_flux` with ``q = h T_amb``."""

    @fem.BilinearForm
    def form(u, v, w):
        return h * u * v

    return form


# HeatConduction's argument ``convection`` shadows the factory inside __init__
_convection_form = convection


def surface_flux() -> fem.LinearForm:
    """Facet form ``q v`` of a heat flux into the body; ``q`` arrives as ``w['q']``
    (a field interpolated from nodal values, W/m^2)."""

    @fem.LinearForm
    def form(v, w):
        return w["q"] * v

    return form


def thermal_coupling(C: np.ndarray, alpha: float) -> fem.BilinearForm:
    """Mixed form ``dT (C : alpha I) : eps(v)``: scalar trial ``dT``, vector test ``v``.

    Its matrix ``G`` (3N x N) turns a nodal temperature rise into the load of
    :func:`brakewear.elasticity.thermal_strain_form`: ``f = G dT`` (tested
    equal to round-off).  Assembled once, the load of every step is then a
    sparse product.
    """
    s = np.asarray(C, dtype=float) @ np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]) * alpha

    @fem.BilinearForm
    def form(u, v, w):
        ev = voigt_strain(v)
        return u * sum(s[i] * ev[i] for i in range(6) if s[i] != 0.0)

    return form


# ------------------------------------------------------------- materials ---

def _check_thermal(th, where: str, fields: Sequence[str] = ("rho", "c", "kappa")) -> Thermal:
    """The :class:`Thermal` data of a material, checked; errors name ``where`` and the field."""
    if isinstance(th, Material):
        th = th.thermal
    if th is None:
        raise ThermalError(f"{where}: thermal data missing (field 'thermal' is None); give "
                           f"rho, c, kappa and alpha (brakewear.materials.Thermal)")
    for key in fields:
        v = getattr(th, key, None)
        if v is None:
            raise ThermalError(f"{where}: thermal field {key!r} is missing; it must be a "
                               "number > 0")
        try:
            ok = np.isfinite(float(v)) and float(v) > 0.0
        except (TypeError, ValueError):
            ok = False
        if not ok:
            unit = {"rho": "kg/m^3", "c": "J/kg K", "kappa": "W/m K", "alpha": "1/K"}[key]
            raise ThermalError(f"{where}: {key} = {v!r} {unit} is not allowed; it must be a "
                               "finite number > 0")
    return th


def _groups(mesh: fem.Mesh, materials, name: str) -> list[tuple[np.ndarray, object]]:
    """Normalise ``materials`` (one material, or (elements, material) pairs) to a list
    covering every element of ``mesh`` once."""
    if isinstance(materials, (Material, Thermal)) or materials is None:
        return [(np.arange(mesh.nelements), materials)]
    out = [(np.arange(mesh.nelements) if e is None else np.asarray(e, dtype=np.int64), m)
           for e, m in materials]
    count = np.bincount(np.concatenate([e for e, _ in out]), minlength=mesh.nelements)
    if count.size != mesh.nelements or np.any(count != 1):
        raise ThermalError(f"body {name!r}: the material groups must cover every one of the "
                           f"{mesh.nelements} elements exactly once")
    return out


def _label(name: str, mat) -> str:
    mname = getattr(mat, "name", None)
    return f"body {name!r}" + (f" (material {mname!r})" if mname else "")


def partition_effusivity(mat_pad, mat_rotor, area_ratio: float | None = None) -> float:
    """Share of the frictional heat that enters the pad.

    ``e = sqrt(kappa rho c)`` (effusivity).  Two half-spaces heated through
    a common face from the same instant have surface temperatures
    ``2 q_i sqrt(t) / (sqrt(pi) e_i)``; equal temperatures on both sides
    give ``q_pad / e_pad = q_rotor / e_rotor``, so::

        fraction_pad = e_pad / (e_pad + e_rotor)            (area_ratio None)

    With ``area_ratio = A_pad / A_swept`` (pad face over the ring it sweeps)
    the rotor's flux is first averaged over a revolution (its mean density
    is ``q_rotor A_pad / A_swept``) and the *mean* surface temperatures are
    matched::

        fraction_pad = e_pad A_pad / (e_pad A_pad + e_rotor A_swept)

    Parameters
    ----------
    mat_pad, mat_rotor
        :class:`~brakewear.materials.Material` or :class:`~brakewear.materials.Thermal`.
    area_ratio
        ``A_pad / A_swept`` in (0, 1], or None.
    """
    e_p = _check_thermal(mat_pad, "pad").effusivity
    e_r = _check_thermal(mat_rotor, "rotor").effusivity
    if area_ratio is None:
        return e_p / (e_p + e_r)
    if not (np.isfinite(area_ratio) and 0.0 < area_ratio <= 1.0):
        raise ThermalError(f"area_ratio = {area_ratio!r} is not allowed; it must lie in (0, 1]")
    return e_p * area_ratio / (e_p * area_ratio + e_r)


def heat_flux(p: np.ndarray, v: np.ndarray, mu) -> np.ndarray:
    """Frictional heat flux ``q = mu p v`` (W/m^2) at the contact nodes.

    ``p`` (Pa; tension counts as zero), ``v`` sliding speed (m/s, >= 0),
    ``mu`` a number or an array per node (e.g. :meth:`FrictionLaw.mu` of the
    face temperature).
    """
    p = np.asarray(p, dtype=float)
    v = np.asarray(v, dtype=float)
    mu = np.asarray(mu, dtype=float)
    if np.any(v < 0) or not np.all(np.isfinite(v)):
        raise ThermalError(f"sliding speed min {v.min()!r} m/s is not allowed; need finite v >= 0")
    if np.any(mu < 0) or not np.all(np.isfinite(mu)):
        raise ThermalError(f"friction coefficient min {mu.min()!r} is not allowed; need mu >= 0")
    return mu * np.clip(p, 0.0, None) * v


@dataclass(frozen=True)
class FrictionLaw:
    """Temperature-dependent friction (fade): ``mu(T) = max(mu_min, mu0 + slope (T - T_ref))``.

    ``slope = 0`` (default) is a constant ``mu0``.  A resin-bonded pad fades
    above a few hundred degrees C: a negative slope above ``T_ref`` models
    it to first order.
    """

    mu0: float
    slope: float = 0.0       # 1/K
    T_ref: float = T_AMBIENT_DEFAULT
    mu_min: float = 0.0

    def __post_init__(self):
        for key in ("mu0", "mu_min"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v >= 0):
                raise ThermalError(f"FrictionLaw: {key} = {v!r} is not allowed; need >= 0")
        if not np.isfinite(self.slope):
            raise ThermalError(f"FrictionLaw: slope = {self.slope!r} is not allowed; need finite")

    def mu(self, T=None):
        """``mu`` at temperature ``T`` (K; None: ``mu0``)."""
        if T is None or self.slope == 0.0:
            return self.mu0
        return np.maximum(self.mu_min, self.mu0 + self.slope * (np.asarray(T, float) - self.T_ref))


# ------------------------------------------------------- one body's heat ---

class HeatConduction:
    """Heat conduction in one meshed body (P1 tetrahedra), assembled once.

    ``rho c dT/dt - div(kappa grad T) = 0`` with a flux ``q`` into the body
    on ``flux_facets``, convection ``-kappa dT/dn = h (T - T_ambient)`` on
    each ``convection`` facet set, fixed temperatures on ``fixed``, and
    ``dT/dn = 0`` elsewhere (symmetry planes, insulated faces).

    Parameters
    ----------
    mesh
        P1 ``MeshTet`` with named facets.
    materials
        A :class:`~brakewear.materials.Material` / :class:`Thermal`, or a list
        of ``(element indices, material)`` covering the mesh.
    flux_facets
        Name of the facets where the heat enters (``None``: no flux input).
    convection
        Facet name -> ``h`` (W/m^2 K).
    T_ambient
        Ambient temperature (K) of the convection.
    fixed
        Facet name -> fixed temperature (K).
    mass
        ``"consistent"`` (default) or ``"lumped"`` (row sums; keeps an
        early, steep transient free of undershoot).
    name
        Body name used in messages.
    contact_conductance
        ``h_c`` (W/m^2 K) on the flux facets, lumped at their nodes: the term
        ``h_c A_i T_i`` is part of the matrix (``Hc``); the other side's
        ``h_c A_i T_other`` arrives with the load (:class:`ThermalModel`).
    reuse
        ``"octave"`` (default): a step ``dt`` is solved by CG preconditioned
        with the factorisation of the nearest power of two (see
        :meth:`solve`); ``"exact"``: one factorisation per distinct ``dt``.
    """

    #: factorisations kept per body (one per time step size in use)
    cache_size = 4
    #: relative residual of the preconditioned CG solves (see :meth:`solve`)
    cg_tol = 1e-12

    def __init__(self, mesh: fem.Mesh, materials, flux_facets: str | None = None,
                 convection: Mapping[str, float] | None = None,
                 T_ambient: float = T_AMBIENT_DEFAULT, fixed: Mapping[str, float] | None = None,
                 mass: str = "consistent", name: str = "body",
                 contact_conductance: float = 0.0, reuse: str = "octave"):
        self.name = name
        if reuse not in ("octave", "exact"):
            raise ThermalError(f"body {name!r}: reuse = {reuse!r}; allowed: 'octave', 'exact'")
        self.reuse = reuse
        self.cg_iterations = 0
        if not isinstance(mesh, fem.MeshTet1):
            raise ThermalError(f"body {name!r}: mesh type {type(mesh).__name__} is not supported; "
                               "heat conduction uses P1 tetrahedra (MeshTet)")
        if mass not in ("consistent", "lumped"):
            raise ThermalError(f"body {name!r}: mass = {mass!r}; allowed: 'consistent', 'lumped'")
        if not np.isfinite(T_ambient) or T_ambient <= 0:
            raise ThermalError(f"body {name!r}: T_ambient = {T_ambient!r} K is not allowed; "
                               "need a temperature > 0 K")
        convection = dict(convection or {})
        fixed = dict(fixed or {})
        names = set(mesh.boundaries or {})
        for label, d in (("convection", convection), ("fixed", fixed)):
            for key in d:
                if key not in names:
                    raise ThermalError(f"body {name!r}: {label} facets {key!r} do not exist; "
                                       f"named facets: {sorted(names)}")
        if flux_facets is not None and flux_facets not in names:
            raise ThermalError(f"body {name!r}: flux facets {flux_facets!r} do not exist; "
                               f"named facets: {sorted(names)}")
        for key, h in convection.items():
            if not (np.isfinite(h) and h >= 0):
                raise ThermalError(f"body {name!r}: convection coefficient h = {h!r} W/m^2 K on "
                                   f"{key!r} is not allowed; need h >= 0")
        for key, T in fixed.items():
            if not (np.isfinite(T) and T > 0):
                raise ThermalError(f"body {name!r}: fixed temperature {T!r} K on {key!r} is not "
                                   "allowed; need T > 0 K")
        if not (np.isfinite(contact_conductance) and contact_conductance >= 0):
            raise ThermalError(f"body {name!r}: contact_conductance = {contact_conductance!r} "
                               "W/m^2 K is not allowed; need >= 0")
        if contact_conductance > 0 and flux_facets is None:
            raise ThermalError(f"body {name!r}: contact_conductance needs flux_facets")
        groups = _groups(mesh, materials, name)
        self.thermal = [(e, _check_thermal(m, _label(name, m))) for e, m in groups]
        self.mesh, self.T_ambient, self.mass_kind = mesh, float(T_ambient), mass
        _ensure_topology(mesh)
        elem = fem.ElementTetP1()
        N = mesh.nvertices
        self.K = sp.csr_matrix((N, N))
        self.M = sp.csr_matrix((N, N))
        for e, th in self.thermal:
            b = fem.Basis(mesh, elem, intorder=2, elements=e)
            self.K = self.K + conduction(th.kappa).assemble(b)
            self.M = self.M + capacity(th.rho * th.c).assemble(b)
        if mass == "lumped":
            self.M = sp.diags(np.asarray(self.M.sum(axis=1)).ravel()).tocsr()
        self.H = sp.csr_matrix((N, N))
        self.b_amb = np.zeros(N)
        for key, h in convection.items():
            fb = fem.FacetBasis(mesh, elem, facets=mesh.boundaries[key], intorder=2)
            self.H = self.H + _convection_form(h).assemble(fb)
            self.b_amb += surface_flux().assemble(fb, q=h * self.T_ambient)
        self.K, self.M, self.H = self.K.tocsr(), self.M.tocsr(), self.H.tocsr()
        self.convection = convection
        # flux input: F = S q with q at the face nodes (S = surface mass, columns of the face)
        self.flux_facets = flux_facets
        if flux_facets is not None:
            self.face = surface_nodes(mesh, flux_facets)
            fb = fem.FacetBasis(mesh, elem, facets=mesh.boundaries[flux_facets], intorder=2)
            Ms = fem.BilinearForm(lambda u, v, w: u * v).assemble(fb).tocsc()
            self.S = Ms[:, self.face].tocsr()
            self.face_area = tributary_areas(mesh, flux_facets, self.face)
        else:
            self.face = np.zeros(0, dtype=np.int64)
            self.S = sp.csr_matrix((N, 0))
            self.face_area = np.zeros(0)
        # fixed temperatures
        fixed_nodes = np.zeros(N, dtype=bool)
        self.T_fixed = np.zeros(N)
        for key, T in fixed.items():
            nodes = surface_nodes(mesh, key)
            fixed_nodes[nodes] = True
            self.T_fixed[nodes] = T
        self.fixed_mask = fixed_nodes
        self.free = np.flatnonzero(~fixed_nodes)
        d = np.zeros(N)
        d[self.face] = contact_conductance * self.face_area
        self.Hc = sp.diags(d).tocsr()
        self.contact_conductance = float(contact_conductance)
        self._lu: OrderedDict = OrderedDict()
        self.factorizations = 0

    # -------------------------------------------------------------------
    @property
    def n(self) -> int:
        return self.mesh.nvertices

    def flux_load(self, q: np.ndarray) -> np.ndarray:
        """Nodal heat input (W) of a flux ``q`` (W/m^2) given at the face nodes."""
        q = np.asarray(q, dtype=float)
        if q.shape != self.face.shape:
            raise ThermalError(f"body {self.name!r}: flux has shape {q.shape}; need "
                               f"{self.face.shape} (one value per {self.flux_facets!r} node)")
        if not np.all(np.isfinite(q)):
            raise ThermalError(f"body {self.name!r}: the heat flux has non-finite values")
        return self.S @ q

    def _factor(self, dt: float | None):
        key = None if dt is None else float(dt)
        if key in self._lu:
            self._lu.move_to_end(key)
            return self._lu[key]
        A = self.K + self.H + self.Hc + (0.0 if key is None else self.M / key)
        Aff = A[self.free][:, self.free].tocsc()
        try:
            lu = spla.splu(Aff, permc_spec="MMD_AT_PLUS_A")
        except RuntimeError as exc:  # exactly singular
            raise ThermalError(self._singular_message()) from exc
        self._lu[key] = (lu, A)
        self.factorizations += 1
        if len(self._lu) > self.cache_size:
            self._lu.popitem(last=False)
        return lu, A

    def _singular_message(self) -> str:
        return (f"body {self.name!r}: the steady heat problem is singular: no convection "
                "(h > 0) and no fixed temperature, so the temperature level is undetermined; "
                "give h_conv > 0 or solve transient steps")

    def solve(self, dt: float | None, rhs: np.ndarray) -> np.ndarray:
        """Solve ``A(dt) T = rhs`` (``dt=None``: steady).

        ``rhs`` may be (N,) or (N, k) (k right-hand sides, then the fixed
        temperatures are taken as zero: for influence columns).

        With ``reuse="octave"`` (default) a single right-hand side is solved
        by CG preconditioned with the factorisation of ``A(dt0)``, ``dt0 =
        2^round(log2 dt)`` (exact when ``dt == dt0``): the preconditioned
        spectrum lies between 1 and ``dt0/dt`` (``M/dt`` is the only change),
        within a factor sqrt(2), so 6-10 iterations reach ``cg_tol``.  A wear
        loop whose step varies continuously then factorises once per octave
        of ``dt`` instead of once per step, and the result depends on ``dt``
        alone, never on the cache (an exactly resumed run repeats itself).
        ``reuse="exact"`` factorises every new ``dt``.
        """
        if dt is None and not self.fixed_mask.any() and self.contact_conductance == 0 and not any(
                h > 0 for h in self.convection.values()):
            raise ThermalError(self._singular_message())
        if dt is not None and rhs.ndim == 1 and self.reuse == "octave":
            dt0 = float(2.0 ** np.round(np.log2(dt)))
            if dt0 != float(dt):
                return self._pcg(dt, rhs, dt0, self._factor(dt0)[0])
        lu, A = self._factor(dt)
        if rhs.ndim == 2:
            T = np.zeros(rhs.shape)
            T[self.free] = lu.solve(np.ascontiguousarray(rhs[self.free]))
        else:
            T = self.T_fixed.copy()
            r = rhs - A @ T
            T[self.free] = lu.solve(r[self.free])
        if not np.all(np.isfinite(T)):
            raise ThermalError(f"body {self.name!r}: the heat solve gave non-finite temperatures")
        return T

    def _pcg(self, dt: float, rhs: np.ndarray, dt0: float, lu) -> np.ndarray:
        """CG on ``A(dt)``, preconditioned by the factorisation of ``A(dt0)``."""
        A = (self.K + self.H + self.Hc + self.M / dt).tocsr()
        T = self.T_fixed.copy()
        f = self.free
        Aff = A if f.size == self.n else A[f][:, f].tocsr()
        b = (rhs - A @ T)[f]
        x = lu.solve(b)
        r = b - Aff @ x
        z = lu.solve(r)
        d = z.copy()
        rz = r @ z
        nb = np.linalg.norm(b)
        it = 0
        while np.linalg.norm(r) > self.cg_tol * nb and it < 100:
            Ad = Aff @ d
            a = rz / (d @ Ad)
            x += a * d
            r -= a * Ad
            z = lu.solve(r)
            rz, rz_old = r @ z, rz
            d = z + (rz / rz_old) * d
            it += 1
        res = np.linalg.norm(b - Aff @ x) / max(nb, 1e-300)
        if not np.isfinite(res) or res > 10 * self.cg_tol:
            raise ThermalError(f"body {self.name!r}: CG with the factorisation of dt = {dt0} "
                               f"did not reach {self.cg_tol:.0e} for dt = {dt} (relative "
                               f"residual {res:.2e} after {it} iterations)")
        self.cg_iterations = it
        T[f] = x
        return T

    def rhs(self, T: np.ndarray | None, F: np.ndarray, dt: float | None) -> np.ndarray:
        """Right-hand side of a step from ``T`` (``dt``) or of the steady state (``None``)."""
        return F + self.b_amb + (0.0 if dt is None else self.M @ T / dt)

    def steady(self, F: np.ndarray) -> np.ndarray:
        """Steady temperature for nodal heat input ``F`` (W; see :meth:`flux_load`)."""
        return self.solve(None, self.rhs(None, F, None))

    def step(self, T: np.ndarray, F: np.ndarray, dt: float) -> np.ndarray:
        """One implicit-Euler step of size ``dt`` (s) from ``T`` with input ``F`` (W)."""
        if not (np.isfinite(dt) and dt > 0):
            raise ThermalError(f"body {self.name!r}: time step dt = {dt!r} s is not allowed; "
                               "need dt > 0")
        return self.solve(dt, self.rhs(T, F, dt))

    def balance(self, T0: np.ndarray | None, T1: np.ndarray, F: np.ndarray,
                dt: float | None) -> dict:
        """Energy balance of a solve (W): heat in = stored + convected + to fixed faces.

        ``stored`` is ``1^T M (T1 - T0) / dt`` (0 for a steady solve);
        conduction moves heat inside the body and sums to zero
        (``1^T K = 0``).  ``relative_error`` is the mismatch over the input.
        """
        stored = 0.0 if dt is None else float(np.sum(self.M @ (T1 - T0)) / dt)
        convected = float(np.sum(self.H @ T1 - self.b_amb))
        contact = float(np.sum(self.Hc @ T1))
        # heat leaving through fixed-temperature faces: the reactions
        A = self.K + self.H + self.Hc + (0.0 if dt is None else self.M / dt)
        to_fixed = -float(np.sum((A @ T1 - self.rhs(T0, F, dt))[self.fixed_mask]))
        heat_in = float(np.sum(F))
        scale = max(abs(heat_in), abs(stored), abs(convected), abs(contact), 1e-300)
        return {"heat_in_W": heat_in, "stored_W": stored, "convected_W": convected,
                "to_fixed_W": to_fixed, "to_contact_W": contact,
                "relative_error": abs(heat_in - stored - convected - to_fixed - contact) / scale}


# --------------------------------------------------------- thermal strain ---

def _elastic_groups(mesh: fem.Mesh, materials, name: str) -> list[tuple[np.ndarray, Material]]:
    groups = _groups(mesh, materials, name)
    for _, m in groups:
        if not isinstance(m, Material):
            raise ThermalError(f"body {name!r}: a thermal-strain load needs Material objects "
                               f"(elastic and thermal data), got {type(m).__name__}")
        _check_thermal(m, _label(name, m), ("alpha",))
    return groups


def thermal_load_matrix(mesh: fem.Mesh, materials, name: str = "body") -> sp.csr_matrix:
    """``G`` (3N x N): the thermal-strain load is ``G @ (T - T_ref)`` (N per node).

    Vector DOF ``3 s + i`` as in :mod:`brakewear.elasticity`; each material
    group contributes with its own ``C`` and ``alpha``.
    """
    if not isinstance(mesh, fem.MeshTet1):
        raise ThermalError(f"body {name!r}: thermal load needs a P1 MeshTet, got "
                           f"{type(mesh).__name__}")
    G = sp.csr_matrix((3 * mesh.nvertices, mesh.nvertices))
    for e, m in _elastic_groups(mesh, materials, name):
        sb = fem.Basis(mesh, fem.ElementTetP1(), intorder=1, elements=e)
        vb = fem.Basis(mesh, fem.ElementVector(fem.ElementTetP1()), intorder=1, elements=e)
        G = G + thermal_coupling(m.voigt(), m.thermal.alpha).assemble(sb, vb)
    return G.tocsr()


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


# ------------------------------------------------------------ the brake ---

class ThermalModel:
    """Temperatures of the brake's pad and rotor, driven by frictional heat.

    Parameters
    ----------
    model
        A :class:`brakewear.scene.BrakeModel`.  The pad (friction layer and
        backplate) always gets a temperature field; the rotor only if it is
        elastic (meshed).  The piston is not heated (its temperature stays at
        ``T_ref``: no thermal strain).
    partition
        ``"effusivity"`` (default; :func:`partition_effusivity`),
        ``"effusivity_area"`` (the revolution-averaged variant) or a number in
        [0, 1]: the share of ``q`` that enters the pad.  The rest enters the
        rotor (with a rigid rotor it leaves the model; reported as
        ``rotor_unmodelled_W`` by :meth:`heat_balance`).
    h_conv
        Convection coefficient (W/m^2 K): one number for all free faces or
        ``{"pad": h, "rotor": h}``.
    T_ambient, T_ref
        Ambient temperature (K) and stress-free reference (default ambient).
    convection_facets
        Free faces per body; default: pad ``back, leading, trailing, inner,
        outer`` (all but the friction face); rotor ``friction, outer,
        rotor_clamp`` (the friction face sheds heat for the part of each
        revolution it is not under the pad, which is 85 % of it for a 55 deg
        pad; the midplane is a symmetry plane: insulated).
    mass
        ``"consistent"`` or ``"lumped"`` capacity matrix.
    T_initial
        Initial temperature (K), default ``T_ambient``.
    contact_conductance
        ``h_c`` (W/m^2 K, default 0: off).  Besides its share of ``q``, each
        pad friction node exchanges ``h_c A_i (T_pad,i - T_ring,i)`` with the
        rotor, ``T_ring,i`` the area-weighted mean temperature of the rotor
        rings under it (the revolution average again); the rotor receives
        it spread over those rings.  Solved monolithically in each step
        (through the ring means, a few dense unknowns: see :meth:`_coupled`),
        so a large ``h_c`` drives the pad face toward the rotor's ring
        temperature and the effective partition follows.  Needs an elastic
        (meshed) rotor.
    """

    PAD_FACETS = ("back", "leading", "trailing", "inner", "outer")
    ROTOR_FACETS = ("friction", "outer", "rotor_clamp")

    def __init__(self, model, partition: str | float = "effusivity",
                 h_conv: float | Mapping[str, float] = H_CONV_DEFAULT,
                 T_ambient: float = T_AMBIENT_DEFAULT, T_ref: float | None = None,
                 convection_facets: Mapping[str, Sequence[str]] | None = None,
                 mass: str = "consistent", T_initial: float | None = None,
                 contact_conductance: float = 0.0):
        self.model = model
        self.bodies = tuple(b for b in ("rotor", "pad") if b in model.bodies)
        if "pad" not in self.bodies:
            raise ThermalError("the brake model has no pad body")
        # ---- input checks first (nothing is assembled before they pass)
        for b in self.bodies:
            for e, m in model.materials[b]:
                _check_thermal(m, _label(b, m), _THERMAL_FIELDS)
        g = model.geometry
        rotor_mat = (self._face_material("rotor") if "rotor" in self.bodies
                     else g.rotor.material)
        if "rotor" not in self.bodies:
            _check_thermal(rotor_mat, _label("rotor", rotor_mat))
        pad_mat = self._face_material("pad")
        if isinstance(partition, str):
            if partition == "effusivity":
                gamma = partition_effusivity(pad_mat, rotor_mat)
            elif partition == "effusivity_area":
                ratio = g.pad.arc_angle / (2 * np.pi)  # pad area / swept ring area
                gamma = partition_effusivity(pad_mat, rotor_mat, ratio)
            else:
                raise ThermalError(f"partition = {partition!r} is not allowed; allowed: "
                                   "'effusivity', 'effusivity_area' or a number in [0, 1]")
        else:
            try:
                gamma = float(partition)
            except (TypeError, ValueError):
                raise ThermalError(
                    f"partition = {partition!r} is not allowed; allowed: 'effusivity', "
                    "'effusivity_area' or a number in [0, 1]") from None
            if not (np.isfinite(gamma) and 0.0 <= gamma <= 1.0):
                raise ThermalError(f"partition = {partition!r} (share of the heat into the pad) "
                                   "is not allowed; it must lie in [0, 1]")
        self.partition = gamma
        hs = dict(h_conv) if isinstance(h_conv, Mapping) else {b: h_conv for b in self.bodies}
        for b in self.bodies:
            h = hs.get(b, H_CONV_DEFAULT)
            if not (np.isfinite(h) and h >= 0):
                raise ThermalError(f"body {b!r}: h_conv = {h!r} W/m^2 K is not allowed; need >= 0")
        h_c = contact_conductance
        if not (isinstance(h_c, (int, float, np.floating)) and np.isfinite(h_c) and h_c >= 0):
            raise ThermalError(f"contact_conductance = {h_c!r} W/m^2 K is not allowed; need a "
                               "number >= 0")
        if h_c > 0 and "rotor" not in self.bodies:
            raise ThermalError("contact_conductance > 0 needs an elastic (meshed) rotor; this "
                               f"model's rotor is {model.rotor!r}")
        self.contact_conductance = float(h_c)
        facets = {"pad": self.PAD_FACETS, "rotor": self.ROTOR_FACETS}
        facets.update(dict(convection_facets or {}))
        self.T_ambient = float(T_ambient)
        self.T_ref = self.T_ambient if T_ref is None else float(T_ref)
        if not (np.isfinite(self.T_ref) and self.T_ref > 0):
            raise ThermalError(f"T_ref = {T_ref!r} K is not allowed; need > 0 K")
        # ---- assembly (once)
        self.heat = {b: HeatConduction(model.meshes[b], model.materials[b], "friction",
                                       {f: hs.get(b, H_CONV_DEFAULT) for f in facets[b]},
                                       T_ambient, mass=mass, name=b,
                                       contact_conductance=h_c if b == "pad" else 0.0)
                     for b in self.bodies}
        pad = model.meshes["pad"]
        self.pad_nodes = self.heat["pad"].face
        self.pad_area = self.heat["pad"].face_area
        x = pad.p[:, self.pad_nodes]
        self.pad_radius = np.hypot(x[0], x[1])
        if "rotor" in self.bodies:
            rotor = model.meshes["rotor"]
            face = self.heat["rotor"].face
            pair = model.contact_pair(0.0)
            self.coupling = pair.coupling[:, face + model.offsets["rotor"]].tocsr()
            self.ring, self.ring_radii = rotor_rings(np.hypot(rotor.p[0, face], rotor.p[1, face]))
            self.rotor_area = self.heat["rotor"].face_area
            if h_c > 0:
                n_ring = int(self.ring.max()) + 1
                E = sp.csr_matrix((np.ones(face.size), (np.arange(face.size), self.ring)),
                                  shape=(face.size, n_ring))
                ring_area = np.bincount(self.ring, weights=self.rotor_area)
                # V: ring means seen by each pad node (rows sum to 1); U: a ring's
                # power spread uniformly over its area (columns sum to 1); the ring
                # mean temperature is U^T T_rotor
                self._V = np.asarray((self.coupling @ E).todense())
                self._U = np.asarray((self.heat["rotor"].S @ E
                                      @ sp.diags(1.0 / ring_area)).todense())
                self._DV = np.zeros((self.heat["pad"].n, n_ring))
                self._DV[self.pad_nodes] = (h_c * self.pad_area)[:, None] * self._V
                self._influence: OrderedDict = OrderedDict()
        self._G: dict[str, sp.csr_matrix] = {}
        T0 = self.T_ambient if T_initial is None else float(T_initial)
        self.T = {b: np.full(self.heat[b].n, T0) for b in self.bodies}
        self.time = 0.0
        self._last: dict | None = None
        logger.info("thermal model: bodies %s, pad share %.4f, %s nodes", self.bodies, gamma,
                    {b: self.heat[b].n for b in self.bodies})

    def _face_material(self, body: str):
        """The material of the elements on the body's friction face (must be one)."""
        mesh = self.model.meshes[body]
        _ensure_topology(mesh)
        elems = mesh.f2t[0, mesh.boundaries["friction"]]
        found = [m for e, m in self.model.materials[body] if np.isin(elems, e).any()]
        if len(found) != 1:
            raise ThermalError(f"body {body!r}: the friction face touches {len(found)} materials; "
                               "the heat partition needs exactly one")
        return found[0]

    # ----------------------------------------------------------- fluxes --
    def flux(self, p: np.ndarray, mu, omega: float) -> np.ndarray:
        """``q = mu p omega r`` at the pad's friction nodes (W/m^2)."""
        if not (np.isfinite(omega) and omega >= 0):
            raise ThermalError(f"omega = {omega!r} rad/s is not allowed; need >= 0")
        return heat_flux(p, omega * self.pad_radius, mu)

    def _loads(self, q_pad: np.ndarray) -> tuple[dict, dict]:
        q = np.asarray(q_pad, dtype=float)
        if q.shape != self.pad_nodes.shape:
            raise ThermalError(f"q_pad has shape {q.shape}; need {self.pad_nodes.shape} (one "
                               "value per pad friction node, order of surface_nodes(pad, "
                               "'friction'))")
        if not np.all(np.isfinite(q)) or np.any(q < 0):
            raise ThermalError(f"q_pad must be finite and >= 0 (friction heats); min {q.min()!r}")
        power = float(q @ self.pad_area)
        F = {"pad": self.heat["pad"].flux_load(self.partition * q)}
        figures = {"friction_power_W": power, "rotor_unmodelled_W": 0.0}
        rotor_power = (1.0 - self.partition) * q * self.pad_area
        if "rotor" in self.bodies:
            q_rot = rotor_wear_rate(rotor_power, self.coupling, self.ring, self.rotor_area)
            F["rotor"] = self.heat["rotor"].flux_load(q_rot)
        else:
            figures["rotor_unmodelled_W"] = float(rotor_power.sum())
        return F, figures

    # ----------------------------------------------------------- solves --
    def _solve(self, q_pad: np.ndarray, dt: float | None) -> dict:
        F, figs = self._loads(q_pad)
        old = self.T
        figs["friction_in"] = {b: float(np.sum(F[b])) for b in self.bodies}
        figs["exchange_W"] = 0.0
        if self.contact_conductance == 0.0:
            self.T = {b: self.heat[b].solve(dt, self.heat[b].rhs(old[b], F[b], dt))
                      for b in self.bodies}
        else:
            self.T, F, figs["exchange_W"] = self._coupled(old, F, dt)
        self._last = {"F": F, "old": old, "dt": dt, **figs}
        return self.T

    def _coupled(self, old: dict, F: dict, dt: float | None):
        """Pad and rotor coupled through the contact conductance, solved exactly.

        The coupling acts only through the ring means ``tau = U^T T_rotor``
        and the ring exchange powers ``g = h_c V^T A (T_pad,face - V tau)``:
        with the influence columns ``Z_p = A_p^-1 (h_c A V)`` and
        ``Z_r = A_r^-1 U`` (cached per ``dt``), the uncoupled solutions plus
        ``Z_p tau`` and ``Z_r g`` solve the monolithic system, and ``tau``
        comes from a dense n_ring x n_ring system.
        """
        pad, rot = self.heat["pad"], self.heat["rotor"]
        key = None if dt is None else float(dt)
        if key not in self._influence:
            Zp = pad.solve(dt, self._DV)
            Zr = rot.solve(dt, self._U)
            DVf = self._DV[self.pad_nodes]
            G = DVf.T @ Zp[self.pad_nodes] - DVf.T @ self._V
            self._influence[key] = (Zp, Zr, self._U.T @ Zr, G)
            if len(self._influence) > HeatConduction.cache_size:
                self._influence.popitem(last=False)
        Zp, Zr, R, G = self._influence[key]
        Tp = pad.solve(dt, pad.rhs(old["pad"], F["pad"], dt))
        Tr = rot.solve(dt, rot.rhs(old["rotor"], F["rotor"], dt))
        g0 = self._DV[self.pad_nodes].T @ Tp[self.pad_nodes]
        tau0 = self._U.T @ Tr
        tau = np.linalg.solve(np.eye(R.shape[0]) - R @ G, tau0 + R @ g0)
        g = g0 + G @ tau
        T = {"pad": Tp + Zp @ tau, "rotor": Tr + Zr @ g}
        Ftot = {"pad": F["pad"] + self._DV @ tau, "rotor": F["rotor"] + self._U @ g}
        return T, Ftot, float(g.sum())

    def step(self, q_pad: np.ndarray, dt: float) -> dict:
        """Advance all bodies by one implicit-Euler step ``dt`` (s) under ``q_pad``
        (W/m^2 at the pad's friction nodes); returns the new temperatures."""
        if not (np.isfinite(dt) and dt > 0):
            raise ThermalError(f"dt = {dt!r} s is not allowed; need dt > 0")
        self._solve(q_pad, dt)
        self.time += dt
        return self.T

    def steady(self, q_pad: np.ndarray) -> dict:
        """Steady temperatures under ``q_pad`` (needs convection)."""
        return self._solve(q_pad, None)

    def heat_balance(self) -> dict:
        """Energy figures of the last solve (W).

        ``heat_into_bodies_W`` counts the friction heat only;
        ``exchange_pad_to_rotor_W`` is the net contact-conductance flow
        (the bodies' ``heat_in_W`` include it, their ``to_contact_W`` is
        the pad's gross outflow ``sum h_c A_i T_i``).  ``partition_error``: |heat into
        the bodies (+ a rigid rotor's share)
        - friction power| / friction power (the flux mapping, incl. the
        rotor's revolution average).  ``bodies[b]['relative_error']``: heat
        in vs stored + convected (the solve).  ``relative_error``: the
        largest of them.
        """
        if self._last is None:
            raise ThermalError("heat_balance: no thermal solve yet")
        L = self._last
        bodies = {b: self.heat[b].balance(L["old"][b], self.T[b], L["F"][b], L["dt"])
                  for b in self.bodies}
        into = sum(L["friction_in"].values())
        P = L["friction_power_W"]
        perr = abs(into + L["rotor_unmodelled_W"] - P) / max(P, 1e-300) if P > 0 else 0.0
        return {"friction_power_W": P, "heat_into_bodies_W": into,
                "rotor_unmodelled_W": L["rotor_unmodelled_W"], "partition_error": perr,
                "exchange_pad_to_rotor_W": L["exchange_W"], "bodies": bodies,
                "relative_error": max([perr] + [v["relative_error"] for v in bodies.values()])}

    # ----------------------------------------------------------- state --
    def state_arrays(self) -> dict:
        """The thermal state for a checkpoint: ``T_<body>`` arrays and ``thermal_time``."""
        return {**{f"T_{b}": self.T[b].copy() for b in self.bodies},
                "thermal_time": float(self.time)}

    def load_state(self, arrays: Mapping[str, np.ndarray]) -> None:
        """Restore :meth:`state_arrays` (e.g. from an ``.npz``); checks the sizes."""
        for b in self.bodies:
            key = f"T_{b}"
            if key not in arrays:
                raise ThermalError(f"thermal state: {key!r} is missing; keys: {sorted(arrays)}")
            T = np.asarray(arrays[key], dtype=float)
            if T.shape != (self.heat[b].n,) or not np.all(np.isfinite(T)) or np.any(T <= 0):
                raise ThermalError(f"thermal state: {key!r} has shape {T.shape}; need "
                                   f"({self.heat[b].n},) finite temperatures > 0 K")
            self.T[b] = T.copy()
        self.time = float(np.asarray(arrays.get("thermal_time", 0.0)))
        self._last = None

    # ------------------------------------------------------ temperatures --
    def face_temperature(self, body: str = "pad") -> np.ndarray:
        """Temperature (K) at the friction-face nodes of ``body`` (sorted node order)."""
        if body not in self.bodies:
            raise ThermalError(f"body = {body!r} has no temperature field; thermal bodies: "
                               f"{self.bodies}")
        return self.T[body][self.heat[body].face]

    def rotor_temperature_under_pad(self) -> np.ndarray:
        """Rotor surface temperature seen by each pad friction node (K), for the
        rotor's ``k(T)``; the ambient if the rotor is rigid."""
        if "rotor" not in self.bodies:
            return np.full(self.pad_nodes.size, self.T_ambient)
        return self.coupling @ self.face_temperature("rotor")

    def thermal_load(self, T: Mapping[str, np.ndarray] | None = None) -> np.ndarray:
        """Thermal-strain load (3 * model.n_nodes,) in the model's global numbering.

        ``int eps(v) : C : alpha (T - T_ref) I`` per body (the form of
        :func:`brakewear.elasticity.thermal_strain_form`); zero on bodies
        without a temperature field.  Add it to the mechanical load:
        ``f = cs.f + cs.P.T @ thermal.thermal_load()`` for a contact system.
        """
        T = self.T if T is None else T
        m = self.model
        f = np.zeros(3 * m.n_nodes)
        for b in self.bodies:
            if b not in self._G:
                self._G[b] = thermal_load_matrix(m.meshes[b], m.materials[b], b)
            fb = self._G[b] @ (np.asarray(T[b], dtype=float) - self.T_ref)
            o = 3 * m.offsets[b]
            f[o:o + fb.size] = fb
        return f

    def stresses(self, u: Mapping[str, np.ndarray]) -> dict:
        """Element stresses ``C (eps - alpha dT I)`` per thermal body (6, n_elements)."""
        return {b: thermal_stress(self.model.meshes[b], u[b], self.model.materials[b],
                                  self.T[b] - self.T_ref, b) for b in self.bodies}


# ------------------------------------------------------ staggered scheme ---

def staggered_amplification(dt, capacity: float, loss: float, gain: float):
    """Amplification per step of the staggered scheme on the scalar model problem.

    ``C dT/dt = -L T + B T`` where ``L`` (``loss``) is conduction plus
    convection and ``B`` (``gain``) the thermoelastic feedback (a hotter
    spot expands, carries more pressure and makes more heat).  The
    staggered scheme solves the heat implicitly with the pressure of the
    last step: ``(C/dt + L) T1 = (C/dt + B) T0``, so

        a(dt) = (1 + dt B / C) / (1 + dt L / C).

    For ``B < L`` (the physical system is stable) ``a`` falls monotonically
    from 1 (``dt -> 0``) to ``B / L`` (``dt -> inf``, the steady fixed-point
    iteration): the staggering is stable for every ``dt``.  For ``B > L``
    (thermoelastic instability) ``a > 1`` for every ``dt``: the scheme grows
    like the physics, never faster than ``B / L`` per step.
    """
    dt = np.asarray(dt, dtype=float)
    return (1.0 + dt * gain / capacity) / (1.0 + dt * loss / capacity)
