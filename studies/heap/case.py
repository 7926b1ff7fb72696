"""Nadukuru & Michalowski (2012), Fig. 1: a prismatic heap whose base subsides at the
centre. The case builder over dem3d (the engine is used as it is).

Paper (Nadukuru & Michalowski 2012, section "Arching", Fig. 1):
~12,000 particles (75 % spheres, 25 % clumps of two spheres overlapping by one radius),
friction 0.65, "particles between 2.3 and 3.7 cm", rained into a box with a base of
4.8 x 0.6 m; side walls removed so a prismatic heap forms by rolling and sliding; the two
halves of the base then rotate about their end (outer) edges to a centre subsidence
Delta/H = 0.0067. Fig. 1(c): the base stress after the deflection has "a distinct local
minimum at the center (a dip)", load shed from the compliant centre to the stiffer parts.

Geometry here: base from x = -L/2 to L/2 (L = 4.8 m) at z = 0, two halves each of
``bins`` / 2 panels (the stress bins); periodic along y (width w = 0.6 m), so the heap is
an infinitely long prism (plane strain), the reading of "prismatic" with no side wall to
carry load by friction or order the packing (the wall study found periodic and smooth
side walls alike, docs/validation/nadukuru_side_walls.json). The end walls at x = +-L/2
hold the rained fill and are then removed; grains that roll off the base edges fall on a
catch floor 1.2 m below, out of reach of the heap.

Assumptions (the paper omits "the remaining details"), all case fields:
* "2.3-3.7 cm" read as radii: exactly half the wall study's diameters 4.60-7.36 cm, and
  with diameters of 2.3-3.7 cm 12,000 particles would fill the box only 0.12 m deep (no
  heap could form); with radii the fill is ~0.9 m deep.
* ``particles`` counts spheres incl. clump members (PFC balls), as the wall study does:
  12,000 spheres = 9,600 bodies. If the paper's "12,000 particles, of which 75 %
  spherical" counts bodies it had 15,000 spheres (``--particles 15000``).
* the wall study's contact law (kn 8.3 MN/m, ks 3.32 MN/m, density 2650 kg/m^3), viscous
  normal damping 0.2, PFC's local damping 0.7 after the fall; base friction 0.65 (as the
  grains); subsidence speed 0.02 m/s at the centre (the wall study's wall speed);
  the flow lasts ``slump_time`` = 2.5 s without local damping before the heap is arrested.
Stress normalisation: rho g (1 - n) H, n the heap's measured porosity, H its height.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

import dem3d
from analytic.errors import InvalidParameter
from analytic.constants import G
from analytic.schema import check_fields, param, seed_param
from studies.granular import CLUMP_VOLUME_FACTOR, MOST_PARTICLE_STEPS


CATCH_DEPTH = 1.2        # m below the base: the spill pile stays clear of the base


GENERATION_FRACTIONS = (0.25, 0.2, 0.15)


@dataclass(frozen=True)
class HeapCase:
    """Everything a heap run needs (the paper's values and the assumptions: module docstring)."""

    # ~4 KB a sphere (engine arrays, double-buffered neighbour pairs): 1e6 spheres ~4 GB; the
    # grains keep their size, so the fill deepens and the steps grow with its height: ~3 days
    # at 1e6 (paper scale, 12,000: 277 s of CPU, docs/validation/heap.md)
    particles: int = param(12_000, lo=50, hi=1_000_000,
                           meaning="spheres including clump members (12,000; 15,000 if the paper counted bodies)")
    clump_fraction: float = param(0.25, lo=0, hi=1, meaning="fraction of the bodies that are two-sphere clumps "
                                                            "(paper 0.25)")
    # 2 radii would make the two spheres one (dem3d.random_specimen's range)
    clump_overlap: float = param(1.0, lo=0, hi=2, hi_open=True,
                                 meaning="overlap of the two spheres of a clump, in radii (paper 1)")
    d_min: float = param(0.046, unit="m", lo=0, lo_open=True,
                         meaning="smallest sphere diameter, uniform up to d_max (the paper's 2.3-3.7 cm read as "
                                 "radii: 0.046-0.0736, the wall study's diameters)")
    d_max: float = param(0.0736, unit="m", lo=0, lo_open=True,
                         meaning="largest sphere diameter (0.0736: the paper's 3.7 cm read as a radius)")
    kn: float = param(8.3e6, unit="N/m", lo=0, lo_open=True,
                      meaning="normal contact stiffness (assumed: the wall study's 8.3e6)")
    ks: float = param(3.32e6, unit="N/m", lo=0, lo_open=True,
                      meaning="shear contact stiffness (assumed: the wall study's 3.32e6)")
    particle_friction: float = param(0.65, lo=0, meaning="friction coefficient between grains (paper 0.65)")
    base_friction: float = param(0.65, lo=0, meaning="friction coefficient of the base halves (assumed 0.65)")
    density: float = param(2650.0, unit="kg/m^3", lo=0, lo_open=True,
                           meaning="grain density (assumed: the wall study's 2650)")
    damping_ratio: float = param(0.2, lo=0, hi=1, hi_open=True,
                                 meaning="viscous normal damping, fraction of critical (assumed 0.2, as the wall "
                                         "study)")
    local_damping: float = param(0.7, lo=0, hi=1, hi_open=True,
                                 meaning="PFC local damping while the rained fill settles and after the flow "
                                         "(PFC's 0.7)")
    # the particle count sets memory and time (the fill is as deep as the grains make it);
    # a heap base longer than 100 m is none of the paper's
    base_length: float = param(4.8, unit="m", lo=0, hi=100, lo_open=True,
                               meaning="length L of the base, two halves that turn (paper 4.8)")
    width: float = param(0.6, unit="m", lo=0, hi=100, lo_open=True,
                         meaning="periodic width w of the base, at least 3.4 d_max (paper 0.6)")
    # every sphere is checked against every panel when the neighbour list is rebuilt, and a
    # bin narrower than a grain reads no stress: 200 bins of 2.4 cm at the paper's base
    bins: int = param(24, lo=4, hi=200, meaning="base panels (stress bins), an even number, half on each half "
                                                "of the base (24)")
    target_porosity: float = param(0.38, lo=0.2, hi=0.7, lo_open=True, hi_open=True,
                                   meaning="porosity used to size the generation box and the fill height (0.38)")
    subsidence_over_H: float = param(0.0067, lo=0, hi=0.1, lo_open=True, hi_open=True,
                                     meaning="Delta/H, the subsidence at the centre over the heap height (paper "
                                             "0.0067)")
    # the run's length (MOST_PARTICLE_STEPS) bounds a slow subsidence
    subsidence_speed: float = param(0.02, unit="m/s", lo=0, lo_open=True,
                                    meaning="speed of the inner edges of the base once ramped up (assumed: the "
                                            "wall study's 0.02)")
    # 10 s: 4e5 steps of the paper-scale 2.55e-5 s
    ramp: float = param(0.05, unit="s", lo=0, hi=10,
                        meaning="time over which the subsidence speed ramps up from 0 (0.05)")
    settle_ratio: float = param(5e-3, lo=0, lo_open=True, meaning="unbalanced-force ratio that ends raining")
    # 60 s: 2.4e6 steps of 2.55e-5 s, ~2 h at 12,000 spheres (each of the three durations)
    slump_time: float = param(2.5, unit="s", lo=0, hi=60, lo_open=True,
                              meaning="time the fill flows without local damping once the end walls go (2.5)")
    arrest_time: float = param(1.0, unit="s", lo=0, hi=60, lo_open=True,
                               meaning="the longest the arrest of the heap (local damping on) may take (1)")
    rest_speed: float = param(2e-3, unit="m/s", lo=0, lo_open=True,
                              meaning="rms speed of the heap's grains at which it counts as at rest (0.002)")
    hold_time: float = param(0.1, unit="s", lo=0, hi=60, lo_open=True,
                             meaning="time the subsided base is held before the stresses are read (0.1)")
    # the panel forces of every averaged step are held in memory: 1e5 steps x (bins + 1)
    # panels x 48 B, 120 MB at 24 bins, 1 GB at 200
    average_steps: int = param(2000, lo=1, hi=100_000,
                               meaning="time steps over which the base stresses are averaged, before and after "
                                       "(2000)")
    seed: int = seed_param(1)

    def __post_init__(self):
        check_fields(self)
        if not self.d_min <= self.d_max:
            raise InvalidParameter("d_min, d_max", f"{self.d_min:g}, {self.d_max:g}", "d_min <= d_max [m]")
        if self.bins % 2:
            raise InvalidParameter("bins", self.bins, "an even whole number in [4, 200]")
        if self.width < 3.4 * self.d_max:
            raise InvalidParameter("width", self.width, f">= {3.4 * self.d_max:.3f} m",
                                   "the periodic length must hold 3 neighbour cells (3.4 d_max)")
        steps = self.most_steps()
        work = self.particles * steps
        if work > MOST_PARTICLE_STEPS:
            raise InvalidParameter("particles x time steps", work, f"<= {MOST_PARTICLE_STEPS:g}",
                                   f"up to {steps:.3g} steps of {time_step(self):.3g} s, ~{work / 4e6 / 86400:.3g} "
                                   "days on 2 cores")

    @property
    def bodies(self) -> int:
        return int(round(self.particles / (1.0 + self.clump_fraction)))

    def most_steps(self) -> float:
        """Time steps of one run at most (``run_heap``): the fall from the tallest cloud,
        each stage at its cap, the subsidence of a heap as high as the rained fill."""
        dt = time_step(self)
        top = fill_height(self) * (1.0 - self.target_porosity) / GENERATION_FRACTIONS[-1]
        fall = 1.2 * math.sqrt(top / G) / dt + 1.0 / dt
        flow = (self.slump_time + self.arrest_time + self.hold_time) / dt
        return fall + flow + subsidence_duration(self, fill_height(self)) / dt + 2 * self.average_steps


# ----------------------------------------------------------------------------- walls
def contact(case: HeapCase, local: float) -> dem3d.ContactParams:
    return dem3d.linear(case.kn, case.ks, case.particle_friction, zeta_n=case.damping_ratio, zeta_s=0.0,
                        local_damping=local)


def time_step(case: HeapCase) -> float:
    """dem3d's DT_SAFETY x the critical step of the lightest sphere [s] (the wall study's rule)."""
    m_min = case.density * math.pi / 6.0 * case.d_min ** 3
    law = dem3d.linear(case.kn, case.ks, 0.0)
    return dem3d.DT_SAFETY * dem3d.critical_time_step(law, m_min, case.d_min / 2, case.density)


def base_half(case: HeapCase, side: int) -> list:
    """The left (side -1) or right (+1) half of the base: bins/2 panels from the outer
    edge x = side L/2 inward to x = 0, normal +z, unbounded along the periodic y. The inner
    edge is marked shared: the halves meet there (a V once they turn, never a step)."""
    half = 0.5 * case.base_length
    panels = dem3d.segmented_wall((side * half, 0.5 * case.width, 0.0), (0.0, 0.0, 1.0), (-side, 0.0, 0.0),
                                  case.width, half, case.bins // 2, case.base_friction, unbounded_width=True)
    last = panels[-1]
    panels[-1] = dataclasses.replace(last, shared=last.shared[:3] + (True,))
    return panels


def subsidence_motion(case: HeapCase, side: int, H: float, t0: float) -> dem3d.Motion:
    """A base half turning about its outer edge so the inner edge goes down at
    ``subsidence_speed`` (ramped over ``ramp``), clock starting at t0. The left half
    (pivot x = -L/2) turns about +y, the right one about -y: omega a x (q - P) = -z."""
    half = 0.5 * case.base_length
    ramp = dem3d.Ramp(case.subsidence_speed / half, case.ramp)
    return dem3d.rotation((side * half, 0.0, 0.0), (0.0, -side, 0.0), lambda t: ramp(t - t0))


def walls(case: HeapCase, motions=(dem3d.FIXED, dem3d.FIXED), ends: bool = False) -> list:
    """Base halves ("base_left", "base_right", with ``motions``), the catch floor, and
    while the fill is rained the frictionless end walls at x = +-L/2."""
    half = 0.5 * case.base_length
    catch = dem3d.plane((0.0, 0.5 * case.width, -CATCH_DEPTH), (0.0, 0.0, 1.0), case.particle_friction,
                        (half + 2.0, 0.5 * case.width))
    out = [dem3d.Wall("base_left", base_half(case, -1), motions[0]),
           dem3d.Wall("base_right", base_half(case, +1), motions[1]), dem3d.Wall("catch", [catch])]
    if ends:
        out.append(dem3d.Wall("ends", [
            dem3d.plane((-half, 0.5 * case.width, 1.0), (1.0, 0.0, 0.0), 0.0, (0.5 * case.width, 1.0)),
            dem3d.plane((half, 0.5 * case.width, 1.0), (-1.0, 0.0, 0.0), 0.0, (0.5 * case.width, 1.0))]))
    return out


def base_ids(sim) -> np.ndarray:
    """Panel ids of the base, left outer edge to right outer edge (x increasing)."""
    left = sim.walls.panel_ids("base_left")            # stacked from the outer edge inward
    right = sim.walls.panel_ids("base_right")
    return np.concatenate([left, right[::-1]])


def bin_centres(case: HeapCase) -> np.ndarray:
    """x of each base bin's centre [m], left to right (the base before it turns)."""
    edges = np.linspace(-0.5 * case.base_length, 0.5 * case.base_length, case.bins + 1)
    return 0.5 * (edges[1:] + edges[:-1])


def fill_height(case: HeapCase) -> float:
    """Depth [m] of the rained fill at ``target_porosity``: the bodies' solid volume over
    the base area (uniform diameters: mean d^3 = (b^4 - a^4) / (4 (b - a)))."""
    a, b = case.d_min, case.d_max
    mean_d3 = (b**4 - a**4) / (4.0 * (b - a)) if b > a else a**3
    v_body = math.pi / 6.0 * mean_d3 * (1.0 + case.clump_fraction * (CLUMP_VOLUME_FACTOR - 1.0))
    return case.bodies * v_body / ((1.0 - case.target_porosity) * case.base_length * case.width)


# ----------------------------------------------------------------------------- subsidence
def subsidence_duration(case: HeapCase, H: float) -> float:
    """Time [s] for the inner edges to go down Delta = subsidence_over_H H when their speed
    ramps linearly to ``subsidence_speed`` over ``ramp``."""
    target, v, ramp = case.subsidence_over_H * H, case.subsidence_speed, case.ramp
    return ramp / 2.0 + target / v if target / v > ramp / 2.0 else math.sqrt(2.0 * target * ramp / v)
