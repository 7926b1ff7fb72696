"""Arching theories of active pressure on a rough translating wall.

All three share one model (Handy 1985; Paik & Salgado 2003; Khosravi et al. 2016):
a horizontal flat element of width B(z) = (H - z) cot(theta) spans the Rankine wedge
between the wall and a planar slip surface through the heel at theta = 45 + phi/2 from
horizontal. Inside the element the minor principal stress follows an arch, so the
wall stress is a fixed multiple of the *average* vertical stress:
sigma_hw = K_w sigma_v_avg, tau_w = sigma_hw tan(delta). Vertical equilibrium of the
element gives

    d sigma_v_avg / dz + a sigma_v_avg / (H - z) = gamma,   sigma_v_avg(0) = q
    sigma_v_avg(z) = gamma H / (1 - a) [ u^a - u ] + q u^a,       u = 1 - z/H
    (a = 1:  -gamma H u ln u + q u)

The methods differ in K_w and in how the slip surface enters the exponent ``a``
(docs/reference/analytic-formulas.md sections 4-6; /work research note):

=================  ==============================  ======================================
method             K_w                             exponent a
=================  ==============================  ======================================
paik-salgado       K_an (circular arch)            K_an tan(delta) tan(theta)        (iii)
handy              1.06 (cos^2 th + Ka sin^2 th)   K_w tan(th) [tan(delta) + cot(th - phi)] - 1   (i)
khosravi           K_an (circular arch)            K_an tan(delta) tan(th) + sigma_1/sigma_v_avg - 1  (ii)
=================  ==============================  ======================================

Status, said plainly (and printed by the CLI): none of the three papers could be read.
theta_w and K_an (Paik & Salgado) and K_w (Handy) are confident; the profiles are not:

* Paik & Salgado: exponent (iii) is what the only public re-implementation found uses
  (GitHub r0664245/stability-of-retainingwalls, Stressdistribution.py); it matches a
  recalled "1 - K_an tan(delta) tan(theta)" denominator. Not confirmed against the paper.
  ``exponent="i"`` gives the form consistent with full Coulomb friction on the slip plane.
* Handy: his printed wall-pressure equation was not found. This is the reconstruction
  documented in analytic-formulas.md section 4 (flat element, form (i), Handy's K_w).
  It is NOT Handy's curve (Khosravi et al.'s DEM paper says Handy fits poorly where
  Paik & Salgado fit well; this reconstruction is close to Paik & Salgado).
* Khosravi et al. (2016): equations not found. This reconstruction follows what the
  DEM paper says they added, a two-dimensional stress state across the element: the
  arch's stresses at any point of the element (``arch_stress_across``) and, at the slip
  surface, the arch's own stress (sigma_1 vertical) instead of the element average.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad

from .classical import rankine_coefficient
from .errors import InvalidParameter, NotApplicable
from .inputs import Soil, Wall, check_wall_friction, require_vertical_level
from .profile import Profile, depth_grid

_GRID = 401


def _checks(name: str, soil: Soil, wall: Wall) -> None:
    require_vertical_level(name, wall)
    check_wall_friction(soil, wall)
    if wall.delta_deg < 0.0:
        raise NotApplicable("delta", wall.delta_deg, f"[0, phi] = [0, {soil.phi_deg:g}] deg",
                            f"{name} is an active theory for a rough wall")


def passive_ratio(phi: float) -> float:
    """N = (1 + sin phi) / (1 - sin phi) = tan^2(45 + phi/2)."""
    s = math.sin(phi)
    return (1 + s) / (1 - s)


def principal_rotation_at_wall(phi: float, delta: float) -> float:
    """theta_w [rad]: angle of the major principal stress at the wall from horizontal
    (Paik & Salgado 2003). Root of tan(delta) = (N - 1) t / (N + t^2), t = tan(theta_w),
    that tends to 90 deg as delta -> 0; equals 45 + phi/2 at delta = phi."""
    if delta <= 0.0:
        return math.pi / 2
    N = passive_ratio(phi)
    td = math.tan(delta)
    disc = (N - 1) ** 2 - 4 * N * td * td
    disc = max(disc, 0.0)  # exactly 0 at delta = phi; rounding must not make it negative
    return math.atan(((N - 1) + math.sqrt(disc)) / (2 * td))


def paik_salgado_coefficient(phi: float, delta: float) -> float:
    """K_an = sigma_hw / sigma_v_avg = 3 (N cos^2 th_w + sin^2 th_w) / (3N - (N - 1) cos^2 th_w)
    (Paik & Salgado 2003; circular minor-principal arc). Equals Ka at delta = 0."""
    N = passive_ratio(phi)
    c2 = math.cos(principal_rotation_at_wall(phi, delta)) ** 2
    return 3 * (N * c2 + (1 - c2)) / (3 * N - (N - 1) * c2)


def handy_coefficient(phi: float) -> float:
    """Handy (1985) K_w = 1.06 (cos^2 theta + Ka sin^2 theta), theta = 45 + phi/2 (fully
    rough wall, catenary arch; 1.06 is the rounded catenary averaging factor, 1.05-1.07)."""
    th = math.pi / 4 + phi / 2
    ka = rankine_coefficient(phi, 0.0)
    return 1.06 * (math.cos(th) ** 2 + ka * math.sin(th) ** 2)


def arch_crown_ratio(phi: float, delta: float) -> float:
    """sigma_1 / sigma_v_avg for the circular arch: 3N / (3N - (N - 1) cos^2 theta_w)."""
    N = passive_ratio(phi)
    c2 = math.cos(principal_rotation_at_wall(phi, delta)) ** 2
    return 3 * N / (3 * N - (N - 1) * c2)


def arch_stress_across(phi: float, delta: float, x_over_B: np.ndarray,
                       sigma_v_avg: float = 1.0) -> dict[str, np.ndarray]:
    """Stresses across a flat element at positions x/B (0 = wall, 1 = slip surface) from
    the circular minor-principal arc with sigma_1 constant along it (Paik & Salgado's arch;
    the 2D stress state behind the Khosravi reconstruction). Returns sigma_v, sigma_h,
    tau_xz [same unit as sigma_v_avg]; the arc is a circle with centre on the slip side,
    so the principal angle theta(x) satisfies cos(theta) = (1 - x/B) cos(theta_w)."""
    N = passive_ratio(phi)
    th_w = principal_rotation_at_wall(phi, delta)
    s1 = sigma_v_avg * arch_crown_ratio(phi, delta)
    s3 = s1 / N
    c = (1.0 - np.asarray(x_over_B, dtype=float)) * math.cos(th_w)
    s = np.sqrt(1.0 - c * c)
    return {"sigma_v": s1 * s * s + s3 * c * c, "sigma_h": s1 * c * c + s3 * s * s,
            "tau_xz": (s1 - s3) * s * c}


def _flat_element(method: str, soil: Soil, wall: Wall, K_w: float, a: float, *, source: str,
                  status: str, notes: str, extra: dict) -> Profile:
    """Profile of sigma_hw = K_w sigma_v_avg(z) with exponent ``a`` (module docstring)."""
    H, g, q = wall.height, soil.unit_weight, wall.surcharge
    if abs(a) < 1e-12:
        a = 0.0  # delta = 0 gives a = 0 exactly; rounding must not make u**a blow up at the heel

    def sig_v(z):
        u = np.clip(1.0 - np.asarray(z, dtype=float) / H, 0.0, 1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            if abs(1.0 - a) < 1e-9:
                core = np.where(u > 0, -u * np.log(np.where(u > 0, u, 1.0)), 0.0)
            else:
                core = (u**a - u) / (1.0 - a)
        return g * H * core + q * u**a

    # u^a - u falls to 0 within a vanishing distance of the heel when a is small: refine
    # geometrically there so the tabulated profile integrates to its thrust
    u = np.unique(np.concatenate([np.linspace(0.0, 1.0, _GRID), np.geomspace(1e-12, 0.05, 120)]))
    z = H * (1.0 - u[::-1])
    sigma = K_w * sig_v(z)
    tau = sigma * math.tan(wall.delta)
    N = quad(lambda s: K_w * float(sig_v(s)), 0.0, H, epsabs=0, epsrel=1e-11, limit=200)[0]
    M = quad(lambda s: K_w * float(sig_v(s)) * s, 0.0, H, epsabs=0, epsrel=1e-11, limit=200)[0]
    thrust = N / math.cos(wall.delta)
    unit = 0.5 * g * H**2
    return Profile(method=method, z=z, sigma_h=sigma, tau=tau, thrust=thrust, thrust_h=N,
                   height=H - M / N, K=thrust / unit, Kh=N / unit, H=H, source=source,
                   status=status, notes=notes, extra={"K_w": K_w, "a": a, **extra})


def paik_salgado(soil: Soil, wall: Wall, exponent: str = "iii") -> Profile:
    """Paik & Salgado (2003) arching profile behind a translating rough wall.

    theta_w, K_an: Paik & Salgado (2003) as in analytic-formulas.md 5.1 (confident).
    exponent "iii" (default): a = K_an tan(delta) tan(45 + phi/2), the form of the public
    re-implementation (slip-surface vertical stress = element average); "i": a =
    K_an tan(theta) [tan(delta) + cot(theta - phi)] - 1 (full Coulomb reaction on the slip
    surface; its thrust equals the Coulomb force on the 45 + phi/2 plane). Either way the
    profile is a reconstruction, not checked against the paper.
    """
    _checks("Paik-Salgado", soil, wall)
    phi, d = soil.phi, wall.delta
    th = math.pi / 4 + phi / 2
    K_an = paik_salgado_coefficient(phi, d)
    if exponent == "iii":
        a = K_an * math.tan(d) * math.tan(th)
    elif exponent == "i":
        a = K_an * math.tan(th) * (math.tan(d) + 1.0 / math.tan(th - phi)) - 1.0
    else:
        raise InvalidParameter("exponent", exponent, "'iii' or 'i'")
    return _flat_element(
        "paik-salgado", soil, wall, K_an, a,
        source="Paik & Salgado (2003), Geotechnique 53(7): theta_w, K_an; flat-element profile",
        status="reconstruction",
        notes=f"profile exponent form ({exponent}) not checked against the paper",
        extra={"theta_w_deg": math.degrees(principal_rotation_at_wall(phi, d)), "exponent": exponent})


def handy(soil: Soil, wall: Wall) -> Profile:
    """Handy (1985) arching coefficient K_w with the documented reconstruction of the
    profile (flat element, exponent form (i); analytic-formulas.md section 4). Handy's
    own wall-pressure equation was not found: this is NOT his published curve. K_w
    assumes a fully rough wall (delta = phi); wall shear uses the given delta."""
    _checks("Handy", soil, wall)
    phi, d = soil.phi, wall.delta
    th = math.pi / 4 + phi / 2
    K_w = handy_coefficient(phi)
    a = K_w * math.tan(th) * (math.tan(d) + 1.0 / math.tan(th - phi)) - 1.0
    return _flat_element(
        "handy", soil, wall, K_w, a,
        source="Handy (1985) K_w = 1.06(cos^2 th + Ka sin^2 th); profile: wallsim reconstruction",
        status="reconstruction",
        notes="Handy's printed profile not found; reconstruction, not the paper's curve",
        extra={"theta_deg": math.degrees(th)})


def khosravi(soil: Soil, wall: Wall) -> Profile:
    """Reconstruction in the spirit of Khosravi, Pipatpongsa & Takemura (2016): the arch's
    2D stress state across the element (``arch_stress_across``), with the slip-surface
    traction taken from the arch (sigma_1 vertical there) rather than the element mean:
    a = K_an tan(delta) tan(theta) + sigma_1/sigma_v_avg - 1. Their published equations
    were not available: this is NOT the paper's formula."""
    _checks("Khosravi", soil, wall)
    phi, d = soil.phi, wall.delta
    th = math.pi / 4 + phi / 2
    K_an = paik_salgado_coefficient(phi, d)
    a = K_an * math.tan(d) * math.tan(th) + arch_crown_ratio(phi, d) - 1.0
    return _flat_element(
        "khosravi", soil, wall, K_an, a,
        source="after Khosravi et al. (2016), Soils Found. 56(4): 2D arch stress in the element; "
               "wallsim reconstruction",
        status="reconstruction",
        notes="Khosravi et al. (2016) equations not found; reconstruction, not the paper's formula",
        extra={"theta_w_deg": math.degrees(principal_rotation_at_wall(phi, d)),
               "sigma1_over_mean": arch_crown_ratio(phi, d)})
