"""Rigid-block limit equilibrium of dry-stone retaining walls (pure, no I/O).

Follows docs/reference/drystone-walls.md (cited below as "ref."):

* section and loads: ref. 5.3 (trapezoid, x inward from the outer toe, y up; when the
  bed joints dip toward the fill at alpha > 0 the base is the bed plane through the
  outer toe, so the heel lies b tan(alpha) / (1 - tan(alpha) tan(lambda2)) lower and the
  water pressure continues down to it);
* sliding along a bed joint: ref. 5.4, H = (W + V) tan(alpha + phi_b);
* toppling about a point O of the outer face, the moving part above a line from O
  rising inward at theta: ref. 5.5, H (y_H - z) = W (x_G - x_o(z)) + V (x_i(y_H) - x_o(z));
* case B (backfill): the simplified Coulomb coupling of ref. 5.3 / 5.6.

Two variants (``method``):

``"bed-joints"``
    rigid blocks separated by bed joints only: sliding along, and toppling about the
    outer edge of, every bed joint z_k = k * course_height (theta = -alpha, the
    separation along the joint). What a DEM wall of bed and head joints allows without
    a staircase, and the design check "for every bed joint".
``"yield-design"``
    the reference's section-5 reconstruction: z searched over [0, h) (a homogenised
    masonry has a bed joint everywhere), and for toppling theta over
    [-alpha, atan(m) - alpha] (m = 2 h_block / l_block, the steepest staircase of a
    half-overlap bond). A superset of the bed-joint mechanisms, so never higher.

Water is horizontal (fixed direction, the paper's choice, ref. 2.1) on the inner face,
gamma_w = 9.81 kN/m3; its vertical share on a battered inner face is H tan(lambda2)
(ref. 5.3). Water heights h_w are measured from the outer toe level. A height above the
crest is the balance extended above the crest, as the reference's table 2.3 does (V2L
sliding at 2.01 m for h = 1.95 m); it means the wall stands in that mechanism with water
to its crest (``LimitEquilibrium.stands_to_crest``).

Units: m, kN/m3, kN/m (per metre run), angles in degrees at the interface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Callable, Iterable, Mapping

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from .constants import GAMMA_W
from .errors import InvalidParameter
from .inputs import require_number

METHODS = ("bed-joints", "yield-design")
# ref. 2.1 / 2.3 [A]: the DEM blocks of S-OET, 0.30 m long and 0.125 m high
BLOCK_LENGTH_M = 0.30
BLOCK_HEIGHT_M = 0.125
DISKS_PER_BLOCK = 160  # ref. 6: hollow clump of 160 disks per block (S-OET)

Point = tuple[float, float]
_BIG = 1e12


def _tan(deg: float) -> float:
    return math.tan(math.radians(deg))


# design/blocks.py builds on this module, so the polygon helpers of analytic/design are
# imported on first use (a module-level import would be circular through design/__init__)
def _area_centroid(poly: list[Point]) -> tuple[float, float, float]:
    """Area [m2] and centroid [m] of a simple polygon (shoelace)."""
    from .design.geometry import area_centroid
    return area_centroid(poly)


def _clip_above(poly: list[Point], point: Point, slope: float) -> list[Point]:
    from .design.geometry import clip_above
    return clip_above(poly, point, slope)


def crest_width(height_m: float, base_width_m: float, batter_outer_deg: float, batter_inner_deg: float) -> float:
    """b_c = b - h (tan lambda1 + tan lambda2) [m] (ref. 5.3 trapezoid), unchecked."""
    return base_width_m - height_m * (_tan(batter_outer_deg) + _tan(batter_inner_deg))


@dataclass(frozen=True)
class WallSection:
    """Plane section of a dry-stone wall (ref. 1 notation, ref. 5.3 coordinates).

    height_m          h, crest above the outer toe [m], > 0
    base_width_m      b, width at the toe level, toe to inner face [m], > 0
    batter_outer_deg  lambda1, outer face from vertical, leaning inward as it rises [deg]
    batter_inner_deg  lambda2, inner face from vertical, leaning outward as it rises
                      (the fill rests on it) [deg], default 0 (ref. 2.3 [A])
    joint_slope_deg   alpha, bed joints dipping toward the fill [deg], default 0

    Outer face x_o(y) = y tan(lambda1), inner face x_i(y) = b - y tan(lambda2).
    """

    height_m: float
    base_width_m: float
    batter_outer_deg: float
    batter_inner_deg: float = 0.0
    joint_slope_deg: float = 0.0

    def __post_init__(self):
        require_number("height_m", self.height_m, 0.0, None, unit="m")
        require_number("base_width_m", self.base_width_m, 0.0, None, unit="m")
        require_number("batter_outer_deg", self.batter_outer_deg, -45.0, 45.0, unit="deg")
        require_number("batter_inner_deg", self.batter_inner_deg, -45.0, 45.0, unit="deg")
        require_number("joint_slope_deg", self.joint_slope_deg, -45.0, 45.0, unit="deg")
        if self.crest_width_m <= 0:
            need = self.base_width_m - self.crest_width_m
            raise InvalidParameter("base_width_m", self.base_width_m,
                                   f"> h (tan lambda1 + tan lambda2) = {need:.4g} m",
                                   "the crest width must stay > 0")

    @property
    def crest_width_m(self) -> float:
        """b_c = b - h (tan lambda1 + tan lambda2) [m]."""
        return crest_width(self.height_m, self.base_width_m, self.batter_outer_deg, self.batter_inner_deg)

    def x_outer(self, y: float) -> float:
        """x_o(y) = y tan(lambda1) [m] (ref. 5.3)."""
        return y * _tan(self.batter_outer_deg)

    def x_inner(self, y: float) -> float:
        """x_i(y) = b - y tan(lambda2) [m] (ref. 5.3)."""
        return self.base_width_m - y * _tan(self.batter_inner_deg)

    def polygon(self) -> list[Point]:
        """The section [m]: the trapezoid between the faces below the crest, cut at the
        base, the bed plane through the outer toe dipping inward at alpha (ref. 5.3)."""
        return list(self._polygon)

    @cached_property
    def _polygon(self) -> tuple:
        lo = -self.base_width_m * (1 + abs(_tan(self.joint_slope_deg))) - 1.0
        h = self.height_m
        quad = [(self.x_outer(lo), lo), (self.x_inner(lo), lo), (self.x_inner(h), h), (self.x_outer(h), h)]
        return tuple(_clip_above(quad, (0.0, 0.0), -_tan(self.joint_slope_deg)))

    def heel(self) -> Point:
        """The heel, where the base plane meets the inner face [m]:
        x = b / (1 - tan(alpha) tan(lambda2)), y = -x tan(alpha)."""
        ta, t2 = _tan(self.joint_slope_deg), _tan(self.batter_inner_deg)
        x = self.base_width_m / (1 - ta * t2)
        return x, -x * ta

    def area_m2(self) -> float:
        return _area_centroid(self.polygon())[0]

    def part_above(self, z: float, slope: float | None = None) -> tuple[list[Point], float]:
        """The part above the line through O = (x_o(z), z) with dy/dx = ``slope``
        (default the bed joint, -tan(alpha)), and the height where that line meets the
        inner face, y_I = [z + (b - x_o(z)) s] / (1 + tan(lambda2) s) [m]
        (ref. 5.4 with s = -tan(alpha), ref. 5.5 with s = tan(theta))."""
        s = -_tan(self.joint_slope_deg) if slope is None else slope
        t2 = _tan(self.batter_inner_deg)
        poly = _clip_above(self._polygon, (self.x_outer(z), z), s)
        y_I = (z + (self.base_width_m - self.x_outer(z)) * s) / (1 + t2 * s)
        return poly, y_I

    @classmethod
    def from_widths(cls, height_m: float, base_width_m: float, crest_width_m: float,
                    batter_inner_deg: float = 0.0, joint_slope_deg: float = 0.0) -> "WallSection":
        """Section from h, b and b_c [m]: lambda1 = atan((b - b_c) / h - tan(lambda2))
        (ref. 2.3 gives b and b_c)."""
        require_number("height_m", height_m, 0.0, None, unit="m")
        require_number("crest_width_m", crest_width_m, 0.0, None, unit="m")
        t1 = (base_width_m - crest_width_m) / height_m - _tan(batter_inner_deg)
        return cls(height_m, base_width_m, math.degrees(math.atan(t1)), batter_inner_deg, joint_slope_deg)

    @classmethod
    def from_area(cls, height_m: float, area_m2: float, batter_outer_deg: float,
                  batter_inner_deg: float = 0.0, joint_slope_deg: float = 0.0) -> "WallSection":
        """Trapezoid of a given area above the toe level [m2]: b = A / h + h (tan lambda1
        + tan lambda2) / 2 (ref. 6; the wedge below the toe level when alpha > 0 is not
        counted in A)."""
        require_number("height_m", height_m, 0.0, None, unit="m")
        require_number("area_m2", area_m2, 0.0, None, unit="m2")
        b = area_m2 / height_m + height_m * (_tan(batter_outer_deg) + _tan(batter_inner_deg)) / 2
        return cls(height_m, b, batter_outer_deg, batter_inner_deg, joint_slope_deg)

    @classmethod
    def from_disk_count(cls, height_m: float, n_disks: float, batter_outer_deg: float,
                        batter_inner_deg: float = 0.0, joint_slope_deg: float = 0.0, *,
                        disks_per_block: float = DISKS_PER_BLOCK, block_length_m: float = BLOCK_LENGTH_M,
                        block_height_m: float = BLOCK_HEIGHT_M) -> "WallSection":
        """The reference's second estimate (ref. 6): area = n_disks / disks_per_block x
        block_length x block_height (S-OET: 160 disks per 0.30 x 0.125 m block; V1L 7089
        disks -> 1.66 m2, V3L 27400 -> 6.42 m2, +-15 %), then ``from_area``."""
        require_number("n_disks", n_disks, 0.0, None)
        require_number("disks_per_block", disks_per_block, 0.0, None)
        area = n_disks / disks_per_block * block_length_m * block_height_m
        return cls.from_area(height_m, area, batter_outer_deg, batter_inner_deg, joint_slope_deg)


@dataclass(frozen=True)
class LimitEquilibrium:
    """Critical load of a wall and the mechanism that reaches it.

    critical_height_m  h_w (case A) or H_b (case B) at failure, above the toe level [m]
    mode               "sliding" | "toppling" (the lower of the two; sliding on a tie)
    mechanism_level_m  z where the governing mechanism leaves the outer face [m]
    sliding_height_m, toppling_height_m  each mechanism's lowest critical load [m]
                       (inf: that mechanism cannot be driven by this load)
    sliding_level_m, toppling_level_m    z of each [m]
    theta_deg          angle of the toppling separation line above the horizontal [deg]
    method             "bed-joints" | "yield-design"
    stands_to_crest    critical_height_m > h: with the load up to the crest the wall stands
    """

    critical_height_m: float
    mode: str
    mechanism_level_m: float
    sliding_height_m: float
    toppling_height_m: float
    sliding_level_m: float
    toppling_level_m: float
    theta_deg: float
    method: str
    stands_to_crest: bool
    load: str = "water"

    def as_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


# ---------------------------------------------------------------- loads (ref. 5.3)

def water_thrust(section: WallSection, y_I: float, h_w: float) -> tuple[float, float, float, float]:
    """Water on the inner face between y_I and h_w (ref. 5.3): H = gamma_w (h_w - y_I)^2 / 2
    [kN/m], horizontal, outward, at y_H = y_I + (h_w - y_I) / 3; V = H tan(lambda2)
    [kN/m], downward, at the face point x_i(y_H). Returns (H, V, x_H, y_H)."""
    d = max(h_w - y_I, 0.0)
    H = 0.5 * GAMMA_W * d ** 2
    y_H = y_I + d / 3
    return H, H * _tan(section.batter_inner_deg), section.x_inner(y_H), y_H


def coulomb_ka(phi_deg: float, delta_deg: float, beta_deg: float, batter_inner_deg: float = 0.0) -> float:
    """Coulomb's active coefficient on the inner face (ref. 5.3, Mueller-Breslau form;
    analytic.classical.coulomb_coefficient). The face angle is omega = +lambda2: the
    fill resting on a face battered at lambda2 > 0 (checked by a trial wedge: phi 30,
    delta 0, beta 0, lambda2 10 -> 0.407; ref. 5.3 writes psi = -lambda2 in the same
    formula, which is the opposite sign, and only lambda2 = 0 occurs in its tables).
    Check values (ref. 5.3, vertical face): phi = delta = 37.7, beta = 32 -> 0.416
    (horizontal 0.329); beta = 0 -> 0.228."""
    from .classical import coulomb_coefficient
    require_number("phi_fill_deg", phi_deg, 0.0, 90.0, unit="deg")
    require_number("delta_deg", delta_deg, 0.0, phi_deg, lo_open=False, hi_open=False, unit="deg")
    require_number("beta_deg", beta_deg, -phi_deg, phi_deg, lo_open=False, hi_open=False, unit="deg")
    r = math.radians
    ka = coulomb_coefficient(r(phi_deg), r(delta_deg), r(batter_inner_deg), r(beta_deg))
    if not math.isfinite(ka):
        raise InvalidParameter("beta_deg", beta_deg, f"< phi = {phi_deg:g} deg", "no Coulomb wedge")
    return ka


def fill_thrust(section: WallSection, y_I: float, H_b: float, gamma_s: float, ka: float,
                delta_deg: float) -> tuple[float, float, float, float]:
    """Fill on the inner face above y_I (ref. 5.3 simplified): p(y) = gamma_s (H_b - y) K_a
    per metre of height for y_I <= y <= min(H_b, h) (fill above the crest only raises
    H_b). Resultant P [kN/m] at y_P (centroid of the trapezoidal diagram); horizontal
    P cos(delta + lambda2) outward, vertical P sin(delta + lambda2) downward at x_i(y_P).
    Returns (H, V, x_P, y_P)."""
    top = min(H_b, section.height_m)
    if top <= y_I:
        return 0.0, 0.0, section.x_inner(y_I), y_I
    P = gamma_s * ka * (H_b * (top - y_I) - (top ** 2 - y_I ** 2) / 2)
    M = gamma_s * ka * (H_b * (top ** 2 - y_I ** 2) / 2 - (top ** 3 - y_I ** 3) / 3)
    y_P = M / P
    w = math.radians(delta_deg + section.batter_inner_deg)
    return P * math.cos(w), P * math.sin(w), section.x_inner(y_P), y_P


# ------------------------------------------------------------ mechanisms (ref. 5.4, 5.5)

def _weight(section: WallSection, poly: list[Point], gamma_m: float) -> tuple[float, float]:
    A, xg, _ = _area_centroid(poly)
    return gamma_m * A, xg


def _sliding_part(section: WallSection, z: float, phi_b_deg: float, gamma_m: float):
    """The part above the bed joint at z for the sliding balances (ref. 5.4): its weight W
    [kN/m], the joint's y_I [m] at the inner face and T = tan(alpha + phi_b); T is None
    when alpha + phi_b >= 90 deg (no sliding)."""
    poly, y_I = section.part_above(z)
    W, _ = _weight(section, poly, gamma_m)
    ang = section.joint_slope_deg + phi_b_deg
    return W, y_I, (None if ang >= 90 else _tan(ang))


def sliding_water_height(section: WallSection, z: float, phi_b_deg: float, gamma_m: float) -> float:
    """h_w [m] at which the part above the bed joint leaving the outer face at z slides
    (ref. 5.4): h_w = y_I + sqrt(2 W tan(alpha + phi_b) / (gamma_w (1 - tan(lambda2)
    tan(alpha + phi_b)))); inf if alpha + phi_b >= 90 deg or the water's vertical share
    grows faster than its push."""
    W, y_I, T = _sliding_part(section, z, phi_b_deg, gamma_m)
    if T is None:
        return math.inf
    den = GAMMA_W * (1 - _tan(section.batter_inner_deg) * T)
    if den <= 0:
        return math.inf
    return y_I + math.sqrt(2 * W * T / den)


def toppling_water_height(section: WallSection, z: float, theta_deg: float, gamma_m: float) -> float:
    """h_w [m] at which the part above the line from O = (x_o(z), z) rising inward at
    theta rotates about O (ref. 5.5). With d = h_w - y_I the balance
    H (y_H - z) - V (x_i(y_H) - x_o) = W (x_G - x_o) is the cubic
    gamma_w (1 + t2^2) d^3 / 6 + gamma_w [(1 + t2^2) y_I - z - t2 (b - x_o)] d^2 / 2 = M_W,
    t2 = tan(lambda2), which has one positive root for M_W > 0. inf when the line leaves
    through the crest (no wetted face on the moving part)."""
    poly, y_I = section.part_above(z, _tan(theta_deg))
    if y_I >= section.height_m:
        return math.inf
    W, xg = _weight(section, poly, gamma_m)
    xo = section.x_outer(z)
    M = W * (xg - xo)
    if M <= 0:
        raise InvalidParameter("batter_outer_deg", section.batter_outer_deg, "a section whose parts stand "
                               "under their own weight", f"the part above z = {z:.3g} m overturns with no load")
    t2 = _tan(section.batter_inner_deg)
    a = GAMMA_W * (1 + t2 * t2) / 6
    c = GAMMA_W * ((1 + t2 * t2) * y_I - z - t2 * (section.base_width_m - xo)) / 2
    # unique positive root: g(d) = a d^3 + c d^2 - M is < 0 up to max(0, -c/a), then
    # rises and is convex (g'' > 0 for d > -c/3a): Newton from a point right of the root
    # decreases monotonically onto it
    d = max(0.0, -c / a) + 1.0
    while a * d ** 3 + c * d * d < M:
        d *= 2
    for _ in range(100):
        step = (a * d ** 3 + c * d * d - M) / (3 * a * d * d + 2 * c * d)
        d -= step
        if step <= 1e-14 * d:
            break
    return y_I + d


def _backfill_height(section: WallSection, z: float, slope: float | None, balance: Callable) -> float:
    """Smallest H_b [m] above the moving part's y_I at which ``balance(H_b) >= 0``,
    searched by doubling then Brent; inf if none below 50 h."""
    _, y_I = section.part_above(z, slope)
    if y_I >= section.height_m:
        return math.inf
    lo, step = y_I, max(section.height_m - y_I, 1e-3) / 8
    hi = lo + step
    while balance(hi) < 0:
        lo, hi = hi, hi + step
        step *= 1.5
        if hi > 50 * section.height_m:
            return math.inf
    return brentq(balance, lo, hi, xtol=1e-10)


def sliding_fill_height(section, z, phi_b_deg, gamma_m, gamma_s, ka, delta_deg) -> float:
    """H_b [m] at which the part above the bed joint at z slides under the fill's thrust
    (ref. 5.4 with the thrust of 5.3): H = (W + V) tan(alpha + phi_b)."""
    W, y_I, T = _sliding_part(section, z, phi_b_deg, gamma_m)
    if T is None:
        return math.inf
    w = math.radians(delta_deg + section.batter_inner_deg)
    if math.cos(w) - math.sin(w) * T <= 0:
        return math.inf

    def balance(Hb):
        H, V, _, _ = fill_thrust(section, y_I, Hb, gamma_s, ka, delta_deg)
        return H - (W + V) * T
    return _backfill_height(section, z, None, balance)


def toppling_fill_height(section, z, theta_deg, gamma_m, gamma_s, ka, delta_deg) -> float:
    """H_b [m] at which the part above the line from O = (x_o(z), z) at theta rotates
    about O under the fill's thrust on its face (ref. 5.5 with the thrust of 5.3/5.6)."""
    s = _tan(theta_deg)
    poly, y_I = section.part_above(z, s)
    if y_I >= section.height_m:
        return math.inf
    W, xg = _weight(section, poly, gamma_m)
    xo = section.x_outer(z)
    M = W * (xg - xo)

    def balance(Hb):
        H, V, xP, yP = fill_thrust(section, y_I, Hb, gamma_s, ka, delta_deg)
        return H * (yP - z) - V * (xP - xo) - M
    return _backfill_height(section, z, s, balance)


