"""Figures a brake engineer reads without the docs: oriented face maps, units, framing."""
from __future__ import annotations

import re

import numpy as np
import pytest

pytest.importorskip("pyvista")
import matplotlib.image as mpimg

from brakewear.cli import main
from brakewear.model import BrakeModel
from brakewear.output import face_maps, figures
from brakewear.output.face_maps import plot_face_map, scale_length
from brakewear.output.figures import TICK_FORMAT, visible_named_surfaces
from brakewear.scene import scene_file


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=8e-3)


def _coloured(img):
    """Pixels that are neither white nor grey-black text: the field."""
    rgb = img[..., :3]
    return (rgb.max(axis=2) - rgb.min(axis=2)) > 0.15


def _is_viridis_high(px) -> bool:            # yellow: red well above blue
    return px[0] > px[2] + 0.3


def _is_viridis_low(px) -> bool:             # dark purple: dark, blue above red
    return px.sum() < 1.2 and px[2] > px[0]


@pytest.mark.parametrize("view,leading_side", [((0.0, 0.0, -1.0), "left"),
                                               ((0.0, 0.0, 1.0), "right")])
def test_the_pad_map_puts_the_edges_where_it_says(tmp_path, model, view, leading_side):
    """A field equal to the angle (leading edge low) and one equal to the radius: seen
    from the rotor (-z) the leading edge is on the left, from the other side on the
    right; the outer radius is up either way."""
    pad, g = model.meshes["pad"], model.geometry.pad
    theta = np.arctan2(pad.p[1], pad.p[0])
    path = plot_face_map(pad, theta, tmp_path / "theta.png", "angle", "theta (rad)", g,
                         view=view)
    img = mpimg.imread(path)
    mask = _coloured(img[:, : int(0.8 * img.shape[1])])    # left of the colour bar
    rows = np.nonzero(mask.any(axis=1))[0]
    row = rows[len(rows) // 2]
    cols = np.nonzero(mask[row])[0]
    left, right = img[row, cols[2], :3], img[row, cols[-3], :3]
    low, high = (left, right) if leading_side == "left" else (right, left)
    assert _is_viridis_low(low) and _is_viridis_high(high), (left, right)
    path = plot_face_map(pad, np.hypot(pad.p[0], pad.p[1]), tmp_path / "r.png", "radius",
                         "r (m)", g, view=view)
    img = mpimg.imread(path)
    mask = _coloured(img[:, : int(0.8 * img.shape[1])])
    col = int(np.median(np.nonzero(mask.any(axis=0))[0]))
    rows = np.nonzero(mask[:, col])[0]
    assert _is_viridis_high(img[rows[2], col, :3]) and _is_viridis_low(img[rows[-3], col, :3])


def test_the_marks_name_edges_radii_rotation_and_scale(monkeypatch, tmp_path, model):
    said = []
    import pyvista as pv
    real = pv.Plotter.add_point_labels

    def record(self, points, labels, **kw):
        said.extend((str(s), kw["justification_horizontal"]) for s in labels)
        return real(self, points, labels, **kw)

    monkeypatch.setattr(pv.Plotter, "add_point_labels", record)
    plot_face_map(model.meshes["pad"], np.zeros(model.meshes["pad"].nvertices),
                  tmp_path / "m.png", "t", "pad wear (\u00b5m)", model.geometry.pad)
    text = dict(said)
    assert text["leading\nedge"] == "right" and text["trailing\nedge"] == "left"
    assert "outer edge, r = 138 mm" in text and "inner edge, r = 95 mm" in text
    assert "rotor turns this way" in text and "10 mm" in text
    said.clear()
    plot_face_map(model.meshes["rotor"], np.zeros(model.meshes["rotor"].nvertices),
                  tmp_path / "r.png", "t", "T", model.geometry.pad, view=(0, 0, 1),
                  rotor_face=True)
    assert {"pad leading\nedge", "pad trailing\nedge", "rotor turns this way",
            "50 mm"} <= dict(said).keys()


def test_scale_lengths_are_round():
    assert scale_length(0.043) == pytest.approx(0.01)
    assert scale_length(0.300) == pytest.approx(0.05)
    assert scale_length(0.036) == pytest.approx(0.01)
    assert scale_length(0.030) == pytest.approx(0.005)
    assert scale_length(0.12) == pytest.approx(0.02)
    assert (TICK_FORMAT % 127.0, TICK_FORMAT % 0.5, TICK_FORMAT % 1234.5) == \
        ("127", "0.5", "1.23e+03")


def test_colour_bars_use_plain_ticks(monkeypatch, tmp_path, model):
    import pyvista as pv
    seen = []
    real = pv.Plotter.add_mesh

    def record(self, mesh, **kw):
        if "scalar_bar_args" in kw:
            seen.append(kw["scalar_bar_args"].get("fmt"))
        return real(self, mesh, **kw)

    monkeypatch.setattr(pv.Plotter, "add_mesh", record)
    pad = model.meshes["pad"]
    figures.plot_field(pad, pad.p[2], tmp_path / "f.png", "z")
    plot_face_map(pad, pad.p[2], tmp_path / "m.png", "z", "z (m)", model.geometry.pad)
    assert seen == [TICK_FORMAT, TICK_FORMAT]


def test_a_thermal_run_draws_temperature_maps_with_units(tmp_path, monkeypatch, capsys):
    """The thermal scene on an 8 mm mesh, 2 steps: every figure its scene file's comment
    names, the maps' units written as µm, MPa and °C."""
    text = scene_file("thermal").read_text()
    comment = re.search(r"^figures = true\s+# (.*)$", text, re.M).group(1)
    text = re.sub(r"\n(rotor_size|friction_layers|backplate_layers|rotor_layers) = .*", "",
                  text)
    text = text.replace("size = 1.5 ", "size = 8.0 ").replace("steps = 30", "steps = 2")
    (tmp_path / "hot.toml").write_text(text)
    labels = []
    real = face_maps.plot_face_map

    def record(mesh, values, path, title, label, pad, **kw):
        labels.append(label)
        return real(mesh, values, path, title, label, pad, **kw)

    monkeypatch.setattr(face_maps, "plot_face_map", record)
    assert main(["run", str(tmp_path / "hot.toml"), "--out", str(tmp_path / "o"),
                 "--quiet"]) == 0
    written = sorted(p.name for p in (tmp_path / "o").glob("*.png"))
    named = sorted(re.findall(r"[\w]+\.png", comment))
    assert written == named == ["history.png", "pad_pressure.png", "pad_temperature.png",
                                "pad_wear.png", "rotor_temperature.png"]
    assert labels == ["pad wear (\u00b5m)", "contact pressure (MPa)",
                      "temperature (\u00b0C)", "temperature (\u00b0C)"]
    for name in written:
        img = mpimg.imread(tmp_path / "o" / name)
        filled = _coloured(img).mean() if name != "history.png" else \
            (img[..., :3].min(axis=2) < 0.9).mean()
        assert img.shape[0] >= 400 and filled > 0.02, (name, filled)


def test_the_surface_picture_lists_what_it_shows(model):
    shown = visible_named_surfaces(model.meshes)
    assert {("rotor", "friction"), ("rotor", "outer"), ("pad", "friction"),
            ("pad", "back"), ("pad", "piston_face"), ("pad", "leading")} <= set(shown)
    # the rotor's mid-plane faces away in every view; the trailing end is behind the pad
    assert ("rotor", "midplane") not in shown and ("pad", "trailing") not in shown
    assert "piston" not in {b for b, _ in shown}        # the demo's piston is a traction
