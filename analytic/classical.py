"""Classical earth-pressure theories: Rankine, Coulomb, Jaky, Janssen.

Formulas, conventions and checked numbers: docs/reference/analytic-formulas.md
sections 1-3 and 9 (and ``analytic-values.txt``). All functions take the frozen
``Soil`` and ``Wall`` records and return a ``Profile`` (see ``profile.py`` for signs).

Surcharge q is a vertical load per unit *horizontal* area of the backfill surface.
For a planar wedge it adds q * L_x to the weight, which is the same as adding
``2 q cos(beta) cos(omega) / (gamma H cos(omega - beta))`` to the unit of
``0.5 gamma H^2`` (derived from the wedge area; reduces to q H for omega = beta = 0).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from .errors import InvalidParameter
from .inputs import Soil, Wall, check_wall_friction, require_number, require_vertical_level
from .profile import Profile, depth_grid

_GRID = 201


def _surcharge_factor(wall: Wall) -> float:
    """Ratio of the surcharge's wedge load to q * H (planar wedge through the heel)."""
    return math.cos(wall.beta) * math.cos(wall.omega) / math.cos(wall.omega - wall.beta)


def _linear_profile(method: str, soil: Soil, wall: Wall, K: float, direction: float,
                    source: str, *, status: str = "verified", notes: str = "",
                    extra: dict | None = None) -> Profile:
    """Profile for a coefficient K whose resultant acts at ``direction`` [rad] from the
    face normal (positive = shear down the face), distributed linearly in depth
    (the usual convention: Coulomb itself gives only the resultant)."""
    H, g, q = wall.height, soil.unit_weight, wall.surcharge
    qe = q * _surcharge_factor(wall)
    z = depth_grid(H, _GRID)
    # stress along the face, per unit face length: p(s) with ds = dz / cos(omega)
    p = K * (g * z + qe) * math.cos(wall.omega)
    sigma = p * math.cos(direction)
    tau = p * math.sin(direction)
    thrust = K * (0.5 * g * H**2 + qe * H)
    # height of the resultant: triangle at H/3, rectangle at H/2
    moment = K * (0.5 * g * H**2 * H / 3 + qe * H * H / 2)
    height = moment / thrust if thrust > 0 else H / 3
    horiz = math.cos(direction + wall.omega)
    # K stays the soil coefficient with a surcharge; the surcharge's thrust is reported apart
    extra = {**(extra or {}), "thrust_q": K * qe * H}
    return Profile(method=method, z=z, sigma_h=sigma, tau=tau, thrust=thrust,
                   thrust_h=thrust * horiz, height=height, K=K,
                   Kh=K * horiz, H=H, omega_deg=wall.omega_deg,
                   source=source, status=status, notes=notes, extra=extra)


# --------------------------------------------------------------------------- Rankine
def rankine_coefficient(phi: float, beta: float, passive: bool = False) -> float:
    """Rankine K for a vertical wall and backfill slope beta [rad] (Nadukuru & Michalowski
    2012 eq. 5). The wall stress K gamma z acts parallel to the backfill surface.
    Requires |beta| <= phi."""
    cb = math.cos(beta)
    root = math.sqrt(max(cb * cb - math.cos(phi) ** 2, 0.0))
    if passive:
        return cb * (cb + root) / (cb - root)
    return cb * (cb - root) / (cb + root)


