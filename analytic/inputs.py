"""Input records shared by every theory and every DEM case.

Angles are in degrees at this interface (what engineers type), radians inside the
solvers. Lengths in m, unit weights in N/m^3, stresses in Pa.

Sign conventions (docs/reference/analytic-formulas.md section 1):

* ``beta``  backfill slope, positive rising away from the wall.
* ``omega`` inclination of the wall back face from vertical, positive when the heel
  lies further into the backfill than the top of the face (backfill rests on the face).
* ``delta`` wall-soil interface friction angle; for the active case the shear on the
  wall points down the face (the wedge settles relative to the wall).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import InvalidParameter, NotApplicable


def require_number(name: str, value, lo: float | None = None, hi: float | None = None,
                   *, lo_open: bool = True, hi_open: bool = True, unit: str = "") -> float:
    """Return ``value`` as a finite float, or raise InvalidParameter naming the valid range.

    ``lo``/``hi`` bound the value; ``*_open`` says whether the bound itself is excluded.
    """
    rng = _range_text(lo, hi, lo_open, hi_open, unit)
    if isinstance(value, bool):
        raise InvalidParameter(name, value, rng)
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InvalidParameter(name, value, rng, "not a number") from None
    if not math.isfinite(x):
        raise InvalidParameter(name, value, rng)
    if lo is not None and (x < lo or (lo_open and x == lo)):
        raise InvalidParameter(name, value, rng)
    if hi is not None and (x > hi or (hi_open and x == hi)):
        raise InvalidParameter(name, value, rng)
    return x


def _range_text(lo, hi, lo_open, hi_open, unit):
    u = f" {unit}" if unit else ""
    if lo is None and hi is None:
        return "a finite number" + (f" ({unit})" if unit else "")
    if hi is None:
        return f"{'>' if lo_open else '>='} {lo:g}{u}"
    if lo is None:
        return f"{'<' if hi_open else '<='} {hi:g}{u}"
    return f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}{u}"


#: bounds of physical sense, refused beyond (inputs such as H = 1e308 overflowed into a
#: traceback, q = 1e300 into K = 9.8e298): no retaining wall is 100 m high, no soil
#: weighs 100 kN/m3, no surcharge reaches 10 MPa
MAX_HEIGHT_M = 100.0
MAX_UNIT_WEIGHT_KN_M3 = 100.0
MAX_PRESSURE_KPA = 10_000.0


@dataclass(frozen=True)
class Soil:
    """Cohesionless, dry backfill.

    phi_deg:      internal friction angle [deg], 0 < phi < 90
    unit_weight:  gamma [N/m^3], (0, 1e5] (e.g. 16.7e3 for Nadukuru & Michalowski's fill)
    undrained:    a clay in total stress instead (phi = 0, its strength c_u given to the
                  design methods of ground.py); only the theory table's title reads it
    """

    phi_deg: float
    unit_weight: float
    undrained: bool = False

    def __post_init__(self):
        phi = require_number("phi", self.phi_deg, 0.0, 90.0, lo_open=not self.undrained, unit="deg")
        object.__setattr__(self, "phi_deg", phi)
        if self.undrained and self.phi_deg != 0:
            raise InvalidParameter("phi", self.phi_deg, "0 for an undrained soil (total stress)")
        object.__setattr__(self, "unit_weight", require_number("gamma", self.unit_weight, 0.0,
                                                               MAX_UNIT_WEIGHT_KN_M3 * 1e3, hi_open=False,
                                                               unit="N/m^3"))

    @property
    def phi(self) -> float:
        """phi [rad]."""
        return math.radians(self.phi_deg)


@dataclass(frozen=True)
class Wall:
    """A rigid retaining wall and the backfill surface behind it.

    height:       H, vertical height of the back face [m], (0, 100]
    delta_deg:    wall friction angle [deg], |delta| <= phi (checked against the soil by each method)
    omega_deg:    back-face inclination from vertical [deg], |omega| < 90
    beta_deg:     backfill slope [deg], |beta| < 90
    surcharge:    q, uniform vertical load per unit horizontal area on the backfill [Pa], [0, 1e7]
    """

    height: float
    delta_deg: float = 0.0
    omega_deg: float = 0.0
    beta_deg: float = 0.0
    surcharge: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "height", require_number("H", self.height, 0.0, MAX_HEIGHT_M, hi_open=False,
                                                          unit="m"))
        object.__setattr__(self, "delta_deg", require_number("delta", self.delta_deg, -90.0, 90.0, unit="deg"))
        object.__setattr__(self, "omega_deg", require_number("omega", self.omega_deg, -90.0, 90.0, unit="deg"))
        object.__setattr__(self, "beta_deg", require_number("beta", self.beta_deg, -90.0, 90.0, unit="deg"))
        object.__setattr__(self, "surcharge", require_number("q", self.surcharge, 0.0, MAX_PRESSURE_KPA * 1e3,
                                                             lo_open=False, hi_open=False, unit="Pa"))

    @property
    def delta(self) -> float:
        return math.radians(self.delta_deg)

    @property
    def omega(self) -> float:
        return math.radians(self.omega_deg)

    @property
    def beta(self) -> float:
        return math.radians(self.beta_deg)


def check_wall_friction(soil: Soil, wall: Wall) -> None:
    """|delta| <= phi: the interface cannot be stronger than the soil."""
    if abs(wall.delta_deg) > soil.phi_deg + 1e-12:
        raise InvalidParameter("delta", wall.delta_deg, f"[-phi, phi] = [{-soil.phi_deg:g}, {soil.phi_deg:g}] deg")


def require_vertical_level(method: str, wall: Wall, *, level: bool = True) -> None:
    """Methods derived for a vertical back (and, if ``level``, level backfill) refuse others."""
    if wall.omega_deg != 0.0:
        raise NotApplicable("omega", wall.omega_deg, "0 deg", f"{method} assumes a vertical back face")
    if level and wall.beta_deg != 0.0:
        raise NotApplicable("beta", wall.beta_deg, "0 deg", f"{method} assumes level backfill")
