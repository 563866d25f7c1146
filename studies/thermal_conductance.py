"""The thermal drag against the contact conductance: what the rough faces' conductance
changes in the heat partition and the face temperatures (docs/rough.md).

Runs the thermal scene's drag (the default brake, 1 MPa, 55 rad/s, mu 0.4, 90 s in 30
steps, effusivity partition) on a coarser mesh for a range of contact conductances: the
rough faces' (:class:`brakewear.rough.RoughConductance` of ``thermal_rough.toml``, both
laws) and the constants 1e3 to 1e6 W/m^2 K (1e5 is the default).  A run whose face
passes ``T_max`` (900 C) stops there, as ``brakewear run`` does, and is reported with the
time it stopped.  ``python studies/thermal_conductance.py [--size MM]`` writes
``thermal_conductance.json`` (docs/data) and ``thermal_conductance.png`` (docs/figures).
"""
from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import brakewear as bw
from brakewear.errors import TemperatureLimitError
from brakewear.scene import load_scene
from brakewear.wear import Run

CONSTANTS = (1e3, 1e4, 1e5, 1e6)


def conductances() -> dict[str, float]:
    """Label -> h_c (W/m^2 K): the rough faces' (both laws) and the constants."""
    s = load_scene("thermal_rough")
    out = {}
    for law in ("halfspace", "mikic"):
        t = replace(s.thermal, conductance_law=law)
        out[f"rough faces, {law} law"] = t.conductance(s.geometry, s.line_pressure)
    for h in CONSTANTS:
        out[f"{h:.0e}" + (" (default)" if h == 1e5 else "")] = h
    return out


def drag(model, h_c: float, duration: float, steps: int) -> dict:
    """One drag; the per-step temperatures and heat, and where it stopped."""
    th = bw.ThermalModel(model, contact_conductance=h_c)
    rows, stop = [], None
    try:
        for s in bw.wear_history(
            Run(
                model,
                1e6,
                55.0,
                duration,
                bw.WearLaw(5e-15),
                bw.WearLaw(5e-16),
                mu=0.4,
                thermal=th,
                numerics=bw.Numerics(steps=steps, update="gap"),
            )
        ):
            rows.append({"time_s": s.time, "pad_T_max_C": s.pad_temperature_max - 273.15,
                         "rotor_T_max_C": s.rotor_temperature_max - 273.15,
                         "heat_pad_W": s.heat["heat_pad_W"],
                         "heat_rotor_W": s.heat["heat_rotor_W"]})
    except TemperatureLimitError as exc:
        stop = {"time_s": exc.time, "body": exc.body,
                "temperature_C": exc.temperature - 273.15}
    last = rows[-1] if rows else {}
    net = (last["heat_pad_W"] / (last["heat_pad_W"] + last["heat_rotor_W"])
           if rows else float("nan"))
    return {"h_c_W_m2K": h_c, "steps": rows, "stopped": stop,
            "pad_share_effusivity": float(th.partition), "pad_share_net_last": net}


def figure(result: dict, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    for i, (label, r) in enumerate(result["cases"].items()):
        t = [0.0] + [s["time_s"] for s in r["steps"]]
        for ax, body in zip(axes, ("pad", "rotor")):
            ax.plot(t, [20.0] + [s[f"{body}_T_max_C"] for s in r["steps"]], "o-", ms=2.5,
                    color=f"C{i}", label=f"{label}: {r['h_c_W_m2K']:.3g} W/m$^2$K")
        if r["stopped"]:
            ax = axes[0 if r["stopped"]["body"] == "pad" else 1]
            ax.plot(r["stopped"]["time_s"], min(r["stopped"]["temperature_C"], 985), "x",
                    color=f"C{i}", ms=9, mew=2)
    for ax, body in zip(axes, ("pad", "rotor")):
        ax.axhline(900, color="k", lw=0.6)
        ax.set_ylim(0, 1000)
        ax.set_xlabel("time (s)")
        ax.set_title(f"hottest {body} face node", fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].text(1, 910, "T_max: the run stops there (x)", fontsize=8)
    axes[0].set_ylabel("temperature (C)")
    axes[1].legend(fontsize=7, loc="upper left")
    fig.suptitle("Thermal drag (default brake, 1 MPa, 55 rad/s, mu 0.4) against the pad-rotor "
                 "contact conductance", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(size: float = 6e-3, duration: float = 90.0, steps: int = 30, which=None,
         out_data="docs/data", out_fig="docs/figures", write: bool = True) -> dict:
    """Run the drags (``which``: labels of :func:`conductances`, default all)."""
    t0 = time.perf_counter()
    model = bw.BrakeModel(size=size)
    hs = conductances()
    cases = {k: drag(model, h, duration, steps) for k, h in hs.items()
             if which is None or k in which}
    result = {"size_m": size, "dofs": int(model.dofs), "duration_s": duration,
              "steps": steps, "command": "python studies/thermal_conductance.py",
              "cases": cases, "seconds": time.perf_counter() - t0}
    if write:
        d, f = Path(out_data), Path(out_fig)
        d.mkdir(parents=True, exist_ok=True)
        f.mkdir(parents=True, exist_ok=True)
        (d / "thermal_conductance.json").write_text(json.dumps(result, indent=1))
        figure(result, f / "thermal_conductance.png")
    return result


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=6.0, help="mesh size (mm)")
    a = ap.parse_args()
    r = main(size=a.size * 1e-3)
    for label, c in r["cases"].items():
        last = c["steps"][-1] if c["steps"] else {}
        stop = (f"stopped at {c['stopped']['time_s']:.0f} s, {c['stopped']['body']} face "
                f"{c['stopped']['temperature_C']:.0f} C" if c["stopped"] else "ran 90 s")
        print(f"{label:32s} h_c {c['h_c_W_m2K']:9.3g}: {stop}; last step pad "
              f"{last.get('pad_T_max_C', float('nan')):6.1f} C, rotor "
              f"{last.get('rotor_T_max_C', float('nan')):6.1f} C, net pad share "
              f"{c['pad_share_net_last']:.3f}")
