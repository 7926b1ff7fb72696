"""Khosravi et al.'s PFC2D translation case as a ``Case`` record and its box builder.

Khosravi, Hamed Azad, Bahaaddini & Pipatpong, "DEM analysis of backfilled walls
subjected to active translation mode" (../shared/seeds/khosravi-dem-translation-pfc2d.txt,
../shared/BENCHMARKS.md §2):

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

from dataclasses import dataclass, field, replace

import numpy as np

from analytic.errors import InvalidParameter
from analytic.inputs import require_number

from dem2d.build import Grains, friction_split, new_space
from dem2d.grading import Grading
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

#: The Khosravi fill: 20 mm layers; grains deeper than 20 mm below the surface are held
#: static while the next layers fall (at 4e-4 s a step), all are released for the last
#: layer, which settles at the run's dt until the floor and walls carry the weight within
#: 0.5 %. At 2x coarser grains: 3.8x less CPU than settling every layer free, porosity
#: 0.170 against 0.172, at-rest K within 2.4 % (docs/dem2d.md, "Holding settled layers").
HELD_LAYERS = Pluviation(layer_thickness=0.02, hold_depth=0.02, layer_dt=4e-4, final_balance=0.005)


@dataclass(frozen=True)
class KhosraviCase:
    """Khosravi et al.'s box, backfill and wall movement (module docstring).

    H:                backfill height [m] (paper: 0.2, 0.25, 0.3)
    box_width, box_height: inside of the box [m]
    n_panels:         segments of the retaining wall over box_height
    d50, cu:          grading of the disks [m, -]
    particles_scale:  multiply every diameter by this (coarser grains, same box)
    gs:               specific gravity of the grains
    friction:         particle-particle Coulomb coefficient; 0.54 is the biaxial calibration at
                      full grain size and 80 sweeps a step, the readings' solver (peak phi
                      20.49 deg, the paper's 20.7 by interpolation at 0.555; the critical
                      state saturates at 18-19.7 deg for mu 0.43-0.8;
                      studies/biaxial/cards/biaxial_full_it80.json). Coarser grains give a lower
                      phi at the same friction: compare reports the phi it measures.
    wall_friction:    particle-wall coefficient; None = friction ("fully rough")
    floor_friction:   particle-floor coefficient; None = friction
    far_wall_friction: particle-far-wall coefficient (0 = smooth)
    wall_speed:       translation speed of the wall away from the backfill [m/s]; 4 mm/s
                      against 2 changed the active thrust at Dis/H 0.003 by 0.3 % (2x
                      coarser grains, same specimen; docs/dem2d.md)
    wall_disp_over_H_max:   end of the translation, Dis/H
    wall_disp_over_H_active: where the active profile and thrust are read, Dis/H (the paper's
                      0.003; at the end if the wall stops earlier). Moving on past it is
                      what lets the steadiness of the pressure be judged
    window:           averaging window of the pressure cells [s]
    rest_time:        extra settling before the at-rest reading [s]
    seed:             random seed (grading, cloud positions, insertion order)
    solver:           dt 2e-4 s and 40 Gauss-Seidel sweeps a step for the fill
    reading_iterations: 80 sweeps a step from the at-rest settling on (readings and
                      translation); None = solver.iterations. The moving wall needs more
                      than the settling fill: with 10 sweeps the unconverged impulses made
                      the full-size fill soft and the active thrust at Dis/H 0.003 read
                      1.11 x Rankine, 20 -> 1.05, 40 -> 1.00 (one specimen), and on the
                      validated one 0.89 -> 0.82 from 40 to 80, while the at-rest K moves
                      by 2 % (docs/dem2d.md, "Sweeps per step"). 80 throughout would add
                      ~13 min to the fill
    pluviation:       ``HELD_LAYERS`` (above)
    """

    H: float = 0.3
    box_width: float = 0.22
    box_height: float = 0.40
    n_panels: int = 40
    d50: float = 1.16e-3
    cu: float = 1.55
    particles_scale: float = 1.0
    gs: float = 2.65
    friction: float = 0.54
    wall_friction: float | None = None
    floor_friction: float | None = None
    far_wall_friction: float = 0.0
    wall_speed: float = 4e-3
    wall_disp_over_H_max: float = 0.003
    wall_disp_over_H_active: float = 0.003
    window: float = 0.01
    rest_time: float = 0.05
    seed: int = 1
    solver: Solver = field(default_factory=lambda: Solver(dt=2e-4, iterations=40))
    reading_iterations: int | None = 80
    pluviation: Pluviation = field(default_factory=lambda: HELD_LAYERS)

    def __post_init__(self):
        require_number("H", self.H, 0.0, None, unit="m")
        require_number("box_height", self.box_height, 0.0, None, unit="m")
        if self.H > self.box_height:
            raise InvalidParameter("H", self.H, f"(0, {self.box_height:g}] m", "higher than the box")
        require_number("box_width", self.box_width, 0.0, None, unit="m")
        require_number("particles_scale", self.particles_scale, 0.0, None)
        if self.H < MIN_READING_PANELS * self.box_height / self.n_panels:
            raise InvalidParameter("H", self.H, f"[{MIN_READING_PANELS * self.box_height / self.n_panels:g}, "
                                                f"{self.box_height:g}] m", "no 4-panel reading below the surface")
        most = min(self.H, self.box_width) / (MIN_GRAINS_ACROSS * self.d50)
        if self.particles_scale > most:
            raise InvalidParameter("particles_scale", self.particles_scale, f"(0, {most:.3g}]",
                                   f"grains of {MIN_GRAINS_ACROSS} x d50 x scale must fit across H and the box")
        require_number("friction", self.friction, 0.0, None, lo_open=False)
        require_number("wall_speed", self.wall_speed, 0.0, None, unit="m/s")
        require_number("wall_disp_over_H_max", self.wall_disp_over_H_max, 0.0, 0.1)
        require_number("wall_disp_over_H_active", self.wall_disp_over_H_active, 0.0, 0.1)
        require_number("window", self.window, 0.0, None, unit="s")
        if not (isinstance(self.n_panels, int) and self.n_panels >= 1):
            raise InvalidParameter("n_panels", self.n_panels, "an integer >= 1")
        if self.reading_iterations is not None and not (
                isinstance(self.reading_iterations, int) and self.reading_iterations >= 1):
            raise InvalidParameter("reading_iterations", self.reading_iterations, "an integer >= 1, or unset")

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


def unit_weight(case: KhosraviCase, porosity: float, g: float = 9.81) -> float:
    """gamma = Gs rho_w g (1 - n) [N/m^3] (Khosravi et al. eq. 1)."""
    return case.gs * RHO_WATER * g * (1.0 - porosity)