# ---------------------------------------------------------------- search (ref. 5.7)

def _joint_levels(section: WallSection, course_height_m: float) -> list[float]:
    n = max(1, math.ceil(section.height_m / course_height_m - 1e-9))
    return [k * course_height_m for k in range(n)]


def _min_over(f: Callable[[float], float], grid: list[float], lo: float, hi: float,
              refine: bool) -> tuple[float, float]:
    """min of f over ``grid`` (then, if ``refine``, a bounded search in the cells next to
    the best point, kept only if lower). Returns (value, argument)."""
    vals = [f(x) for x in grid]
    k = int(np.argmin(vals))
    best = (vals[k], grid[k])
    if refine and len(grid) > 1 and math.isfinite(best[0]):
        a, b = grid[max(k - 1, 0)], grid[k + 1] if k + 1 < len(grid) else hi
        a, b = max(a, lo), min(b, hi)
        if b > a:
            # inf (a mechanism the load cannot drive) would break Brent's parabolic steps
            r = minimize_scalar(lambda x: min(f(x), _BIG), bounds=(a, b), method="bounded",
                                options={"xatol": 1e-7})
            if r.fun < best[0]:
                best = (float(r.fun), float(r.x))
    return best


def _theta_range(section: WallSection, staircase_m: float, method: str) -> tuple[float, float]:
    lo = -section.joint_slope_deg
    if method == "bed-joints" or staircase_m <= 0:
        return lo, lo
    return lo, math.degrees(math.atan(staircase_m)) - section.joint_slope_deg


