"""Biaxial test of the capsule gravel: ``studies.elements.biaxial`` with capsule grains.

S-OET (docs/reference/drystone-walls.md 3.1) calibrated the gravel's local friction
so that the DEM reproduces Colas's triaxial tests at the representative mean stress of
35 kPa: peak 37.7 deg, dilatancy 8 deg, critical state about 32 deg (the angle of
repose). This module runs the same biaxial test as the Khosravi calibration
(``studies.elements.biaxial``: frictionless rigid walls, a stress-controlled lateral piston, a
strain-controlled top platen, no gravity) on ``dem2d.gravel`` capsules:

* grains: a sparse cloud of randomly oriented capsules (``gravel.cloud``, one grain per
  cell of 1.05 L_max: none overlap), compacted isotropically to sigma_3 at the
  preparation friction, then sheared at the local friction;
* porosity: 1 - capsule area / specimen area (walls included: grains pack looser
  against a flat wall), and ``inner_porosity`` one grain length in from every wall
  (``gravel.porosity``, the window the fill's porosity is read in);
* frames draw each capsule as its two end circles (``gravel.register_grains``);
* other grain shapes (``Gravel.shape``: clumps of three circles, rounded hexagons) run
  the same way, for the shape probe.

The case holds angles in degrees; ``friction`` / ``prep_friction`` (coefficients) are
what the biaxial test reads.

Pure engine: no files, no printing. SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pymunk

from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param, seed_param

from studies.elements.biaxial import BiaxialTest
from dem2d.build import Grains, new_space
from dem2d.gravel import Gravel, add_grains, cloud, grain_area, porosity, register_grains
from dem2d.params import Material, Solver


@dataclass(frozen=True)
class GravelBiaxialCase:
    """Biaxial test of the gravel (module docstring). ``gravel``: grain shape, grading,
    density; its ``friction_deg`` is the local friction while shearing,
    ``placement_friction_deg`` while compacting.

    solver: dt 5e-4 s, 40 sweeps a step, slop 1e-4 m (slop_fraction x w_min / 2), overlap
    time 0.02 s: the block solver's settings (``BlockSolver``). Sweeps measured (local
    45 deg, n = 0.20, 1,069 grains, seed 1, strain rate 0.05/s; critical state, eps_v at
    20 % strain): 10 -> the specimen never stops compacting (eps_v +5 %, phi still rising
    past 40 deg: the unconverged solver lets grains creep into one another); 20 -> 31.3 deg,
    +2.4 %; 40 -> 27.4 deg, 0.0 %; 80 -> 28.7 deg, -1.6 %.
    """

    gravel: Gravel = Gravel()
    # ~2,350 grains per m^2 of 10-16 mm hexagons, ~3.4 KB each in pymunk, 3.8e5 grain-steps per
    # CPU-s at 40 sweeps: 10 m x 1.4 m is ~33,000 grains, ~6 min a test of ~4,000 steps;
    # 10 m x 10 m ~2.4e5 grains (~0.8 GB), ~45 min
    width: float = param(0.5, unit="m", lo=0, hi=10, lo_open=True,
                         meaning="specimen width after compaction, at least 5 grain lengths (sizes the grain count)")
    height: float = param(1.0, unit="m", lo=0, hi=10, lo_open=True,
                          meaning="specimen height after compaction, at least 5 grain lengths (sizes the grain count)")
    confining: float = param(35e3, unit="Pa", lo=0, hi=1e8, lo_open=True, hi_open=True,
                             meaning="confining stress sigma_3 (S-OET's representative mean stress: 35 kPa)")
    target_fraction: float = param(0.78, lo=0.3, hi=0.95, lo_open=True, hi_open=True,
                                   meaning="expected solid fraction, sizes the grain count (1 - 0.22)")
    # steps = max_strain / (strain_rate dt): at 1e-3 /s a 0.2-strain test is 4e5 steps, ~40 min at
    # 2,300 grains (3.8e5 grain-steps per CPU-s); below it hours a test
    strain_rate: float = param(0.2, unit="1/s", lo=1e-3, hi=10, hi_open=True,
                               meaning="axial strain rate (inertial number ~6e-4 at 0.2)")
    max_strain: float = param(0.20, lo=0, hi=0.5, lo_open=True, hi_open=True, meaning="axial strain that ends the test")
    piston_mass_fraction: float = param(0.05, lo=0, hi=1, lo_open=True,
                                        meaning="mass of the lateral piston / mass of the specimen")
    compaction_rate: float = param(1.5, unit="1/s", lo=0, hi=10, lo_open=True,
                                   meaning="piston speed limit while compacting / current specimen size")
    sample_every: int = param(10, lo=1, hi=10_000, meaning="steps between samples of the stresses")
    seed: int = seed_param(1, meaning="random seed of the specimen: grain sizes, orientations")
    solver: Solver = field(default_factory=lambda: Solver(dt=5e-4, iterations=40, slop_fraction=0.02))

    def __post_init__(self):
        check_fields(self)
        least = 5 * self.gravel.aspect_ratio * self.gravel.width_max_m
        for name in ("width", "height"):
            if not getattr(self, name) > least:
                raise InvalidParameter(name, getattr(self, name), f"({least:g}, 10] m",
                                       "at least 5 lengths of the largest grain")

    # what studies.elements.biaxial reads
    @property
    def friction(self) -> float:
        return math.tan(math.radians(self.gravel.friction_deg))

    @property
    def prep_friction(self) -> float:
        return math.tan(math.radians(self.gravel.placement_friction_deg))

    @property
    def grading(self):
        return self.gravel.grading

    def material(self, friction: float) -> Material:
        return Material(density=self.gravel.density, friction=friction, wall_friction=0.0)

    def inertial_number(self) -> float:
        """I = strain_rate w50 / sqrt(sigma_3 / rho_s) [-] (quasi-static below ~1e-3)."""
        return self.strain_rate * self.gravel.grading.d50 / math.sqrt(self.confining / self.gravel.density)


class GravelBiaxialTest(BiaxialTest):
    """``BiaxialTest`` on capsules: ``prepare()``, ``shear()``, ``result()`` as there."""

    case: GravelBiaxialCase
    #: rigid capsules slip in bursts (sigma_1 swings by +-5 deg of phi within 0.5 % strain
    #: at 2,000 grains): the peak is read on stresses smoothed over 1 % strain
    smooth_strain = 0.01

    def _grain_count(self) -> int:
        g = self.case.gravel
        mean = grain_area(g.grading.sample(20000, np.random.default_rng(12345)), g.aspect_ratio, g.shape).mean()
        return int(round(self.case.width * self.case.height * self.case.target_fraction / mean))

    def _new_space(self, n: int) -> pymunk.Space:
        g = self.case.gravel
        # the hash cell spans a whole grain (its length), as GravelBox's
        return new_space(self.case.solver, gravity=(0.0, 0.0), r_min=g.width_min_m / 2,
                         d_max=1.05 * g.aspect_ratio * g.width_max_m, expected_shapes=n)

    def _cloud(self, n: int, w0: float, f_cloud: float, rng: np.random.Generator) -> tuple:
        g = self.case.gravel
        centres, cell = cloud(n, w0, g)
        widths = g.grading.sample(n, rng)
        angles = rng.uniform(0.0, math.pi, n)
        return centres, widths, angles, float(centres[:, 1].max() + cell / 2)

    def _wall_height(self, h0: float, h_cloud: float) -> float:
        # the capsule cloud is sparse (one grain per square of its length): walls above it
        return 2 * max(h0, h_cloud)

    def _add_grains(self, space, grains: Grains, cloud_: tuple, rng) -> None:
        g = self.case.gravel
        centres, widths, angles, _ = cloud_
        f_grain = math.sqrt(self.case.prep_friction)      # product rule, walls frictionless
        bodies = add_grains(space, centres, angles, widths, g, f_grain)
        register_grains(grains, bodies, widths, g)
        self.widths = widths

    def _solid_area(self, grains: Grains) -> float:
        g = self.case.gravel
        return float(grain_area(self.widths, g.aspect_ratio, g.shape).sum())

    def inner_porosity(self) -> float:
        """Porosity one longest grain in from every wall (``gravel.porosity``) [-]."""
        g = self.case.gravel
        inset = g.aspect_ratio * g.width_max_m
        pos = self.sim.state().position
        return porosity(pos, self.widths, g.aspect_ratio,
                        (inset, self.width() - inset, inset, self.height() - inset), g.shape)
