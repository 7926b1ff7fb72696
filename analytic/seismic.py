"""Pseudo-static seismic thrust: Mononobe-Okabe and the Seed & Whitman simplification.

Formulas: docs/reference/analytic-formulas.md section 8 (checked against the
EN 1998-5 example K_ad = 0.4856177, K_pd = 2.6, and a pseudo-static trial wedge).
kh, kv are the horizontal and vertical seismic coefficients; kv > 0 is upward
(reduces the weight), as in Das/Kramer.
"""

from __future__ import annotations

import math

import numpy as np

from .classical import _coulomb_checks, coulomb, coulomb_coefficient, trial_wedge
from .errors import InvalidParameter
from .inputs import Soil, Wall, require_number, require_vertical_level
from .profile import Profile, depth_grid

#: Seed & Whitman (1970): the dynamic increment acts at 0.6 H above the base. A linear
#: stress p(z) = a (1 - 0.75 z/H) has its resultant exactly there.
_SW_SHAPE = 0.75


def inertia_angle(kh: float, kv: float) -> float:
    """psi = atan(kh / (1 - kv)) [rad], the tilt of the pseudo-static gravity."""
    return math.atan2(kh, 1.0 - kv)


def _seismic_inputs(kh, kv):
    kh = require_number("kh", kh, 0.0, 1.0, lo_open=False)
    kv = require_number("kv", kv, -1.0, 1.0)
    return kh, kv


def mononobe_okabe_coefficient(phi, delta, omega, beta, kh, kv, passive=False) -> float:
    """K_AE or K_PE (Okabe 1926; Mononobe & Matsuo 1929), angles in rad; the thrust is
    P = 0.5 gamma H^2 (1 - kv) K. nan where no real solution exists."""
    psi = inertia_angle(kh, kv)
    if not passive:
        den = math.cos(delta + omega + psi) * math.cos(beta - omega)
        arg = math.sin(phi + delta) * math.sin(phi - beta - psi) / den if den > 0 else -1.0
        if arg < 0:
            return math.nan
        return math.cos(phi - psi - omega) ** 2 / (
            math.cos(psi) * math.cos(omega) ** 2 * math.cos(delta + omega + psi) * (1 + math.sqrt(arg)) ** 2)
    den = math.cos(delta - omega + psi) * math.cos(beta - omega)
    arg = math.sin(phi + delta) * math.sin(phi + beta - psi) / den if den > 0 else -1.0
    if arg < 0 or math.sqrt(arg) >= 1.0:
        return math.nan
    return math.cos(phi - psi + omega) ** 2 / (
        math.cos(psi) * math.cos(omega) ** 2 * math.cos(delta - omega + psi) * (1 - math.sqrt(arg)) ** 2)


