"""Sizkow & El Shamy's figures: thrusts, displacements, moments and passive K against
time (Figs. 2-6), K against rotation, and the maximum shear strain field."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from viz.figures import plt, save_figure


def plot_seismic(N: float, readings, series: dict, profiles: dict, mo: dict, path, *,
                 settlement: dict | None = None, title: str = "") -> Path:
    """Sizkow & El Shamy's figures in one sheet, prototype units (model x N): the wall's
    deformed shape (Fig. 2), face pressures static / max / residual with Mononobe-Okabe
    active and passive (Fig. 3), thrust on both faces against time (Fig. 5), bending
    moment static / max / residual (Fig. 6) and the ground settlement (Fig. 8).
    ``readings``: measures.WallReading list (model units), the first static, the last
    residual; ``mo``: measures.mononobe_okabe_overlay."""
    fig, ax = plt.subplots(2, 3, figsize=(14, 8.5))
    z = _deformed_shape(ax[0, 0], N, readings, series)
    _face_pressures(ax[0, 1], profiles, mo, z)
    t = series["time_s"]
    _thrusts(ax[0, 2], t, series)
    _moments(ax[1, 0], N, readings)
    _displacements(ax[1, 1], t, series)
    _settlement(ax[1, 2], settlement)
    for a in ax.ravel():
        a.grid(alpha=0.3)
    ax[0, 0].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return save_figure(fig, path)


def _deformed_shape(ax, N: float, readings, series: dict) -> np.ndarray:
    """Fig. 2: the wall static and residual; returns the readings' heights [m, prototype]."""
    r0, r1 = readings[0], readings[-1]
    z = r0.z * N
    x_ref = r0.x
    base = np.asarray(series["base_displacement_m"])
    for r, b, label, c in ((r0, base[0], "static (start of shaking)", "C0"), (r1, base[-1], "residual", "C3")):
        ax.plot((-(r.x - x_ref) * N + b) * 1e3, z, "o-", ms=3, color=c, label=label)
    ax.set_xlabel("wall displacement since the static state, relative to the base,\n"
                  "toward the excavation [mm]")
    ax.set_ylabel("height above the base [m]")
    ax.set_title("deformed shape (Fig. 2)")
    return z


def _face_pressures(ax, p: dict, mo: dict, z: np.ndarray) -> None:
    """Fig. 3: both faces static / max / residual, with Mononobe-Okabe active and passive."""
    for face, sign in (("front", -1), ("back", 1)):
        for kind, ls in (("static", "-"), ("max", "--"), ("residual", ":")):
            ax.plot(sign * p[f"{face}_{kind}_kPa"], p["height_m"], ls, color="C0" if face == "back" else "C1",
                    label=f"{face} {kind}")
    top = float(z[-1] + 0.5 * (z[1] - z[0]))
    for key, sign, c in (("active_static", 1, "k"), ("active_MO", 1, "C3"), ("passive_static", -1, "0.5"),
                         ("passive_MO", -1, "C4")):
        prof = mo[key]
        ztop = top if sign > 0 else top - (mo["active_static"].H - prof.H)
        ax.plot(sign * prof.sigma_h / 1e3, ztop - prof.z, "-", lw=0.8, color=c, label=f"{key} (theory)")
    ax.set_xlabel("pressure on the face [kPa]: back (retained) +, front (excavated) -")
    ax.set_title("lateral pressure (Fig. 3)")
    ax.legend(fontsize=6)


def _thrusts(ax, t, series: dict) -> None:
    """Fig. 5: the thrust on both faces against time."""
    ax.plot(t, series["thrust_back_kN_per_m"], color="C0", label="back (active side)")
    ax.plot(t, series["thrust_front_kN_per_m"], color="C1", label="front (passive side)")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("thrust [kN/m]")
    ax.set_title("total thrust on both faces (Fig. 5)")
    ax.legend(fontsize=8)


def _moments(ax, N: float, readings) -> None:
    """Fig. 6: the bending moment static, at its largest and residual."""
    zc = readings[0].cut_z * N
    m_all = np.array([r.moment for r in readings]) * N * N / 1e3
    ax.plot(m_all[0], zc, "-", label="static")
    ax.plot(m_all[np.argmax(np.abs(m_all).max(axis=1))], zc, "--", label="at the largest moment")
    ax.plot(m_all[-1], zc, ":", label="residual")
    ax.set_xlabel("bending moment [kN m/m]")
    ax.set_ylabel("height above the base [m]")
    ax.set_title("bending moment (Fig. 6)")
    ax.legend(fontsize=8)


