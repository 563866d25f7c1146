"""How the bracket holds the pad decides how friction tilts it (docs/wear.md).

The default brake under a line pressure, once per support of the pad in the
caliper bracket (:mod:`brakewear.contact.supports`) and friction coefficient:

* ``bilateral``: both backplate end faces held in their plane (a support that
  can pull and blocks any tilt of the end faces);
* ``push``: the trailing abutment bears (a unilateral stop, no clearance), the
  leading end has the clearance;
* ``pull``: the leading hook bears, the trailing end has the clearance;

both unilateral designs with the bracket's radial rails and anti-rattle
spring.  Sliding friction drags the friction face (z = 0) along the rotor's
motion (+theta); the bracket holds the backplate, higher up.  The couple of
the two tips the pad toward its leading end: statics about the pad's radial
centre line moves the centre of pressure by ``-lever mu`` (times the mean
cosine of the drag's angle to the centre line), ``lever`` being the height
above the friction face of the line of action of the bracket's in-plane
force.  Where the bracket takes that force -- over the whole end faces, at
the lower edge of the trailing end (push: the pad tilts and its end face
rocks on the stop's lower edge) or at the leading hook -- sets the lever.

Per support and mu: the centre of pressure (``cop_mm`` along the arc at its
radius from the pad's centre line, along the motion; < 0: toward the leading
end), its shift from mu = 0 (``shift_mm``) against the statics estimate
(``statics_shift_mm``), the contact coverage (share of the friction face's
area in contact), the bracket's tangential force at each end as a share of
``mu F`` (``leading_share``, ``trailing_share``) and the ``lever_mm``.

Run ``python studies/pad_support.py [--out DIR] [--size MM] [--mu 0 0.4]
[--clearance MM] [--pressure MPA] [--rotor rigid|elastic] [--no-figures]``;
writes ``pad_support.json`` and ``pad_support.png`` into ``DIR`` (default
``docs/figures``).
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from brakewear.caliper.geometry import SupportGeometry
from brakewear.contact import solve_contact, with_supports
from brakewear.contact.supports import abutment_faces
from brakewear.mesh.surface import surface_nodes
from brakewear.model import BrakeModel

SUPPORTS = ("bilateral", "push", "pull")


def bracket_forces(model, cs, u_all: np.ndarray) -> dict:
    """The bracket's nodal forces on each pad end (``{"leading": (n, 3),
    "trailing": (n, 3)}``, N) and the nodes' heights: ``K_pad u - f`` at the
    backplate end-face nodes, which no other load or contact touches."""
    pad, off = model.meshes["pad"], model.offsets["pad"]
    n = pad.p.shape[1]
    u = u_all[3 * off:3 * (off + n)]
    f = model.loads(cs.clamp_force / model.geometry.piston.hydraulic_area)[3 * off:3 * (off + n)]
    r = (model.stiffness("pad") @ u - f).reshape(-1, 3)
    out = {}
    for end in ("leading", "trailing"):
        nodes = surface_nodes(pad, np.concatenate(list(abutment_faces(pad, end).values())))
        out[end] = (r[nodes], pad.p[2, nodes])
    return out


def solve_support(model, kind: str, mu: float, line_pressure: float, clearance: float) -> dict:
    """One static contact solve of the pad held by a ``kind`` support; its numbers."""
    g = model.geometry.pad
    cs = model.contact_system(line_pressure, mu)
    support = SupportGeometry(type=kind, clearance=clearance)
    cs = with_supports(cs, model.meshes["pad"], model.offsets["pad"], g, support)
    res = solve_contact(cs.K, cs.f, cs.fixed, cs.coords, [cs.pair, *cs.supports])
    u = cs.P @ res.u
    x = cs.coords[:, cs.pair.slave]
    fz, area = res.force[0], cs.pair.area
    r, th = np.hypot(x[0], x[1]), np.arctan2(x[1], x[0]) - g.center_angle
    rc = float((fz * r).sum() / fz.sum())
    tang = np.array([-np.sin(g.center_angle), np.cos(g.center_angle), 0.0])
    F = cs.clamp_force
    out = {"cop_mm": 1e3 * rc * float((fz * th).sum() / fz.sum()), "cop_radius_mm": 1e3 * rc,
           "coverage": float(area[res.active[0]].sum() / area.sum()),
           "peak_pressure_MPa": float(res.pressure[0].max() / 1e6),
           "normal_force_N": float(fz.sum()), "clamp_force_N": float(F),
           "stop_forces_N": {pr.name: float(v) for pr, v in
                             zip(cs.supports, res.info["normal_force"][1:])},
           "active_set_iterations": res.info["active_set_iterations"]}
    if mu > 0:
        ends = bracket_forces(model, cs, u)
        S = sum(R.sum(axis=0) for R, _ in ends.values())
        M = sum((z[:, None] * R).sum(axis=0) for R, z in ends.values())
        out["lever_mm"] = 1e3 * float(M[:2] @ S[:2] / (S[:2] @ S[:2]))
        out["statics_shift_mm"] = -out["lever_mm"] * mu * float((fz * np.cos(th)).sum()
                                                               / fz.sum())
        for end, (R, _) in ends.items():
            out[f"{end}_share"] = float(-(R.sum(axis=0) @ tang) / (mu * F))
    bins = np.linspace(-0.5 * g.arc_angle, 0.5 * g.arc_angle, 13)
    k = np.clip(np.digitize(th, bins) - 1, 0, bins.size - 2)
    prof = np.bincount(k, fz, bins.size - 1) / np.bincount(k, area, bins.size - 1)
    out["profile"] = {"arc_mm": list(1e3 * rc * 0.5 * (bins[1:] + bins[:-1])),
                      "pressure_MPa": list(prof / 1e6)}
    return out


def main(size: float = 6.0, mu_values: tuple[float, ...] = (0.0, 0.4), clearance: float = 0.1,
         line_pressure: float = 1e6, rotor: str = "rigid", out: str | Path | None = None,
         figures: bool = True) -> dict:
    """Solve each support at each mu; return (and with ``out``, write) the numbers.

    ``size`` and ``clearance`` in mm, ``line_pressure`` in Pa; ``rotor``
    ``"rigid"`` (the plane z = 0) or ``"elastic"``.
    """
    t0 = time.perf_counter()
    model = BrakeModel(rotor=rotor, size=size * 1e-3)
    runs = {kind: {f"mu={mu:g}": solve_support(model, kind, mu, line_pressure,
                                                 clearance * 1e-3) for mu in mu_values}
            for kind in SUPPORTS}
    if 0.0 in mu_values:
        for by_mu in runs.values():
            for v in by_mu.values():
                v["shift_mm"] = v["cop_mm"] - by_mu["mu=0"]["cop_mm"]
    res = {"settings": {"mesh_size_mm": size, "rotor": rotor, "dofs": int(model.dofs),
                        "line_pressure_Pa": line_pressure, "clearance_mm": clearance,
                        "mu_values": list(mu_values),
                        "lining_thickness_mm": 1e3 * model.geometry.pad.friction_thickness,
                        "backplate_thickness_mm": 1e3 * model.geometry.pad.backplate_thickness},
           "runs": runs, "time_s": time.perf_counter() - t0}
    _print(res)
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "pad_support.json").write_text(json.dumps(res, indent=1))
        if figures:
            _figure(res, out / "pad_support.png")
    return res


def _print(res: dict) -> None:
    print(f"{'support':>10} {'mu':>5} {'cop mm':>8} {'shift':>7} {'statics':>8} "
          f"{'lever':>6} {'cover':>6} {'lead':>6} {'trail':>6}")
    for kind, by_mu in res["runs"].items():
        for key, v in by_mu.items():
            print(f"{kind:>10} {key[3:]:>5} {v['cop_mm']:8.3f} {v.get('shift_mm', np.nan):7.3f} "
                  f"{v.get('statics_shift_mm', np.nan):8.3f} {v.get('lever_mm', np.nan):6.2f} "
                  f"{v['coverage']:6.3f} {v.get('leading_share', np.nan):6.3f} "
                  f"{v.get('trailing_share', np.nan):6.3f}")


def _figure(res: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keys = list(next(iter(res["runs"].values())))
    fig, axes = plt.subplots(1, len(keys), figsize=(5.2 * len(keys), 3.8), sharey=True,
                             squeeze=False)
    for ax, key in zip(axes[0], keys):
        for (kind, by_mu), style in zip(res["runs"].items(), ("o-", "s--", "^:")):
            v = by_mu[key]
            line, = ax.plot(v["profile"]["arc_mm"], v["profile"]["pressure_MPa"], style, ms=4,
                            label=f"{kind}: centre {v['cop_mm']:.2f} mm")
            ax.axvline(v["cop_mm"], color=line.get_color(), ls=":", lw=1)
        ax.set_title(f"μ = {key[3:]}, {res['settings']['line_pressure_Pa'] / 1e6:g} MPa line "
                     "pressure")
        ax.set_xlabel("arc from the pad's centre line (mm), leading end left")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("mean contact pressure over radius (MPa)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--size", type=float, default=6.0, help="mesh size (mm)")
    ap.add_argument("--mu", type=float, nargs="+", default=[0.0, 0.4])
    ap.add_argument("--clearance", type=float, default=0.1, help="clearance (mm)")
    ap.add_argument("--pressure", type=float, default=1.0, help="line pressure (MPa)")
    ap.add_argument("--rotor", default="rigid", choices=["rigid", "elastic"])
    ap.add_argument("--no-figures", action="store_true")
    a = ap.parse_args()
    main(a.size, tuple(a.mu), a.clearance, a.pressure * 1e6, a.rotor, a.out, not a.no_figures)
