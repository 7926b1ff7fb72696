"""The one earth-pressure interface of the design checks: ``design_thrust``.

Every check asks this module for the thrust of the fill on a ``WallBack`` and gets its
parts (soil, surcharge, water, seismic increment) as forces with a point of application.
A dry, cohesionless fill under Rankine or Coulomb takes the closed forms of
``analytic/classical.py`` (``_active_parts``); a cohesive fill, a water table in the
fill or EN 1997-1 Annex C take ``analytic.ground.earth_pressure`` (``_ground_parts``):
effective stresses below the water table (gamma_sat - gamma_w), Bell's cohesion term
with the tension crack not counted (Rankine), EN 1997-1 C.1 K_ac with a = 0 (Coulomb),
Annex C.2 K_gamma, K_q, K_c (ec7-annex-c), and the water pressure as its own part.

Units: kN/m3, kPa, m, degrees; forces in kN per metre run. Sign: ``Ph`` > 0 pushes the
wall toward its front (away from the fill), ``Pv`` > 0 acts downward on the wall.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..classical import coulomb_coefficient, rankine_coefficient
from ..errors import InvalidParameter, NotApplicable
from ..constants import GAMMA_W
from ..ground import Ground, Layer, earth_pressure
from ..inputs import MAX_PRESSURE_KPA, MAX_UNIT_WEIGHT_KN_M3, Wall, require_number
from ..seismic import mononobe_okabe_coefficient
from .walls import WallBack

METHODS = ("rankine-virtual-back", "coulomb", "ec7-annex-c")
GROUND_METHODS = {"rankine-virtual-back": "rankine", "coulomb": "coulomb", "ec7-annex-c": "ec7-annex-c"}


def check_soil(table: str, soil) -> None:
    """gamma > 0 [kN/m3], phi in [0, 50] [deg], c >= 0 [kPa], gamma_sat >= gamma_w;
    phi = 0 is an undrained clay in total stress, whose c is c_u > 0."""
    require_number(f"{table}.gamma", soil.gamma, 0.0, MAX_UNIT_WEIGHT_KN_M3, hi_open=False, unit="kN/m3")
    require_number(f"{table}.phi", soil.phi, 0.0, 50.0, lo_open=False, hi_open=False, unit="deg")
    require_number(f"{table}.c", soil.c, 0.0, MAX_PRESSURE_KPA, lo_open=False, hi_open=False, unit="kPa")
    if soil.phi == 0 and soil.c <= 0:
        raise InvalidParameter(f"{table}.c", soil.c, "> 0 with phi = 0", "phi = 0 is the undrained case: c is c_u")
    if soil.gamma_sat is not None:
        require_number(f"{table}.gamma_sat", soil.gamma_sat, GAMMA_W, None, lo_open=False, unit="kN/m3")


@dataclass(frozen=True)
class FillLayer:
    """A layer of the fill above the ``Backfill`` soil: thickness [m] down the back from
    the fill surface (or from the layer above), gamma, gamma_sat [kN/m3], phi [deg] in
    (0, 50], c [kPa] (effective c')."""

    thickness: float
    gamma: float
    phi: float
    c: float = 0.0
    gamma_sat: float | None = None

    def __post_init__(self):
        require_number("backfill.layers.thickness", self.thickness, 0.0, None, unit="m")
        check_soil("backfill.layers", self)

    @property
    def gamma_wet(self) -> float:
        """Unit weight below the water table [kN/m3]."""
        return self.gamma if self.gamma_sat is None else self.gamma_sat


@dataclass(frozen=True)
class Backfill:
    """Fill behind (or soil in front of) the wall: gamma [kN/m3], phi [deg] in (0, 50],
    c [kPa] (effective c'), beta [deg] surface slope, + rising away from the wall;
    gamma_sat [kN/m3] below a water table (default: gamma); layers: ``FillLayer``
    records from the fill surface down, above this soil, which reaches the base."""

    gamma: float
    phi: float
    c: float = 0.0
    beta: float = 0.0
    gamma_sat: float | None = None
    layers: tuple = ()

    gamma_wet = FillLayer.gamma_wet

    @property
    def cohesive(self) -> bool:
        """c' > 0 in any layer."""
        return any(x.c > 0 for x in (self, *self.layers))

    def strata(self, H: float) -> list:
        """(depth of the top, depth of the bottom [m], soil) down a back of height H [m]:
        the layers, cut at H, then this soil down to H."""
        out, z = [], 0.0
        for x in (*self.layers, self):
            bot = H if x is self else min(z + x.thickness, H)
            if bot > z:
                out.append((z, bot, x))
            z = bot
        return out

    def __post_init__(self):
        check_soil("backfill", self)
        if not all(isinstance(x, FillLayer) for x in self.layers):
            raise InvalidParameter("backfill.layers", len(self.layers), "tables with thickness, gamma, phi "
                                   "(and c, gamma_sat)")
        if abs(self.beta) > self.phi:
            raise InvalidParameter("backfill.beta", self.beta, f"[-phi, phi] = [{-self.phi:g}, {self.phi:g}] deg",
                                   "no active wedge on a slope steeper than phi")


@dataclass(frozen=True)
class ThrustPart:
    """One part of a thrust: resultant P [kN/m], components Ph (toward the front) and
    Pv (down) [kN/m], point of application (x, y) [m]; ``kind`` 'soil', 'surcharge',
    'water' (normal to the back) or 'seismic' (the dynamic increment of the soil and
    surcharge thrust)."""

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
        return math.fsum(p.Ph for p in self.parts)

    @property
    def Pv(self) -> float:
        return math.fsum(p.Pv for p in self.parts)


@dataclass(frozen=True)
class MeasuredThrust:
    """A characteristic thrust of the fill and its surcharge on the back measured rather
    than computed (a DEM of the same back, ``studies.wall``): horizontal Ph (toward the
    front) and vertical Pv (down) [kN/m], acting ``height`` [m] above the back's bottom;
    ``source`` says where it came from."""

    Ph: float
    Pv: float
    height: float
    source: str = ""

    def __post_init__(self):
        require_number("measured_thrust.Ph", self.Ph, 0.0, None, lo_open=False, unit="kN/m")
        require_number("measured_thrust.Pv", self.Pv, None, None, unit="kN/m")
        require_number("measured_thrust.height", self.height, 0.0, None, lo_open=False, unit="m")


def with_measured(design: Thrust, characteristic: Thrust, measured: MeasuredThrust) -> Thrust:
    """``design`` with its soil and surcharge parts replaced by ``measured``: each part
    carries its share of the characteristic classical thrust (``characteristic``, same
    back, unfactored) times the measured thrust, times the factor the combination puts on
    the classical thrust (design over characteristic Ph: a measured load keeps the margin
    EN 1997-1 puts on phi), each moved by the same distance so that their characteristic
    resultant acts at the measured height (the permanent and variable parts keep their
    own factors and their spacing). Water and seismic parts stay."""
    loads = ("soil", "surcharge")
    back = design.back
    char = {p.name: (p.Ph, p.y - back.y0) for p in characteristic.parts if p.kind in loads}
    total_char = math.fsum(ph for ph, _ in char.values())
    total_design = math.fsum(p.Ph for p in design.parts if p.kind in loads)
    factor = total_design / total_char if total_char > 0 else 1.0
    height_char = math.fsum(ph * h for ph, h in char.values()) / total_char if total_char > 0 else 0.0
    shift = measured.height - height_char
    parts = []
    for p in design.parts:
        if p.kind not in loads:
            parts.append(p)
            continue
        ph, h = char[p.name]
        share = ph / total_char if total_char > 0 else 0.0
        Ph, Pv = factor * share * measured.Ph, factor * share * measured.Pv
        x, y = back.point_at(back.y0 + min(max(h + shift, 0.0), back.height))
        parts.append(ThrustPart(f"{p.name} (measured)", p.kind, math.hypot(Ph, Pv), Ph, Pv, x, y))
    scale = measured.Ph / total_char if total_char > 0 else 1.0
    note = (f"soil and surcharge thrust measured ({measured.source}): Ph {measured.Ph:.4g} kN/m, Pv "
            f"{measured.Pv:.4g} kN/m at {measured.height:.4g} m, x {factor:.4g} (this combination's factor on the "
            "classical thrust)")
    return Thrust(design.method, design.K * scale, design.Kh * scale, design.direction, tuple(parts),
                  notes=f"{design.notes}; {note}", back=back)


def design_thrust(backfill: Backfill, back: WallBack, method: str, *, q: float = 0.0,
                  delta: float | None = None, kh: float = 0.0, kv: float = 0.0,
                  increment_height: float = 0.5, water_level: float = 0.0,
                  permeability: str | None = None) -> Thrust:
    """Active thrust of ``backfill`` on ``back`` [kN/m] and where it acts.

    method: 'rankine-virtual-back' (Rankine 1857 for a sloping surface, parallel to the
    surface, on a vertical back), 'coulomb' (Mueller-Breslau form, at delta to the face
    normal; delta defaults to beta on a virtual back, where Coulomb with delta = beta is
    Rankine), 'ec7-annex-c' (EN 1997-1 Annex C.2, eqs. C.3-C.9: normal components,
    shear at delta). q: uniform surcharge [kPa] per horizontal area, its thrust
    K q H cos(beta) cos(omega) / cos(omega - beta) at mid-height.
    Soil thrust 0.5 K gamma H^2 at H/3 (linear distribution, the usual convention).
    Cohesion c > 0, a water table ``water_level`` [m] above the back's bottom, or
    Annex C: ``analytic.ground.earth_pressure`` (see ``_ground_parts``).
    kh > 0: Mononobe-Okabe (EN 1998-5 Annex E, E.2-E.4) with kv > 0 upward; total
    0.5 gamma H^2 (1 - kv) K_AE; the increment over the static thrust acts at
    ``increment_height`` x H above the back's bottom (default 0.5: mid-height, the usual
    EN 1998-5 Annex E reading for walls that do not rotate about the toe; recalled, not
    checked against the text, hence a setting; the static part stays at H/3).
    Seismic with the fill submerged to its surface (``water_level`` = H): EN 1998-5 E.6
    (``permeability`` 'impervious': tan(psi) = gamma_sat / (gamma_sat - gamma_w) x
    kh / (1 - kv)) or E.7 ('pervious': gamma / (gamma_sat - gamma_w) x kh / (1 - kv),
    gamma standing for the dry unit weight, plus the hydrodynamic thrust
    7/12 kh gamma_w H^2 at 0.4 H, normal to the back); the increment scales the
    effective (gamma_sat - gamma_w) static thrust, the water stays hydrostatic."""
    if method not in METHODS:
        raise InvalidParameter("method.earth_pressure", method, " | ".join(METHODS))
    if method == "rankine-virtual-back" and not back.virtual:
        raise InvalidParameter("method.earth_pressure", method, "'coulomb' or 'ec7-annex-c' on a real back")
    d = backfill.beta if delta is None or method == "rankine-virtual-back" else delta
    if abs(d) > backfill.phi + 1e-12:
        raise InvalidParameter("method.wall_friction", d, f"[-phi, phi] = [{-backfill.phi:g}, {backfill.phi:g}] deg")
    if not 0.0 <= water_level <= back.height + 1e-9:
        raise InvalidParameter("water.behind", water_level, f"[0, {back.height:g}] m (up to the fill surface "
                               "at the back)")
    if backfill.cohesive or water_level > 0 or method == "ec7-annex-c" or backfill.layers:
        return _ground_parts(backfill, back, method, q, d, water_level, kh, kv, increment_height, permeability)
    return _active_parts(backfill, back, method, q, d, kh, kv, increment_height)


def _active_parts(fill: Backfill, back: WallBack, method: str, q: float, delta: float,
                  kh: float, kv: float, inc: float) -> Thrust:
    """Closed-form K for a dry cohesionless fill, then the parts."""
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
        parts.append(_seismic_increment(fill, back, K, parts, dl, kh, kv, inc))
        K_total = (1 - kv) * mononobe_okabe_coefficient(phi, dl, om, b, kh, kv)
    return Thrust(method, K_total, K_total * horiz, math.degrees(dl), tuple(parts),
                  notes=f"delta = {delta:g} deg on the {'virtual' if back.virtual else 'real'} back", back=back)


def _seismic_increment(fill: Backfill, back: WallBack, K: float, static: list, dl: float,
                       kh: float, kv: float, inc: float, angle_factor: float = 1.0) -> ThrustPart:
    """Mononobe-Okabe increment over the static thrust ``static`` (its soil and surcharge
    parts, coefficient K along the thrust): ((1 - kv) K_AE / K - 1) x static, at ``inc``
    x H (EN 1998-5 Annex E, E.2-E.4); ``angle_factor`` scales tan(psi) for a submerged
    fill (E.6, E.7)."""
    phi, b, om = (math.radians(a) for a in (fill.phi, fill.beta, back.omega))
    K_AE = mononobe_okabe_coefficient(phi, dl, om, b, angle_factor * kh, kv)
    if not math.isfinite(K_AE):
        lim = (1 - kv) * math.tan(phi - b) / angle_factor
        raise InvalidParameter("seismic.kh", kh, f"[0, (1 - kv) tan(phi - beta){' / ' if angle_factor != 1 else ''}"
                               f"{f'{angle_factor:.4g}' if angle_factor != 1 else ''}] = [0, {lim:.4g}]",
                               "no active Mononobe-Okabe wedge")
    ratio = (1 - kv) * K_AE / K - 1.0
    total = math.fsum(p.P for p in static if p.kind in ("soil", "surcharge"))
    return _part(back, "seismic increment", "seismic", ratio * total, math.cos(dl + om), math.sin(dl + om), inc)


def _submerged_angle_factor(fill: Backfill, H: float, water_level: float, permeability: str | None) -> float:
    """tan(psi) factor of EN 1998-5 E.6 / E.7 for a fill submerged to its surface (1 when
    dry); anything else Annex E does not give is refused, one line."""
    if fill.cohesive or fill.layers:
        raise InvalidParameter("seismic.alpha", "> 0", "0 with a cohesive or layered fill",
                               "Mononobe-Okabe (EN 1998-5 Annex E) is for a uniform, cohesionless fill")
    if water_level <= 0:
        return 1.0
    if water_level < H - 1e-9:
        raise InvalidParameter("water.behind", water_level, f"0 or {H:g} m (the fill surface) in the seismic "
                               "situation", "EN 1998-5 Annex E covers a water table below the wall (E.5) or "
                               "the whole fill submerged (E.6, E.7), not one in between")
    if permeability not in ("impervious", "pervious"):
        raise InvalidParameter("seismic.fill_permeability", "missing", "'impervious' (EN 1998-5 E.6) or "
                               "'pervious' (E.7)", "needed with water behind the wall")
    g_sat = fill.gamma_wet
    if g_sat <= GAMMA_W:
        raise InvalidParameter("backfill.gamma_sat", g_sat, f"> gamma_w = {GAMMA_W:g} kN/m3",
                               "EN 1998-5 E.6/E.7 divide by gamma_sat - gamma_w")
    return (g_sat if permeability == "impervious" else fill.gamma) / (g_sat - GAMMA_W)


def _ground_parts(fill: Backfill, back: WallBack, method: str, q: float, delta: float, water_level: float,
                  kh: float, kv: float, inc: float, permeability: str | None = None) -> Thrust:
    """Soil, surcharge and water parts from ``analytic.ground.earth_pressure`` (the
    strata of the fill; kN -> N). Each effective part acts at delta (beta for Rankine) to
    the face normal, P = N / cos(delta); the water part is normal to the face. Seismic
    (Mononobe-Okabe, same ratio rule) for a uniform cohesionless fill, dry or submerged to
    its surface (``design_thrust``); a cohesive or layered fill, or a water table between
    the base and the surface, is refused: Annex E does not give them."""
    seismic = kh > 0 or kv != 0
    factor = _submerged_angle_factor(fill, back.height, water_level, permeability) if seismic else 1.0
    H = back.height
    layers = tuple(Layer(b - t, x.phi, x.gamma * 1e3, x.c * 1e3, None if x.gamma_sat is None else x.gamma_sat * 1e3)
                   for t, b, x in fill.strata(H))
    ground = Ground(layers, water_depth=H - water_level if water_level > 0 else None)
    wall = Wall(H, delta_deg=delta, omega_deg=back.omega, beta_deg=fill.beta, surcharge=q * 1e3)
    try:
        prof = earth_pressure(ground, wall, GROUND_METHODS[method])
    except NotApplicable as err:
        raise InvalidParameter("method.earth_pressure", method, "ec7-annex-c for this back and fill",
                               f"{err.name} = {err.value:g}: {err.why}") from None
    d, om = math.radians(prof.direction_deg), math.radians(back.omega)
    parts = []
    for key, name, ang in (("soil", "earth thrust", d), ("surcharge", "surcharge thrust", d),
                           ("water", "water thrust", 0.0)):
        p = prof.parts[key]
        if p.N > 0:
            P = float(p.N) / 1e3 / math.cos(ang)
            x, y = back.point_at(back.y0 + float(p.height))
            parts.append(ThrustPart(name, "soil" if key == "soil" else key, P, P * math.cos(ang + om),
                                    P * math.sin(ang + om), x, y))
    K = float(prof.K_layers[0])
    K_total = K
    if seismic:
        parts.append(_seismic_increment(fill, back, K, parts, d, kh, kv, inc, factor))
        K_total = (1 - kv) * mononobe_okabe_coefficient(math.radians(fill.phi), d, om, math.radians(fill.beta),
                                                       factor * kh, kv)
        if water_level > 0 and permeability == "pervious":
            Ewd = 7.0 / 12.0 * kh * GAMMA_W * H * H
            x, y = back.point_at(back.y0 + 0.4 * H)
            parts.append(ThrustPart("hydrodynamic water (EN 1998-5 E.7)", "seismic", Ewd, Ewd * math.cos(om),
                                    Ewd * math.sin(om), x, y))
    notes = f"delta = {delta:g} deg on the {'virtual' if back.virtual else 'real'} back; {prof.source}"
    return Thrust(method, K_total, K_total * math.cos(d + om), prof.direction_deg, tuple(parts),
                  notes="; ".join(x for x in (notes, prof.notes) if x), back=back)


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
