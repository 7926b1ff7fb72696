"""Solver settings and material records for the pymunk engine (frozen dataclasses, SI).

pymunk (Chipmunk2D / Munk2D) is an impulse-based contact-dynamics solver: contacts are
rigid, forces are accumulated impulses / dt (Lagrange multipliers), and there is no
contact stiffness. What follows from that is written in ``docs/dem2d.md``; the
settings that matter are chosen here on purpose:

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
from analytic.schema import check_fields, param


@dataclass(frozen=True)
class Solver:
    """Integration and contact-solver settings (module docstring)."""

    # below 1e-5 s the full Khosravi case (~1e4 steps at 2e-4 s, ~0.6 s a step at 61k disks
    # and 80 sweeps) needs > 2e5 steps, ~1.5 days; every run of the repository uses >= 5e-5 s
    dt: float = param(1e-4, unit="s", lo=1e-5, hi=0.01, hi_open=True,
                      meaning="time step; keep v_max dt a small fraction of the smallest grain radius")
    # a step costs ~sweeps^0.7 (40 -> 80: 1.6-1.7x, docs/dem2d.md): 1000 sweeps are ~6x the
    # readings' 80, ~4 s a step at 61k disks (0.58 s at 80) and ~1e4 steps a case: ~half a day
    iterations: int = param(10, lo=1, hi=1000, meaning="Gauss-Seidel sweeps of the contact solver per step "
                                                       "(pymunk default 10)")
    slop_fraction: float = param(0.02, lo=0,
                                 meaning="overlap left uncorrected, as a fraction of the smallest grain radius "
                                         "(sets pymunk's collision_slop)")
    overlap_time: float = param(0.02, unit="s", lo=0, lo_open=True,
                                meaning="time constant of the overlap correction (collision_bias = "
                                        "exp(-1 / overlap_time))")
    spatial_hash: bool = param(True, unit="",
                               meaning="broad phase on pymunk's spatial hash (cell = largest diameter) instead of "
                                       "the bounding-box tree")
    threads: int = param(1, lo=1, hi=2,
                         meaning="solver threads: 1 = serial and bit-for-bit repeatable, 2 = Chipmunk's threaded "
                                 "\"hasty\" solver (not repeatable)")

    def __post_init__(self):
        check_fields(self)

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
