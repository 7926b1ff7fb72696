"""Ultimate-limit-state checks of a wall on its base: sliding, overturning, bearing,
eccentricity, and the base pressure distribution.

Each check returns E_d (effect of the actions), R_d (resistance) and the utilisation
E_d / R_d (<= 1 passes). With every partial factor 1 the utilisation is the reciprocal
of the classical factor of safety, whose textbook convention is followed:
* sliding (EN 1997-1 6.5.3, eq. 6.3a): E = H, R = (V tan delta_b,d + a B) / gamma_R;h
  (+ passive P_p,d / gamma_R;e when switched on); undrained R = A' c_u,d / gamma_R;h
  (eq. 6.4a);
* overturning about the toe: E = sum of overturning moments (horizontal pushes, uplift),
  R = sum of restoring moments (weights, the vertical component of the thrust, water in
  front); passive resistance is not counted;
* bearing (Annex D, ``bearing.py``): E = V, R = q_ult B' / gamma_R;v, B' = B - 2 e;
* eccentricity: e against B/6 (resultant in the middle third: classical, no tension
  under the base) or B/3 (middle two thirds, EN 1997-1 6.5.4(1)P).
Units kN/m, kN m/m, m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .actions import Force


@dataclass(frozen=True)
class Check:
    """E_d, R_d [kN/m, kN m/m or m] and utilisation E_d / R_d (inf if R_d = 0)."""

    name: str
    E_d: float
    R_d: float
    utilisation: float
    note: str = ""


def make_check(name: str, E: float, R: float, note: str = "") -> Check:
    u = E / R if R > 0 else (0.0 if E <= 0 else math.inf)
    return Check(name, E, R, u, note)


def unfavourable(f: Force, check: str, tan_db: float) -> bool:
    """Whether a force as a whole acts against the check (EN 1997-1 2.4.2(9)P): for
    sliding if Fh - Fv tan(delta_b) > 0, for overturning if its moment about the toe
    Fh y - Fv x > 0; for 'bearing' every action counts as unfavourable."""
    if check == "sliding":
        return f.Fh - f.Fv * tan_db > 0
    if check == "overturning":
        return f.Fh * f.y - f.Fv * f.x > 0
    return True


def factor_of(f: Force, combo, check: str, tan_db: float, single_source: bool) -> float:
    """The partial factor on one force in one check (1 for inertia and passive)."""
    if f.kind in ("E", "P"):
        return 1.0
    table = combo.structural_actions if f.source == "structural" else combo.actions
    bad = unfavourable(f, check, tan_db)
    if f.kind == "Q":
        return table["Q_unfav"] if bad else table["Q_fav"]
    return table["G_unfav"] if bad or single_source else table["G_fav"]


def resultant(forces: list[Force], factors: list[float]) -> tuple[float, float, float]:
    """Design V, H [kN/m] and moment about the toe sum(Fv x - Fh y) [kN m/m] of the
    actions (passive resistance excluded)."""
    V = H = M = 0.0
    for f, g in zip(forces, factors):
        if f.kind == "P":
            continue
        V += g * f.Fv
        H += g * f.Fh
        M += g * (f.Fv * f.x - f.Fh * f.y)
    return V, H, M


def eccentricity(V: float, M_toe: float, B: float) -> float:
    """e = B/2 - M_toe / V [m], positive toward the toe (inf if V <= 0)."""
    return B / 2 - M_toe / V if V > 0 else math.inf


def overturning_moments(forces: list[Force], factors: list[float], *, net: bool = False) -> tuple[float, float]:
    """(M_dst, M_stb) about the toe [kN m/m]. Default (textbook factor-of-safety
    convention): each force split into its horizontal and vertical moments, so the
    vertical thrust component restores. ``net``: each force's net moment Fh y - Fv x
    counts as destabilising or restoring as a whole (the convention of the JRC worked
    example A.4 / Bond & Harris for EC7 toppling)."""
    dst = stb = 0.0
    for f, g in zip(forces, factors):
        if f.kind == "P":
            continue
        parts = (f.Fh * f.y - f.Fv * f.x,) if net else (f.Fh * f.y, -f.Fv * f.x)
        for m in parts:
            if m > 0:
                dst += g * m
            else:
                stb -= g * m
    return dst, stb


def base_pressure(V: float, e: float, B: float, n: int = 201) -> tuple[np.ndarray, np.ndarray]:
    """Contact pressure q(x) [kPa] under a rigid base (x from the toe [m]), linear, no
    tension: trapezoid V/B (1 +- 6e/B) for |e| <= B/6, else a triangle over
    3 (B/2 - |e|) from the more loaded edge with peak 2V / (3 (B/2 - |e|))."""
    x = np.linspace(0.0, B, n)
    if abs(e) >= B / 2:
        return x, np.full_like(x, np.inf)
    if abs(e) <= B / 6:
        return x, V / B * (1 + 6 * e / B * (1 - 2 * x / B))
    a = B / 2 - abs(e)
    s = x if e > 0 else B - x
    q = np.clip(2 * V / (3 * a) * (1 - s / (3 * a)), 0.0, None)
    return x, q
