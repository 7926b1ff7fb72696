"""The dry-stone case record and what it resolves to: the wall's section (one of the two
geometry estimates of docs/reference/drystone-walls.md), masonry, solver and
loading plan, with every value tagged found / derived / assumed."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from analytic.drystone import WallSection
from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param, seed_param

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


#: the validation's tolerances (reference.json: kept with the targets, out of code)
ACCURACY_LIMIT_PERCENT = float(reference()["targets"]["critical_height_vs_measured_percent"])
CONVERGENCE_LIMIT_PERCENT = float(reference()["targets"]["convergence_change_percent"])


@dataclass(frozen=True)
class BackfillSettings:
    """Case B (``studies.drystone.backfill``), used by the C walls only. Local values: ours from
    docs/validation/gravel_calibration.md (rigid rounded hexagons), the paper's (PFC2D) beside."""

    # ours 50: nearest to both biaxial targets at 35 kPa, peak 36.7 (37.7) and critical state
    # 31.2 (32)
    grain_friction_deg: float = param(50.0, unit="deg", lo=0, hi=89,
                                      meaning="grain-grain local friction angle (ours 50, calibrated; paper's 45)")
    # ours 45: global 37.7 on a flat face is out of reach, the global angle stays at 28-30 deg for
    # any local value from 45 to 89; 45 gives the highest, 30.4
    interface_friction_deg: float = param(45.0, unit="deg", lo=0, hi=89,
                                          meaning="fill-block local friction angle (ours 45, calibrated; paper's 25)")
    # ours 45: n = 0.22 in ``GravelBox``; the paper's 15.6 gives n = 0.146 here
    placement_friction_deg: float = param(
        45.0, unit="deg", lo=0, hi=89,
        meaning="fill-fill friction angle while a layer falls (ours 45; paper's 15.6)")
    # the grain count goes as 1 / w^2: a fill of 4 mm grains holds ~10x C3S's 19,000 (~2e5 grains,
    # ~0.7 GB at ~3.4 KB a pymunk grain) and takes ~10x its hour of CPU
    width_min_m: float = param(0.010, unit="m", lo=0.004, hi=0.2, hi_open=True,
                               meaning="smallest grain width (10 mm; larger only for tests)")
    width_max_m: float = param(0.016, unit="m", lo=0.004, hi=0.2, hi_open=True,
                               meaning="largest grain width, at least width_min_m (16 mm)")
    # the local frictions above are the hexagons': another shape needs its own calibration
    # (capsules: 72.8 and 84.6 deg), gravel_calibration_discussion.md. Why hexagons: capsules
    # calibrated on the peak have a critical state of 25 deg, under the 32-deg slope the fill
    # is re-cut to
    grain_shape: Literal["capsule", "clump3", "hexagon"] = param(
        "hexagon", unit="", meaning="grain shape (dem2d.gravel): hexagon, the calibrated one; capsule; clump3")
    # stages go as 1 / layer: 1 cm layers are ~10x C3S's 26 stages, ~10 h of CPU; thinner than a
    # grain means nothing
    layer_m: float = param(0.10, unit="m", lo=0.01, hi=2, hi_open=True,
                           meaning="rise of the fill surface at the inner face per stage (S-OET: 0.10)")
    slope_deg: float = param(
        32.0, unit="deg", lo=0, hi=60,
        meaning="fill surface slope beta, re-cut each stage, rising away from the wall (S-OET: 32)")
    # each stage drops a band across the whole container: 20 m is ~8x C3S's fill work, ~4e5 grains
    # in all (~1.5 GB), ~8 h of CPU
    container_m: float = param(2.5, unit="m", lo=0, hi=20, lo_open=True,
                               meaning="fill width from the inner face at the heel (S-OET: 2.5 m container)")
    # a 20 m column lets the fill rise ~9x as high as C3S's: ~9x the stages, ~4x the unheld
    # grains, ~1.5 days of CPU
    formwork_m: float = param(1.0, unit="m", lo=0, hi=20, hi_open=True,
                              meaning="height of the formwork column above the crest [A] (1.0)")
    formwork: Literal["crest", "fixed"] = param(
        "crest", unit="",
        meaning="crest: the column is part of the innermost top-course block (S-OET 5.2); fixed: a static column")
    # as formwork_m: a 20 m fill, ~1.5 days of CPU
    max_height_m: float | None = param(
        None, unit="m", lo=0, hi=20, lo_open=True, hi_open=True,
        meaning="stop filling at this height at the inner face; none: the crest plus the formwork")
    hold_depth_m: float | None = param(0.5, unit="m", lo=0, hi=100, lo_open=True, hi_open=True,
                                       meaning="grains this far below the surface are held static [A]; none: no hold")
    hold_distance_m: float = param(
        1.5, unit="m", lo=0, hi=100, lo_open=True, hi_open=True,
        meaning="held grains are at least this far from the inner face, outside the failure wedge [A]")
    iterations: int = param(40, lo=1, hi=500,
                            meaning="contact-solver sweeps per step of case B (40: the gravel's calibration solver)")
    # four fifths of a wall's CPU settle each new layer, 2,000-3,000 steps of 5e-4 s a stage
    # (a third of the stages reach this cap); 100 s a stage would be days at full size
    max_stage_s: float = param(1.5, unit="s", lo=0, hi=100, lo_open=True,
                               meaning="settling time allowed a stage, for each of its two settlings (1.5)")
    seed: int = seed_param(1, meaning="random seed of the backfill: grain sizes and orientations")

    def __post_init__(self):
        check_fields(self)
        if not self.width_max_m >= self.width_min_m:
            raise InvalidParameter("width_max_m", self.width_max_m, f"[{self.width_min_m:g}, 0.2) m",
                                   "the largest grain is at least the smallest")
        try:                # the engine records check the rest
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
        from .backfill import FillPlan
        return FillPlan(layer_m=self.layer_m, slope_deg=self.slope_deg, container_m=self.container_m,
                        formwork_m=self.formwork_m, formwork=self.formwork, hold_depth_m=self.hold_depth_m,
                        hold_distance_m=self.hold_distance_m, max_stage_s=self.max_stage_s)


