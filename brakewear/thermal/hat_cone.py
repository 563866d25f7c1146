"""The cone of a hat rotor whose friction ring is heated: closed forms, an axisymmetric model.

The ring grows radially by ``alpha dT r``; the cold hat wall holds its inner
corner back, so the ring's section rotates and the friction faces cone.
:func:`hat_cone_estimate` gives the cone in closed form (the ring as a free
annular plate, :func:`annulus_edge`, or as a rigid section, on a Timoshenko
cylindrical shell clamped at the flange, :func:`shell_edge_stiffness`);
:func:`axisymmetric_cone` solves the rotor's (r, z) section with P2 triangles.
A free plate heated linearly through its thickness dishes without stress
(:func:`plate_curvature`).  docs/thermal.md compares both with the 3D model.
"""
from __future__ import annotations

import numpy as np
import skfem as fem

from ..errors import ThermalError
from ..fem import apply_dirichlet
from ..fem.forms import lame_parameters
from ..solvers.direct import direct_solve

__all__ = ["plate_curvature", "shell_constants", "shell_edge_stiffness", "annulus_edge",
           "hat_cone_estimate", "section_mesh", "axisymmetric_cone", "face_cone"]


def plate_curvature(alpha: float, dT: float, t: float) -> float:
    """Curvature of a free plate whose temperature rises linearly through its thickness.

    Parameters
    ----------
    alpha
        Thermal expansion (1/K).
    dT
        Temperature difference between the faces (K).
    t
        Thickness (m).

    Returns
    -------
    float
        ``alpha dT / t`` (1/m): the plate dishes into a sphere, free of stress.

    >>> round(plate_curvature(1.2e-5, 100.0, 0.012), 12)
    0.1
    """
    return alpha * dT / t


def shell_constants(E: float, nu: float, a: float, h: float) -> tuple[float, float]:
    """Decay constant and bending stiffness of a thin cylindrical shell.

    Parameters
    ----------
    E, nu
        Young's modulus (Pa) and Poisson's ratio.
    a, h
        Mid-surface radius and wall thickness (m).

    Returns
    -------
    tuple of float
        ``beta = (3 (1 - nu^2) / (a h)^2)^(1/4)`` (1/m) and
        ``D = E h^3 / 12 (1 - nu^2)`` (N m).
    """
    return (3.0 * (1.0 - nu ** 2) / (a * h) ** 2) ** 0.25, E * h ** 3 / (12.0 * (1.0 - nu ** 2))


def _decaying(beta: float, y: float, A: float, B: float, k: int) -> float:
    """``d^k/dy^k`` of ``exp(-beta y) (A cos beta y + B sin beta y)``."""
    for _ in range(k):
        A, B = beta * (B - A), -beta * (A + B)
    return float(np.exp(-beta * y) * (A * np.cos(beta * y) + B * np.sin(beta * y)))


def shell_edge_stiffness(beta: float, D: float, L: float = np.inf) -> np.ndarray:
    """Edge stiffness of a cylindrical shell under axisymmetric bending.

    ``[Q, M] = K [w0, theta0]`` (per unit circumference) for the radial
    displacement ``w0`` and slope ``theta0 = dw/dx`` of the edge ``x = 0``, the
    other end ``x = L`` clamped (Timoshenko's beam on elastic foundation,
    ``D w'''' + 4 beta^4 D w = 0``).

    Parameters
    ----------
    beta, D
        :func:`shell_constants`.
    L
        Length to the clamped end (m); ``inf``: the semi-infinite shell,
        ``K = 2 beta D [[2 beta^2, beta], [beta, 1]]``.

    Returns
    -------
    numpy.ndarray
        The 2 x 2 matrix ``K``.
    """
    if not np.isfinite(L):
        return 2.0 * beta * D * np.array([[2.0 * beta ** 2, beta], [beta, 1.0]])
    # four solutions: decaying from x = 0 and from x = L
    basis = [(0, 1.0, 0.0), (0, 0.0, 1.0), (1, 1.0, 0.0), (1, 0.0, 1.0)]

    def val(fn, x, k):
        far, A, B = fn
        return (
            _decaying(beta, x, A, B, k) if not far else (-1) ** k * _decaying(beta, L - x, A, B, k)
        )

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

    Parameters
    ----------
    b, a
        Inner and outer radius (m).
    nu
        Poisson's ratio.
    r
        Radii (m) at which to give the slope and the rise, or None.

    Returns
    -------
    float or tuple
        ``s = (1/b^2 - 1/a^2) / ((1 - nu) b / a^2 + (1 + nu) / b)``: the
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

    Parameters
    ----------
    geom
        A brake geometry whose rotor has a hat.
    dT
        Temperature rise of the ring (K).
    ring
        ``"plate"`` or ``"rigid"`` (below).
    L
        Length of the shell to its clamp (m); default the hat's height less half
        its flange.

    Returns
    -------
    dict
        ``psi``, ``cone``, ``U``, ``runout`` (below), the shell's ``beta``, ``L``,
        ``beta_L``, the ring's and the shell's stiffnesses.

    Notes
    -----
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
        raise ThermalError(f"hat_cone_estimate: ring = {ring!r} is not allowed; "
                           "allowed: 'plate', 'rigid'")
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


