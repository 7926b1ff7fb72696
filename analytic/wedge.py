"""Coulomb's trial wedge with cohesion c and wall adhesion a (c-a wedge).

Source: Coulomb (1776) extended to c-phi soil as set out in Terzaghi (1943, Theoretical
Soil Mechanics, ch. 5) and Craig's Soil Mechanics (sec. "Coulomb's theory", cohesive
soil: forces W, P, R, C = c L on the slip plane, C_w = a L_w on the wall, the wedge cut
by a tension crack). Vertical back, level fill, uniform surcharge q, dry soil.

Wall AB vertical (heel at the origin, top at height H), fill to the right. A trial plane
leaves the heel at theta to the horizontal and meets the bottom of a tension crack of
depth z_c; the crack is vertical and carries no stress (no water in it). Forces on the
wedge, per metre of wall:

    W + Q = (gamma (H^2 - z_c^2) / 2 + q (H - z_c)) cot(theta)     (down)
    C     = c (H - z_c) / sin(theta)                     along the plane, against sliding
    C_w   = a (H - z_c)                                  along the wall, against sliding
    R     at phi to the plane's normal, against sliding
    P     at delta to the wall's normal (the thrust)

Force equilibrium (two equations) gives P and the normal part of R for each theta. The
active thrust is the largest P over theta, the passive the least (no crack, C, C_w and
the friction reversed). With c = a = 0 this is Coulomb's (Mueller-Breslau) K; with
delta = a = 0 and no crack it is Bell's 1/2 K_a gamma H^2 - 2 c H sqrt(K_a); with
phi = 0 and delta = 0 it is 1/2 gamma H^2 - 2 c H sqrt(1 + a/c), the origin of
EN 1997-1 C.1's K_ac = 2 sqrt(K_n (1 + a/c)) (tests/analytic/test_wedge.py).

Active tension-crack depth: the depth where the active pressure p(z) = dP_0(z)/dz of the
uncracked wedge (P_0(z) the largest thrust on a wall of height z, q included) turns
positive, found by root-finding; it is Bell's z_0 = (2 c sqrt(K_a) - K_a q) / (K_a gamma)
when delta = a = 0 and 2 c sqrt(1 + a/c) / gamma - q / gamma when phi = 0. The thrust is
then the largest P of the wedge cut by that crack. Adhesion acts only below the crack.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from .errors import InvalidParameter
from .inputs import require_number

SOURCE = ("Coulomb trial wedge with cohesion and adhesion (Terzaghi 1943; Craig's Soil Mechanics, "
          "Coulomb's theory for cohesive soil), vertical back, level fill, tension crack")


@dataclass(frozen=True)
class WedgeResult:
    """Thrust of the critical c-a wedge, per metre of wall.

    P:             resultant on the wall [N/m], at delta to the normal
    P_h:           its horizontal (normal) component [N/m]
    theta_deg:     the critical plane's angle to the horizontal [deg]
    crack_depth:   tension-crack depth used [m] (0 when passive or none)
    """

    P: float
    P_h: float
    theta_deg: float
    crack_depth: float
    passive: bool
    source: str = SOURCE


def _wedge_force(theta: float, H: float, phi: float, gamma: float, c: float, a: float, delta: float,
                 q: float, z_c: float, passive: bool) -> float:
    """P [N/m] from the two force-equilibrium equations of the wedge at plane angle theta
    (module docstring). Active: the wedge slides down the plane and down the wall, so C,
    C_w and the friction on both faces act up; passive: all reversed."""
    h = H - z_c
    s = -1.0 if passive else 1.0               # sense of the resisting forces (up = +1)
    ct, st = math.cos(theta), math.sin(theta)
    W = (0.5 * gamma * (H * H - z_c * z_c) + q * h) * ct / st
    C, Cw = c * h / st, a * h
    # unknowns P (along (cos d, s sin d)) and N (reaction normal to the plane, into the
    # wedge: (-sin t, cos t), friction s N tan(phi) along (cos t, sin t))
    tp = math.tan(phi)
    A = np.array([[math.cos(delta), -st + s * tp * ct],
                  [s * math.sin(delta), ct + s * tp * st]])
    rhs = np.array([-s * C * ct, W - s * C * st - s * Cw])
    P, N = np.linalg.solve(A, rhs)
    # passive: a plane past the pole of the system (N < 0) is no mechanism. Active: no
    # sign check, since above the crack depth the uncracked wedge is in tension and its
    # dP/dz is what locates the crack (as Bell's negative stresses do)
    return math.nan if passive and N < 0.0 else float(P)


def _critical(H, phi, gamma, c, a, delta, q, z_c, passive) -> tuple[float, float]:
    """(P, theta) of the critical plane: the largest P (active) or least (passive)."""
    sign = 1.0 if passive else -1.0            # minimise sign * P

    def f(t):
        v = _wedge_force(t, H, phi, gamma, c, a, delta, q, z_c, passive)
        return sign * v if math.isfinite(v) else math.inf

    grid = np.linspace(1e-3, math.pi / 2 - 1e-3, 400)
    vals = np.array([f(t) for t in grid])
    k = int(np.argmin(vals))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    res = minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    t = float(res.x) if res.fun <= vals[k] else float(grid[k])
    return sign * f(t), t


def _crack_depth(H, phi, gamma, c, a, delta, q) -> float:
    """Depth where the uncracked wedge's active pressure dP_0/dz turns positive [m]
    (0 when it is positive at the top; H when never inside the wall)."""
    if c == 0.0:
        return 0.0

    def p(z, dz=1e-6):
        lo = _critical(max(z - dz, 1e-9), phi, gamma, c, a, delta, q, 0.0, False)[0]
        hi = _critical(z + dz, phi, gamma, c, a, delta, q, 0.0, False)[0]
        return (hi - lo) / (z + dz - max(z - dz, 1e-9))

    if p(1e-4) >= 0.0:
        return 0.0
    if p(H) <= 0.0:
        return H
    return brentq(p, 1e-4, H, xtol=1e-10)


def cohesive_wedge(H: float, phi_deg: float, gamma: float, c: float = 0.0, adhesion: float = 0.0,
                   delta_deg: float = 0.0, q: float = 0.0, passive: bool = False,
                   tension_crack: bool = True) -> WedgeResult:
    """Critical c-a wedge (module docstring).

    H [m] > 0; phi_deg [deg] in [0, 90); gamma [N/m^3] > 0; c, adhesion a [Pa] >= 0 with
    a <= c; delta_deg [deg] in [0, phi]; q [Pa] >= 0 (uniform, vertical).
    tension_crack=False gives the active thrust "before the crack forms" (textbooks'
    1/2 Ka gamma H^2 - 2 c H sqrt(Ka) when delta = a = 0): the uncracked wedge, its
    tension counted.
    """
    H = require_number("H", H, 0.0, None, unit="m")
    phi_deg = require_number("phi", phi_deg, 0.0, 90.0, lo_open=False, unit="deg")
    gamma = require_number("gamma", gamma, 0.0, None, unit="N/m^3")
    c = require_number("c", c, 0.0, None, lo_open=False, unit="Pa")
    adhesion = require_number("adhesion", adhesion, 0.0, c, lo_open=False, hi_open=False, unit="Pa")
    delta_deg = require_number("delta", delta_deg, 0.0, phi_deg, lo_open=False, hi_open=False, unit="deg")
    q = require_number("q", q, 0.0, None, lo_open=False, unit="Pa")
    if phi_deg == 0.0 and delta_deg > 0.0:
        raise InvalidParameter("delta", delta_deg, "0 deg when phi = 0")
    phi, delta = math.radians(phi_deg), math.radians(delta_deg)
    z_c = 0.0 if passive or not tension_crack else _crack_depth(H, phi, gamma, c, adhesion, delta, q)
    if z_c >= H:
        return WedgeResult(0.0, 0.0, math.nan, H, passive)
    P, t = _critical(H, phi, gamma, c, adhesion, delta, q, z_c, passive)
    return WedgeResult(P, P * math.cos(delta), math.degrees(t), z_c, passive)
