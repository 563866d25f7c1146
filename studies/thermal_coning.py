"""Thermal coning of the rotor: the free plate's dish and the hat rotor's cone (docs/thermal.md).

Two elastic problems, each checked against an independent estimate:

(a) **Free plate, temperature linear through the thickness.**  The whole
    friction ring (no clamp; rigid-body modes removed by a statically
    determinate 3-2-1 support) with ``T = dT (z + t/2) / t``.  The thermal
    strain ``alpha T I`` is then linear in the coordinates, hence compatible:
    the ring bends without stress into a spherical dish of curvature
    ``kappa = alpha dT / t`` (``u_z = -kappa r^2 / 2`` plus a rigid motion).
    The 3D FE curvature and the stress left in it converge to that.

(b) **Hat rotor, ring heated, hat cold.**  The friction ring (with the neck
    over the wall) is heated uniformly by ``dT``, the hat stays at the
    reference temperature (the end of a short hard stop: the heat has not
    yet reached the hat), the flange's mounting face is clamped out to the
    bolt circle.  The ring grows radially by ``alpha dT r``; the cold wall
    holds its outboard inner corner back, so the ring's section rotates:
    the ring cones.  Compared with (1) an axisymmetric P2 FE model of the
    same section (forms of this module) and (2) the closed form of
    :func:`hat_cone_estimate` (rigid-section ring on a Timoshenko cylindrical
    shell clamped at the flange).  The temperature is element-wise (ring
    elements ``dT``, hat elements 0), so the step at the junction is exact on
    every mesh.

Cone angle = ``d u_z / d r`` of the inboard friction face at the friction
band's mid radius; run-out = ``u_z`` of the inboard face at the outer radius
(the mounting face is held, so it is the axial run-out against the hub).

Thermal strain enters the elastic solve as in :mod:`brakewear.thermal.strain`:
the load is ``G dT`` with ``G`` the matrix of
:func:`brakewear.fem.heat.thermal_coupling` (assembled on P2 bases, or on an
element subset, here).

Run ``python studies/thermal_coning.py [--out DIR] [--sizes MM ...]
[--order N] [--no-figures]``; writes ``DIR/data/thermal_coning.json`` and
``DIR/figures/thermal_coning.png``.
"""
from __future__ import annotations

import argparse
import json
import logging
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import skfem as fem

from brakewear.fem import apply_dirichlet, assemble_stiffness, boundary_dofs, scalar_element
from brakewear.fem.forms import lame_parameters
from brakewear.fem.heat import thermal_coupling
from brakewear.geometry import load_geometry
from brakewear.caliper.geometry import HatGeometry
from brakewear.mesh import full_rotor_mesh, rotor_mesh
from brakewear.solvers.amg import amg_solver
from brakewear.solvers.direct import direct_solve
from brakewear.thermal.strain import thermal_stress

logger = logging.getLogger("thermal_coning")

#: A hat for the default 300 mm rotor (m): 45 mm deep, 6 mm wall whose outer
#: surface is the ring's inner radius, 7 mm flange, 66 mm bore, clamped out
#: to the 114.3 mm bolt circle (radius 57 mm).
HAT = HatGeometry(height=0.045, wall_radius=0.087, wall_thickness=0.006, flange_thickness=0.007,
                  bore_radius=0.033, bolt_circle_radius=0.057)
DT = 100.0  # K; every result is linear in dT and reported per 100 K


def hat_geometry(base=None):
    """The default geometry with :data:`HAT` and ``mount = "hat"``."""
    g = load_geometry("default") if base is None else base
    return replace(g, rotor=replace(g.rotor, mount="hat", hat=HAT))


# ---------------------------------------------------------------- closed forms

def plate_curvature(alpha: float, dT: float, t: float) -> float:
    """Curvature (1/m) of a free plate with a linear through-thickness rise ``dT``."""
    return alpha * dT / t


def shell_constants(E: float, nu: float, a: float, h: float) -> tuple[float, float]:
    """``beta = (3 (1 - nu^2) / (a h)^2)^(1/4)`` (1/m) and ``D = E h^3 / 12 (1 - nu^2)``."""
    return (3.0 * (1.0 - nu ** 2) / (a * h) ** 2) ** 0.25, E * h ** 3 / (12.0 * (1.0 - nu ** 2))