def _search(section: WallSection, method: str, course_height_m: float, staircase_m: float,
            slide: Callable[[float], float], topple: Callable[[float, float], float],
            n_z: int = 200, n_theta: int = 17, n_z_topple: int = 40, water: bool = True) -> tuple:
    """(h_S, z_S, h_T, z_T, theta_T) minimised over the mechanisms of ``method``.

    With water (``water``), a mechanism that no level reaches below the crest is reported
    by its base-joint value (z = 0): the balance extended above the crest tends to h from
    above as z -> h (a vanishing top sliver), so its minimum over z would only say "h";
    the base value measures the margin, as ref. 2.3 reports V2L's sliding at 2.01 m."""
    h = section.height_m
    t_lo, t_hi = _theta_range(section, staircase_m, method)
    if method == "bed-joints":
        zs = _joint_levels(section, course_height_m)
        h_s, z_s = _min_over(slide, zs, 0.0, h, refine=False)
        h_t, z_t = _min_over(lambda z: topple(z, t_lo), zs, 0.0, h, refine=False)
        if water and h_s >= h:
            h_s, z_s = slide(0.0), 0.0
        if water and h_t >= h:
            h_t, z_t = topple(0.0, t_lo), 0.0
        return h_s, z_s, h_t, z_t, t_lo
    zs = [h * k / n_z for k in range(n_z)]  # z = h excluded: nothing above it
    z_max = h * (1 - 0.5 / n_z)
    h_s, z_s = _min_over(slide, zs, 0.0, z_max, refine=True)
    thetas = [t_lo + (t_hi - t_lo) * k / (n_theta - 1) for k in range(n_theta)] if t_hi > t_lo else [t_lo]

    def best_theta(z, refine=True):
        return _min_over(lambda t: topple(z, t), thetas, t_lo, t_hi, refine=refine and len(thetas) > 1)

    # (z, theta) grid, then coordinate descent in the grid cells around the best point:
    # theta at that z, z at that theta, theta again
    zc = [h * k / n_z_topple for k in range(n_z_topple)]
    per_z = [best_theta(z, refine=False) for z in zc]
    k = int(np.argmin([p[0] for p in per_z]))
    h_t, th = best_theta(zc[k])
    z_t = zc[k]
    a, b = zc[max(k - 1, 0)], zc[k + 1] if k + 1 < len(zc) else z_max
    if math.isfinite(h_t) and b > a:
        r = minimize_scalar(lambda z: min(topple(z, th), _BIG), bounds=(a, b), method="bounded",
                            options={"xatol": 1e-7})
        if r.fun < h_t:
            z_t = float(r.x)
            h_t, th = best_theta(z_t)
    if water and h_s >= h:
        h_s, z_s = slide(0.0), 0.0
    if water and h_t >= h:
        z_t = 0.0
        h_t, th = best_theta(0.0)
    return h_s, z_s, h_t, z_t, th


