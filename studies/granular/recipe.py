"""Granular blocks shared by the 3D studies: the recipe of a sphere-and-clump backfill
(grains, contacts and raining; Nadukuru & Michalowski's mixture by default), its linear
contact law, the volume of a two-sphere clump, and the longest run a case may ask for.
The wall study rains it (``studies.nadukuru``), the triaxial test calibrates it
(``studies.triaxial``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import dem3d
from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param

#: clump volume over one sphere's for two equal spheres overlapping by one radius
#: (lens of two spheres at centre distance r: 5 pi r^3 / 12)
CLUMP_VOLUME_FACTOR = 2.0 - (5.0 / 12.0) / (4.0 / 3.0)


#: the longest run a case may ask for, in particle-steps (spheres x time steps): ~6 days
#: on 2 cores at the 4e6 particle-steps/s of the paper-scale preparation (29,053 spheres,
#: 60,478 steps in 394 s, docs/validation/nadukuru_prep_time_2threads_alone.json)
MOST_PARTICLE_STEPS = 2e12


@dataclass(frozen=True)
class SpecimenRecipe:
    """How the backfill is made: Nadukuru & Michalowski's grains, contacts and raining."""

    # ~4 KB a sphere (engine arrays, double-buffered neighbour pairs, a checkpoint copy):
    # 1e6 spheres ~4 GB; the grains shrink and the time step with them (steps ~ sqrt(N)),
    # so a mode takes ~(N / 30,000)^1.5 x 20 min: ~3 days at 1e6
    particles: int = param(30_000, lo=50, hi=1_000_000,
                           meaning="spheres including clump members (PFC balls; paper ~30,000 behind the wall, "
                                   "8,200 in the triaxial test)")
    clump_fraction: float = param(0.30, lo=0, hi=1, meaning="fraction of the bodies that are two-sphere clumps "
                                                            "(paper 0.30)")
    # 2 radii would make the two spheres one (dem3d.random_specimen's range)
    clump_overlap: float = param(1.0, lo=0, hi=2, hi_open=True,
                                 meaning="overlap of the two spheres of a clump, in radii (paper 1.0)")
    d_min: float = param(0.046, unit="m", lo=0, lo_open=True,
                         meaning="smallest sphere diameter, uniform up to d_max (paper 0.046 at 30,000 particles; "
                                 "the wall box scales the grains up for fewer particles)")
    d_max: float = param(0.0736, unit="m", lo=0, lo_open=True,
                         meaning="largest sphere diameter, scaled with d_min (paper 0.0736 at 30,000 particles)")
    kn: float = param(8.3e6, unit="N/m", lo=0, lo_open=True, meaning="normal contact stiffness (paper 8.3e6)")
    ks: float = param(3.32e6, unit="N/m", lo=0, lo_open=True, meaning="shear contact stiffness (paper 3.32e6)")
    particle_friction: float = param(0.65, lo=0, meaning="friction coefficient between grains (paper 0.65)")
    # the wall study reaches angles above the mixture's ~37 deg with it (its phi card);
    # 0 keeps the paper's recipe and every cache key made before it existed
    rolling_friction: float = param(0.0, lo=0, hi=1,
                                    meaning="rolling resistance of the grain contacts once the particle friction is "
                                            "on (moment <= this x r_eff x F_n; 0 = none, the paper's recipe)")
    density: float = param(2650.0, unit="kg/m^3", lo=0, lo_open=True, meaning="grain density (paper 2650)")
    damping_ratio: float = param(0.2, lo=0, hi=1, hi_open=True,
                                 meaning="viscous normal damping, fraction of critical (not given in the paper)")
    local_damping: float = param(0.7, lo=0, hi=1, hi_open=True,
                                 meaning="PFC local damping while raining and settling (0.7 is PFC's default)")
    deposition_friction: float = param(
        0.1, lo=0, meaning="particle friction while raining, below particle_friction to densify (0.1 gave "
                           "porosity 0.348 at 3000 particles, 0 gave 0.330, paper ~0.35)")
    # 0.2 was fitted to one number, the rough-wall translation resultant height (paper
    # scale: floor 0 / 0.2 / 0.65 gave h/H 0.308 / 0.401 / 0.444 against 0.391), and then
    # predicted the smooth-wall translation (K 0.220, h/H 0.418 against 0.230 / 0.401; 0.472
    # with floor 0.65) and the rough mixed mode (docs/validation/nadukuru_floor_friction.json);
    # a full validation at 0.1 misses 6 of the 14 table figures against 5 at 0.2
    # (docs/validation/archive/nadukuru_floor0.1/)
    floor_friction: float = param(0.2, lo=0, meaning="friction coefficient of the floor (not given in the paper; "
                                                     "0.2 fitted to the rough-wall translation's resultant height)")
    # the fill is loaded from here to full g with friction, a 1D compression that sets the
    # at-rest K: at 3,000 particles 1.0 / 0.5 / 0.25 / 0.1 gave K0 0.83 / 0.54 / 0.41 / 0.34;
    # at 29,000, 0.25 gave 0.458 and 0.1 gave 0.396 against the paper's 0.385
    rain_gravity: float = param(0.1, lo=0, lo_open=True,
                                meaning="gravity at which the particle friction is switched on, as a fraction "
                                        "of g (sets the at-rest K)")
    deposition_gravity: float = param(2.0, lo=0, lo_open=True,
                                      meaning="gravity while the grains fall and pack, as a fraction of g (a "
                                              "shorter fall; frictionless packing does not depend on it)")
    # the paper's stiffness is restored before friction is switched on
    deposition_softening: float = param(10.0, lo=0, lo_open=True,
                                        meaning="kn and ks are divided by this while the grains fall and pack "
                                                "(a sqrt(softening) larger time step)")
    target_porosity: float = param(0.36, lo=0.2, hi=0.7, lo_open=True, hi_open=True,
                                   meaning="porosity used to size the grains so the box fills to H (paper 0.36)")
    dt: float | None = param(None, unit="s", lo=0, lo_open=True,
                             meaning="time step (none: 0.2 x the critical step of the lightest grain)")
    settle_ratio: float = param(2e-3, lo=0, lo_open=True, meaning="unbalanced-force ratio that ends settling")

    def __post_init__(self):
        check_fields(self)
        if not self.d_min <= self.d_max:
            raise InvalidParameter("d_min, d_max", f"{self.d_min:g}, {self.d_max:g}", "d_min <= d_max [m]")


