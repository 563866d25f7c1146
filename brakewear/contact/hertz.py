"""Verification models inside the package: Hertz, a rigid sphere pressed into an
elastic half-space, 3D quarter model (used by ``studies/hertz.py`` and by
``brakewear bench contact``).

Set-up (docs/references.md, "Hertz, sphere on a flat"):

* A rigid sphere of radius ``R`` sits above the block ``0 < x, y < L``,
  ``-L < z < 0`` (a quarter of the half-space; symmetry ``u_x = 0`` on
  ``x = 0`` and ``u_y = 0`` on ``y = 0``).  Its lower surface is
  ``z = R - sqrt(R^2 - r^2) - delta``: the approach ``delta`` is prescribed,
  the force ``F`` (full model: four times the quarter's contact force) comes
  out.  Frictionless node-to-rigid contact on the top face
  (:func:`brakewear.contact.pair_to_rigid`, gaps along z, the small-slope
  approximation Hertz also makes).  With ``a/R = 0.01`` the sphere differs
  from Hertz's paraboloid by ``(a/R)^2/4 ~ 3e-5`` in relative terms.
* The block truncates the half-space.  Its far faces (``x = L``, ``y = L``,
  ``z = -L``) carry the Boussinesq displacement of a point force ``F`` (the
  half-space solution far from the patch), so the truncation error falls as
  ``(a/L)^2`` instead of ``a/L`` and the approach is measured against points
  at infinity, as in Hertz's theory.  ``F`` is an output: it is found by a
  secant iteration on ``F_bc = F(F_bc)`` (the problem is affine in ``F_bc``
  for a fixed active set, so 3-4 solves converge to 1e-9).
* Mesh: a tensor grid (P1 tetrahedra) with uniform spacing ``h`` over
  ``[0, 1.25 a]`` in x and y and ``[0, 0.5 a]`` in depth, geometric growth
  (factor ``GROWTH``) beyond, out to ``L = 12 a``.  Split ``"mirrored"``
  (default, :func:`mirrored_tets`): the mesh is its own mirror image across
  every grid plane, so the quarter model equals the symmetric full model.
  The plain Kuhn split (``"kuhn"``) is not: its quarter model is a full model
  folded at the symmetry planes, whose nodes there carry 4-9 % too much
  pressure, a bias that hardly falls with ``h``.

Measured against Hertz at the computed ``F``:

* peak pressure ``p0_h``: the recovered pressure (:func:`recovered_pressure`,
  nodal forces over tributary areas in a tent window of half-width
  ``RECOVERY h``) at the origin.  Nodal force / area alone oscillates with
  the node type of the mirrored split (``p0_nodal_err``);
* contact radius ``a_h``: area-weighted least-squares fit of
  ``p^2 = c + m r^2`` (Hertz: ``p0^2 (1 - r^2/a^2)``) to the nodal pressures
  of the active nodes with ``r < 0.85 a``, so ``a_h^2 = -c / m`` -- uses the
  whole patch rather than the last active node, whose position is only known
  to within ``h``; reported beside it, the radius of the active nodes'
  tributary area (``a_area_err``) and of the outermost active node
  (``a_outer_err``), as the peers read it;
* approach: ``delta`` against ``a(F)^2 / R``;
* L2 pressure error over the top face:
  ``sqrt(sum A_s (p_s - p_H(r_s))^2 / sum A_s p_H(r_s)^2)`` with tributary
  areas ``A_s``, of the recovered pressure (``l2_err``), the same inside
  ``r < a - RECOVERY h`` (``l2_inner_err``, away from the square-root edge)
  and of the nodal pressure (``l2_nodal_err``).

With ``order=2`` (:func:`hertz_problem`, :func:`solve`) the block is meshed
with quadratic tetrahedra and its top face is a dual mortar pair
(:mod:`brakewear.contact.quadratic`); the pressure is then the nodal value of
the dual multiplier, without a recovery window (``studies/hertz_p2.py``).

``python studies/hertz.py [--out DIR] [--data DIR]`` runs the convergence study
(table, ``hertz_convergence.csv``/``.json``/``.png``, ``hertz_pressure.png``).
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from ..analytic import effective_modulus, hertz_sphere, hertz_sphere_pressure
from ..errors import ContactError, GeometryError, MeshError
from ..fem.assembly import assemble_stiffness
from ..fem.boundary import boundary_dofs
from ..materials import Isotropic
from ..mesh.structured import KUHN, mapped_mesh, structured_tets
from .lagrange import solve_contact
from .pairs import pair_to_rigid

logger = logging.getLogger(__name__)

__all__ = [
    "MATERIAL",
    "R",
    "A0",
    "ES",
    "DELTA",
    "L_OVER_A",
    "FINE_XY",
    "FINE_Z",
    "GROWTH",
    "FIT_R",
    "RECOVERY",
    "GAP_TOL",
    "boussinesq",
    "sphere_height",
    "axis",
    "mirrored_tets",
    "block_mesh",
    "HertzProblem",
    "hertz_dofs",
    "hertz_resolution",
    "hertz_problem",
    "hertz_force",
    "solve_problem",
    "solve",
    "recovered_pressure",
    "measure",
]


MATERIAL = Isotropic(E=210e9, nu=0.3, name="steel")


R = 0.01            # sphere radius (m)


A0 = 1e-4           # design contact radius (m), a/R = 0.01


ES = effective_modulus(MATERIAL.E, MATERIAL.nu)   # rigid sphere: E / (1 - nu^2)


DELTA = A0 ** 2 / R  # prescribed approach: Hertz's a(F(delta)) = A0


L_OVER_A = 12.0     # block size / contact radius


FINE_XY = 1.25      # uniform spacing out to this multiple of a in x and y


FINE_Z = 0.5        # ... and to this depth / a


GROWTH = 1.2        # cell growth factor beyond the fine region


FIT_R = 0.85        # contact-radius fit over r < FIT_R a


RECOVERY = 2.0      # pressure recovery window half-width / h (see recovered_pressure)


# penetration tolerated before a node is activated, relative to the approach: the
# default (1e-10 x model size = 2e-7 delta) and the fixed multiplier tolerance
# (1e-12 max) are below the AMG solver noise of a node at
# the contact edge, whose gap and multiplier are both ~0, and the set cycles
GAP_TOL = 1e-4


def boussinesq(
    x: np.ndarray, F: float, E: float = MATERIAL.E, nu: float = MATERIAL.nu
) -> np.ndarray:
    """Displacement (3, n) of a half-space z < 0 under a point force ``F`` at
    the origin pressing into the body (along -z).

    Johnson, Contact Mechanics, eq. 3.20, with depth ``d = -z`` and ``u_d``
    positive into the body (our ``u_z = -u_d``)::

        u_d = F/(4 pi G) [2 (1 - nu)/rho + d^2/rho^3]
        u_r = F/(4 pi G) [r d/rho^3 - (1 - 2 nu)/(rho (rho + d))] r

    (radial component positive outward; on the surface it points inward).
    """
    x = np.asarray(x, dtype=float)
    G = E / (2.0 * (1.0 + nu))
    d = -x[2]
    r2 = x[0] ** 2 + x[1] ** 2
    rho = np.sqrt(r2 + d ** 2)
    c = F / (4.0 * np.pi * G)
    ud = c * (2.0 * (1.0 - nu) / rho + d ** 2 / rho ** 3)
    ur_over_r = c * (d / rho ** 3 - (1.0 - 2.0 * nu) / (rho * (rho + d)))
    return np.vstack([ur_over_r * x[0], ur_over_r * x[1], -ud])


def sphere_height(delta: float, profile: str = "sphere"):
    """Lower surface of the rigid indenter, ``z(x, y)``, after the approach ``delta``."""
    if profile == "sphere":
        return lambda x, y: R - np.sqrt(R ** 2 - (x ** 2 + y ** 2)) - delta
    if profile == "paraboloid":
        return lambda x, y: (x ** 2 + y ** 2) / (2.0 * R) - delta
    raise GeometryError(f"profile = {profile!r}; allowed: 'sphere', 'paraboloid'")


def axis(h: float, fine: float, length: float, growth: float | None = None) -> np.ndarray:
    """Nodes from 0 to ``length``: spacing ``h`` up to ``fine`` (rounded up
    to a whole number of cells), then cells growing by ``growth``."""
    growth = GROWTH if growth is None else growth
    nf = int(np.ceil(fine / h - 1e-9))
    x = list(np.arange(nf + 1) * h)
    size = h
    while x[-1] + size * growth * (1.0 + growth) / 2.0 < length:  # room for one more + the end
        size *= growth
        x.append(x[-1] + size)
    x = np.array(x + [length])
    return x


def mirrored_tets(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Tetrahedra on the tensor grid, each hexahedron Kuhn-split and reflected
    in every axis along which its index is odd.

    Neighbouring hexahedra are mirror images across their shared face, so the
    mesh is conforming and is its own mirror image across every grid plane:
    reflected across the symmetry planes it continues the same pattern.
    """
    p, _ = structured_tets(x, y, z)
    nx, ny, nz = len(x), len(y), len(z)
    idx = np.arange(nx * ny * nz).reshape(nx, ny, nz)
    i, j, k = (c.ravel() for c in np.meshgrid(np.arange(nx - 1), np.arange(ny - 1),
                                               np.arange(nz - 1), indexing="ij"))
    tets = []
    for path in KUHN:
        tets.append(np.vstack([idx[i + (dx ^ (i & 1)), j + (dy ^ (j & 1)), k + (dz ^ (k & 1))]
                               for dx, dy, dz in path]))
    return p, np.hstack(tets)