def _result(section, method, load, h_s, z_s, h_t, z_t, th) -> LimitEquilibrium:
    sliding = h_s <= h_t
    crit = h_s if sliding else h_t
    return LimitEquilibrium(
        critical_height_m=crit, mode="sliding" if sliding else "toppling",
        mechanism_level_m=z_s if sliding else z_t, sliding_height_m=h_s, toppling_height_m=h_t,
        sliding_level_m=z_s, toppling_level_m=z_t, theta_deg=th, method=method,
        stands_to_crest=crit > section.height_m, load=load)


def _check_common(method: str, phi_b_deg: float, gamma_m: float, staircase_m: float,
                  course_height_m: float) -> None:
    if method not in METHODS:
        raise InvalidParameter("method", method, " | ".join(repr(m) for m in METHODS))
    require_number("phi_b_deg", phi_b_deg, 0.0, 90.0, unit="deg")
    require_number("unit_weight_kN_m3", gamma_m, 0.0, None, unit="kN/m3")
    require_number("staircase_m", staircase_m, 0.0, 10.0, lo_open=False)
    require_number("course_height_m", course_height_m, 0.0, None, unit="m")


def water_limit_equilibrium(section: WallSection, phi_b_deg: float, unit_weight_kN_m3: float,
                            staircase_m: float = 0.83, method: str = "yield-design",
                            course_height_m: float = BLOCK_HEIGHT_M) -> LimitEquilibrium:
    """Critical water height h_w [m] above the toe level and the mechanism (case A).

    phi_b_deg       block-block friction angle phi_b [deg] (ref. 4: tilt-test angle)
    unit_weight_kN_m3   unit weight of the dry masonry, voids included [kN/m3]
    staircase_m     m = tan(theta_max) of the steepest stepped line, 2 h_block / l_block
                    (ref. 2.3 [A]: 2 x 0.125 / 0.30 = 0.83); "yield-design" only
    method          "bed-joints" (joints at z_k = k course_height_m, theta = -alpha) or
                    "yield-design" (ref. 5.7: z over [0, h), theta over [-alpha, atan(m) - alpha])
    course_height_m height of a course along the outer face [m] (ref. 2.1: DEM blocks
                    0.125 m [A]); "bed-joints" only

    Sliding: ref. 5.4 (closed form); toppling: ref. 5.5 (cubic in h_w - y_I).
    """
    _check_common(method, phi_b_deg, unit_weight_kN_m3, staircase_m, course_height_m)
    g = unit_weight_kN_m3
    found = _search(section, method, course_height_m, staircase_m,
                    lambda z: sliding_water_height(section, z, phi_b_deg, g),
                    lambda z, t: toppling_water_height(section, z, t, g))
    return _result(section, method, "water", *found)