def _decaying(beta: float, y: float, A: float, B: float, k: int) -> float:
    """``d^k/dy^k`` of ``exp(-beta y) (A cos beta y + B sin beta y)``."""
    for _ in range(k):
        A, B = beta * (B - A), -beta * (A + B)
    return float(np.exp(-beta * y) * (A * np.cos(beta * y) + B * np.sin(beta * y)))


def shell_edge_stiffness(beta: float, D: float, L: float = np.inf) -> np.ndarray:
    """Edge stiffness (per unit circumference) of a cylindrical shell under
    axisymmetric bending: ``[Q, M] = K [w0, theta0]`` for the radial
    displacement ``w0`` and slope ``theta0 = dw/dx`` of the edge ``x = 0``,
    the other end ``x = L`` clamped (Timoshenko's beam on elastic foundation,
    ``D w'''' + 4 beta^4 D w = 0``).  ``L = inf``: the semi-infinite shell,
    ``K = 2 beta D [[2 beta^2, beta], [beta, 1]]``."""
    if not np.isfinite(L):
        return 2.0 * beta * D * np.array([[2.0 * beta ** 2, beta], [beta, 1.0]])
    # four solutions: decaying from x = 0 and from x = L
    basis = [(0, 1.0, 0.0), (0, 0.0, 1.0), (1, 1.0, 0.0), (1, 0.0, 1.0)]

    def val(fn, x, k):
        far, A, B = fn
        return _decaying(beta, x, A, B, k) if not far else (-1) ** k * _decaying(beta, L - x, A, B, k)

    M = np.array([[val(fn, x, k) for fn in basis] for x, k in ((0, 0), (0, 1), (L, 0), (L, 1))])
    K = np.zeros((2, 2))
    for j, rhs in enumerate(np.eye(4)[:2]):
        c = np.linalg.solve(M, rhs)
        # energy = (D w''' w - D w'' w')|_0 ... : generalized forces (D w'''(0), -D w''(0))
        K[0, j] = D * sum(ci * val(fn, 0.0, 3) for ci, fn in zip(c, basis))
        K[1, j] = -D * sum(ci * val(fn, 0.0, 2) for ci, fn in zip(c, basis))
    return K


def annulus_edge(b: float, a: float, nu: float, r: np.ndarray | float | None = None):
    """The free annulus ``b < r < a`` loaded on its inner edge only.

    Returns ``s = (1/b^2 - 1/a^2) / ((1 - nu) b / a^2 + (1 + nu) / b)``: the
    inner-edge stiffness is ``E t s`` in plane (Lame, radial line load) and
    ``E t^3 s / 12`` in bending (Kirchhoff plate, edge moment; slope
    ``phi(r) ~ (1 - nu) r / ((1 + nu) a^2) + 1 / r``).  With ``r``: also
    ``phi(r) / phi(b)`` and ``int_b^r phi / phi(b)``.
    """
    s = (1 / b ** 2 - 1 / a ** 2) / ((1 - nu) * b / a ** 2 + (1 + nu) / b)
    if r is None:
        return s
    k = (1 - nu) / ((1 + nu) * a ** 2)
    r = np.asarray(r, dtype=float)
    slope = (k * r + 1 / r) / (k * b + 1 / b)
    rise = (0.5 * k * (r ** 2 - b ** 2) + np.log(r / b)) / (k * b + 1 / b)
    return s, slope, rise