def rankine(soil: Soil, wall: Wall, passive: bool = False) -> Profile:
    """Rankine (1857) active or passive pressure, sloping backfill (Nadukuru & Michalowski
    2012, eqs. 1-5): sigma_w = K (gamma z + q) parallel to the surface, resultant at H/3
    for q = 0. Rankine's stress is inclined at beta, so the wall is implicitly rough
    enough to carry it; wall friction delta is not used. Vertical back only."""
    require_vertical_level("Rankine", wall, level=False)
    if abs(wall.beta_deg) > soil.phi_deg:
        raise InvalidParameter("beta", wall.beta_deg, f"[-phi, phi] = [{-soil.phi_deg:g}, {soil.phi_deg:g}] deg",
                               "Rankine has no real solution for a slope steeper than phi")
    K = rankine_coefficient(soil.phi, wall.beta, passive)
    # active: traction parallel to the surface points down-slope toward the wall -> shear down the face
    direction = wall.beta if not passive else -wall.beta
    return _linear_profile("rankine", soil, wall, K, direction,
                           "Rankine (1857); Nadukuru & Michalowski (2012) eq. 5",
                           extra={"passive": passive})


# --------------------------------------------------------------------------- Coulomb
def _coulomb_checks(soil: Soil, wall: Wall, passive: bool) -> None:
    check_wall_friction(soil, wall)
    if not passive and wall.beta_deg > soil.phi_deg:
        raise InvalidParameter("beta", wall.beta_deg, f"<= phi = {soil.phi_deg:g} deg",
                               "no active Coulomb wedge on a slope steeper than phi")
    if passive and -wall.beta_deg > soil.phi_deg:
        raise InvalidParameter("beta", wall.beta_deg, f">= -phi = {-soil.phi_deg:g} deg",
                               "no passive Coulomb wedge below a slope falling faster than phi")
    if abs(wall.omega_deg - wall.beta_deg) >= 90.0:
        raise InvalidParameter("omega", wall.omega_deg, f"(beta - 90, beta + 90) deg")


def coulomb_coefficient(phi: float, delta: float, omega: float, beta: float,
                        passive: bool = False) -> float:
    """Mueller-Breslau form of Coulomb's K (resultant at delta to the face normal).
    Angles in rad; conventions of analytic-formulas.md section 1. Returns nan where the
    square root or the passive denominator has no real, positive value."""
    if not passive:
        den_root = math.cos(delta + omega) * math.cos(omega - beta)
        arg = math.sin(phi + delta) * math.sin(phi - beta) / den_root
        if arg < 0 or den_root <= 0:
            return math.nan
        return math.cos(phi - omega) ** 2 / (
            math.cos(omega) ** 2 * math.cos(delta + omega) * (1 + math.sqrt(arg)) ** 2)
    den_root = math.cos(delta - omega) * math.cos(beta - omega)
    arg = math.sin(phi + delta) * math.sin(phi + beta) / den_root
    if arg < 0 or den_root <= 0 or math.sqrt(arg) >= 1.0:
        return math.nan
    return math.cos(phi + omega) ** 2 / (
        math.cos(omega) ** 2 * math.cos(delta - omega) * (1 - math.sqrt(arg)) ** 2)


def coulomb(soil: Soil, wall: Wall, passive: bool = False) -> Profile:
    """Coulomb (1776) active or passive thrust, with wall friction delta, back-face
    inclination omega and backfill slope beta (Mueller-Breslau trigonometric form;
    analytic-formulas.md section 2; checked against Das Table 6.4). The resultant acts
    at delta to the face normal; its linear distribution over depth is a convention.
    ``extra['wedge_angle_deg']`` is the critical slip-plane angle from horizontal."""
    _coulomb_checks(soil, wall, passive)
    K = coulomb_coefficient(soil.phi, wall.delta, wall.omega, wall.beta, passive)
    if not math.isfinite(K):
        side = "passive" if passive else "active"
        if math.isfinite(coulomb_coefficient(soil.phi, 0.0, wall.omega, wall.beta, passive)):
            raise InvalidParameter("delta", wall.delta_deg, f"values where the {side} Coulomb wedge has a finite "
                                   "solution for this phi, omega and beta")
        raise InvalidParameter("omega", wall.omega_deg, f"face inclinations where the {side} Coulomb wedge has a "
                               "finite solution for this phi and beta")
    K_trial, rho = trial_wedge(soil, wall, passive=passive)
    direction = wall.delta if not passive else -wall.delta
    notes = "planar-wedge Kp is unconservative for rough walls (delta > phi/2)" \
        if passive and abs(wall.delta_deg) > soil.phi_deg / 2 else ""
    return _linear_profile("coulomb", soil, wall, K, direction,
                           "Coulomb (1776), Mueller-Breslau form; Das Table 6.4",
                           notes=notes,
                           extra={"passive": passive, "wedge_angle_deg": math.degrees(rho),
                                  "K_trial_wedge": K_trial})


