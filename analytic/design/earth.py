"""The one earth-pressure interface of the design checks: ``design_thrust``.

Every check asks this module for the thrust of the fill on a ``WallBack`` and gets its
parts (soil, surcharge, seismic increment) as forces with a point of application.
Today it wraps the closed forms of ``analytic/`` (Rankine, Coulomb, Mononobe-Okabe) for
a dry, cohesionless fill and a uniform surcharge. Issue 21 (c-phi soils, water table,
layers, EN 1997-1 Annex C) plugs in at ``_active_parts``: a new ``method`` name there,
or cohesion / water passed through ``Backfill``, returning more ``ThrustPart`` records
(e.g. a 'water' part); nothing else in ``analytic/design`` changes.

Units: kN/m3, kPa, m, degrees; forces in kN per metre run. Sign: ``Ph`` > 0 pushes the
wall toward its front (away from the fill), ``Pv`` > 0 acts downward on the wall.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..classical import coulomb_coefficient, rankine_coefficient
from ..errors import InvalidParameter
from ..inputs import require_number
from ..seismic import mononobe_okabe_coefficient
from .walls import WallBack

METHODS = ("rankine-virtual-back", "coulomb", "ec7-annex-c")


@dataclass(frozen=True)
class Backfill:
    """Fill behind (or soil in front of) the wall: gamma [kN/m3], phi [deg] in (0, 50],
    c [kPa] (active: only 0 until issue 21), beta [deg] surface slope, + rising away
    from the wall."""

    gamma: float
    phi: float
    c: float = 0.0
    beta: float = 0.0

    def __post_init__(self):
        require_number("backfill.gamma", self.gamma, 0.0, None, unit="kN/m3")
        require_number("backfill.phi", self.phi, 0.0, 50.0, hi_open=False, unit="deg")
        require_number("backfill.c", self.c, 0.0, None, lo_open=False, unit="kPa")
        if abs(self.beta) > self.phi:
            raise InvalidParameter("backfill.beta", self.beta, f"[-phi, phi] = [{-self.phi:g}, {self.phi:g}] deg",
                                   "no active wedge on a slope steeper than phi")


@dataclass(frozen=True)
class ThrustPart:
    """One part of a thrust: resultant P [kN/m], components Ph (toward the front) and
    Pv (down) [kN/m], point of application (x, y) [m]; ``kind`` 'soil', 'surcharge' or
    'seismic' (the dynamic increment of the soil and surcharge thrust)."""

    name: str
    kind: str
    P: float
    Ph: float
    Pv: float
    x: float
    y: float


@dataclass(frozen=True)
class Thrust:
    """The thrust on one back: its parts, the coefficient K along the thrust and its
    horizontal share Kh, the direction from the face normal [deg], and the method."""

    method: str
    K: float
    Kh: float
    direction: float
    parts: tuple[ThrustPart, ...] = field(default_factory=tuple)
    notes: str = ""
    back: WallBack | None = None

    @property
    def Ph(self) -> float:
        return sum(p.Ph for p in self.parts)

    @property
    def Pv(self) -> float:
        return sum(p.Pv for p in self.parts)


def design_thrust(backfill: Backfill, back: WallBack, method: str, *, q: float = 0.0,
                  delta: float | None = None, kh: float = 0.0, kv: float = 0.0,
                  increment_height: float = 0.5) -> Thrust:
    """Active thrust of ``backfill`` on ``back`` [kN/m] and where it acts.

    method: 'rankine-virtual-back' (Rankine 1857 for a sloping surface, parallel to the
    surface, on a vertical back), 'coulomb' (Mueller-Breslau form, at delta to the face
    normal; delta defaults to beta on a virtual back, where Coulomb with delta = beta is
    Rankine), 'ec7-annex-c' (issue 21). q: uniform surcharge [kPa] per horizontal area,
    its thrust K q H cos(beta) cos(omega) / cos(omega - beta) at mid-height.
    Soil thrust 0.5 K gamma H^2 at H/3 (linear distribution, the usual convention).
    kh > 0: Mononobe-Okabe (EN 1998-5 Annex E, E.2-E.4) with kv > 0 upward; total
    0.5 gamma H^2 (1 - kv) K_AE; the increment over the static thrust acts at
    ``increment_height`` x H above the back's bottom (default 0.5: mid-height, the usual
    EN 1998-5 Annex E reading for walls that do not rotate about the toe; recalled, not
    checked against the text, hence a setting; the static part stays at H/3)."""
    if method not in METHODS:
        raise InvalidParameter("method.earth_pressure", method, " | ".join(METHODS))
    if method == "ec7-annex-c":
        raise InvalidParameter("method.earth_pressure", method, "'rankine-virtual-back' or 'coulomb' "
                               "(EN 1997-1 Annex C comes with issue 21)")
    if backfill.c > 0:
        raise InvalidParameter("backfill.c", backfill.c, "0 kPa until issue 21 (c-phi active thrust)")
    if method == "rankine-virtual-back" and not back.virtual:
        raise InvalidParameter("method.earth_pressure", method, "'coulomb' on a real back")
    d = backfill.beta if delta is None or method == "rankine-virtual-back" else delta
    if abs(d) > backfill.phi + 1e-12:
        raise InvalidParameter("method.wall_friction", d, f"[-phi, phi] = [{-backfill.phi:g}, {backfill.phi:g}] deg")
    return _active_parts(backfill, back, method, q, d, kh, kv, increment_height)


def _active_parts(fill: Backfill, back: WallBack, method: str, q: float, delta: float,
                  kh: float, kv: float, inc: float) -> Thrust:
    """Closed-form K, then the parts. Issue 21's cohesion, water and Annex C go here."""
    phi, b, om, dl = (math.radians(a) for a in (fill.phi, fill.beta, back.omega, delta))
    if method == "rankine-virtual-back":
        K = rankine_coefficient(phi, b)
    else:
        K = coulomb_coefficient(phi, dl, om, b)
    if not math.isfinite(K):
        raise InvalidParameter("method.wall_friction", delta, "a range with a finite Coulomb wedge")
    H, g = back.height, fill.gamma
    surf = math.cos(b) * math.cos(om) / math.cos(om - b)
    horiz, vert = math.cos(dl + om), math.sin(dl + om)
    parts = [_part(back, "earth thrust", "soil", 0.5 * K * g * H * H, horiz, vert, 1 / 3)]
    if q > 0:
        parts.append(_part(back, "surcharge thrust", "surcharge", K * q * H * surf, horiz, vert, 0.5))
    K_total = K
    if kh > 0 or kv != 0:
        K_AE = mononobe_okabe_coefficient(phi, dl, om, b, kh, kv)
        if not math.isfinite(K_AE):
            lim = (1 - kv) * math.tan(phi - b)
            raise InvalidParameter("seismic.kh", kh, f"[0, (1 - kv) tan(phi - beta)] = [0, {lim:.4g}]",
                                   "no active Mononobe-Okabe wedge")
        ratio = (1 - kv) * K_AE / K - 1.0
        static = sum(p.P for p in parts)
        parts.append(_part(back, "seismic increment", "seismic", ratio * static, horiz, vert, inc))
        K_total = (1 - kv) * K_AE
    return Thrust(method, K_total, K_total * horiz, math.degrees(dl), tuple(parts),
                  notes=f"delta = {delta:g} deg on the {'virtual' if back.virtual else 'real'} back", back=back)


