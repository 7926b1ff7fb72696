"""Static report figures (matplotlib, Agg backend): PNGs for run folders and the
validation reports. Each function takes plain results and a path, draws one figure in
the style of the paper figure it mirrors, and returns the path."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

THEORY_STYLE = {"rankine": ("-", "C0"), "coulomb": ("--", "C1"), "jaky": (":", "C2"),
          "mononobe-okabe": ("-.", "C3"), "seed-whitman": ("-.", "C4"), "handy": ("-", "C5"),
          "paik-salgado": ("-", "C6"), "khosravi": ("--", "C7"), "janssen": (":", "C8"),
          "ec7-annex-c": ("--", "C9"), "log-spiral": ("-", "olive"), "dsm": ("-", "k")}


def save_figure(fig, path, tight: bool = True) -> Path:
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
        ls, c = THEORY_STYLE.get(p.method, ("-", None))
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
    return save_figure(fig, path)


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


def plot_shear_test(curves: dict, path, *, title: str = "") -> Path:
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
    return save_figure(fig, path)


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
    return save_figure(fig, path)


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
    return save_figure(fig, path)


def plot_force_chains(frame, path, *, axes=(0, 2), title: str = "", max_lines: int = 40_000,
                      window=None, above: float = 1.0) -> Path:
    """Side view of a frame: grains as light discs, contacts above the mean normal force
    as lines whose width grows with the force (Nadukuru Fig. 3b, Khosravi Fig. 11).
    ``axes`` picks the two coordinates drawn (x, z for a wall along y); ``window``
    ((lo, hi) of the first, (lo, hi) of the second) [m] draws only that part, the mean
    force still of the whole frame; ``above``: contacts above this multiple of that mean."""
    from matplotlib.collections import LineCollection

    i, j = axes
    pos = np.asarray(frame.positions)
    fig, ax = plt.subplots(figsize=(8, 6.5))
    if window is not None and pos.shape[1] == 2:       # a close-up of disks: each at its size
        from matplotlib.collections import EllipseCollection
        d = 2.0 * np.asarray(frame.radii)
        ax.add_collection(EllipseCollection(d, d, np.zeros(len(d)), units="xy", offsets=pos[:, [i, j]],
                                            offset_transform=ax.transData, facecolors="0.85", edgecolors="0.6",
                                            linewidths=0.2))
    else:
        ax.scatter(pos[:, i], pos[:, j], s=2, c="0.8", linewidths=0)
    f = np.asarray(frame.contact_force)
    if len(f):
        strong = np.nonzero(f > above * f.mean())[0]
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
    if window is not None:
        ax.set_xlim(*window[0])
        ax.set_ylim(*window[1])
    else:
        lo, hi = pos[:, [i, j]].min(axis=0), pos[:, [i, j]].max(axis=0)
        ax.set_xlim(lo[0] - 0.05 * (hi[0] - lo[0]), hi[0] + 0.05 * (hi[0] - lo[0]))
        ax.set_ylim(lo[1] - 0.05 * (hi[1] - lo[1]), hi[1] + 0.05 * (hi[1] - lo[1]))
    ax.set_xlabel("x [m]" if i == 0 else "coordinate [m]")
    ax.set_ylabel("z [m]" if j == 2 else "y [m]")
    ax.set_title(title or "force chains: contacts above the mean normal force")
    return save_figure(fig, path)


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
    return save_figure(fig, path)


def plot_cell_map(centres, values, path, *, cell: float, label: str, lines=(), title: str = "") -> Path:
    """A value per square cell (``centres`` (k,2) [m], ``values`` (k,)) drawn as squares
    of side ``cell`` [m], coloured by value (colour bar ``label``); ``lines``: straight
    lines to draw over the map, each ((x, y) a point [m], angle from the x axis [deg],
    legend label)."""
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Rectangle
    c, v = np.asarray(centres, float), np.asarray(values, float)
    fig, ax = plt.subplots(figsize=(5, 8))
    squares = PatchCollection([Rectangle((x - cell / 2, y - cell / 2), cell, cell) for x, y in c], cmap="magma")
    squares.set_array(v)
    ax.add_collection(squares)
    fig.colorbar(squares, ax=ax, label=label)
    lo, hi = c.min(axis=0) - cell, c.max(axis=0) + cell
    for (x0, y0), angle, text in lines:
        t = np.radians(angle)
        s = np.linspace(-2.0, 2.0, 2) * float(np.hypot(*(hi - lo)))
        ax.plot(x0 + s * np.cos(t), y0 + s * np.sin(t), "c--", lw=1.5, label=text)
    if lines:
        ax.legend(loc="upper right", fontsize=8)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title)
    return save_figure(fig, path)


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
    return save_figure(fig, path)


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
    return save_figure(fig, path)


def notes_box(fig, notes: list[str]) -> None:
    """The assumptions under a figure, small."""
    if notes:
        fig.text(0.01, 0.005, "Assumed: " + "; ".join(notes), fontsize=6, wrap=True, va="bottom")


