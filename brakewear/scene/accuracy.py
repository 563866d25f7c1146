"""How far a scene's mesh puts its pad wear from the mesh-converged answer.

The rating rests on the measured mesh convergence of the running-in
(docs/performance.md, "Mesh convergence of the running-in", and its P2
section): the default brake under the default drag (1 MPa, 55 rad/s,
mu 0.4, the materials' Archard laws, elastic rotor), 48 equal implicit steps,
each mesh's pad wear compared, as a relative L2 distance over the pad face,
with the Richardson estimate of the mesh-converged pad wear, after 20 minutes
and after the hour.  The figures are :data:`P1_MEASURED` and
:data:`P2_MEASURED` (tests/test_accuracy.py checks them against
docs/data/mesh_convergence.json and mesh_convergence_p2.json).  They are
the meshes' errors alone: a run's own steps add theirs (the default scene's
60 equal steps 0.25 %, docs/wear.md), which the rating does not include.

:func:`mesh_accuracy` rates a scene's mesh:

* a mesh that *was measured* (the default brake, the same order, pad size and
  layers, and the same rotor mesh when the rotor is elastic) gets its
  measured error, banded by the estimate's own uncertainty (how far the
  converged estimate moves at convergence rate 1: 0.89 points after the
  hour, 1.22 after 20 minutes);
* any other mesh gets a fit to the measured meshes of its order: P1
  ``log e = c0 + c1 log(h / w) + c2 log(n_b)`` (``h`` the pad's in-plane
  element size, ``w`` the lining's radial width, ``n_b`` the element layers
  through the backplate, whose bending P1 elements lock in when they are
  few), P2 ``log e = c0 + c1 log(h / w)``; its band is the fit's largest
  residual on the measured meshes (a factor) widened by the estimate's own
  uncertainty.

What the rating does not cover is said in its ``caveats``: another brake
(the same dimensionless mesh on another geometry is assumed to be as far
off: an extrapolation), a mesh outside the measured range, runs shorter
than the hour (rated by the 20-minute figures, which are larger; shorter
than 20 minutes was not measured), schedules, thermal coupling, the full
model and a rigid rotor (measured on the half model with an elastic
rotor).  An interface model that does not give the FE contact's answer (the
Winkler foundation; its registry entry's ``fe_answer``) and the user's own
mesh files are not rated.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

__all__ = ["TARGET", "P1_MEASURED", "P2_MEASURED", "mesh_accuracy", "accuracy_lines"]

#: the error the default scene's mesh is chosen for (pad wear, relative L2): a mesh
#: whose estimate exceeds it gets a warning
TARGET = 0.02

#: the measured P1 meshes of the default brake: pad size (mm), friction, backplate
#: layers, rotor size (mm), rotor layers, error of the pad wear (relative L2 from the
#: converged estimate) after 3600 s and after 1200 s
P1_MEASURED = (
    (9.0, 2, 2, 9.0, 2, 0.1473, 0.2538),
    (6.0, 3, 3, 6.0, 3, 0.1049, 0.1654),
    (4.5, 4, 4, 4.5, 4, 0.0804, 0.1191),
    (3.0, 6, 6, 3.0, 6, 0.0461, 0.0636),
    (2.0, 9, 9, 2.0, 9, 0.0234, 0.0302),
    (1.5, 12, 12, 1.5, 12, 0.0141, 0.0175),
    (1.125, 16, 16, 1.125, 16, 0.0084, 0.0101),
    (6.0, 3, 1, 6.0, 2, 0.1486, 0.2551),
    (3.0, 4, 4, 4.5, 3, 0.0535, 0.0752),
    (2.0, 6, 6, 4.5, 3, 0.0279, 0.0365),
    (1.5, 6, 6, 4.5, 3, 0.0206, 0.0266),
    (1.5, 8, 8, 4.5, 3, 0.0169, 0.0214),
    (1.5, 4, 8, 4.5, 3, 0.0190, 0.0239),
    (1.0, 6, 6, 4.5, 3, 0.0155, 0.0196),
)
#: the measured P2 meshes (same columns; after the hour only, against the P1 estimate)
P2_MEASURED = (
    (18.0, 1, 1, 18.0, 1, 0.0205, None),
    (12.0, 2, 2, 12.0, 2, 0.0266, None),
    (9.0, 2, 2, 9.0, 2, 0.0199, None),
    (6.0, 3, 3, 6.0, 3, 0.0098, None),
    (4.5, 4, 4, 4.5, 4, 0.0051, None),
)
#: how far the converged estimate moves at convergence rate 1 (after 3600 s, 1200 s)
ESTIMATE_SHIFT = {3600.0: 0.0089, 1200.0: 0.0122}
#: the radial width of the default brake's lining (m), the measured meshes' scale
_WIDTH = 0.043
_SOURCE = 'docs/performance.md, "Mesh convergence of the running-in"'


def _fit(rows: tuple, col: int, order: int) -> tuple[np.ndarray, float]:
    """Least-squares coefficients of ``log e`` and the largest |log residual|."""
    rows = [r for r in rows if r[col] is not None]
    h = np.log(np.array([r[0] * 1e-3 / _WIDTH for r in rows]))
    cols = [np.ones_like(h), h] + ([np.log([float(r[2]) for r in rows])] if order == 1 else [])
    a = np.column_stack(cols)
    y = np.log([r[col] for r in rows])
    c, *_ = np.linalg.lstsq(a, y, rcond=None)
    return c, float(np.abs(a @ c - y).max())


def _same_brake(geom) -> bool:
    from ..geometry.files import load_geometry

    ref = load_geometry("default")
    return replace(geom, mesh=ref.mesh) == ref


def _mesh_of(scene) -> dict:
    from ..mesh.estimate import mesh_layers

    geom = scene.meshed_geometry
    lay = mesh_layers(geom, scene.mesh_size)
    order = scene.order or geom.mesh.order
    return {"order": int(order), **lay,
            "lining_width_m": geom.pad.outer_radius - geom.pad.inner_radius}


def _measured(mesh: dict, rows: tuple, elastic: bool) -> tuple | None:
    for r in rows:
        pad = (math.isclose(r[0] * 1e-3, mesh["pad_size"], rel_tol=1e-6)
               and (r[1], r[2]) == (mesh["friction_layers"], mesh["backplate_layers"]))
        rot = (math.isclose(r[3] * 1e-3, mesh["rotor_size"], rel_tol=1e-6)
               and r[4] == mesh["rotor_layers"])
        if pad and (rot or not elastic):
            return r
    return None


def _caveats(scene, mesh: dict, rows: tuple, when: float, same: bool) -> list[str]:
    out = []
    if not same:
        out.append("another brake than the measured one (the default brake): the same "
                   "element size relative to the lining's radial width and the same "
                   "backplate layers are assumed to be as far off (an extrapolation)")
    x = mesh["pad_size"] / mesh["lining_width_m"]
    xs = [r[0] * 1e-3 / _WIDTH for r in rows]
    if not min(xs) * (1 - 1e-9) <= x <= max(xs) * (1 + 1e-9) or (
            mesh["order"] == 1 and not min(r[2] for r in rows) <= mesh["backplate_layers"]
            <= max(r[2] for r in rows)):
        out.append("a mesh outside the measured range (an extrapolation of the fit)")
    if scene.schedule:
        out.append("measured on a steady drag, not on a schedule of stops: rated by the "
                   "20-minute figures")
    elif scene.duration < 3600.0 and when == 1200.0:
        out.append("a run shorter than the hour: rated by the 20-minute figures"
                   + ("; shorter than 20 minutes was not measured (the error of a new "
                      "pad's wear is larger still)" if scene.duration < 1200.0 else ""))
    elif scene.duration < 3600.0:
        out.append("a run shorter than the hour: P2 was measured after the hour only")
    if scene.thermal.enabled:
        out.append("measured without thermal coupling: the temperature field's own mesh "
                   "error is not rated")
    from ..caliper.loads import resolve_layout
    if resolve_layout(scene.geometry, scene.layout, scene.rotor) == "full":
        out.append("measured on the half model (one pad); here both pads, each rated alike")
    if scene.rotor == "rigid":
        out.append("measured with an elastic rotor (a rigid one changes the pad wear by "
                   "about 0.2 %)")
    return out


def _rate(mesh: dict, rows: tuple, when: float, hit: tuple | None) -> tuple:
    """(estimate, low, high, basis) of the pad wear's error after ``when`` seconds."""
    col, shift = (5 if when == 3600.0 else 6), ESTIMATE_SHIFT[when]
    if hit is not None:
        return hit[col], hit[col] - shift, hit[col] + shift, "measured"
    c, resid = _fit(rows, col, mesh["order"])
    x = [1.0, math.log(mesh["pad_size"] / mesh["lining_width_m"])]
    x += [math.log(mesh["backplate_layers"])] if mesh["order"] == 1 else []
    est = float(math.exp(np.dot(c, x)))
    # a measured mesh at least as fine in every respect bounds the error from below, one
    # at least as coarse from above (the errors fall monotonically in the measurements)
    finer, coarser = _bounds(mesh, rows, col)
    est = min(max(est, finer), coarser)
    return (est, max(est * math.exp(-resid), finer) - shift,
            min(est * math.exp(resid), coarser) + shift, "fit")


