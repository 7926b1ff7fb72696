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
          "ec7-annex-c": ("--", "C9"), "log-spiral": ("-", "olive"), "dsm": ("-", "k")}


def _finish(fig, path, tight: bool = True) -> Path:
    """Save at 130 dpi (folders made) and close; ``tight=False`` keeps a layout set by hand
    (room left for a notes box)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def plot_theory_profiles(rows, wall, path, *, dem=None, title: str | None = None) -> Path:
    """sigma_h(z) of every applicable method (kPa vs depth), optionally with DEM points
    ``dem = (z_m, sigma_Pa, label)``. Reconstructed profiles are marked in the legend."""
    fig, ax = plt.subplots(figsize=(6, 6.5))
    profiles = [getattr(r, "profile", r) for r in rows]
    profiles = [p for p in profiles if p is not None]
    shaded = next((p for p in profiles if "design" in p.extra or p.extra.get("thrust_q")), None)
    if shaded is not None:
        _shade_parts(ax, shaded)
    for p in profiles:
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


def _shade_parts(ax, p) -> None:
    """Shade one method's surcharge and water parts apart from its soil part (kPa). A
    design profile carries its parts; a linear method's uniform-surcharge part is its
    constant stress at the top (the weight part is zero there)."""
    d = p.extra.get("design")
    if d is not None:
        soil = d.sigma_soil / 1e3
        with_q = soil + (d.sigma_q + d.sigma_loads) / 1e3
        total = with_q + d.u / 1e3
        z = d.z
    else:
        soil = (p.sigma_h - p.sigma_h[0]) / 1e3
        with_q = total = p.sigma_h / 1e3
        z = p.z
    ax.fill_betweenx(z, 0, soil, color="0.85", label=f"soil part ({p.method})")
    if np.any(with_q > soil):
        ax.fill_betweenx(z, soil, with_q, color="gold", alpha=0.5, label=f"surcharge part ({p.method})")
    if np.any(total > with_q):
        ax.fill_betweenx(z, with_q, total, color="C0", alpha=0.25, label=f"water part ({p.method})")


# ----------------------------------------------------------------------------- dem2d
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
    return _finish(fig, path)


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
    return _finish(fig, path)


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
        ls, c = _STYLE.get(p.method, ("-", None))
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
    return _finish(fig, path)


def plot_biaxial(curves: dict, path, *, title: str = "") -> Path:
    """Khosravi et al. Fig. 4 style: deviatoric stress (sigma_1 - sigma_3) [kPa] and the
    mobilised friction angle against axial strain, one curve per test.
    ``curves``: label -> (eps_axial, sigma_1 [Pa], sigma_3 [Pa], eps_vol)."""
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for k, (label, (eps, s1, s3, ev)) in enumerate(curves.items()):
        eps, s1, s3 = map(np.asarray, (eps, s1, s3))
        c = f"C{k % 10}"
        axes[0].plot(eps * 100, (s1 - s3) / 1e3, color=c, lw=0.8, label=label)
        phi = np.degrees(np.arcsin(np.clip((s1 - s3) / (s1 + s3), -1, 1)))
        axes[1].plot(eps * 100, phi, color=c, lw=0.8, label=label)
        axes[2].plot(eps * 100, np.asarray(ev) * 100, color=c, lw=0.8, label=label)
    axes[0].set_ylabel("sigma_1 - sigma_3 [kPa]")
    axes[1].set_ylabel("mobilised phi [deg]")
    axes[2].set_ylabel("volumetric strain [%] (compression +)")
    for ax in axes:
        ax.set_xlabel("axial strain [%]")
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=7)
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def plot_series(x, ys: dict, path, *, xlabel: str, ylabel: str, title: str = "",
                logx: bool = False) -> Path:
    """A plain line plot of several series against one x (solver-settings figures)."""
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for k, (label, y) in enumerate(ys.items()):
        ax.plot(x if not isinstance(y, tuple) else y[0], y if not isinstance(y, tuple) else y[1],
                "o-", color=f"C{k % 10}", label=label)
    if logx:
        ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return _finish(fig, path)


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
    return _finish(fig, path)


def plot_dsm_modes(results: dict, presets: dict, path) -> Path:
    """Nadukuru & Michalowski Fig. 8: (a) k_l(d), (b) phi*(d)/phi, (c) wall stress
    sigma_n / (gamma H) against d/H for each mode; the paper's Table 3 centroids marked."""
    fig, axes = plt.subplots(1, 3, figsize=(12, 5), sharey=True)
    u = np.linspace(0, 1, 201)
    for (code, res), c in zip(results.items(), ("C0", "C1", "C2")):
        pre = presets[code]
        p = res.profile
        axes[0].plot([pre.k_wall(x) for x in u], u, color=c, label=pre.title)
        axes[1].plot([pre.phi_factor(x) for x in u], u, color=c, label=pre.title)
        gH = 2 * p.thrust_h / (p.Kh * p.H) if p.Kh else 1.0   # gamma H
        axes[2].plot(p.sigma_h / gH, p.z / p.H, color=c,
                     label=f"{pre.title}: K {p.K:.3f}, h/H {p.height_over_H:.3f} "
                           f"(paper {pre.paper_K:.3f}, {pre.paper_height:.3f})")
        axes[2].axhline(1 - p.height_over_H, color=c, lw=0.6, ls=":")
    axes[0].set_xlabel("k_l = sigma_n / sigma_z at the wall")
    axes[1].set_xlabel("mobilised phi* / phi")
    axes[2].set_xlabel("sigma_n / (gamma H)")
    axes[0].set_ylabel("d / H (depth)")
    for ax, t in zip(axes, ("(a)", "(b)", "(c)")):
        ax.set_ylim(1, 0)
        ax.grid(alpha=0.3)
        ax.set_title(t)
    axes[2].set_xlim(0, 0.5)
    axes[2].legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12))
    axes[0].legend(fontsize=8)
    fig.suptitle("Differential slice method (Nadukuru & Michalowski 2012, Fig. 8); dotted: resultant depth")
    return _finish(fig, path)


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
    return _finish(fig, path)


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
    return _finish(fig, path)


