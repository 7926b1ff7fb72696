"""The load of a backfill on its wall, from a frame: the normal
force, its height above the base (from the panel forces and moments), the downward
shear and the stress on each segment (``wall_load``), and the load coefficient of
Nadukuru & Michalowski's eq. 6 (``load_coefficient``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.constants import G

from .recipe import SpecimenRecipe
from .wall import WallSetup


@dataclass(frozen=True)
class WallLoad:
    normal: float          # normal force on the wall [N] (compression +)
    height: float          # height of its line of action above the base [m]
    shear: float           # force along the wall, + downward on the wall [N]
    segment_stress: np.ndarray   # (segments,) normal stress [Pa], bottom to top


def wall_load(frame, ids: np.ndarray, H: float, base=None) -> WallLoad:
    """Resultant of the panel loads of the retaining wall: normal force, its height above
    the wall base (from the panel forces *and* moments, so not limited to segment
    centres), downward shear, and the stress on each segment (bottom to top)."""
    F = frame.panel_force[ids]
    M = frame.panel_moment[ids]
    n = frame.panel_normal[ids]
    c = frame.panel_corners[ids].mean(axis=1)
    normal_k = -np.einsum("pd,pd->p", F, n)          # compression on each panel
    N = float(normal_k.sum())
    corners = frame.panel_corners[ids]
    if base is None:
        base = 0.5 * (corners[0, 0] + corners[0, 1])    # middle of the bottom edge
    up = corners[0, 3] - corners[0, 0]
    up = up / np.linalg.norm(up)
    axis = np.cross(up, n[0])
    # moment about the base edge of the soil's push (-F is the wall's reaction; use the
    # push F and its panel moments M consistently): height = (arm x (-F) + (-M)) . axis / N
    mom = float(np.sum((np.cross(c - base, -F) - M) @ axis))
    height = mom / N if N != 0 else float("nan")
    shear = float(-np.sum(F @ up))                     # + when the soil drags the wall down
    sigma = normal_k / frame.panel_area[ids]
    return WallLoad(N, height, shear, sigma)


def load_coefficient(normal_force: float, porosity: float, rec: SpecimenRecipe, wall: WallSetup) -> float:
    """Eq. 6: K = F / (0.5 rho (1 - n) g H^2 w)."""
    return normal_force / (0.5 * rec.density * (1.0 - porosity) * G * wall.height**2 * wall.width)
