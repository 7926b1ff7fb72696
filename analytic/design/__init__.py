"""Design checks of retaining walls: sliding, overturning, bearing and
eccentricity of cantilever, gravity and block walls, verified to EN 1997-1 (DA1, DA2,
DA3, EQU), EN 1998-5 (seismic) or by classical factors of safety.

Pure: no printing, no file I/O except ``factors.load_factors`` reading the package's
own factor table. Units kN, kPa, m, degrees; forces per metre run.
"""

from .bearing import bearing_resistance, bearing_undrained
from .case import DesignCase, Foundation, Loads, Method, Seismic, Water
from .earth import Backfill, FillLayer, MeasuredThrust, Thrust, ThrustPart, design_thrust
from .factors import Factors, load_factors
from .formats import FormatResult, factors_of_safety, verify
from .walls import CantileverWall, GravityWall, WallBack

__all__ = ["bearing_resistance", "bearing_undrained", "DesignCase", "Foundation", "Loads", "Method",
           "Seismic", "Water", "Backfill", "FillLayer", "MeasuredThrust", "Thrust", "ThrustPart", "design_thrust", "Factors",
           "load_factors", "FormatResult", "factors_of_safety", "verify", "CantileverWall", "GravityWall",
           "WallBack"]