def _bounds(mesh: dict, rows: tuple, col: int) -> tuple[float, float]:
    """The largest error of the measured meshes at least as fine as ``mesh`` (in-plane
    size relative to the lining width, friction and backplate layers) and the
    smallest of those at least as coarse (0 and inf where there are none)."""
    x = mesh["pad_size"] / mesh["lining_width_m"]
    nf, nb = mesh["friction_layers"], mesh["backplate_layers"]
    lo, hi = 0.0, math.inf
    for r in rows:
        xr = r[0] * 1e-3 / _WIDTH
        if xr <= x * (1 + 1e-9) and r[1] >= nf and r[2] >= nb:
            lo = max(lo, r[col])
        if xr >= x * (1 - 1e-9) and r[1] <= nf and r[2] <= nb:
            hi = min(hi, r[col])
    return lo, hi


def mesh_accuracy(scene) -> dict:
    """The estimated error of a scene's pad wear from the mesh-converged answer.

    Parameters
    ----------
    scene : brakewear.scene.Scene
        A checked scene (nothing is meshed).

    Returns
    -------
    dict
        ``rated`` (False: no estimate, ``why`` says why); ``estimate`` and
        ``band`` (relative L2 of the pad wear over the pad face); ``basis``
        (``"measured"`` or ``"fit"``); ``after_s`` (the measured time the
        figures are of: 1200 s for runs shorter than the hour); ``target``
        and ``within_target`` (the mesh's error after the hour at most
        :data:`TARGET`: as fine as the default scene's); ``mesh`` (the
        resolved sizes and layers); ``caveats``; ``quantity``; ``source``.
    """
    base = {"quantity": "pad wear, relative L2 over the pad face, from the mesh-converged "
                        "answer", "source": _SOURCE, "target": TARGET}
    if scene.mesh_files:
        return {**base, "rated": False, "why": "the scene's own mesh files: the measured "
                "convergence is of the parametric meshes"}
    entry = scene.interface.entry
    if not getattr(entry, "fe_answer", False):
        return {**base, "rated": False, "why": (getattr(entry, "why_not", None) or {}).get(
            "fe_answer", f"interface.model = {entry.name!r} does not give the FE contact's "
                         "answer: the measured convergence is of FE contact")}
    mesh = _mesh_of(scene)
    rows = P1_MEASURED if mesh["order"] == 1 else P2_MEASURED
    short = bool(scene.schedule) or scene.duration < 3600.0
    when = 1200.0 if short and mesh["order"] == 1 else 3600.0
    same = _same_brake(scene.geometry)
    hit = _measured(mesh, rows, scene.rotor == "elastic") if same else None
    est, lo, hi, basis = _rate(mesh, rows, when, hit)
    hour = est if when == 3600.0 else _rate(mesh, rows, 3600.0, hit)[0]
    return {**base, "rated": True, "estimate": float(est),
            "band": [max(0.0, float(lo)), float(hi)], "basis": basis, "after_s": when,
            "estimate_after_hour": float(hour), "within_target": bool(hour <= TARGET),
            "mesh": mesh, "caveats": _caveats(scene, mesh, rows, when, same)}


