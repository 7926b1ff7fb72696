"""Solver settings and material records for the pymunk engine (frozen dataclasses, SI).

pymunk (Chipmunk2D / Munk2D) is an impulse-based contact-dynamics solver: contacts are
rigid, forces are accumulated impulses / dt (Lagrange multipliers), and there is no
contact stiffness. What follows from that is written in ``docs/dem2d.md``; the
settings that matter (../shared/STACK.md 1.4) are chosen here on purpose:

* ``dt``: not limited by stiffness; limited by how far a grain may move in a step
  before its contact is detected (overlap is allowed and corrected afterwards).
  Keep ``v_max dt`` a small fraction of the smallest radius.
* ``iterations``: Gauss-Seidel sweeps per step (pymunk default 10).
* ``collision_slop``: overlap that is *not* corrected. pymunk's default is 0.1 world
  units = 100 mm here, which would never correct a mm-grain overlap; it is set as a
  fraction of the smallest radius instead.
* ``overlap_time``: time constant [s] of the overlap correction. pymunk's
  ``collision_bias`` is the fraction of overlap left after 1 s; bias = exp(-1/overlap_time).
  pymunk's default (0.9^60) is overlap_time = 0.16 s, long against a 0.1 s layer.
* Friction: pymunk multiplies the two shapes' friction values. ``Material`` takes the
  *pair* coefficients and ``build.friction_split`` turns them into shape values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytic.errors import InvalidParameter
from analytic.inputs import require_number


@dataclass(frozen=True)
class Solver:
    """Integration and contact-solver settings.

    dt:             time step [s]
    iterations:     solver sweeps per step [-]
    slop_fraction:  allowed overlap as a fraction of the smallest grain radius [-]
    overlap_time:   time constant of the overlap correction [s] (sets collision_bias)
    spatial_hash:   use pymunk's spatial hash (cell = largest diameter) instead of the
                    bounding-box tree for the broad phase
    threads:        1 = serial and bit-for-bit repeatable; 2 = Chipmunk's threaded
                    "hasty" solver (not repeatable; ../shared/STACK.md 1.8)
    """

    dt: float = 1e-4
    iterations: int = 10
    slop_fraction: float = 0.02
    overlap_time: float = 0.02
    spatial_hash: bool = True
    threads: int = 1

    def __post_init__(self):
        require_number("dt", self.dt, 0.0, 0.01, unit="s")
        if not (isinstance(self.iterations, int) and 1 <= self.iterations <= 1000):
            raise InvalidParameter("iterations", self.iterations, "an integer in [1, 1000]")
        require_number("slop_fraction", self.slop_fraction, 0.0, None, lo_open=False)
        require_number("overlap_time", self.overlap_time, 0.0, None, unit="s")
        if self.threads not in (1, 2):
            raise InvalidParameter("threads", self.threads, "1 or 2")

    @property
    def collision_bias(self) -> float:
        """pymunk's collision_bias: overlap fraction left after 1 s."""
        return math.exp(-1.0 / self.overlap_time)


@dataclass(frozen=True)
class Material:
    """Grain material (per metre of wall in 2D: densities multiply 1 m of thickness).

    density:        solid density rho_s = Gs rho_w [kg/m^3] (Khosravi: Gs = 2.65)
    friction:       particle-particle Coulomb coefficient mu_pp [-]
    wall_friction:  particle-wall coefficient mu_pw [-] (fully rough wall: = mu_pp)
    elasticity:     restitution [-] (0: perfectly plastic impacts)

    Disks roll freely (no rolling resistance), like PFC2D disks without a rolling
    model, which is what Khosravi et al. used; their strength comes from mu_pp alone.
    """

    density: float = 2650.0
    friction: float = 0.5
    wall_friction: float = 0.5
    elasticity: float = 0.0

    def __post_init__(self):
        require_number("density", self.density, 0.0, None, unit="kg/m^3")
        require_number("friction", self.friction, 0.0, None, lo_open=False)
        require_number("wall_friction", self.wall_friction, 0.0, None, lo_open=False)
        require_number("elasticity", self.elasticity, 0.0, 1.0, lo_open=False, hi_open=False)
        if self.friction == 0.0 and self.wall_friction > 0.0:
            raise InvalidParameter("wall_friction", self.wall_friction, "0 when friction = 0",
                                   "pymunk multiplies shape frictions")
