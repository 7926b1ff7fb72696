"""A segmented retaining wall and the box of backfill behind it (``WallSetup``; the
paper's 3.1 m wall of 6 segments by default), how the wall moves away from the fill
(``Movement``: translation, rotation about the base or the top, or about a point above
the top, to Delta/H), a level or sloping fill surface, the grain scale a particle count needs to fill the box, and the
checks and run length of a case made of a recipe, a wall and a movement.

Geometry: wall face at x = 0 (normal +x, backfill at x > 0), floor z = 0, far wall at
x = L, periodic along y (width w) or, with ``WallSetup.side_friction`` set, between two
side walls at y = 0 and y = w. Wall movement is away from the backfill (-x), or into it
(+x) with ``Movement.direction`` passive.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Literal, Protocol

from analytic.constants import G
from analytic.errors import InvalidParameter
from analytic.inputs import MAX_HEIGHT_M
from analytic.schema import check_fields, param

from .recipe import CLUMP_VOLUME_FACTOR, MOST_PARTICLE_STEPS, SpecimenRecipe, time_step


MODES = ("T", "RB", "RT", "mixed")


MODE_TITLES = {"T": "translation", "RB": "rotation about the base", "RT": "rotation about the top",
               "mixed": "rotation about a point H/2 above the top"}


@dataclass(frozen=True)
class WallSetup:
    """The wall and the box behind it (the paper's 3.1 m wall of 6 segments)."""

    # the particle count, not the box, sets memory and time (grain_scale sizes the grains to
    # fill the box; NadukuruCase refuses a box the count cannot fill with grains of H / 10);
    # above 100 m the theories beside the DEM refuse the wall (analytic.inputs.MAX_HEIGHT_M);
    # the box's other sides as far
    height: float = param(3.1, unit="m", lo=0, hi=MAX_HEIGHT_M, lo_open=True, meaning="wall height H (paper 3.1)")
    width: float = param(0.5, unit="m", lo=0, hi=100, lo_open=True,
                         meaning="width w of the backfill slab along the wall (0.5; a reduced run widens it to "
                                 "3.4 grain diameters)")
    # one wall panel each, read every step: 100 add nothing measurable
    segments: int = param(6, lo=1, hi=100, meaning="equal wall segments whose stresses are read, bottom to top "
                                                   "(paper 6)")
    friction: float = param(0.35, lo=0, meaning="wall friction coefficient: 0.35 rough or 0 smooth (paper)")
    backfill_length: float = param(3.3, unit="m", lo=0, hi=100, lo_open=True,
                                   meaning="backfill length L from the wall to the far wall (3.3)")
    side_friction: float | None = param(
        None, lo=0, meaning="none: periodic along the width; a number: two side walls at y = 0 and y = w with this "
                            "friction (0 = the paper's smooth side walls)")
    # steeper than 40 deg stands in no cohesionless fill the recipe makes (phi <= 45 at most)
    surface_slope: float | None = param(
        None, unit="deg", lo=-40, hi=40, meaning="none: a level fill at H; a number: the surface rises at this angle "
                                                 "from the wall top away from the wall (the fill is rained higher and "
                                                 "cut to it)")

    def __post_init__(self):
        check_fields(self)

    @property
    def rained_height(self) -> float:
        """Height [m] the fill is rained to before it is cut: H, or for a sloping surface
        its highest point (at the far wall when it rises, at the wall when it falls)."""
        if self.surface_slope is None:
            return self.height
        return self.height + max(0.0, self.backfill_length * math.tan(math.radians(self.surface_slope)))

    def surface_height(self, x):
        """Height [m] of the fill surface at distance x [m] from the wall (H when level)."""
        if self.surface_slope is None:
            return self.height
        return self.height + x * math.tan(math.radians(self.surface_slope))


@dataclass(frozen=True)
class Movement:
    """How the wall moves away from the backfill (quasi-statically, to Delta/H)."""

    mode: Literal["T", "RB", "RT", "mixed"] = param(
        "T", unit="", meaning="how the wall moves: T translation, RB rotation about the base, RT about the top, "
                              "mixed about a point H/2 above the top")
    wall_disp_over_H: float = param(0.008, lo=0, hi=0.1, lo_open=True, hi_open=True,
                                    meaning="Delta/H at the end, Delta at the edge opposite the pivot (paper 0.008)")
    # the run's length (NadukuruCase, MOST_PARTICLE_STEPS) bounds a slow movement
    speed: float = param(0.02, unit="m/s", lo=0, hi=1.0, lo_open=True, hi_open=True,
                         meaning="speed of the edge opposite the pivot once ramped up (0.02)")
    # 10 s: 4e5 steps of the paper-scale 2.6e-5 s, ~1 h at 30,000 spheres
    ramp: float = param(0.05, unit="s", lo=0, hi=10, meaning="time over which the speed ramps up from 0 (0.05)")
    # a sample's panel history is held in memory: 1e5 steps x (segments + 4) panels x 48 B,
    # 500 MB at 100 segments
    record_every: int = param(50, lo=1, hi=100_000, meaning="time steps averaged into one load sample (50)")
    # Nadukuru & Michalowski move the wall away from the fill only; toward it the passive
    # wedge reaches ~2-3 H, so the box must be longer (the wall study makes it 3 H)
    direction: Literal["active", "passive"] = param(
        "active", unit="", meaning="active: the wall moves away from the fill; passive: into it (the same "
                                   "modes, mirrored)")
    # the paper does not say; PFC3D's default, 0.7, acts in every cycle unless the user
    # turns it off (`--set movement.local_damping=0.7` to run that way)
    local_damping: float = param(0.0, lo=0, hi=1, hi_open=True,
                                 meaning="PFC local damping while the wall moves (0: viscous contact damping only)")

    def __post_init__(self):
        check_fields(self)


#: the coarsest grains a reduced specimen may use: d_max x grain scale <= H / this
GRAINS_PER_HEIGHT = 10.0


def fewest_particles(rec: SpecimenRecipe, wall: WallSetup) -> int:
    """The smallest particle count whose scaled grains stay at most H / 10 across (the
    grains grow as the count falls, ``grain_scale``): 878 for the paper's wall."""
    def too_coarse(n: int) -> bool:
        scale, _ = grain_scale(dataclasses.replace(rec, particles=n), wall)
        return scale * rec.d_max > wall.height / GRAINS_PER_HEIGHT

    lo, hi = 1, max(rec.particles, 2)
    while too_coarse(hi):
        lo, hi = hi, hi * 2
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if too_coarse(mid) else (lo, mid)
    return hi


def grain_scale(rec: SpecimenRecipe, wall: WallSetup) -> tuple[float, float]:
    """(factor on the paper's diameters, periodic width [m]) so that the bodies fill
    L x w x H at the target porosity (factor ~1.0 at 30,000 particles). With few
    particles the grains grow; once the width would hold fewer than ~3 cells of the
    neighbour grid (3.4 d_max, the engine's minimum periodic length) the width grows
    instead and the grains less, so a reduced run keeps the wall height and backfill length."""
    n_bodies = rec.particles / (1.0 + rec.clump_fraction)
    a, b = rec.d_min, rec.d_max
    mean_d3 = (b**4 - a**4) / (4.0 * (b - a)) if b > a else a**3
    v_body = math.pi / 6.0 * mean_d3 * (1.0 + rec.clump_fraction * (CLUMP_VOLUME_FACTOR - 1.0))
    solid_per_width = (1.0 - rec.target_porosity) * wall.backfill_length * wall.rained_height * OVERFILL
    s = (solid_per_width * wall.width / (n_bodies * v_body)) ** (1.0 / 3.0)
    min_width = MIN_CELLS * b
    if min_width * s <= wall.width:
        return s, wall.width
    # width = min_width * s  ->  solid_per_width * min_width * s = n v s^3
    s = math.sqrt(solid_per_width * min_width / (n_bodies * v_body))
    return s, min_width * s


#: shaping the preparation: the fill is rained 4 % above H; the periodic length is at least
#: this many d_max; the cloud is generated in these fractions of the box height
OVERFILL = 1.04     # fill 4 % above H, trimmed to H after deposition


MIN_CELLS = 3.4     # periodic length >= 3 (2 r_max + skin): 3.4 d_max with skin 0.4 r_min


GENERATION_FRACTIONS = (0.20, 0.15, 0.10)


def movement_duration(mv: Movement, H: float) -> float:
    """Time [s] for the edge that defines Delta to reach wall_disp_over_H * H [m] when its
    speed ramps linearly to ``speed`` over ``ramp`` (``_ramp_distance`` inverted)."""
    target = mv.wall_disp_over_H * H
    return mv.ramp / 2.0 + target / mv.speed if target / mv.speed > mv.ramp / 2 else \
        math.sqrt(2.0 * target * mv.ramp / mv.speed)


def check_backfill_case(case) -> None:
    """The checks that span a wall-backfill case's records (``case.specimen``,
    ``case.wall``, ``case.movement``), each an InvalidParameter naming the key: a time
    step the grains allow, enough particles to fill the box with grains under H/10, and a
    run that ends (MOST_PARTICLE_STEPS)."""
    rec = case.specimen
    if rec.dt is not None:
        safe = time_step(dataclasses.replace(rec, dt=None), grain_scale(rec, case.wall)[0])
        if rec.dt > safe * (1 + 1e-9):
            raise InvalidParameter("dt", rec.dt, f"(0, {safe:.4g}] s", "0.2 x the critical step of the "
                                   "lightest grain at these particles; the default takes it")
    least = fewest_particles(case.specimen, case.wall)
    if case.specimen.particles < least:
        raise InvalidParameter("particles", case.specimen.particles, f">= {least} for this wall",
                               f"fewer would need grains over H/{GRAINS_PER_HEIGHT:g} to fill the box")
    preparation, movement, dt = most_steps(case)
    work = rec.particles * (preparation + movement)
    if work > MOST_PARTICLE_STEPS:
        raise InvalidParameter("particles x time steps", work, f"<= {MOST_PARTICLE_STEPS:g}",
                               f"up to {preparation:.3g} steps to prepare and {movement:.3g} to move the wall, "
                               f"of {dt:.3g} s: ~{work / 4e6 / 86400:.3g} days on 2 cores")


def most_steps(case) -> tuple[float, float, float]:
    """(time steps of the preparation at most, of the movement, the time step [s]) of a
    wall-backfill case: ``prepare_specimen``'s stages at their caps (fall from the
    tallest cloud, pack, stiffen, friction on, load to g, at rest) and ``move_wall``'s."""
    rec, wall = case.specimen, case.wall
    dt = time_step(rec, grain_scale(rec, wall)[0])
    dt_soft = dt * math.sqrt(rec.deposition_softening)
    top = (1.0 - rec.target_porosity) * wall.rained_height * OVERFILL / GENERATION_FRACTIONS[-1]
    fall = 1.2 * math.sqrt(2.0 * top / (G * rec.deposition_gravity)) / dt_soft + 1.0 / dt_soft
    settle = (1.0 + 2.0 + 2.0) / dt + 2000 + 5000 + 2000
    return fall + settle, movement_duration(case.movement, wall.height) / dt, dt


class WallCase(Protocol):
    """What the wall-backfill pipeline (``specimen``, ``movement``) reads of a case: the
    recipe, the wall and its box, the movement and the seed (``NadukuruCase`` is one)."""

    specimen: SpecimenRecipe
    wall: WallSetup
    movement: Movement
    seed: int
