"""Block (dry-stone) walls: courses of blocks whose bed joints dip toward the fill at the
counter-slope alpha, checked for sliding and toppling at every bed joint.

Section (drystone-walls.md 5.3): outer face x_o(y) = y tan(lambda1), inner face
x_i(y) = b - y tan(lambda2), crest at y = h; the base is the bed plane through the toe,
dipping inward at alpha. Bed joint k leaves the outer face at z_k = k h / n and meets the
inner face at y_I = [z - (b - x_o(z)) tan(alpha)] / (1 - tan(lambda2) tan(alpha)).
For the part above a joint:
* sliding along the joint (5.4): E = H, R = (W + V) tan(alpha + phi_b,d) (no sliding
  if alpha + phi_b >= 90 deg);
* toppling about the joint's outer edge O = (x_o(z), z) (5.5 with theta = -alpha):
  E = overturning moment, R = restoring moment (vertical components restore);
* loads on the moving part's inner face only: water from y_I up to the water level
  h_w (H = gamma_w (h_w - y_I)^2 / 2 at a third, V = H tan(lambda2)), or the fill's
  Coulomb thrust above y_I (``earth.design_thrust`` on the real back; with a water table
  in the fill, effective stresses below it and the same water pressure as a separate
  part). Dry joints drain: no uplift in the joints.
* with ``stair_slope`` m > 0 toppling is also tried about lines from O rising inward at
  theta in [-alpha, atan(m) - alpha] through head and bed joints (drystone-walls.md 5.5,
  a pure opening that costs nothing); m = 0 keeps the bed joints only.
Units kN/m3, m, degrees, kN/m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

from scipy.optimize import minimize_scalar

from ..drystone import WallSection, crest_width, water_thrust
from ..errors import InvalidParameter
from ..inputs import MAX_HEIGHT_M, MAX_UNIT_WEIGHT_KN_M3, require_number
from .actions import Force, design_backfill, thrust_forces
from .case import GAMMA_W, DesignCase, design_angle
from .checks import factor_of, make_check, overturning_moments, resultant
from .earth import design_thrust
from .geometry import area_centroid
from .results import CombinationResult, bearing_checks
from .walls import Part, WallBack


@dataclass(frozen=True)
class BlockWall:
    """height h, base b [m]; front_batter lambda1, back_batter lambda2 [deg] (faces'
    angles from vertical, both leaning toward the other face as they rise); courses n;
    joint_slope alpha [deg] (counter-slope toward the fill); joint_friction phi_b [deg];
    unit_weight of the masonry [kN/m3]; stair_slope m = 2 h_block / l_block of a
    half-overlap bond (0: toppling about bed joints only; > 0: also about lines stepping
    through head joints, rising inward at theta in [-alpha, atan(m) - alpha],
    drystone-walls.md 5.5)."""

    height: float
    base: float
    front_batter: float = 0.0
    back_batter: float = 0.0
    courses: int = 10
    joint_slope: float = 0.0
    joint_friction: float = 35.0
    unit_weight: float = 22.0
    stair_slope: float = 0.0
    kind = "blocks"

    def __post_init__(self):
        require_number("wall.height", self.height, 0.0, MAX_HEIGHT_M, hi_open=False, unit="m")
        require_number("wall.base", self.base, 0.0, MAX_HEIGHT_M, hi_open=False, unit="m")
        require_number("wall.front_batter", self.front_batter, -45.0, 45.0, unit="deg")
        require_number("wall.back_batter", self.back_batter, -45.0, 45.0, unit="deg")
        require_number("wall.joint_slope", self.joint_slope, -45.0, 45.0, unit="deg")
        require_number("wall.joint_friction", self.joint_friction, 0.0, 90.0, unit="deg")
        require_number("wall.unit_weight", self.unit_weight, 0.0, MAX_UNIT_WEIGHT_KN_M3, hi_open=False, unit="kN/m3")
        require_number("wall.stair_slope", self.stair_slope, 0.0, 10.0, lo_open=False)
        if isinstance(self.courses, bool) or not isinstance(self.courses, int) or self.courses < 1:
            raise InvalidParameter("wall.courses", self.courses, "an integer >= 1")
        if self.crest <= 0:
            raise InvalidParameter("wall.base", self.base, f"> h (tan lambda1 + tan lambda2) = "
                                   f"{self.base - self.crest:.4g} m", "a base narrower than the wall above it")

    @property
    def B(self) -> float:
        return self.base

    @property
    def H(self) -> float:
        return self.height

    @property
    def crest(self) -> float:
        """Crest width [m] (checked before ``profile`` exists, so the message names wall.base)."""
        return crest_width(self.height, self.base, self.front_batter, self.back_batter)

    @cached_property
    def profile(self) -> WallSection:
        """The section as the dry-stone limit equilibrium sees it (analytic/drystone.py):
        one geometry for the design checks and the dry-stone study."""
        return WallSection(self.height, self.base, self.front_batter, self.back_batter, self.joint_slope)

    def x_o(self, y: float) -> float:
        return self.profile.x_outer(y)

    def x_i(self, y: float) -> float:
        return self.profile.x_inner(y)

    def section(self) -> list:
        """The section polygon, its base the bed plane through the toe."""
        return self.profile.polygon()

    def joints(self) -> list[float]:
        """Heights z_k [m] where the bed joints leave the outer face (z_0 = 0: the base)."""
        return [k * self.height / self.courses for k in range(self.courses)]

    def above(self, z: float, slope: float | None = None) -> tuple[list, float]:
        """The part above the line through (x_o(z), z) with dy/dx = slope (default the
        bed joint, -tan alpha), and where that line meets the inner face, y_I [m]
        (``WallSection.part_above``)."""
        return self.profile.part_above(z, slope)

    def parts(self) -> list[Part]:
        return [Part("masonry", tuple(self.section()), self.unit_weight, "structural")]

    def fill_top(self):
        return self.x_i(self.height), self.height

    def with_dimension(self, name: str, value: float) -> "BlockWall":
        if name != "base":
            raise InvalidParameter("solve", name, "'base' for a block wall")
        return replace(self, base=value)


def joint_forces(case: DesignCase, z: float, materials: dict, kh: float = 0.0,
                 kv: float = 0.0, slope: float | None = None) -> tuple[list[Force], float]:
    """Forces on the part above the joint at z (or above the line of ``slope`` from the
    joint's outer edge): weight, inertia, water or fill thrust."""
    wall = case.wall
    poly, y_I = wall.above(z, slope)
    A, xg, yg = area_centroid(poly)
    W = A * wall.unit_weight
    out = [Force("masonry above joint", "G", "structural", 0.0, W, xg, yg)]
    if kh > 0 or kv != 0:
        out.append(Force("masonry inertia", "E", "structural", kh * W, -kv * W, xg, yg))
    hw = min(case.water.behind, wall.height)
    if hw > y_I and case.backfill is None:
        Hw, Vw, xH, yH = water_thrust(wall.profile, y_I, hw)
        out.append(Force("water on back", "G", "geotechnical", Hw, Vw, xH, yH))
        if kh > 0:
            out.append(_hydrodynamic_on_back(wall, y_I, hw, kh))
    if case.backfill is not None and wall.height > y_I:
        fill = design_backfill(case.backfill, materials)
        back = WallBack(wall.x_i(y_I), y_I, wall.height - y_I, wall.back_batter)
        delta = case.method.wall_friction if case.method.wall_friction is not None else 2 / 3 * fill.phi
        thrust = design_thrust(fill, back, "coulomb", q=case.loads.surcharge, delta=min(delta, fill.phi),
                               kh=kh, kv=kv, increment_height=case.seismic.increment_height,
                               water_level=max(hw - y_I, 0.0), permeability=case.seismic.fill_permeability)
        out += thrust_forces(thrust, case.loads.surcharge_permanent)
    return out, y_I


def _hydrodynamic_on_back(wall: BlockWall, y_I: float, hw: float, kh: float) -> Force:
    """EN 1998-5 Annex E.8 for the free water behind the wall (depth hw [m] from the
    toe's level): q(z) = 7/8 kh gamma_w sqrt(hw z) at depth z, integrated over the face
    above y_I [m] (d = hw - y_I): 7/12 kh gamma_w sqrt(hw) d^1.5 at 0.4 d above y_I,
    horizontal (Westergaard's vertical face), toward the front (the unfavourable sign)."""
    d = hw - y_I
    y = y_I + 0.4 * d
    return Force("hydrodynamic water on back (EN 1998-5 E.8)", "E", "geotechnical",
                 7.0 / 12.0 * kh * GAMMA_W * math.sqrt(hw) * d ** 1.5, 0.0, wall.x_i(y), y)


def _shift(forces: list[Force], x0: float, y0: float) -> list[Force]:
    return [replace(f, x=f.x - x0, y=f.y - y0) for f in forces]


def joint_checks(case: DesignCase, combo, z: float, kh: float = 0.0, kv: float = 0.0) -> dict:
    """Sliding along the bed joint at z and toppling about its outer edge (over the
    stepped lines too when ``stair_slope`` > 0): utilisations of the part above."""
    wall, mats = case.wall, combo.materials
    forces, y_I = joint_forces(case, z, mats, kh, kv)
    local = _shift(forces, wall.x_o(z), z)
    ang = wall.joint_slope + design_angle(wall.joint_friction, mats["phi"])
    tan_r = math.tan(math.radians(ang)) if ang < 90 else math.inf
    ss = case.method.single_source and combo.name != "EQU"
    g_s = [factor_of(f, combo, "sliding", min(tan_r, 1e9), ss) for f in local]
    V, H, _ = resultant(local, g_s)
    slide = make_check("sliding", H, V * tan_r if math.isfinite(tan_r) else math.inf,
                       f"bed joint at z = {z:.3f} m, tan(alpha + phi_b,d)")
    topple = _topple_worst(case, combo, z, kh, kv, ss)
    return {"z": z, "y_I": y_I, "sliding": slide, "overturning": topple, "V": V, "H": H}


def _topple(case: DesignCase, combo, z: float, theta: float, kh: float, kv: float, ss: bool):
    """Toppling about (x_o(z), z) of the part above the line rising inward at theta [deg]."""
    wall = case.wall
    forces, _ = joint_forces(case, z, combo.materials, kh, kv, slope=math.tan(math.radians(theta)))
    local = _shift(forces, wall.x_o(z), z)
    g = [factor_of(f, combo, "overturning", 0.0, ss) for f in local]
    dst, stb = overturning_moments(local, g, net=case.method.thrust_moment == "net")
    return make_check("overturning", dst, stb, f"toppling about the outer edge of the joint at z = {z:.3f} m, "
                                               f"line at theta = {theta:.2f} deg")


def _topple_worst(case: DesignCase, combo, z: float, kh: float, kv: float, ss: bool):
    """The bed joint (theta = -alpha) or, with stair_slope m > 0, the worst line over
    theta in [-alpha, atan(m) - alpha] (a 17-point grid refined by a bounded search)."""
    wall = case.wall
    lo = -wall.joint_slope
    if wall.stair_slope <= 0:
        return _topple(case, combo, z, lo, kh, kv, ss)
    hi = math.degrees(math.atan(wall.stair_slope)) - wall.joint_slope
    grid = [lo + (hi - lo) * k / 16 for k in range(17)]
    checks = [_topple(case, combo, z, t, kh, kv, ss) for t in grid]
    k = max(range(17), key=lambda i: checks[i].utilisation)
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, 16)]
    res = minimize_scalar(lambda t: -_topple(case, combo, z, t, kh, kv, ss).utilisation, bounds=(a, b),
                          method="bounded", options={"xatol": 1e-4})
    best = _topple(case, combo, z, float(res.x), kh, kv, ss)
    return best if best.utilisation > checks[k].utilisation else checks[k]