def _section_blocks(geom) -> list[tuple[float, float, float, float]]:
    """The hat rotor's section as rectangles (r0, r1, z0, z1), ring first."""
    ro_, hat = geom.rotor, geom.rotor.hat
    t, ri, ro = ro_.thickness, ro_.inner_radius, ro_.outer_radius
    wi, wo = hat.wall_radius - 0.5 * hat.wall_thickness, hat.wall_radius + 0.5 * hat.wall_thickness
    zb = -t - hat.height
    return [(min(ri, wi), ro, -t, 0.0), (wi, wo, zb, -t),
            (hat.bore_radius, wo, zb, zb + hat.flange_thickness)]


def section_mesh(geom, size: float) -> fem.MeshTri:
    """Triangles of a hat rotor's (r, z) section.

    Parameters
    ----------
    geom
        A brake geometry whose rotor has a hat.
    size
        Element size (m).

    Returns
    -------
    skfem.MeshTri
        One tensor grid through every break, cells outside the section dropped;
        subdomains ``ring`` and ``hat``, facets ``clamp`` (the mounting face out
        to the bolt circle) and ``face`` (the inboard friction face, z = 0).
    """
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
    """The cone of a hat rotor whose ring is heated by ``dT``, as an axisymmetric body.

    The section (:func:`section_mesh`, P2 triangles) is clamped at the mounting
    face; ``r`` weights the isotropic forms, and the thermal load of the ring's
    elements is ``int (3 lambda + 2 mu) alpha dT tr eps(v) r``.

    Parameters
    ----------
    geom
        A brake geometry whose rotor has a hat.
    dT
        Temperature rise of the ring (K); the hat stays at the reference.
    size
        Element size (m).

    Returns
    -------
    dict
        :func:`face_cone`'s ``cone``, ``runout`` and face profile, with the
        ``dofs``, the ``mesh``, the displacement ``u`` and its ``basis``.
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
    out = face_cone(geom, xr, uz)
    out.update(dofs=int(K.shape[0]), mesh=m, u=u, basis=basis)
    return out


def face_cone(geom, r: np.ndarray, uz: np.ndarray) -> dict:
    """Cone angle and run-out of a friction face from its axial displacements.

    Parameters
    ----------
    geom
        The brake geometry (its rotor's radii).
    r, uz
        Radius (m) and axial displacement (m) of the face's nodes.

    Returns
    -------
    dict
        ``cone`` (rad, the slope of a cubic fit of ``u_z(r)`` over the friction
        band at its mid radius), ``runout`` (m, the fit at the outer radius),
        ``fit_rms`` and the band's ``r``, ``uz``.
    """
    ri, ro = geom.rotor.inner_radius, geom.rotor.outer_radius
    sel = r >= ri - 1e-9
    c = np.polyfit(r[sel] - ri, uz[sel], 3)
    rm = 0.5 * (ro - ri)
    return {"cone": float(np.polyval(np.polyder(c), rm)), "runout": float(np.polyval(c, ro - ri)),
            "fit_rms": float(np.sqrt(np.mean((np.polyval(c, r[sel] - ri) - uz[sel]) ** 2))),
            "r": r[sel], "uz": uz[sel]}
