"""The dry-stone walls' figures: water (or fill) height against crest displacement, and
the wall at failure with its mechanism."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from viz.figures import notes_box, plt, save_figure


def plot_drystone_history(water_height_m, crest_displacement_m, path, *, title: str, measured_m: float | None = None,
                          le_m: float | None = None, critical_m: float | None = None,
                          notes: list[str] = ()) -> Path:
    """Water height against outward crest displacement up to failure (rigid-block
    kinematics: the displacements before failure are numerical, not physical, and are
    not to be set against the site sensors)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    ax.plot(np.asarray(crest_displacement_m) * 1e3, water_height_m, "o-", ms=2.5, color="k", label="DEM (rigid blocks)")
    for y, style, label in ((measured_m, ("--", "C3"), "measured (Villemus)"),
                            (le_m, (":", "C0"), "limit equilibrium"), (critical_m, ("-.", "C2"), "DEM failure")):
        if y is not None and np.isfinite(y):
            ax.axhline(y, ls=style[0], color=style[1], lw=1, label=f"{label} {y:.2f} m")
    ax.set_xlabel("crest displacement outward [mm] (rigid blocks: pre-failure values numerical)")
    ax.set_ylabel("water height h_w [m]")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(alpha=0.3)
    notes_box(fig, list(notes))
    fig.subplots_adjust(bottom=0.2)
    return save_figure(fig, path, tight=False)


def plot_drystone_mechanism(outlines_ref, outlines, velocities, path, *, water_height: float | None, title: str,
                            level_m: float | None = None, pivot=None, backfill_height: float | None = None,
                            notes: list[str] = ()) -> Path:
    """Blocks at failure: the last settled wall in grey, the wall at failure coloured by
    block speed, velocity arrows, the water level (case A) or the backfill height at the
    inner face (case B) and the mechanism (level, pivot)."""
    from matplotlib.collections import PolyCollection

    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    ax.add_collection(PolyCollection(outlines_ref, facecolors="none", edgecolors="0.75", linewidths=0.6))
    speed = np.hypot(*np.asarray(velocities).T) * 1e3
    pc = PolyCollection(outlines, array=speed, cmap="viridis", edgecolors="k", linewidths=0.4)
    ax.add_collection(pc)
    fig.colorbar(pc, ax=ax, shrink=0.7, label="block speed at failure [mm/s]")
    cents = np.array([np.mean(o, axis=0) for o in outlines])
    v = np.asarray(velocities)
    if np.abs(v).max() > 0:
        ax.quiver(cents[:, 0], cents[:, 1], v[:, 0], v[:, 1], color="C3", width=0.003)
    allpts = np.vstack(outlines)
    x0, x1 = allpts[:, 0].min(), allpts[:, 0].max()
    if water_height is not None:
        ax.plot([x1, x1 + 0.4], [water_height, water_height], color="C0", lw=2, label=f"water {water_height:.2f} m")
    if backfill_height is not None:
        ax.plot([x1, x1 + 0.4], [backfill_height, backfill_height], color="C5", lw=2,
                label=f"backfill at the inner face {backfill_height:.2f} m")
    if level_m is not None:
        ax.axhline(level_m, color="C1", ls="--", lw=1, label=f"mechanism level {level_m:.3f} m")
    if pivot is not None:
        ax.plot(*pivot, "x", color="C1", ms=10, label="pivot")
    ax.set_xlim(x0 - 0.3, x1 + 0.5)
    ax.set_ylim(allpts[:, 1].min() - 0.2, allpts[:, 1].max() + 0.2)
    ax.set_aspect("equal")
    ax.set_xlabel("x inward from the outer toe [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    notes_box(fig, list(notes))
    fig.subplots_adjust(bottom=0.15)
    return save_figure(fig, path, tight=False)


def plot_block_forces(outlines, forces, path, *, title: str, notes: list[str] = ()) -> Path:
    """Oetomo et al.'s Fig. 20: the fill's force on each block of the wall, (a) horizontal
    (toward the outside positive) and (b) vertical (downward positive) [kN/m], each block
    coloured by its own; blocks the fill does not touch in white."""
    from matplotlib.collections import PolyCollection

    f = np.asarray(forces, float).reshape(-1, 2) / 1e3
    polys = [np.asarray(o, float) for o in outlines]
    pts = np.vstack(polys)
    fig, axes = plt.subplots(1, 2, figsize=(10.5, 5.4), sharey=True)
    for ax, col, label in ((axes[0], 0, "(a) horizontal, outward [kN/m]"), (axes[1], 1, "(b) vertical, down [kN/m]")):
        values = f[:, col]
        touched = np.abs(f).sum(axis=1) > 0
        top = float(np.abs(values).max()) or 1.0
        ax.add_collection(PolyCollection([p for p, t in zip(polys, touched) if not t], facecolors="white",
                                         edgecolors="0.6", linewidths=0.5))
        pc = PolyCollection([p for p, t in zip(polys, touched) if t], array=values[touched], cmap="coolwarm",
                            clim=(-top, top), edgecolors="k", linewidths=0.5)
        ax.add_collection(pc)
        fig.colorbar(pc, ax=ax, shrink=0.75, label=label)
        ax.set_xlim(pts[:, 0].min() - 0.1, pts[:, 0].max() + 0.1)
        ax.set_ylim(pts[:, 1].min() - 0.1, pts[:, 1].max() + 0.1)
        ax.set_aspect("equal")
        ax.set_xlabel("x inward from the outer toe [m]")
        ax.set_title(label.split(" [")[0] + f"; {int(touched.sum())} of {len(polys)} blocks carry a fill force",
                     fontsize=9)
    axes[0].set_ylabel("y [m]")
    fig.suptitle(title, fontsize=10)
    notes_box(fig, list(notes))
    fig.subplots_adjust(bottom=0.18)
    return save_figure(fig, path, tight=False)
