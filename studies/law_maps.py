"""The illustrative resin-pad map: mu and k over pressure and speed at two temperatures
(the figure of docs/laws.md).

The map shipped with the package (:func:`brakewear.laws.maps.example_map`, ILLUSTRATIVE
numbers, not a measurement) is evaluated through the per-node laws
:class:`brakewear.laws.maps.FrictionMap` and :class:`brakewear.laws.maps.WearMap` over the
sliding speed at three pressures and two temperatures, one below the wear
transition (100 C) and one above it and in the friction fade (450 C).  Between
the grid's speeds (1, 3, 10, 30 m/s) the curves are the map's linear
interpolation; the markers are the grid points.

Run ``python studies/law_maps.py [--out DIR]``; writes ``laws_example_map.png``
and ``laws_example_map.csv`` (the plotted numbers) into ``DIR`` (default
docs/figures).
"""
from __future__ import annotations

import argparse
import csv
import logging
from pathlib import Path

import numpy as np

from brakewear.laws.maps import FrictionMap, WearMap, example_map

logger = logging.getLogger(__name__)

T_C = (100.0, 450.0)
P_MPA = (0.5, 2.0, 8.0)
V = np.linspace(1.0, 30.0, 59)


def curves() -> dict:
    """mu and k (m^2/N) at ``T_C`` x ``P_MPA`` x ``V``, nested lists [T][p][v]."""
    mu_law, k_law = FrictionMap(example_map("mu")), WearMap(example_map("k"))
    mu, k = [], []
    for t in T_C:
        T = np.full(V.shape, t + 273.15)
        mu.append([mu_law.mu_at(p * 1e6, V, T).tolist() for p in P_MPA])
        k.append([k_law.coefficient_at(p * 1e6, V, T).tolist() for p in P_MPA])
    return {"T_C": list(T_C), "p_MPa": list(P_MPA), "v_m_s": V.tolist(), "mu": mu, "k_m2_N": k}


def plot(res: dict, path: Path) -> None:
    """Two rows (mu, k) by two columns (the temperatures), one curve per pressure."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    grid_v = np.array(example_map("mu").grid[1])
    fig, axes = plt.subplots(2, 2, figsize=(9.0, 6.5), sharex=True, sharey="row")
    for j, t in enumerate(res["T_C"]):
        for i, p in enumerate(res["p_MPa"]):
            for row, key, scale in ((0, "mu", 1.0), (1, "k_m2_N", 1e15)):
                y = np.array(res[key][j][i]) * scale
                line, = axes[row, j].plot(res["v_m_s"], y, label=f"p = {p:g} MPa")
                on_grid = np.isin(np.round(res["v_m_s"], 9), grid_v)
                axes[row, j].plot(np.array(res["v_m_s"])[on_grid], y[on_grid], "o",
                                  color=line.get_color(), ms=4)
        axes[0, j].set_title(f"T = {t:g} C")
        axes[1, j].set_xlabel("sliding speed v (m/s)")
    axes[0, 0].set_ylabel("friction coefficient mu")
    axes[1, 0].set_ylabel("specific wear rate k (1e-15 m$^2$/N)")
    axes[1, 0].set_yscale("log")
    axes[1, 0].set_yticks([5, 10, 20, 50, 100, 200], ["5", "10", "20", "50", "100", "200"])
    axes[1, 0].minorticks_off()
    axes[0, 0].legend(loc="lower left", fontsize=8)
    for ax in axes.flat:
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("ILLUSTRATIVE resin-pad map (brakewear/data/maps): lines interpolated, "
                 "markers grid points", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def write_csv(res: dict, path: Path) -> None:
    """The plotted numbers, one row per (T, p, v)."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["T_C", "p_MPa", "v_m_s", "mu", "k_m2_N"])
        for j, t in enumerate(res["T_C"]):
            for i, p in enumerate(res["p_MPa"]):
                for n, v in enumerate(res["v_m_s"]):
                    w.writerow([f"{t:g}", f"{p:g}", f"{v:.6g}", f"{res['mu'][j][i][n]:.6g}",
                                f"{res['k_m2_N'][j][i][n]:.6g}"])


def main(out: str | Path = Path(__file__).parents[1] / "docs" / "figures") -> dict:
    """Evaluate, plot and write; returns the numbers (see :func:`curves`)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    res = curves()
    plot(res, out / "laws_example_map.png")
    write_csv(res, out / "laws_example_map.csv")
    logger.info("wrote %s and %s", out / "laws_example_map.png", out / "laws_example_map.csv")
    return res


if __name__ == "__main__":
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(Path(__file__).parents[1] / "docs" / "figures"))
    main(ap.parse_args().out)