def hat_cone_estimate(geom, dT: float, ring: str = "plate", L: float | None = None) -> dict:
    """Closed-form cone of a hat rotor whose ring is heated by ``dT`` (hat cold).

    The ring (with the neck: radii ``b = r_lo .. ro``, thickness ``t``) grows
    freely by ``alpha dT r`` and takes on top of that a radial shift ``U`` and
    a rotation ``psi`` of its inner edge.  ``ring="plate"``: a free annular
    plate (membrane stiffness ``E t s`` and bending stiffness ``E t^3 s/12``
    of :func:`annulus_edge`; the slope falls off toward the outer edge);
    ``ring="rigid"``: a rigid section that stores only hoop strain
    (``E t ln(ro/b) / a`` and ``E t^3 ln(ro/b) / (12 a)``; slope uniform).
    The wall (mid radius ``a``, thickness ``h``) is a cylindrical shell
    clamped at the flange's mid-plane (``L = height - flange/2``;
    :func:`shell_edge_stiffness`), joined at ``(a, -t)``: its edge moves by
    ``w0 = alpha dT a + U + psi t/2`` and turns with the ring,
    ``theta0 = psi``.  The energy, minimised over ``(U, psi)``, is a 2x2
    system.  Returns ``psi`` (rad, the inner edge), ``cone`` (the slope at
    the friction band's mid radius; negative: the outer edge moves toward the
    hat) and ``runout`` (m, ``u_z`` of the inboard face at the outer radius,
    the thickness growth ``alpha dT t`` included).
    """
    if ring not in ("plate", "rigid"):
        raise ValueError(f"ring = {ring!r}; allowed: 'plate', 'rigid'")
    ro_, hat, mat = geom.rotor, geom.rotor.hat, geom.rotor.material
    E, nu, alpha = mat.elastic.E, mat.elastic.nu, mat.thermal.alpha
    t, ro, ri = ro_.thickness, ro_.outer_radius, ro_.inner_radius
    a, h = hat.wall_radius, hat.wall_thickness
    b = min(ri, a - 0.5 * h)
    L = hat.height - 0.5 * hat.flange_thickness if L is None else L
    beta, D = shell_constants(E, nu, a, h)
    Ks = shell_edge_stiffness(beta, D, L)
    rm = 0.5 * (ri + ro)
    if ring == "plate":
        sk, slope, rise = annulus_edge(b, ro, nu, np.array([rm, ro]))
        k = E * t * sk * b / a  # per unit length of the junction circle
        slope, rise = float(slope[0]), float(rise[1])
    else:
        k = E * t * np.log(ro / b) / a
        slope, rise = 1.0, ro - a
    kr = np.diag([k, k * t ** 2 / 12.0])
    J = np.array([[1.0, 0.5 * t], [0.0, 1.0]])  # (U, psi) -> (w0, theta0)
    w_free = np.array([alpha * dT * a, 0.0])
    U, psi = np.linalg.solve(kr + J.T @ Ks @ J, -J.T @ Ks @ w_free)
    return {"ring": ring, "psi": float(psi), "cone": float(psi * slope), "U": float(U),
            "runout": float(psi * rise + alpha * dT * t), "beta": float(beta), "L": float(L),
            "beta_L": float(beta * L), "k_ring": kr.diagonal().tolist(), "K_shell": Ks.tolist()}


# ------------------------------------------------------- axisymmetric FE model

def _section_blocks(geom) -> list[tuple[float, float, float, float]]:
    """The hat rotor's section as rectangles (r0, r1, z0, z1), ring first."""
    ro_, hat = geom.rotor, geom.rotor.hat
    t, ri, ro = ro_.thickness, ro_.inner_radius, ro_.outer_radius
    wi, wo = hat.wall_radius - 0.5 * hat.wall_thickness, hat.wall_radius + 0.5 * hat.wall_thickness
    zb = -t - hat.height
    return [(min(ri, wi), ro, -t, 0.0), (wi, wo, zb, -t),
            (hat.bore_radius, wo, zb, zb + hat.flange_thickness)]


