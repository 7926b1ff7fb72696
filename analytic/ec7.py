"""EN 1997-1:2004 Annex C.2: earth-pressure coefficients by the Annex's numerical procedure.

The Annex writes the procedure for the passive case; the active case follows by
replacing phi by -phi and delta by -delta (the Annex's own rule). For the passive case:

    cos(2 m_t + phi + beta) = -sin(beta) / sin(phi)                      (C.3)
    cos(2 m_w + phi + delta) = sin(delta) / sin(phi)                     (C.4)
    nu = m_t + beta - m_w - theta                                        (C.5)
    K_n = (1 + sin phi sin(2 m_w + phi)) / (1 - sin phi sin(2 m_t + phi)) exp(2 nu tan phi)   (C.6)
    K_q = K_n cos^2(beta)                                                (C.7)
    K_c = (K_n - 1) cot(phi)                                             (C.8)
    K_gamma = K_n cos(beta) cos(beta - theta)                            (C.9)

theta is the inclination of the back face from vertical, positive when the wall leans
away from the soil (the top behind the heel): wallsim's ``omega``. The coefficients give
the *normal* stress on the face per unit face length, e_n = K_gamma gamma z + K_q q
(- K_c c when active, + K_c c when passive), z the vertical depth. With delta = theta =
beta = 0 they are Rankine's (1 - sin phi)/(1 + sin phi) and its inverse.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import InvalidParameter
from .inputs import Soil, Wall, check_wall_friction
from .profile import Profile, depth_grid

SOURCE = "EN 1997-1:2004 Annex C.2, eqs. C.3-C.9"


@dataclass(frozen=True)
class AnnexCCoefficients:
    """Normal-component coefficients of EN 1997-1 Annex C.2 (dimensionless).

    K_n: base coefficient (C.6); K_q: uniform vertical surcharge (C.7);
    K_c: cohesion (C.8); K_gamma: soil weight (C.9)."""

    K_n: float
    K_q: float
    K_c: float
    K_gamma: float


def annex_c_coefficients(phi_deg: float, delta_deg: float = 0.0, beta_deg: float = 0.0,
                         theta_deg: float = 0.0, passive: bool = False) -> AnnexCCoefficients:
    """EN 1997-1 Annex C.2 coefficients (angles in degrees; see the module docstring).

    Requires |delta| <= phi and |beta| <= phi (no real m_t or m_w otherwise)."""
    if abs(delta_deg) > phi_deg + 1e-12:
        raise InvalidParameter("delta", delta_deg, f"[-phi, phi] = [{-phi_deg:g}, {phi_deg:g}] deg")
    if abs(beta_deg) > phi_deg + 1e-12:
        raise InvalidParameter("beta", beta_deg, f"[-phi, phi] = [{-phi_deg:g}, {phi_deg:g}] deg",
                               "EN 1997-1 Annex C has no real m_t for a slope steeper than phi")
    s = 1.0 if passive else -1.0          # the Annex's rule: active = passive with -phi, -delta
    phi, delta = s * math.radians(phi_deg), s * math.radians(delta_deg)
    beta, theta = math.radians(beta_deg), math.radians(theta_deg)
    sp = math.sin(phi)
    m_t = 0.5 * (math.acos(_clip(-math.sin(beta) / sp)) - phi - beta)
    m_w = 0.5 * (math.acos(_clip(math.sin(delta) / sp)) - phi - delta)
    nu = m_t + beta - m_w - theta
    K_n = (1 + sp * math.sin(2 * m_w + phi)) / (1 - sp * math.sin(2 * m_t + phi)) * math.exp(2 * nu * math.tan(phi))
    return AnnexCCoefficients(K_n=K_n, K_q=K_n * math.cos(beta) ** 2,
                              K_c=(K_n - 1) / math.tan(phi),
                              K_gamma=K_n * math.cos(beta) * math.cos(beta - theta))


def _clip(x: float) -> float:
    """acos argument kept in [-1, 1] against round-off at |delta| = phi or |beta| = phi."""
    return max(-1.0, min(1.0, x))


def ec7_annex_c(soil: Soil, wall: Wall, passive: bool = False) -> Profile:
    """Dry cohesionless earth pressure from EN 1997-1 Annex C.2 (eqs. C.3-C.9).

    Normal stress per unit face length e_n(z) = K_gamma gamma z + K_q q'; the shear is
    e_n tan(delta) (down the face when active, up when passive), so the resultant acts at
    delta to the face normal. q' is wallsim's q, a vertical load per unit horizontal area
    (the Annex's q for level ground; for a sloping surface wallsim takes it the same way).

    Profile.K = K_gamma / (cos(delta) cos(omega)), the coefficient along the resultant
    (as Coulomb's K), and Kh its horizontal part; ``extra`` holds K_n, K_q, K_c, K_gamma.
    """
    check_wall_friction(soil, wall)
    if abs(wall.omega_deg) >= 90.0 - 1e-9:
        raise InvalidParameter("omega", wall.omega_deg, "(-90, 90) deg")
    co = annex_c_coefficients(soil.phi_deg, wall.delta_deg, wall.beta_deg, wall.omega_deg, passive)
    H, g = wall.height, soil.unit_weight
    qe = wall.surcharge
    z = depth_grid(H, 201)
    sigma = co.K_gamma * g * z + co.K_q * qe
    direction = -wall.delta if passive else wall.delta
    tau = sigma * math.tan(direction)
    cos_o = math.cos(wall.omega)
    # per unit face length; a face element spans dz / cos(omega)
    N_soil = co.K_gamma * 0.5 * g * H**2 / cos_o
    N_q = co.K_q * qe * H / cos_o
    N = N_soil + N_q
    thrust = N / math.cos(direction)
    height = (N_soil * H / 3 + N_q * H / 2) / N if N > 0 else H / 3
    horiz = math.cos(direction + wall.omega)
    K = co.K_gamma / (math.cos(direction) * cos_o)
    return Profile(method="ec7-annex-c", z=z, sigma_h=sigma, tau=tau, thrust=thrust,
                   thrust_h=thrust * horiz, height=height, K=K, Kh=K * horiz, H=H,
                   omega_deg=wall.omega_deg, source=SOURCE,
                   notes="normal components from the Annex; linear distribution"
                   + ("; passive = Lancellotta (2002) lower bound for this vertical wall and level fill"
                      if passive and wall.omega_deg == 0 and wall.beta_deg == 0 else ""),
                   extra={"passive": passive, "K_n": co.K_n, "K_q": co.K_q, "K_c": co.K_c,
                          "K_gamma": co.K_gamma, "thrust_q": N_q / math.cos(direction)})
