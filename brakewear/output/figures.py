"""Pictures: pyvista off-screen renderings of meshes and fields (PNG files).

Nothing here is needed to compute; figures only call down into the meshes.
pyvista renders off-screen (``pyvista.OFF_SCREEN = True``) so no display is
needed; while a figure is drawn VTK's own warnings (e.g. "bad X server
connection" on a machine without a display) are kept off the terminal.
"""
from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from contextlib import contextmanager
from os import PathLike
from pathlib import Path

import numpy as np
import skfem as fem

from ..errors import MeshError

logger = logging.getLogger(__name__)

__all__ = [
    "skfem_to_pyvista",
    "facets_to_pyvista",
    "plot_named_surfaces",
    "visible_named_surfaces",
    "plot_field",
    "label_log_axis",
    "offscreen_pyvista",
    "TICK_FORMAT",
]


#: tick labels of colour bars: three significant digits, no trailing dot (VTK's own
#: format, ``%-#6.3g``, writes ``127.``)
TICK_FORMAT = "%.3g"

# VTK cell type of a linear tetrahedron / triangle
_VTK_TETRA = 10


_VTK_TRIANGLE = 5


@contextmanager
def quiet_vtk():
    """VTK's warnings off stderr while drawing (its errors still show); restored after."""
    try:
        from vtkmodules.vtkCommonCore import vtkLogger, vtkObject
    except ImportError:  # pragma: no cover - pyvista without vtkmodules
        yield
        return
    cutoff = vtkLogger.GetCurrentVerbosityCutoff()
    shown = vtkObject.GetGlobalWarningDisplay()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
    vtkObject.GlobalWarningDisplayOff()
    try:
        yield
    finally:
        vtkLogger.SetStderrVerbosity(vtkLogger.ConvertToVerbosity(cutoff))
        vtkObject.SetGlobalWarningDisplay(shown)


def offscreen_pyvista():
    """pyvista, set to render off-screen (imported on first use: an optional cost)."""
    import pyvista as pv

    pv.OFF_SCREEN = True
    return pv


def skfem_to_pyvista(mesh: fem.Mesh, point_data: Mapping[str, np.ndarray] | None = None):
    """A pyvista ``UnstructuredGrid`` of the (P1 vertices of the) tetrahedra of ``mesh``.

    Parameters
    ----------
    mesh : skfem.MeshTet or skfem.MeshTet2
        For ``MeshTet2`` only the vertices and straight-sided cells are used.
    point_data : dict, optional
        Nodal arrays (vertex values first; longer P2 arrays are cut).

    Returns
    -------
    pyvista.UnstructuredGrid
    """
    pv = offscreen_pyvista()
    nv = int(mesh.t.max()) + 1
    t = mesh.t
    cells = np.vstack([np.full(t.shape[1], t.shape[0]), t]).T.ravel()
    grid = pv.UnstructuredGrid(cells, np.full(t.shape[1], _VTK_TETRA, dtype=np.uint8),
                               np.ascontiguousarray(mesh.p[:, :nv].T))
    for k, v in (point_data or {}).items():
        grid.point_data[k] = np.asarray(v)[:nv]
    return grid


def facets_to_pyvista(mesh: fem.Mesh, facets: np.ndarray, shift: Sequence[float] = (0, 0, 0)):
    """A pyvista ``PolyData`` of the triangular facets ``facets`` of ``mesh``."""
    pv = offscreen_pyvista()
    f = mesh.facets[:, np.asarray(facets, dtype=np.int64)]
    used, inv = np.unique(f, return_inverse=True)
    pts = mesh.p[:, used].T + np.asarray(shift, dtype=float)
    faces = np.vstack([np.full(f.shape[1], 3), inv.reshape(f.shape)]).T.ravel()
    return pv.PolyData(np.ascontiguousarray(pts), faces)