def section_mesh(geom, size: float) -> fem.MeshTri:
    """Triangles of the (r, z) section: one tensor grid through every break,
    cells outside the blocks dropped.  Subdomains ``ring`` and ``hat``, facets
    ``clamp`` (mounting face out to the bolt circle) and ``face`` (z = 0)."""
    blocks = _section_blocks(geom)

    def axis(k):
        extra = [geom.rotor.hat.bolt_circle_radius] if k == 0 else []
        br = np.unique(np.round([b[i] for b in blocks for i in (2 * k, 2 * k + 1)] + extra, 12))
        parts = [np.linspace(a, b, max(2, int(np.ceil((b - a) / size))) + 1)
                 for a, b in zip(br[:-1], br[1:])]
        return np.unique(np.concatenate(parts))

    m = fem.MeshTri.init_tensor(axis(0), axis(1))
    c = m.p[:, m.t].mean(axis=1)
    inside = np.zeros(m.t.shape[1], dtype=bool)
    for r0, r1, z0, z1 in blocks:
        inside |= (c[0] > r0) & (c[0] < r1) & (c[1] > z0) & (c[1] < z1)
    t = m.t[:, inside]
    used = np.unique(t)
    renum = np.zeros(m.p.shape[1], dtype=np.int64)
    renum[used] = np.arange(used.size)
    m = fem.MeshTri(np.ascontiguousarray(m.p[:, used]), np.ascontiguousarray(renum[t]))
    zb, rb, tol = blocks[1][2], geom.rotor.hat.bolt_circle_radius, 1e-9
    m = m.with_boundaries({"clamp": lambda x: (np.abs(x[1] - zb) < tol) & (x[0] < rb + tol),
                           "face": lambda x: np.abs(x[1]) < tol})
    zc = m.p[1, m.t].mean(axis=0)
    return m.with_subdomains({"ring": np.nonzero(zc > blocks[0][2])[0],
                              "hat": np.nonzero(zc < blocks[0][2])[0]})


def _axi_strain(u, r):
    """(rr, zz, theta-theta, engineering rz) strains of an axisymmetric (u_r, u_z) field."""
    g = u.grad
    return [g[0][0], g[1][1], u[0] / r, g[0][1] + g[1][0]]


def axisymmetric_cone(geom, dT: float, size: float) -> dict:
    """The hat rotor's section solved as an axisymmetric body (P2 triangles).

    ``2 pi r`` weights the isotropic forms; the thermal load of the ring's
    elements is ``int (3 lambda + 2 mu) alpha dT tr eps(v) r``.  Returns the
    cone angle, run-out and the inboard face's ``u_z(r)``.
    """
    mat = geom.rotor.material
    lam, mu = lame_parameters(mat.elastic.E, mat.elastic.nu)
    C = np.full((3, 3), lam) + 2 * mu * np.eye(3)
    m = section_mesh(geom, size)
    e = fem.ElementVector(fem.ElementTriP2())

    @fem.BilinearForm
    def stiff(u, v, w):
        eu, ev = _axi_strain(u, w.x[0]), _axi_strain(v, w.x[0])
        s = sum(C[i, j] * eu[j] * ev[i] for i in range(3) for j in range(3))
        return (s + mu * eu[3] * ev[3]) * w.x[0]

    @fem.LinearForm
    def thermal(v, w):
        ev = _axi_strain(v, w.x[0])
        return (3 * lam + 2 * mu) * mat.thermal.alpha * dT * (ev[0] + ev[1] + ev[2]) * w.x[0]

    basis = fem.Basis(m, e, intorder=4)
    K = stiff.assemble(basis)
    f = thermal.assemble(fem.Basis(m, e, intorder=4, elements=m.subdomains["ring"]))
    fixed = basis.get_dofs("clamp").all()
    Kd, fd = apply_dirichlet(K, f, fixed)
    u = direct_solve(Kd, fd)
    face = basis.get_dofs("face")
    xr = np.concatenate([basis.doflocs[0, face.nodal["u^1"]], basis.doflocs[0, face.facet["u^1"]]])
    uz = np.concatenate([u[face.nodal["u^2"]], u[face.facet["u^2"]]])
    out = _cone_from_face(geom, xr, uz)
    out.update(dofs=int(K.shape[0]), mesh=m, u=u, basis=basis)
    return out


def _cone_from_face(geom, r: np.ndarray, uz: np.ndarray) -> dict:
    """Cone angle (rad) at the band's mid radius and run-out (m) at the outer
    radius from a cubic fit of ``u_z(r)`` over the friction band."""
    ri, ro = geom.rotor.inner_radius, geom.rotor.outer_radius
    sel = r >= ri - 1e-9
    c = np.polyfit(r[sel] - ri, uz[sel], 3)
    rm = 0.5 * (ro - ri)
    return {"cone": float(np.polyval(np.polyder(c), rm)), "runout": float(np.polyval(c, ro - ri)),
            "fit_rms": float(np.sqrt(np.mean((np.polyval(c, r[sel] - ri) - uz[sel]) ** 2))),
            "r": r[sel], "uz": uz[sel]}


