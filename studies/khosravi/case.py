"""Khosravi et al.'s PFC2D translation case as a ``Case`` record and its box builder.

Khosravi, Hamed Azad, Bahaaddini & Pipatpong, "DEM analysis of backfilled walls
subjected to active translation mode" (PFC2D; the values its text states):

* box 220 mm wide x 400 mm high; one side is the rigid retaining wall, fully rough
  (wall friction = backfill friction), split into 40 segments of 10 mm (pressure cells);
  readings average 4 segments, and the bottom segment PS0 is read alone (Fig. 8);
* disks D50 = 1.16 mm, Cu = 1.55, Gs = 2.65 (porosity 0.21 in the paper);
* layered pluviation to H = 200, 250 or 300 mm;
* translation away from the backfill to Dis/H = 0.003, quasi-static (0.002 mm/s in PFC).

Not given in the paper, chosen here and stated in the docs: the grading curve shape
(grading.py), the friction of the floor (rough, = backfill) and of the far side wall
(smooth by default), the drop height and layer thickness, and the wall speed (0.002
mm/s is impractical for an explicit run; quasi-static is checked instead by halving it).

Coordinates: retaining wall on x = 0 with the backfill at x > 0, floor at y = 0, far wall
at x = box_width. Panel 0 of the wall is the bottom segment (PS0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param, seed_param

from dem2d.build import Grains, friction_split, new_space
from dem2d.grading import Grading
from analytic.constants import G
from dem2d.params import Material, Solver
from dem2d.pluviation import Pluviation
from dem2d.sim import Sim
from dem2d.walls import PANEL_TYPE_BASE, panel_wall

RHO_WATER = 1000.0  # kg/m^3
#: the smallest fill that still has a reading: one 4-panel group (PS1) below the surface
MIN_READING_PANELS = 4
#: the coarsest grains: this many d50 across the fill height and the box width (the
#: tiny box of the tests, H 0.1 m at scale 5, has 17)
MIN_GRAINS_ACROSS = 8
#: the most disks a case may hold: pymunk keeps ~4.2 kB a packed disk (measured: 200k disks,
#: 0.84 GB), so ~4 GB, and steps ~5e4 disks a CPU-second at 80 sweeps (0.58 s a step at 61k,
#: slower per disk in larger spaces): ~20 s a step, the case's ~1e4 steps ~2 days
MAX_DISKS = 1_000_000

#: The Khosravi fill: 20 mm layers; grains deeper than 20 mm below the surface are held
#: static while the next layers fall (at 4e-4 s a step), all are released for the last
#: layer, which settles at the run's dt until the floor and walls carry the weight within
#: 0.5 %. At 2x coarser grains: 3.8x less CPU than settling every layer free, porosity
#: 0.170 against 0.172, at-rest K within 2.4 % (docs/dem2d.md, "Holding settled layers").
HELD_LAYERS = Pluviation(layer_thickness=0.02, hold_depth=0.02, layer_dt=4e-4, final_balance=0.005)


@dataclass(frozen=True)
class KhosraviCase:
    """Khosravi et al.'s box, backfill and wall movement (module docstring)."""

    # the box and the fill set the disk count, W H 0.85 / mean disk area (61k at the paper's
    # 0.22 x 0.3 m): 2 m x 0.3 m of the paper's grains is ~565k disks; MAX_DISKS bounds the product
    H: float = param(0.3, unit="m", lo=0, hi=2, lo_open=True,
                     meaning="backfill height, at most box_height (paper: 0.2, 0.25, 0.3)")
    box_width: float = param(0.22, unit="m", lo=0, hi=2, lo_open=True,
                             meaning="inside width of the box, wall to far wall (paper 0.22)")
    box_height: float = param(0.40, unit="m", lo=0, hi=2, lo_open=True,
                              meaning="inside height of the box and of both walls (paper 0.40)")
    # a segment is one shape and one column of readings, nothing beside the disks; 1000 segments
    # of the 0.4 m wall are 0.4 mm each, below the finest grain
    n_panels: int = param(40, lo=1, hi=1000,
                          meaning="segments (pressure cells) of the retaining wall over box_height (paper 40 "
                                  "of 10 mm)")
    # below 0.25 x the paper's D50 the paper's box holds > 16 x its 61k disks (MAX_DISKS)
    d50: float = param(1.16e-3, unit="m", lo=2.5e-4, meaning="median disk diameter by mass (paper 1.16 mm)")
    cu: float = param(1.55, lo=1, hi=6, hi_open=True,
                      meaning="uniformity coefficient D60 / D10 of the linear-by-mass grading (paper 1.55)")
    # 0.25: 16 x the paper's disks, ~1M in its box (MAX_DISKS); the upper end is set by the grains
    # that must fit across H and the box (__post_init__)
    particles_scale: float = param(1.0, lo=0.25,
                                   meaning="multiply every diameter by this (coarser grains, same box; 2 = ~15k "
                                           "disks at H 0.3)")
    gs: float = param(2.65, lo=0, hi=20, lo_open=True, meaning="specific gravity of the grains (paper 2.65)")
    # 0.54 is the biaxial calibration at full grain size and 80 sweeps a step, the readings'
    # solver (peak phi 20.49 deg, the paper's 20.7 by interpolation at 0.555; the critical
    # state saturates at 18-19.7 deg for mu 0.43-0.8; studies/biaxial/cards/biaxial_full_it80.json).
    # Coarser grains give a lower phi at the same friction: compare reports the phi it measures.
    friction: float = param(0.54, lo=0,
                            meaning="particle-particle Coulomb coefficient (0.54: the biaxial calibration for "
                                    "phi 20.7 deg at full size and 80 sweeps)")
    wall_friction: float | None = param(None, lo=0,
                                        meaning="particle-wall coefficient (none = friction, \"fully rough\")")
    floor_friction: float | None = param(None, lo=0, meaning="particle-floor coefficient (none = friction)")
    far_wall_friction: float = param(0.0, lo=0, meaning="particle-far-wall coefficient (0 = smooth)")
    # 4 mm/s against 2 changed the active thrust at Dis/H 0.003 by 0.3 % (2x coarser grains,
    # same specimen; docs/dem2d.md). The translation is wall_disp_over_H_max H / wall_speed: at the
    # paper's 0.002 mm/s, Dis/H 0.003 at H 0.3 is 450 s, 2.25e6 steps at 2e-4 s, ~2 weeks at 61k
    # disks (~0.6 s a step at 80 sweeps), ~2 days at particles_scale 2; slower has no run that ends
    wall_speed: float = param(4e-3, unit="m/s", lo=2e-6,
                              meaning="translation speed of the wall away from the backfill (the paper's PFC: "
                                      "0.002 mm/s)")
    # 0.1 at 4 mm/s and H 0.3 is 7.5 s, 3.75e4 steps, ~6 h at 61k disks and 80 sweeps
    wall_disp_over_H_max: float = param(0.003, lo=0, hi=0.1, lo_open=True, hi_open=True,
                                        meaning="end of the translation, Dis/H")
    # moving on past it is what lets the steadiness of the pressure be judged
    wall_disp_over_H_active: float = param(0.003, lo=0, hi=0.1, lo_open=True, hi_open=True,
                                           meaning="where the active profile and thrust are read, Dis/H (the "
                                                   "paper's 0.003; at the end if the wall stops earlier)")
    # one reading runs window / dt steps: 1 s is 5000 steps at 2e-4 s, ~50 min at 61k disks
    window: float = param(0.01, unit="s", lo=0, hi=1, lo_open=True, meaning="averaging window of the pressure cells")
    # 10 s is 5e4 steps at 2e-4 s, ~8 h at 61k disks and 80 sweeps
    rest_time: float = param(0.05, unit="s", lo=0, hi=10, meaning="extra settling before the at-rest reading")
    seed: int = seed_param(1, meaning="random seed of the grading, cloud positions and insertion order: the same "
                                      "seed gives the same bits")
    # dt 2e-4 s and 40 Gauss-Seidel sweeps a step for the fill
    solver: Solver = field(default_factory=lambda: Solver(dt=2e-4, iterations=40))
    # The moving wall needs more sweeps than the settling fill: with 10 the unconverged
    # impulses made the full-size fill soft and the active thrust at Dis/H 0.003 read
    # 1.11 x Rankine, 20 -> 1.05, 40 -> 1.00 (one specimen), and on the validated one
    # 0.89 -> 0.82 from 40 to 80, while the at-rest K moves by 2 % (docs/dem2d.md, "Sweeps
    # per step"). 80 throughout would add ~13 min to the fill. 1000 as Solver.iterations.
    reading_iterations: int | None = param(80, lo=1, hi=1000,
                                           meaning="sweeps a step from the at-rest settling on (readings and "
                                                   "translation); none = solver.iterations")
    pluviation: Pluviation = field(default_factory=lambda: HELD_LAYERS)
    # pymunk cannot restore a space to the bits it had (its contact cache and spatial index
    # are rebuilt), so a run that may be interrupted goes on from its own snapshot at
    # fixed marks, and a resumed run, starting from the same bytes, is the same run
    checkpoint_layers: int = param(3, lo=1, hi=10_000,
                                   meaning="every this many layers the fill is snapshotted and goes on from the "
                                           "snapshot (an interrupted fill resumes there; part of the run's result)")
    checkpoint_readings: int = param(10, lo=1, hi=100_000,
                                     meaning="every this many readings the translation is snapshotted and goes on "
                                             "from the snapshot (an interrupted run resumes there)")

    def __post_init__(self):
        check_fields(self)
        if self.H > self.box_height:
            raise InvalidParameter("H", self.H, f"(0, {self.box_height:g}] m", "higher than the box")
        if self.H < MIN_READING_PANELS * self.box_height / self.n_panels:
            raise InvalidParameter("H", self.H, f"[{MIN_READING_PANELS * self.box_height / self.n_panels:g}, "
                                                f"{self.box_height:g}] m", "no 4-panel reading below the surface")
        most = min(self.H, self.box_width) / (MIN_GRAINS_ACROSS * self.d50)
        if self.particles_scale > most:
            raise InvalidParameter("particles_scale", self.particles_scale, f"[0.25, {most:.3g}]",
                                   f"grains of {MIN_GRAINS_ACROSS} x d50 x scale must fit across H and the box")
        disks = self.estimated_disks()
        if disks > MAX_DISKS:
            least = self.particles_scale * math.sqrt(disks / MAX_DISKS)
            raise InvalidParameter("particles_scale", self.particles_scale, f">= {least:.3g}",
                                   f"~{disks:,.0f} disks, more than {MAX_DISKS:,}: coarser grains or a smaller box")

    def estimated_disks(self) -> float:
        """The disks the fill will hold, as ``build_box`` expects them (nothing built)."""
        return self.box_width * self.H * 0.85 / self.grading.mean_area()

    @property
    def grading(self) -> Grading:
        return Grading(self.d50, self.cu).scaled(self.particles_scale)

    @property
    def material(self) -> Material:
        mu_w = self.friction if self.wall_friction is None else self.wall_friction
        return Material(density=self.gs * RHO_WATER, friction=self.friction, wall_friction=mu_w)

    @property
    def reading_solver(self) -> Solver:
        """The solver of the readings: ``solver`` with ``reading_iterations`` sweeps."""
        if self.reading_iterations is None:
            return self.solver
        return replace(self.solver, iterations=self.reading_iterations)

    @property
    def panel_height(self) -> float:
        return self.box_height / self.n_panels