def _exclusive_labels(mesh: fem.Mesh) -> dict[str, np.ndarray]:
    """Each boundary facet once, under the smallest named set that holds it
    (so ``piston_face`` shows on top of ``back`` and ``abutment`` on the ends)."""
    sets = {k: np.asarray(v, dtype=np.int64) for k, v in (mesh.boundaries or {}).items()}
    label = {}
    for name in sorted(sets, key=lambda k: -len(sets[k])):
        for f in sets[name]:
            label[f] = name
    out: dict[str, list] = {k: [] for k in sets}
    for f, name in label.items():
        out[name].append(f)
    return {k: np.array(v, dtype=np.int64) for k, v in out.items() if v}


# distinct colours for up to 20 named surfaces (a categorical palette)
_PALETTE = [
    (0.12, 0.47, 0.71), (1.00, 0.50, 0.05), (0.17, 0.63, 0.17), (0.84, 0.15, 0.16),
    (0.58, 0.40, 0.74), (0.55, 0.34, 0.29), (0.09, 0.75, 0.81), (0.50, 0.50, 0.50),
    (0.74, 0.74, 0.13), (0.89, 0.47, 0.76), (0.98, 0.85, 0.20), (0.40, 0.76, 0.65),
    (0.00, 0.20, 0.50), (0.99, 0.55, 0.38), (0.60, 0.00, 0.30), (0.65, 0.85, 0.33),
    (0.20, 0.20, 0.20), (0.70, 0.70, 1.00), (0.50, 0.25, 0.00), (1.00, 0.75, 0.80),
]


_DEFAULT_SHIFT = {"rotor": -0.02, "pad": 0.0, "piston": 0.02}

#: the views of :func:`plot_named_surfaces`: subtitle, hidden body, camera direction,
#: whether the view closes in on the pad
_VIEWS = (
    ("the whole brake, from the piston side", None, (0.35, -1.0, 0.45), False),
    ("pad and piston, from the piston side (rotor hidden)", "rotor", (0.35, -1.0, 0.45), True),
    ("pad, from the rotor side (rotor hidden)", "rotor", (0.55, -1.0, -0.45), True),
)


def _surface_pieces(meshes: Mapping[str, fem.Mesh],
                    explode: Mapping[str, float] | None) -> list[tuple]:
    """(body, name, PolyData) of every named facet set, each facet under one name."""
    explode = dict(_DEFAULT_SHIFT if explode is None else explode)
    pieces = []
    for body, mesh in meshes.items():
        shift = (0.0, 0.0, explode.get(body, 0.0))
        labels = _exclusive_labels(mesh)
        if not labels:
            logger.warning("plot_named_surfaces: mesh %r has no named facets", body)
        for name in sorted(labels):
            pieces.append((body, name, facets_to_pyvista(mesh, labels[name], shift)))
    if not pieces:
        raise MeshError("plot_named_surfaces: none of the meshes has named facets")
    return pieces


def _aim(pl, shown: list, direction, close: bool) -> None:
    """Point the active view's camera along ``direction`` at what it shows (all of it)."""
    b = np.array([pd.bounds for _, _, pd in shown])
    lo, hi = b[:, 0::2].min(axis=0), b[:, 1::2].max(axis=0)
    d = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    focus = 0.5 * (lo + hi)
    pl.camera.focal_point = tuple(focus)
    pl.camera.position = tuple(focus + np.linalg.norm(hi - lo) * d)
    pl.camera.up = (0.0, 0.0, 1.0)
    pl.reset_camera()            # keeps the direction, frames everything shown
    pl.camera.zoom(1.15 if close else 1.05)