# ------------------------------------------------------------------- 3D solves

def thermal_load(mesh: fem.Mesh, material, T: np.ndarray, elements=None) -> np.ndarray:
    """``G T``: the load of the thermal strain ``alpha T I`` (T per scalar DOF),
    ``G`` from :func:`brakewear.fem.heat.thermal_coupling` on the mesh's own
    (P1 or P2) elements, optionally on an element subset."""
    el = scalar_element(mesh)
    # the library's rule: one point is exact for P1; degree 4 on the curved P2 elements
    kw = {"intorder": 1 if el.maxdeg == 1 else 4, "elements": elements}
    G = thermal_coupling(material.voigt(), material.thermal.alpha).assemble(
        fem.Basis(mesh, el, **kw), fem.Basis(mesh, fem.ElementVector(el), **kw))
    return G @ T


def _solve(K, f, fixed, coords, tol=1e-10) -> tuple[np.ndarray, dict]:
    Kd, fd = apply_dirichlet(K, f, fixed)
    solver = amg_solver(Kd, coords=coords, fixed=fixed, tol=tol)
    u = solver.solve(fd)
    return u, {"iterations": int(solver.info.iterations), "dofs": int(K.shape[0]),
               "relative_residual": float(solver.info.relative_residual)}


def _three_two_one(coords: np.ndarray, ri: float, t: float) -> np.ndarray:
    """DOFs of a statically determinate support: all three at the node nearest
    ``(ri, 0, -t/2)``, y and z at the one nearest ``(-ri, 0, -t/2)``, z at the
    one nearest ``(0, ri, -t/2)``."""
    def near(x, y):
        return int(np.argmin(np.sum((coords - np.array([[x], [y], [-0.5 * t]])) ** 2, axis=0)))
    a, b, c = near(ri, 0.0), near(-ri, 0.0), near(0.0, ri)
    return np.array([3 * a, 3 * a + 1, 3 * a + 2, 3 * b + 1, 3 * b + 2, 3 * c + 2])


def free_plate(size: float, order: int, dT: float = DT, geom=None) -> dict:
    """(a): the whole ring, ``T = dT (z + t/2) / t``, 3-2-1 support.

    Returns the FE curvature (from a least-squares fit of ``u_z`` at every
    node to ``a + b x + c y + d r^2 + e z^2``: ``kappa = -2 d``), the closed
    form, the largest von Mises stress over ``E alpha dT / (1 - nu)`` and the
    largest reaction over the load (zero: the load is self-equilibrated).
    """
    g = load_geometry("default") if geom is None else geom
    mat, t = g.rotor.material, g.rotor.thickness
    m = rotor_mesh(g, size=size, order=order, full=True)
    X = fem.Basis(m, scalar_element(m), intorder=1).doflocs
    T = dT * (X[2] + 0.5 * t) / t
    K, _ = assemble_stiffness(m, mat)
    f = thermal_load(m, mat, T)
    fixed = _three_two_one(X, g.rotor.inner_radius, t)
    u, info = _solve(K, f, fixed, X)
    reaction = np.abs((K @ u - f)[fixed]).max() / np.abs(f).max()
    uz = u[2::3]
    A = np.column_stack([np.ones(X.shape[1]), X[0], X[1], X[0] ** 2 + X[1] ** 2, X[2] ** 2])
    coef = np.linalg.lstsq(A, uz, rcond=None)[0]
    kappa = plate_curvature(mat.thermal.alpha, dT, t)
    s = thermal_stress(m, u, mat, T, name="rotor")
    vm = np.sqrt(0.5 * ((s[0] - s[1]) ** 2 + (s[1] - s[2]) ** 2 + (s[2] - s[0]) ** 2)
                 + 3 * (s[3] ** 2 + s[4] ** 2 + s[5] ** 2))
    scale = mat.elastic.E * mat.thermal.alpha * dT / (1 - mat.elastic.nu)
    return {"size_mm": 1e3 * size, "order": order, "kappa_fe": float(-2 * coef[3]),
            "kappa": kappa, "kappa_error": float(abs(-2 * coef[3] / kappa - 1)),
            "stress_ratio": float(vm.max() / scale), "reaction_ratio": float(reaction),
            "h_z_mm": 1e3 * float(np.diff(np.unique(np.round(m.p[2], 12))).max()), **info}


