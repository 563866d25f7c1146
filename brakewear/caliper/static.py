"""A static solve of the brake held by its caliper's parts, and every body's balance.

:func:`brakewear.static.solve_contact` of a ``BrakeModel(piston="rigid")`` comes here: one
application from
rest on :class:`~brakewear.interfaces.CaliperInterface`, the FE displacement
recovered from the condensed solution (``u = K^+ F + Z alpha``, the
condensation's own generalised inverse), and a
:class:`~brakewear.static.StaticResult` whose ``support_force`` carries every
force on the pads but the rotor's: the caliper's rows (rim, fingers,
abutments, with their friction) and the bracket's rails and clip
(:func:`~brakewear.caliper.rows.bracket_springs`).

:func:`part_balance` sums the forces on every rigid part -- each piston, the
housing, the bracket -- from the rows' forces, the seal's springs (ring point
by ring point) and the hydraulic pressure: a piston is in force and moment
balance to round-off; the housing axially (its pins carry the rest to the
bracket, reported); :func:`abutment_friction_work` is the work the abutments'
friction takes from one application (force times slip from rest).
"""
from __future__ import annotations

import logging
import time

import numpy as np

from ..checks import check_line_pressure
from ..contact.compliant import constraint_rows, drag_loads
from ..mesh.surface import face_nodes
from .parts import bracket_springs, part_loads

logger = logging.getLogger(__name__)

__all__ = ["solve_caliper", "part_balance", "abutment_friction_work"]


def solve_caliper(model, line_pressure: float, mu: float = 0.0, tol: float = 1e-9,
                  load: np.ndarray | None = None, offset: np.ndarray | None = None,
                  interface=None):
    """One application from rest of a ``piston = "rigid"`` model: the fields of its
    :class:`~brakewear.static.StaticResult` (``info["caliper"]`` holds the rows'
    forces, gaps and state, the rigid DOFs and the interface).  ``offset``: a gap
    offset per pad friction node (m); ``interface``: a
    :class:`~brakewear.interfaces.CaliperInterface` of ``model`` to reuse."""
    from .interface import CaliperInterface

    check_line_pressure(line_pressure)
    t0 = time.perf_counter()
    itf = interface if interface is not None else CaliperInterface(model, line_pressure, mu, tol)
    itf = itf.at_line_pressure(line_pressure)
    n = itf.area.size
    sol = itf.solve(np.zeros(n) if offset is None else offset, None, load=load, mu=mu)
    cal = sol.info["caliper"]
    cs = itf.fe.cs
    N = cs.K.shape[0]
    lam = cal["lam"]
    F = (constraint_rows(cs.pair, N).T @ lam + drag_loads(cs.pair, N, mu=mu) @ lam
         + itf.rows.C.T @ cal["force"] + cs.f)
    if load is not None:
        F = F + cs.P.T @ load
    sup = itf.supported()
    u_r = sup.apply(np.where(sup.held, 0.0, F)) + sup.Z @ cal["alpha"]
    u = cs.P @ u_r
    pad, off = model.meshes["pad"], model.offsets["pad"]
    npad = pad.p.shape[1]
    rows_on_pad = (cs.P @ (itf.rows.C.T @ cal["force"]))[3 * off:3 * (off + npad)]
    g = model.geometry
    springs = bracket_springs(pad, off, g.pad, g.support, u.size)
    support = rows_on_pad - (springs @ u)[3 * off:3 * (off + npad)]
    pair = cs.pair
    force = pair.normal * lam + np.asarray(mu) * pair.drag * lam if pair.drag is not None \
        else pair.normal * lam
    info = {"interface": "caliper (condensed)", "mu": mu, "rotor": model.rotor,
            "dofs": int(model.dofs), "total_s": time.perf_counter() - t0,
            **{k: v for k, v in sol.info.items() if k != "caliper"},
            "caliper": {**cal, "interface": itf}}
    return dict(u=model.by_body(u), interface_nodes=face_nodes(pad, "friction"),
                interface_force=force, interface_pressure=sol.pressure,
                clamp_force=line_pressure * g.clamp_area, info=info, active=sol.active,
                normal_z=np.sign(pair.normal[2]), support_force=support)


def part_balance(result, line_pressure: float) -> dict:
    """Force and moment balance of each rigid part of a caliper solve (see the
    module), relative to the clamp force (moments to it times the pad's outer
    radius): ``{"piston in": {"force", "moment"}, "housing": {"axial", "pins_force_N",
    "pins_moment_Nm"}, "bracket": {"force_N", "moment_Nm"}}``."""
    cal = result.info["caliper"]
    itf = cal["interface"]
    rows = itf.rows
    F0 = result.clamp_force
    R = itf.model.geometry.pad.outer_radius
    out = {}
    for part, (F, x) in part_loads(rows, cal["force"], cal["q"], line_pressure).items():
        f, m = F.sum(axis=1), np.cross(x.T, F.T).sum(axis=0)
        if part.startswith("piston"):
            out[part] = {"force": float(np.linalg.norm(f) / F0),
                         "moment": float(np.linalg.norm(m) / (F0 * R))}
        elif part == "housing":
            out[part] = {"axial": float(abs(f[2]) / F0), "pins_force_N": (-f).tolist(),
                         "pins_moment_Nm": (-m).tolist()}
        else:
            out[part] = {"force_N": f.tolist(), "moment_Nm": m.tolist()}
    return out


def abutment_friction_work(result) -> dict:
    """The work (J) the abutments' friction takes from one application from rest,
    per end face: ``sum |lam_k s_k|`` over its friction rows (force times slip)."""
    cal = result.info["caliper"]
    rows = cal["interface"].rows
    out = {}
    for k in np.nonzero(~rows.normal)[0]:
        g = rows.group[k]
        if g.startswith("abutment"):
            key = g.replace(" friction", "")
            out[key] = out.get(key, 0.0) + abs(float(cal["force"][k] * cal["gap"][k]))
    return out