def plot_force_chains(frame, path, *, axes=(0, 2), title: str = "", max_lines: int = 40_000) -> Path:
    """Side view of a frame: grains as light discs, contacts above the mean normal force
    as lines whose width grows with the force (Nadukuru Fig. 3b, Khosravi Fig. 11).
    ``axes`` picks the two coordinates drawn (x, z for a wall along y)."""
    from matplotlib.collections import LineCollection

    i, j = axes
    pos = np.asarray(frame.positions)
    fig, ax = plt.subplots(figsize=(8, 6.5))
    ax.scatter(pos[:, i], pos[:, j], s=2, c="0.8", linewidths=0)
    f = np.asarray(frame.contact_force)
    if len(f):
        strong = np.nonzero(f > f.mean())[0]
        strong = strong[np.argsort(f[strong])][-max_lines:]
        a, b = np.asarray(frame.contact_a)[strong], np.asarray(frame.contact_b)[strong]
        segs = np.stack([a[:, [i, j]], b[:, [i, j]]], axis=1)
        w = 0.3 + 3.0 * f[strong] / f[strong].max()
        ax.add_collection(LineCollection(segs, linewidths=w, colors="firebrick", alpha=0.8))
    corners = getattr(frame, "panel_corners", None)
    if corners is not None and len(corners):
        for c in np.asarray(corners):
            pts = c[:, [i, j]] if c.shape[-1] > 2 else c
            ax.plot(pts[:, 0], pts[:, 1], color="navy", lw=2)
    ax.set_aspect("equal")
    lo, hi = pos[:, [i, j]].min(axis=0), pos[:, [i, j]].max(axis=0)
    ax.set_xlim(lo[0] - 0.05 * (hi[0] - lo[0]), hi[0] + 0.05 * (hi[0] - lo[0]))
    ax.set_ylim(lo[1] - 0.05 * (hi[1] - lo[1]), hi[1] + 0.05 * (hi[1] - lo[1]))
    ax.set_xlabel("x [m]" if i == 0 else "coordinate [m]")
    ax.set_ylabel("z [m]" if j == 2 else "y [m]")
    ax.set_title(title or "force chains: contacts above the mean normal force")
    return _finish(fig, path)


