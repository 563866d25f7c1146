"""The rotors of geometry/floating.toml: hat rotor and vented ring, meshed, cut open, and volumes.

Two rotors: ``hat``, the floating brake's solid friction ring on its hat
(``geometry/floating.toml`` as it is), and ``vented``, the same with the
vented ring that the file describes in its commented ``[rotor.vents]`` table
(8 mm cheeks, 37 radial vanes of 6 mm).  Each is meshed whole
(:func:`brakewear.mesh.rotor.full_rotor_mesh`) with linear and quadratic
tetrahedra; the volume of each mesh is set against the section's volume
worked out by hand (ring, the neck that continues it over the hat wall,
wall, flange, less the vent channels between straight vanes) and against
:func:`brakewear.mesh.rotor.rotor_volume`.

The figure cuts both P1 meshes open along the plane through the axis and
the pad's centre line (the half ``y < 0`` is kept) and, over the quarter
``x < 0``, also along the ring's mid-plane (the inboard half of the ring
taken off there, so that a vented ring's channels and vanes show); each
named facet group has its colour, the cut faces are grey, so the section of
the hat wall and flange, and of the cheeks and vanes, can be read off them.
Top: seen from the inboard side; bottom: from the outboard side, where the
hat is.

Run ``python studies/rotor_shapes.py [--out DIR] [--data DIR] [--size MM]``:
prints the table, writes ``rotor_mounts.png`` (to ``--out``, default
``docs/figures``) and ``rotor_mounts.json`` (to ``--data``, default
``docs/data``).  Under a minute.
"""
from __future__ import annotations

import argparse
import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import skfem as fem

from brakewear.caliper.geometry import VentGeometry
from brakewear.geometry import load_geometry
from brakewear.mesh.rotor import full_rotor_mesh, rotor_volume

#: the vented ring of geometry/floating.toml's commented [rotor.vents] table (m)
VENTS = VentGeometry(cheek_thickness=8e-3, vane_count=37, vane_width=6e-3)

#: a colour per named facet group, and the cut face's
COLOURS = {"friction_in": (0.84, 0.15, 0.16), "friction_out": (0.12, 0.47, 0.71),
           "outer": (0.74, 0.74, 0.13), "vents": (1.0, 0.5, 0.05),
           "hat": (0.58, 0.40, 0.74), "rotor_clamp": (0.17, 0.63, 0.17),
           "cut": (0.80, 0.80, 0.80)}


def rotors() -> dict:
    """name -> geometry of each rotor pictured."""
    g = load_geometry("floating")
    return {"hat": g, "vented": replace(g, rotor=replace(g.rotor, vents=VENTS))}


def closed_form_volume(geom) -> dict:
    """The rotor's volume (m^3) by hand, block by block (the section of
    :mod:`brakewear.mesh.rotor`): ring, neck (the ring continued inward over
    the hat wall: its whole thickness, or the outboard cheek of a vented
    ring), wall, flange, less the channels between the vanes (a vane the slab
    ``|y| < w / 2`` between the ring's radii)."""
    rot, hat, v = geom.rotor, geom.rotor.hat, geom.rotor.vents
    ri, ro, t = rot.inner_radius, rot.outer_radius, rot.thickness
    wi, wo = hat.wall_radius - 0.5 * hat.wall_thickness, hat.wall_radius + 0.5 * hat.wall_thickness
    out = {"ring": math.pi * (ro ** 2 - ri ** 2) * t,
           "neck": math.pi * max(ri ** 2 - wi ** 2, 0.0) * (t if v is None else v.cheek_thickness),
           "wall": math.pi * (wo ** 2 - wi ** 2) * (hat.height - hat.flange_thickness),
           "flange": math.pi * (wo ** 2 - hat.bore_radius ** 2) * hat.flange_thickness,
           "channels": 0.0}
    if v is not None:
        a = 0.5 * v.vane_width

        def chord(R):   # the vane's area inside radius R: int_{-a}^{a} sqrt(R^2 - y^2) dy
            return a * math.sqrt(R * R - a * a) + R * R * math.asin(a / R)

        vane = chord(ro) - chord(ri)
        out["channels"] = -(math.pi * (ro ** 2 - ri ** 2) - v.vane_count * vane) * (
            t - 2 * v.cheek_thickness)
    out["total"] = sum(out.values())
    return out


def mesh_volume(m: fem.Mesh) -> float:
    """Volume (m^3) integrated over the mesh (isoparametric for P2)."""
    e = fem.ElementTetP2() if isinstance(m, fem.MeshTet2) else fem.ElementTetP1()
    return float(fem.Basis(m, e, intorder=4).dx.sum())


def groups(m: fem.Mesh) -> dict:
    """Each boundary facet once, under its most specific name."""
    out, seen = {}, np.zeros(m.facets.shape[1], dtype=bool)
    for name in ("rotor_clamp", "vents", "outer", "friction_in", "friction_out", "hat"):
        if name in m.boundaries:
            f = np.asarray(m.boundaries[name])
            out[name] = f[~seen[f]]
            seen[f] = True
    return out


#: the two views: from the inboard side (friction_in, the hat's inside) and from
#: the outboard side (friction_out, the flange's clamped face); camera direction
VIEWS = (("seen from the inboard side", (0.25, 1.0, 0.55)),
         ("seen from the outboard side", (0.25, 1.0, -0.55)))


def _keep(pd, normal, origin):
    """The part of ``pd`` on the side of a plane opposite to ``normal``."""
    return pd.clip(normal=normal, origin=origin)


