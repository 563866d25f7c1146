"""The default brake's contact pressure with linear (P1) and quadratic (P2) elements.

P1 tetrahedra with one or two layers through the backplate lock in bending:
the pad bends too little under the piston footprint, and the contact spreads
over too much of its face.  This study solves the frictionless contact at
1 MPa line pressure on P1 and P2 meshes of several sizes and reports the
contact's share of the pad face (by area: tributary areas on P1, the
transformed basis's areas on P2), the largest nodal pressure and the centre
of pressure.

Run ``python studies/brake_order.py [--data DIR]``: prints the table and
writes ``brake_order.json`` (default ``docs/data``).  About a minute.
"""
from __future__ import annotations

import argparse
import json
import logging
import time
from pathlib import Path

import numpy as np

from brakewear.mesh.quadratic import quadratic_face_areas
from brakewear.mesh.surface import tributary_areas
from brakewear.model import BrakeModel
from brakewear.static import solve_contact, static_summary

logger = logging.getLogger(__name__)

SIZES = {1: (12e-3, 8e-3, 6e-3, 4e-3, 3e-3), 2: (12e-3, 8e-3, 6e-3)}


def row(order: int, size: float, line_pressure: float = 1e6) -> dict:
    """One frictionless contact solve of the default brake."""
    t0 = time.perf_counter()
    model = BrakeModel("default", size=size, order=order)
    res = solve_contact(model, line_pressure)
    pad = model.meshes["pad"]
    area = (quadratic_face_areas(pad, "friction")[1] if order == 2
            else tributary_areas(pad, "friction", res.interface_nodes))
    s = static_summary(model, res)["interface"]
    return {"order": order, "size_mm": 1e3 * size, "dofs": int(model.dofs),
            "time_s": time.perf_counter() - t0,
            "contact_share": float(area[res.active].sum() / area.sum()),
            "pressure_max_MPa": s["pressure_max_Pa"] / 1e6,
            "centre_r_mm": 1e3 * s["centre_of_pressure_r_m"],
            "centre_theta_deg": s["centre_of_pressure_theta_deg"]}


def main(sizes: dict = SIZES, data: str | Path | None = None) -> dict:
    """Every order and size of ``sizes`` (one solve at a time); with ``data``, the JSON."""
    rows = [row(order, size) for order, group in sizes.items() for size in group]
    result = {"rows": rows, "line_pressure_Pa": 1e6}
    if data is not None:
        Path(data).mkdir(parents=True, exist_ok=True)
        (Path(data) / "brake_order.json").write_text(json.dumps(result, indent=1) + "\n")
    return result


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="docs/data", help="directory of the JSON numbers")
    args = ap.parse_args()
    logging.basicConfig(level=logging.WARNING)
    res = main(data=args.data)
    print(f"{'order':>5} {'size mm':>7} {'dofs':>7} {'time s':>6} {'contact':>7} "
          f"{'p max MPa':>9} {'r_c mm':>7} {'theta_c':>7}")
    for r in res["rows"]:
        print(f"{'P' + str(r['order']):>5} {r['size_mm']:>7.1f} {r['dofs']:>7} {r['time_s']:>6.1f} "
              f"{r['contact_share']:>7.1%} {r['pressure_max_MPa']:>9.3f} {r['centre_r_mm']:>7.2f} "
              f"{r['centre_theta_deg']:>7.2f}")
    share = np.array([r["contact_share"] for r in res["rows"]])
    print(f"contact share: {share.min():.1%} ... {share.max():.1%}")