def mononobe_okabe(soil: Soil, wall: Wall, kh: float, kv: float = 0.0,
                   passive: bool = False) -> Profile:
    """Mononobe-Okabe pseudo-static thrust P_AE = 0.5 gamma H^2 (1 - kv) K_AE at delta to
    the face normal (``K`` of the Profile is (1 - kv) K_AE). Active distribution: the
    static Coulomb part linear (at H/3) plus the increment P_AE - P_A at 0.6 H
    (Seed & Whitman 1970 practice). Passive: linear (a convention; M-O gives only the
    resultant). Requires phi - beta - psi >= 0 (active), phi + beta - psi >= 0 (passive)."""
    kh, kv = _seismic_inputs(kh, kv)
    _coulomb_checks(soil, wall, passive)
    psi = inertia_angle(kh, kv)
    if not passive and soil.phi - wall.beta - psi < 0:
        lim = (1 - kv) * math.tan(soil.phi - wall.beta)
        raise InvalidParameter("kh", kh, f"[0, (1 - kv) tan(phi - beta)] = [0, {lim:.4g}]",
                               "the inertia angle leaves no active Mononobe-Okabe wedge")
    if passive and soil.phi + wall.beta - psi < 0:
        lim = (1 - kv) * math.tan(soil.phi + wall.beta)
        raise InvalidParameter("kh", kh, f"[0, (1 - kv) tan(phi + beta)] = [0, {lim:.4g}]",
                               "the inertia angle leaves no passive Mononobe-Okabe wedge")
    KE = mononobe_okabe_coefficient(soil.phi, wall.delta, wall.omega, wall.beta, kh, kv, passive)
    if not math.isfinite(KE):
        raise InvalidParameter("kh", kh, "a range with a finite Mononobe-Okabe solution for these angles")
    static = coulomb(soil, wall, passive)
    # total thrust incl. surcharge: the same wedge load as Coulomb's, scaled by (1-kv) K_E / K_C
    K_C = coulomb_coefficient(soil.phi, wall.delta, wall.omega, wall.beta, passive)
    total = (1.0 - kv) * KE * static.thrust / K_C
    H, g = wall.height, soil.unit_weight
    unit = 0.5 * g * H**2
    direction = wall.delta if not passive else -wall.delta
    horiz = math.cos(direction + wall.omega)
    z = static.z
    if passive:
        scale = total / static.thrust
        sig, tau = static.sigma_h * scale, static.tau * scale
        thrust = static.thrust * scale
        height = static.height
    else:
        dP = total - static.thrust                          # increment of the resultant [N/m]
        shape = 1.0 - _SW_SHAPE * z / H                     # integrates to 0.625 H
        dp = dP / (0.625 * H) * shape * math.cos(wall.omega)
        sig = static.sigma_h + dp * math.cos(direction)
        tau = static.tau + dp * math.sin(direction)
        thrust = static.thrust + dP
        height = (static.thrust * static.height + dP * 0.6 * H) / thrust
    K_trial, rho = trial_wedge(soil, wall, passive=passive, kh=kh, kv=kv)
    return Profile(method="mononobe-okabe", z=z, sigma_h=sig, tau=tau, thrust=thrust,
                   thrust_h=thrust * horiz, height=height, K=thrust / unit,
                   Kh=thrust * horiz / unit, H=H, omega_deg=wall.omega_deg,
                   source="Mononobe-Okabe (1926/1929); EN 1998-5 Annex E; increment at 0.6H (Seed & Whitman 1970)",
                   notes="" if not passive else "passive distribution linear by convention",
                   extra={"K_E": KE, "kh": kh, "kv": kv, "psi_deg": math.degrees(psi),
                          "wedge_angle_deg": math.degrees(rho), "K_trial_wedge": K_trial,
                          "passive": passive})


def seed_whitman(soil: Soil, wall: Wall, kh: float) -> Profile:
    """Seed & Whitman (1970): K_AE ~ K_A + 0.75 kh, the increment 3/8 kh gamma H^2 taken
    horizontal at 0.6 H; static Coulomb part unchanged. Vertical wall, level backfill,
    derived for phi ~ 35 deg (within ~0.04 of M-O for kh <= 0.2, phi 20.7-39)."""
    kh = require_number("kh", kh, 0.0, 1.0, lo_open=False)
    require_vertical_level("Seed-Whitman", wall)
    static = coulomb(soil, wall)
    H, g = wall.height, soil.unit_weight
    unit = 0.5 * g * H**2
    dP = 0.75 * kh * unit
    z = static.z
    dp = dP / (0.625 * H) * (1.0 - _SW_SHAPE * z / H)
    thrust_h = static.thrust_h + dP
    thrust = static.thrust + dP
    height = (static.thrust_h * static.height + dP * 0.6 * H) / thrust_h
    return Profile(method="seed-whitman", z=z, sigma_h=static.sigma_h + dp, tau=static.tau,
                   thrust=thrust, thrust_h=thrust_h, height=height, K=thrust / unit,
                   Kh=thrust_h / unit, H=H,
                   source="Seed & Whitman (1970): K_AE = K_A + 0.75 kh, increment at 0.6 H",
                   notes="increment taken horizontal; K adds it to the inclined Coulomb resultant",
                   extra={"kh": kh})
