"""Maps of a friction face that a brake engineer reads without the docs.

:func:`plot_face_map` draws a nodal field on a friction face (the pad's, or
the rotor ring's) flat, seen from the other body, in parallel projection,
with the pad's outer radius up, and marks what orients it: the pad's
leading and trailing edges (the rotor turns in +theta, so a rotor point
meets the leading edge first), its inner and outer edge with their radii,
the direction the rotor moves under the pad, and a length scale.  On the
rotor's face the pad's outline is drawn where the pad sits.  The colour bar
carries the unit (``µm``, ``MPa``, ``°C``) and plain tick labels.
"""
from __future__ import annotations

import logging
import math
import re
from collections.abc import Sequence
from os import PathLike
from pathlib import Path

import numpy as np
import skfem as fem

from ..errors import MeshError
from .figures import TICK_FORMAT, offscreen_pyvista, quiet_vtk

logger = logging.getLogger(__name__)

__all__ = ["plot_face_map", "run_maps", "scale_length"]

_INK = (0.1, 0.1, 0.1)
_ARROW = (0.75, 0.1, 0.1)


def scale_length(width: float) -> float:
    """A round length (m) of at most 30 % of ``width`` (m) for a scale bar: 1, 2 or 5
    times a power of ten."""
    target = 0.3 * width
    base = 10.0 ** math.floor(math.log10(target))
    return max(m * base for m in (1.0, 2.0, 5.0) if m * base <= target * (1 + 1e-12))


def _polar(r, theta, z):
    return np.array([r * math.cos(theta), r * math.sin(theta), z])


def _arc(r: float, t0: float, t1: float, z: float, n: int = 40) -> np.ndarray:
    return np.array([_polar(r, t, z) for t in np.linspace(t0, t1, n)])


def _annotate(pl, pv, pad, z: float, front: float, right: np.ndarray, width: float,
              ring: tuple[float, float] | None) -> None:
    """Edges, radii, rotation and scale on the plotter ``pl`` (``z + front``: just in
    front of the face; ``right``: the screen's right in the world); ``ring``: the
    rotor's radii when the face is the rotor's."""
    z = z + front
    ri, ro = pad.inner_radius, pad.outer_radius
    tc, half = pad.center_angle, 0.5 * pad.arc_angle
    lead, trail = tc - half, tc + half
    rm, gap = 0.5 * (ri + ro), 0.06 * (ro - ri) + 0.002
    labels: dict[str, list] = {"left": [], "center": [], "right": []}
    # the ends' labels stand clear of the ends (on the rotor: beyond the ring, with a
    # leader to the pad's outline), on whichever side of the screen they are
    for name, theta, sign in (("leading", lead, -1.0), ("trailing", trail, 1.0)):
        out = sign * np.array([-math.sin(theta), math.cos(theta), 0.0])
        side = "left" if float(out @ right) > 0 else "right"   # the text's anchor
        if ring is None:
            labels[side].append((_polar(rm, theta, z) + gap * out, f"{name}\nedge"))
        else:
            far = ring[1] + 2.5 * gap
            pl.add_mesh(pv.Line(_polar(ro, theta, z), _polar(far, theta, z)), color=_INK,
                        line_width=2)
            labels[side].append((_polar(far, theta, z) + 0.5 * gap * out,
                                 f"pad {name}\nedge"))
    if ring is None:
        labels["center"] += [(_polar(ro + 0.9 * gap, tc, z), f"outer edge, r = {ro * 1e3:.4g} mm"),
                             (_polar(ri - 0.9 * gap, tc, z), f"inner edge, r = {ri * 1e3:.4g} mm")]
    else:                             # the pad's outline on the rotor's face
        outline = np.vstack([_arc(ri, lead, trail, z), _arc(ro, trail, lead, z),
                             _polar(ri, lead, z)[None]])
        # white under black: the outline shows on dark and light colours alike
        pl.add_mesh(pv.lines_from_points(outline), color="white", line_width=7)
        pl.add_mesh(pv.lines_from_points(outline + (0.0, 0.0, 0.5 * front)), color=_INK,
                    line_width=3)
    top = ro + 1.8 * gap if ring is None else ring[1] + gap
    bottom = ri * math.cos(half) if ring is None else -ring[1]
    # the rotor's motion under the pad: an arc with its head toward the trailing edge
    span = 0.3 * pad.arc_angle if ring is None else 0.5 * pad.arc_angle
    arc = _arc(top, tc - span, tc + span, z)
    pl.add_mesh(pv.lines_from_points(arc), color=_ARROW, line_width=5)
    pl.add_mesh(pv.Cone(center=arc[-1], direction=arc[-1] - arc[-2], height=1.4 * gap,
                        radius=0.55 * gap, resolution=24), color=_ARROW)
    labels["center"].append((_polar(top + 1.3 * gap, tc, z), "rotor turns this way"))
    # a length scale below the face, centred on the pad's centre line
    L = scale_length(width)
    e_t = np.array([-math.sin(tc), math.cos(tc), 0.0])
    c = _polar(bottom - 1.8 * gap, tc, z)
    pl.add_mesh(pv.Line(c - 0.5 * L * e_t, c + 0.5 * L * e_t), color=_INK, line_width=6)
    labels["center"].append((_polar(bottom - 3.0 * gap, tc, z), f"{L * 1e3:g} mm"))
    for just, items in labels.items():
        if items:
            pl.add_point_labels(np.array([p for p, _ in items]), [s for _, s in items],
                                font_size=16, text_color="black", show_points=False,
                                shape=None, always_visible=True,
                                justification_horizontal=just,
                                justification_vertical="center")