def trial_wedge(soil: Soil, wall: Wall, passive: bool = False, kh: float = 0.0,
                kv: float = 0.0) -> tuple[float, float]:
    """Brute-force planar trial wedge (the force polygon solved for every slip angle).

    Heel at (0, 0), face top at (-H tan omega, H), backfill on x > 0, slip plane from the
    heel at rho [rad] from horizontal. Weight W(1 - kv) down, inertia kh W toward the wall
    (active) or away from it (passive). Returns (K, rho*) with K = 2 P / (gamma H^2),
    maximised over rho for the active case and minimised for the passive case.
    Independent of the closed forms, so it checks them (analytic-formulas.md section 11).
    """
    H, g = wall.height, soil.unit_weight
    phi, d, om, b = soil.phi, wall.delta, wall.omega, wall.beta
    top_x, top_y = -H * math.tan(om), H
    sx, sy = math.cos(b), math.sin(b)
    sign = -1.0 if passive else 1.0
    px, py = math.cos(om + sign * d), math.sin(om + sign * d)

    def thrust(rho):
        """P(rho) for an array of slip angles (2x2 systems solved by Cramer's rule)."""
        rho = np.asarray(rho, dtype=float)
        ux, uy = np.cos(rho), np.sin(rho)
        # slip line heel + t u meets the surface top + s (sx, sy)
        t = (-top_x * sy + sx * top_y) / (-ux * sy + sx * uy)
        Sx, Sy = t * ux, t * uy
        area = 0.5 * np.abs(top_x * Sy - top_y * Sx)
        W = g * area + wall.surcharge * (Sx - top_x)
        ex, ey = -sign * kh * W, -(1.0 - kv) * W        # inertia toward the wall when active
        rx, ry = -np.sin(rho - sign * phi), np.cos(rho - sign * phi)
        # passive: at the one slip angle where R is parallel to P no wedge balances (P
        # infinite), and the minimum over the grid passes it by
        with np.errstate(divide="ignore"):
            return (-ex * ry + ey * rx) / (px * ry - py * rx)

    # the slip plane must cut the surface (rho > beta) and stay in front of the face; an
    # active wedge under inertia can slip below phi, down to phi - psi (psi the inertia angle)
    psi = math.atan2(kh, 1.0 - kv)
    lo = (b if passive else max(phi - psi, b)) + 1e-6
    hi = math.pi / 2 + om - 1e-6
    if lo >= hi:
        raise InvalidParameter("omega", math.degrees(om), f"> {math.degrees(lo) - 90:.1f} deg",
                               "the face leans so far over the fill that no slip plane fits between it and phi")
    grid = np.linspace(lo, hi, 2001)
    vals = thrust(grid)
    if passive:
        vals = np.where(vals > 0, vals, np.inf)
        k = int(np.argmin(vals))
    else:
        k = int(np.argmax(vals))
    a, c = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    # P(rho) is unimodal between the bounds: refine inside the bracketing cell
    res = minimize_scalar(lambda r: float(thrust(r)) * (1.0 if passive else -1.0), bounds=(a, c),
                          method="bounded", options={"xatol": 1e-12})
    P = float(thrust(res.x))
    return 2 * P / (g * H**2), float(res.x)


