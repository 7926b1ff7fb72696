"""Line and strip loads on the backfill surface: horizontal stress on a rigid vertical wall
by elastic theory, as used in practice.

Both are Boussinesq's half-space solutions doubled for the unyielding wall (the image
load; Spangler 1938 and Terzaghi 1954 measured about twice the half-space value).
With x the distance of the load from the back of the wall, z the depth, H the height,
m = x / H and n = z / H:

* line load Q [N/m] (Terzaghi 1954, as tabulated in NAVFAC DM-7.02 and Das, Principles
  of Foundation Engineering):
    m > 0.4:   sigma_h = 4 Q / (pi H) * m^2 n / (m^2 + n^2)^2     (doubled Boussinesq)
    m <= 0.4:  sigma_h = 0.203 Q / H * n / (0.16 + n^2)^2         (Terzaghi's modification)
* strip load q [Pa] from x1 to x2 (doubled Boussinesq/Carothers; Das):
    sigma_h = 2 q / pi * (b - sin b cos 2a),  b = th2 - th1, a = (th1 + th2) / 2,
    th_i = atan(x_i / z) the angle of each edge from the vertical through the point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .inputs import require_number


@dataclass(frozen=True)
class LineLoad:
    """A line load parallel to the wall: Q [N/m] at x [m] behind the back of the wall."""

    Q: float
    x: float

    def __post_init__(self):
        object.__setattr__(self, "Q", require_number("line-load Q", self.Q, 0.0, None, lo_open=False, unit="N/m"))
        object.__setattr__(self, "x", require_number("line-load x", self.x, 0.0, None, lo_open=False, unit="m"))

    def sigma_h(self, z, H: float) -> np.ndarray:
        """Horizontal stress [Pa] on the wall at depths z [m] (module docstring)."""
        n = np.asarray(z, dtype=float) / H
        m = self.x / H
        if m <= 0.4:
            return 0.203 * self.Q / H * n / (0.16 + n * n) ** 2
        return 4 * self.Q / (math.pi * H) * m * m * n / (m * m + n * n) ** 2

    def resultant(self, H: float) -> float:
        """Closed-form integral over 0..H [N/m]: 0.203 Q (1/0.32 - 1/2.32) = 0.547 Q for
        m <= 0.4 (Terzaghi's 0.55 Q), 2 Q / (pi (1 + m^2)) otherwise (0.64 Q / (m^2 + 1))."""
        m = self.x / H
        if m <= 0.4:
            return 0.203 * self.Q * (1 / 0.32 - 1 / 2.32)
        return 2 * self.Q / (math.pi * (1 + m * m))


@dataclass(frozen=True)
class StripLoad:
    """A strip load parallel to the wall: q [Pa] from x1 to x2 [m] behind the wall, x1 < x2."""

    q: float
    x1: float
    x2: float

    def __post_init__(self):
        object.__setattr__(self, "q", require_number("strip-load q", self.q, 0.0, None, lo_open=False, unit="Pa"))
        object.__setattr__(self, "x1", require_number("strip-load x1", self.x1, 0.0, None, lo_open=False, unit="m"))
        object.__setattr__(self, "x2", require_number("strip-load x2", self.x2, self.x1, None, unit="m"))

    def sigma_h(self, z, H: float) -> np.ndarray:
        """Horizontal stress [Pa] on the wall at depths z [m] (module docstring)."""
        z = np.maximum(np.asarray(z, dtype=float), 1e-12 * H)
        th1, th2 = np.arctan(self.x1 / z), np.arctan(self.x2 / z)
        b, a = th2 - th1, 0.5 * (th1 + th2)
        return 2 * self.q / math.pi * (b - np.sin(b) * np.cos(2 * a))

    def resultant(self, H: float) -> float:
        """Jarquio (1981, J. Geotech. Eng. Div. ASCE 107(GT10)) as given by Das: P = q/90 H
        (th2 - th1) with th_i = atan(x_i / H) in degrees, i.e. 2 q H (th2 - th1) / pi in rad."""
        return 2 * self.q * H * (math.atan(self.x2 / H) - math.atan(self.x1 / H)) / math.pi
