"""The dry-stone case record and what it resolves to: the wall's section (one of the two
geometry estimates of ../shared/reference/drystone-walls.md), masonry, solver and
loading plan, with every value tagged found / derived / assumed."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

from analytic.drystone import WallSection
from analytic.errors import InvalidParameter
from analytic.inputs import require_number

WALLS = ("V1L", "V2L", "V3L", "V4L", "V5S")
#: case B: Colas's walls under gravel backfill (reference 3)
WALLS_B = ("C2S", "C3S", "C4L")
#: case-B sections: reference 3.3's back-analysis row taken as "back-fit" (delta = 2 phi / 3)
GEOMETRY_B = {"back-fit": "2phi/3"}
GEOMETRIES = ("back-fit", "disk-count")
DIRECTIONS = ("normal", "fixed")
REFERENCE = Path(__file__).with_name("reference.json")


def reference() -> dict:
    return json.loads(REFERENCE.read_text())


@dataclass(frozen=True)
class BackfillSettings:
    """Case B (``dem2d.backfill``), used by the C walls only. Local values: ours from
    docs/validation/gravel_calibration.md (rigid rounded hexagons), the paper's (PFC2D) beside.

    grain_friction_deg:     grain-grain local friction [deg] (ours 50: nearest to both biaxial
                            targets at 35 kPa, peak 36.7 (37.7) and critical state 31.2 (32);
                            paper's 45)
    interface_friction_deg: fill-block local friction [deg] (ours 45: global 37.7 on a flat
                            face is out of reach, the global angle stays at 28-30 deg for any
                            local value from 45 to 89; 45 gives the highest, 30.4; paper's 25)
    placement_friction_deg: fill-fill friction while a layer falls [deg] (ours 45: n = 0.22
                            in ``GravelBox``; paper's 15.6, n = 0.146 here)
    width_min_m, width_max_m: grain widths [m] (10-16 mm; larger only for tests)
    grain_shape:            hexagon (rounded elongated hexagon, the calibrated one, default) |
                            capsule | clump3 (``dem2d.gravel``; the local frictions above are the
                            hexagons': another shape needs its own calibration (capsules: 72.8 and
                            84.6 deg), gravel_calibration_discussion.md). Why hexagons: capsules
                            calibrated on the peak have a critical state of 25 deg, under the
                            32-deg slope the fill is re-cut to
    layer_m, slope_deg, container_m, formwork_m: ``FillPlan`` (0.10 m, 32 deg, 2.5 m; the
                            formwork column height [A] 1.0 m)
    formwork:               "crest" (S-OET 5.2: the column is fixed to the inner face, part of
                            the innermost top-course block, so the fill above the crest loads
                            the wall through it; the default) | "fixed" (a static column, as
                            the site's formwork carried by the side formworks)
    max_height_m:           stop filling at this height at the inner face [m] (None: the
                            crest plus the formwork)
    hold_depth_m, hold_distance_m: grains held static this far below the surface and from
                            the inner face [m] (None: no hold) [A]: outside the failure wedge
    iterations:             sweeps per step (40: the gravel's calibration solver; case A
                            uses the case's ``iterations``)
    seed:                   grain sizes and orientations
    """

    grain_friction_deg: float = 50.0
    interface_friction_deg: float = 45.0
    placement_friction_deg: float = 45.0
    width_min_m: float = 0.010
    width_max_m: float = 0.016
    grain_shape: str = "hexagon"
    layer_m: float = 0.10
    slope_deg: float = 32.0
    container_m: float = 2.5
    formwork_m: float = 1.0
    formwork: str = "crest"
    max_height_m: float | None = None
    hold_depth_m: float | None = 0.5
    hold_distance_m: float = 1.5
    iterations: int = 40
    seed: int = 1

    def __post_init__(self):
        for name in ("grain_friction_deg", "interface_friction_deg", "placement_friction_deg"):
            require_number(name, getattr(self, name), 0.0, 89.0, lo_open=False, hi_open=False, unit="deg")
        require_number("width_min_m", self.width_min_m, 0.001, 0.2, unit="m")
        require_number("width_max_m", self.width_max_m, self.width_min_m, 0.2, lo_open=False, unit="m")
        if self.max_height_m is not None:
            require_number("max_height_m", self.max_height_m, 0.0, 20.0, unit="m")
        if not (isinstance(self.iterations, int) and 1 <= self.iterations <= 500):
            raise InvalidParameter("iterations", self.iterations, "an integer in [1, 500]")
        from dem2d.backfill import FORMWORKS
        from dem2d.gravel import SHAPES
        if self.grain_shape not in SHAPES:
            raise InvalidParameter("backfill.grain_shape", self.grain_shape, " | ".join(SHAPES))
        if self.formwork not in FORMWORKS:      # before the engine's, whose name is formwork_m's prefix
            raise InvalidParameter("backfill.formwork", self.formwork, " | ".join(FORMWORKS))
        try:                # the engine records check the rest (slope, layer, container, ...)
            self.gravel()
            self.plan()
        except InvalidParameter as err:     # named by this record's key
            key = next((f for f in self.__dataclass_fields__ if f.startswith(err.name)), err.name)
            raise InvalidParameter(f"backfill.{key}", err.value, err.valid, err.why) from None

    def gravel(self):
        from dem2d.gravel import Gravel
        return Gravel(width_min_m=self.width_min_m, width_max_m=self.width_max_m,
                      friction_deg=self.grain_friction_deg, interface_friction_deg=self.interface_friction_deg,
                      placement_friction_deg=self.placement_friction_deg, shape=self.grain_shape)

    def plan(self):
        from dem2d.backfill import FillPlan
        return FillPlan(layer_m=self.layer_m, slope_deg=self.slope_deg, container_m=self.container_m,
                        formwork_m=self.formwork_m, formwork=self.formwork, hold_depth_m=self.hold_depth_m,
                        hold_distance_m=self.hold_distance_m)


@dataclass(frozen=True)
class DrystoneCase:
    """One of Villemus's walls loaded by water (case A), or one of Colas's walls under
    gravel backfill (case B).

    wall:               V1L | V2L | V3L | V4L | V5S (case A) | C2S | C3S | C4L (case B)
    geometry:           "back-fit" (reference 2.3, the default) or "disk-count" (reference 6)
    unit_weight_kN_m3:  gamma_m [kN/m^3] (ASSUMPTION 20, plausible 18-22)
    joint_slope_deg:    alpha [deg]; None: the wall's value (V5S 8.53 found, else 0 assumed)
    height_m:           wall height [m]; None: the wall's (found). A smaller wall is for tests
    base_width_m:       base width [m]; None: the geometry's (assumed or derived)
    water_direction:    "normal" (to the current face) or "fixed" (S-OET's: the initial normal)
    increment_fraction: water added per increment, fraction of h (S-OET: 0.01)
    dt:                 time step [s]
    iterations:         contact-solver sweeps per step
    block_length_m, block_height_m: block size [m] (S-OET: 0.30 x 0.125 case A; None: the
                        case's, 0.33 x 0.12 for case B)
    backfill:           case B settings (``BackfillSettings``)
    """

    wall: str = "V1L"
    geometry: str = "back-fit"
    unit_weight_kN_m3: float = 20.0
    joint_slope_deg: float | None = None
    height_m: float | None = None
    base_width_m: float | None = None
    water_direction: str = "normal"
    increment_fraction: float = 0.01
    dt: float = 5e-4
    iterations: int = 20
    block_length_m: float | None = None
    block_height_m: float | None = None
    backfill: BackfillSettings = BackfillSettings()

    def __post_init__(self):
        if self.wall not in WALLS + WALLS_B:
            raise InvalidParameter("wall", self.wall, " | ".join(WALLS + WALLS_B))
        if self.case_b and self.geometry not in GEOMETRY_B:
            raise InvalidParameter("geometry", self.geometry, " | ".join(GEOMETRY_B),
                                   "case B has the reference 3.3 back-analysis only")
        if self.geometry not in GEOMETRIES:
            raise InvalidParameter("geometry", self.geometry, " | ".join(GEOMETRIES))
        if self.water_direction not in DIRECTIONS:
            raise InvalidParameter("water_direction", self.water_direction, " | ".join(DIRECTIONS))
        require_number("unit_weight_kN_m3", self.unit_weight_kN_m3, 5.0, 40.0, unit="kN/m^3")
        if self.joint_slope_deg is not None:
            require_number("joint_slope_deg", self.joint_slope_deg, 0.0, 30.0, lo_open=False, unit="deg")
        if self.height_m is not None:
            require_number("height_m", self.height_m, 2 * self.block_height, 20.0, unit="m")
        if self.base_width_m is not None:
            require_number("base_width_m", self.base_width_m, self.block_length, 10.0, unit="m")
        require_number("increment_fraction", self.increment_fraction, 0.0, 0.2, unit="")
        # below 1e-5 s a wall needs > 10^7 steps: no run would end
        require_number("dt", self.dt, 1e-5, 2e-3, lo_open=False, unit="s")
        if not (isinstance(self.iterations, int) and 1 <= self.iterations <= 500):
            raise InvalidParameter("iterations", self.iterations, "an integer in [1, 500]")
        require_number("block_length_m", self.block_length, 0.05, 2.0, unit="m")
        require_number("block_height_m", self.block_height, 0.02, 1.0, unit="m")
        self.section()        # the section itself checks the widths (crest > 0)

    @property
    def case_b(self) -> bool:
        return self.wall in WALLS_B

    @property
    def block_length(self) -> float:
        """Block length [m]: the case's, else 0.33 (case B) or 0.30 (case A) (S-OET)."""
        return self.block_length_m if self.block_length_m is not None else (0.33 if self.case_b else 0.30)

    @property
    def block_height(self) -> float:
        """Course height [m]: the case's, else 0.12 (case B) or 0.125 (case A) (S-OET)."""
        return self.block_height_m if self.block_height_m is not None else (0.12 if self.case_b else 0.125)

    def wall_reference(self) -> dict:
        return reference()["walls_b" if self.case_b else "walls"][self.wall]

    def geometry_reference(self) -> dict:
        return self.wall_reference()["geometry"][GEOMETRY_B.get(self.geometry, self.geometry) if self.case_b
                                                 else self.geometry]

    def section(self) -> WallSection:
        """The section this case builds (raises InvalidParameter if the crest vanishes)."""
        w = self.wall_reference()
        h = w["height_m"]["value"] if self.height_m is None else self.height_m
        b = self.geometry_reference()["base_width_m"] if self.base_width_m is None else self.base_width_m
        a = w["joint_slope_deg"]["value"] if self.joint_slope_deg is None else self.joint_slope_deg
        return WallSection(h, b, w["batter_outer_deg"]["value"], w["batter_inner_deg"]["value"], a)

    @property
    def phi_b_deg(self) -> float:
        return self.wall_reference()["phi_b_deg"]["value"]


def assumptions(case: DrystoneCase) -> list[str]:
    """Which values of this run are assumptions or derived, one line each (every output
    repeats these)."""
    w = case.wall_reference()
    s = case.section()
    g = case.geometry_reference()
    lines = []
    if case.base_width_m is None:
        tag = "ASSUMED" if g["tag"] == "A" else "derived"
        lines.append(f"base width {s.base_width_m:.3g} m ({tag}: {case.geometry} geometry"
                     + (f", {g['note']}" if "note" in g else "") + ")")
    else:
        lines.append(f"base width {s.base_width_m:.3g} m (set for this run)")
    lines.append(f"crest width {s.crest_width_m:.3g} m (follows from the base width and the batter)")
    if w["batter_outer_deg"]["tag"] == "A":
        lines.append(f"outer batter {s.batter_outer_deg:g} deg (ASSUMED: not found"
                     + (f"; {w['batter_outer_deg']['note']})" if "note" in w["batter_outer_deg"] else ")"))
    elif s.batter_outer_deg:
        lines.append(f"outer batter {s.batter_outer_deg:g} deg (found, read in degrees; 15 % = 8.53 deg possible)")
    lines.append(f"inner face vertical (ASSUMED)")
    if case.joint_slope_deg is not None:
        lines.append(f"joint counter-slope {s.joint_slope_deg:g} deg (set for this run)")
    elif w["joint_slope_deg"]["tag"] == "A" and case.case_b:
        lines.append(f"joint counter-slope {s.joint_slope_deg:g} deg (ASSUMED: {w['joint_slope_deg']['note']})")
    elif w["joint_slope_deg"]["tag"] == "A":
        lines.append("joint counter-slope 0 deg (ASSUMED: not found, 0-8.5 plausible)")
    lines.append(f"unit weight {case.unit_weight_kN_m3:g} kN/m3 (ASSUMED: not found, 18-22 plausible)")
    if case.height_m is not None:
        lines.append(f"wall height {s.height_m:g} m (set for this run; the real wall is "
                     f"{w['height_m']['value']:g} m)")
    return lines


def masonry(case: DrystoneCase):
    from dem2d.blocks import Masonry
    # case A: first course fixed (S-OET 5.1); case B: free on the foundation, block-foundation
    # friction = block-block (S-OET 3.1)
    return Masonry(unit_weight_kN_m3=case.unit_weight_kN_m3, friction_deg=case.phi_b_deg,
                   block_length_m=case.block_length, block_height_m=case.block_height,
                   first_course_fixed=not case.case_b)


def solver(case: DrystoneCase):
    from dem2d.blocks import BlockSolver
    return BlockSolver(dt=case.dt, iterations=case.iterations)


def plan(case: DrystoneCase):
    from dem2d.blocks import LoadingPlan
    return LoadingPlan(increment_fraction=case.increment_fraction, direction=case.water_direction)


def staircase_m(case: DrystoneCase) -> float:
    """m = 2 h_block / l_block (reference 2.3 [A]: 0.83 for 0.30 x 0.125 m blocks)."""
    return 2 * case.block_height / case.block_length


def mode_word(letter_or_word: str) -> str:
    return {"S": "sliding", "T": "toppling"}.get(letter_or_word, letter_or_word)


def percent_error(value: float, target: float) -> float:
    return 100.0 * (value - target) / target if math.isfinite(value) else math.nan
