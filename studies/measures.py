"""Measurements on wall records, shared by the 2D and 3D studies: the thrust and its
height from panel stresses, the at-rest coefficient of a depth range, and the
displacement by which the thrust has settled. (3D panels also carry moments:
``granular.load.wall_load`` takes the height from forces and moments.)"""

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


def displacement_parallelism(start: np.ndarray, end: np.ndarray, *, axes=(0, 2),
                             moving_fraction: float = 0.25) -> dict:
    """How nearly parallel the grain displacements of the moving region are, in the plane
    of ``axes`` (x, z: the side view). Nadukuru & Michalowski (2012, text of Fig. 3): in
    translation and rotation about the base "all displacement vectors tend to be
    parallel", inclined along a failure plane; in rotation about the top the field is
    curved.

    The moving region: grains whose in-plane displacement is at least
    ``moving_fraction`` of the 99th percentile of all (the percentile, not the maximum,
    so one thrown grain does not set it). Returns moving_grains, resultant_length R =
    |mean of their unit displacement vectors| (1: all parallel, 0: no common direction:
    the mean resultant length of directional statistics), spread_deg, the circular
    standard deviation sqrt(-2 ln R) of their directions [deg] (Mardia & Jupp 2000,
    eq. 2.3.11; 0 when parallel), and inclination_deg, the direction of that mean below
    the horizontal [deg] (positive: downward)."""
    i, j = axes
    u = (np.asarray(end, float) - np.asarray(start, float))[:, [i, j]]
    size = np.hypot(u[:, 0], u[:, 1])
    moving = size >= moving_fraction * np.percentile(size, 99.0)
    moving &= size > 0.0
    e = u[moving] / size[moving, None]
    mean = e.mean(axis=0) if len(e) else np.zeros(2)
    r = float(min(np.hypot(*mean), 1.0))           # 1 + an ulp for a parallel field
    spread = float(np.degrees(np.sqrt(-2.0 * np.log(r)))) if r > 0.0 else float("inf")
    return {"moving_grains": int(moving.sum()), "resultant_length": r, "spread_deg": spread,
            "inclination_deg": float(np.degrees(np.arctan2(-mean[1], abs(mean[0]))))}


def profile_nonlinearity(stress: np.ndarray) -> float:
    """How far a wall's stress profile is from a straight line: the root-mean-square
    residual of the least-squares line through the segment stresses (against the
    segments' centre heights, segments of equal height), over the mean stress [-].
    0 for any linear profile (a Rankine triangle or an at-rest trapezium); the order
    of ``stress`` (top-down or bottom-up) does not change it."""
    s = np.asarray(stress, float)
    z = (np.arange(len(s)) + 0.5) / len(s)
    fit = np.polyval(np.polyfit(z, s, 1), z)
    return float(np.sqrt(np.mean((s - fit) ** 2)) / np.mean(s))
