"""Measurements on wall-movement records, shared by the 2D and 3D cases."""

from __future__ import annotations

import numpy as np


def steady_displacement(dis_over_H: np.ndarray, thrust: np.ndarray, fraction: float = 0.9,
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
    return float(dis_over_H[reached[0]])
