"""The pad of geometry/floating.toml: its mesh in two views, volumes and areas by closed forms.

Left: the friction face seen from the rotor, with the chamfers and the
radial slot.  Right: the back seen from the caliper, with the piston's rim
(54/57 mm, on the inboard pad) and the two finger footprints (on the
outboard pad, the inboard pad mirrored through the rotor's mid-plane, so at
the same x, y) drawn on the backplate outline.  The JSON holds the numbers:
mesh sizes, the lining and backplate volumes and the friction-face area of
the mesh beside their closed forms, the footprints.

Run ``python studies/pad_shape.py [--out DIR] [--data DIR] [--size MM]``:
prints the table, writes ``floating_pad.png`` (to ``--out``, default
``docs/figures``) and ``floating_pad.json`` (to ``--data``, default
``docs/data``).  A few seconds.
"""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
import skfem as fem

from brakewear.geometry import load_geometry
from brakewear.mesh import pad_mesh
from brakewear.output.figures import facets_to_pyvista, offscreen_pyvista

FACE_COLOURS = {"friction": (0.75, 0.75, 0.72), "leading_chamfer": (0.12, 0.47, 0.71),
                "trailing_chamfer": (0.84, 0.15, 0.16), "slot": (1.0, 0.5, 0.05),
                "inner": (0.55, 0.55, 0.60), "outer": (0.55, 0.55, 0.60),
                "leading": (0.65, 0.8, 0.9), "trailing": (0.95, 0.7, 0.7),
                "back": (0.6, 0.6, 0.65), "piston_face": (0.17, 0.63, 0.17)}


def _sheet(r: float, g: float) -> float:
    """``int sqrt(r^2 + g^2) dr``: a chamfer sheet's area per radian of arc."""
    return 0.5 * (r * math.sqrt(r * r + g * g) + g * g * math.asinh(r / g))

def closed_forms(pad) -> dict:
    """Lining and backplate volumes (m^3) and friction-face area (m^2) of the pad,
    chamfers and slot included (the shapes of :mod:`brakewear.mesh.pad_block`)."""
    ri, ro = pad.inner_radius, pad.outer_radius
    dr2, r_mean = ro ** 2 - ri ** 2, 0.5 * (ri + ro)
    a = 0.5 * pad.slot_width

    def F(r):   # integral of r asin(a / r) dr
        return 0.5 * r * r * math.asin(a / r) + 0.5 * a * math.sqrt(r * r - a * a)

    slot = 2.0 * (F(ro) - F(ri))
    depth = pad.friction_thickness if pad.slot_depth is None else pad.slot_depth
    chamfer_area, wedges, chamfer_arc = 0.0, 0.0, 0.0
    for length, d in (pad.leading_chamfer, pad.trailing_chamfer):
        if length > 0:
            th, g = length / r_mean, d / (length / r_mean)
            chamfer_area += th * (_sheet(ro, g) - _sheet(ri, g))
            wedges += 0.25 * d * th * dr2
            chamfer_arc += th
    bri, bro = pad.backplate_radii
    return {
        "lining_volume": 0.5 * pad.arc_angle * dr2 * pad.friction_thickness - wedges - slot * depth,
        "backplate_volume": 0.5 * pad.arc_angle * (bro**2 - bri**2) * pad.backplate_thickness,
        "friction_area": 0.5 * (pad.arc_angle - chamfer_arc) * dr2 - slot + chamfer_area,
    }


def measured(m: fem.Mesh) -> dict:
    """The same quantities integrated over the mesh."""
    e = fem.ElementTetP2() if isinstance(m, fem.MeshTet2) else fem.ElementTetP1()
    vol = {k: float(fem.Basis(m, e, elements=m.subdomains[s]).dx.sum())
           for k, s in (("lining_volume", "friction_layer"), ("backplate_volume", "backplate"))}
    vol["friction_area"] = float(fem.FacetBasis(m, e, facets=m.boundaries["friction"]).dx.sum())
    return vol


def _circle(pv, xc, yc, radius, z, colour, pl, width=4):
    ang = np.linspace(0.0, 2 * np.pi, 121)
    pts = np.column_stack([xc + radius * np.cos(ang), yc + radius * np.sin(ang), np.full(121, z)])
    pl.add_mesh(pv.lines_from_points(pts), color=colour, line_width=width)


