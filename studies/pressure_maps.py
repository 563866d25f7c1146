"""Grids of contact-pressure maps of friction faces, one row per face and one column per
line pressure (``studies/load_path.py``), drawn off screen with pyvista."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from brakewear.output.figures import offscreen_pyvista


def draw_maps(runs: dict, faces, mu: float, pressures, path: Path) -> Path:
    """Pressure over nominal on every face (rows) at every pressure (columns).

    ``runs``: case -> ``{"geometry": ..., "maps": {(mu, MPa): {face: {"facets", "p",
    "xy"}}}}``; ``faces``: (case, face, label) of every row."""
    pv = offscreen_pyvista()
    pl = pv.Plotter(off_screen=True, shape=(len(faces), len(pressures)),
                    window_size=[320 * len(pressures), 300 * len(faces)], border=False)
    for i, (case, face, label) in enumerate(faces):
        geom = runs[case]["geometry"]
        nominal = geom.clamp_area / geom.pad.area
        for j, p_mpa in enumerate(pressures):
            m = runs[case]["maps"][(mu, p_mpa)][face]
            f = m["facets"]
            used, inv = np.unique(f, return_inverse=True)
            pts = np.vstack([m["xy"][:, used], np.zeros(used.size)]).T
            surf = pv.PolyData(np.ascontiguousarray(pts),
                               np.vstack([np.full(f.shape[1], 3), inv.reshape(f.shape)]).T.ravel())
            surf.point_data["p / p_nominal"] = m["p"][used] / (p_mpa * 1e6 * nominal)
            pl.subplot(i, j)
            pl.add_mesh(surf, scalars="p / p_nominal", cmap="inferno", clim=(0.0, 3.0),
                        show_scalar_bar=(i == len(faces) - 1 and j == len(pressures) - 1),
                        scalar_bar_args={"title": "p / p_nominal", "color": "black",
                                         "vertical": True, "position_x": 0.8,
                                         "position_y": 0.1, "height": 0.8, "width": 0.08,
                                         "n_labels": 4, "fmt": "%.0f",
                                         "title_font_size": 12, "label_font_size": 11})
            pl.add_text(f"{label}\n{p_mpa:g} MPa", font_size=7, color="black")
            pl.view_xy()
            pl.set_background("white")
    path.parent.mkdir(parents=True, exist_ok=True)
    pl.screenshot(str(path))
    pl.close()
    return path
