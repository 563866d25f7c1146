"""Elastic-foundation (Winkler) interface model of the pad-rotor contact.

A condensed interface model: the friction layer (and, optionally, the rotor)
is a bed of independent springs, ``p_i = k_i * max(0, delta_i)``, under a
rigid pad backing with three degrees of freedom -- the approach ``w`` at the
load point and two tilts ``(a, b)``::

    delta_i = w + a (x_i - x_L) + b (y_i - y_L) - g_i

``(x_L, y_L)`` is the load point (centre of the piston footprint) and
``g_i`` the gap (initial offset plus wear).  The backing is in force *and*
moment balance with the clamp force ``F`` at the load point and with the
friction couple: sliding friction ``mu p`` drags the pad along the rotor's
velocity at the friction face (z = 0), the abutment holds it at a height
``lever_arm`` above the face, and the couple ``lever_arm x (friction
resultant)`` tips the pad toward its leading edge::

    sum_i A_i p_i                                   = F
    sum_i A_i p_i (x_i - x_L + lever_arm mu d_x,i)  = 0
    sum_i A_i p_i (y_i - y_L + lever_arm mu d_y,i)  = 0

(``d`` the unit rotor-velocity direction at node i).  The equations are
piecewise linear in ``(w, a, b)``.  Without friction they are the gradient
of a convex energy: a semi-smooth Newton iteration with its own active set
``delta_i > 0`` and an exact line search solves them from any start, and
exactly -- once the active set repeats, the last step solved that set's
linear system, so the residual is round-off.  With friction, a fixed point
on the effective load line (contraction ~ lever_arm mu / r) is finished by
exact Newton steps on the full balance.  A solve on the default brake's
friction face takes about a millisecond or less.

The modulus is Johnson's thin-layer formula (:func:`johnson_modulus`;
:func:`layer_modulus` for a transversely isotropic friction layer) or is
calibrated against an FE contact solution by :func:`calibrate`, which
reports what it matched and how far off the rest is.  See docs/foundation.md.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import FoundationError, FoundationSolveError

logger = logging.getLogger(__name__)

__all__ = ["layer_modulus", "WinklerInterface", "FoundationResult"]


def layer_modulus(material, thickness: float, constrained: bool = True) -> float:
    """Foundation modulus of a layer of ``material`` (a :class:`brakewear.materials.Material`
    or its elastic part) of the given thickness.

    Constrained: ``C_zz / h``, the layer's one-dimensional (oedometric)
    modulus over its thickness -- Johnson's constrained formula for an
    isotropic layer, and its natural extension to the transversely isotropic
    friction material.  Unconstrained: ``E_normal / h``.
    """
    if not (np.isfinite(thickness) and thickness > 0):
        raise FoundationError(f"thickness = {thickness!r} m is not allowed; need a finite "
                              "value > 0")
    el = getattr(material, "elastic", material)
    if constrained:
        return float(el.voigt()[2, 2]) / thickness
    return float(el.E_normal) / thickness


def _positive_array(name: str, value, n: int) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        if not (np.isfinite(arr) and arr > 0):
            raise FoundationError(f"{name} = {float(arr)!r} is not allowed; need a finite "
                                  "value > 0")
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        raise FoundationError(f"{name} has shape {arr.shape}; need a number or an array of "
                              f"shape ({n},), one value per interface node")
    bad = ~(np.isfinite(arr) & (arr > 0))
    if bad.any():
        i = int(np.nonzero(bad)[0][0])
        raise FoundationError(f"{name} = {float(arr[i])!r} at node {i} is not allowed "
                              f"({int(bad.sum())} such value(s)); need finite values > 0")
    return arr


@dataclass
class FoundationResult:
    """Solution of one foundation contact (arrays over the interface nodes)."""

    pressure: np.ndarray      # (n,) Pa
    active: np.ndarray        # (n,) bool, in contact
    approach: float           # m, approach of the backing at the load point
    tilts: np.ndarray         # (2,) slopes d delta/dx, d delta/dy of the backing (rad)
    force: float              # N, normal force carried (= the clamp force)
    interference: np.ndarray  # (n,) m, w + a x + b y - g (negative: open gap)
    friction: np.ndarray      # (2,) N, in-plane friction resultant on the pad
    centre: np.ndarray        # (2,) m, centre of pressure (x, y)
    iterations: int
    residual: float           # relative force/moment residual at the end
    time_s: float
    area: np.ndarray = field(repr=False, default=None)  # (n,) tributary areas (m^2)

    @property
    def stiffness(self) -> float:
        """Secant stiffness F / approach (N/m) of the interface at this load."""
        return self.force / self.approach

    @property
    def contact_area(self) -> float:
        """Area of the nodes in contact (m^2)."""
        return float(self.area[self.active].sum())


@dataclass(frozen=True)
class WinklerInterface:
    """Winkler contact of a rigidly backed pad face against the rotor.

    Parameters
    ----------
    xy
        (2, n) node positions in the interface plane (m).
    area
        (n,) tributary areas (m^2).
    modulus
        Foundation modulus (Pa/m): a number or (n,) per node, > 0.  This is
        the effective modulus (pad and rotor layers in series already).
    load_point
        (x, y) where the clamp force acts (m).
    offset
        (n,) initial gap of each node (m), default 0 (flat pad on a flat rotor).
    drag
        (2, n) unit direction of the rotor's velocity at each node (friction
        drags the pad along it); needed for ``mu > 0``.
    lever_arm
        Height of the abutment reaction above the friction face (m): the
        friction couple is ``lever_arm x`` the friction resultant.
    hydraulic_area
        Converts line pressure to clamp force (m^2); 1 makes "line pressure"
        the force itself.
    nodes
        Pad vertex indices of the interface nodes (from :meth:`from_model`).
    footprint
        Centre of the piston footprint (m), where the approach that does work
        with the clamp force is measured (:attr:`FoundationResult.approach`
        is at ``load_point``); default ``load_point``.  They differ only
        after a pressure calibration moves the effective load line.
    load_nodes, load_weights
        The pad nodes the FE model's clamp load acts on and their shares of it
        (summing to 1; from :meth:`from_model`), or None.
    info
        Where the modulus came from (for reports).
    """

    xy: np.ndarray
    area: np.ndarray
    modulus: np.ndarray
    load_point: np.ndarray
    offset: np.ndarray | None = None
    drag: np.ndarray | None = None
    lever_arm: float = 0.0
    hydraulic_area: float = 1.0
    nodes: np.ndarray | None = None
    footprint: np.ndarray | None = None
    load_nodes: np.ndarray | None = field(default=None, repr=False)
    load_weights: np.ndarray | None = field(default=None, repr=False)
    info: dict = field(default_factory=dict)

    def __post_init__(self):
        xy = np.asarray(self.xy, dtype=float)
        if xy.ndim != 2 or xy.shape[0] != 2 or xy.shape[1] < 3:
            raise FoundationError(f"xy has shape {xy.shape}; need (2, n) with n >= 3 nodes")
        n = xy.shape[1]
        object.__setattr__(self, "xy", xy)
        try:
            from scipy.spatial import ConvexHull
            eq = ConvexHull(xy.T).equations          # inside: eq[:, :2] x + eq[:, 2] <= 0
        except Exception as exc:                      # collinear nodes
            raise FoundationError(f"the interface nodes span no area ({exc})") from None
        object.__setattr__(self, "_hull", eq)
        object.__setattr__(self, "area", _positive_array("area", self.area, n))
        object.__setattr__(self, "modulus", _positive_array("modulus", self.modulus, n))
        lp = np.asarray(self.load_point, dtype=float)
        if lp.shape != (2,) or not np.all(np.isfinite(lp)):
            raise FoundationError(f"load_point = {self.load_point!r}; need finite (x, y)")
        object.__setattr__(self, "load_point", lp)
        fp = lp.copy() if self.footprint is None else np.asarray(self.footprint, dtype=float)
        if fp.shape != (2,):
            raise FoundationError(f"footprint = {self.footprint!r}; need (x, y)")
        object.__setattr__(self, "footprint", fp)
        off = np.zeros(n) if self.offset is None else np.asarray(self.offset, dtype=float)
        if off.shape != (n,) or not np.all(np.isfinite(off)):
            raise FoundationError(f"offset has shape {off.shape}; need finite values, shape ({n},)")
        object.__setattr__(self, "offset", off)
        if self.drag is not None:
            d = np.asarray(self.drag, dtype=float)
            if d.shape != (2, n):
                raise FoundationError(f"drag has shape {d.shape}; need (2, {n})")
            object.__setattr__(self, "drag", d)
        if not (np.isfinite(self.lever_arm) and self.lever_arm >= 0):
            raise FoundationError(f"lever_arm = {self.lever_arm!r} m; need a finite value >= 0")
        if not (np.isfinite(self.hydraulic_area) and self.hydraulic_area > 0):
            raise FoundationError(f"hydraulic_area = {self.hydraulic_area!r}; need > 0")

    # ------------------------------------------------------------ builders --
    @classmethod
    def from_model(cls, model, modulus=None, rotor: str = "rigid",
                   lever_arm: float | None = None, constrained: bool = True) -> WinklerInterface:
        """The pad-rotor interface of a :class:`brakewear.model.BrakeModel`.

        Nodes are the pad's friction nodes in the order of
        ``surface_nodes(pad_mesh, "friction")`` (the order of the FE contact
        results), with their tributary areas.

        Parameters
        ----------
        model
            The brake model (only its geometry and pad mesh are used).
        modulus
            Modulus of the pad's friction layer (Pa/m): ``None`` --
            :func:`layer_modulus` of the friction material over the friction
            thickness (constrained layer, ``C_zz / h_f``); a number; or one
            value per node.
        rotor
            ``"rigid"``: the rotor does not deform; ``"foundation"``: the
            rotor's half thickness (the meshed half, symmetric about its
            mid-plane) is a second constrained layer, in series:
            ``1/k = 1/k_pad + 1/k_rotor``.
        lever_arm
            Height of the abutment reaction above the friction face (m);
            default the mid-height of the backplate's end faces,
            ``friction_thickness + backplate_thickness / 2`` (the FE model
            holds the pad in-plane on those faces).
        """
        from ..mesh.surface import surface_nodes, tributary_areas

        if rotor not in ("rigid", "foundation"):
            raise FoundationError(f"rotor = {rotor!r} is not allowed; allowed: 'rigid', "
                                  "'foundation'")
        g = model.geometry
        pad = model.meshes["pad"]
        nodes = surface_nodes(pad, "friction")
        area = tributary_areas(pad, "friction", nodes)
        xy = pad.p[:2, nodes]
        if modulus is None:
            k_pad = np.full(nodes.size, layer_modulus(g.pad.friction_material,
                                                      g.pad.friction_thickness, constrained))
            source = f"layer_modulus(friction material, h = {g.pad.friction_thickness:.4g} m)"
        else:
            k_pad = _positive_array("modulus", modulus, nodes.size)
            source = "given"
        k = k_pad
        k_rot = None
        if rotor == "foundation":
            k_rot = layer_modulus(g.rotor.material, 0.5 * g.rotor.thickness, constrained)
            k = 1.0 / (1.0 / k_pad + 1.0 / k_rot)
            source += f" in series with the rotor half thickness (k_rotor = {k_rot:.4g} Pa/m)"
        # the FE model's clamp load (the piston footprints integrated on the back
        # facets): its nodal shares, and its resultant's point
        from ..caliper.loads import clamp_loads

        fz = -clamp_loads(g, pad, 1.0, full=False, sides=("in",))[2::3]
        lnodes = np.flatnonzero(fz)
        lw = fz[lnodes]
        load_point = (pad.p[:2, lnodes] * lw).sum(axis=1) / lw.sum()
        r = np.hypot(xy[0], xy[1])
        drag = np.vstack([-xy[1], xy[0]]) / r
        if lever_arm is None:
            lever_arm = g.pad.friction_thickness + 0.5 * g.pad.backplate_thickness
        return cls(xy, area, k, load_point, drag=drag, lever_arm=float(lever_arm),
                   hydraulic_area=g.clamp_area, nodes=nodes, load_nodes=lnodes,
                   load_weights=lw / lw.sum(),
                   info={"modulus_source": source, "rotor": rotor,
                         "pad_modulus_mean": float(k_pad.mean()),
                         "rotor_modulus": k_rot})

    def with_modulus(self, modulus, offset=None, **info) -> WinklerInterface:
        """A copy with another modulus (and optionally offset); ``info`` is added."""
        n = self.xy.shape[1]
        return replace(self, modulus=_positive_array("modulus", modulus, n),
                       offset=self.offset if offset is None else offset,
                       info={**self.info, **info})

    @property
    def n(self) -> int:
        return self.xy.shape[1]

    # --------------------------------------------------------------- solve --
    def solve(self, line_pressure: float, mu: float = 0.0, gap=None,
              tol: float = 1e-10, max_iter: int = 100) -> FoundationResult:
        """Contact under a line pressure (Pa): clamp force = line_pressure * hydraulic_area.

        ``gap`` (n,) is an extra gap per node (m), e.g. the wear depths of pad
        and rotor seen by each pad node; it adds to :attr:`offset`.
        """
        if not (np.isfinite(line_pressure) and line_pressure > 0):
            raise FoundationError(f"line_pressure = {line_pressure!r} Pa is not allowed; need > 0")
        return self.solve_force(line_pressure * self.hydraulic_area, mu, gap, tol, max_iter)

    def solve_force(self, force: float, mu: float = 0.0, gap=None, tol: float = 1e-10,
                    max_iter: int = 100) -> FoundationResult:
        """Contact under a clamp force (N) at the load point; see :meth:`solve`."""
        t0 = time.perf_counter()
        if not (np.isfinite(force) and force > 0):
            raise FoundationError(f"force = {force!r} N is not allowed; need > 0")
        if not (np.isfinite(mu) and mu >= 0):
            raise FoundationError(f"mu = {mu!r} is not allowed; need a friction coefficient >= 0")
        if mu > 0 and self.drag is None:
            raise FoundationError("mu > 0 needs the rotor's velocity direction (drag) per node")
        n = self.n
        g = self.offset
        if gap is not None:
            gap = np.asarray(gap, dtype=float)
            if gap.shape != (n,):
                raise FoundationError(f"gap has shape {gap.shape}; need ({n},), one value per "
                                      "interface node, in the order of the interface nodes")
            if not np.all(np.isfinite(gap)):
                raise FoundationError("gap contains non-finite values")
            g = g + gap
        c = self.area * self.modulus
        X0 = self.xy - self.load_point[:, None]
        L = float(np.abs(X0).max()) or 1.0
        if mu > 0 and self.lever_arm > 0:
            # The friction couple: sum A p (x - x_L + lever mu d) = 0, i.e. the centre
            # of pressure is x_L - lever mu dbar(p), dbar the pressure-weighted drag.
            # dbar varies slowly with p (its tangent turns by the shift over the
            # radius), so a fixed point on the effective load point, each a
            # frictionless solve, converges fast (factor ~ lever mu / r).
            lp, q, its, done = self.load_point.copy(), None, 0, False
            e = self.lever_arm * mu * self.drag
            for _ in range(100):
                q, d, k = _frictionless(self.xy, lp, c, g, force, L, q, max_iter, self._hull)
                its += k
                fz = c * np.maximum(d, 0.0)
                new = self.load_point - (e * fz).sum(axis=1) / fz.sum()
                q = q.copy()  # same backing, expressed at the new load point
                q[0] += (q[1] * (new - lp)[0] + q[2] * (new - lp)[1]) / L
                step = float(np.abs(new - lp).max())
                lp = new
                if step <= 1e-6 * L:
                    # close: the exact semi-smooth Newton on the full balance finishes
                    pol = _polish(self.xy, self.load_point, lp, q, c, g, e, force, L)
                    if pol is not None:
                        q, d, k = pol
                        its += k
                        lp, done = self.load_point, True
                        break
                if step <= 1e-13 * L:
                    break
            else:
                raise FoundationSolveError(
                    f"foundation contact: the friction fixed point did not settle in 100 "
                    f"iterations (last load-line change {step:.2e} m, mu = {mu}, lever_arm = "
                    f"{self.lever_arm} m)")
            if not done:
                q, d, k = _frictionless(self.xy, lp, c, g, force, L, q, max_iter, self._hull)
                its += k
            it = its
        else:
            lp = self.load_point
            q, d, it = _frictionless(self.xy, lp, c, g, force, L, None, max_iter, self._hull)
        # the approach and tilts of the backing, at the load point
        tilts = q[1:] / L
        w = float(q[0] + tilts @ (self.load_point - lp))
        # residual of the full balance (friction couple included)
        P = c * np.maximum(d, 0.0)
        Xr = X0 + (self.lever_arm * mu * self.drag if mu > 0 else 0.0)
        R = np.array([P.sum() - force, (P * Xr[0]).sum() / L, (P * Xr[1]).sum() / L])
        rel = float(np.linalg.norm(R) / force)
        if rel > tol:
            raise FoundationSolveError(
                f"foundation contact: balance residual {rel:.2e} > tol {tol:.1e} after {it} "
                f"iterations ({int((d > 0).sum())} of {n} nodes in contact)")
        p = self.modulus * np.maximum(d, 0.0)
        Fn = float((self.area * p).sum())
        fr = mu * (self.area * p * self.drag).sum(axis=1) if mu > 0 else np.zeros(2)
        centre = (self.xy * (self.area * p)).sum(axis=1) / Fn
        res = FoundationResult(p, d > 0, w, tilts, Fn, d, fr, centre, it, rel,
                               time.perf_counter() - t0, self.area)
        logger.debug("foundation solve: %d iterations, %d/%d in contact, residual %.1e",
                     it, int((d > 0).sum()), n, rel)
        return res


def _frictionless(xy, load_point, c, g, force, L, q0, max_iter, hull=None):
    """Minimise the convex energy 1/2 sum c max(delta, 0)^2 - F w over the backing
    q = (w, a L, b L) (delta = B q - g): its gradient is the force and moment
    balance about ``load_point``.  Semi-smooth Newton on the active set, each
    step followed by an exact line search (the energy is piecewise quadratic
    along a line), so it converges from any start and the last step, once the
    active set repeats, is exact.  Returns (q, delta, iterations).

    A load line outside the convex hull of the nodes cannot be balanced by
    any compressive pressure: refused at once (the pad would tip off).
    """
    n = xy.shape[1]
    if hull is not None:
        out = float((hull[:, :2] @ load_point + hull[:, 2]).max())
        if out > 1e-12 * L:
            raise FoundationSolveError(
                f"foundation contact found no equilibrium: the load line (clamp force and "
                f"friction couple) passes through {load_point} m, {out:.3g} m outside the "
                "contact face; no compressive pressure can balance it (the pad tips off its "
                "contact). Check the load point, mu and lever_arm.")
    X = (xy - load_point[:, None]) / L
    B = np.column_stack([np.ones(n), X[0], X[1]])
    rhs = np.array([force, 0.0, 0.0])
    H_all = B.T @ (c[:, None] * B)
    q = np.linalg.solve(H_all, rhs + B.T @ (c * g)) if q0 is None else q0
    d = B @ q - g
    for it in range(1, max_iter + 1):
        act = d > 0
        R = B.T @ (c * np.maximum(d, 0.0)) - rhs
        if act.any() and np.linalg.norm(R) <= 1e-13 * force:
            return q, d, it - 1
        H = B[act].T @ (c[act, None] * B[act])
        if not act.any() or np.linalg.cond(H) > 1e12:
            H = H + 1e-8 * H_all  # fewer than three nodes carry: keep the step defined
        dq = np.linalg.solve(H, -R)
        t = _line_minimum(d, B @ dq, c, float(rhs @ dq), force, load_point)
        q = q + t * dq
        d = B @ q - g
        R = B.T @ (c * np.maximum(d, 0.0)) - rhs
        if np.array_equal(d > 0, act) and np.linalg.norm(R) <= 1e-13 * force:
            return q, d, it
    raise FoundationSolveError(
        f"foundation contact found no equilibrium in {max_iter} iterations (relative residual "
        f"{np.linalg.norm(R) / force:.2e}, {int((d > 0).sum())} of {n} nodes in contact)")


def _polish(xy, load_point, lp, q, c, g, e, force, L, steps: int = 4):
    """A few exact semi-smooth Newton steps on the full balance (friction couple
    ``e = lever mu drag`` included) from a backing ``q`` given at ``lp``;
    returns (q at ``load_point``, delta, steps) or None if it does not settle."""
    n = xy.shape[1]
    q = q.copy()
    q[0] += (q[1] * (load_point - lp)[0] + q[2] * (load_point - lp)[1]) / L
    X = (xy - load_point[:, None]) / L
    B = np.column_stack([np.ones(n), X[0], X[1]])
    C = np.column_stack([np.ones(n), X[0] + e[0] / L, X[1] + e[1] / L])
    rhs = np.array([force, 0.0, 0.0])
    act_prev = None
    for k in range(steps + 1):
        d = B @ q - g
        act = d > 0
        R = C.T @ (c * np.maximum(d, 0.0)) - rhs
        if np.linalg.norm(R) <= 1e-13 * force and (act_prev is None or
                                                  np.array_equal(act, act_prev)):
            return q, d, k
        if k == steps or act.sum() < 3:
            return None
        J = C[act].T @ (c[act, None] * B[act])
        q = q - np.linalg.solve(J, R)
        act_prev = act
    return None


def _line_minimum(d, s, c, r0, force, load_point):
    """Exact minimiser t > 0 of the energy along q + t dq: the root of
    phi'(t) = sum c s max(d + t s, 0) - r0, a non-decreasing piecewise-linear
    function (breakpoints where nodes touch or open)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        tb = np.where(s != 0, -d / s, np.inf)
    on0 = (d > 0) | ((d == 0) & (s > 0))
    A0 = float((c * s * d)[on0].sum())
    S0 = float((c * s * s)[on0].sum())
    ev = np.nonzero((tb > 0) & np.isfinite(tb))[0]
    ev = ev[np.argsort(tb[ev])]
    sign = np.where(s[ev] > 0, 1.0, -1.0)   # entering (s > 0) or leaving contact
    A = A0 + np.concatenate([[0.0], np.cumsum(sign * c[ev] * s[ev] * d[ev])])
    S = S0 + np.concatenate([[0.0], np.cumsum(sign * c[ev] * s[ev] ** 2)])
    # phi' at the end of each interval (the last one is unbounded)
    tend = tb[ev]
    dphi = A[:-1] + tend * S[:-1] - r0
    k = int(np.argmax(dphi >= 0)) if np.any(dphi >= 0) else ev.size
    if S[k] <= 0:
        raise FoundationSolveError(
            "foundation contact found no equilibrium: the energy decreases without bound "
            f"along the Newton direction -- the clamp force {force:.4g} N at the load point "
            f"{load_point} m cannot be balanced by the face (the pad tips off its contact, "
            "or the load line lies outside the face)")
    return max((r0 - A[k]) / S[k], 0.0)
