"""The records a design check takes: foundation, loads, water, method, seismic, and the
``DesignCase`` that holds them with the wall and the backfill.

Units: kN/m3, kPa, m, degrees. Levels of water are heights above the underside of the
base (at the toe). Everything is validated on construction (``InvalidParameter``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InvalidParameter
from ..inputs import MAX_PRESSURE_KPA, MAX_UNIT_WEIGHT_KN_M3, require_number
from .earth import GAMMA_W, METHODS, Backfill, MeasuredThrust


def require_bool(name: str, value) -> None:
    """A switch must be true or false (TOML booleans)."""
    if not isinstance(value, bool):
        raise InvalidParameter(name, value, "true or false")


@dataclass(frozen=True)
class Foundation:
    """Soil under and in front of the base. phi [deg] in (0, 50], c [kPa] (drained c'),
    gamma [kN/m3]; base friction delta_b = base_friction_ratio x phi, or
    base_friction_angle [deg] if given (EN 1997-1 6.5.3(10): delta_b = k phi'_cv);
    base_adhesion [kPa] on the full base B (textbook k2 c2; default 0, EN 1997-1 6.5.3
    neglects it); embedment [m] of the base underside below the ground in front
    (overburden q' = gamma x embedment); cu [kPa]: adds the undrained checks."""

    gamma: float
    phi: float
    c: float = 0.0
    base_friction_ratio: float = 2.0 / 3.0
    base_friction_angle: float | None = None
    base_adhesion: float = 0.0
    embedment: float = 0.0
    cu: float | None = None

    def __post_init__(self):
        require_number("foundation.gamma", self.gamma, 0.0, MAX_UNIT_WEIGHT_KN_M3, hi_open=False, unit="kN/m3")
        require_number("foundation.phi", self.phi, 0.0, 50.0, hi_open=False, unit="deg")
        require_number("foundation.c", self.c, 0.0, MAX_PRESSURE_KPA, lo_open=False, hi_open=False, unit="kPa")
        require_number("foundation.base_friction_ratio", self.base_friction_ratio, 0.0, 1.0, hi_open=False)
        if self.base_friction_angle is not None:
            require_number("foundation.base_friction_angle", self.base_friction_angle, 0.0, self.phi,
                           hi_open=False, unit="deg")
        require_number("foundation.base_adhesion", self.base_adhesion, 0.0, MAX_PRESSURE_KPA, lo_open=False,
                       hi_open=False, unit="kPa")
        require_number("foundation.embedment", self.embedment, 0.0, None, lo_open=False, unit="m")
        if self.cu is not None:
            require_number("foundation.cu", self.cu, 0.0, MAX_PRESSURE_KPA, hi_open=False, unit="kPa")

    @property
    def delta_b(self) -> float:
        """Characteristic base friction angle [deg]."""
        if self.base_friction_angle is not None:
            return self.base_friction_angle
        return self.base_friction_ratio * self.phi


@dataclass(frozen=True)
class Loads:
    """Uniform surcharge q [kPa] on the fill surface, variable unless permanent."""

    surcharge: float = 0.0
    surcharge_permanent: bool = False

    def __post_init__(self):
        require_number("loads.surcharge", self.surcharge, 0.0, MAX_PRESSURE_KPA, lo_open=False, hi_open=False,
                       unit="kPa")
        require_bool("loads.surcharge_permanent", self.surcharge_permanent)


@dataclass(frozen=True)
class Water:
    """Free-water levels [m] above the base underside in front and behind the wall.
    Uplift varies linearly under the base between the two. Behind a cantilever or
    gravity wall ``behind`` is the water table in the fill (effective stresses below it,
    the water thrust a separate action; ``actions.py``)."""

    front: float = 0.0
    behind: float = 0.0

    def __post_init__(self):
        require_number("water.front", self.front, 0.0, None, lo_open=False, unit="m")
        require_number("water.behind", self.behind, 0.0, None, lo_open=False, unit="m")


@dataclass(frozen=True)
class Method:
    """earth_pressure: see ``earth.METHODS``; wall_friction [deg] on the back (default:
    beta on a virtual back, 2/3 phi on a real back); passive: count passive resistance
    in front (sliding only) times passive_mobilisation (off by default); single_source:
    every permanent action takes the unfavourable factor (EN 1997-1 2.4.2(9)P Note 1;
    off: each action is favourable or not by its own effect on the check);
    thrust_moment: 'restoring' (the vertical thrust component adds to the restoring
    moment, the textbook factor-of-safety convention) or 'net' (each force's net moment
    about the toe, as in the JRC EC7 worked example A.4)."""

    earth_pressure: str = "rankine-virtual-back"
    wall_friction: float | None = None
    passive: bool = False
    passive_mobilisation: float = 0.5
    single_source: bool = False
    thrust_moment: str = "restoring"

    def __post_init__(self):
        if self.thrust_moment not in ("restoring", "net"):
            raise InvalidParameter("method.thrust_moment", self.thrust_moment, "'restoring' or 'net'")
        if self.earth_pressure not in METHODS:
            raise InvalidParameter("method.earth_pressure", self.earth_pressure, " | ".join(METHODS))
        require_number("method.passive_mobilisation", self.passive_mobilisation, 0.0, 1.0, hi_open=False)
        require_bool("method.passive", self.passive)
        require_bool("method.single_source", self.single_source)
        if self.wall_friction is not None:
            require_number("method.wall_friction", self.wall_friction, -50.0, 50.0, lo_open=False,
                           hi_open=False, unit="deg")


@dataclass(frozen=True)
class Seismic:
    """EN 1998-5 7.3.2.2: alpha = a_g/g (design ground acceleration incl. gamma_I),
    S soil factor, r from Table 7.1 (1 to 2: how much displacement the wall accepts),
    vertical_ratio = a_vg/a_g; increment_height: where the dynamic increment acts, as a
    fraction of the back's height (0.5 = mid-height); fill_permeability: 'impervious'
    (EN 1998-5 E.6) or 'pervious' (E.7, k > 5e-4 m/s), needed with water behind.
    given: the case has a seismic situation (a [seismic] table); the default of a case
    without one is ``NO_SEISMIC``, which the seismic format refuses."""

    alpha: float = 0.0
    S: float = 1.0
    r: float = 1.0
    vertical_ratio: float = 0.9
    increment_height: float = 0.5
    fill_permeability: str | None = None
    given: bool = True

    def __post_init__(self):
        require_number("seismic.alpha", self.alpha, 0.0, 1.0, lo_open=False)
        require_number("seismic.S", self.S, 0.0, 3.0)
        require_number("seismic.r", self.r, 1.0, 2.0, lo_open=False, hi_open=False)
        require_number("seismic.vertical_ratio", self.vertical_ratio, 0.0, 2.0, lo_open=False)
        require_number("seismic.increment_height", self.increment_height, 0.0, 1.0, hi_open=False)
        if self.fill_permeability not in (None, "impervious", "pervious"):
            raise InvalidParameter("seismic.fill_permeability", self.fill_permeability, "'impervious' or 'pervious'")

    @property
    def kh(self) -> float:
        """k_h = alpha S / r (EN 1998-5 eq. 7.1)."""
        return self.alpha * self.S / self.r

    @property
    def kv(self) -> float:
        """|k_v| = 0.5 k_h if a_vg/a_g > 0.6, else 0.33 k_h (EN 1998-5 eqs. 7.2, 7.3)."""
        return (0.5 if self.vertical_ratio > 0.6 else 0.33) * self.kh


#: a case without a [seismic] table: no earthquake (k_h = 0), and no seismic check
NO_SEISMIC = Seismic(given=False)

#: the widest base accepted, as a multiple of the wall's height (practice: 0.4-0.8)
MAX_BASE_OVER_HEIGHT = 10.0


@dataclass(frozen=True)
class DesignCase:
    """A wall (walls.py / blocks.py), its backfill (None: a block wall loaded by water
    only), foundation and the rest; ``measured_thrust`` (none: classical) replaces the
    computed soil and surcharge thrust (``earth.with_measured``)."""

    wall: object
    backfill: Backfill | None
    foundation: Foundation | None = None
    loads: Loads = Loads()
    water: Water = Water()
    method: Method = Method()
    seismic: Seismic = NO_SEISMIC
    measured_thrust: MeasuredThrust | None = None

    def __post_init__(self):
        kind = getattr(self.wall, "kind", "")
        if kind != "blocks" and self.backfill is None:
            raise InvalidParameter("backfill", "missing", "a [backfill] table for a cantilever or gravity wall")
        if kind != "blocks" and self.foundation is None:
            raise InvalidParameter("foundation", "missing", "a [foundation] table")
        self._check_proportions()

    def _check_proportions(self) -> None:
        """Dimensions that no wall has, refused before anything is computed: a base more
        than ``MAX_BASE_OVER_HEIGHT`` times the height (a length typed in mm, e.g. heel =
        3000), an embedment as deep as the wall, water above its top, fill layers thicker
        than the retained height."""
        H, B = self.wall.H, self.wall.B
        if B > MAX_BASE_OVER_HEIGHT * H:
            raise InvalidParameter("wall base width B", f"{B:g} m", f"<= {MAX_BASE_OVER_HEIGHT * H:g} m "
                                   f"({MAX_BASE_OVER_HEIGHT:g} x the height {H:g} m)",
                                   "no retaining wall is this wide: a length in mm?")
        if self.foundation is not None and self.foundation.embedment >= H:
            raise InvalidParameter("foundation.embedment", self.foundation.embedment, f"[0, height = {H:g}) m",
                                   "the wall would be buried in front")
        for side in ("front", "behind"):
            level = getattr(self.water, side)
            if level > H:
                raise InvalidParameter(f"water.{side}", level, f"[0, height = {H:g}] m", "above the wall's top")
        if self.backfill is not None and self.backfill.layers:
            total = math.fsum(x.thickness for x in self.backfill.layers)
            if total > H + 1e-9:
                raise InvalidParameter("backfill.layers", f"{total:g} m in all", f"<= the retained height "
                                       f"{H:g} m (the [backfill] soil fills the rest below them)")

    def replace_wall(self, wall) -> "DesignCase":
        from dataclasses import replace
        return replace(self, wall=wall)


def design_angle(phi: float, gamma_phi: float) -> float:
    """phi_d = atan(tan(phi_k) / gamma_phi') [deg] (EN 1997-1 2.4.6.2, Table A.4)."""
    return math.degrees(math.atan(math.tan(math.radians(phi)) / gamma_phi))
