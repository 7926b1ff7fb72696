"""Differential slice method (DSM) for the active load on a rough wall.

Michalowski (1984), Int. J. Numer. Anal. Methods Geomech. 8(5), 493-502; Nadukuru &
Michalowski (2012), J. Geotech. Geoenviron. Eng. 138(5), eqs. 7-19 and Appendix.

Geometry (Fig. 7): a wedge between the wall (inclined theta_l from vertical, friction
delta) and a slip surface (inclined theta_r from vertical, mobilised friction phi*) is
cut into horizontal slices of width l. z is the height of a slice above the apex O where
the two boundary tangents meet (for a planar surface, O is the heel); d = H - z is depth.
On a slice face the vertical stress varies linearly from sigma_l (wall end) to sigma_r
(slip-surface end); tau is the mean shear on the face. At the ends
sigma_n = k sigma_z and sigma_t = sigma_n tan(angle) (eqs. 8-9); at the slip surface
k_r follows from the limit state (eq. 12), at the wall k_l(d) is prescribed.

Derivation (re-done here from slice equilibrium, because the extracted text of eq. 10
has two errors; analytic-formulas.md section 7). With compression positive, the wall
pushing the slice with sigma_n^l (1 - tan(delta) tan(th_l), tan(th_l) + tan(delta)) dz,
the slip surface with sigma_n^r (tan(phi) tan(th_r) - 1, tan(th_r) + tan(phi)) dz, and
T = l tau_p the shear force on a face (tau_p = -sigma_xz, the paper's sign):

* x-force:   d(l tau)/dz = D_l sigma_l - D_r sigma_r                          (eq. 14)
* z-force:   d(l (sigma_l + sigma_r)/2)/dz = sigma_n^l (t_l + t_d) + sigma_n^r (t_r + t_f) - gamma l
                                                                               (eq. 15)
* moment about O (both boundary lines pass through O, so only their normal forces
  have an arm): d/dz [ l z/6 (sigma_l (t_r - 2 t_l) + sigma_r (2 t_r - t_l)) + z l tau ]
  = z (k_r (1 + t_r^2) sigma_r - k_l (1 + t_l^2) sigma_l) - gamma z^2 (t_r^2 - t_l^2)/2
                                                                               (eq. 16)

with l = z (t_l + t_r) (eq. 7), t_x = tan(x). Solving for the three derivatives gives
exactly the paper's eq. 10 with the two corrections (checked symbolically for
theta_l = 0 in the commit that added this module):

    d sigma_l/dz = (A_l sigma_l + B_r sigma_r + 6 tau)/l - gamma cos(beta)
    d sigma_r/dz = (B_l sigma_l + A_r sigma_r - 6 tau)/l - gamma cos(beta)   (paper: "+ gamma")
    d tau/dz     = (D_l sigma_l - D_r sigma_r)/l - tau/z - gamma sin(beta)
    A_l = 4 k_l (t_l + t_d) - 3 t_l       A_r = 4 k_r (t_r + t_f) - 3 t_r
    B_l = 2 t_l - t_r - 2 k_l (t_l + t_d) B_r = 2 t_r - t_l - 2 k_r (t_r + t_f)
    D_l = k_l (t_l t_d - 1)               D_r = k_r (t_r t_f - 1)           (paper: t_l in D_r)
    k_r = cos^2(phi*) / (1 + sin(phi*) sin(phi* + 2 theta_r))                   (eq. 12)

Boundary conditions at the top (d = 0): sigma_l = sigma_r = q, tau = 0. The equations
are integrated downward (in depth) with scipy's ``solve_ivp`` (LSODA, rtol 1e-9); the
coefficients grow like 1/l toward the apex (l -> 0), where the paper notes oscillation,
so the integration stops at d = H (1 - 1e-7): the omitted sliver carries < 1e-6 of the
load. The wall load is integrated along with the stresses as two quadrature states.

Curved slip surface (rotation about the top): each slice uses the tangent to the surface
at its right end, theta_r(d), and its own apex O below it at z = l / (t_l + t_r) (paper,
Appendix). The slice width is the true width l(d) = x_r(d) - x_l(d). The surface shape
is not given in the paper; wallsim's family is documented in ``curved_surface``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from .classical import coulomb_coefficient, trial_wedge
from .errors import InvalidParameter
from .inputs import Soil, Wall, check_wall_friction, require_number
from .profile import Profile

DepthFunction = Callable[[float], float]   # f(d / H) -> value

_STOP = 1e-7       # stop this close to the apex (fraction of H)


def slip_coefficient(phi: float, theta_r: float) -> float:
    """k_r = sigma_n / sigma_z on a slip surface inclined theta_r [rad] from vertical with
    friction phi [rad] fully mobilised (Nadukuru & Michalowski eq. 12, Mohr circle).
    theta_r = 45 - phi/2 gives 1 - sin(phi)."""
    return math.cos(phi) ** 2 / (1.0 + math.sin(phi) * math.sin(phi + 2.0 * theta_r))


@dataclass(frozen=True)
class SlipSurface:
    """The surface behind the wedge, as its inclination from vertical at each depth.

    kind:       "planar" or "curved"
    theta_r:    f(d/H) -> inclination from vertical [rad] (constant for planar)
    label:      how it was chosen (printed by the CLI)
    """

    kind: str
    theta_r: DepthFunction
    label: str = ""
    offset: DepthFunction | None = None   # x_r / H at depth d/H, if known in closed form

    @classmethod
    def planar(cls, theta_r_deg: float, label: str = "") -> "SlipSurface":
        th = math.radians(require_number("theta_r", theta_r_deg, 0.0, 90.0, unit="deg"))
        return cls("planar", lambda u, th=th: th, label or f"planar, theta_r = {theta_r_deg:.2f} deg")


def curved_surface(theta_top_deg: float, theta_heel_deg: float, label: str = "") -> SlipSurface:
    """A curved slip surface through the heel whose inclination from vertical changes
    linearly with depth, from theta_top at the ground surface to theta_heel at the heel.

    The paper used a curved surface for rotation about the top, "as in Fig. 3(a)", but
    does not give it. wallsim picks this two-parameter family (it contains the plane,
    and concave and convex arcs close to circular and log-spiral ones) and chooses the
    member by the same condition the paper applies to the planar surfaces: maximum wall
    reaction (``maximise_over_curves``).
    """
    t0, t1 = math.radians(theta_top_deg), math.radians(theta_heel_deg)
    if abs(t1 - t0) < 1e-9:
        offset = (lambda u: (1.0 - u) * math.tan(t0))
    else:   # x_r/H = int_u^1 tan(theta(s)) ds = ln(cos theta(u) / cos theta(1)) / (t1 - t0)
        offset = (lambda u: math.log(math.cos(t0 + (t1 - t0) * u) / math.cos(t1)) / (t1 - t0))
    return SlipSurface("curved", lambda u: t0 + (t1 - t0) * u,
                       label or f"curved: theta_r {theta_top_deg:.1f} deg at the top -> "
                                f"{theta_heel_deg:.1f} deg at the heel", offset)


def local_failure_surface(phi_mobilised: DepthFunction) -> SlipSurface:
    """Alternative curved surface: at every depth a Mohr-Coulomb plane of the mobilised
    strength with sigma_1 vertical, theta_r(d) = 45 deg - phi*(d)/2 (no free parameter)."""
    return SlipSurface("curved", lambda u: math.pi / 4 - phi_mobilised(u) / 2,
                       "curved: theta_r(d) = 45 - phi*(d)/2 (local Mohr-Coulomb plane)")


@dataclass(frozen=True)
class DSMCase:
    """One DSM problem. Angles in rad inside the callables, degrees in the fields.

    phi_deg:     friction angle of the backfill [deg]
    delta_deg:   wall friction [deg]
    H:           wall height [m]; gamma: unit weight [N/m^3]; q: surcharge [Pa]
    k_wall:      f(d/H) -> k_l = sigma_n / sigma_z at the wall (eq. 9)
    phi_mob:     f(d/H) -> mobilised friction on the slip surface [rad]
    surface:     SlipSurface (planar or curved)
    theta_l_deg: wall inclination from vertical [deg] (0: vertical)
    """

    phi_deg: float
    delta_deg: float
    H: float
    gamma: float
    k_wall: DepthFunction
    phi_mob: DepthFunction
    surface: SlipSurface
    q: float = 0.0
    theta_l_deg: float = 0.0
    name: str = "dsm"
    notes: str = ""


@dataclass(frozen=True)
class DSMResult:
    """Wall load of a DSM solve; ``profile`` uses the shared Profile record."""

    profile: Profile
    theta_r_deg: float          # at the heel (planar: the plane's inclination)
    solve_time_s: float
    d: np.ndarray = field(repr=False)          # depths [m]
    sigma_l: np.ndarray = field(repr=False)    # vertical stress at the wall end [Pa]
    sigma_r: np.ndarray = field(repr=False)    # vertical stress at the slip-surface end [Pa]
    tau: np.ndarray = field(repr=False)        # mean shear on slice faces [Pa] (paper's sign)

    @property
    def K(self) -> float:
        return self.profile.K

    @property
    def resultant_height_over_H(self) -> float:
        return self.profile.height_over_H


def _surface_offset(case: DSMCase, d: np.ndarray) -> np.ndarray:
    """x_r(d) for the slip surface: the integral of tan(theta_r) from d to H [m]."""
    H = case.H
    u = np.linspace(0.0, 1.0, 4001)
    t = np.array([math.tan(case.surface.theta_r(x)) for x in u])
    # cumulative integral from the heel (u = 1) upward
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (t[1:] + t[:-1]) * np.diff(u))]) * H
    x_from_top = cum[-1] - cum          # x_r at depth u H, measured from the heel
    return np.interp(d / H, u, x_from_top)


def solve(case: DSMCase, n_out: int = 401) -> DSMResult:
    """Integrate eq. 10 from the top (d = 0) to the apex and return the wall load.

    K = 2 P / (gamma H^2) with P the inclined resultant N / cos(delta) (Table 3's K);
    the resultant height comes from the normal stress k_l sigma_l (Table 3's centroid).
    """
    t0 = time.perf_counter()
    H, g = case.H, case.gamma
    tl = math.tan(math.radians(case.theta_l_deg))
    td = math.tan(math.radians(case.delta_deg))
    planar = case.surface.kind == "planar"
    if planar:
        th_r0 = case.surface.theta_r(0.0)
        width_factor = tl + math.tan(th_r0)

        def width(d):
            return (H - d) * width_factor
    elif case.surface.offset is not None:
        off = case.surface.offset

        def width(d):
            return H * off(d / H) + (H - d) * tl
    else:
        dd = np.linspace(0.0, H, 4001)
        xr = _surface_offset(case, dd)

        def width(d):
            return float(np.interp(d, dd, xr)) + (H - d) * tl

    def rhs(d, y):
        sl, sr, tau = y[0], y[1], y[2]
        u = d / H
        kl = case.k_wall(u)
        ph = case.phi_mob(u)
        th_r = case.surface.theta_r(u)
        tr, tf = math.tan(th_r), math.tan(ph)
        kr = slip_coefficient(ph, th_r)
        l = width(d)
        s_ = tl + tr                           # parallel tangents (s_ = 0): apex at infinity
        A_l = 4 * kl * (tl + td) - 3 * tl
        A_r = 4 * kr * (tr + tf) - 3 * tr
        B_l = 2 * tl - tr - 2 * kl * (tl + td)
        B_r = 2 * tr - tl - 2 * kr * (tr + tf)
        D_l = kl * (tl * td - 1)
        D_r = kr * (tr * tf - 1)
        dsl_dz = (A_l * sl + B_r * sr + 6 * tau) / l - g
        dsr_dz = (B_l * sl + A_r * sr - 6 * tau) / l - g
        dtau_dz = (D_l * sl - D_r * sr) / l - (tau * s_ / l if s_ > 0 else 0.0)  # tau / z, z = l / s_
        sn = kl * sl                            # normal stress on the wall
        # d/dd = -d/dz; quadratures: normal force and its moment about the base
        return [-dsl_dz, -dsr_dz, -dtau_dz, sn, sn * (H - d)]

    d_end = H * (1.0 - _STOP)
    d_out = H * (1.0 - np.geomspace(1.0, _STOP, n_out)[::-1])[::-1]
    d_out = np.unique(np.concatenate([np.linspace(0.0, d_end, n_out), d_out]))
    sol = solve_ivp(rhs, (0.0, d_end), [case.q, case.q, 0.0, 0.0, 0.0], method="LSODA",
                    t_eval=d_out, rtol=1e-9, atol=1e-9 * g * H)
    if not sol.success:
        raise InvalidParameter("theta_r", math.degrees(case.surface.theta_r(0.0)),
                               "a slip surface for which the slice equations integrate", sol.message)
    d = sol.t
    sl, sr, tau = sol.y[0], sol.y[1], sol.y[2]
    N, M = sol.y[3, -1], sol.y[4, -1]
    kl = np.array([case.k_wall(x) for x in d / H])
    sigma_n = kl * sl
    cos_d = math.cos(math.radians(case.delta_deg))
    unit = 0.5 * g * H**2
    profile = Profile(method="dsm", z=d, sigma_h=sigma_n, tau=sigma_n * td, thrust=N / cos_d, thrust_h=N,
                      height=M / N, K=N / cos_d / unit, Kh=N / unit, H=H,
                      source="differential slice method: Michalowski (1984); Nadukuru & Michalowski (2012) eqs. 7-19",
                      status="verified" if planar else "reconstruction",
                      notes=case.notes or case.surface.label,
                      extra={"theta_r_deg": math.degrees(case.surface.theta_r(1.0)),
                             "surface": case.surface.label, "case": case.name})
    return DSMResult(profile=profile, theta_r_deg=math.degrees(case.surface.theta_r(1.0)),
                     solve_time_s=time.perf_counter() - t0, d=d, sigma_l=sl, sigma_r=sr, tau=tau)


# --------------------------------------------------------------------------- presets
@dataclass(frozen=True)
class ModePreset:
    """A wall-movement mode of Nadukuru & Michalowski's DSM (Table 3, Appendix)."""

    code: str
    title: str
    phi_deg: float
    k_wall: Callable[[float], float]
    phi_factor: Callable[[float], float]      # phi*(d)/phi as f(d/H)
    surface: str                              # "coulomb" (planar) or "curved"
    paper_K: float
    paper_height: float
    fang_ishibashi_K: float
    fang_ishibashi_height: float
    equation: str


MODES = {
    "T": ModePreset("T", "translation", 34.0, lambda u: 0.254 * (1 + 1.57 * (1 - u) ** 2), lambda u: 1.0,
                    "coulomb", 0.254, 0.363, 0.27, 0.41, "eq. 13: k_l = 0.254 [1 + 1.57 (1 - d/H)^2], phi* = phi"),
    "RB": ModePreset("RB", "rotation about the base", 33.4, lambda u: 0.2602 * (1 + u**15),
                     lambda u: (1 - u) ** 0.13, "coulomb", 0.312, 0.292, 0.31, 0.28,
                     "eq. 18: k_l = 0.2602 [1 + (d/H)^15], phi* = phi (1 - d/H)^0.13"),
    "RT": ModePreset("RT", "rotation about the top", 40.4, lambda u: 0.1961 * (1 + 20 * (1 - u) ** 4),
                     lambda u: u**0.25, "curved", 0.292, 0.492, 0.25, 0.56,
                     "eq. 19: k_l = 0.1961 [1 + 20 (1 - d/H)^4], phi* = phi (d/H)^0.25, curved surface"),
}


def coulomb_angle_from_vertical(phi_deg: float, delta_deg: float, theta_l_deg: float = 0.0) -> float:
    """Inclination from vertical [deg] of the Coulomb critical plane: the planar surface of
    maximum wall reaction with phi fully mobilised (the condition the paper uses)."""
    _, rho = trial_wedge(Soil(phi_deg, 1.0), Wall(1.0, delta_deg, theta_l_deg))
    return 90.0 - math.degrees(rho)


def mode_case(mode: str, *, phi_deg: float | None = None, delta_deg: float = 24.7, H: float = 1.0,
              gamma: float = 1.0, theta_r_deg: float | str | None = None) -> DSMCase:
    """The paper's DSM case for a mode ("T", "RB", "RT"), optionally with another phi,
    delta, H, gamma or slip surface. theta_r_deg: None (the mode's own surface: the
    Coulomb critical plane for T and RB, the curved surface for RT), a number (planar at
    that inclination from vertical) or "max" (the planar plane maximising the DSM load)."""
    if mode not in MODES:
        raise InvalidParameter("mode", mode, "T | RB | RT")
    m = MODES[mode]
    phi_deg = m.phi_deg if phi_deg is None else require_number("phi", phi_deg, 0.0, 90.0, unit="deg")
    check_wall_friction(Soil(phi_deg, 1.0), Wall(1.0, delta_deg))
    phi = math.radians(phi_deg)
    phi_mob = (lambda u, f=m.phi_factor: phi * f(u))
    # eqs. 13, 18, 19 scale with the Coulomb Ka of the mode's own phi and delta = 24.7;
    # keep the shape and rescale to the chosen phi and delta
    base = {"T": 0.254, "RB": 0.2602, "RT": 0.1961}[mode]
    ka = coulomb_coefficient(phi, math.radians(delta_deg), 0.0, 0.0)
    scale = ka / base if (phi_deg != m.phi_deg or delta_deg != 24.7) else 1.0
    k_wall = (lambda u, k=m.k_wall, s=scale: s * k(u))
    if theta_r_deg is None:
        surface = (SlipSurface.planar(coulomb_angle_from_vertical(phi_deg, delta_deg),
                                      "planar, Coulomb critical angle (maximum wall reaction)")
                   if m.surface == "coulomb" else "curved-max")
    elif theta_r_deg == "max":
        surface = "planar-max"
    elif theta_r_deg == "local":
        surface = local_failure_surface(phi_mob)
    else:
        surface = SlipSurface.planar(float(theta_r_deg), f"planar, theta_r = {float(theta_r_deg):.2f} deg (fixed)")
    case = DSMCase(phi_deg=phi_deg, delta_deg=delta_deg, H=H, gamma=gamma, k_wall=k_wall, phi_mob=phi_mob,
                   surface=surface if isinstance(surface, SlipSurface) else SlipSurface.planar(45.0),
                   name=mode, notes=m.equation)
    if surface == "planar-max":
        case = maximise_over_plane(case)
    elif surface == "curved-max":
        case = maximise_over_curves(case)
    return case


def maximise_over_plane(case: DSMCase) -> DSMCase:
    """The planar slip surface that maximises the DSM resultant itself."""
    def neg_K(th_deg):
        c = _with_plane(case, th_deg, "")
        return -solve(c, n_out=41).K
    res = minimize_scalar(neg_K, bounds=(5.0, 70.0), method="bounded", options={"xatol": 1e-3})
    return _with_plane(case, float(res.x), f"planar, theta_r = {res.x:.2f} deg (maximum DSM load)")


def maximise_over_curves(case: DSMCase) -> DSMCase:
    """The member of ``curved_surface``'s family that maximises the DSM resultant
    (coarse grid over (theta_top, theta_heel), then Nelder-Mead)."""
    from dataclasses import replace
    from scipy.optimize import minimize

    def K_of(x):
        t_top, t_heel = x
        if not (0.0 <= t_top <= 80.0 and 1.0 <= t_heel <= 80.0):
            return 0.0
        return solve(replace(case, surface=curved_surface(t_top, t_heel)), n_out=21).K

    grid = [(a, b) for a in range(0, 61, 10) for b in range(10, 61, 10)]
    start = max(grid, key=K_of)
    res = minimize(lambda x: -K_of(x), np.array(start, float), method="Nelder-Mead",
                   options={"xatol": 0.05, "fatol": 1e-7})
    t_top, t_heel = (float(v) for v in res.x)
    return replace(case, surface=curved_surface(
        t_top, t_heel, f"curved, maximum wall reaction: theta_r {t_top:.1f} deg at the top -> "
                       f"{t_heel:.1f} deg at the heel"))


def _with_plane(case: DSMCase, th_deg: float, label: str) -> DSMCase:
    from dataclasses import replace
    return replace(case, surface=SlipSurface.planar(th_deg, label))