def _displacements(ax, t, series: dict) -> None:
    """The base and the wall top (relative to the base) against time."""
    ax.plot(t, series["base_displacement_m"] * 1e3, color="k", label="base")
    ax.plot(t, series["top_displacement_m"] * 1e3, color="C3",
            label="wall top relative to the base (toward excavation)")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("displacement [mm]")
    ax.legend(fontsize=8)


def _settlement(ax, settlement: dict | None) -> None:
    """Fig. 8: the ground settlement against the distance from the wall."""
    if settlement is not None:
        ax.plot(settlement["distance_m"], np.asarray(settlement["settlement_m"]) * 1e3, "o-", ms=3)
    ax.set_xlabel("distance from the wall [m]")
    ax.set_ylabel("settlement [mm]")
    ax.set_title("ground settlement (Fig. 8)")


def plot_seismic_K_rotation(rotation_deg, K, K_mean, path, *, K_p: dict | None = None, title: str = "",
                            note: str = "") -> Path:
    """Sizkow & El Shamy's Fig. 4: the earth-pressure coefficient sigma_h / (gamma z) on
    the front (passive) face 1.5 m (prototype) below the dredge line against the wall's
    rotation [deg] over the whole record, each reading and its mean over one period of the
    base motion; ``K_p``: {label: K} horizontal lines (e.g. Coulomb / M-O passive)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    ax.plot(rotation_deg, K, "-", lw=0.6, color="0.6", label="each reading (dynamic)")
    ax.plot(rotation_deg, K_mean, "-", lw=1.4, color="C1", label="mean over one period of the base motion")
    ax.plot(rotation_deg[:1], K[:1], "o", color="C0", label="start of shaking (static)")
    ax.plot(rotation_deg[-1:], K[-1:], "s", color="C3", label="end (residual)")
    for (label, value), ls in zip((K_p or {}).items(), ("--", ":", "-.")):
        ax.axhline(value, ls=ls, color="k", lw=0.9, label=label)
    ax.set_xlabel("wall rotation toward the excavation [deg]")
    ax.set_ylabel("K = sigma_h / (gamma z) on the front face")
    ax.set_title(title or "K 1.5 m below the dredge line vs wall rotation (Fig. 4)", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    if note:
        fig.text(0.01, 0.01, note, fontsize=6, va="bottom")
    return save_figure(fig, path)


def plot_seismic_strain(x_edges, z_edges, fields: list, path, *, wall: tuple, ground: tuple, title: str = "",
                        note: str = "") -> Path:
    """Sizkow & El Shamy's Fig. 7: maximum shear strain [%] in the x-z plane at the
    snapshot times, one panel each, one colour scale. ``fields``: [(time [s], (nx, nz)
    gamma_max)]; ``wall``: (x_front, x_back, z_toe, z_top) [m]; ``ground``: (z_front,
    z_back) surfaces [m]; all in prototype units."""
    k = max(1, len(fields))
    cols = min(k, 2)
    rows = (k + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5.5 * cols + 1.0, 2.6 * rows + 0.8), squeeze=False)
    finite = [g[np.isfinite(g)] for _, g in fields]
    vals = np.concatenate(finite) if finite else np.array([])
    vmax = float(np.percentile(vals, 99)) * 100 if len(vals) else 1.0
    mesh = None
    for a, (t, g) in zip(axes.ravel(), fields):
        mesh = a.pcolormesh(x_edges, z_edges, np.ma.masked_invalid(g.T * 100), cmap="viridis", vmin=0.0,
                            vmax=vmax if vmax > 0 else 1.0)
        x0, x1, zt, zw = wall
        a.fill_between([x0, x1], zt, zw, color="k")
        a.plot([x_edges[0], x0], [ground[0]] * 2, "k-", lw=0.8)
        a.plot([x1, x_edges[-1]], [ground[1]] * 2, "k-", lw=0.8)
        a.set_title(f"{t:.2f} s", fontsize=9)
        a.set_aspect("equal")
        a.set_xlabel("x from the wall's front face [m]")
        a.set_ylabel("height [m]")
    for a in axes.ravel()[len(fields):]:
        a.set_visible(False)
    if mesh is not None:
        fig.colorbar(mesh, ax=axes.ravel().tolist(), label="maximum shear strain [%]", shrink=0.8)
    fig.suptitle(title or "maximum shear strain (Fig. 7)", fontsize=10)
    if note:
        fig.text(0.01, 0.005, note, fontsize=6, va="bottom")
    return save_figure(fig, path, tight=False)


def _by_frequency(tables: dict, fig_title: str, draw, path, *, sharey: bool = True) -> Path:
    """One panel per frequency (prototype Hz -> table), drawn by ``draw(ax, table)``."""
    freqs = sorted(tables)
    fig, axes = plt.subplots(1, len(freqs), figsize=(3.2 * len(freqs) + 0.6, 4.2), squeeze=False, sharey=sharey)
    for a, f in zip(axes[0], freqs):
        draw(a, tables[f])
        a.set_title(f"{f:g} Hz", fontsize=9)
        a.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=6)
    fig.suptitle(fig_title, fontsize=10)
    return save_figure(fig, path)


def plot_pressures_by_frequency(profiles: dict, path) -> Path:
    """Sizkow & El Shamy's Fig. 3 for every frequency: static, maximum and residual
    pressure on both faces [kPa, prototype] against height above the base [m]
    (``profiles``: Hz -> pressure_profiles.csv columns)."""
    return _by_frequency(profiles, "lateral pressure on both faces: back +, front - (Fig. 3)",
                         lambda ax, p: _face_pressures_only(ax, p), path)


def _face_pressures_only(ax, p: dict) -> None:
    for face, sign, c in (("back", 1, "C0"), ("front", -1, "C1")):
        for kind, ls in (("static", "-"), ("max", "--"), ("residual", ":")):
            ax.plot(sign * np.asarray(p[f"{face}_{kind}_kPa"]), p["height_m"], ls, color=c, label=f"{face} {kind}")
    ax.set_xlabel("pressure [kPa]")
    ax.set_ylabel("height above the base [m]")


def plot_thrusts_by_frequency(series: dict, path) -> Path:
    """Sizkow & El Shamy's Fig. 5 for every frequency: thrust on both faces [kN/m] against
    time since the base started to move [s] (``series``: Hz -> series.csv columns)."""
    def draw(ax, s):
        ax.plot(s["time_s"], s["thrust_back_kN_per_m"], color="C0", lw=0.8, label="back (active side)")
        ax.plot(s["time_s"], s["thrust_front_kN_per_m"], color="C1", lw=0.8, label="front (passive side)")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("thrust [kN/m]")
    return _by_frequency(series, "total soil thrust on both faces (Fig. 5)", draw, path)


def plot_K_rotation_by_frequency(series: dict, path, *, K_p: dict | None = None) -> Path:
    """Sizkow & El Shamy's Fig. 4 (3-6 Hz in the paper): K on the front face 1.5 m below
    the dredge line, each reading and its mean over one period, against the wall's
    rotation [deg]; ``K_p``: {label: K} lines."""
    def draw(ax, s):
        ax.plot(s["rotation_deg"], s["passive_K_at_1_5m"], lw=0.5, color="0.6", label="each reading")
        ax.plot(s["rotation_deg"], s["passive_K_period_mean_at_1_5m"], lw=1.3, color="C1",
                label="mean over one period")
        for (label, value), ls in zip((K_p or {}).items(), ("--", ":")):
            ax.axhline(value, ls=ls, color="k", lw=0.9, label=label)
        ax.set_xlabel("wall rotation [deg]")
        ax.set_ylabel("K on the front face")
    return _by_frequency(series, "K 1.5 m below the dredge line vs wall rotation (Fig. 4)", draw, path)


def plot_settlement_by_frequency(settlements: dict, path) -> Path:
    """Sizkow & El Shamy's Fig. 8: ground settlement [mm] against distance from the wall
    [m], every frequency on one axes (``settlements``: Hz -> settlement.csv columns)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for f in sorted(settlements):
        s = settlements[f]
        ax.plot(s["distance_m"], np.asarray(s["settlement_m"]) * 1e3, "o-", ms=3, label=f"{f:g} Hz")
    ax.axvline(8.0, color="k", lw=0.8, ls=":", label="8 m (the paper: ~0 beyond)")
    ax.set_xlabel("distance from the wall [m]")
    ax.set_ylabel("settlement [mm]")
    ax.set_title("ground settlement behind the wall (Fig. 8)")
    ax.invert_yaxis()
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, path)
