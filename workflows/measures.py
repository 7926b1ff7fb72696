"""Measurements on wall-movement records, shared by the 2D and 3D cases."""

from __future__ import annotations

import numpy as np


def steady_displacement(dis_over_H: np.ndarray, thrust: np.ndarray, fraction: float = 0.9,
                        smooth: int = 3) -> float:
    """Dis/H at which the thrust has completed ``fraction`` of its drop from the first to
    the final value and stays there: the first point after which the (running-mean
    smoothed) thrust never again rises above F_end + (1 - fraction)(F_0 - F_end),
    F_end = mean of the last 20 % of the readings. nan if it never drops."""
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
    above = np.nonzero(t > level)[0]
    if len(above) == 0:
        return float(dis_over_H[0])
    k = above[-1] + 1
    return float(dis_over_H[min(k, len(t) - 1)])
