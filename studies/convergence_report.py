"""The figures and the shared table pieces of the mesh-convergence studies (P1:
``studies/mesh_convergence.py``; P2 beside P1: ``studies/mesh_convergence_p2.py``),
drawn from their results."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from brakewear.mesh.convergence import interpolate
from brakewear.scene.accuracy import TARGET


def label(r: dict) -> str:
    """A run's mesh as the tables and legends name it: size(s) and layers f/b/r."""
    m = r["mesh"]
    lay = "/".join(str(m.get(k, "-")) for k in ("friction_layers", "backplate_layers",
                                                "rotor_layers"))

    def mm(k):
        return f"{m.get(k, m['size']) * 1e3:.3g}"

    size = (f"{mm('size')} mm" if mm("pad_size") == mm("rotor_size") == mm("size") else
            f"pad {mm('pad_size')} / rotor {mm('rotor_size')} mm")
    return f"{size}, {lay}"


def pct(v, signed: bool = True) -> str:
    """A relative error as the tables write it ("-" for none)."""
    return "-" if v is None else (f"{v:+.2%}" if signed else f"{v:.2%}")


def rates_line(est: dict, keys, missing: str) -> str:
    """Each quantity's observed rate from the three finest levels and every triple's."""
    return "; ".join(f"{k} {est[k]['rate']:.2f}" + ("" if est[k].get("asymptotic") else
                                                     f" ({missing})") + " (triples: "
                     + ", ".join(f"{x:.2f}" for x in est[k].get("rates", [])) + ")"
                     for k in keys)


def order_table(result: dict) -> str:
    """The one table of both orders: order, mesh, DOFs, time, pad wear error."""
    lines = ["| order | mesh (size, layers f/b/r) | DOFs | wall s | CPU s | err pad wear L2 "
             "(P1 estimate) | err pad wear L2 (P2 estimate) |",
             "|---|---|---:|---:|---:|---:|---:|"]
    for r in sorted(result["error_vs_time"], key=lambda r: (r["order"], r["cpu_s"])):
        name = (f"n={r['level']:g}: " if r["kind"] == "level" else "candidate ") + r["mesh"]
        lines.append(f"| P{r['order']} | {name} | {r['dofs']} | {r['wall_s']:.1f} | "
                     f"{r['cpu_s']:.1f} | "
                     f"{pct(r['err_pad_wear'], False)} | "
                     f"{pct(r.get('err_pad_wear_own'), False)} |")
    return "\n".join(lines)


