"""The seismic sheet-pile case (Sizkow & El Shamy): a frozen record in model units (a
50 g centrifuge model, SI), its resolution presets and the centrifuge scaling to
prototype units. Data and every assumption: ../shared/reference/seismic-sheetpile.md,
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

from analytic.errors import InvalidParameter
from analytic.inputs import require_number

G = 9.81

#: grain_scale of each resolution preset: coarse 3x the paper's grains (~15k spheres, the
#: default: one frequency in < 30 min on one core; 3 is the largest the 3 cm periodic slab
#: admits), medium 2x (~51k), paper 1x (~3.6e5)
RESOLUTIONS = {"coarse": 3.0, "medium": 2.0, "paper": 1.0}

#: prototype frequencies the paper reports (Hz)
PAPER_FREQUENCIES = (1.0, 3.0, 4.0, 5.0, 6.0)


@dataclass(frozen=True)
class SeismicCase:
    """Model units (SI) unless a name says prototype; defaults are the paper's values or
    the reference's assumptions (reference.json tags each).

    frequency:            base-motion frequency, prototype [Hz] (1-6 in the paper)
    amplitude_g:          peak base acceleration, prototype [g] (0.1)
    ramp_s, hold_s, decay_s: envelope of the base motion, prototype [s] (3, 4, 1; linear ramps [A])
    end_s:                analysis length from the start of shaking, prototype [s] (9)
    scale_N:              g-level N of the centrifuge model (50)
    resolution:           coarse | medium | paper: the grain_scale preset (3, 2, 1)
    grain_scale:          0 = from resolution; else grains and wall balls x this
    retained_height:      soil height behind the wall [m] (0.18)
    front_height:         soil height in front after excavation [m] (0.12)
    wall_length:          sheet-pile length, top flush with the retained surface [m] (0.135)
    behind:               lateral boundary distance behind the wall [m] (0.40)
    front:                lateral boundary distance in front of the wall [m] (0.14)
    width:                periodic slab thickness [m] (0.03)
    d_min, d_max:         grain diameters at the paper's resolution [m] (1.5e-3, 2.5e-3)
    grain_density:        [kg/m^3] (2650)
    porosity:             target porosity of the deposit (0.40)
    shear_modulus, poisson: grain elastic constants for Hertz-Mindlin [Pa], [-] (29 GPa, 0.15 [A])
    friction:             inter-particle and wall-soil friction coefficient (0.5 [A])
    rolling_resistance:   rolling-resistance coefficient mu_r of grain contacts (dem3d ContactParams.mu_roll;
                          0.25 [A], calibrated: the deposit's triaxial peak phi is 29.9 / 32.3 / 33.4 deg at
                          mu_r 0.2 / 0.3 / 0.4 (70 kPa, porosity 0.40), paper ~31; the paper names none; not
                          applied while raining, so the porosity stays ~0.40)
    deposition_friction:  friction while the deposit is rained (sets its porosity [A]; 0.5, the grains'
                          own, gives ~0.40)
    deposition_damping:   viscous contact damping while raining, fraction of critical (0.5 [A]: the
                          landing grains' energy is dissipated in their first contacts)
    damping_ratio:        viscous contact damping, fraction of critical (0.05 [A])
    softening:            grain moduli / this while raining (a sqrt(.) larger step; 100)
    wall_youngs:          sheet-pile Young's modulus [Pa] (40 GPa)
    wall_thickness:       at the paper's resolution [m] (5e-3; two sheets of 2.5 mm balls)
    wall_mass_per_area:   [kg/m^2] (12: 2400 kg/m^3 x 5 mm)
    boundary_friction:    friction of the lateral free-field segments and the base (0.5 [A])
    column_length:        free-field column length along x, in mean grain diameters (10 [A])
    slice_grains:         free-field slice thickness, in mean grain diameters (2.5 [A])
    segment_mass_grains:  mass of one free-field segment, in mean grain masses (0.1 [A])
    free_field_every:     steps between refreshes of the free-field state (20)
    dt_fraction:          time step / critical step (0.2, dem3d's limit)
    settle_ratio:         unbalanced-force ratio ending each static stage (1e-2: rattlers keep bouncing at N g)
    rain_energy:          kinetic energy per grain ending the rain, in m g d_mean (1e-3)
    settle_energy:        kinetic energy per grain ending a static stage, in m g d_mean, when the
                          ratio is held up by rattlers (1e-4)
    static_time:          longest static stage (wall installed, front excavated), model [s] (0.05)
    record_every:         time between readings of the dynamic stage, prototype [s] (0.02)
    seed:                 random seed of the deposit
    """

    frequency: float = 5.0
    amplitude_g: float = 0.1
    ramp_s: float = 3.0
    hold_s: float = 4.0
    decay_s: float = 1.0
    end_s: float = 9.0
    scale_N: float = 50.0
    resolution: Literal["coarse", "medium", "paper"] = "coarse"
    grain_scale: float = 0.0
    retained_height: float = 0.18
    front_height: float = 0.12
    wall_length: float = 0.135
    behind: float = 0.40
    front: float = 0.14
    width: float = 0.03
    d_min: float = 1.5e-3
    d_max: float = 2.5e-3
    grain_density: float = 2650.0
    porosity: float = 0.40
    shear_modulus: float = 29e9
    poisson: float = 0.15
    friction: float = 0.5
    rolling_resistance: float = 0.25
    deposition_friction: float = 0.5
    deposition_damping: float = 0.5
    damping_ratio: float = 0.05
    softening: float = 100.0
    wall_youngs: float = 40e9
    wall_thickness: float = 5e-3
    wall_mass_per_area: float = 12.0
    boundary_friction: float = 0.5
    column_length: float = 10.0
    slice_grains: float = 2.5
    segment_mass_grains: float = 0.1
    free_field_every: int = 20
    dt_fraction: float = 0.2
    settle_ratio: float = 1e-2
    rain_energy: float = 1e-3
    settle_energy: float = 1e-4
    static_time: float = 0.05
    record_every: float = 0.02
    seed: int = 1

    def __post_init__(self):
        require_number("frequency", self.frequency, 0.0, 20.0, unit="Hz (prototype)")
        require_number("amplitude_g", self.amplitude_g, 0.0, 0.5, hi_open=False, unit="g (prototype)")
        for name in ("ramp_s", "hold_s", "decay_s"):
            require_number(name, getattr(self, name), 0.0, 60.0, lo_open=False, unit="s (prototype)")
        require_number("end_s", self.end_s, 0.0, 120.0, unit="s (prototype)")
        require_number("scale_N", self.scale_N, 1.0, 500.0, lo_open=False)
        if self.resolution not in RESOLUTIONS:
            raise InvalidParameter("resolution", self.resolution, " | ".join(RESOLUTIONS))
        require_number("grain_scale", self.grain_scale, 0.0, 8.0, lo_open=False, hi_open=False)
        if 0.0 < self.grain_scale < 0.5:
            raise InvalidParameter("grain_scale", self.grain_scale, "0 (the resolution's) or [0.5, 8]")
        for name in ("retained_height", "wall_length", "behind", "front", "width", "d_min", "grain_density",
                     "shear_modulus", "wall_youngs", "wall_thickness", "wall_mass_per_area", "softening"):
            require_number(name, getattr(self, name), 0.0, None)
        require_number("d_max", self.d_max, self.d_min, None, lo_open=False, unit="m (>= d_min)")
        require_number("front_height", self.front_height, 0.0, self.retained_height, unit="m (< retained_height)")
        require_number("wall_length", self.wall_length, self.retained_height - self.front_height,
                       self.retained_height, unit="m (between the free height and the retained height)")
        require_number("porosity", self.porosity, 0.3, 0.5)
        require_number("poisson", self.poisson, 0.0, 0.5)
        for name in ("friction", "deposition_friction", "boundary_friction"):
            require_number(name, getattr(self, name), 0.0, 2.0, lo_open=False)
        require_number("rolling_resistance", self.rolling_resistance, 0.0, 1.0, lo_open=False, hi_open=False)
        for name in ("damping_ratio", "deposition_damping"):
            require_number(name, getattr(self, name), 0.0, 1.0, lo_open=False)
        for name in ("rain_energy", "settle_energy"):
            require_number(name, getattr(self, name), 0.0, 1.0, unit="m g d_mean per grain")
        require_number("column_length", self.column_length, 4.0, 100.0, lo_open=False, unit="grain diameters")
        require_number("slice_grains", self.slice_grains, 1.0, 20.0, lo_open=False, unit="grain diameters")
        require_number("segment_mass_grains", self.segment_mass_grains, 0.0, 10.0, unit="grain masses")
        require_number("free_field_every", self.free_field_every, 1, 1000, lo_open=False, hi_open=False)
        require_number("dt_fraction", self.dt_fraction, 0.0, 0.2, hi_open=False)
        require_number("settle_ratio", self.settle_ratio, 0.0, 0.1)
        require_number("static_time", self.static_time, 0.0, 1.0, unit="s (model)")
        require_number("record_every", self.record_every, 0.0, 1.0, unit="s (prototype)")
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
