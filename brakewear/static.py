"""Static solves of a brake model, and what they report.

:func:`solve_tied` (the pad tied to the rotor) and :func:`solve_contact`
(frictional contact; a model whose piston is rigid is held by its caliper's
parts, :func:`brakewear.caliper.static.solve_caliper`) take a
:class:`~brakewear.model.BrakeModel`, which is data: meshes, materials,
stiffness matrices and the contact system; they return a
:class:`StaticResult`.  :func:`static_summary` and :func:`body_stresses`
report it.

Per friction face (the half model has one, the full model the inboard
``in`` and outboard ``out`` face): the normal force, the contact coverage
(the share of the face's area whose nodes carry pressure), the largest and
mean pressure and the centre of pressure in (r, theta).
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np

from .caliper.static import solve_caliper
from .checks import check_line_pressure
from .contact.lagrange import solve_contact as solve_active_set
from .contact.pairs import ContactSystem
from .contact.supports import support_forces
from .errors import SceneError
from .fem.boundary import apply_dirichlet
from .fem.stress import element_stress, nodal_stress, von_mises
from .mesh.surface import face_nodes
from .solvers.amg import amg_solver

logger = logging.getLogger(__name__)

__all__ = ["StaticResult", "solve_tied", "solve_contact", "body_stresses", "static_summary",
           "face_report", "friction_faces", "pad_balance", "caliper_balance"]

@dataclass
class StaticResult:
    """Result of a static solve of the brake under a line pressure.

    Parameters
    ----------
    u
        Body -> displacement (3 N_body,) in DOF order ``3 s + i``.
    interface_nodes
        The pad's vertex indices on the friction face.
    interface_force
        (3, n) force the rotor exerts on each of those nodes (N).
    interface_pressure
        (n,) normal pressure at those nodes (Pa).
    clamp_force
        Line pressure times the hydraulic piston area (N).
    info
        The solver's figures.
    active
        Contact status per interface node (contact solves; None when tied).
    normal_z
        z of the rotor face's normal toward each node (+-1), or None.
    support_force
        The pad's DOFs: abutment stops, rails and springs (N), or None.
    """

    u: dict                      # body -> displacement (3 N_body,) in DOF order 3 s + i
    interface_nodes: np.ndarray  # pad vertex indices on the friction face
    interface_force: np.ndarray  # (3, n) force the rotor exerts on each pad friction node (N)
    interface_pressure: np.ndarray  # (n,) normal pressure at those nodes (Pa)
    clamp_force: float           # line pressure x hydraulic piston area (N)
    info: dict = field(default_factory=dict)
    active: np.ndarray | None = None  # contact status per interface node (contact solves)
    normal_z: np.ndarray | None = None  # z of the rotor face's normal toward each node (+-1)
    support_force: np.ndarray | None = None  # pad DOFs: abutment stops + rails and springs (N)

    @property
    def normal_force(self) -> float:
        """Total normal force the rotor exerts on the pads (N), both faces."""
        nz = 1.0 if self.normal_z is None else self.normal_z
        return float((self.interface_force[2] * nz).sum())


def solve_tied(model, line_pressure: float = 1e6, tol: float = 1e-10) -> StaticResult:
    """Static solve of ``model`` with the pad tied to the rotor under ``line_pressure``.

    With a rigid rotor the pad's friction face is held fixed instead.

    Parameters
    ----------
    model : brakewear.model.BrakeModel
        The brake.
    line_pressure : float
        Hydraulic line pressure (Pa).
    tol : float
        Relative residual of the AMG-preconditioned CG solve.

    Returns
    -------
    StaticResult
        Displacements per body and the interface forces (the tie's reactions).
    """
    check_line_pressure(line_pressure)
    t0 = time.perf_counter()
    K, P, retained, col = model.tie_reduction(tie_interface=True)
    f = model.loads(line_pressure)
    pad_nodes = face_nodes(model.meshes["pad"], "friction")
    pad_nodes = pad_nodes[np.abs(model.meshes["pad"].p[2, pad_nodes]) < 1e-12]
    extra = None
    if model.rotor == "rigid":
        extra = (3 * (pad_nodes + model.offsets["pad"])[:, None] + np.arange(3)).ravel()
    fixed_r = model.reduced_fixed_dofs(col, extra)
    Kd, fd = apply_dirichlet((P.T @ K @ P).tobsr(blocksize=(3, 3)), P.T @ f, fixed_r)
    t1 = time.perf_counter()
    solver = amg_solver(Kd, coords=model.coordinates()[:, retained], fixed=fixed_r, tol=tol)
    ur = solver.solve(fd)
    t2 = time.perf_counter()
    u = P @ ur
    # reaction (constraint) forces on the pad's friction nodes = interface forces
    pad_nodes, r, area = model.friction_forces(K @ u - f)
    F = line_pressure * model.geometry.clamp_area
    nz = model.rotor_normal_z(pad_nodes)
    res = StaticResult(
        u=model.by_body(u), interface_nodes=pad_nodes, interface_force=r,
        interface_pressure=nz * r[2] / area, clamp_force=F, normal_z=nz,
        info={"interface": "tied", "rotor": model.rotor, "dofs": int(model.dofs),
              "reduced_dofs": int(Kd.shape[0]),
              "iterations": int(solver.info.iterations),
              "relative_residual": float(solver.info.relative_residual),
              "assemble_s": t1 - t0, "amg_setup_s": solver.setup_s,
              "solve_s": solver.info.solve_s, "total_s": t2 - t0, **model.timings},
    )
    logger.info("tied solve: %d DOFs, %d CG iterations, %.2f s", model.dofs,
                solver.info.iterations, t2 - t0)
    return res


def solve_contact(model, line_pressure: float = 1e6, mu: float = 0.0, method: str = "segment",
                  tol: float = 1e-9, linear: str = "amg",
                  load: np.ndarray | None = None) -> StaticResult:
    """Frictional contact of pad and rotor of ``model`` under ``line_pressure``.

    Sliding friction ``mu p`` drags the pad along the rotor's velocity
    (+theta); equal and opposite on the rotor.  A model whose piston is rigid
    (``BrakeModel(piston="rigid")``) is held by its caliper's rows
    (:func:`brakewear.caliper.static.solve_caliper`).

    Parameters
    ----------
    model : brakewear.model.BrakeModel
        The brake.
    line_pressure : float
        Hydraulic line pressure (Pa).
    mu : float
        Friction coefficient (>= 0).
    method : str
        ``"segment"`` or ``"mortar"``: how pad nodes meet the rotor's facets.
    tol : float
        Relative residual of the linear solves.
    linear : str
        ``"amg"`` (pyamg-preconditioned CG) or ``"direct"``.
    load : numpy.ndarray, optional
        An extra nodal load (N, every DOF; e.g. a thermal strain's).

    Returns
    -------
    StaticResult
        The nodal contact pressure on the pad's friction face (zero where it
        lifts off), the active set, the displacements and the support forces.
    """
    if model.piston == "rigid":
        return StaticResult(**solve_caliper(model, line_pressure, mu, tol=tol, load=load))
    t0 = time.perf_counter()
    cs = model.contact_system(line_pressure, mu, method)
    t1 = time.perf_counter()
    f = cs.f if load is None else cs.f + cs.P.T @ load
    cres = solve_active_set(cs.K, f, cs.fixed, cs.coords, [cs.pair, *cs.supports], tol=tol,
                            linear=linear)
    return _contact_result(model, cs, cres, {"interface": f"contact ({method})", "mu": mu,
                                             "assemble_s": t1 - t0,
                                             "total_s": time.perf_counter() - t0})


def _contact_result(model, cs: ContactSystem, cres, extra: dict) -> StaticResult:
    u = cs.P @ cres.u
    force = cs.pair.normal * cres.force[0] + cres.friction[0]
    info = {"rotor": model.rotor, "dofs": int(model.dofs), **extra,
            **{k: v for k, v in cres.info.items() if k != "active_counts"}, **model.timings}
    logger.info("contact solve: %d DOFs, %d active-set iterations", model.dofs,
                cres.info["active_set_iterations"])
    pad, off = model.meshes["pad"], model.offsets["pad"]
    return StaticResult(u=model.by_body(u), interface_nodes=face_nodes(pad, "friction"),
                        interface_force=force, interface_pressure=cres.pressure[0],
                        clamp_force=cs.clamp_force, info=info, active=cres.active[0],
                        normal_z=np.sign(cs.pair.normal[2]),
                        support_force=support_forces(cs, cres.force[1:], u, pad, off,
                                                     model.geometry.pad, model.geometry.support))


def body_stresses(model, result: StaticResult) -> dict:
    """Nodal von Mises stress per body.

    Parameters
    ----------
    model
        The :class:`~brakewear.model.BrakeModel` solved.
    result
        Its :class:`StaticResult`.

    Returns
    -------
    dict
        Body name -> (nodes,) von Mises stress (Pa).
    """
    out = {}
    for b in model.bodies:
        se = element_stress(model.meshes[b], result.u[b], model.materials[b])
        out[b] = von_mises(nodal_stress(model.meshes[b], se))
    return out


def friction_faces(model, result) -> dict[str, np.ndarray]:
    """Face name -> boolean mask over ``result.interface_nodes`` (``"in"`` and
    ``"out"`` in the full model, ``"in"`` alone in the half model)."""
    nodes = result.interface_nodes
    if not getattr(model, "full", False):
        return {"in": np.ones(nodes.size, dtype=bool)}
    pad = model.meshes["pad"]
    return {side: np.isin(nodes, face_nodes(pad, f"friction_{side}")) for side in ("in", "out")}


def face_report(model, result, mask: np.ndarray, area: np.ndarray) -> dict:
    """Normal force, coverage, pressures and centre of pressure of one face."""
    x = model.meshes["pad"].p[:, result.interface_nodes[mask]]
    p = result.interface_pressure[mask]
    nz = 1.0 if result.normal_z is None else result.normal_z[mask]
    fz = result.interface_force[2][mask] * nz
    a = area[mask]
    r, th = np.hypot(x[0], x[1]), np.arctan2(x[1], x[0])
    F = fz.sum()
    return {
        "normal_force_N": float(F),
        "coverage": float(a[p > 0].sum() / a.sum()),
        "pressure_max_Pa": float(p.max()), "pressure_mean_Pa": float(F / a.sum()),
        "pressure_min_Pa": float(p.min()),
        "centre_of_pressure_r_m": float((fz * r).sum() / F) if F > 0 else float("nan"),
        "centre_of_pressure_theta_deg": (float(np.degrees((fz * th).sum() / F)) if F > 0
                                         else float("nan")),
    }


def static_summary(model, result) -> dict:
    """A JSON-ready summary of a static solve.

    Parameters
    ----------
    model
        The :class:`~brakewear.model.BrakeModel` solved.
    result
        Its :class:`StaticResult`.

    Returns
    -------
    dict
        The interface (all faces together, and per face), the bodies and the
        solver's figures.
    """
    g = model.geometry
    area = model.friction_areas()
    faces = {k: face_report(model, result, m, area) for k, m in
             friction_faces(model, result).items()}
    whole = face_report(model, result, np.ones(area.size, dtype=bool), area)
    n_faces = len(faces)
    whole["force_balance_error"] = abs(whole["normal_force_N"] - n_faces * result.clamp_force) / (
        n_faces * result.clamp_force)
    vm = body_stresses(model, result)
    return {
        "geometry": str(g.source),
        "layout": getattr(model, "layout", "half"),
        "line_pressure_Pa": result.clamp_force / g.clamp_area,
        "clamp_force_N": float(result.clamp_force),
        "interface": whole,
        "faces": faces,
        "bodies": {b: {"nodes": int(model.meshes[b].p.shape[1]),
                       "elements": int(model.meshes[b].nelements),
                       "max_displacement_m": float(np.abs(result.u[b]).max()),
                       "max_von_mises_Pa": float(vm[b].max())} for b in model.bodies},
        "solver": result.info,
    }


def _pad_sides(model) -> dict[str, np.ndarray]:
    """Pad nodes of each side: ``"in"`` and, in the full model, ``"out"``."""
    x = model.meshes["pad"].p
    n = x.shape[1]
    if not model.full:
        return {"in": np.ones(n, dtype=bool)}
    inboard = x[2] > -0.5 * model.geometry.rotor.thickness
    return {"in": inboard, "out": ~inboard}


def _traction_only(model) -> None:
    if model.piston == "body":
        raise SceneError("pad and caliper balances need piston = 'traction' or 'rigid' (a "
                         "meshed piston is tied to the pad)")


def caliper_balance(model, line_pressure: float) -> dict:
    """Force and moment balance of a full model's caliper: what its pistons
    (inboard) and its fingers or outboard pistons (outboard) press onto the pads
    is, by reaction, what the pads press back onto the caliper; the caliper
    slides on its pins, so these forces must cancel (the bridge carries them
    from one side to the other) and only a couple is left, carried by the pins
    to the bracket.  The clamp loads alone decide it (no solve needed).
    Needs ``piston = "traction"``.

    Returns
    -------
    dict
        ``inboard_force_N`` and ``outboard_force_N``: the normal force of each
        side's footprints; ``force``: the norm of the caliper's resultant
        force relative to ``F = line_pressure x clamp_area``;
        ``pin_moment_Nm``: the moment ``[mx, my, mz]`` of the pads' reactions
        on the caliper (the resultant being zero, it is the same about any
        point, so it is the moment about the pins).
    """
    _traction_only(model)
    if not model.full:
        raise SceneError("caliper_balance needs the full model: the half model has one pad")
    pad, off = model.meshes["pad"], model.offsets["pad"]
    n = pad.p.shape[1]
    fa = -model.loads(line_pressure)[3 * off:3 * (off + n)].reshape(-1, 3)
    sides = _pad_sides(model)
    F = line_pressure * model.geometry.clamp_area
    return {"inboard_force_N": float(fa[sides["in"], 2].sum()),
            "outboard_force_N": float(-fa[sides["out"], 2].sum()),
            "force": float(np.linalg.norm(fa.sum(axis=0)) / F),
            "pin_moment_Nm": np.cross(pad.p.T, fa).sum(axis=0).tolist()}


def pad_balance(model, result, line_pressure: float, extra: dict | None = None) -> dict:
    """Force and moment balance of each pad: applied clamp load + contact forces
    (the solve's multipliers and friction) + support reactions (``K u - f`` at the
    supported DOFs; the abutment stops, rails and springs of push and pull
    supports, ``result.support_force``) + ``extra`` forces (name -> pad-DOF vector, e.g. springs or
    abutments), each resultant relative to the clamp force (moments to the clamp
    force times the pad's outer radius).  Needs ``piston = "traction"`` or
    ``"rigid"``.  In the full model also the caliper (:func:`caliper_balance`);
    with the rigid piston every rigid part
    (:func:`brakewear.caliper.static.part_balance`).

    Returns
    -------
    dict
        ``{"in": {"force": rel, "moment": rel}, "out": ..., "caliper":
        {"inboard_force_N": ..., "outboard_force_N": ..., "force": rel,
        "pin_moment_Nm": [mx, my, mz]}}``.
    """
    from .caliper.loads import pad_support_dofs  # caliper_loads sits beside model, above static

    _traction_only(model)
    pad, off = model.meshes["pad"], model.offsets["pad"]
    n = pad.p.shape[1]
    f = model.loads(line_pressure)[3 * off:3 * (off + n)]
    u = result.u["pad"]
    r = model.stiffness("pad") @ u - f
    fixed = pad_support_dofs(model.geometry, pad)
    ext = f.copy()
    ext[fixed] += r[fixed]
    c = np.zeros(3 * n)
    c.reshape(-1, 3)[result.interface_nodes] += result.interface_force.T
    ext += c
    if result.support_force is not None:
        ext += result.support_force
    for v in (extra or {}).values():
        ext += v
    F = line_pressure * model.geometry.clamp_area
    R = model.geometry.pad.outer_radius
    x = pad.p
    out = {}
    for side, mask in _pad_sides(model).items():
        e = ext.reshape(-1, 3)[mask]
        m = np.cross(x[:, mask].T, e).sum(axis=0)
        out[side] = {"force": float(np.linalg.norm(e.sum(axis=0)) / F),
                     "moment": float(np.linalg.norm(m) / (F * R))}
    if model.piston == "rigid":
        from .caliper.static import part_balance  # each piston, the housing, the bracket

        out.update(part_balance(result, line_pressure))
    elif model.full:
        out["caliper"] = caliper_balance(model, line_pressure)
    return out