def backfill_limit_equilibrium(section: WallSection, phi_b_deg: float, unit_weight_kN_m3: float,
                               gamma_s_kN_m3: float, phi_fill_deg: float, delta_deg: float,
                               beta_deg: float, staircase_m: float = 0.73, method: str = "yield-design",
                               course_height_m: float = 0.12) -> LimitEquilibrium:
    """Critical backfill height H_b [m] above the toe level and the mechanism (case B),
    with the simplified coupling of ref. 5.3 / 5.6: the Coulomb pressure
    p = gamma_s (H_b - y) K_a (``coulomb_ka``) on the moving part's face only. A
    quasi-kinematic estimate, not a strict upper bound (ref. 5.6); probably
    unconservative for large delta (ref. 3.3).

    gamma_s_kN_m3  fill unit weight [kN/m3] (ref. 3.1: 14.9)
    phi_fill_deg   fill friction angle [deg] (ref. 3.1: 37.7)
    delta_deg      wall-fill interface angle [deg], 0 <= delta <= phi
    beta_deg       fill surface slope, rising away from the wall [deg] (ref. 3.3 [A]: 32)
    staircase_m    ref. 3.3 [A]: 2 x 0.12 / 0.33 = 0.73; course_height_m: ref. 3.1 blocks 0.12 m
    H_b is a vertical height (equal to the length along a vertical inner face).
    """
    _check_common(method, phi_b_deg, unit_weight_kN_m3, staircase_m, course_height_m)
    require_number("gamma_s_kN_m3", gamma_s_kN_m3, 0.0, None, unit="kN/m3")
    ka = coulomb_ka(phi_fill_deg, delta_deg, beta_deg, section.batter_inner_deg)
    args = (unit_weight_kN_m3, gamma_s_kN_m3, ka, delta_deg)
    found = _search(section, method, course_height_m, staircase_m,
                    lambda z: sliding_fill_height(section, z, phi_b_deg, *args),
                    lambda z, t: toppling_fill_height(section, z, t, *args), n_z=100, n_theta=13,
                    n_z_topple=40, water=False)
    return _result(section, method, "backfill", *found)