def _mm(x: float) -> str:
    return f"{x * 1e3:.4g} mm"


def _pct(x: float) -> str:
    return f"{100 * x:.1f} %" if x < 0.1 else f"{100 * x:.0f} %"


def accuracy_lines(acc: dict) -> list[str]:
    """What a run prints first about its accuracy (a warning line when the mesh is
    coarser than the :data:`TARGET` mesh)."""
    if not acc["rated"]:
        return [f"accuracy: not rated ({acc['why']})"]
    m = acc["mesh"]
    lo, hi = acc["band"]
    basis = ("measured for this mesh" if acc["basis"] == "measured" else
             "fitted to the measured meshes")
    lines = [f"mesh: P{m['order']}, pad {_mm(m['pad_size'])} with {m['friction_layers']} + "
             f"{m['backplate_layers']} layers (friction layer + backplate), rotor "
             f"{_mm(m['rotor_size'])} with {m['rotor_layers']} layers",
             f"accuracy: pad wear about {_pct(acc['estimate'])} from the mesh-converged "
             f"answer (band {_pct(lo)} to {_pct(hi)}), {basis} on the default brake after "
             f"{acc['after_s'] / 60:.0f} min of drag ({acc['source']})"]
    lines += [f"  not covered: {c}" for c in acc["caveats"]]
    if not acc["within_target"]:
        lines.append(f"warning: this mesh is coarser than the {100 * acc['target']:g} % mesh (the "
                     "default scene's: pad 1.5 mm with 4 + 8 layers, rotor 4.5 mm with 3; "
                     f"about {_pct(acc['estimate_after_hour'])} here after the hour); refine "
                     "mesh.size (or mesh.pad_size) and mesh.backplate_layers for answers "
                     "within about 2 %")
    return lines
