"""Off-screen pictures: files exist, are PNGs and are not blank."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pyvista")
import matplotlib.image as mpimg

from brakewear.geometry import load_geometry
from brakewear.mesh import brake_meshes
from brakewear.output.figures import plot_field, plot_named_surfaces, skfem_to_pyvista


@pytest.fixture(scope="module")
def coarse():
    return brake_meshes(load_geometry(), size=6e-3)


def check_png(path, min_colours):
    assert path.exists(), f"{path} not written"
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    assert path.stat().st_size > 20_000, f"{path} is only {path.stat().st_size} bytes"
    img = mpimg.imread(path)[..., :3]
    assert img.shape[0] >= 400 and img.shape[1] >= 400, f"image shape {img.shape}"
    var = img.reshape(-1, 3).var(axis=0).sum()
    assert var > 0.01, f"pixel variance {var:.4f}: blank image?"
    nonwhite = (img.min(axis=2) < 0.95).mean()
    assert 0.05 < nonwhite < 0.95, f"{nonwhite:.2%} of the pixels are not white"
    colours = np.unique((img.reshape(-1, 3) * 15).round().astype(int), axis=0).shape[0]
    assert colours >= min_colours, f"only {colours} distinct (quantised) colours"


def test_named_surfaces_png(tmp_path, coarse):
    path = plot_named_surfaces(coarse, tmp_path / "surfaces.png", title="test brake")
    n_sets = sum(len(m.boundaries) for m in coarse.values())
    check_png(path, min_colours=n_sets)


def test_field_png(tmp_path, coarse):
    pad = coarse["pad"]
    r = np.hypot(pad.p[0], pad.p[1])
    path = plot_field(pad, r, tmp_path / "field.png", title="radius (m)",
                      facets="friction", view=(0.0, 0.0, -1.0))
    check_png(path, min_colours=20)
    path = plot_field(pad, pad.p[2], tmp_path / "warped.png", title="z (m)",
                      warp=np.zeros((3, pad.p.shape[1])))
    check_png(path, min_colours=20)
    with pytest.raises(ValueError, match="no boundary 'nope'"):
        plot_field(pad, r, tmp_path / "x.png", title="x", facets="nope")
    with pytest.raises(ValueError, match="one per vertex"):
        plot_field(pad, r[:10], tmp_path / "x.png", title="x")


def test_skfem_to_pyvista(coarse):
    m = coarse["piston"]
    grid = skfem_to_pyvista(m, point_data={"z": m.p[2]})
    assert grid.n_cells == m.t.shape[1] and grid.n_points == m.p.shape[1]
    x = m.p[:, m.t]
    vol = np.abs(np.einsum("ij,ij->j", x[:, 1] - x[:, 0],
                           np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0], axis=0))).sum() / 6
    assert grid.volume == pytest.approx(vol, rel=1e-9), f"pyvista volume {grid.volume} vs {vol}"