@dataclass(frozen=True)
class DrystoneCase:
    """One of Villemus's walls loaded by water (case A), or one of Colas's walls under
    gravel backfill (case B)."""

    wall: Literal["V1L", "V2L", "V3L", "V4L", "V5S", "C2S", "C3S", "C4L"] = param(
        "V1L", unit="", meaning="the wall: Villemus's V1L to V5S under water (case A), Colas's C2S, C3S, C4L under "
                                "gravel (case B)")
    geometry: Literal["back-fit", "disk-count"] = param(
        "back-fit", unit="",
        meaning="section estimate: back-fit (reference 2.3) or disk-count (reference 6; case A only)")
    unit_weight_kN_m3: float = param(20.0, unit="kN/m^3", lo=5, hi=40, lo_open=True, hi_open=True,
                                     meaning="masonry unit weight gamma_m (ASSUMPTION 20, plausible 18-22)")
    joint_slope_deg: float | None = param(None, unit="deg", lo=0, hi=30, hi_open=True,
                                          meaning="joint counter-slope alpha; none: the wall's (V5S 8.53 found, else 0 "
                                                  "assumed)")
    # a 20 x 10 m section of S-OET's blocks is ~5,000 blocks: up to 6e5 steps (100 increments of
    # at most 3 s) at ~3e5 block-steps per CPU-s, ~3 h (V5S, 139 blocks, 45,000 steps: 16 s)
    height_m: float | None = param(
        None, unit="m", lo=0, hi=20, lo_open=True, hi_open=True,
        meaning="wall height, at least two courses; none: the wall's (found); smaller is for tests")
    base_width_m: float | None = param(
        None, unit="m", lo=0, hi=10, lo_open=True, hi_open=True,
        meaning="base width, at least one block; none: the geometry's (assumed or derived)")
    water_direction: Literal["normal", "fixed"] = param(
        "normal", unit="",
        meaning="water pressure normal to the current face, or fixed at its initial normal (S-OET's)")
    # 1e-4: 1e4 increments of ~400 steps, 4e6 steps: ~10 min for a 40-block wall, ~30 min for V5S
    increment_fraction: float = param(
        0.01, lo=1e-4, hi=0.2, hi_open=True,
        meaning="water added per increment, as a fraction of the wall height (S-OET: 0.01)")
    # below 1e-5 s a wall needs > 10^7 steps: no run would end
    dt: float = param(5e-4, unit="s", lo=1e-5, hi=2e-3, hi_open=True, meaning="time step of the block solver")
    iterations: int = param(20, lo=1, hi=500,
                            meaning="contact-solver sweeps per step (case A; case B takes backfill.iterations)")
    # the block count goes as 1 / (length x height): 0.05 x 0.02 m blocks make V5S ~5,200 blocks,
    # ~15 min at its 45,000 steps (~3e5 block-steps per CPU-s); a 20 x 10 m section of them
    # ~2e5 blocks (~0.6 GB), days
    block_length_m: float | None = param(
        None, unit="m", lo=0.05, hi=2, lo_open=True, hi_open=True,
        meaning="block length; none: the case's, 0.30 (case A) or 0.33 (case B) (S-OET)")
    block_height_m: float | None = param(
        None, unit="m", lo=0.02, hi=1, lo_open=True, hi_open=True,
        meaning="course height; none: the case's, 0.125 (case A) or 0.12 (case B) (S-OET)")
    backfill: BackfillSettings = BackfillSettings()

    def __post_init__(self):
        check_fields(self)
        if self.case_b and self.geometry not in GEOMETRY_B:
            raise InvalidParameter("geometry", self.geometry, " | ".join(GEOMETRY_B),
                                   "case B has the reference 3.3 back-analysis only")
        if self.height_m is not None and not self.height_m > 2 * self.block_height:
            raise InvalidParameter("height_m", self.height_m, f"({2 * self.block_height:g}, 20) m",
                                   "at least two courses")
        if self.base_width_m is not None and not self.base_width_m > self.block_length:
            raise InvalidParameter("base_width_m", self.base_width_m, f"({self.block_length:g}, 10) m",
                                   "at least one block long")
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
    lines.append("inner face vertical (ASSUMED)")
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
