"""The designer's wall in DEM: the case. A WALL.toml as ``wallsim design`` reads it
(the wall, its backfill, loads and method) plus the DEM's own keys (movement, size,
seed), turned into the shared wall-backfill pipeline's records (``studies.granular``):

* the wall: a rigid vertical wall of the retained height of the design's back (the
  virtual back through the heel, or the real back of a gravity wall when it is
  vertical), friction tan(delta) with delta by the file's convention
  (``analytic.design.actions.back_and_delta``: beta on a virtual back, 2/3 phi on a
  real one, or ``method.wall_friction``), in a periodic slab as the Nadukuru study's;
* the backfill: the Nadukuru recipe with the grain friction and rolling resistance the
  phi card gives for the file's phi (``card``), the grain density that gives the file's
  unit weight at the recipe's target porosity;
* the surface: level, or rising at the file's beta from the top of the back (the fill
  rained higher and cut to the plane);
* the surcharge: a load on the top layer of grains (``surcharge``).

What the DEM cannot model yet is refused, one line naming the key: a block wall, water
behind the wall, c' > 0, fill layers, a battered back.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Literal

from analytic.constants import G
from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param, seed_param

from ..granular.recipe import SpecimenRecipe
from ..granular.wall import Movement, WallSetup, check_backfill_case, most_steps
from .card import CardMatch, load_card, match_phi

#: the backfill's length behind the wall, as Nadukuru & Michalowski's box (3.3 m behind
#: 3.1 m): the active wedge of phi 25 deg reaches 0.64 H
LENGTH_OVER_HEIGHT = 3.3 / 3.1

#: the same for a passive movement: the log-spiral surface of phi 45 deg with delta = phi
#: reaches about 2.5 H behind the wall
PASSIVE_LENGTH_OVER_HEIGHT = 3.0

#: the design formats the DEM's thrust is checked in (``wallsim design --format``)
FORMATS = ("DA1", "DA2", "DA3", "EQU", "fs")


@dataclass(frozen=True)
class WallStudyCase:
    """A designer's wall file and how the DEM runs it."""

    design_file: str | None = param(None, unit="", meaning="the WALL.toml that `wallsim design` checks (required; "
                                                            "e.g. docs/examples/cantilever.toml)")
    movement: Movement = field(default_factory=Movement)
    # the worked example (a 6 m back) at 4,000 took 29 s of CPU, time grows as N^1.5:
    # 15,000 keeps the default run within a few minutes on 2 cores
    particles: int = param(15_000, lo=50, hi=1_000_000,
                           meaning="spheres incl. clump members (grains scale to fill the box; more is finer)")
    segments: int = param(6, lo=1, hi=100, meaning="equal wall segments whose stresses are read, bottom to top")
    backfill_length: float | None = param(None, unit="m", lo=0, hi=1000, lo_open=True,
                                          meaning="backfill length behind the wall (none: 1.065 H, the Nadukuru "
                                                  "box; 3 H for a passive movement)")
    design_format: Literal["DA1", "DA2", "DA3", "EQU", "fs"] = param(
        "DA1", unit="", meaning="format of the design checks rerun with the DEM's thrust (as `wallsim design "
                                "--format`)")
    phi_card: str | None = param(None, unit="", meaning="a phi card from `wallsim calibrate wall` (none: the "
                                                        "card shipped with wallsim)")
    seed: int = seed_param(1)

    def __post_init__(self):
        check_fields(self)
        if self.design_file is not None:
            refuse_what_dem_cannot_model(self.design)
            check_design(self.design, self.design_format)
            check_backfill_case(self)

    # the records the pipeline reads (studies.granular.wall.WallCase) ------------------
    @cached_property
    def design(self):
        """The ``analytic.design.DesignCase`` of the file."""
        from analytic.design.config import case_from_dict
        if self.design_file is None:
            raise InvalidParameter("design_file", "missing", "a WALL.toml (e.g. docs/examples/cantilever.toml)")
        return case_from_dict(read_wall_file(self.design_file))

    @cached_property
    def back(self):
        """(the design's back, delta on it [deg]) by the file's convention."""
        from analytic.design.actions import back_and_delta
        back, delta = back_and_delta(self.design, self.design.backfill)
        return back, (self.design.backfill.beta if delta is None else delta)

    @cached_property
    def phi_match(self) -> CardMatch:
        """The grain friction and rolling resistance for the file's phi (the phi card)."""
        card = load_card(self.phi_card)
        return match_phi(self.design.backfill.phi, card, source=self.phi_card)

    @cached_property
    def specimen(self) -> SpecimenRecipe:
        base = SpecimenRecipe()
        m = self.phi_match
        return dataclasses.replace(base, particles=self.particles, particle_friction=m.particle_friction,
                                   rolling_friction=m.rolling_friction,
                                   density=grain_density(self.design.backfill.gamma, base.target_porosity))

    @cached_property
    def wall(self) -> WallSetup:
        back, delta = self.back
        H = back.height
        ratio = PASSIVE_LENGTH_OVER_HEIGHT if self.movement.direction == "passive" else LENGTH_OVER_HEIGHT
        L = self.backfill_length if self.backfill_length is not None else round(ratio * H, 2)
        beta = self.design.backfill.beta
        return WallSetup(height=H, segments=self.segments, friction=wall_friction_coefficient(delta),
                         backfill_length=L, surface_slope=beta if beta != 0 else None)

    @property
    def surcharge(self) -> float:
        """Uniform surcharge on the fill surface [kPa] (the file's ``loads.surcharge``)."""
        return self.design.loads.surcharge

    def most_steps(self) -> tuple[float, float, float]:
        return most_steps(self)