def visible_named_surfaces(meshes: Mapping[str, fem.Mesh],
                           explode: Mapping[str, float] | None = None,
                           window_size: tuple[int, int] = (900, 800),
                           min_fraction: float = 1e-3) -> list[tuple[str, str]]:
    """The ``(body, name)`` facet sets that :func:`plot_named_surfaces` shows: those
    that cover at least ``min_fraction`` of a view's pixels in one of its views (each
    set drawn in a colour of its own, unlit, and the pixels of each colour counted;
    a face seen edge-on, a sliver of a few pixels, does not count)."""
    pv = offscreen_pyvista()
    pieces = _surface_pieces(meshes, explode)
    code = [((k + 1) * 7 % 256, (k + 1) * 53 % 256, (k + 1) * 97 % 256)
            for k in range(len(pieces))]
    seen = set()
    for _, hide, direction, close in _VIEWS:
        pl = pv.Plotter(off_screen=True, window_size=list(window_size), lighting="none")
        pl.disable_anti_aliasing()
        shown = [(k, pc) for k, pc in enumerate(pieces) if pc[0] != hide]
        for k, (_, _, pd) in shown:
            pl.add_mesh(pd, color=tuple(c / 255 for c in code[k]), lighting=False)
        _aim(pl, [pc for _, pc in shown], direction, close)
        pl.set_background("white")
        img = pl.screenshot(return_img=True)[..., :3].reshape(-1, 3).astype(int)
        pl.close()
        ids = (img[:, 0] << 16) | (img[:, 1] << 8) | img[:, 2]
        counts = dict(zip(*np.unique(ids, return_counts=True)))
        seen |= {k for k, _ in shown
                 if counts.get((code[k][0] << 16) | (code[k][1] << 8) | code[k][2], 0)
                 >= min_fraction * img.shape[0]}
    return [(pieces[k][0], pieces[k][1]) for k in sorted(seen)]


@quiet_vtk()
def plot_named_surfaces(meshes: Mapping[str, fem.Mesh], path: str | PathLike,
                        title: str | None = None, explode: Mapping[str, float] | None = None,
                        window_size: tuple[int, int] = (2700, 800)) -> Path:
    """Picture the named facet sets of the meshes in their own colours, with a legend.

    Three views of the same exploded assembly: the whole brake from the
    piston side (the rotor's friction face, the pad's back and ends, the
    piston), then, with the rotor hidden, the pad and piston from the piston
    side and the pad from the rotor side (its friction face).  The legend, in
    a panel of its own, lists the sets that show in at least one view
    (:func:`visible_named_surfaces`); sets hidden in every view (the rotor's
    mid-plane, say) are left out of it.

    Parameters
    ----------
    meshes : dict of str to skfem.Mesh
        Body name -> mesh with named boundaries (e.g. :func:`brake_meshes`).
    path
        PNG file to write.
    title : str, optional
        Figure title.
    explode : dict of str to float, optional
        z shift of each body in the picture (m); default rotor -20 mm,
        pad 0, piston +20 mm.
    window_size : (int, int)
        Image size in pixels.

    Returns
    -------
    pathlib.Path
        The PNG written.
    """
    pv = offscreen_pyvista()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    visible = visible_named_surfaces(meshes, explode,
                                     (int(window_size[0] / 3.3), window_size[1]))
    colour = {key: _PALETTE[i % len(_PALETTE)] for i, key in enumerate(visible)}
    pieces = [pc for pc in _surface_pieces(meshes, explode) if (pc[0], pc[1]) in colour]
    pl = pv.Plotter(off_screen=True, shape=(1, 4), col_weights=[1.0, 1.0, 1.0, 0.3],
                    window_size=list(window_size), border=False, lighting="three lights")
    for col, (subtitle, hide, direction, close) in enumerate(_VIEWS):
        pl.subplot(0, col)
        shown = [pc for pc in pieces if pc[0] != hide]
        for body, name, pd in shown:
            pl.add_mesh(pd, color=colour[(body, name)], show_edges=True,
                        edge_color=(0.15, 0.15, 0.15), line_width=0.2)
        _aim(pl, shown, direction, close)
        pl.add_text(subtitle, position="upper_edge", font_size=11, color="black")
    pl.subplot(0, 3)
    if title:
        pl.add_text(title, position="upper_left", font_size=12, color="black")
    pl.add_legend([[f"{body}: {name}", colour[(body, name)]] for body, name in visible],
                  bcolor=(1.0, 1.0, 1.0), border=False, size=(0.95, 0.8),
                  loc="center left", face="rectangle")
    pl.set_background("white")
    pl.screenshot(str(path))
    pl.close()
    logger.info("wrote %s", path)
    return path


