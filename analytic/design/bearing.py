"""Bearing resistance of a footing under an inclined, eccentric load.

``method='ec7'``: EN 1997-1:2004 Annex D. Drained (D.4): 
    R/A' = c' Nc bc sc ic + q' Nq bq sq iq + 0.5 gamma' B' Ngamma bgamma sgamma igamma
    Nq = e^(pi tan phi) tan^2(45 + phi/2), Nc = (Nq - 1) cot phi,
    Ngamma = 2 (Nq - 1) tan phi (rough base, delta >= phi/2),
    sq = 1 + (B'/L') sin phi, sgamma = 1 - 0.3 B'/L', sc = (sq Nq - 1)/(Nq - 1),
    load inclined in the B direction: m = mB = (2 + B'/L')/(1 + B'/L'),
    iq = [1 - H/(V + A' c' cot phi)]^m, igamma = [...]^(m+1), ic = iq - (1 - iq)/(Nc tan phi).
Undrained (D.3): R/A' = (pi + 2) cu bc sc ic + q, sc = 1 + 0.2 B'/L',
    ic = 0.5 (1 + sqrt(1 - H/(A' cu))).
``method='vesic'``: Vesic (1975): Ngamma = 2 (Nq + 1) tan phi, sc = 1 + (B'/L') Nq/Nc,
    sq = 1 + (B'/L') tan phi, sgamma = 1 - 0.4 B'/L', inclination as above.
Conventions: effective width B' = B - 2 e (Meyerhof), L' = L - 2 e_L; a strip (L = inf)
has B'/L' = 0 and per-metre V, H, R. Base inclination factors b = 1 (horizontal base).
Depth factors are NOT applied: Annex D has none (other methods' depth factors are often
borrowed; they are not used here). Units: kPa, kN (or kN/m), m, degrees.

Range of validity: the inclination factors are meant in [0, 1]. Past a limiting
horizontal load H_lim they would turn negative (and with them q_ult and R), so there the
bearing fails instead, with H_lim and the reason (``Bearing.fails``), and q_ult = R = 0:
* drained, c' > 0: i_c = 0 at i_q = 1/N_q, H_lim = (V + A' c' cot phi') (1 - N_q^(-1/m));
* drained, c' = 0: i_q = 0 at H_lim = V (the c term is absent);
* undrained: i_c's root is real up to H_lim = A' c_u (beyond, the base slides).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import InvalidParameter
from ..inputs import MAX_PRESSURE_KPA, MAX_UNIT_WEIGHT_KN_M3, require_number

MAX_FOOTING_M = 1000.0
MAX_LOAD_KN = 1e8


@dataclass(frozen=True)
class Bearing:
    """q_ult [kPa], R = q_ult A' [kN, or kN/m for a strip], B', L' [m] (L' = inf for a
    strip), the factors used and the method; H_limit [kN or kN/m], the horizontal load at
    which an inclination factor reaches 0, and ``fails``: the one-line reason when
    H >= H_limit (then q_ult = R = 0), else None."""

    q_ult: float
    R: float
    B_eff: float
    L_eff: float
    method: str
    factors: dict = field(default_factory=dict)
    H_limit: float = math.inf
    fails: str | None = None      # why the bearing fails (H >= H_limit), else None


def _loads(q: float, B: float, L: float, V: float, H: float) -> None:
    """Overburden, footing size and loads within physical sense (``MAX_*``): a footing
    up to 1 km, loads up to 1e8 kN."""
    require_number("q", q, 0.0, MAX_PRESSURE_KPA, lo_open=False, hi_open=False, unit="kPa")
    require_number("B", B, 0.0, MAX_FOOTING_M, hi_open=False, unit="m")
    if not math.isinf(L):
        require_number("L", L, 0.0, MAX_FOOTING_M, hi_open=False, unit="m")
    require_number("V", V, 0.0, MAX_LOAD_KN, hi_open=False, unit="kN")
    require_number("H", H, 0.0, MAX_LOAD_KN, lo_open=False, hi_open=False, unit="kN")


def _effective(B: float, L: float, e: float, e_L: float) -> tuple[float, float, float, float]:
    """B', L', A' and B'/L' (0 for a strip)."""
    B_eff = B - 2 * abs(e)
    if B_eff <= 0:
        raise InvalidParameter("e", e, f"(-B/2, B/2) = ({-B / 2:g}, {B / 2:g}) m", "no effective width left")
    if math.isinf(L):
        return B_eff, math.inf, B_eff, 0.0
    L_eff = L - 2 * abs(e_L)
    if L_eff <= 0:
        raise InvalidParameter("e_L", e_L, f"(-L/2, L/2) m")
    B_eff, L_eff = min(B_eff, L_eff), max(B_eff, L_eff)
    return B_eff, L_eff, B_eff * L_eff, B_eff / L_eff


