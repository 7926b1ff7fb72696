"""The wall study's figures: the pressure on each segment beside the theories' profiles,
and K against the wall's movement."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from viz.figures import THEORY_STYLE, plt, save_figure


def plot_pressure(H: float, dem_sigma_kPa, theories: list[dict], path, *, title: str = "") -> Path:
    """Normal stress on each wall segment [kPa, compression +] against depth [m], as steps
    over the segments, with each theory's stress at the segment centres."""
    sigma = np.asarray(dem_sigma_kPa)[::-1]             # top segment first, as depth grows
    n = len(sigma)
    edges = np.linspace(0.0, H, n + 1)
    centres = 0.5 * (edges[1:] + edges[:-1])
    fig, ax = plt.subplots(figsize=(5.5, 6))
    ax.stairs(sigma, edges, orientation="horizontal", baseline=None, color="k", lw=1.8,
              label="DEM (segment mean)")
    for row in theories:
        ls, colour = _style(row["method"])
        ax.plot(np.asarray(row["segment_sigma_kPa"])[::-1], centres, marker="o", ms=3, lw=0.9, ls=ls,
                color=colour, label=f"{row['name']} (K {row['K']:.3f})")
    ax.set_ylim(H, 0)
    ax.set_xlim(left=0)
    ax.set_ylabel("depth below the top of the back [m]")
    ax.set_xlabel("normal stress on the wall [kPa], compression +")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(title, fontsize=9)
    return save_figure(fig, path)


def plot_K_history(disp_over_H, K, theories: list[dict], K_at_rest: float, path, *, title: str = "") -> Path:
    """K of the total thrust against Delta/H, with each theory's K and the at-rest K."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(np.asarray(disp_over_H), np.asarray(K), color="k", label="DEM")
    for row in theories:
        ls, colour = _style(row["method"])
        ax.axhline(row["K"], color=colour, ls=ls, lw=0.8, label=f"{row['name']} {row['K']:.3f}")
    ax.axhline(K_at_rest, color="grey", ls=":", lw=0.8, label=f"at rest (DEM) {K_at_rest:.3f}")
    ax.set_xlabel("wall movement Delta / H")
    ax.set_ylabel("K = thrust / (0.5 gamma H^2 + q H)")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(title, fontsize=9)
    return save_figure(fig, path)


def _style(method: str) -> tuple[str, str]:
    """(line style, colour) of a theory, as every figure draws it; the DEM is black."""
    return THEORY_STYLE.get(method.replace("-virtual-back", ""), ("--", "grey"))