@quiet_vtk()
def plot_face_map(mesh: fem.Mesh, values: np.ndarray, path: str | PathLike, title: str,
                  label: str, pad, *, facets: str = "friction",
                  view: Sequence[float] = (0.0, 0.0, -1.0), cmap: str = "viridis",
                  clim: tuple[float, float] | None = None, rotor_face: bool = False,
                  window_size: tuple[int, int] | None = None) -> Path:
    """Picture a nodal field on a friction face, oriented and to scale.

    Parameters
    ----------
    mesh, values, path, title
        The pad's or the rotor's mesh, one value per vertex, the PNG file and the
        title, as for :func:`brakewear.output.figures.plot_field`.
    label : str
        Colour-bar title with its unit, e.g. ``"pad wear (µm)"``.
    pad : brakewear.geometry.PadGeometry
        The pad whose edges are marked (``geometry.pad``, m and rad).
    facets : str
        The mesh's named face to draw (``"friction"``, ``"friction_in"``, ...).
    view : sequence of 3 floats
        Direction from the face to the camera: the face is seen from the other
        body (``(0, 0, -1)`` for a pad face at z = 0 seen from the rotor).
    cmap, clim
        Colour map and range (default the range of ``values``).
    rotor_face : bool
        The face is the rotor's: the pad's outline is drawn on it.
    window_size : (int, int), optional
        Image size in pixels; default 1400 x 780 for a pad face, 1300 x 1000 for
        the rotor's (the face fills it).

    Returns
    -------
    pathlib.Path
        The PNG written.
    """
    pv = offscreen_pyvista()
    if window_size is None:
        window_size = (1300, 1000) if rotor_face else (1400, 780)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if facets not in (mesh.boundaries or {}):
        raise MeshError(f"plot_face_map: mesh has no boundary {facets!r}; its boundaries: "
                         f"{sorted(mesh.boundaries or {})}")
    nv = int(mesh.t.max()) + 1
    values = np.asarray(values, dtype=float)
    if values.shape[0] < nv:
        raise MeshError(f"plot_face_map: values has {values.shape[0]} entries; need one "
                         f"per vertex ({nv})")
    f = mesh.facets[:, np.asarray(mesh.boundaries[facets], dtype=np.int64)]
    used, inv = np.unique(f, return_inverse=True)
    faces = np.vstack([np.full(f.shape[1], 3), inv.reshape(f.shape)]).T.ravel()
    surf = pv.PolyData(np.ascontiguousarray(mesh.p[:, used].T), faces)
    surf.point_data[label] = values[:nv][used]
    d = np.asarray(view, dtype=float) / np.linalg.norm(view)
    r = np.hypot(*mesh.p[:2, used])
    ring = (float(r.min()), float(r.max())) if rotor_face else None
    pl = pv.Plotter(off_screen=True, window_size=list(window_size), lighting=None)
    pl.add_mesh(surf, scalars=label, cmap=cmap, clim=clim, show_edges=False,
                scalar_bar_args={"title": label, "color": "black", "vertical": True,
                                 "fmt": TICK_FORMAT, "title_font_size": 18,
                                 "label_font_size": 16, "position_x": 0.86,
                                 "position_y": 0.2, "height": 0.6})
    z_face = float(mesh.p[2, used].mean())
    tc = pad.center_angle
    e_r = np.array([math.cos(tc), math.sin(tc), 0.0])
    right = np.cross(-d, e_r)                # the camera looks along -d with e_r up
    width = 2.0 * ring[1] if ring else pad.outer_radius - pad.inner_radius
    _annotate(pl, pv, pad, z_face, 1e-3 * np.sign(d[2] or 1.0), right, width, ring)
    pl.add_text(title, position="upper_edge", font_size=12, color="black")
    pl.add_text(f"{'rotor' if ring else 'pad'} friction face, seen from the "
                f"{'pad' if ring else 'rotor'}", position="lower_left", font_size=10,
                color="black")
    _frame(pl, pad, d, z_face, ring)
    pl.set_background("white")
    pl.screenshot(str(path))
    pl.close()
    logger.info("wrote %s", path)
    return path