# -------------------------------------------------------------------------- band

@dataclass(frozen=True)
class Band:
    """Critical heights over a set of inputs ("band_m" of the validation report).

    lo_m, hi_m        lowest and highest critical height [m]
    lo_label, hi_label  the input that gave each
    modes             the set of modes met across the inputs
    results           label -> LimitEquilibrium
    """

    lo_m: float
    hi_m: float
    lo_label: str
    hi_label: str
    modes: tuple
    results: dict = field(repr=False)


def band(results: Mapping[str, LimitEquilibrium]) -> Band:
    """Min and max critical height over labelled results, and which gave each."""
    if not results:
        raise InvalidParameter("results", 0, ">= 1 labelled result")
    items = list(results.items())
    lo = min(items, key=lambda kv: kv[1].critical_height_m)
    hi = max(items, key=lambda kv: kv[1].critical_height_m)
    modes = tuple(sorted({r.mode for r in results.values()}))
    return Band(lo[1].critical_height_m, hi[1].critical_height_m, lo[0], hi[0], modes, dict(results))


def water_band(sections: Mapping[str, WallSection], phi_b_deg: float, gamma_m_values: Iterable[float],
               joint_slopes_deg: Iterable[float] | None = None, **kwargs) -> Band:
    """``water_limit_equilibrium`` over every section x unit weight [kN/m3] x joint slope
    alpha [deg] (None: each section's own); labels "<section> gamma_m=<g> alpha=<a>";
    ``kwargs`` go to ``water_limit_equilibrium`` (staircase_m, method, course_height_m).
    Issue 23 asks for both geometries (ref. 2.3 and 6), gamma_m 18-22 and alpha 0-8.5 deg."""
    out = {}
    gammas = list(gamma_m_values)
    alphas = list(joint_slopes_deg) if joint_slopes_deg is not None else [None]
    for name, sec in sections.items():
        for a in alphas:
            s = sec if a is None else replace(sec, joint_slope_deg=float(a))
            for g in gammas:
                label = f"{name} gamma_m={g:g} alpha={s.joint_slope_deg:g}"
                out[label] = water_limit_equilibrium(s, phi_b_deg, g, **kwargs)
    return band(out)


def section_above_fixed_course(section: WallSection, course_height_m: float) -> tuple[WallSection, float]:
    """The part of ``section`` above the bed joint on top of a fixed first course of height
    ``course_height_m`` [m], as a wall of its own (its toe where that joint meets the outer
    face), and that toe's height y [m] above the base. The joint at counter-slope alpha
    leaves the outer face at y = c / (tan(lambda1) sin(alpha) + cos(alpha)) (pure geometry;
    S-OET 5.1 fixes the first course, so the DEM's mechanisms start there)."""
    a = math.radians(section.joint_slope_deg)
    t1, t2 = _tan(section.batter_outer_deg), _tan(section.batter_inner_deg)
    y = course_height_m / (t1 * math.sin(a) + math.cos(a))
    return WallSection(section.height_m - y, section.base_width_m - y * (t1 + t2), section.batter_outer_deg,
                       section.batter_inner_deg, section.joint_slope_deg), y
