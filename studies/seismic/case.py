"""The seismic sheet-pile case (Sizkow & El Shamy): a frozen record in model units (a
50 g centrifuge model, SI), its resolution presets and the centrifuge scaling to
prototype units. Data and every assumption: docs/reference/seismic-sheetpile.md,
tagged per value in reference.json ([F] found, [D] derived, [A] assumption).

Coordinates (model, m): x along the model, the wall's front face (excavated side) at
x = 0, the wall occupying 0 <= x <= t, the retained soil at x > t; y across the
periodic slab [0, width); z up from the rigid base at z = 0.

Resolution: the paper's grains (1.5-2.5 mm) and wall balls (2.5 mm) make ~3.6e5
spheres and ~1e6 steps a run. ``grain_scale`` s multiplies every grain and the wall
balls (so the wall-thickness-to-grain ratio stays the paper's 2.5), while the bonds are
recalibrated so the wall keeps the paper's EI per width (E_eff = E / s^3 for a wall s
times thicker) and the ball density keeps its mass per area: the wall's bending
stiffness and inertia, the soil's bulk density, porosity and stresses stay those of
the paper; what changes is the grain count across the geometry (the soil is coarser,
the wall 5 s mm thick instead of 5 mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from analytic.constants import G
from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param, seed_param


#: grain_scale of each resolution preset: coarse 3x the paper's grains (~15k spheres, the
#: default: one frequency in < 30 min on one core; 3 is the largest the 3 cm periodic slab
#: admits), medium 2x (~51k), paper 1x (~3.6e5)
RESOLUTIONS = {"coarse": 3.0, "medium": 2.0, "paper": 1.0}

#: prototype frequencies the paper reports (Hz)
PAPER_FREQUENCIES = (1.0, 3.0, 4.0, 5.0, 6.0)


@dataclass(frozen=True)
class SeismicCase:
    """Model units (SI) unless a name says prototype; defaults are the paper's values or
    the reference's assumptions (reference.json tags each)."""

    # Size bounds: the coarse default is ~16,000 spheres (13,392 + 2,581 in the free-field
    # columns) and ~3.8e5 steps of 4.7e-7 s, ~1,000 s of one core at 6.5e6 particle-steps per
    # CPU-s (docs/validation/seismic_step_speed.json); the spheres go as the soil volume over the grain
    # volume, the steps as the model duration over dt (dt ~ the smallest grain's Hertz step).
    # Each estimate below is that run with one field at its bound.
    frequency: float = param(5.0, unit="Hz", lo=0, hi=20, lo_open=True, hi_open=True,
                             meaning="base-motion frequency, prototype (1-6 in the paper)")
    amplitude_g: float = param(0.1, unit="g", lo=0, hi=0.5, lo_open=True,
                               meaning="peak base acceleration, prototype (0.1)")
    # the static stage settles with rigid side walls and local damping; the shaking model has
    # free-field boundaries and 5 % viscous damping, and left at rest it moves on for ~0.4 s
    # (prototype; the wall top 25 -> 75 mm at seed 2): the static reading is taken after this
    rest_s: float = param(1.0, unit="s", lo=0, hi=60, hi_open=True,
                          meaning="prototype time the shaking model (free-field boundaries, viscous damping) "
                                  "rests before the base moves; the static reading is taken at its end (1 [A])")
    # the dynamic stage lasts max(end_s, ramp + hold + decay): 180 s prototype is 20x the 9 s
    # default, ~6 h of one core at the coarse default
    ramp_s: float = param(3.0, unit="s", lo=0, hi=60, hi_open=True,
                          meaning="linear ramp up of the base motion, prototype (3 [A])")
    hold_s: float = param(4.0, unit="s", lo=0, hi=60, hi_open=True,
                          meaning="full-amplitude part of the base motion, prototype (4)")
    decay_s: float = param(1.0, unit="s", lo=0, hi=60, hi_open=True,
                           meaning="linear ramp down of the base motion, prototype (1 [A])")
    # 120 s: 13x the default's steps, ~3.5 h at the coarse default
    end_s: float = param(9.0, unit="s", lo=0, hi=120, lo_open=True, hi_open=True,
                         meaning="analysis length from the start of shaking, prototype (9)")
    # the model duration goes as 1 / N: at N = 1 the 9 s are 50x the default's steps, ~13 h coarse
    scale_N: float = param(50.0, lo=1, hi=500, hi_open=True, meaning="g-level N of the centrifuge model (50)")
    resolution: Literal["coarse", "medium", "paper"] = param(
        "coarse", unit="", meaning="grain-scale preset: coarse 3x the paper's grains, medium 2x, paper 1x")
    # 0.5: 8x the paper's ~3.6e5 spheres (~2.9e6, a few GB) and 2x its steps: ~2 weeks of one core
    grain_scale: float = param(0.0, lo=0, hi=8,
                               meaning="grains and wall balls x this; 0: the resolution's (otherwise at least 0.5)")
    # the spheres go as retained_height x (front + behind): 1 m is ~5.6x the default's, ~1.7 h coarse
    # (50 m prototype at 50 g)
    retained_height: float = param(0.18, unit="m", lo=0, hi=1, lo_open=True,
                                   meaning="soil height behind the wall (0.18)")
    front_height: float = param(0.12, unit="m", lo=0, hi=1, lo_open=True, hi_open=True,
                                meaning="soil height in front after excavation, below retained_height (0.12)")
    wall_length: float = param(0.135, unit="m", lo=0, hi=1, lo_open=True, hi_open=True,
                               meaning="sheet-pile length, top flush with the retained surface (0.135)")
    # 2 m behind or in front: ~4x the default's spheres, ~1 h coarse
    behind: float = param(0.40, unit="m", lo=0, hi=2, lo_open=True,
                          meaning="lateral boundary distance behind the wall (0.40)")
    front: float = param(0.14, unit="m", lo=0, hi=2, lo_open=True,
                         meaning="lateral boundary distance in front of the wall (0.14)")
    # 0.5 m: ~17x the default's spheres (~2.7e5), ~5 h coarse
    width: float = param(0.03, unit="m", lo=0, hi=0.5, lo_open=True,
                         meaning="periodic slab thickness, at least three cells of the largest grain (0.03)")
    # 5e-4 m: ~2.4x the spheres and ~3x the steps of the default (dt ~ the smallest grain), ~2 h coarse
    d_min: float = param(1.5e-3, unit="m", lo=5e-4,
                         meaning="smallest grain diameter at the paper's resolution (1.5e-3)")
    d_max: float = param(2.5e-3, unit="m", lo=5e-4,
                         meaning="largest grain diameter at the paper's resolution, at least d_min (2.5e-3)")
    # dt goes as sqrt(density): 500 kg/m^3 is ~2.3x the default's steps
    grain_density: float = param(2650.0, unit="kg/m^3", lo=500, hi=20_000, meaning="grain solid density (2650)")
    porosity: float = param(0.40, lo=0.3, hi=0.5, lo_open=True, hi_open=True,
                            meaning="target porosity of the deposit (0.40)")
    # dt goes as 1 / sqrt(G): 1e12 Pa (stiffer than any mineral) is ~6x the default's steps
    shear_modulus: float = param(29e9, unit="Pa", lo=0, hi=1e12, lo_open=True,
                                 meaning="grain shear modulus for Hertz-Mindlin (29 GPa [A])")
    poisson: float = param(0.15, lo=0, hi=0.5, lo_open=True, hi_open=True,
                           meaning="grain Poisson's ratio for Hertz-Mindlin (0.15 [A])")
    friction: float = param(0.5, lo=0, hi=2, hi_open=True,
                            meaning="inter-particle and wall-soil friction coefficient (0.5 [A])")
    # calibrated: the deposit's triaxial peak phi is 29.9 / 32.3 / 33.4 deg at mu_r 0.2 / 0.3 / 0.4
    # (70 kPa, porosity 0.40), paper ~31; the paper names none; not applied while raining, so the
    # porosity stays ~0.40
    rolling_resistance: float = param(0.25, lo=0, hi=1,
                                      meaning="rolling-resistance coefficient mu_r of grain contacts (0.25 [A], "
                                              "calibrated on phi)")
    deposition_friction: float = param(
        0.5, lo=0, hi=2, hi_open=True,
        meaning="friction while the deposit is rained, sets its porosity (0.5 [A]: ~0.40)")
    # the landing grains' energy is dissipated in their first contacts
    deposition_damping: float = param(0.5, lo=0, hi=1, hi_open=True,
                                      meaning="viscous contact damping while raining, fraction of critical (0.5 [A])")
    damping_ratio: float = param(0.05, lo=0, hi=1, hi_open=True,
                                 meaning="viscous contact damping, fraction of critical (0.05 [A])")
    # below 1 the rain would be stiffer than the grains (a smaller step): 1 is ~10x the rain's steps
    softening: float = param(100.0, lo=1, meaning="grain moduli / this while raining, a sqrt(.) larger step (100)")
    wall_youngs: float = param(40e9, unit="Pa", lo=0, hi=1e12, lo_open=True,
                               meaning="sheet-pile Young's modulus (40 GPa)")
    # the wall balls are s t / 2: below 1 mm they outnumber the grains and shrink dt
    wall_thickness: float = param(
        5e-3, unit="m", lo=1e-3,
        meaning="sheet-pile thickness at the paper's resolution (5e-3: two sheets of 2.5 mm balls)")
    # the bonds' step goes as sqrt(mass): 1 kg/m^2 is ~1.7x the default's steps
    wall_mass_per_area: float = param(12.0, unit="kg/m^2", lo=1,
                                      meaning="sheet-pile mass per area (12: 2400 kg/m^3 x 5 mm)")
    boundary_friction: float = param(0.5, lo=0, hi=2, hi_open=True,
                                     meaning="friction of the lateral free-field segments and the base (0.5 [A])")
    column_length: float = param(10.0, lo=4, hi=100, hi_open=True,
                                 meaning="free-field column length along x, in mean grain diameters (10 [A])")
    slice_grains: float = param(2.5, lo=1, hi=20, hi_open=True,
                                meaning="free-field slice thickness, in mean grain diameters (2.5 [A])")
    segment_mass_grains: float = param(0.1, lo=0, hi=10, lo_open=True, hi_open=True,
                                       meaning="mass of one free-field segment, in mean grain masses (0.1 [A])")
    free_field_every: int = param(20, lo=1, hi=1000, meaning="steps between refreshes of the free-field state (20)")
    # steps go as 1 / dt_fraction: 0.01 is 20x the default's, ~8 h coarse
    dt_fraction: float = param(0.2, lo=0.01, hi=0.2, meaning="time step / critical step (0.2, dem3d's limit)")
    settle_ratio: float = param(
        1e-2, lo=0, hi=0.1, lo_open=True, hi_open=True,
        meaning="unbalanced-force ratio ending each static stage (1e-2: rattlers keep bouncing at N g)")
    rain_energy: float = param(1e-3, lo=0, hi=1, lo_open=True, hi_open=True,
                               meaning="kinetic energy per grain ending the rain, in m g d_mean (1e-3)")
    settle_energy: float = param(1e-4, lo=0, hi=1, lo_open=True, hi_open=True,
                                 meaning="kinetic energy per grain ending a static stage held up by rattlers, in m g "
                                         "d_mean (1e-4)")
    # 1 s: 20x the default's static budget
    static_time: float = param(0.05, unit="s", lo=0, hi=1, lo_open=True, hi_open=True,
                               meaning="longest static stage (wall installed, front excavated), model (0.05)")
    # a reading (wall profiles, section forces) every ~40 steps at 1e-3 s, ~10^4 readings
    record_every: float = param(0.02, unit="s", lo=1e-3, hi=1, hi_open=True,
                                meaning="time between readings of the dynamic stage, prototype (0.02)")
    # false by default: true is 1.04x faster (seismic_step_speed_direct_sums.json), but the report's
    # runs and pins are the rows'; over twelve seeds its static states stand where a 1e-12 m move
    # of one grain puts the rows' (seismic_static_seeds.json), above the unmoved rows' (46 kN/m of
    # back thrust against 56-69 when perturbed before the fall), unexplained (seismic_discussion.md)
    direct_sums: bool = param(False, unit="", absent_means=False,
                              meaning="the contact pass adds each pair's force to both its spheres at once (true: "
                                      "4 % faster, sums in another order; not validated) or stores the second "
                                      "sphere's rows and gathers them after (false: the report's runs)")
    seed: int = seed_param(1, meaning="random seed of the deposit")

    def __post_init__(self):
        check_fields(self)
        if 0.0 < self.grain_scale < 0.5:
            raise InvalidParameter("grain_scale", self.grain_scale, "0 (the resolution's) or [0.5, 8]")
        if not self.d_max >= self.d_min:
            raise InvalidParameter("d_max", self.d_max, f">= {self.d_min:g} m", "the largest grain is at least d_min")
        if not self.front_height < self.retained_height:
            raise InvalidParameter("front_height", self.front_height, f"(0, {self.retained_height:g}) m",
                                   "below retained_height")
        free = self.retained_height - self.front_height
        if not free < self.wall_length < self.retained_height:
            raise InvalidParameter("wall_length", self.wall_length, f"({free:g}, {self.retained_height:g}) m",
                                   "between the free height and the retained height")
        s = self.scale
        if self.width < 3.0 * (s * self.d_max + 0.4 * s * self.d_min):
            raise InvalidParameter("width", self.width, f">= {3 * 1.4 * s * self.d_max:.4g} m",
                                   "three neighbour cells of the largest grain across the periodic slab")
        if self.wall_length - (self.retained_height - self.front_height) < 2 * s * self.d_max:
            raise InvalidParameter("wall_length", self.wall_length, "an embedment of >= 2 grains below the dredge line")

    # ------------------------------------------------------------------ derived
    @property
    def scale(self) -> float:
        """Grain scale s actually used (grain_scale, or the resolution's)."""
        return self.grain_scale if self.grain_scale > 0 else RESOLUTIONS[self.resolution]

    @property
    def grains(self) -> tuple[float, float]:
        """(d_min, d_max) of the soil at this resolution [m]."""
        return self.scale * self.d_min, self.scale * self.d_max

    @property
    def d_mean(self) -> float:
        return 0.5 * sum(self.grains)

    @property
    def wall_ball(self) -> float:
        """Wall ball diameter D [m]: two sheets make the thickness s t, rounded so a whole
        number of balls spans the periodic width."""
        target = 0.5 * self.scale * self.wall_thickness
        return self.width / max(1, round(self.width / target))

    @property
    def toe(self) -> float:
        """Height of the wall toe above the base [m] (wall top flush with the retained surface)."""
        return self.retained_height - self.wall_length

    @property
    def gravity(self) -> float:
        """N g [m/s^2]."""
        return self.scale_N * G

    # ------------------------------------------------------------------ scaling
    def to_prototype_time(self, t_model: float) -> float:
        return t_model * self.scale_N

    def to_model_time(self, t_proto: float) -> float:
        return t_proto / self.scale_N

    @property
    def model_frequency(self) -> float:
        """Base-motion frequency in model units [Hz] (N x prototype)."""
        return self.frequency * self.scale_N

    @property
    def model_amplitude(self) -> float:
        """Peak base acceleration in model units [m/s^2] (N x prototype)."""
        return self.amplitude_g * G * self.scale_N

    @property
    def duration(self) -> float:
        """Model time of the dynamic stage [s]."""
        return self.to_model_time(max(self.end_s, self.ramp_s + self.hold_s + self.decay_s))


#: centrifuge similitude, model value x factor = prototype value (reference section 1)
def prototype_factors(N: float) -> dict[str, float]:
    return {"length": N, "time": N, "frequency": 1.0 / N, "acceleration": 1.0 / N, "stress": 1.0,
            "force_per_width": N, "moment_per_width": N * N, "EI_per_width": N ** 3}


def wall_youngs_effective(case: SeismicCase) -> float:
    """E_eff [Pa] of the s-times-thicker wall with the paper's EI per width:
    E_eff (2 D)^3 / 12 = E t^3 / 12."""
    t = 2.0 * case.wall_ball
    return case.wall_youngs * case.wall_thickness ** 3 / t ** 3


def wall_ball_density(case: SeismicCase) -> float:
    """Ball density [kg/m^3] giving the wall's mass per area with a square array of two
    sheets: m / A = 2 rho (pi / 6) D^3 / D^2 = rho pi D / 3."""
    return case.wall_mass_per_area * 3.0 / (math.pi * case.wall_ball)
