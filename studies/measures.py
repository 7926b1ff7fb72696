"""Measurements on wall records, shared by the 2D and 3D studies: the thrust and its
height from panel stresses, the at-rest coefficient of a depth range, and the
displacement by which the thrust has settled. (3D panels also carry moments:
``nadukuru.model.wall_load`` takes the height from forces and moments.)"""

from __future__ import annotations

import numpy as np


def steady_displacement(wall_disp_over_H: np.ndarray, thrust: np.ndarray, fraction: float = 0.9,
                        smooth: int = 3) -> float:
    """Dis/H at which the (running-mean smoothed) thrust first completes ``fraction`` of
    its drop from the first to the final value: the first point at or below
    F_end + (1 - fraction)(F_0 - F_end), F_end = mean of the last 20 % of the readings;
    nan if it never drops. First reach, not "never again above": at reduced size the
    active load fluctuates by about 10 % of the drop (K +-0.015 at 2,400 spheres), and
    "never again above" then measured the last fluctuation, not the approach."""
    t = np.asarray(thrust, float)
    if smooth > 1 and len(t) >= smooth:
        k = np.ones(smooth) / smooth
        t = np.convolve(np.concatenate([np.full(smooth // 2, t[0]), t, np.full(smooth - 1 - smooth // 2, t[-1])]),
                        k, mode="valid")
    tail = max(1, len(t) // 5)
    f_end = float(np.mean(t[-tail:]))
    f0 = float(t[0])
    if f0 <= f_end:
        return float("nan")
    level = f_end + (1.0 - fraction) * (f0 - f_end)
    reached = np.nonzero(t <= level)[0]
    return float(wall_disp_over_H[reached[0]])


def normal_thrust(sigma: np.ndarray, depth: np.ndarray, panel_height: float) -> float:
    """Normal force on the wall below the surface [N/m]: sum sigma_i L_i over panels
    whose centre is below the surface (L = panel height)."""
    return float(np.sum(sigma[depth > 0]) * panel_height)


def k_upper_half(sigma: np.ndarray, depth: np.ndarray, panel_height: float, gamma: float,
                 H: float) -> float:
    """Lateral earth pressure coefficient of the upper half of the wall: the normal force
    on the panels with centres at 0 < z <= H/2, over the geostatic force on the same
    depth range, gamma (H/2)^2 / 2 (a force-weighted mean of sigma_h / (gamma z))."""
    up = (depth > 0) & (depth <= H / 2)
    lo_edge = np.clip(depth[up] - panel_height / 2, 0.0, None)
    hi_edge = depth[up] + panel_height / 2
    geo = gamma * np.sum(hi_edge**2 - lo_edge**2) / 2.0
    return float(np.sum(sigma[up]) * panel_height / geo)


def resultant_height_over_H(sigma: np.ndarray, depth: np.ndarray, panel_height: float, H: float) -> float:
    """Height of the resultant of the normal stresses above the base over H [-]: the
    moment about the base of sigma_i L over the panels below the surface, each force at
    its panel centre (a 2D panel reports a force, no moment), over the thrust."""
    below = depth > 0
    F = np.sum(sigma[below])
    return float(np.sum(sigma[below] * (H - depth[below])) / max(F, 1e-12)) / H


def dem_profile(depth: np.ndarray, sigma: np.ndarray, tau: np.ndarray, panel_height: float, H: float,
                gamma: float, height: float | None = None, source: str = "DEM panel readings"):
    """The DEM wall load as the record every theory returns (``analytic.Profile``), so
    one comparison path serves both: sigma_h and tau at the panel centres below the
    surface [Pa], thrust = the normal force sum sigma_i L [N/m] (vertical wall: thrust_h
    the same), K = Kh = 2 thrust / (gamma H^2), and the resultant's height [m] (given,
    e.g. from panel moments in 3D, or from the panel centres)."""
    from analytic.profile import Profile

    below = depth > 0
    order = np.argsort(depth[below])
    F = normal_thrust(sigma, depth, panel_height)
    h = resultant_height_over_H(sigma, depth, panel_height, H) * H if height is None else height
    K = 2.0 * F / (gamma * H**2)
    return Profile("dem", depth[below][order], sigma[below][order], tau[below][order], F, F, h, K, K, H,
                   source=source, status="measured")


def max_shear_strain_field(x_ref: np.ndarray, x_cur: np.ndarray, cell: float, axes: tuple[int, int] = (0, 2),
                           radius: float | None = None, min_grains: int = 6):
    """Maximum shear strain of a granular mass between two states, on a square grid in
    the plane of ``axes`` (for a thin 3D slab the third axis is averaged out).

    At every grid node the displacement of the grains whose reference position lies
    within ``radius`` (default: ``cell``) is fitted by an affine map x = c + F X (least
    squares, the best-fit deformation gradient of Cundall & Strack's measurement
    circles); from F the Green-Lagrange strain E = (F^T F - I) / 2, which a rigid
    rotation leaves at zero, and the maximum shear strain gamma_max = E1 - E2 =
    sqrt((E11 - E22)^2 + 4 E12^2) (engineering shear, dimensionless). Nodes with fewer
    than ``min_grains`` grains (outside the mass) are NaN.

    x_ref, x_cur: (n, d) positions [m]; cell: grid spacing [m]. Returns (u, v, gamma):
    node coordinates along the two axes [m] and gamma of shape (len(v), len(u))."""
    from scipy.spatial import cKDTree

    a, b = axes
    X = np.asarray(x_ref, float)[:, [a, b]]
    Y = np.asarray(x_cur, float)[:, [a, b]]
    r = cell if radius is None else radius
    lo, hi = X.min(axis=0), X.max(axis=0)
    u = np.arange(lo[0], hi[0] + 0.5 * cell, cell)
    v = np.arange(lo[1], hi[1] + 0.5 * cell, cell)
    nodes = np.stack(np.meshgrid(u, v), axis=-1).reshape(-1, 2)
    near = cKDTree(X).query_ball_point(nodes, r)
    count = np.fromiter((len(k) for k in near), np.int64, len(near))
    node = np.repeat(np.arange(len(nodes)), count)
    grain = np.fromiter((g for k in near for g in k), np.int64, int(count.sum()))
    # centred sums per node: F = (sum dY dX^T)(sum dX dX^T)^-1
    n = np.maximum(count, 1)[:, None]
    Xm = np.zeros((len(nodes), 2))
    Ym = np.zeros((len(nodes), 2))
    np.add.at(Xm, node, X[grain])
    np.add.at(Ym, node, Y[grain])
    Xm, Ym = Xm / n, Ym / n
    dX = X[grain] - Xm[node]
    dY = Y[grain] - Ym[node]
    Sxx = np.zeros((len(nodes), 2, 2))
    Syx = np.zeros((len(nodes), 2, 2))
    np.add.at(Sxx, node, dX[:, :, None] * dX[:, None, :])
    np.add.at(Syx, node, dY[:, :, None] * dX[:, None, :])
    det = Sxx[:, 0, 0] * Sxx[:, 1, 1] - Sxx[:, 0, 1] ** 2
    ok = (count >= min_grains) & (det > 1e-12 * np.maximum(Sxx[:, 0, 0] + Sxx[:, 1, 1], 1e-300) ** 2)
    gamma = np.full(len(nodes), np.nan)
    F = np.einsum("nij,njk->nik", Syx[ok], np.linalg.inv(Sxx[ok]))
    E = 0.5 * (np.einsum("nji,njk->nik", F, F) - np.eye(2))
    gamma[ok] = np.sqrt((E[:, 0, 0] - E[:, 1, 1]) ** 2 + 4.0 * E[:, 0, 1] ** 2)
    return u, v, gamma.reshape(len(v), len(u))
