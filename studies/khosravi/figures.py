"""Khosravi et al.'s figures (paper-style PNGs of the run folder and the validation):
Fig. 9 (backfilling), Fig. 10 (at rest), Fig. 11(b) (force chains in the lower corner),
Fig. 12 (pressure against Dis/H) and Fig. 13 (profiles against the theories)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from viz.figures import THEORY_STYLE, plot_force_chains, plt, save_figure


def plot_khosravi_at_rest(z_over_H, sigma_norm, path, *, jaky_K: float, ps0=None,
                          panels=None, title: str = "") -> Path:
    """Khosravi et al. Fig. 10 style: at-rest sigma_h/(gamma H) against z/H, reading
    points (4-panel means) as markers, single panels faint, PS0 marked, Jaky's line
    K0 z/H for the given K0 (from the biaxial phi)."""
    fig, ax = plt.subplots(figsize=(5, 6))
    zz = np.linspace(0, 1, 50)
    ax.plot(jaky_K * zz, zz, "--", color="C2", label=f"Jaky K0 = {jaky_K:.3f}")
    if panels is not None:
        pz, ps = panels
        ax.plot(ps, pz, ".", color="0.6", ms=4, label="single 10 mm panels")
    ax.plot(sigma_norm, z_over_H, "ks-", ms=6, label="DEM readings (4 panels)")
    if ps0 is not None:
        ax.plot([ps0[1]], [ps0[0]], "r^", ms=9, label="PS0 (bottom panel)")
    ax.set_ylim(1.02, 0)
    ax.set_xlim(left=0)
    ax.set_xlabel("sigma_h / (gamma H)")
    ax.set_ylabel("z / H")
    ax.set_title(title or "At rest (Khosravi Fig. 10)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, path)


def plot_khosravi_vs_displacement(wall_disp_over_H, series: dict, path, *, title: str = "",
                                  steady: float | None = None) -> Path:
    """Khosravi et al. Fig. 12 style: sigma_h/(gamma H) of each reading point against
    Dis/H. ``series``: label -> (n,) values."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for k, (label, vals) in enumerate(series.items()):
        ls = "--" if label.startswith("PS0") else "-"
        ax.plot(wall_disp_over_H, vals, ls, color=f"C{k % 10}", label=label)
    if steady is not None and np.isfinite(steady):
        ax.axvline(steady, color="k", lw=0.8, ls=":", label=f"steady at Dis/H = {steady:.4f}")
    ax.set_xlabel("Dis / H")
    ax.set_ylabel("sigma_h / (gamma H)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.set_title(title or "Lateral pressure against wall displacement (Khosravi Fig. 12)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    return save_figure(fig, path)


def plot_khosravi_profiles(z_over_H, sigma_rest, sigma_active, theories, path, *, jaky_K: float,
                           gamma: float, H: float, wall_disp_over_H: float = 0.003, title: str = "") -> Path:
    """Khosravi et al. Fig. 13 style: at rest and active (at ``wall_disp_over_H``) readings against
    z/H with Jaky (at rest) and Rankine, Handy, Paik-Salgado, Khosravi (active).
    ``theories``: Profiles (sigma_h in Pa, z in m), normalised here by gamma H."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 6), sharey=True)
    zz = np.linspace(0, 1, 50)
    ax = axes[0]
    ax.plot(jaky_K * zz, zz, "--", color="C2", label=f"Jaky (K0 = {jaky_K:.3f})")
    ax.plot(sigma_rest, z_over_H, "ks-", label="DEM at rest")
    ax.set_title("(a) at rest")
    ax = axes[1]
    for p in theories:
        ls, c = THEORY_STYLE.get(p.method, ("-", None))
        label = p.method + (" (reconstruction)" if p.status != "verified" else "")
        ax.plot(p.sigma_h / (gamma * H), p.z / H, ls, color=c, label=label)
    ax.plot(sigma_active, z_over_H, "ko-", label=f"DEM Dis/H = {wall_disp_over_H:.4g}")
    ax.set_title("(b) active")
    for ax in axes:
        ax.set_ylim(1.02, 0)
        ax.set_xlim(left=0)
        ax.set_xlabel("sigma_h / (gamma H)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("z / H")
    if title:
        fig.suptitle(title)
    return save_figure(fig, path)


def _backfill_points(sig: np.ndarray, surf: float, group: int, panel_height: float):
    """(heights [m], sigma [Pa]) of the 4-panel readings wholly below the surface whose
    cells were all read, else of the single cells that were."""
    starts = np.arange(0, len(sig) - group + 1, group)
    starts = starts[(starts + group) * panel_height <= surf + 1e-9]
    groups = [(s + group / 2, np.mean(sig[s:s + group])) for s in starts if not np.isnan(sig[s:s + group]).any()]
    if not groups:
        cells = np.nonzero(~np.isnan(sig) & ((np.arange(len(sig)) + 1) * panel_height <= surf + 1e-9))[0]
        groups = [(c + 0.5, sig[c]) for c in cells]
    if not groups:
        return np.zeros(0), np.zeros(0)
    mids, values = np.array(groups).T
    return mids * panel_height, values


def plot_khosravi_backfilling(layers, path, *, gamma: float, H: float, group: int = 4,
                              panel_height: float = 0.01, title: str = "") -> Path:
    """Khosravi et al. Fig. 9 style: lateral pressure on the wall after each layer of the
    pluviation, sigma_h/(gamma H) against height above the base / H, 4-panel readings.
    ``layers``: list of (layer, surface [m], (p,) panel sigma [Pa], panel 0 at the bottom).
    Cells not read (NaN: grains held static below the free strip of a held-layer fill)
    are left out: a 4-panel reading needs its four cells, else the single read cells
    are drawn, so the near-surface readings of every layer show."""
    fig, ax = plt.subplots(figsize=(5, 6))
    n = len(layers)
    unread = False
    for k, (layer, surf, sig) in enumerate(layers):
        sig = np.asarray(sig, float)
        unread |= bool(np.isnan(sig[: int(surf / panel_height)]).any())
        heights, values = _backfill_points(sig, surf, group, panel_height)
        ax.plot(values / (gamma * H), heights / H, "o-", ms=3, color=plt.cm.viridis(k / max(n - 1, 1)),
                label=f"layer {layer} (surface {surf * 1e3:.0f} mm)" if k in (0, n - 1) or k % 3 == 0 else None)
    if unread:
        ax.text(0.98, 0.02, "cells below the free strip not read\n(grains held static while layers fall)",
                transform=ax.transAxes, ha="right", va="bottom", fontsize=7)
    ax.set_xlim(left=0)
    ax.set_ylim(0, 1.05)
    ax.set_xlabel("sigma_h / (gamma H)")
    ax.set_ylabel("height above the base / H")
    ax.set_title(title or "During backfilling (Khosravi Fig. 9)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    return save_figure(fig, path)


#: the corner drawn: a square of this fraction of H; contacts drawn above this multiple of
#: the mean force (the strong network, where arching shows)
CORNER = 0.3
CHAIN_ABOVE_MEAN = 2.0


def plot_corner_chains(frame, wall_x: float, fill_side: int, H: float, path) -> Path:
    """Khosravi et al.'s Fig. 11(b): the force chains at rest in the lower corner between
    the wall (at ``wall_x`` [m], the fill on the side of sign ``fill_side``) and the base,
    a square of ``CORNER`` H; the paper sees local arching there (chains turning off the wall
    toward the base), which lowers the at-rest pressure of the lowest cells (Fig. 10)."""
    x = sorted((wall_x, wall_x + fill_side * CORNER * H))
    return plot_force_chains(frame, path, axes=(0, 1), window=((x[0] - 0.02 * H, x[1]), (-0.02 * H, CORNER * H)),
                             above=CHAIN_ABOVE_MEAN,
                             title=f"Force chains at rest, lower corner (H = {H * 1e3:.0f} mm; Fig. 11b)\n"
                                   f"contacts above {CHAIN_ABOVE_MEAN:g} x the mean normal force of the whole fill")