def block_mesh(h: float, a: float = A0, split: str = "mirrored", model: str = "quarter",
               order: int = 1):
    """The block with named faces, element size ``h`` at the patch
    (``model``: ``"quarter"`` 0 < x, y < L or ``"full"`` -L < x, y < L;
    ``split``: ``"mirrored"``, :func:`mirrored_tets`, or ``"kuhn"``, the plain
    Kuhn split, kept for comparison -- see the module)."""
    L = L_OVER_A * a
    xs = axis(h, FINE_XY * a, L)
    if model == "full":
        xs = np.concatenate([-xs[::-1], xs[1:]])
    elif model != "quarter":
        raise MeshError(f"model = {model!r}; allowed: 'quarter', 'full'")
    zs = -axis(h, FINE_Z * a, L)[::-1]
    if split == "mirrored":
        p, t = mirrored_tets(xs, xs, zs)
    elif split == "kuhn":
        p, t = structured_tets(xs, xs, zs)
    else:
        raise MeshError(f"split = {split!r}; allowed: 'mirrored', 'kuhn'")
    m = mapped_mesh(p, t, lambda q: q, order=order)
    tol = 1e-9 * L
    return m.with_boundaries({
        "top": lambda q: q[2] > -tol,
        "bottom": lambda q: q[2] < -L + tol,
        "x0": lambda q: q[0] < tol,
        "y0": lambda q: q[1] < tol,
        "xL": lambda q: np.abs(q[0]) > L - tol,
        "yL": lambda q: np.abs(q[1]) > L - tol,
    })


