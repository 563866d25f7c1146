"""P1 at the default scene's mesh against P2 at a coarser one, on each interface.

The running-in of the mesh-convergence studies (the default scene's physics,
48 equal implicit steps over the hour, gap offset) on two meshes of about the
default's accuracy: the default scene's P1 mesh (pad 1.5 mm, rotor 4.5 mm,
4/8/3 layers) and the P2 mesh of level 2 (9 mm, 2/2/2 layers), each on the FE
interface and on the condensed one (its condensation timed in the same
process, no cache).  Errors: the pad wear after the hour against the P1
family's converged estimate (docs/data/mesh_convergence.json, relative L2 on
the r-theta grid), and the largest pad wear against its estimate.

Run ``python studies/p2_interfaces.py [--steps 48] [--out docs]``; writes
``data/p2_interfaces.json``.  Importable: ``main(meshes=..., steps=...)``
returns the rows.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mesh_convergence as mc  # noqa: E402  (sibling scripts, not a package)
import mesh_convergence_p2 as mc2  # noqa: E402
from brakewear import (  # noqa: E402
    BrakeModel,
    CondensedInterface,
    FEInterface,
    Numerics,
    wear_history,  # noqa: E402
)
from brakewear.mesh.convergence import pad_grid  # noqa: E402
from brakewear.scene import load_scene  # noqa: E402
from brakewear.wear import Run

logger = logging.getLogger(__name__)

#: (label, order, [mesh] keys in m)
MESHES = (
    ("P1, the default scene's mesh", 1,
     {"size": 1.5e-3, "rotor_size": 4.5e-3, "friction_layers": 4, "backplate_layers": 8,
      "rotor_layers": 3}),
    ("P2, level 2 (9 mm, 2/2/2)", 2, mc.level_settings(2.0)),
)


def run(scene, order: int, mesh: dict, steps: int, interface: str, grid: dict) -> dict:
    """One running-in: its cost (the condensation apart) and its end state."""
    g = scene.geometry
    geom = replace(g, mesh=replace(g.mesh, order=order, **mesh))
    t0, c0 = time.perf_counter(), time.process_time()
    model = BrakeModel(geom, rotor=scene.rotor, piston=scene.piston)
    itf = FEInterface(model, scene.line_pressure, scene.interface.mu)
    build = (time.perf_counter() - t0, time.process_time() - c0)
    condense = (0.0, 0.0)
    if interface == "condensed":
        t1, c1 = time.perf_counter(), time.process_time()
        itf = CondensedInterface(model, scene.line_pressure, scene.interface.mu, fe=itf,
                                 cache=False)
        condense = (time.perf_counter() - t1, time.process_time() - c1)
    pad_law, rotor_law = scene.wear_laws()
    t2, c2 = time.perf_counter(), time.process_time()
    for s in wear_history(  # noqa: B007  (the last step)
        Run(
            model,
            scene.line_pressure,
            scene.omega,
            scene.duration,
            pad_law,
            rotor_law,
            scene.interface.mu,
            interface=itf,
            numerics=Numerics(scheme="implicit", update="gap", steps=steps),
        )
    ):
        pass
    loop = (time.perf_counter() - t2, time.process_time() - c2)
    return {"order": order, "mesh": mesh, "interface": interface, "dofs": int(model.dofs),
            "contact_nodes": int(itf.area.size), "steps": steps,
            "build_wall_s": build[0], "build_cpu_s": build[1],
            "condense_wall_s": condense[0], "condense_cpu_s": condense[1],
            "loop_wall_s": loop[0], "loop_cpu_s": loop[1],
            "total_wall_s": sum(x[0] for x in (build, condense, loop)),
            "total_cpu_s": sum(x[1] for x in (build, condense, loop)),
            "end": mc.snapshot(itf, s, grid)}


def main(meshes=MESHES, steps: int = 48, interfaces=("fe", "condensed"),
         p1=mc2.P1_DATA, out=None) -> list:
    """Each mesh on each interface; the rows (and ``data/p2_interfaces.json`` in ``out``)."""
    scene = load_scene("default")
    grid = pad_grid(scene.geometry)
    record = json.loads(Path(p1).read_text()) if p1 is not None else None
    ref = None if record is None else mc2.reference(record, "P1", "end")
    rows = []
    for label, order, mesh in meshes:
        for kind in interfaces:
            r = run(scene, order, mesh, steps, kind, grid)
            end = r.pop("end")
            r["label"] = label
            r["pad_wear_max_um"] = end["pad_wear_max"] * 1e6
            if ref is not None and steps == record["case"]["steps"]:
                e = mc2.errors_from(end, ref, grid)
                r["err_pad_wear_l2"], r["err_pad_wear_max"] = e["pad_wear"], e["pad_wear_max"]
            rows.append(r)
            logger.info("%s", r)
    if out is not None:
        (Path(out) / "data").mkdir(parents=True, exist_ok=True)
        (Path(out) / "data" / "p2_interfaces.json").write_text(json.dumps(rows, indent=1))
    return rows


if __name__ == "__main__":
    logging.basicConfig(level=logging.WARNING)
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=48)
    ap.add_argument("--out", default="docs")
    a = ap.parse_args()
    for r in main(steps=a.steps, out=a.out):
        err = (f"err pad wear L2 {r['err_pad_wear_l2']:.2%}, max {r['err_pad_wear_max']:+.2%}"
               if "err_pad_wear_l2" in r else "")
        print(f"{r['label']:32s} {r['interface']:9s} {r['dofs']:>7} DOFs {r['contact_nodes']:>5} "
              f"nodes: total {r['total_wall_s']:.1f} s wall, {r['total_cpu_s']:.1f} s CPU "
              f"(condensation {r['condense_cpu_s']:.1f} s CPU, loop {r['loop_cpu_s']:.1f} s "
              f"CPU); {err}")
