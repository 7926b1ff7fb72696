"""Grain-size distributions for disk assemblies.

A grading is given the way a soil report gives it: the median diameter D50 and the
uniformity coefficient Cu = D60 / D10, both *by mass* (sieve passing). In 2D the
mass of a disk is proportional to its area, d^2.

Khosravi et al.'s Fig. 1 (D50 = 1.16 mm, Cu = 1.55) is only available as a picture we
could not read, so the shape of the curve is an assumption: passing by mass is linear
in d between d_min and d_max (the "uniform" gradings PFC users generate). Then

    P(d) = (d - d_min) / (d_max - d_min),   D50 = (d_min + d_max) / 2,
    Cu = (d_min + 0.6 w) / (d_min + 0.1 w),  w = d_max - d_min,

which gives d_min = D50 / (1 + k/2), w = k d_min with k = (Cu - 1) / (0.6 - 0.1 Cu).
For D50 = 1.16 mm, Cu = 1.55: d_min = 0.717 mm, d_max = 1.603 mm.
Number density follows from the mass density: n(d) ~ P'(d) / d^2 ~ d^-2, sampled by
inverting its cumulative distribution.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.errors import InvalidParameter


@dataclass(frozen=True)
class Grading:
    """Linear-by-mass grading fixed by D50 [m] and Cu = D60/D10 [-] (module docstring)."""

    d50: float
    cu: float

    def __post_init__(self):
        if not (self.d50 > 0 and np.isfinite(self.d50)):
            raise InvalidParameter("d50", self.d50, "> 0 m")
        # Cu = 1 is a single size; Cu >= 6 has no linear-by-mass curve (d_min -> 0)
        if not (1.0 <= self.cu < 6.0):
            raise InvalidParameter("cu", self.cu, "[1, 6)", "linear-by-mass grading")

    @property
    def _k(self) -> float:
        return (self.cu - 1.0) / (0.6 - 0.1 * self.cu)

    @property
    def d_min(self) -> float:
        """Smallest diameter [m]."""
        return self.d50 / (1.0 + self._k / 2.0)

    @property
    def d_max(self) -> float:
        """Largest diameter [m]."""
        return self.d_min * (1.0 + self._k)

    def passing(self, d) -> np.ndarray:
        """Fraction by mass finer than d [-]."""
        d = np.asarray(d, dtype=float)
        if self.d_max == self.d_min:
            return (d >= self.d50).astype(float)
        return np.clip((d - self.d_min) / (self.d_max - self.d_min), 0.0, 1.0)

    def mean_area(self) -> float:
        """Expected disk area [m^2] under the number density n(d) ~ d^-2:
        E[pi d^2/4] = pi/4 * d_min d_max (exact for this density)."""
        return np.pi / 4.0 * self.d_min * self.d_max

    def sample(self, n: int, rng: np.random.Generator) -> np.ndarray:
        """``n`` diameters [m] drawn by number from n(d) ~ d^-2 on [d_min, d_max]
        (inverse CDF: 1/d = 1/d_min - u (1/d_min - 1/d_max))."""
        if self.d_max == self.d_min:
            return np.full(n, self.d50)
        u = rng.random(n)
        inv = 1.0 / self.d_min - u * (1.0 / self.d_min - 1.0 / self.d_max)
        return 1.0 / inv

    def scaled(self, factor: float) -> "Grading":
        """Same curve with every diameter multiplied by ``factor`` (coarser grains for
        reduced-size runs: the box stays, the particle count falls as factor^-2)."""
        return Grading(self.d50 * factor, self.cu)


def mass_percentile(diameters: np.ndarray, p: float) -> float:
    """Diameter [m] with a fraction ``p`` of the total (2D) mass finer: D_p of a sample."""
    d = np.sort(np.asarray(diameters, dtype=float))
    m = np.cumsum(d * d)
    m /= m[-1]
    return float(np.interp(p, m, d))


def measured_d50_cu(diameters: np.ndarray) -> tuple[float, float]:
    """(D50 [m], Cu = D60/D10) of a sample of disk diameters, by mass."""
    return mass_percentile(diameters, 0.5), mass_percentile(diameters, 0.6) / mass_percentile(diameters, 0.1)