def plot(result: dict, path: Path) -> None:
    """Four panels: errors against CPU time, pad wear along the mid-radius arc, the
    estimated pad wear field, the rotor wear profiles."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name, res = next(iter(result["orders"].items()))
    runs, cands, est, grid = res["runs"], res["candidates"], res["end"], result["grid"]
    fig, ax = plt.subplots(2, 2, figsize=(13, 10))
    _plot_errors(ax[0, 0], name, runs, cands)
    a = ax[0, 1]
    th = np.degrees(np.array(grid["theta"]))
    for r in runs:
        a.plot(th, np.array(r["end"]["pad_wear_arc"]) * 1e6, label=f"n={r['level']:g}: "
               + label(r))
    f0 = est["pad_wear"]["field"]
    if f0 is not None:
        arc = interpolate(np.array(f0), np.array(grid["xy"]), np.array(grid["arc_xy"]))
        a.plot(th, arc * 1e6, "k--", label="Richardson estimate")
    a.set_xlabel("theta (deg); the rotor enters at the leading edge, theta < 0")
    a.set_ylabel("pad wear at the mid radius (um)")
    a.set_title("(b) pad wear along the mid-radius arc", fontsize=9)
    a.grid(True, alpha=0.3)
    a.legend(fontsize=7)
    a = ax[1, 0]
    xy = np.array(grid["xy"])
    field = np.array(runs[-1]["end"]["pad_wear"] if f0 is None else f0)
    sc = a.tricontourf(xy[0] * 1e3, xy[1] * 1e3, field * 1e6, 20, cmap="viridis")
    fig.colorbar(sc, ax=a, label="pad wear (um)")
    a.set_aspect("equal")
    a.set_xlabel("x (mm)")
    a.set_ylabel("y (mm); the rotor turns toward +y")
    a.set_title("(c) pad wear at the end: " + ("finest mesh" if f0 is None
                                               else "Richardson estimate"), fontsize=9)
    a = ax[1, 1]
    rg = np.array(grid["r"]) * 1e3
    for r in runs:
        a.plot(rg, np.array(r["end"]["rotor_wear"]) * 1e6, label=f"n={r['level']:g}")
    if est["rotor_wear"]["field"] is not None:
        a.plot(rg, np.array(est["rotor_wear"]["field"]) * 1e6, "k--", label="estimate")
    a.set_xlabel("r (mm)")
    a.set_ylabel("rotor wear, mean over the ring (um)")
    a.set_title("(d) rotor wear profile at the end", fontsize=9)
    a.grid(True, alpha=0.3)
    a.legend(fontsize=7)
    c = result["case"]
    fig.suptitle(f"Mesh convergence: default scene, {c['duration_s']:g} s running-in at "
                 f"{c['line_pressure'] / 1e6:g} MPa, {c['omega']:g} rad/s, mu {c['mu']:g}, "
                 f"{c['steps']} implicit steps", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _plot_errors(a, name: str, runs: list, cands: list) -> None:
    """Panel (a): errors from the estimate against CPU time; candidates as stars."""
    for q, mk, lw in (("pad_wear", "o-", 2.0), ("pad_wear_max", "s-", 1.0),
                      ("pad_wear_volume", "^-", 1.0), ("r_eff", "d-", 1.0)):
        pts = [(r["cpu_s"], abs(r["errors"]["end"][q])) for r in runs
               if r["errors"]["end"][q] is not None]
        if pts:
            a.loglog(*zip(*pts), mk, lw=lw, ms=5 if lw < 2 else 7,
                     label="pad wear, relative L2 of the field" if q == "pad_wear" else
                     f"|{q}|")
    for r in runs:
        e = r["errors"]["end"]["pad_wear"]
        if e is not None:
            a.annotate(f"n={r['level']:g}", (r["cpu_s"], e), textcoords="offset points",
                       xytext=(5, 4), fontsize=8)
    key = []
    for i, r in enumerate(cands, 1):
        e = r["errors"]["end"]["pad_wear"]
        if e is not None:
            a.loglog(r["cpu_s"], e, "k*", ms=10, label="candidates (pad wear L2)"
                     if i == 1 else None)
            a.annotate(f"c{i}", (r["cpu_s"], e), textcoords="offset points",
                       xytext=(-4, -12), fontsize=8)
            key.append(f"c{i}: {label(r)}")
    a.axhline(0.02, color="0.6", lw=0.8, ls=":")
    if key:
        a.text(0.02, 0.02, "\n".join(key), transform=a.transAxes, fontsize=7,
               va="bottom", bbox={"facecolor": "white", "alpha": 0.8, "lw": 0.3})
    a.set_xlabel("CPU time of the run (s)")
    a.set_ylabel("relative error from the Richardson estimate")
    a.set_title(f"(a) {name}: error against cost; level n: size 18/n mm, n layers through "
                "friction layer, backplate, rotor half", fontsize=8.5)
    a.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=7.5, loc="upper right")


def plot_p2(result: dict, path: Path) -> None:
    """(a) pad wear error against wall time, P1 and P2; (b) the P2 meshes' pad wear
    along the mid-radius arc against the two estimates."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(14, 5.8))
    a = ax[0]
    rows = result["error_vs_time"]
    for order, kind, style, lab in (
            (1, "level", "o-", "P1 levels n (size 18/n mm, n layers)"),
            (1, "candidate", "*", "P1 graded candidates (pad finer than rotor)"),
            (2, "level", "s-", "P2 levels n, from the P1 estimate")):
        pts = [r for r in rows if r["order"] == order and r["kind"] == kind
               and r["err_pad_wear"] is not None]
        if pts:
            a.loglog([r["cpu_s"] for r in pts], [r["err_pad_wear"] for r in pts], style,
                     ms=9 if kind == "candidate" else 6, label=lab,
                     color="C3" if order == 2 else ("k" if kind == "candidate" else "C0"))
        for r in pts:
            if kind == "level":
                a.annotate(f"n={r['level']:g}", (r["cpu_s"], r["err_pad_wear"]),
                           textcoords="offset points", xytext=(5, 3), fontsize=7,
                           color="C3" if order == 2 else "C0")
    own = [r for r in rows if r["order"] == 2 and r.get("err_pad_wear_own") is not None]
    if own:
        rate = result["orders"]["P2"]["end"]["pad_wear"]["rate"]
        a.loglog([r["cpu_s"] for r in own], [r["err_pad_wear_own"] for r in own], "s:",
                 color="C3", mfc="none",
                 label=f"P2 levels, from the P2 estimate (its rate {rate:.2f})")
    a.axhline(TARGET, color="0.5", lw=0.8, ls="--")
    a.text(a.get_xlim()[0] * 1.1, TARGET * 1.05, "2 %", fontsize=8, color="0.4")
    # CPU time: the wall time of a run on 2 shared cores varies with the others' load
    a.set_xlabel("CPU time of the run (s), one process on 2 cores")
    a.set_ylabel("pad wear after the hour: relative L2 error")
    a.set_title("(a) error against run time, P1 and P2 (error from the P1 Richardson "
                "estimate)", fontsize=9)
    a.grid(True, which="both", alpha=0.3)
    if a.get_legend_handles_labels()[0]:
        a.legend(fontsize=7.5, loc="lower left")
    else:
        a.text(0.5, 0.5, "no Richardson estimate: no errors to show", ha="center",
               transform=a.transAxes)
    _plot_arc(ax[1], result)
    c = result["case"]
    fig.suptitle(f"Default scene's running-in, {c['duration_s']:g} s, {c['steps']} implicit "
                 "steps: linear (P1) and quadratic (P2) tetrahedra", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _plot_arc(a, result: dict) -> None:
    """Panel (b): pad wear along the mid-radius arc of each P2 mesh and the estimates."""
    grid = result["grid"]
    th = np.degrees(np.asarray(grid["theta"]))
    xy, arc = np.asarray(grid["xy"]), np.asarray(grid["arc_xy"])
    p2 = result["orders"]["P2"]
    for i, r in enumerate(p2["runs"]):
        a.plot(th, np.asarray(r["end"]["pad_wear_arc"]) * 1e6, color=f"C{i}", lw=1.2,
               label=f"P2 n={r['level']:g}: {label(r)}")
    f2 = p2["end"]["pad_wear"]["field"]
    if f2 is not None:
        a.plot(th, interpolate(np.asarray(f2), xy, arc) * 1e6, "r--", lw=2,
               label="P2 Richardson estimate")
    f1 = result.get("p1_field")
    if f1 is not None:
        a.plot(th, interpolate(np.asarray(f1), xy, arc) * 1e6, "k:", lw=2,
               label="P1 Richardson estimate")
    a.set_xlabel("theta (deg); the rotor enters at the leading edge, theta < 0")
    a.set_ylabel("pad wear at the mid radius (um)")
    a.set_title("(b) P2 pad wear along the mid-radius arc", fontsize=9)
    a.grid(True, alpha=0.3)
    a.legend(fontsize=7)
