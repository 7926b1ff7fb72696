"""Constant-normal-load interface shear test: gravel against a block face.

S-OET (docs/reference/drystone-walls.md 3.1) calibrated the local fill-block friction
(25 deg) to the global interface angle of Colas's backfill (37.7 deg) in a PFC2D shear
test: a 0.90 x 0.50 m box of about 925 grains sheared over a block face at a constant
normal stress of 35 kPa and 5e-4 m/s. Here:

* the block face is a kinematic polygon (``BLOCK_TYPE``) under the box, moved along x at
  the shear speed;
* the box sides are static frictionless segments (``WALL_TYPE``) ending ``gap`` above the
  face (less than the smallest grain width: no grain escapes), so they carry no vertical
  load and the face reads the whole normal load;
* the lid is a dynamic slab (no rotation, no horizontal motion) pushed down by
  sigma_n L, frictionless;
* the global interface angle is atan(T / N), T and N the forces of the face on the grains
  (contact impulses / dt, averaged over a reading window).

Flat face: once the face moves every grain-face contact slides, so T / N = mu_fb exactly
and the global angle equals the local one (reduced test: 25.00 deg from 25, 96 grains).
S-OET's 25 -> 37.7 deg comes from the roughness of their block faces (hollow clumps of
disks: bumps of a disk radius) that the grains must ride over or shear through; a flat
polygon block has none. Case B therefore needs either a local interface friction set
to the global target (37.7 deg) on flat faces, or a rough face (bumps of the site's
R_n ~ 1.5) calibrated here: an open choice. Measured at S-OET's size
(0.90 x 0.50 m, 962 grains at n = 0.22 sizing, 35 kPa, seed 1, dt 5e-4 s, 10 iterations,
5e-3 m/s): 24.91 deg from a local 25 deg, N within 0.01 % of the applied load, 790
steps per CPU-second. At S-OET's 5e-4 m/s (same box, 10 mm): 24.92 deg at 4 mm, then
falling to 23.24 deg at 10 mm (still falling; 54 s CPU): some grains roll or stick on
the face instead of sliding. On a flat face Coulomb bounds it: T = sum t_i <= mu sum n_i
= mu N, so the global angle can never exceed the local one.

Frictions come from one ``blocks.pair_friction`` table (fill-fill, fill-block, fill-wall = 0).

Pure engine: no files, no printing. SI units, angles in degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import pymunk

from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param, seed_param

from analytic.constants import G

from dem2d.blocks import BLOCK_TYPE, BlockSolver, pair_friction
from dem2d.gravel import FILL_TYPE, Gravel, add_grains, cloud, grain_area, grain_outlines

WALL_TYPE = 23


@dataclass(frozen=True)
class ShearCase:
    """The constant-normal-load shear box of gravel on a block face (module docstring)."""

    gravel: Gravel = Gravel()
    # ~2,100 grains per m^2 at n = 0.22 (962 in S-OET's 0.90 x 0.50 m), ~3.4 KB each in pymunk,
    # ~5e5 grain-steps per CPU-s: 10 x 0.5 m is ~11,000 grains, ~1 h at S-OET's 2e5 steps;
    # 10 x 10 m ~2e5 grains (~0.7 GB)
    length_m: float = param(0.90, unit="m", lo=0, hi=10, lo_open=True, hi_open=True,
                            meaning="inner length of the shear box (S-OET: 0.90)")
    height_m: float = param(0.50, unit="m", lo=0, hi=10, lo_open=True, hi_open=True,
                            meaning="inner height of the shear box (S-OET: 0.50)")
    normal_stress_Pa: float = param(35e3, unit="Pa", lo=0, hi=1e7, lo_open=True, hi_open=True,
                                    meaning="normal stress sigma_n on the lid (S-OET: 35e3)")
    # steps = displacement / (speed dt): 1e-6 m/s shears S-OET's 0.05 m in 1e8 steps, ~2 days at
    # 962 grains (5e5 grain-steps per CPU-s)
    speed_m_s: float = param(5e-4, unit="m/s", lo=1e-6, hi=1, hi_open=True,
                             meaning="shear speed of the face (S-OET: 5e-4)")
    # below the box length (10 m): 4e7 steps at S-OET's speed, ~1 day at 962 grains
    displacement_m: float = param(0.05, unit="m", lo=0, hi=10, lo_open=True, hi_open=True,
                                  meaning="total shear displacement of the face, below length_m")
    gap_m: float = param(0.004, unit="m", lo=0, hi=1, lo_open=True, hi_open=True,
                         meaning="gap between the box sides and the face, below the smallest grain width")
    porosity: float = param(0.22, lo=0, hi=0.9, lo_open=True, hi_open=True,
                            meaning="porosity that sizes the number of grains (S-OET: 0.22)")
    seed: int = seed_param(0, meaning="random seed of the box: grain sizes and orientations")
    # 60 s: 1.2e5 steps of 5e-4 s, ~4 min at 962 grains
    place_s: float = param(1.0, unit="s", lo=0, hi=60,
                           meaning="settling time at the placement friction before the lid is set")
    load_s: float = param(0.5, unit="s", lo=0, hi=60, meaning="settling time under the normal load (ramped over 40 %)")
    solver: BlockSolver = BlockSolver(dt=5e-4, iterations=10)

    def __post_init__(self):
        check_fields(self)
        if not self.displacement_m < self.length_m:
            raise InvalidParameter("displacement_m", self.displacement_m, f"(0, {self.length_m:g}) m",
                                   "the face moves less than the box length")
        if not self.gap_m < self.gravel.width_min_m:
            raise InvalidParameter("gap_m", self.gap_m, f"(0, {self.gravel.width_min_m:g}) m",
                                   "below the smallest grain width: no grain escapes")


class ShearReading(NamedTuple):
    """Face displacement [m], shear T and normal N force of the face on the grains [N/m],
    lid height [m], global interface angle atan(T/N) [deg]."""

    displacement: float
    shear: float
    normal: float
    lid_y: float
    angle_deg: float


@dataclass
class InterfaceShear:
    case: ShearCase
    space: pymunk.Space = None
    bodies: list = field(default_factory=list)
    widths: np.ndarray = None
    face: pymunk.Body = None
    lid: pymunk.Body = None
    steps: int = 0

    def build(self) -> "InterfaceShear":
        """Grains placed at the placement friction, the lid set and loaded, the local
        friction restored and the box settled under sigma_n."""
        c, g = self.case, self.case.gravel
        rng = np.random.default_rng(c.seed)
        mean_area = grain_area(g.grading.sample(20000, np.random.default_rng(12345)), g.aspect_ratio, g.shape).mean()
        n = int(round(c.length_m * c.height_m * (1 - c.porosity) / mean_area))
        centres, cell = cloud(n, c.length_m, g)
        top = centres[:, 1].max() + cell
        self.space = pymunk.Space()
        self.space.gravity = (0.0, -G)
        self.space.iterations = c.solver.iterations
        self.space.collision_slop = c.solver.collision_slop
        self.space.collision_bias = math.exp(-1.0 / c.solver.overlap_time)
        self.space.sleep_time_threshold = math.inf
        self.space.use_spatial_hash(cell, max(4 * n, 1000))
        fr = self._frictions(g.placement_friction_deg)
        self.face = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        span = c.length_m + 2 * c.displacement_m + 0.2
        face = pymunk.Poly(self.face, [(-span, -0.1), (span, -0.1), (span, 0.0), (-span, 0.0)])
        face.collision_type, face.friction = BLOCK_TYPE, fr[BLOCK_TYPE]
        self.space.add(self.face, face)
        for x in (0.0, c.length_m):
            s = pymunk.Segment(self.space.static_body, (x, c.gap_m), (x, top + 0.5), 0.0)
            s.collision_type, s.friction = WALL_TYPE, 0.0
            self.space.add(s)
        widths = g.grading.sample(n, rng)
        self.widths = widths
        self.bodies = add_grains(self.space, centres, rng.uniform(0, math.pi, n), widths, g, fr[FILL_TYPE])
        self._run(c.place_s)
        self._add_lid()
        self._frictions(None)
        self._run(c.load_s, ramp=0.4 * c.load_s)
        return self

    def _frictions(self, fill_deg):
        g = self.case.gravel
        table = g.table(fill_deg)
        table[(FILL_TYPE, WALL_TYPE)] = 0.0
        fr = pair_friction(self.space, table)
        if not fr:   # not a product table (fill-fill friction 0): the handler sets all pairs
            fr = pair_friction(self.space, table, handler=True)
        for s in self.space.shapes:
            if s.collision_type in fr:
                s.friction = fr[s.collision_type]
        return fr

    def _add_lid(self) -> None:
        c = self.case
        ys = [b.position.y for b in self.bodies]
        y0 = max(ys) + c.gravel.width_max_m * c.gravel.aspect_ratio / 2 + 0.002
        self.lid = pymunk.Body(1.0, math.inf)   # mass 1 kg/m: its weight is negligible beside sigma_n L
        self.lid.position = (c.length_m / 2, y0 + 0.025)
        s = pymunk.Poly.create_box(self.lid, (c.length_m - 0.002, 0.05))
        s.collision_type, s.friction = WALL_TYPE, 0.0
        self.space.add(self.lid, s)
        self._load = 0.0

    def _run(self, seconds: float, ramp: float = 0.0, speed: float = 0.0) -> np.ndarray:
        """Step ``seconds``; returns the mean (T, N) of the face on the grains [N/m]."""
        dt = self.case.solver.dt
        n = max(int(round(seconds / dt)), 1)
        self.face.velocity = (speed, 0.0)
        total = np.zeros(2)
        full = self.case.normal_stress_Pa * self.case.length_m
        for k in range(n):
            if self.lid is not None:
                f = full * min(1.0, (k + 1) * dt / ramp) if ramp > 0 else full
                self.lid.velocity = (0.0, self.lid.velocity.y)
                self.lid.force = (0.0, -f)
            self.space.step(dt)
            total += _face_impulse(self.face)
        self.steps += n
        return total / (n * dt)

    def shear(self, readings: int = 20, on_reading=None) -> list[ShearReading]:
        """Move the face by ``displacement_m`` at ``speed_m_s``; one reading per
        1/readings of the displacement (forces averaged over the reading).
        ``on_reading(box)``: after each reading."""
        c = self.case
        out, x0 = [], self.face.position.x
        for _ in range(readings):
            t, nn = self._run(c.displacement_m / c.speed_m_s / readings, speed=c.speed_m_s)
            out.append(ShearReading(self.face.position.x - x0, float(t), float(nn), self.lid.position.y,
                                    math.degrees(math.atan2(abs(t), nn))))
            if on_reading is not None:
                on_reading(self)
        self.face.velocity = (0.0, 0.0)
        return out

    def outlines(self) -> list:
        """World outlines (k,2) [m] of the grains, then of the face and the lid."""
        pos = np.array([tuple(b.position) for b in self.bodies]).reshape(-1, 2)
        ang = np.array([b.angle for b in self.bodies])
        grains = list(grain_outlines(pos, ang, self.widths, self.case.gravel)) if len(pos) else []
        rigid = [[tuple(s.body.local_to_world(v)) for v in s.get_vertices()]
                 for body in (self.face, self.lid) for s in body.shapes]
        return grains + rigid

    def applied_normal(self) -> float:
        """sigma_n L plus the weight of grains and lid [N/m]: what the face must carry."""
        return self.case.normal_stress_Pa * self.case.length_m + G * (math.fsum(b.mass for b in self.bodies) + self.lid.mass)


def _face_impulse(face: pymunk.Body) -> np.ndarray:
    """Sum of the last step's contact impulses of ``face`` on the grains [N s/m]: the face's
    own arbiter list (each_arbiter puts the face's shape first, and total_impulse is the
    impulse on that first shape, so the grains get minus it)."""
    out = np.zeros(2)

    def visit(arb):
        j = arb.total_impulse
        out[0] -= j.x
        out[1] -= j.y
    face.each_arbiter(visit)
    return out