@dataclass
class HertzProblem:
    """The assembled Hertz model at one mesh size (everything before the solves)."""

    h_over_a: float
    mesh: object
    K: object            # stiffness (N x N, CSR/BSR), no boundary conditions
    pair: object         # ContactPair of the top face against the rigid sphere
    sym: np.ndarray      # symmetry DOFs (held at zero)
    far: np.ndarray      # far-field DOFs (Boussinesq displacements)
    copies: float        # 4 for the quarter model, 1 for the full one
    setup_s: float       # mesh + stiffness + pair

    @property
    def dofs(self) -> int:
        return int(self.K.shape[0])

    @property
    def fixed(self) -> np.ndarray:
        return np.concatenate([self.sym, self.far])

    def fixed_values(self, F_bc: float) -> np.ndarray:
        """Prescribed values of :attr:`fixed` for a far-field point force ``F_bc``."""
        far = self.far
        return np.concatenate([np.zeros(self.sym.size),
                               boussinesq(self.mesh.p[:, far // 3], F_bc)[far % 3,
                                                                          np.arange(far.size)]])


def hertz_dofs(h_over_a: float, model: str = "quarter", order: int = 1) -> int:
    """DOF count of :func:`block_mesh` at ``h = h_over_a * a``, without building it."""
    h = h_over_a * A0
    L = L_OVER_A * A0
    nx = len(axis(h, FINE_XY * A0, L))
    if model == "full":
        nx = 2 * nx - 1
    nz = len(axis(h, FINE_Z * A0, L))
    if order == 2:       # one mid-edge node per edge, face diagonal and cell diagonal
        return 3 * (2 * nx - 1) ** 2 * (2 * nz - 1)
    return 3 * nx * nx * nz


def hertz_resolution(target_dofs: float, model: str = "quarter") -> float:
    """``h / a`` whose mesh has the DOF count closest to ``target_dofs`` (log scale)."""
    best = None
    for ha in np.geomspace(0.01, 1.0, 600):
        err = abs(np.log(hertz_dofs(ha, model) / float(target_dofs)))
        if best is None or err < best[0]:
            best = (err, float(ha))
    return best[1]


def hertz_problem(h_over_a: float, profile: str = "sphere", model: str = "quarter",
                  split: str = "mirrored", order: int = 1) -> HertzProblem:
    """Mesh, stiffness and contact pair with element size ``h = h_over_a * a`` at the patch."""
    t0 = time.perf_counter()
    h = h_over_a * A0
    m = block_mesh(h, split=split, model=model, order=order)
    copies = 4.0 if model == "quarter" else 1.0
    K, _ = assemble_stiffness(m, MATERIAL)
    sym = (np.concatenate([boundary_dofs(m, "x0", [0]), boundary_dofs(m, "y0", [1])])
           if model == "quarter" else np.zeros(0, dtype=np.int64))
    far = np.concatenate([boundary_dofs(m, name) for name in ("xL", "yL", "bottom")])
    far_nodes = np.unique(far // 3)
    pair = pair_to_rigid(m, "top", 0, height=sphere_height(DELTA, profile), side=-1,
                         exclude=far_nodes, name="hertz")
    return HertzProblem(h_over_a, m, K, pair, sym, far, copies, time.perf_counter() - t0)


def hertz_force() -> float:
    """Hertz's force for the prescribed approach (the first far-field force)."""
    return 4.0 / 3.0 * ES * np.sqrt(R) * DELTA ** 1.5


def solve_problem(prob: HertzProblem, linear: str | None = None, outer_tol: float = 1e-9,
                  max_outer: int = 8, tol: float = 1e-10):
    """The secant iteration on the far-field force ``F_bc = F(F_bc)`` (see the module).

    Returns ``(out, res, F_bc)``: the figures of :func:`solve` (without the
    mesh-level ones), the last :class:`~brakewear.contact.ContactResult` and
    the far-field force of that last solve.  ``out["solve_s"]`` lists the
    time of every contact solve (the first is a cold start from the initial
    gaps, the others start from the previous active set).
    """
    K, pair, f = prob.K, prob.pair, np.zeros(prob.dofs)
    fixed = prob.fixed
    if linear is None:
        linear = "direct" if prob.dofs < 20_000 else "amg"  # SuperLU: 90 s at 43k DOFs, AMG 16 s

    def run(F_bc, active):
        res = solve_contact(K, f, fixed, prob.mesh.p, [pair], fixed_values=prob.fixed_values(F_bc),
                            linear=linear, tol=tol, gap_tol=GAP_TOL * DELTA,
                            initial_active=active)
        return res, prob.copies * float(res.force[0].sum())

    # secant iteration on F_bc = F_out(F_bc), starting from Hertz's F(delta)
    F_bc = hertz_force()
    hist, active, as_its, lin_its, times = [], None, [], [], []
    for k in range(max_outer):
        res, F_out = run(F_bc, active)
        active = res.active
        as_its.append(res.info["active_set_iterations"])
        lin_its.append(res.info["linear_iterations"])
        times.append(res.info["time_s"])
        hist.append((F_bc, F_out))
        logger.info("outer %d: F_bc %.9g N -> F %.9g N", k + 1, F_bc, F_out)
        if abs(F_out - F_bc) <= outer_tol * abs(F_out):
            break
        if len(hist) == 1:
            F_bc = F_out
        else:
            (x0, g0), (x1, g1) = hist[-2], hist[-1]
            s = (g1 - g0) / (x1 - x0)
            F_bc = x1 + (g1 - x1) / (1.0 - s)
    else:
        logger.warning("Boussinesq force iteration: |F - F_bc| / F = %.2e after %d solves",
                       abs(F_out - F_bc) / abs(F_out), max_outer)
    F_last = hist[-1][0]
    out = measure(prob.mesh, pair, res, F_out, h=prob.h_over_a * A0)
    out.update({
        "linear": linear, "outer_iterations": len(hist),
        "active_set_iterations": int(sum(as_its)), "active_set_iterations_per_solve": as_its,
        "linear_iterations_per_solve": lin_its, "solve_s": times,
        "outer_residual": abs(F_out - F_last) / abs(F_out),
        "F": F_out, "F_hertz_delta": hertz_force(),
    })
    return out, res, F_last


def solve(h_over_a: float, linear: str | None = None, profile: str = "sphere",
          model: str = "quarter", split: str = "mirrored",
          outer_tol: float = 1e-9, max_outer: int = 8, order: int = 1) -> dict:
    """Solve with element size ``h = h_over_a * a`` at the patch and element
    ``order``; errors against Hertz."""
    t0 = time.perf_counter()
    prob = hertz_problem(h_over_a, profile=profile, model=model, split=split, order=order)
    out, _, _ = solve_problem(prob, linear=linear, outer_tol=outer_tol, max_outer=max_outer)
    dt = time.perf_counter() - t0
    m = prob.mesh
    out.update({"h_over_a": h_over_a, "order": order, "dofs": prob.dofs, "nodes": m.p.shape[1],
                "elements": m.nelements, "time_s": dt, "setup_s": prob.setup_s})
    logger.info("hertz h/a=%.4g (%s): %d dofs, %.1f s, p0 %.2e a %.2e delta %.2e L2 %.2e",
                h_over_a, split, prob.dofs, dt, out["p0_err"], out["a_err"], out["delta_err"],
                out["l2_err"])
    return out


def recovered_pressure(x: np.ndarray, y: np.ndarray, force: np.ndarray, area: np.ndarray,
                       active: np.ndarray, width: float, mirror: bool = True) -> np.ndarray:
    """Contact pressure recovered from nodal contact forces: force over area
    in a tent window of half-width ``width`` around each node.

    ``p_i = sum_j w_ij f_j / sum_j w_ij A_j`` over the active nodes ``j``,
    ``w_ij = (1 - |x_i - x_j| / width)+ (1 - |y_i - y_j| / width)+``; zero on
    open nodes.  On the tensor grid with ``width = 2 h`` the weights are
    ``[1/4, 1/2, 1/4]`` in each direction, which give each of the four node
    types of the mirror-symmetric split (parity of the grid indices) the
    same total weight: the node-type oscillation of ``f_i / A_i`` cancels
    and a smooth pressure is reproduced to ``(h^2 / 4) lap p``.
    ``mirror``: the nodes are a quarter model (symmetry planes ``x = 0`` and
    ``y = 0``); their mirror images enter the sums, so a node on a plane
    counts with its full force and area.
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    force, area = np.asarray(force, float), np.asarray(area, float)
    active = np.asarray(active, bool)
    if not width > 0.0:
        raise ContactError(f"recovered_pressure: width = {width!r}; need a positive length")
    for name, v in (("y", y), ("force", force), ("area", area), ("active", active)):
        if v.shape != x.shape:
            raise ContactError(f"recovered_pressure: {name} has shape {v.shape}, x has {x.shape}")
    out = np.zeros(x.shape)
    ia = np.flatnonzero(active)
    if ia.size == 0:
        return out
    xa, ya, fa, aa = x[ia], y[ia], force[ia], area[ia]
    num = np.zeros(ia.size)
    den = np.zeros(ia.size)
    for sx, sy in (((1, 1), (-1, 1), (1, -1), (-1, -1)) if mirror else ((1, 1),)):
        w = (np.clip(1.0 - np.abs(xa[:, None] - sx * xa[None]) / width, 0.0, None)
             * np.clip(1.0 - np.abs(ya[:, None] - sy * ya[None]) / width, 0.0, None))
        num += w @ fa
        den += w @ aa
    out[ia] = num / den
    return out


def measure(m, pair, res, F: float, h: float | None = None) -> dict:
    """Errors of the contact solution against Hertz at the computed force ``F``.

    ``h``: element size at the patch (the recovery window is ``RECOVERY * h``);
    by default the distance from the origin to its nearest slave node.
    """
    hz = hertz_sphere(F, R, ES)
    xs = m.p[:, pair.slave]
    r = np.hypot(xs[0], xs[1])
    p_nodal = res.pressure[0]
    act = res.active[0]
    A = pair.area
    origin = int(np.argmin(r))
    if r[origin] > 1e-12 * A0:
        raise ContactError(f"measure: no slave node at the origin (nearest at r = "
                           f"{r[origin]:.3g} m)")
    if h is None:
        h = float(np.sort(r)[1])
    # a quadratic face: the dual multiplier's nodal values as they are (a window
    # over its node-type period 2h would blur the peak by (h^2/4) lap p, -21 % at h = a/2)
    p = p_nodal if pair.basis is not None else \
        recovered_pressure(xs[0], xs[1], res.force[0], A, act, RECOVERY * h)
    p0_h = float(p[origin])
    # contact radius: area-weighted fit of p^2 = c + m r^2 to the nodal pressures
    # (the weights balance the node types; the recovered pressure is smoothed by
    # ~h^2 lap p, which grows toward the edge)
    sel = act & (r < FIT_R * hz["a"])
    slope, icpt = np.polyfit(r[sel] ** 2, p_nodal[sel] ** 2, 1, w=np.sqrt(A[sel]))
    a_h = float(np.sqrt(-icpt / slope)) if slope < 0 < icpt else float("nan")
    ph = hertz_sphere_pressure(r, F, R, ES)
    norm = np.sum(A * ph ** 2)
    inner = r < hz["a"] - RECOVERY * h
    # the radius as the peers read it: of the active nodes' tributary area (the quarter's
    # mirror images included) and of the outermost active node
    copies = 4.0 if xs[0].min() >= -1e-12 * A0 and xs[1].min() >= -1e-12 * A0 else 1.0
    a_area = float(np.sqrt(copies * A[act].sum() / np.pi))
    a_outer = float(r[act].max()) if act.any() else float("nan")
    return {
        "p0_err": p0_h / hz["p0"] - 1.0, "a_err": a_h / hz["a"] - 1.0,
        "a_area_err": a_area / hz["a"] - 1.0, "a_outer_err": a_outer / hz["a"] - 1.0,
        "delta_err": DELTA / hz["delta"] - 1.0,
        "l2_err": float(np.sqrt(np.sum(A * (p - ph) ** 2) / norm)),
        # nan when the mesh is too coarse to have a node inside a - 2h
        "l2_inner_err": float(np.sqrt(np.sum((A * (p - ph) ** 2)[inner])
                                      / np.sum((A * ph ** 2)[inner]))) if inner.any()
        else float("nan"),
        "p0_nodal_err": float(p_nodal[origin]) / hz["p0"] - 1.0,
        "l2_nodal_err": float(np.sqrt(np.sum(A * (p_nodal - ph) ** 2) / norm)),
        "p0_h": p0_h, "p0": hz["p0"], "a_h": a_h, "a": hz["a"], "delta": DELTA,
        "n_active": int(act.sum()), "a_fit_points": int(sel.sum()),
        "profile": {"x": xs[0], "y": xs[1], "r": r, "p": p, "p_nodal": p_nodal,
                    "p_hertz": ph, "area": A, "active": act},
    }
