"""Contact-law parameters and the time-step rule.

``ContactParams`` is a NamedTuple of plain numbers so numba types it (and caches kernels
that take it); frozen dataclasses are rejected by numba.
Build it with :func:`linear` (PFC linear model) or :func:`hertz_mindlin`.

The same law acts between two particles and between a particle and a wall panel; a panel
brings only its own friction coefficient (walls are rigid and of the grains' material).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from analytic.errors import InvalidParameter
from analytic.inputs import require_number

LINEAR = 0          #: law id: linear spring, kn/ks constant (PFC "linear", LIGGGHTS hooke/stiffness)
HERTZ_MINDLIN = 1   #: law id: Hertz normal + Mindlin (no-slip) tangential stiffness

RATIO = 0           #: damping given as critical-damping ratios zeta_n, zeta_s [-]
ABSOLUTE = 1        #: damping given as dashpot coefficients c_n, c_s [N s/m]

COULOMB_ELASTIC = 0  #: |F_t| <= mu F_n,elastic (PFC linear model)
COULOMB_TOTAL = 1    #: |F_t| <= mu |F_n,elastic + F_n,viscous| (LIGGGHTS tangential history)


class ContactParams(NamedTuple):
    """One contact law, used for particle-particle and particle-wall contacts.

    law:            LINEAR or HERTZ_MINDLIN
    kn, ks:         normal / tangential spring stiffness [N/m] (LINEAR)
    e_star, g_star: effective Young's and shear moduli E*, G* [Pa] (HERTZ_MINDLIN);
                    F_n = 4/3 E* sqrt(R*) delta^1.5, k_t = 8 G* sqrt(R* delta)
    damping:        RATIO or ABSOLUTE (how damp_n/damp_s are read)
    damp_n, damp_s: normal / tangential viscous damping: critical ratios [-] (RATIO) or
                    coefficients [N s/m] (ABSOLUTE); for RATIO, c = 2 zeta sqrt(m* k)
                    (linear) and c = 2 sqrt(5/6) zeta sqrt(m* k_tangent) (Hertz, Tsuji et al. 1992)
    mu:             particle-particle Coulomb friction coefficient [-]
    local_damping:  PFC local (non-viscous) damping alpha [-], 0 <= alpha < 1:
                    each force/moment component is reduced by alpha |F| sign(v)
                    (Cundall 1987; PFC3D manual) -- for quasi-static stages only
    coulomb:        COULOMB_ELASTIC (cap on the elastic normal force, PFC) or
                    COULOMB_TOTAL (on the total normal force, LIGGGHTS)
    mu_roll:        rolling-resistance coefficient mu_r [-] of particle-particle contacts
                    (0 = none): a torque opposing the relative rolling, of magnitude
                    mu_r R* F_n (constant directional torque, Ai et al. 2011 model A;
                    LIGGGHTS ``rolling_friction cdt``), clipped to what stops the
                    relative rolling within one step so a contact at rest does not chatter
    """

    law: int
    kn: float
    ks: float
    e_star: float
    g_star: float
    damping: int
    damp_n: float
    damp_s: float
    mu: float
    local_damping: float
    coulomb: int = COULOMB_ELASTIC
    mu_roll: float = 0.0


def linear(kn: float, ks: float, mu: float, *, zeta_n: float | None = None, zeta_s: float | None = None,
           c_n: float | None = None, c_s: float | None = None, local_damping: float = 0.0,
           coulomb: str = "elastic", mu_roll: float = 0.0) -> ContactParams:
    """PFC-style linear contact: F_n = kn delta + c_n v_n, incremental F_t = -ks u_t - c_s v_t,
    |F_t| <= mu kn delta.

    Damping is given either as critical-damping ratios (``zeta_n``, ``zeta_s``; a head-on
    collision then has restitution e = exp(-zeta pi / sqrt(1 - zeta^2))) or as absolute
    coefficients (``c_n``, ``c_s`` in N s/m, LIGGGHTS ``absolute_damping on``), not both.
    ``coulomb="total"`` caps |F_t| by mu times the total normal force as LIGGGHTS does
    (its benchmark uses this); the default "elastic" is PFC's cap.
    """
    kn = require_number("kn", kn, 0.0, None, unit="N/m")
    ks = require_number("ks", ks, 0.0, None, lo_open=False, unit="N/m")
    mode, dn, ds = _damping(zeta_n, zeta_s, c_n, c_s)
    return ContactParams(LINEAR, kn, ks, 0.0, 0.0, mode, dn, ds, _mu("mu", mu), _alpha(local_damping),
                         _coulomb(coulomb), _mu("mu_roll", mu_roll))


def hertz_mindlin(youngs: float, poisson: float, mu: float, *, zeta_n: float | None = None,
                  zeta_s: float | None = None, c_n: float | None = None, c_s: float | None = None,
                  local_damping: float = 0.0, coulomb: str = "elastic", mu_roll: float = 0.0) -> ContactParams:
    """Hertz-Mindlin contact between grains of one material (Young's modulus ``youngs`` [Pa],
    Poisson's ratio ``poisson``): E* = E / (2 (1 - nu^2)), G* = E / (4 (2 - nu)(1 + nu))
    (Johnson 1985; LIGGGHTS ``hertz``/``tangential history``). Walls use the same E*, G*.
    """
    youngs = require_number("youngs", youngs, 0.0, None, unit="Pa")
    poisson = require_number("poisson", poisson, -1.0, 0.5, hi_open=False)
    mode, dn, ds = _damping(zeta_n, zeta_s, c_n, c_s)
    e_star = youngs / (2.0 * (1.0 - poisson ** 2))
    g_star = youngs / (4.0 * (2.0 - poisson) * (1.0 + poisson))
    return ContactParams(HERTZ_MINDLIN, 0.0, 0.0, e_star, g_star, mode, dn, ds, _mu("mu", mu),
                         _alpha(local_damping), _coulomb(coulomb), _mu("mu_roll", mu_roll))


def restitution_to_damping_ratio(e: float) -> float:
    """zeta for a linear spring-dashpot with restitution e: zeta = -ln e / sqrt(pi^2 + ln^2 e)."""
    e = require_number("restitution", e, 0.0, 1.0, hi_open=False)
    return -math.log(e) / math.sqrt(math.pi ** 2 + math.log(e) ** 2)


def _damping(zeta_n, zeta_s, c_n, c_s):
    if (zeta_n is not None or zeta_s is not None) and (c_n is not None or c_s is not None):
        raise InvalidParameter("damping", "ratios and coefficients", "either zeta_n/zeta_s or c_n/c_s")
    if c_n is not None or c_s is not None:
        return (ABSOLUTE, require_number("c_n", c_n or 0.0, 0.0, None, lo_open=False, unit="N s/m"),
                require_number("c_s", c_s or 0.0, 0.0, None, lo_open=False, unit="N s/m"))
    return (RATIO, require_number("zeta_n", zeta_n or 0.0, 0.0, 1.0, lo_open=False),
            require_number("zeta_s", zeta_s or 0.0, 0.0, 1.0, lo_open=False))


def _coulomb(kind):
    if kind not in ("elastic", "total"):
        raise InvalidParameter("coulomb", kind, "'elastic' or 'total'")
    return COULOMB_ELASTIC if kind == "elastic" else COULOMB_TOTAL


def _mu(name, mu):
    return require_number(name, mu, 0.0, None, lo_open=False)


def _alpha(alpha):
    return require_number("local_damping", alpha, 0.0, 1.0, lo_open=False)


def with_local_damping(params: ContactParams, alpha: float) -> ContactParams:
    """The same law with PFC local damping ``alpha`` (e.g. 0.7 to settle, 0 to measure)."""
    return params._replace(local_damping=_alpha(alpha))


#: refuse dt above this fraction of sqrt(m_min / k_max). A sphere held by Z springs of
#: stiffness k has omega_max <= sqrt(2 Z k / m) (Gershgorin bound, each contact counted for
#: both bodies); for Z = 12 the central-difference limit 2/omega is 0.41 sqrt(m/k), so 0.2
#: keeps a factor ~2 margin, plus room for viscous damping (which lowers the limit).
DT_SAFETY = 0.2


def critical_time_step(params: ContactParams, min_mass: float, min_radius: float,
                       density: float) -> float:
    """Reference critical step [s].

    LINEAR: sqrt(m_min / k_max) with k_max = max(kn, ks) (PFC3D manual, "Time step
    determination"; 1/omega of the lightest sphere on its stiffest spring).
    HERTZ_MINDLIN: the Rayleigh-wave step pi R_min sqrt(rho / G) / (0.1631 nu + 0.8766)
    (Li et al. 2005), with G and nu recovered from E*, G*.
    """
    if params.law == LINEAR:
        return math.sqrt(min_mass / max(params.kn, params.ks))
    # invert E* = E/(2(1-nu^2)), G* = E/(4(2-nu)(1+nu)) for nu by bisection (monotone on [-1, 0.5])
    ratio = params.g_star / params.e_star
    lo, hi = -0.999, 0.5
    for _ in range(200):
        nu = 0.5 * (lo + hi)
        r = 2.0 * (1.0 - nu ** 2) / (4.0 * (2.0 - nu) * (1.0 + nu))
        if r > ratio:
            lo = nu
        else:
            hi = nu
    youngs = params.e_star * 2.0 * (1.0 - nu ** 2)
    shear = youngs / (2.0 * (1.0 + nu))
    return math.pi * min_radius * math.sqrt(density / shear) / (0.1631 * nu + 0.8766)


def check_time_step(dt: float, dt_critical: float, *, allow_unsafe: bool = False,
                    safety: float = DT_SAFETY) -> float:
    """Return dt, or raise a one-line InvalidParameter if dt > safety * dt_critical.

    ``allow_unsafe=True`` is the expert override (blow-up detection still runs).
    """
    dt = require_number("dt", dt, 0.0, None, unit="s")
    limit = safety * dt_critical
    if dt > limit and not allow_unsafe:
        raise InvalidParameter("dt", dt, f"(0, {limit:.4g}] s",
                               f"{safety:g} x critical step {dt_critical:.4g} s from the lightest "
                               "sphere and stiffest spring; allow_unsafe=True overrides")
    return dt


# --------------------------------------------------------------------------------------
# materials: contact parameters per pair of materials
# --------------------------------------------------------------------------------------

#: number of float slots per pair in a material table (the ContactParams fields, in order)
N_PARAM_FIELDS = len(ContactParams._fields)


def mix(a: ContactParams, b: ContactParams) -> ContactParams:
    """Contact parameters between a grain of material ``a`` and one of material ``b``,
    where each material is described by the ContactParams of a contact between two of
    its own grains.

    Mixing rule (stated, and exact for Hertz-Mindlin):
    * stiffnesses combine as springs in series of the two half-contacts, i.e. the
      harmonic mean: k_ab = 2 k_a k_b / (k_a + k_b) for kn, ks (linear) and for E*, G*
      (Hertz). For Hertz this is Johnson's (1985) 1/E* = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b
      and 1/G* = (2 - nu_a)/G_a + (2 - nu_b)/G_b, since E*_a = E_a / (2 (1 - nu_a^2)) and
      G*_a = G_a / (2 (2 - nu_a)) (``hertz_mindlin``); a material paired with itself gives
      itself back.
    * friction: the smaller coefficient, mu_ab = min(mu_a, mu_b) (the weaker surface
      governs sliding);
    * damping ratios / coefficients: the arithmetic mean;
    * rolling resistance: the smaller coefficient, as friction.
    Law, damping mode, Coulomb cap and local damping must be the same for both (they are
    properties of the model, not of a surface). Pass explicit pair parameters to
    ``material_table`` to override the rule (LIGGGHTS ``peratomtypepair``).
    """
    for name in ("law", "damping", "coulomb", "local_damping"):
        if getattr(a, name) != getattr(b, name):
            raise InvalidParameter(f"materials' {name}", (getattr(a, name), getattr(b, name)), "equal")

    def series(p, q):
        return 2.0 * p * q / (p + q) if p + q > 0.0 else 0.0

    return ContactParams(a.law, series(a.kn, b.kn), series(a.ks, b.ks), series(a.e_star, b.e_star),
                         series(a.g_star, b.g_star), a.damping, 0.5 * (a.damp_n + b.damp_n),
                         0.5 * (a.damp_s + b.damp_s), min(a.mu, b.mu), a.local_damping, a.coulomb,
                         min(a.mu_roll, b.mu_roll))


def material_table(materials, pairs=None):
    """(nm, nm, N_PARAM_FIELDS) float table of ContactParams per pair of materials
    (row [a, b] = the fields of ``mix(materials[a], materials[b])`` in ContactParams order,
    law/damping/coulomb stored as floats), symmetric; ``pairs`` maps (a, b) to explicit
    ContactParams overriding the rule for that pair (both orders).

    The kernels look the pair's row up by the two material ids (int32 per sphere and per
    panel) and rebuild a ContactParams from it, so a two-material contact follows exactly
    the single-material code with the pair's numbers.
    """
    mats = list(materials)
    if not mats:
        raise InvalidParameter("materials", 0, ">= 1 material")
    nm = len(mats)
    table = np.zeros((nm, nm, N_PARAM_FIELDS))
    for a in range(nm):
        for b in range(nm):
            table[a, b] = tuple(float(v) for v in mix(mats[a], mats[b]))
    for (a, b), prm in (pairs or {}).items():
        if not (0 <= a < nm and 0 <= b < nm):
            raise InvalidParameter("pairs", (a, b), f"material ids in [0, {nm})")
        mix(mats[a], prm)           # checks the model-wide fields agree
        table[a, b] = table[b, a] = tuple(float(v) for v in prm)
    return table


def pair_params(table, a: int, b: int) -> ContactParams:
    """The ContactParams of the pair (a, b) in a ``material_table``."""
    row = table[a, b]
    return ContactParams(int(row[0]), *(float(v) for v in row[1:5]), int(row[5]),
                         *(float(v) for v in row[6:10]), int(row[10]), float(row[11]))