# --------------------------------------------------------------------------- Jaky
def jaky_coefficient(phi: float, form: str = "1948") -> float:
    """Jaky at-rest coefficient: "1948" K0 = 1 - sin(phi) (the form everyone uses;
    Nadukuru & Michalowski 2012 quote 0.371 at 39 deg); "1944" the original
    (1 + 2/3 sin phi)(1 - sin phi)/(1 + sin phi) (from memory in the reference notes)."""
    s = math.sin(phi)
    if form == "1948":
        return 1.0 - s
    if form == "1944":
        return (1 + 2 * s / 3) * (1 - s) / (1 + s)
    raise InvalidParameter("form", form, "'1948' or '1944'")


def jaky(soil: Soil, wall: Wall, form: str = "1948") -> Profile:
    """At-rest pressure sigma_h = K0 (gamma z + q), horizontal, at H/3 (Jaky 1944/1948).
    Normally consolidated, level backfill, vertical back; no wall shear."""
    require_vertical_level("Jaky", wall)
    K0 = jaky_coefficient(soil.phi, form)
    return _linear_profile("jaky", soil, wall, K0, 0.0,
                           f"Jaky ({form}): K0 = " + ("1 - sin(phi)" if form == "1948" else
                                                      "(1 + 2/3 sin phi)(1 - sin phi)/(1 + sin phi)"),
                           status="verified" if form == "1948" else "reconstruction")


# --------------------------------------------------------------------------- Janssen
def janssen(soil: Soil, wall: Wall, width: float, k: float | None = None) -> Profile:
    """Janssen (1895) stress in a plane-strain slot of width B between the wall and a
    parallel rough boundary (narrow backfill; Kniss et al. 2007):

        d sigma_v/dz = gamma - lambda sigma_v,  lambda = 2 K tan(delta) / B
        sigma_v(z) = gamma/lambda (1 - exp(-lambda z)) + q exp(-lambda z),  sigma_h = K sigma_v

    K defaults to Jaky's K0 = 1 - sin(phi), the usual silo choice. The wall shear is
    tau = tan(delta) sigma_h, so the resultant acts at delta to the normal; as B -> inf
    the profile tends to K (gamma z + q). Checked against xcfem/xc test_k_janssen_01."""
    require_vertical_level("Janssen", wall)
    check_wall_friction(soil, wall)
    B = require_number("width", width, 0.0, None, unit="m")
    K = jaky_coefficient(soil.phi) if k is None else require_number("k", k, 0.0, None)
    H, g, q = wall.height, soil.unit_weight, wall.surcharge
    lam = 2.0 * K * math.tan(wall.delta) / B

    def sigma_v(z):
        return janssen_vertical_stress(z, g, q, lam)

    z = depth_grid(H, _GRID)
    sig = K * sigma_v(z)
    tau = sig * math.tan(wall.delta)
    N = quad(lambda s: K * float(sigma_v(s)), 0.0, H, epsabs=0, epsrel=1e-12)[0]
    M = quad(lambda s: K * float(sigma_v(s)) * s, 0.0, H, epsabs=0, epsrel=1e-12)[0]
    thrust = N / math.cos(wall.delta)
    unit = 0.5 * g * H**2
    return Profile(method="janssen", z=z, sigma_h=sig, tau=tau, thrust=thrust, thrust_h=N,
                   height=H - M / N, K=thrust / unit, Kh=N / unit, H=H,
                   source="Janssen (1895); plane-strain slot, Kniss et al. (2007)",
                   notes=f"backfill width B = {B:g} m, K = {K:.4f}",
                   extra={"width": B, "k": K, "lambda": lam})


def janssen_vertical_stress(z, gamma: float, q: float, lam: float) -> np.ndarray:
    """Janssen's mean vertical stress [Pa] at depth z [m]:
    gamma/lambda (1 - exp(-lambda z)) + q exp(-lambda z); gamma z + q as lambda -> 0."""
    z = np.asarray(z, dtype=float)
    if lam * max(float(np.max(z, initial=0.0)), 1.0) < 1e-12:
        return gamma * z + q
    return gamma / lam * (-np.expm1(-lam * z)) + q * np.exp(-lam * z)