def _part(back: WallBack, name: str, kind: str, P: float, horiz: float, vert: float,
          frac: float) -> ThrustPart:
    x, y = back.point_at(back.y0 + frac * back.height)
    return ThrustPart(name, kind, P, P * horiz, P * vert, x, y)


def passive_resistance(soil: Backfill, depth: float, x: float) -> Thrust:
    """Rankine-Bell passive resistance of level ground in front of the wall over
    ``depth`` [m] (embedment plus key), horizontal, at x [m]:
    Pp = 0.5 Kp gamma D^2 (at D/3) + 2 c sqrt(Kp) D (at D/2), Kp = tan^2(45 + phi/2).
    Ph < 0: it pushes the wall back toward the fill. The bottom is the base underside."""
    Kp = rankine_coefficient(math.radians(soil.phi), 0.0, passive=True)
    D = depth
    p1 = 0.5 * Kp * soil.gamma * D * D
    p2 = 2.0 * soil.c * math.sqrt(Kp) * D
    parts = [ThrustPart("passive (soil)", "soil", p1, -p1, 0.0, x, D / 3)]
    if p2 > 0:
        parts.append(ThrustPart("passive (cohesion)", "soil", p2, -p2, 0.0, x, D / 2))
    return Thrust("rankine-bell-passive", Kp, Kp, 0.0, tuple(parts))