def evaluate_blocks(case: DesignCase, combo, *, kh: float = 0.0, kv: float = 0.0,
                    ecc_limit: float = 1 / 3):
    """Every bed joint's checks; the worst sliding and toppling become the combination's
    'sliding' and 'overturning'; with a foundation, bearing and eccentricity of the base
    (B = b, the base's tilt neglected)."""
    rows = [joint_checks(case, combo, z, kh, kv) for z in case.wall.joints()]
    out = CombinationResult(combo.name, B=case.wall.B, kh=kh, kv=kv)
    out.joints = rows
    for name in ("overturning",) if combo.name == "EQU" else ("sliding", "overturning"):
        out.checks[name] = max((r[name] for r in rows), key=lambda c: c.utilisation)
    base = rows[0]
    out.V_d, out.H_d = base["V"], base["H"]
    if case.foundation is not None and combo.name != "EQU":
        forces, _ = joint_forces(case, 0.0, combo.materials, kh, kv)
        g = [factor_of(f, combo, "bearing", 0.0, False) for f in forces]
        V, H, M = resultant(forces, g)
        out.e = case.wall.B / 2 - M / V
        bchecks, out.q_ult, out.B_eff = bearing_checks(case, combo, V, H, out.e)
        for c in bchecks:
            out.checks[c.name] = c
        out.checks["eccentricity"] = make_check("eccentricity", abs(out.e), ecc_limit * case.wall.B)
    return out


def critical_water_height(case: DesignCase, combo, tol: float = 1e-6,
                          mechanisms: tuple = ("sliding", "overturning")) -> tuple[float, str, float]:
    """Water level h_w [m] above the toe at which the worst joint reaches utilisation 1
    in one of ``mechanisms`` (bisection on [0, h]); returns (h_w, mechanism, joint z).
    h_w = inf if the wall stands with water up to its crest (water cannot rise higher
    against it)."""
    from .case import Water

    def worst(hw):
        c = replace(case, water=Water(behind=hw))
        rows = [joint_checks(c, combo, z) for z in case.wall.joints()]
        best = max(((r[m].utilisation, m, r["z"]) for r in rows for m in mechanisms))
        return best
    if worst(case.wall.height)[0] < 1.0:
        return math.inf, "", math.nan
    lo, hi = 0.0, case.wall.height
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if worst(mid)[0] < 1.0 else (lo, mid)
    u, mech, z = worst(hi)
    return hi, mech, z