def _frame(pl, pad, d: np.ndarray, z: float, ring) -> None:
    """Parallel projection along ``d`` with the pad's centre line up, the face and its
    marks in the frame."""
    tc, half = pad.center_angle, 0.5 * pad.arc_angle
    e_r = np.array([math.cos(tc), math.sin(tc), 0.0])
    gap = 0.06 * (pad.outer_radius - pad.inner_radius) + 0.002
    if ring is None:
        lo = pad.inner_radius * math.cos(half) - 3.6 * gap
        hi = pad.outer_radius + 3.8 * gap
        half_w = pad.outer_radius * math.sin(half) + 5.0 * gap
    else:
        lo, hi, half_w = -ring[1] - 3.6 * gap, ring[1] + 4.0 * gap, ring[1] + 6.0 * gap
    centre = 0.5 * (lo + hi) * e_r + np.array([0.0, 0.0, z])
    pl.enable_parallel_projection()
    cam = pl.camera
    cam.focal_point = tuple(centre)
    cam.position = tuple(centre + 1.0 * d)
    cam.up = tuple(e_r)
    aspect = pl.window_size[0] / pl.window_size[1]
    # the title takes the top 8 % of the window, the colour bar the right 16 %
    cam.parallel_scale = max(0.5 * (hi - lo) / 0.92, half_w / (0.84 * aspect))
    cam.clipping_range = (0.5, 1.5)


#: the maps of a run's last step: VTU field, PNG name, scale, colour-bar title, colours
_MAPS = (("pad_wear", "pad_wear", 1e6, "pad wear (µm)", "viridis"),
         ("pressure", "pad_pressure", 1e-6, "contact pressure (MPa)", "inferno"),
         ("temperature_C", "pad_temperature", 1.0, "temperature (°C)", "inferno"))


def run_maps(model, out: str | PathLike, name: str) -> list[str]:
    """The maps of a run in ``out`` at its last written step: pad wear, pressure and
    (thermal runs) temperature on each pad friction face (``pad_wear.png``,
    ``pad_pressure.png``, ``pad_temperature.png``; the full model ``_in`` and
    ``_out`` of each), and the temperature of the rotor's friction faces
    (``rotor_temperature.png``); ``name`` starts each title.  Returns the paths."""
    import meshio

    out = Path(out)
    files, pad, pad_geom = [], model.meshes["pad"], model.geometry.pad
    full = "friction_out" in (pad.boundaries or {})
    # the full model's two friction faces, each seen from the rotor (pad) side
    faces = ((("friction_in", "_in", "inboard ", -1.0), ("friction_out", "_out", "outboard ",
                                                          1.0)) if full else
             (("friction", "", "", -1.0),))
    last = sorted(out.glob("pad_*.vtu"))
    if not ((out / "pad.pvd").exists() and last):
        return files
    m = meshio.read(last[-1])
    t = _last_time(out / "pad.pvd")
    for fld, png, scale, label, cmap in _MAPS:
        if fld not in m.point_data:
            continue
        what = {"pad_wear": f"pad wear after {t:g} s", "pressure": "contact pressure of the "
                f"last step (t = {t:g} s)", "temperature_C": f"pad temperature at {t:g} s"}
        for facets, suffix, which, side in faces:
            files.append(str(plot_face_map(
                pad, m.point_data[fld] * scale, out / f"{png}{suffix}.png",
                f"{name}: {which}{what[fld]}", label, pad_geom, facets=facets,
                view=(0.0, 0.0, side), cmap=cmap)))
    rotor = model.meshes.get("rotor")
    last = sorted(out.glob("rotor_*.vtu"))
    if rotor is not None and last:
        m = meshio.read(last[-1])
        if "temperature_C" in m.point_data:
            for facets, suffix, which, side in faces:
                files.append(str(plot_face_map(
                    rotor, m.point_data["temperature_C"], out / f"rotor_temperature{suffix}.png",
                    f"{name}: {which}rotor face temperature at {t:g} s",
                    "temperature (°C)", pad_geom, facets=facets, view=(0.0, 0.0, -side),
                    cmap="inferno", rotor_face=True)))
    return files


def _last_time(pvd: Path) -> float:
    """The time of the last frame of a ParaView series."""
    times = re.findall(r'timestep="([^"]+)"', pvd.read_text())
    return float(times[-1]) if times else float("nan")
