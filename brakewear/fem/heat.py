"""Transient heat conduction of one body: scikit-fem forms and :class:`HeatConduction`.

Form factories in scikit-fem style: :func:`conduction` (``kappa grad T .
grad v``), :func:`capacity` (``rho c T v``), :func:`convection` (facet,
``h T v``) and :func:`surface_flux` (facet, ``q v`` with the flux ``q``
given at the nodes and interpolated linearly).  :class:`HeatConduction`
assembles them once for a meshed body and solves steady and implicit-Euler
steps with a cached sparse factorisation per time step, with an energy
balance of every solve.  Temperatures are in kelvin.
"""
from __future__ import annotations

import logging
from collections import OrderedDict
from collections.abc import Mapping, Sequence

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem as fem
from skfem.helpers import dot, grad

from ..errors import ConvergenceError, ThermalError
from ..materials import T_AMBIENT_DEFAULT, Material, Thermal
from ..mesh.surface import surface_nodes, tributary_areas
from ..mesh.topology import ensure_topology
from .forms import voigt_strain

logger = logging.getLogger(__name__)

__all__ = [
    "conduction",
    "capacity",
    "convection",
    "surface_flux",
    "thermal_coupling",
    "HeatConduction",
]


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
    :func:`brakewear.fem.thermal_strain_form`: ``f = G dT`` (tested
    equal to round-off).  Assembled once, the load of every step is then a
    sparse product.
    """
    s = np.asarray(C, dtype=float) @ np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]) * alpha

    @fem.BilinearForm
    def form(u, v, w):
        ev = voigt_strain(v)
        return u * sum(s[i] * ev[i] for i in range(6) if s[i] != 0.0)

    return form


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
        convection, fixed = _check_boundaries(name, mesh, flux_facets, convection, fixed,
                                              contact_conductance)
        groups = material_groups(mesh, materials, name)
        self.thermal = [(e, check_thermal(m, body_label(name, m))) for e, m in groups]
        self.mesh, self.T_ambient, self.mass_kind = mesh, float(T_ambient), mass
        ensure_topology(mesh)
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
        H = sp.csr_matrix((N, N))
        self.b_amb = np.zeros(N)
        for key, h in convection.items():
            fb = fem.FacetBasis(mesh, elem, facets=mesh.boundaries[key], intorder=2)
            H = H + _convection_form(h).assemble(fb)
            self.b_amb += surface_flux().assemble(fb, q=h * self.T_ambient)
        self.H = H
        self.K, self.M, self.H1 = self.K.tocsr(), self.M.tocsr(), self.H.tocsr()
        self.b_amb1 = self.b_amb
        #: factor on every convection coefficient (a speed-dependent one: set_convection_scale)
        self.h_scale = 1.0
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

    def set_convection_scale(self, scale: float) -> None:
        """Multiply every convection coefficient by ``scale`` (>= 0) from now on: a
        coefficient that follows the rotor's speed.  Factorisations are kept per
        ``(dt, scale)``."""
        if not (np.isfinite(scale) and scale >= 0):
            raise ThermalError(f"body {self.name!r}: convection scale {scale!r} is not "
                               "allowed; need >= 0")
        self.h_scale = float(scale)
        s = self.h_scale
        self.H = self.H1 if s == 1.0 else (s * self.H1).tocsr()
        self.b_amb = self.b_amb1 if s == 1.0 else s * self.b_amb1

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
        key = (None if dt is None else float(dt), self.h_scale)
        if key in self._lu:
            self._lu.move_to_end(key)
            return self._lu[key]
        A = self.K + self.H + self.Hc + (0.0 if dt is None else self.M / float(dt))
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
                h * self.h_scale > 0 for h in self.convection.values()):
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
        while np.linalg.norm(r) > self.cg_tol * nb and it < _CG_MAXITER:
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
            raise ConvergenceError(
                f"body {self.name!r}: CG with the factorisation of dt = {dt0} did not reach "
                f"{self.cg_tol:.0e} for dt = {dt} (relative residual {res:.2e} after {it} "
                f"iterations; budget {_CG_MAXITER})",
                figures={"iterations": it, "relative_residual": float(res),
                         "maxiter": _CG_MAXITER, "tol": self.cg_tol})
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


THERMAL_FIELDS = ("rho", "c", "kappa", "alpha")


def check_thermal(th, where: str, fields: Sequence[str] = ("rho", "c", "kappa")) -> Thermal:
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


def material_groups(mesh: fem.Mesh, materials, name: str) -> list[tuple[np.ndarray, object]]:
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


def body_label(name: str, mat) -> str:
    mname = getattr(mat, "name", None)
    return f"body {name!r}" + (f" (material {mname!r})" if mname else "")


def _check_boundaries(name, mesh, flux_facets, convection, fixed, contact_conductance):
    """The checked boundary conditions of a body: ``(convection, fixed)`` as dicts."""
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
    return convection, fixed


#: iterations of the heat solve's CG preconditioned by another step's factorisation
#: before :class:`~brakewear.errors.ConvergenceError` (it needs a few when the step is
#: near the factorised one)
_CG_MAXITER = 100