def read_wall_file(path: str) -> dict:
    """The parsed WALL.toml, or one line naming it and what is wrong."""
    try:
        return tomllib.loads(Path(path).read_text())
    except (FileNotFoundError, IsADirectoryError, NotADirectoryError):
        raise InvalidParameter("design_file", path, "an existing WALL.toml") from None
    except (PermissionError, UnicodeDecodeError) as err:
        raise InvalidParameter("design_file", path, "a readable TOML text file", type(err).__name__) from None
    except tomllib.TOMLDecodeError as err:
        raise InvalidParameter("design_file", path, "valid TOML", str(err).splitlines()[0]) from None


def grain_density(gamma_kN_m3: float, porosity: float) -> float:
    """Grain density [kg/m^3, whole] for a fill of unit weight gamma [kN/m^3] at
    ``porosity``: rho = gamma / (g (1 - n)); whole kg/m^3, so the Nadukuru fill's 16.64
    kN/m^3 at n = 0.36 is its 2650."""
    return float(round(gamma_kN_m3 * 1e3 / (G * (1.0 - porosity))))


def wall_friction_coefficient(delta_deg: float) -> float:
    """tan(delta) to 4 decimals (the paper's rough wall, 0.35, is delta = 19.29 deg)."""
    return round(math.tan(math.radians(delta_deg)), 4)


def check_design(design, fmt: str) -> None:
    """The file's own checks in ``fmt`` run once before any grain is made, so what
    `wallsim design` would refuse in the file (a wall friction above phi, say) stops
    here in one line, not after the DEM."""
    from analytic.design import load_factors, verify
    verify(design, load_factors(), fmt)


def refuse_what_dem_cannot_model(design) -> None:
    """One line naming the key for a wall the DEM cannot model yet (module docstring)."""
    kind = getattr(design.wall, "kind", "")
    if kind == "blocks":
        raise InvalidParameter("wall.type", "blocks", "cantilever | gravity",
                               "a block wall's joints are modelled in 2D by `compare drystone`, not here")
    fill = design.backfill
    if fill.c > 0 or any(x.c > 0 for x in fill.layers):
        raise InvalidParameter("backfill.c", fill.c, "0", "the DEM backfill is cohesionless")
    if fill.layers:
        raise InvalidParameter("backfill.layers", len(fill.layers), "none", "the DEM backfill is one material")
    if abs(fill.beta) > 40:
        raise InvalidParameter("backfill.beta", fill.beta, "[-40, 40] deg", "no DEM fill of the phi card stands "
                               "steeper")
    if design.water.behind > 0:
        raise InvalidParameter("water.behind", design.water.behind, "0", "the DEM backfill is dry")
    from analytic.design.actions import back_and_delta
    back, delta = back_and_delta(design, fill)
    if abs(back.omega) > 1e-9:
        raise InvalidParameter("method.earth_pressure", design.method.earth_pressure,
                               "rankine-virtual-back (a vertical back)",
                               f"the DEM wall is vertical; this back leans {back.omega:.3g} deg")
    if delta is not None and delta < 0:
        raise InvalidParameter("method.wall_friction", delta, ">= 0 deg", "the DEM wall's friction is a coefficient")