def hat_cone(size: float, order: int, dT: float = DT, hat_size: float | None = None,
             geom=None) -> dict:
    """(b): the hat rotor, ring elements heated by ``dT``, hat cold, mounting
    face clamped to the bolt circle.  Cone angle and run-out of the inboard
    face (:func:`_cone_from_face`) and the face's ``u_z(r)``."""
    g = hat_geometry() if geom is None else geom
    mat = g.rotor.material
    m = full_rotor_mesh(g, size=size, order=order, hat_size=size if hat_size is None else hat_size)
    X = fem.Basis(m, scalar_element(m), intorder=1).doflocs
    K, _ = assemble_stiffness(m, mat)
    f = thermal_load(m, mat, np.full(X.shape[1], dT), elements=m.subdomains["ring"])
    fixed = boundary_dofs(m, "rotor_clamp")
    u, info = _solve(K, f, fixed, X)
    face = np.abs(X[2]) < 1e-9 * g.rotor.outer_radius
    out = _cone_from_face(g, np.hypot(X[0, face], X[1, face]), u[2::3][face])
    out.update(size_mm=1e3 * size, order=order, **info)
    return out


# ------------------------------------------------------------------- the study

def _axisymmetric_reference(g, dT: float, sizes) -> tuple[dict, dict]:
    """The section model on halving sizes; the finest run and the Richardson
    extrapolation of its cone and run-out."""
    runs = [axisymmetric_cone(g, dT, h) for h in sizes]
    c = [r["cone"] for r in runs]
    rate = 1.0
    if len(c) >= 3:
        rate = float(np.log2(abs((c[-3] - c[-2]) / (c[-2] - c[-1]))))
    q = 2.0 ** rate - 1.0
    ref = {"cone": c[-1] + (c[-1] - c[-2]) / q, "cones": c, "rate": rate,
           "runout": runs[-1]["runout"] + (runs[-1]["runout"] - runs[-2]["runout"]) / q}
    print(f"axisymmetric: cone {', '.join(f'{1e3 * x:.4f}' for x in c)} mrad at "
          f"{', '.join(f'{1e3 * h:g}' for h in sizes)} mm (rate {rate:.2f}) -> "
          f"{1e3 * ref['cone']:.4f} mrad")
    return runs[-1], ref


def _rate(h, err) -> float:
    return float(np.polyfit(np.log(h), np.log(err), 1)[0])