@quiet_vtk()
def plot_field(mesh: fem.Mesh, values: np.ndarray, path: str | PathLike, title: str,
               label: str | None = None, cmap: str = "viridis",
               clim: tuple[float, float] | None = None, warp: np.ndarray | None = None,
               warp_scale: float = 1.0, view: Sequence[float] = (1.0, -0.9, 0.9),
               facets: np.ndarray | str | None = None,
               window_size: tuple[int, int] = (1200, 900)) -> Path:
    """Picture a nodal scalar field on the surface of a mesh.

    Parameters
    ----------
    mesh : skfem.Mesh
        Tetrahedral mesh (P2 meshes are drawn with their vertices).
    values : ndarray
        One value per vertex (longer P2 arrays are cut to the vertices).
    path
        PNG file to write.
    title : str
        Figure title.
    label : str, optional
        Colour-bar label (default ``title``).
    cmap : str
        Matplotlib colour map name.
    clim : (float, float), optional
        Colour range; default the range of ``values``.
    warp : ndarray, optional
        Vertex displacements (3, nvertices) (or (3, ndofs) for P2) to draw the
        deformed shape, scaled by ``warp_scale``.
    view : sequence of 3 floats
        Direction from the centre of the mesh to the camera.
    facets : ndarray or str, optional
        Only draw these facets (indices, or the name of a boundary), e.g.
        ``"friction"`` for a contact-pressure map; default the whole surface.
    window_size : (int, int)
        Image size in pixels.

    Returns
    -------
    pathlib.Path
        The PNG written.
    """
    pv = offscreen_pyvista()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    nv = int(mesh.t.max()) + 1
    values = np.asarray(values, dtype=float)
    if values.shape[0] < nv:
        raise MeshError(f"plot_field: values has {values.shape[0]} entries; need one per "
                        f"vertex ({nv})")
    values = values[:nv]
    if isinstance(facets, str):
        if facets not in (mesh.boundaries or {}):
            raise MeshError(f"plot_field: mesh has no boundary {facets!r}; its boundaries: "
                            f"{sorted(mesh.boundaries or {})}")
        facets = mesh.boundaries[facets]
    if facets is None:
        facets = mesh.boundary_facets()
    f = mesh.facets[:, np.asarray(facets, dtype=np.int64)]
    used, inv = np.unique(f, return_inverse=True)
    pts = mesh.p[:, used].T.copy()
    if warp is not None:
        pts += warp_scale * np.asarray(warp)[:, :nv][:, used].T
    faces = np.vstack([np.full(f.shape[1], 3), inv.reshape(f.shape)]).T.ravel()
    surf = pv.PolyData(np.ascontiguousarray(pts), faces)
    label = title if label is None else label
    surf.point_data[label] = values[used]
    pl = pv.Plotter(off_screen=True, window_size=list(window_size), lighting="three lights")
    pl.add_mesh(surf, scalars=label, cmap=cmap, clim=clim, show_edges=False,
                scalar_bar_args={"title": label, "color": "black", "vertical": True,
                                 "fmt": TICK_FORMAT, "position_x": 0.8, "position_y": 0.15,
                                 "height": 0.7})
    pl.add_text(title, position="upper_edge", font_size=12, color="black")
    b = np.array(surf.bounds)
    focus = 0.5 * (b[0::2] + b[1::2])
    d = np.asarray(view, dtype=float)
    d /= np.linalg.norm(d)
    pl.camera.focal_point = tuple(focus)
    pl.camera.position = tuple(
        focus + 2.0 * np.linalg.norm(b[1::2] - b[0::2]) * d
    )  # margin for the title
    pl.camera.up = (0.0, 0.0, 1.0) if abs(d[2]) < 0.99 else (0.0, 1.0, 0.0)
    pl.set_background("white")
    pl.screenshot(str(path))
    pl.close()
    logger.info("wrote %s", path)
    return path


def label_log_axis(axis, ticks) -> None:
    """Put plain-number labels at ``ticks`` on a logarithmic matplotlib axis
    (``ax.xaxis``), without the minor labels that collide at small ranges."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    axis.set_major_locator(FixedLocator(list(ticks)))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.3g}"))
    axis.set_minor_formatter(NullFormatter())
