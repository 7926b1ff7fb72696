"""Static report figures (matplotlib, Agg backend): PNGs for run folders and the
validation reports. Each function takes plain results and a path, draws one figure in
the style of the paper figure it mirrors, and returns the path."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

_STYLE = {"rankine": ("-", "C0"), "coulomb": ("--", "C1"), "jaky": (":", "C2"),
          "mononobe-okabe": ("-.", "C3"), "seed-whitman": ("-.", "C4"), "handy": ("-", "C5"),
          "paik-salgado": ("-", "C6"), "khosravi": ("--", "C7"), "janssen": (":", "C8"),
          "dsm": ("-", "k")}


def _finish(fig, path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def plot_theory_profiles(rows, wall, path, *, dem=None, title: str | None = None) -> Path:
    """sigma_h(z) of every applicable method (kPa vs depth), optionally with DEM points
    ``dem = (z_m, sigma_Pa, label)``. Reconstructed profiles are marked in the legend."""
    fig, ax = plt.subplots(figsize=(6, 6.5))
    for r in rows:
        p = getattr(r, "profile", r)
        if p is None:
            continue
        ls, c = _STYLE.get(p.method, ("-", None))
        label = p.method + (" (reconstruction)" if p.status != "verified" else "")
        ax.plot(p.sigma_h / 1e3, p.z, ls, color=c, label=label)
    if dem is not None:
        z, s, label = dem
        ax.plot(np.asarray(s) / 1e3, z, "ks", ms=5, label=label)
    ax.set_ylim(wall.height, 0)
    ax.set_xlim(left=0)
    ax.set_xlabel("normal stress on the wall sigma_h [kPa] (compression +)")
    ax.set_ylabel("depth below the wall top z [m]")
    ax.set_title(title or f"H = {wall.height:g} m, delta = {wall.delta_deg:g} deg")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return _finish(fig, path)