def main(out: str | Path | None = "docs", plate_sizes=(0.016, 0.012, 0.008),
         hat_sizes=(0.012, 0.008, 0.006), hat_size_ratio: float = 0.5, order: int = 2,
         axi_sizes=(2e-3, 1e-3, 5e-4), dT: float = DT, figures: bool = True) -> dict:
    """Run (a) and (b); return the numbers (per ``dT``; ``dT`` = 100 K by default).

    Parameters
    ----------
    out
        Folder: writes ``out/data/thermal_coning.json`` and
        ``out/figures/thermal_coning.png``; None: nothing is written.
    plate_sizes, hat_sizes
        In-plane mesh sizes (m) of the free ring (a) and of the hat rotor (b).
    hat_size_ratio
        Size in the hat's section over the ring's size (b).
    order
        Element order of the 3D meshes.
    axi_sizes
        Element sizes (m) of the axisymmetric section model, halving: the
        finest run, extrapolated (Richardson, with the observed rate from
        three sizes, else rate 1), is the reference of (b).
    """
    t0 = time.perf_counter()
    plate = [free_plate(s, order, dT) for s in plate_sizes]
    for p in plate:
        print(f"(a) size {p['size_mm']:4.1f} mm P{order}: {p['dofs']:6d} DOFs, kappa "
              f"{p['kappa_fe']:.5f} / {p['kappa']:.5f} 1/m (error {100 * p['kappa_error']:.3f} %), "
              f"max von Mises {100 * p['stress_ratio']:.2f} % of E alpha dT/(1-nu)")
    g = hat_geometry()
    axi, ref = _axisymmetric_reference(g, dT, axi_sizes)
    est = {k: hat_cone_estimate(g, dT, k) for k in ("plate", "rigid")}
    hat = [hat_cone(s, order, dT, hat_size=hat_size_ratio * s) for s in hat_sizes]
    for h in hat:
        h["diff_vs_axisymmetric"] = h["cone"] / ref["cone"] - 1
        print(f"(b) size {h['size_mm']:4.1f} mm P{order}: {h['dofs']:6d} DOFs, cone "
              f"{1e3 * h['cone']:.4f} mrad, run-out {1e6 * h['runout']:.2f} um "
              f"({100 * h['diff_vs_axisymmetric']:+.2f} % vs axisymmetric)")
    ext = None
    if len(hat) >= 2:  # Richardson with rate 1 (the section's corner limits both models to it)
        h1, h2 = hat[-2], hat[-1]
        ext = h2["cone"] + (h2["cone"] - h1["cone"]) / (h1["size_mm"] / h2["size_mm"] - 1.0)
        print(f"(b) 3D extrapolated (rate 1): {1e3 * ext:.4f} mrad "
              f"({100 * (ext / ref['cone'] - 1):+.2f} % vs axisymmetric)")
    per = 100.0 / dT
    res = {
        "settings": {"dT_K": dT, "order": order, "axi_sizes_mm": [1e3 * h for h in axi_sizes],
                     "hat_size_ratio": hat_size_ratio,
                     "hat_mm": {k: 1e3 * getattr(HAT, k) for k in HAT.__dataclass_fields__}},
        "plate": plate,
        "plate_rate": _rate([p["size_mm"] for p in plate], [p["kappa_error"] for p in plate]),
        "axisymmetric": {"cone_mrad": 1e3 * ref["cone"], "runout_um": 1e6 * ref["runout"],
                         "finest_cone_mrad": 1e3 * axi["cone"], "dofs": axi["dofs"],
                         "runs_cone_mrad": [1e3 * c for c in ref["cones"]], "rate": ref["rate"],
                         "richardson_change": ref["cone"] / axi["cone"] - 1},
        "estimate": {k: {"cone_mrad": 1e3 * e["cone"], "edge_rotation_mrad": 1e3 * e["psi"],
                         "runout_um": 1e6 * e["runout"], "beta_L": e["beta_L"],
                         "diff_vs_axisymmetric": e["cone"] / ref["cone"] - 1,
                         "runout_diff_vs_axisymmetric": e["runout"] / ref["runout"] - 1}
                     for k, e in est.items()},
        "hat": [{k: v for k, v in h.items() if k not in ("r", "uz")} for h in hat],
        "hat_extrapolated": None if ext is None else {
            "cone_mrad": 1e3 * ext, "diff_vs_axisymmetric": ext / ref["cone"] - 1},
        "per_100K": {"cone_mrad": 1e3 * hat[-1]["cone"] * per,
                     "runout_um": 1e6 * hat[-1]["runout"] * per,
                     "cone_mrad_axisymmetric": 1e3 * ref["cone"] * per,
                     "runout_um_axisymmetric": 1e6 * ref["runout"] * per},
    }
    res["total_s"] = time.perf_counter() - t0
    p100 = res["per_100K"]
    print(f"per 100 K: cone {p100['cone_mrad']:.3f} mrad, run-out at the outer radius "
          f"{p100['runout_um']:.1f} um (axisymmetric {p100['cone_mrad_axisymmetric']:.3f} mrad, "
          f"{p100['runout_um_axisymmetric']:.1f} um); closed form (plate ring) "
          f"{res['estimate']['plate']['cone_mrad'] * per:.3f} mrad "
          f"({100 * res['estimate']['plate']['diff_vs_axisymmetric']:+.1f} %)")
    if out is not None:
        out = Path(out)
        (out / "data").mkdir(parents=True, exist_ok=True)
        (out / "data" / "thermal_coning.json").write_text(json.dumps(res, indent=1) + "\n")
        if figures:
            (out / "figures").mkdir(parents=True, exist_ok=True)
            _figure(g, axi, est, hat[-1], dT, out / "figures" / "thermal_coning.png")
    return res