def draw(geom, m: fem.Mesh, path: Path) -> None:
    """The two views (friction face from the rotor, back from the caliper)."""
    pv = offscreen_pyvista()
    pad = geom.pad
    pl = pv.Plotter(off_screen=True, shape=(1, 2), window_size=[1800, 640], border=False)
    for col, names, up, title in (
            (0, ("friction", "leading_chamfer", "trailing_chamfer", "slot", "inner", "outer",
                 "leading", "trailing"), -1.0,
             "friction face, seen from the rotor: chamfers (blue, red), slot (orange)"),
            (1, ("back", "piston_face", "inner", "outer", "leading", "trailing"), 1.0,
             "back, seen from the caliper: piston rim (green), fingers (purple)")):
        pl.subplot(0, col)
        chamfers = np.concatenate([m.boundaries["leading_chamfer"],
                                   m.boundaries["trailing_chamfer"]])
        for name in names:
            f = m.boundaries[name]
            if name == "friction":      # the chamfers get their own colour
                f = np.setdiff1d(f, chamfers)
            if len(f):
                pl.add_mesh(facets_to_pyvista(m, f), color=FACE_COLOURS[name], show_edges=True,
                            edge_color=(0.2, 0.2, 0.2), line_width=0.3)
        if col == 1:
            z = pad.thickness * 1.02
            xc, yc = geom.piston_center
            for d in (geom.piston.diameter, geom.piston.rim_inner_diameter or 0.0):
                if d:
                    _circle(pv, xc, yc, 0.5 * d, z, (0.0, 0.45, 0.0), pl)
            for fg in geom.caliper.fingers:
                ang = pad.center_angle + fg.angle
                _circle(pv, fg.radius * math.cos(ang), fg.radius * math.sin(ang),
                        0.5 * fg.diameter, z, (0.5, 0.1, 0.6), pl)
        c = pad.center_angle
        r_lab = pad.backplate_radii[0] - 0.004
        ends = [(pad.leading_angle, "leading end"), (pad.trailing_angle, "trailing end")]
        pl.add_point_labels(np.array([[r_lab * math.cos(a), r_lab * math.sin(a),
                                       pad.thickness * (col + 0.1)] for a, _ in ends]),
                            [t for _, t in ends], font_size=20, point_size=1,
                            shape_opacity=0.0, text_color="black", always_visible=True)
        mid = 0.5 * sum(pad.backplate_radii)
        focus = np.array([mid * math.cos(c), mid * math.sin(c), 0.5 * pad.thickness])
        pl.camera.focal_point = tuple(focus)
        pl.camera.position = tuple(focus + np.array([0.0, 0.0, up * 0.5]))
        pl.camera.up = (math.cos(c), math.sin(c), 0.0)
        pl.enable_parallel_projection()
        pl.reset_camera()
        pl.camera.zoom(1.35)
        pl.add_text(title, position="upper_edge", font_size=11, color="black")
    pl.set_background("white")
    path.parent.mkdir(parents=True, exist_ok=True)
    pl.screenshot(str(path))
    pl.close()


def main(size_mm: float = 2.5, out: str = "docs/figures", data: str = "docs/data",
         figure: bool = True) -> dict:
    geom = load_geometry("floating")
    result = {"geometry": "floating", "size_mm": size_mm, "orders": {}}
    exact = closed_forms(geom.pad)
    print(
        f"{'order':>5} {'nodes':>7} {'tets':>7}  {'quantity':<17} {'mesh':>12} {'closed form':>12} "
        f"{'rel. diff':>10}"
    )
    for order in (1, 2):
        m = pad_mesh(geom, size=size_mm * 1e-3, order=order)
        got = measured(m)
        row = {"nodes": int(m.doflocs.shape[1]), "tets": int(m.t.shape[1]),
               "facets": {k: int(len(v)) for k, v in sorted(m.boundaries.items())}}
        for k, v in got.items():
            row[k] = {"mesh": v, "closed_form": exact[k], "rel_diff": v / exact[k] - 1.0}
            print(f"{order:>5} {row['nodes']:>7} {row['tets']:>7}  {k:<17} {v:>12.6e} "
                  f"{exact[k]:>12.6e} {v / exact[k] - 1.0:>10.2e}")
        result["orders"][f"P{order}"] = row
        if order == 1 and figure:
            draw(geom, m, Path(out) / "floating_pad.png")
    pad = geom.pad
    result["pad_mm"] = {"lining_radii": [pad.inner_radius * 1e3, pad.outer_radius * 1e3],
                        "backplate_radii": [r * 1e3 for r in pad.backplate_radii],
                        "leading_chamfer": [x * 1e3 for x in pad.leading_chamfer],
                        "trailing_chamfer": [x * 1e3 for x in pad.trailing_chamfer],
                        "slot_width": pad.slot_width * 1e3}
    result["footprints_mm_deg"] = {
        "piston_rim": [geom.piston.rim_inner_diameter * 1e3, geom.piston.diameter * 1e3,
                       geom.piston.radius * 1e3, math.degrees(geom.piston.angle)],
        "fingers": [[f.diameter * 1e3, f.radius * 1e3, math.degrees(f.angle)]
                    for f in geom.caliper.fingers]}
    Path(data).mkdir(parents=True, exist_ok=True)
    (Path(data) / "floating_pad.json").write_text(json.dumps(result, indent=1) + "\n")
    return result


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--data", default="docs/data")
    ap.add_argument("--size", type=float, default=2.5, help="element size (mm)")
    a = ap.parse_args()
    main(a.size, a.out, a.data)
