"""What a static solve of the brake reports: stresses, contact coverage, centres of pressure.

Per friction face (the half model has one, the full model the inboard
``in`` and outboard ``out`` face): the normal force, the contact coverage
(the share of the face's area whose nodes carry pressure), the largest and
mean pressure and the centre of pressure in (r, theta).
"""
from __future__ import annotations

import logging

import numpy as np

from .fem.stress import element_stress, nodal_stress, von_mises
from .mesh.surface import face_nodes

logger = logging.getLogger(__name__)

__all__ = ["body_stresses", "static_summary", "face_report", "friction_faces"]


def body_stresses(model, result) -> dict:
    """Nodal von Mises stress per body (Pa)."""
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
    """A JSON-ready summary of a static solve: interface (all faces together,
    and per face), bodies, solver."""
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