def _figure(g, axi, est, hat3d, dT, path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    m, u, basis = axi["mesh"], axi["u"], axi["basis"]
    ur, uz = u[basis.nodal_dofs[0]], u[basis.nodal_dofs[1]]
    raw = 0.1 * g.rotor.outer_radius / max(np.abs(ur).max(), np.abs(uz).max())
    decade = 10.0 ** np.floor(np.log10(raw))
    scale = decade * max(k for k in (1, 2, 5) if k * decade <= raw)  # a round 1-2-5 factor
    fig, ax = plt.subplots(1, 2, figsize=(13, 5), width_ratios=(1.1, 1))
    tri = Triangulation(1e3 * m.p[0], 1e3 * m.p[1], m.t.T)
    ax[0].triplot(tri, color="0.8", lw=0.3)
    td = Triangulation(1e3 * (m.p[0] + scale * ur), 1e3 * (m.p[1] + scale * uz), m.t.T)
    pc = ax[0].tripcolor(td, 1e6 * uz, shading="gouraud", cmap="coolwarm")
    fig.colorbar(pc, ax=ax[0], label="u_z (um)")
    ax[0].set(aspect="equal", xlabel="r (mm)", ylabel="z (mm)",
              title=f"hat section: ring +{dT:.0f} K, hat cold\n(grey: undeformed; "
                    f"displacement x {scale:.0f})")
    ri, ro, t = g.rotor.inner_radius, g.rotor.outer_radius, g.rotor.thickness
    ax[1].plot(1e3 * hat3d["r"], 1e6 * hat3d["uz"], ".", ms=2, color="0.5",
               label=f"3D FE, P{hat3d['order']}, {hat3d['size_mm']:.0f} mm (every face node)")
    o = np.argsort(axi["r"])
    ax[1].plot(1e3 * axi["r"][o], 1e6 * axi["uz"][o], "k-", lw=1.5, label="axisymmetric FE")
    r = np.linspace(ri, ro, 50)
    alpha = g.rotor.material.thermal.alpha
    e = est["plate"]
    b = min(ri, g.rotor.hat.wall_radius - 0.5 * g.rotor.hat.wall_thickness)
    rise = annulus_edge(b, ro, g.rotor.material.elastic.nu, r)[2]
    ax[1].plot(1e3 * r, 1e6 * (e["psi"] * rise + alpha * dT * t), "C1--",
               label="closed form: annular plate on a cylindrical shell")
    e = est["rigid"]
    ax[1].plot(1e3 * r, 1e6 * (e["psi"] * (r - g.rotor.hat.wall_radius) + alpha * dT * t), "C2:",
               label="closed form: rigid-section ring on the shell")
    ax[1].set(xlabel="r (mm)", ylabel="u_z of the inboard friction face (um)",
              title=f"cone at mid band: {1e3 * hat3d['cone']:.2f} mrad (3D), "
                    f"{1e3 * axi['cone']:.2f} mrad (axisymmetric)\nring +{dT:.0f} K")
    ax[1].grid(alpha=0.3)
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description="Thermal coning: free plate and hat rotor")
    ap.add_argument("--out", default="docs", help="folder of data/ and figures/")
    ap.add_argument("--sizes", type=float, nargs="+", default=[12.0, 8.0, 6.0],
                    help="hat rotor mesh sizes (mm)")
    ap.add_argument("--order", type=int, default=2)
    ap.add_argument("--no-figures", action="store_true")
    a = ap.parse_args()
    logging.basicConfig(level=logging.WARNING)
    main(a.out, hat_sizes=tuple(1e-3 * s for s in a.sizes), order=a.order,
         figures=not a.no_figures)
