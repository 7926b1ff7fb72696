"""Passive earth pressure on a curved slip surface: Terzaghi's trial log-spiral, and
Lancellotta's closed-form lower bound for comparison.

Terzaghi (1943, Theoretical Soil Mechanics, ch. 7; as set out in Terzaghi & Peck 1967 and
Das, Principles of Foundation Engineering, "passive pressure, curved failure surface"):
vertical wall AB (heel A, top B), level cohesionless fill. A line BD leaves the wall top
at 45 - phi/2 below the horizontal; a trial centre O on BD carries the log spiral
r = r_A exp(theta tan phi) from the heel A to the point E where its radius lies along
BD; beyond E the slip surface is straight, at 45 - phi/2 to the horizontal, bounding a
Rankine passive zone. On the vertical plane EF (F on the surface above E) the Rankine
passive force 1/2 gamma d^2 Kp + q d Kp acts horizontally (Kp Rankine). Every reaction
on the spiral passes through O, so moments about O give the wall force P (at delta to
the normal, at H/3 for the weight part, H/2 for the surcharge part); the spiral whose
P is least is the answer. The weight and surcharge parts are minimised separately, as
Terzaghi did.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

from .errors import InvalidParameter
from .inputs import Soil, Wall, check_wall_friction, require_vertical_level
from .profile import Profile, depth_grid

TERZAGHI = ("Terzaghi (1943) trial log-spiral, passive (Terzaghi & Peck 1967; Das, "
            "Principles of Foundation Engineering, curved failure surface)")
_SPIRAL_POINTS = 400


def _spiral_wall_force(t: float, phi: float, delta: float, H: float, gamma: float, q: float,
                       y_p: float) -> float:
    """Wall force P [N/m] for the trial centre O = B + t (cos a, -sin a), a = 45 - phi/2,
    from moments about O (see the module docstring); nan for an inadmissible trial."""
    a = math.pi / 4 - phi / 2
    ux, uy = math.cos(a), -math.sin(a)
    Ox, Oy = t * ux, H + t * uy
    th_A = math.atan2(-Oy, -Ox)
    d_th = -a - th_A                        # sweep from the heel to E, counter-clockwise
    if not 0.0 < d_th < math.pi:
        return math.nan
    r_A = math.hypot(Ox, Oy)
    th = th_A + np.linspace(0.0, d_th, _SPIRAL_POINTS)
    r = r_A * np.exp((th - th_A) * math.tan(phi))
    xs, ys = Ox + r * np.cos(th), Oy + r * np.sin(th)
    ex, ey = xs[-1], ys[-1]
    if ex <= 0.0 or ey >= H or np.any(xs < -1e-12):
        return math.nan
    # free body A -> spiral -> E -> F (ex, H) -> B (0, H): area and centroid (shoelace)
    px = np.concatenate([xs, [ex, 0.0]])
    py = np.concatenate([ys, [H, H]])
    cross = px * np.roll(py, -1) - np.roll(px, -1) * py
    area = 0.5 * cross.sum()
    gx = ((px + np.roll(px, -1)) * cross).sum() / (6 * area)
    W, Q = gamma * abs(area), q * ex
    d = H - ey
    kp = (1 + math.sin(phi)) / (1 - math.sin(phi))
    Pg, Pq = 0.5 * gamma * d * d * kp, q * d * kp       # Rankine zone on EF, horizontal
    # moments about O, counter-clockwise positive; EF pushes the body toward the wall (-x)
    M = -W * (gx - Ox) - Q * (ex / 2 - Ox) + Pg * (ey + d / 3 - Oy) + Pq * (ey + d / 2 - Oy)
    arm = Ox * math.sin(delta) - (y_p - Oy) * math.cos(delta)   # wall force (cos d, -sin d)
    return -M / arm if abs(arm) > 1e-12 else math.nan


def terzaghi_log_spiral_kp(phi_deg: float, delta_deg: float, *, part: str = "gamma") -> tuple[float, float]:
    """Terzaghi's passive coefficient along the resultant (at delta to the normal) for a
    vertical wall and level fill: ``part="gamma"`` K_p = 2 P / (gamma H^2), ``"q"``
    K_pq = P / (q H). Returns (K, t/H), t the critical centre's distance from the wall
    top along BD. 0 <= delta <= phi."""
    phi, delta = math.radians(phi_deg), math.radians(delta_deg)
    H = 1.0
    gamma, q, y_p, unit = (1.0, 0.0, H / 3, 0.5) if part == "gamma" else (0.0, 1.0, H / 2, 1.0)

    def P(t):
        v = _spiral_wall_force(t, phi, delta, H, gamma, q, y_p)
        return v if math.isfinite(v) and v > 0 else math.inf

    # t = H cot(s) spans the whole line BD: at delta = 0 the least P lies at t -> -inf,
    # where the spiral flattens into Rankine's plane
    def P_s(s):
        return P(H / math.tan(s))

    grid = np.linspace(0.002, math.pi - 0.002, 241)
    vals = np.array([P_s(s) for s in grid])
    k = int(np.argmin(vals))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    res = minimize_scalar(P_s, bounds=(lo, hi), method="bounded", options={"xatol": 1e-10})
    s = float(res.x) if res.fun <= vals[k] else float(grid[k])
    return P_s(s) / unit, H / math.tan(s)


def lancellotta_kp(phi_deg: float, delta_deg: float) -> float:
    """Lancellotta (2002, Geotechnique 52(8) 617-619) lower-bound passive coefficient,
    normal component, vertical wall, level fill:
    K_pn = cos(delta)/(1 - sin phi) [cos(delta) + sqrt(sin^2 phi - sin^2 delta)] exp(2 th tan phi),
    2 th = asin(sin delta / sin phi) + delta. Equal to EN 1997-1 Annex C.2 for these walls."""
    phi, d = math.radians(phi_deg), math.radians(delta_deg)
    th2 = math.asin(math.sin(d) / math.sin(phi)) + d
    return (math.cos(d) / (1 - math.sin(phi)) * (math.cos(d) + math.sqrt(math.sin(phi) ** 2 - math.sin(d) ** 2))
            * math.exp(th2 * math.tan(phi)))


def log_spiral(soil: Soil, wall: Wall) -> Profile:
    """Terzaghi's trial log-spiral passive pressure (module docstring). Vertical back,
    level fill, 0 <= delta <= phi. The distribution is linear by convention (the method
    gives resultants only): weight part at H/3, surcharge part at H/2.
    Profile.K is the weight coefficient along the resultant; Kh its horizontal part."""
    require_vertical_level("Terzaghi's log-spiral", wall)
    check_wall_friction(soil, wall)
    if wall.delta_deg < 0:
        raise InvalidParameter("delta", wall.delta_deg, f"[0, phi] = [0, {soil.phi_deg:g}] deg",
                               "the log-spiral passive case is set up for the soil rising along the wall")
    K, t = terzaghi_log_spiral_kp(soil.phi_deg, wall.delta_deg)
    Kq = terzaghi_log_spiral_kp(soil.phi_deg, wall.delta_deg, part="q")[0] if wall.surcharge > 0 else K
    H, g, q = wall.height, soil.unit_weight, wall.surcharge
    z = depth_grid(H, 201)
    cd = math.cos(wall.delta)
    p = K * g * z + Kq * q                  # along the resultant, per unit (vertical) face length
    P_g, P_q = 0.5 * K * g * H**2, Kq * q * H
    thrust = P_g + P_q
    height = (P_g * H / 3 + P_q * H / 2) / thrust
    return Profile(method="log-spiral", z=z, sigma_h=p * cd, tau=-p * math.sin(wall.delta),
                   thrust=thrust, thrust_h=thrust * cd, height=height, K=K, Kh=K * cd, H=H,
                   source=TERZAGHI, notes="Terzaghi variant; linear distribution by convention",
                   extra={"passive": True, "variant": "terzaghi", "K_q": Kq, "centre_t_over_H": t,
                          "thrust_q": P_q})