def cutaway(m: fem.Mesh, geom) -> list:
    """``(group, PolyData)`` of the rotor cut open: the half ``y < 0`` kept, and of
    its quarter ``x < 0`` only what lies outboard of the ring's mid-plane
    ``z = -t / 2`` (so the channels and vanes of a vented ring show); each named
    facet group in that region, and the cut faces as ``"cut"``."""
    from brakewear.output.figures import facets_to_pyvista, skfem_to_pyvista

    zc = -0.5 * geom.rotor.thickness
    o = (0.0, 0.0, zc)

    def region(pd, cut_y=True):
        half = _keep(pd, (0, 1, 0), o) if cut_y else pd
        parts = [_keep(half, (-1, 0, 0), o), _keep(_keep(half, (1, 0, 0), o), (0, 0, 1), o)]
        parts = [q for q in parts if q.n_cells]
        return parts[0].merge(parts[1:]) if len(parts) > 1 else (parts[0] if parts else half)

    grid = skfem_to_pyvista(m)
    out = [(g, region(facets_to_pyvista(m, f))) for g, f in groups(m).items() if len(f)]
    # each cut face is clipped by the other planes only (not by its own)
    out.append(("cut", region(grid.slice(normal=(0, 1, 0), origin=o), cut_y=False)))
    out.append(("cut", _keep(_keep(grid.slice(normal=(0, 0, 1), origin=o), (1, 0, 0), o),
                             (0, 1, 0), o)))
    out.append(("cut", _keep(_keep(grid.slice(normal=(1, 0, 0), origin=o), (0, 1, 0), o),
                             (0, 0, -1), o)))
    return out


def draw(meshes: dict, path: Path) -> None:
    """The P1 meshes cut open (:func:`cutaway`), each facet group in its colour,
    the cut faces grey; from both sides."""
    from brakewear.output.figures import offscreen_pyvista

    pv = offscreen_pyvista()
    pl = pv.Plotter(off_screen=True, shape=(2, 2), window_size=[2000, 1400], border=False,
                    lighting="three lights")
    for col, (geom, m) in enumerate(meshes.values()):
        pieces = cutaway(m, geom)
        v = geom.rotor.vents
        title = ("hat rotor, solid ring" if v is None else
                 f"hat rotor, vented ring ({v.vane_count} vanes)")
        for row, (view, d) in enumerate(VIEWS):
            pl.subplot(row, col)
            labelled = set()
            for g, pd in pieces:
                if pd.n_cells:
                    pl.add_mesh(pd, color=COLOURS[g], show_edges=True,
                                edge_color=(0.15, 0.15, 0.15), line_width=0.3,
                                label=None if g in labelled else g.replace("_", " "))
                    labelled.add(g)
            focus = np.array([0.0, 0.0, -0.5 * geom.rotor.thickness - 0.02])
            pl.camera.focal_point = tuple(focus)
            pl.camera.position = tuple(focus + 0.6 * np.asarray(d))
            pl.camera.up = (0.0, 0.0, 1.0)
            pl.reset_camera()
            pl.camera.zoom(1.35)
            pl.add_text(f"{title}, {view}: {3 * m.p.shape[1]} DOFs (P1)",
                        position="upper_edge", font_size=11, color="black")
            if (row, col) == (1, len(meshes) - 1):
                pl.add_legend(bcolor=(1.0, 1.0, 1.0), border=False, size=(0.2, 0.3),
                              loc="lower right", face="rectangle")
    pl.set_background("white")
    path.parent.mkdir(parents=True, exist_ok=True)
    pl.screenshot(str(path))
    pl.close()


def main(size_mm: float = 4.5, out: str = "docs/figures", data: str = "docs/data",
         figure: bool = True) -> dict:
    """Mesh both rotors (P1 and P2), compare their volumes with the closed forms;
    returns the numbers (and writes them, and the figure)."""
    result = {"geometry": "floating", "size_mm": size_mm,
              "vents_mm": {"cheek_thickness": VENTS.cheek_thickness * 1e3,
                           "vane_count": VENTS.vane_count,
                           "vane_width": VENTS.vane_width * 1e3}, "rotors": {}}
    drawn = {}
    print(f"{'rotor':>7} {'order':>5} {'DOFs':>8} {'tets':>7} {'volume (cm^3)':>14} "
          f"{'by hand':>10} {'rel. diff':>10}")
    for name, geom in rotors().items():
        exact = closed_form_volume(geom)
        row = {"closed_form_m3": exact, "rotor_volume_m3": rotor_volume(geom), "orders": {}}
        for order in (1, 2):
            m = full_rotor_mesh(geom, size=size_mm * 1e-3, order=order)
            vol = mesh_volume(m)
            row["orders"][f"P{order}"] = {
                "dofs": int(3 * m.doflocs.shape[1]), "tets": int(m.t.shape[1]),
                "volume_m3": vol, "rel_diff": vol / exact["total"] - 1.0,
                "facets": {k: int(len(v)) for k, v in sorted(m.boundaries.items())}}
            print(f"{name:>7} {order:>5} {3 * m.doflocs.shape[1]:>8} {m.t.shape[1]:>7} "
                  f"{vol * 1e6:>14.3f} {exact['total'] * 1e6:>10.3f} "
                  f"{vol / exact['total'] - 1.0:>10.2e}")
            if order == 1:
                drawn[name] = (geom, m)
        result["rotors"][name] = row
    if figure:
        draw(drawn, Path(out) / "rotor_mounts.png")
    if data:
        Path(data).mkdir(parents=True, exist_ok=True)
        (Path(data) / "rotor_mounts.json").write_text(json.dumps(result, indent=1) + "\n")
    return result


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--data", default="docs/data")
    ap.add_argument("--size", type=float, default=4.5, help="element size of the ring (mm)")
    a = ap.parse_args()
    main(a.size, a.out, a.data)