def build_box(case: KhosraviCase) -> Sim:
    """The empty box: retaining wall (``case.n_panels`` panels, pivot at its toe),
    floor (10 mm panels, running 20 mm under the wall so no gap opens when it moves)
    and far wall. Returns a ``Sim`` seeded with ``case.seed``."""
    gr = case.grading
    mat = case.material
    f_grain, f_wall = friction_split(mat.friction, mat.wall_friction)
    mu_floor = case.friction if case.floor_friction is None else case.floor_friction
    f_floor = mu_floor / f_grain if f_grain > 0 else 0.0
    f_far = case.far_wall_friction / f_grain if f_grain > 0 else 0.0
    if f_grain == 0 and (mu_floor > 0 or case.far_wall_friction > 0):
        raise InvalidParameter("friction", case.friction, "> 0 when a wall is rough")
    W, Hb = case.box_width, case.box_height
    n_exp = int(W * case.H * 0.85 / gr.mean_area())
    space = new_space(case.solver, r_min=gr.d_min / 2, d_max=gr.d_max, expected_shapes=n_exp)
    t = PANEL_TYPE_BASE
    wall = panel_wall(space, "wall", (0.0, 0.0), (0.0, Hb), case.n_panels, friction=f_wall,
                      into=(1.0, 0.0), pivot=(0.0, 0.0), first_type=t)
    n_floor = max(1, int(round((W + 0.02) / 0.01)))
    floor = panel_wall(space, "floor", (-0.02, 0.0), (W, 0.0), n_floor, friction=f_floor,
                       into=(0.0, 1.0), first_type=t + case.n_panels)
    far = panel_wall(space, "far", (W, 0.0), (W, Hb), case.n_panels, friction=f_far,
                     into=(0.0, 0.0), pivot=(W, 0.0), first_type=t + case.n_panels + n_floor)
    sim = Sim(space=space, grains=Grains(), walls={"wall": wall, "floor": floor, "far": far},
              solver=case.solver, rng=np.random.default_rng(case.seed))
    sim.meta.update(r_min=gr.d_min / 2, d_max=gr.d_max, case="khosravi")
    return sim


def unit_weight(case: KhosraviCase, porosity: float, g: float = G) -> float:
    """gamma = Gs rho_w g (1 - n) [N/m^3] (Khosravi et al. eq. 1)."""
    return case.gs * RHO_WATER * g * (1.0 - porosity)
