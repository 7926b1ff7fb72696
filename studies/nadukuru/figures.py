"""Nadukuru & Michalowski's figures: K against wall movement for each mode (Fig. 4) and
the normal stress on each wall segment (Fig. 5a)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from viz.figures import plt, save_figure


def plot_load_history(curves: dict, path, *, paper: dict | None = None, at_rest: float | None = None,
                      title: str = "", ylabel: str = "load coefficient K (eq. 6)") -> Path:
    """Nadukuru & Michalowski Fig. 4: K against wall movement Delta/H for each mode.
    curves: {label: (wall_disp_over_H, K)}; paper: {label: K} drawn as dashed levels;
    at_rest: the DEM specimen's at-rest K (dotted)."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for (label, (x, y)), c in zip(curves.items(), (f"C{i}" for i in range(10))):
        ax.plot(np.asarray(x), np.asarray(y), color=c, label=f"{label} (DEM)")
        if paper and label in paper:
            ax.axhline(paper[label], color=c, ls="--", lw=0.8, label=f"{label} paper {paper[label]:.3f}")
    if at_rest is not None:
        ax.axhline(at_rest, color="k", ls=":", lw=0.8, label=f"at rest (DEM) {at_rest:.3f}")
    ax.set_xlabel("wall movement Delta / H")
    ax.set_ylabel(ylabel)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    ax.set_title(title)
    return save_figure(fig, path)


def plot_segment_stress(profiles: dict, edges_over_H, path, *, theory: dict | None = None,
                        title: str = "", xlabel: str = "sigma_n / (rho g (1 - n) H)") -> Path:
    """Nadukuru & Michalowski Fig. 5(a): normalised normal stress on each wall segment
    (steps over the segment heights) against depth, per mode; optional theory lines
    {label: (z_over_H, sigma_norm)}."""
    e = np.asarray(edges_over_H)
    fig, ax = plt.subplots(figsize=(5.5, 6))
    for (label, s), c in zip(profiles.items(), (f"C{i}" for i in range(10))):
        s = np.asarray(s)
        ax.stairs(s, e, orientation="horizontal", color=c, label=label, lw=1.6)
    for label, (z, s) in (theory or {}).items():
        ax.plot(s, z, ls="--", lw=0.9, label=label)
    ax.set_ylim(1, 0)
    ax.set_xlim(left=0)
    ax.set_ylabel("depth / H")
    ax.set_xlabel(xlabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(title)
    return save_figure(fig, path)