def plot_displacement_field(start, end, path, *, axes=(0, 2), cell: float = 0.2, magnify: float = 15.0,
                            title: str = "") -> Path:
    """Grain displacements from ``start`` to ``end`` (matching (n, 3) positions [m]) in a
    side view, averaged over the width in square cells of ``cell`` m and drawn ``magnify``
    times their length (Nadukuru & Michalowski Fig. 3a: 15x at 0.008 rad). Cells with
    fewer than 3 grains are left out; colour is the magnitude in mm."""
    i, j = axes
    p0, p1 = np.asarray(start), np.asarray(end)
    u = (p1 - p0)[:, [i, j]]
    xy = p0[:, [i, j]]
    lo = xy.min(axis=0)
    ij = np.floor((xy - lo) / cell).astype(int)
    shape = ij.max(axis=0) + 1
    flat = ij[:, 0] * shape[1] + ij[:, 1]
    count = np.bincount(flat, minlength=shape[0] * shape[1])
    keep = np.nonzero(count >= 3)[0]
    mean_u = np.stack([np.bincount(flat, weights=u[:, k], minlength=count.size)[keep] / count[keep]
                       for k in (0, 1)], axis=1)
    centre = lo + (np.stack([keep // shape[1], keep % shape[1]], axis=1) + 0.5) * cell
    mag_mm = 1e3 * np.hypot(mean_u[:, 0], mean_u[:, 1])
    fig, ax = plt.subplots(figsize=(8, 6.5))
    q = ax.quiver(centre[:, 0], centre[:, 1], magnify * mean_u[:, 0], magnify * mean_u[:, 1], mag_mm,
                  angles="xy", scale_units="xy", scale=1.0, cmap="viridis", width=0.003)
    fig.colorbar(q, ax=ax, label="mean displacement [mm]")
    ax.set_aspect("equal")
    hi = xy.max(axis=0)
    ax.set_xlim(lo[0] - 0.1, hi[0] + 0.1)
    ax.set_ylim(lo[1] - 0.1, hi[1] + 0.1)
    ax.set_xlabel("x [m]" if i == 0 else "coordinate [m]")
    ax.set_ylabel("z [m]" if j == 2 else "y [m]")
    ax.set_title(title or f"grain displacements (x{magnify:g}), mean per {cell:g} m cell")
    return _finish(fig, path)


def plot_wall_design(case, result, path) -> Path:
    """A wall design check to scale (analytic.design): the wall and the fill moving with
    it, the horizontal earth-pressure diagram on the back, every characteristic force as
    an arrow on its line of action, the design resultant and the base pressure
    distribution (kPa, drawn below the base) of the combination heading ``result``."""
    from analytic.design.actions import thrust_for, uses_virtual_back, wall_forces
    from analytic.design.checks import base_pressure

    wall, unit = case.wall, {"phi": 1.0, "c": 1.0, "cu": 1.0, "gamma": 1.0}
    blocks = wall.kind == "blocks"
    fig, ax = plt.subplots(figsize=(7, 7))
    parts = list(wall.parts())
    if not blocks and uses_virtual_back(case):
        parts += wall.fill_parts(case.backfill.beta, case.backfill.gamma)
    for p in parts:
        ax.fill(*zip(*p.polygon), color="0.7" if p.source == "structural" else "wheat", ec="k", lw=0.8)
    if blocks:
        from analytic.design.blocks import joint_forces
        forces = joint_forces(case, 0.0, unit)[0]
    else:
        from analytic.design.actions import passive_force
        forces = wall_forces(case, unit) + [f for f in [passive_force(case, unit)] if f is not None]
    _water_lines(ax, case)
    scale = 0.25 * wall.H / max([abs(f.Fh) + abs(f.Fv) for f in forces] + [1.0])
    if not blocks:
        _pressure_diagram(ax, thrust_for(case, unit), scale)
    else:
        for z in wall.joints():
            y_I = wall.above(z)[1]
            ax.plot([wall.x_o(z), wall.x_i(y_I)], [z, y_I], "k:", lw=0.6)
    for f in forces:
        ax.annotate("", (f.x, f.y), (f.x + f.Fh * scale, f.y + f.Fv * scale),
                    arrowprops=dict(arrowstyle="->", color="C3" if f.Fh else "C0", lw=1.2))
    lead = result.lead
    if not blocks and lead.V_d > 0 and abs(lead.e) < wall.B / 2:
        x, q = base_pressure(lead.V_d, lead.e, wall.B)
        qs = 0.15 * wall.H / max(q.max(), 1e-9)
        ax.fill_between(x, -q * qs - 0.05 * wall.H, -0.05 * wall.H, color="C2", alpha=0.4,
                        label=f"base pressure ({result.format}), max {q.max():.0f} kPa")
        x_R = wall.B / 2 - lead.e
        ax.annotate("", (x_R, 0.0), (x_R + lead.H_d * scale, lead.V_d * scale),
                    arrowprops=dict(arrowstyle="->", color="k", lw=1.6))
        ax.plot([x_R, x_R - lead.H_d * scale], [0.0, -lead.V_d * scale], "k--", lw=0.6)
    name, combo, u = result.governing
    ax.set_title(f"{wall.kind} wall, {result.format}: governing {name} ({combo}) {u:.3f}")
    ax.set_aspect("equal")
    ax.set_xlabel("x from the toe [m]")
    ax.set_ylabel("y above the base underside [m]")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left", fontsize=8)
    return _finish(fig, path)


def _water_lines(ax, case) -> None:
    """Free-water levels in front and behind the wall (blue lines)."""
    B = case.wall.B
    if case.water.front > 0:
        ax.plot([-0.3 * B, 0.0], [case.water.front] * 2, color="C9", lw=1.5, label="water in front")
    if case.water.behind > 0:
        ax.plot([B, 1.4 * B], [case.water.behind] * 2, color="C9", lw=1.5, label="water behind")


def _pressure_diagram(ax, thrust, scale) -> None:
    """Horizontal pressure of each thrust part drawn outward from the back it acts on
    (linear soil part, uniform surcharge part), with the resultant's line of action."""
    back = thrust.back
    y0, H = back.y0, back.height
    ys = np.linspace(y0, y0 + H, 41)
    xb = np.array([back.point_at(y)[0] for y in ys])
    for p in thrust.parts:
        if p.kind == "seismic" or p.P <= 0:
            continue
        depth = (y0 + H - ys) / H
        shape = 2 * depth if p.kind == "soil" else np.ones_like(ys)    # integrates to 1 over H
        w = p.Ph / H * shape * scale * H / 2
        ax.fill_betweenx(ys, xb, xb + w, color="C1" if p.kind == "soil" else "C4", alpha=0.3, label=p.name)
        ax.plot([p.x - p.Ph * scale, p.x], [p.y - p.Pv * scale, p.y], "C1--", lw=0.6)


def plot_sweep(groups: list[dict], keys: list[str], outputs: list[str], path, *, title: str = "") -> Path:
    """A sweep's outputs against its first varied key, one line per value of the other
    varied keys, the seed spread as error bars (+- one standard deviation, the range as
    thin bars). ``groups``: rows with the keys and ``<output>_mean``/``_sd``/``_min``/``_max``
    (studies.sweep.group_rows). Text values of the key are placed evenly."""
    x_key, series_keys = (keys[0], keys[1:]) if keys else (None, [])
    xs = [g[x_key] if x_key else "all" for g in groups]
    numeric = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in xs)
    ticks = list(dict.fromkeys(xs))
    cols = min(3, len(outputs))
    rows = -(-len(outputs) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False)
    for ax, name in zip(axes.flat, outputs):
        series: dict[tuple, list[dict]] = {}
        for g in groups:
            series.setdefault(tuple(g[k] for k in series_keys), []).append(g)
        for k, (label, members) in enumerate(series.items()):
            pts = [(g[x_key] if x_key else "all", g[f"{name}_mean"], g[f"{name}_sd"] or 0.0,
                    g[f"{name}_min"], g[f"{name}_max"]) for g in members if g[f"{name}_mean"] is not None]
            if not pts:
                continue
            x = np.array([p[0] if numeric else ticks.index(p[0]) for p in pts], dtype=float)
            mean, sd = np.array([p[1] for p in pts]), np.array([p[2] for p in pts])
            lo, hi = mean - np.array([p[3] for p in pts]), np.array([p[4] for p in pts]) - mean
            ax.errorbar(x, mean, yerr=[lo, hi], fmt="none", ecolor=f"C{k % 10}", elinewidth=0.6, alpha=0.5)
            ax.errorbar(x, mean, yerr=sd, fmt="o-" if numeric else "o", color=f"C{k % 10}", capsize=3,
                        label=" ".join(f"{s}={v}" for s, v in zip(series_keys, label)) or None)
        if not numeric:
            ax.set_xticks(range(len(ticks)), [str(t) for t in ticks])
        ax.set_xlabel(x_key or "")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
        if series_keys:
            ax.legend(fontsize=7)
    for ax in list(axes.flat)[len(outputs):]:
        ax.set_visible(False)
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def _notes_box(fig, notes: list[str]) -> None:
    """The assumptions under a figure, small."""
    if notes:
        fig.text(0.01, 0.005, "Assumed: " + "; ".join(notes), fontsize=6, wrap=True, va="bottom")


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
    _notes_box(fig, list(notes))
    fig.subplots_adjust(bottom=0.2)
    return _finish(fig, path, tight=False)


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
    _notes_box(fig, list(notes))
    fig.subplots_adjust(bottom=0.15)
    return _finish(fig, path, tight=False)


def plot_drystone_summary(rows: list[dict], path, *, title: str) -> Path:
    """Critical water height per wall: measured, DEM (with its band), limit equilibrium."""
    fig, ax = plt.subplots(figsize=(7, 4.2))
    x = np.arange(len(rows))
    meas = [r["measured_height_m"] for r in rows]
    dem = [r["critical_height_m"] if r["critical_height_m"] is not None else np.nan for r in rows]
    le = [r["limit_equilibrium_height_m"] for r in rows]
    lo = [r["band_m"][0] for r in rows]
    hi = [r["band_m"][1] for r in rows]
    ax.bar(x - 0.25, meas, 0.25, color="C3", label="measured")
    ax.bar(x, dem, 0.25, color="C2", label="DEM (default geometry)")
    ax.bar(x + 0.25, le, 0.25, color="C0", label="limit equilibrium")
    ax.vlines(x, lo, hi, color="k", lw=2, label="band (geometry, gamma_m, alpha)")
    ax.set_xticks(x, [r["wall"] for r in rows])
    ax.set_ylabel("critical water height [m]")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8)


def plot_seismic(N: float, readings, series: dict, profiles: dict, mo: dict, path, *,
                 settlement: dict | None = None, title: str = "") -> Path:
    """Sizkow & El Shamy's figures in one sheet, prototype units (model x N): the wall's
    deformed shape (Fig. 2), face pressures static / max / residual with Mononobe-Okabe
    active and passive (Fig. 3), thrust on both faces against time (Fig. 5), bending
    moment static / max / residual (Fig. 6) and the ground settlement (Fig. 8).
    ``readings``: measures.WallReading list (model units), the first static, the last
    residual; ``mo``: measures.mononobe_okabe_overlay."""
    fig, ax = plt.subplots(2, 3, figsize=(14, 8.5))
    r0, r1 = readings[0], readings[-1]
    z = r0.z * N
    x_ref = r0.x
    base = np.asarray(series["base_displacement_m"])
    for r, b, label, c in ((r0, base[0], "static (start of shaking)", "C0"), (r1, base[-1], "residual", "C3")):
        ax[0, 0].plot((-(r.x - x_ref) * N + b) * 1e3, z, "o-", ms=3, color=c, label=label)
    ax[0, 0].set_xlabel("wall displacement since the static state, relative to the base,\n"
                        "toward the excavation [mm]")
    ax[0, 0].set_ylabel("height above the base [m]")
    ax[0, 0].set_title("deformed shape (Fig. 2)")
    p = profiles
    for face, sign in (("front", -1), ("back", 1)):
        for kind, ls in (("static", "-"), ("max", "--"), ("residual", ":")):
            ax[0, 1].plot(sign * p[f"{face}_{kind}_kPa"], p["height_m"], ls, color="C0" if face == "back" else "C1",
                          label=f"{face} {kind}")
    top = float(z[-1] + 0.5 * (z[1] - z[0]))
    for key, sign, c in (("active_static", 1, "k"), ("active_MO", 1, "C3"), ("passive_static", -1, "0.5"),
                         ("passive_MO", -1, "C4")):
        prof = mo[key]
        ztop = top if sign > 0 else top - (mo["active_static"].H - prof.H)
        ax[0, 1].plot(sign * prof.sigma_h / 1e3, ztop - prof.z, "-", lw=0.8, color=c, label=f"{key} (theory)")
    ax[0, 1].set_xlabel("pressure on the face [kPa]: back (retained) +, front (excavated) -")
    ax[0, 1].set_title("lateral pressure (Fig. 3)")
    ax[0, 1].legend(fontsize=6)
    t = series["time_s"]
    ax[0, 2].plot(t, series["thrust_back_kN_per_m"], color="C0", label="back (active side)")
    ax[0, 2].plot(t, series["thrust_front_kN_per_m"], color="C1", label="front (passive side)")
    ax[0, 2].set_xlabel("time [s]")
    ax[0, 2].set_ylabel("thrust [kN/m]")
    ax[0, 2].set_title("total thrust on both faces (Fig. 5)")
    ax[0, 2].legend(fontsize=8)
    zc = r0.cut_z * N
    m_all = np.array([r.moment for r in readings]) * N * N / 1e3
    ax[1, 0].plot(m_all[0], zc, "-", label="static")
    ax[1, 0].plot(m_all[np.argmax(np.abs(m_all).max(axis=1))], zc, "--", label="at the largest moment")
    ax[1, 0].plot(m_all[-1], zc, ":", label="residual")
    ax[1, 0].set_xlabel("bending moment [kN m/m]")
    ax[1, 0].set_ylabel("height above the base [m]")
    ax[1, 0].set_title("bending moment (Fig. 6)")
    ax[1, 0].legend(fontsize=8)
    ax[1, 1].plot(t, series["base_displacement_m"] * 1e3, color="k", label="base")
    ax[1, 1].plot(t, series["top_displacement_m"] * 1e3, color="C3",
                  label="wall top relative to the base (toward excavation)")
    ax[1, 1].set_xlabel("time [s]")
    ax[1, 1].set_ylabel("displacement [mm]")
    ax[1, 1].legend(fontsize=8)
    if settlement is not None:
        ax[1, 2].plot(settlement["distance_m"], np.asarray(settlement["settlement_m"]) * 1e3, "o-", ms=3)
    ax[1, 2].set_xlabel("distance from the wall [m]")
    ax[1, 2].set_ylabel("settlement [mm]")
    ax[1, 2].set_title("ground settlement (Fig. 8)")
    for a in ax.ravel():
        a.grid(alpha=0.3)
    ax[0, 0].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


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
    return _finish(fig, path)


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
    return _finish(fig, path, tight=False)