def contact_law(rec: SpecimenRecipe, mu: float, local: float, softening: float = 1.0,
                rolling: float = 0.0) -> dem3d.ContactParams:
    """The recipe's linear law; ``softening`` divides both stiffnesses (deposition only),
    ``rolling`` is the rolling-resistance coefficient (dem3d ``mu_roll``)."""
    return dem3d.linear(rec.kn / softening, rec.ks / softening, mu, zeta_n=rec.damping_ratio, zeta_s=0.0,
                        local_damping=local, mu_roll=rolling)


def frictional_law(rec: SpecimenRecipe, local: float) -> dem3d.ContactParams:
    """The recipe's law with its grains' own friction and rolling resistance (after
    deposition): ``local`` is the PFC local damping."""
    return contact_law(rec, rec.particle_friction, local, rolling=rec.rolling_friction)


def time_step(rec: SpecimenRecipe, scale: float = 1.0) -> float:
    """The recipe's time step [s]: its ``dt``, else dem3d's DT_SAFETY x the critical step
    of its lightest sphere (diameter ``scale`` x d_min; dem3d.critical_time_step)."""
    if rec.dt is not None:
        return rec.dt
    d = scale * rec.d_min
    m_min = rec.density * math.pi / 6.0 * d ** 3
    return dem3d.DT_SAFETY * dem3d.critical_time_step(contact_law(rec, 0.0, 0.0), m_min, d / 2, rec.density)