def bearing_resistance(*, phi: float, c: float, gamma: float, q: float, B: float, V: float,
                       H: float = 0.0, L: float = math.inf, e: float = 0.0, e_L: float = 0.0,
                       method: str = "ec7") -> Bearing:
    """Drained bearing resistance (see the module docstring for every factor).
    phi [deg] in (0, 50], c [kPa], gamma [kN/m3] below the base, q [kPa] overburden at
    base level beside the footing, B, L [m], V, H [kN or kN/m] (H along B), e [m]."""
    require_number("phi", phi, 0.0, 50.0, hi_open=False, unit="deg")
    require_number("c", c, 0.0, MAX_PRESSURE_KPA, lo_open=False, hi_open=False, unit="kPa")
    require_number("gamma", gamma, 0.0, MAX_UNIT_WEIGHT_KN_M3, hi_open=False, unit="kN/m3")
    _loads(q, B, L, V, H)
    if method not in ("ec7", "vesic"):
        raise InvalidParameter("method", method, "'ec7' or 'vesic'")
    B_eff, L_eff, A, r = _effective(B, L, e, e_L)
    t = math.tan(math.radians(phi))
    Nq = math.exp(math.pi * t) * math.tan(math.radians(45 + phi / 2)) ** 2
    Nc = (Nq - 1) / t
    if method == "ec7":
        Ng = 2 * (Nq - 1) * t
        sq, sg = 1 + r * math.sin(math.radians(phi)), 1 - 0.3 * r
        sc = (sq * Nq - 1) / (Nq - 1)
    else:
        Ng = 2 * (Nq + 1) * t
        sq, sg, sc = 1 + r * t, 1 - 0.4 * r, 1 + r * Nq / Nc
    m = (2 + r) / (1 + r)
    carried = V + A * c / t                      # V + A' c' cot phi'
    H_lim = carried * (1 - Nq ** (-1 / m)) if c > 0 else V
    f = {"Nq": Nq, "Nc": Nc, "Ngamma": Ng, "sq": sq, "sc": sc, "sgamma": sg, "m": m, "b": 1.0,
         "depth_factors": "none (not in EN 1997-1 Annex D)"}
    unit = "kN/m" if math.isinf(L) else "kN"
    if H >= H_lim:
        where = ("(V + A' c' cot phi') (1 - N_q^(-1/m)), where i_c reaches 0" if c > 0 else "V, where i_q reaches 0")
        reason = (f"bearing fails: H = {H:.4g} {unit} >= H_lim = {H_lim:.4g} {unit} = {where}: the load leans "
                  f"beyond what the base can carry ({'EN 1997-1 D.4' if method == 'ec7' else 'Vesic 1975'})")
        return Bearing(0.0, 0.0, B_eff, L_eff, method, f | {"iq": 0.0, "ic": 0.0, "igamma": 0.0}, H_lim, reason)
    base = 1 - H / carried
    iq, ig = base ** m, base ** (m + 1)
    ic = iq - (1 - iq) / (Nc * t)
    if c == 0:
        ic = max(ic, 0.0)         # no cohesion term to scale: below i_q = 1/N_q D.4's i_c means nothing
    q_ult = c * Nc * sc * ic + q * Nq * sq * iq + 0.5 * gamma * B_eff * Ng * sg * ig
    f |= {"iq": iq, "ic": ic, "igamma": ig}
    return Bearing(q_ult, q_ult * A, B_eff, L_eff, method, f, H_lim)


def bearing_undrained(*, cu: float, q: float, B: float, V: float, H: float = 0.0,
                      L: float = math.inf, e: float = 0.0, e_L: float = 0.0) -> Bearing:
    """Undrained bearing resistance, EN 1997-1 Annex D.3 (see the module docstring);
    cu [kPa] > 0. For H > A' cu the base slides before it can bear: the bearing fails
    (``Bearing.fails``, q_ult = R = 0)."""
    require_number("cu", cu, 0.0, MAX_PRESSURE_KPA, hi_open=False, unit="kPa")
    _loads(q, B, L, V, H)
    B_eff, L_eff, A, r = _effective(B, L, e, e_L)
    sc = 1 + 0.2 * r
    H_lim = A * cu
    f = {"Nc": math.pi + 2, "sc": sc, "b": 1.0, "depth_factors": "none (not in EN 1997-1 Annex D)"}
    if H > H_lim:
        unit = "kN/m" if math.isinf(L) else "kN"
        reason = (f"bearing fails: H = {H:.4g} {unit} > H_lim = {H_lim:.4g} {unit} = A' c_u, where i_c has no "
                  f"real value: the base slides before it can bear (EN 1997-1 D.3)")
        return Bearing(0.0, 0.0, B_eff, L_eff, "ec7-undrained", f | {"ic": 0.0}, H_lim, reason)
    ic = 0.5 * (1 + math.sqrt(1 - H / H_lim))
    q_ult = (math.pi + 2) * cu * sc * ic + q
    return Bearing(q_ult, q_ult * A, B_eff, L_eff, "ec7-undrained", f | {"ic": ic}, H_lim)
