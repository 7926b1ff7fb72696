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

A run (``run_heap``) goes through ``STAGES``; it hands over checkpoints between engine
calls (every 300 s and every 10 % of a stage) and resumes from one bit for bit.
The engine is called ``chunk_steps`` steps at a time, so Ctrl-C acts within about a second.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

import dem3d
from analytic.errors import InvalidParameter
from analytic.constants import G
from analytic.schema import check_fields, param, seed_param
from dem3d import measure
from studies.granular import CLUMP_VOLUME_FACTOR, MOST_PARTICLE_STEPS
from studies.store import content_key

_CATCH_DEPTH = 1.2        # m below the base: the spill pile stays clear of the base
_GENERATION_FRACTIONS = (0.25, 0.2, 0.15)


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
        top = fill_height(self) * (1.0 - self.target_porosity) / _GENERATION_FRACTIONS[-1]
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
    catch = dem3d.plane((0.0, 0.5 * case.width, -_CATCH_DEPTH), (0.0, 0.0, 1.0), case.particle_friction,
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


# ----------------------------------------------------------------------------- stages
@dataclass
class StageLog:
    """Steps, wall and CPU time [s] of each stage (CPU counts every thread)."""

    stages: dict = field(default_factory=dict)
    tic: float = field(default_factory=_time.perf_counter)
    cpu: float = field(default_factory=_time.process_time)

    def stage(self, name: str, steps: int, **extra) -> None:
        self.stages[name] = {"steps": int(steps), "wall_s": round(_time.perf_counter() - self.tic, 1),
                             "cpu_s": round(_time.process_time() - self.cpu, 1), **extra}
        self.tic, self.cpu = _time.perf_counter(), _time.process_time()


#: particle-steps in one call of the engine (~0.5 s of 2 cores at 4e6 particle-steps/s):
#: a run returns to Python that often, so Ctrl-C acts within about a second at any size
CHUNK_PARTICLE_STEPS = 2e6


def chunk_steps(sim, most: int = 1000) -> int:
    """Steps of one engine call: ``CHUNK_PARTICLE_STEPS`` over the sphere count, 1 to ``most``."""
    return max(1, min(int(most), int(CHUNK_PARTICLE_STEPS // max(1, sim.n_spheres))))


def advance(sim, n_steps: int, *, record_panels: bool = False) -> np.ndarray | None:
    """``sim.step(n_steps)`` in engine calls of ``chunk_steps`` steps, the same bits (the
    engine keeps nothing between calls but its state, and its wall schedule accumulates
    time as the steps do); with ``record_panels`` the panel forces of every step
    (n_steps, panels, 3), as ``sim.step`` returns them."""
    hist = np.zeros((n_steps, sim.walls.n_panels, 3)) if record_panels else None
    done = 0
    while done < n_steps:
        k = min(chunk_steps(sim), n_steps - done)
        out = sim.step(k, record_panels=record_panels)
        if record_panels:
            hist[done:done + k] = out[0]
        done += k
    return hist


#: the stages of a run, in order (``_Run``); a checkpoint names the one it was taken in.
#: The stage log's "rain" is fall + settle
STAGES = ("fall", "settle", "slump", "arrest", "before", "subsidence", "hold", "after")

#: a checkpoint of the run is handed over every this many seconds of wall time ...
CHECKPOINT_EVERY_S = 300.0
#: ... and each time another this fraction of a stage's steps is done (a short run
#: interrupted before 300 s would otherwise start over); only between engine calls
CHECKPOINT_EVERY_FRACTION = 0.1

#: the steps between the base readings of the subsidence (``subside``)
RECORD_EVERY = 200


def fill_height(case: HeapCase) -> float:
    """Depth [m] of the rained fill at ``target_porosity``: the bodies' solid volume over
    the base area (uniform diameters: mean d^3 = (b^4 - a^4) / (4 (b - a)))."""
    a, b = case.d_min, case.d_max
    mean_d3 = (b**4 - a**4) / (4.0 * (b - a)) if b > a else a**3
    v_body = math.pi / 6.0 * mean_d3 * (1.0 + case.clump_fraction * (CLUMP_VOLUME_FACTOR - 1.0))
    return case.bodies * v_body / ((1.0 - case.target_porosity) * case.base_length * case.width)


def loose_cloud(case: HeapCase, rng) -> tuple[dem3d.Specimen, float]:
    """Bodies placed at random over the base up to a height for a solid fraction of 0.25
    (0.2, 0.15 if that jams); returns the specimen and that height [m]."""
    half = 0.5 * case.base_length
    h = fill_height(case) * (1.0 - case.target_porosity)
    for fraction in _GENERATION_FRACTIONS:
        top = h / fraction
        try:
            spec = dem3d.random_specimen(rng, (-half + 1e-3, 1e-3, 1e-3), (half - 1e-3, case.width - 1e-3, top),
                                         case.bodies, case.d_min, case.d_max, clump_fraction=case.clump_fraction,
                                         clump_overlap=case.clump_overlap, density=case.density)
            return spec, top
        except InvalidParameter:
            continue
    raise InvalidParameter("particles", case.particles, "a count whose grains fit the generation box")


def rain(case: HeapCase, log: StageLog, progress=None) -> dem3d.Simulation:
    """Stage 1 (``STAGES`` fall, settle): the cloud falls into the box (end walls in
    place) at 2 g without local damping (it would slow the fall), then settles at g with
    local damping until the unbalanced-force ratio is below ``settle_ratio`` (checked
    every 500 steps, at most 1 s)."""
    run = _Run(case, log, progress=progress)
    run.run("fall", "settle")
    return run.sim


def rebuilt(case: HeapCase, sim, keep: np.ndarray | None = None) -> dem3d.Simulation:
    """A new simulation of the grains (all, or the bodies with a sphere in ``keep``), with
    the base and catch floor only: how the end walls are removed, and the spill on the
    catch floor dropped. Contact history restarts (PFC's would not); both happen while
    the grains move (the fill about to collapse, the heap still flowing)."""
    sph = sim.spheres
    body = np.isin(sph.body_id, np.unique(sph.body_id[keep])) if keep is not None else np.ones(sim.n_spheres, bool)
    labels = np.where(sph.clump >= 0, sph.clump, -1)[body]
    _, relabel = np.unique(labels[labels >= 0], return_inverse=True)   # clump ids contiguous again
    labels[labels >= 0] = relabel
    spec = dem3d.Specimen(sph.x[body].copy(), sph.r[body].copy(), labels, case.density, sph.v[body].copy())
    return dem3d.Simulation(spec, contact(case, case.local_damping), dt=sim.dt, walls=walls(case),
                            periodic=sim.periodic)


def slump(case: HeapCase, sim, log: StageLog, progress=None, on_frame=None) -> dem3d.Simulation:
    """Stage 2 (``STAGES`` slump, arrest): with the end walls gone the fill slumps off the
    base edges into a heap. The flow runs ``slump_time`` s without local damping (PFC's
    0.7 makes a 0.7 m face creep for seconds: measured at 1,500 spheres), a frame every
    0.25 s; the grains that fell off the base are dropped (``rebuilt``) and the heap is
    brought to rest with local damping until its rms speed is below ``rest_speed``
    (checked every 500 steps, at most ``arrest_time``). Returns the heap."""
    run = _Run(case, log, progress=progress, on_frame=on_frame)
    run.sim = sim
    run.run("slump", "arrest")
    return run.sim


def heap_speed(case: HeapCase, sim) -> float:
    """Root-mean-square speed [m/s] of the grains on the base (the global unbalanced-force
    ratio would count the odd grain falling off the edge to the catch floor)."""
    keep = on_base(case, sim.spheres.x, sim.spheres.r) & (sim.spheres.x[:, 2] > 0.0)
    v = sim.spheres.v[keep]
    return float(np.sqrt(np.mean(np.sum(v * v, axis=1)))) if len(v) else 0.0


# ----------------------------------------------------------------------------- measures
def on_base(case: HeapCase, x: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Spheres of the heap: above the catch floor's spill (z > -2 r) and over the base."""
    return (x[:, 2] > -2.0 * r) & (np.abs(x[:, 0]) <= 0.5 * case.base_length + r)


@dataclass(frozen=True)
class Shape:
    """The heap's shape: height H [m] (mean surface height over the central 0.4 m),
    slope [deg] (a line fitted to the surface of both flanks between 0.2 H and 0.8 H),
    the surface height of each 0.1 m column (x, top) and the grains on the base."""

    H: float
    slope_deg: float
    x: np.ndarray
    top: np.ndarray
    spheres: int


def heap_shape(case: HeapCase, sim) -> Shape:
    x, r = sim.spheres.x, sim.spheres.r
    keep = on_base(case, x, r)
    edges = np.arange(-0.5 * case.base_length, 0.5 * case.base_length + 1e-9, 0.1)
    col = np.clip(np.digitize(x[keep, 0], edges) - 1, 0, len(edges) - 2)
    top = np.zeros(len(edges) - 1)
    np.maximum.at(top, col, x[keep, 2] + r[keep])
    xc = 0.5 * (edges[1:] + edges[:-1])
    H = float(top[np.abs(xc) < 0.2].mean())
    flank = (top > 0.2 * H) & (top < 0.8 * H)
    slope = -np.polyfit(np.abs(xc[flank]), top[flank], 1)[0] if flank.sum() >= 2 else float("nan")
    return Shape(H, math.degrees(math.atan(slope)), xc, top, int(keep.sum()))


def heap_porosity(case: HeapCase, sim, H: float) -> float:
    """Porosity in the heap's core: |x| < L/8 (at least 0.3 m), 0.1 H < z < 0.5 H."""
    a = max(0.3, case.base_length / 8.0)
    return measure.porosity(sim, (-a, 0.0, 0.1 * H), (a, case.width, 0.5 * H))


def base_stress(sim, hist_f: np.ndarray | None = None) -> np.ndarray:
    """Normal stress [Pa] (compression +) on each base bin, left to right: the panel
    forces (averaged over ``hist_f`` (steps, panels, 3) when given) over the panel areas."""
    ids = base_ids(sim)
    force = sim.panel_force if hist_f is None else hist_f.mean(axis=0)
    fn = -np.einsum("pd,pd->p", force[ids], sim.walls.panels.normal[ids])
    return fn / sim.walls.areas()[ids]


def averaged_base_stress(sim, steps: int) -> np.ndarray:
    """The base stress averaged over the next ``steps`` steps (``base_stress``)."""
    return base_stress(sim, advance(sim, steps, record_panels=True))


def centre_over_peak(sigma: np.ndarray) -> tuple[float, float, float]:
    """(centre stress, peak stress, their ratio) of a base profile (left to right,
    symmetric bins): the profile is folded about the centre (mean of the bins at +-x,
    the heap being symmetric) to halve the noise; the centre stress is the folded bin
    next to the centre, the peak the largest folded bin. Ratio < 1: a dip (Fig. 1c)."""
    n = len(sigma) // 2
    folded = 0.5 * (sigma[:n][::-1] + sigma[n:])        # index 0 = next to the centre
    centre, peak = float(folded[0]), float(folded.max())
    return centre, peak, centre / peak if peak > 0 else float("nan")


def heap_weight(case: HeapCase, sim) -> float:
    """Weight [N] of the grains above the base (centres over it), a clump's mass shared
    equally by its spheres."""
    sph, clumps = sim.spheres, sim.clumps
    free = sph.clump < 0
    m = np.empty(sim.n_spheres)
    m[free] = 1.0 / sph.inv_m[free]
    c = sph.clump[~free]
    members = (clumps.members[c, 1] - clumps.members[c, 0]).astype(float)
    m[~free] = 1.0 / clumps.inv_m[c] / members
    over = (sph.x[:, 2] > -sph.r) & (np.abs(sph.x[:, 0]) <= 0.5 * case.base_length)
    return float(np.sum(m[over]) * G)


# ----------------------------------------------------------------------------- subsidence
def subsidence_duration(case: HeapCase, H: float) -> float:
    """Time [s] for the inner edges to go down Delta = subsidence_over_H H when their speed
    ramps linearly to ``subsidence_speed`` over ``ramp``."""
    target, v, ramp = case.subsidence_over_H * H, case.subsidence_speed, case.ramp
    return ramp / 2.0 + target / v if target / v > ramp / 2.0 else math.sqrt(2.0 * target * ramp / v)


def centre_drop(sim) -> float:
    """Subsidence [m] of the base at the centre: depth of the inner edge of the left half."""
    corners = sim.walls.corners()[sim.walls.panel_ids("base_left")[-1]]
    return float(-corners[:, 2].min())


@dataclass
class Subsidence:
    """The base profile along the subsidence: Delta/H, centre and peak stress [Pa] of each
    chunk of ``record_every`` steps (panel forces averaged over the chunk)."""

    disp_over_H: list = field(default_factory=list)
    step: list = field(default_factory=list)
    time: list = field(default_factory=list)
    centre: list = field(default_factory=list)
    peak: list = field(default_factory=list)
    sigma: list = field(default_factory=list)


def subside(case: HeapCase, sim, H: float, log: StageLog, *, record_every: int = RECORD_EVERY, on_frame=None,
            frame_every: int = 2000, progress=None):
    """Stage 3 (``STAGES`` subsidence, hold): both base halves turn about their outer
    edges until the centre is down by subsidence_over_H x H, the base stress read every
    ``record_every`` steps (averaged over them); the base is then held for ``hold_time``.
    Returns (the simulation, now with fixed walls, and the Subsidence history).
    ``on_frame(frame, disp_over_H)`` is called every ``frame_every`` steps."""
    run = _Run(case, log, progress=progress, on_frame=on_frame, record_every=record_every, frame_every=frame_every)
    run.sim = sim
    run.kept["H"] = H
    run.run("subsidence", "hold")
    return run.sim, run.hist


@dataclass
class HeapRun:
    """Everything a heap run measured (SI units; stresses in Pa, left to right)."""

    shape: Shape
    porosity: float
    sigma_before: np.ndarray
    sigma_after: np.ndarray
    history: Subsidence
    disp_over_H: float
    weight_N: float
    base_force_before_N: float
    frames: dict
    spheres: int          # rained (the case's particle count)
    bodies: int           # rained
    dt: float
    stages: dict
    #: wall and CPU time [s] the run had taken up to the checkpoint it was resumed from
    #: (0, 0 for a run in one go)
    before_resume_s: tuple = (0.0, 0.0)


def run_heap(case: HeapCase, *, on_frame=None, progress=None, checkpoint=None, resume: dict | None = None,
             checkpoint_every_s: float | None = None, checkpoint_every_fraction: float | None = None) -> HeapRun:
    """Rain, slump, measure the base before, subside, measure after (module docstring).
    ``on_frame(frame, Delta/H or None)`` gets the rained fill, the heap, frames along the
    subsidence and the end state.

    ``checkpoint(state)`` is called between engine calls every ``checkpoint_every_s`` of
    wall time (``CHECKPOINT_EVERY_S``) and each time another ``checkpoint_every_fraction``
    of a stage's steps is done (``CHECKPOINT_EVERY_FRACTION``; ``STAGES``), after the
    frame or reading of that point was handed over, never at the run's end; ``state`` is
    a dict of numpy arrays (save it with ``studies.store.npz_bytes``). ``resume=state``
    (as saved, or loaded back) continues that run: the result is the uninterrupted run's
    bit for bit (its stage times those of both parts), and ``on_frame`` gets the frames
    after the checkpoint only."""
    run = _Run(case, StageLog(), on_frame=on_frame, progress=progress, checkpoint=checkpoint, resume=resume,
               checkpoint_every_s=checkpoint_every_s, checkpoint_every_fraction=checkpoint_every_fraction)
    run.run()
    return run.result()


# ----------------------------------------------------------------------------- the run, resumable
def checkpoint_key(case: HeapCase, record_every: int = RECORD_EVERY) -> str:
    """What a checkpoint of ``run_heap`` belongs to: the case and the subsidence's
    sampling (a resume with any other would not continue the same run)."""
    return content_key({"case": dataclasses.asdict(case), "record_every": int(record_every), "v": 1})


def checkpoint_stage(state: dict) -> tuple[str, int]:
    """(stage, steps of that stage done) of a checkpoint of ``run_heap``."""
    return STAGES[int(state["heap/stage"])], int(state["heap/done"])


def _prefixed(arrays: dict, prefix: str) -> dict:
    return {k[len(prefix):]: v for k, v in arrays.items() if k.startswith(prefix)}


class _Run:
    """A heap run in progress: the stage it is in (``STAGES``), the steps of that stage
    done, the simulation, and what the later stages need: ``kept`` (the fall's length,
    the settle ratio, the arrest speed, the spheres and bodies rained, the heap's shape,
    porosity and weight, the base stress before, the subsidence's start time and frame
    counter), the subsidence history, the panel forces of an averaging window in
    progress and the frame before subsidence. ``state()`` is all of it as numpy arrays
    (the engine's by ``Simulation.to_arrays``, which resumes bit for bit); ``resume=``
    such a state continues from it. No random number is drawn after the cloud is placed,
    so no generator state is kept.

    Each stage's loop runs from ``done`` and decides only at the boundaries a straight
    run has (the settle checks, the arrest checks, the 0.25 s frames of the flow, the
    subsidence readings), so a run resumed at any checkpoint takes the same steps: one
    taken between engine calls inside such an interval goes on to its boundary, one at
    a boundary is taken after the decision there (``_tick``)."""

    def __init__(self, case: HeapCase, log: StageLog, *, on_frame=None, progress=None, checkpoint=None,
                 resume: dict | None = None, checkpoint_every_s: float | None = None,
                 checkpoint_every_fraction: float | None = None, record_every: int = RECORD_EVERY,
                 frame_every: int = 2000):
        self.case, self.log, self.on_frame, self.progress, self.checkpoint = case, log, on_frame, progress, checkpoint
        self.every_s = CHECKPOINT_EVERY_S if checkpoint_every_s is None else float(checkpoint_every_s)
        self.every_fraction = (CHECKPOINT_EVERY_FRACTION if checkpoint_every_fraction is None
                               else float(checkpoint_every_fraction))
        self.record_every, self.frame_every = int(record_every), int(frame_every)
        self.key = checkpoint_key(case, self.record_every)
        self.stage, self.done, self.sim = 0, 0, None
        self.kept: dict = {}
        self.hist = Subsidence()
        self.avg: np.ndarray | None = None          # panel forces of the averaging window in progress
        self.frames: dict = {}
        self.sigma_after: np.ndarray | None = None
        self.clock = (_time.perf_counter(), _time.process_time())
        self.before_resume = (0.0, 0.0)
        self.last_checkpoint = self.clock[0]
        self.mark = self.next_mark = 1
        self.resumed = resume is not None
        if resume is not None:
            self._restore(resume)

    # ------------------------------------------------------------------ driving
    def run(self, first: str = STAGES[0], last: str = STAGES[-1]) -> None:
        """The stages ``first`` to ``last``; a resumed run from its checkpoint's stage and step."""
        start = self.stage if self.resumed else STAGES.index(first)
        for k in range(start, STAGES.index(last) + 1):
            fresh = not (self.resumed and k == start)
            self.stage = k
            if fresh:
                self.done = 0
            getattr(self, "_" + STAGES[k])(fresh)

    def result(self) -> HeapRun:
        k = self.kept
        shape = Shape(k["H"], k["slope_deg"], k["surface_x"], k["surface_top"], k["heap_spheres"])
        return HeapRun(shape, k["porosity"], k["sigma_before"], self.sigma_after, self.hist,
                       centre_drop(self.sim) / shape.H, k["weight"], k["base_force_before"], self.frames,
                       k["spheres"], k["bodies"], self.sim.dt, self.log.stages, self.before_resume)

    def _begin(self, total: int) -> None:
        """The fraction marks of a stage of ``total`` steps, the next one after the steps done."""
        self.mark = max(1, int(self.every_fraction * total))
        self.next_mark = (self.done // self.mark + 1) * self.mark

    def _tick(self, final: bool = False) -> None:
        """A checkpoint when another fraction of the stage is done or ``every_s`` of wall
        time have passed since the last one (``final``: the run's end, none)."""
        if self.checkpoint is None or final:
            return
        if self.done >= self.next_mark or _time.perf_counter() - self.last_checkpoint > self.every_s:
            self.next_mark = (self.done // self.mark + 1) * self.mark
            self.checkpoint(self.state())
            self.last_checkpoint = _time.perf_counter()

    def _task(self, label: str, total: int):
        if self.progress is None:
            return None
        return self.progress.add_task(label, total=total, completed=self.done, status="")

    def _steps(self, until: int, task=None, *, tick: bool = True) -> None:
        """Advance the stage to ``until`` steps done, one engine call (``chunk_steps``) at
        a time; a checkpoint may follow each call but the last unless ``tick``
        (the caller decides something there first and then ticks itself)."""
        while self.done < until:
            k = min(chunk_steps(self.sim), until - self.done)
            self.sim.step(k)
            self.done += k
            if task is not None:
                self.progress.update(task, advance=k, status=f"t = {self.sim.time:.2f} s")
            if tick or self.done < until:
                self._tick()

    def _average(self) -> np.ndarray:
        """The base stress averaged over ``average_steps`` (the window ``self.avg``)."""
        total = self.case.average_steps
        self._begin(total)
        while self.done < total:
            k = min(chunk_steps(self.sim), total - self.done)
            self.avg[self.done:self.done + k] = self.sim.step(k, record_panels=True)[0]
            self.done += k
            self._tick(final=self.stage == len(STAGES) - 1 and self.done >= total)
        return base_stress(self.sim, self.avg)

    def _walls(self) -> list:
        """The walls of the current stage's simulation."""
        case, name = self.case, STAGES[self.stage]
        if name in ("fall", "settle"):
            return walls(case, ends=True)
        if name == "subsidence":
            H, t0 = self.kept["H"], self.kept["t0"]
            return walls(case, motions=(subsidence_motion(case, -1, H, t0), subsidence_motion(case, +1, H, t0)))
        return walls(case)

    # ------------------------------------------------------------------ stages
    def _fall(self, fresh: bool) -> None:
        case = self.case
        if fresh:
            spec, top = loose_cloud(case, np.random.default_rng(case.seed))
            dt = time_step(case)
            self.sim = dem3d.Simulation(spec, contact(case, 0.0), dt=dt, walls=walls(case, ends=True),
                                        periodic=dem3d.Periodic(1, 0.0, case.width))
            self.sim.gravity = np.array([0.0, 0.0, -2.0 * G])
            self.kept["fall_steps"] = int(1.2 * math.sqrt(top / G) / dt)
        total = self.kept["fall_steps"]
        self._begin(total)
        self._steps(total, self._task("raining", total))

    def _settle(self, fresh: bool) -> None:
        """dem3d.settle's loop (ratio checked every 500 steps, at most 1 s), resumable."""
        case = self.case
        if fresh:
            self.sim.gravity = np.array([0.0, 0.0, -G])
            self.sim.set_params(contact(case, case.local_damping))
            self.kept["ratio"] = math.inf
        most, every = int(1.0 / self.sim.dt), 500
        self._begin(most)
        while self.done < most and not self.kept["ratio"] < case.settle_ratio:
            self._steps(min(most, (self.done // every + 1) * every), tick=False)
            self.kept["ratio"] = measure.unbalanced_force_ratio(self.sim)
            self._tick()
        self.log.stage("rain", self.kept["fall_steps"] + self.done, ratio=self.kept["ratio"])
        self.kept["spheres"] = self.sim.n_spheres
        self.kept["bodies"] = int(len(np.unique(self.sim.spheres.body_id)))
        if self.on_frame is not None:
            self.on_frame(dem3d.frame(self.sim), None)

    def _slump(self, fresh: bool) -> None:
        case = self.case
        if fresh:
            self.sim = rebuilt(case, self.sim)
            self.sim.set_params(contact(case, 0.0))
        total = int(case.slump_time / self.sim.dt)
        every = max(1, int(0.25 / self.sim.dt))            # a frame every 0.25 s of the flow
        task = self._task("slumping", total)
        self._begin(total)
        while self.done < total:
            self._steps(min(total, (self.done // every + 1) * every), task, tick=False)
            if self.on_frame is not None:
                self.on_frame(dem3d.frame(self.sim), None)
            self._tick()
        self.log.stage("slump", total)

    def _arrest(self, fresh: bool) -> None:
        case = self.case
        if fresh:
            sim = self.sim
            self.sim = rebuilt(case, sim, on_base(case, sim.spheres.x, sim.spheres.r) & (sim.spheres.x[:, 2] > 0.0))
            self.kept["speed"] = math.inf
        most, every = int(case.arrest_time / self.sim.dt), 500
        self._begin(most)
        # the test of the loop at every 500 steps (a resume inside 500 steps goes on to its end)
        while self.done % every or (self.done < most and self.kept["speed"] > case.rest_speed):
            self._steps((self.done // every + 1) * every, tick=False)
            self.kept["speed"] = heap_speed(case, self.sim)
            self._tick()
        self.log.stage("arrest", self.done, rms_speed=self.kept["speed"])

    def _before(self, fresh: bool) -> None:
        case = self.case
        if fresh:
            shape = heap_shape(case, self.sim)
            self.kept |= {"H": shape.H, "slope_deg": shape.slope_deg, "surface_x": shape.x,
                          "surface_top": shape.top, "heap_spheres": shape.spheres,
                          "porosity": heap_porosity(case, self.sim, shape.H)}
            self.avg = np.zeros((case.average_steps, self.sim.walls.n_panels, 3))
        sigma = self._average()
        self.avg = None
        areas = self.sim.walls.areas()[base_ids(self.sim)]
        self.kept |= {"sigma_before": sigma, "weight": heap_weight(case, self.sim),
                      "base_force_before": float(np.sum(sigma * areas))}
        self.log.stage("before", case.average_steps)
        self.frames["before"] = dem3d.frame(self.sim)
        if self.on_frame is not None:
            self.on_frame(self.frames["before"], 0.0)

    def _subsidence(self, fresh: bool) -> None:
        case, H = self.case, self.kept["H"]
        if fresh:
            self.kept["t0"] = self.sim.time
            self.sim = dem3d.Simulation.from_arrays(self.sim.to_arrays(), walls=self._walls())
            self.sim.walls.reset_pivots()          # the stored pivots are those of the fixed base
            self.kept["since"] = 0
            self.hist = Subsidence()
        sim, hist = self.sim, self.hist
        n_total = int(math.ceil(subsidence_duration(case, H) / sim.dt))
        task = self._task("subsidence", n_total)
        self._begin(n_total)
        while self.done < n_total:
            m = min(self.record_every, n_total - self.done)
            hist_f = advance(sim, m, record_panels=True)
            self.done += m
            self.kept["since"] += m
            sigma = base_stress(sim, hist_f)
            c, p, _ = centre_over_peak(sigma)
            hist.disp_over_H.append(centre_drop(sim) / H)
            hist.step.append(sim.step_count)
            hist.time.append(sim.time)
            hist.centre.append(c)
            hist.peak.append(p)
            hist.sigma.append(sigma)
            if self.on_frame is not None and (self.kept["since"] >= self.frame_every or self.done >= n_total):
                self.kept["since"] = 0
                self.on_frame(dem3d.frame(sim), hist.disp_over_H[-1])
            if task is not None:
                self.progress.update(task, advance=m, status=f"Delta/H {hist.disp_over_H[-1]:.4f}  "
                                                             f"centre/peak {c / p:.2f}")
            self._tick()
        self.log.stage("subsidence", n_total)

    def _hold(self, fresh: bool) -> None:
        if fresh:                                  # the base stops
            self.sim = dem3d.Simulation.from_arrays(self.sim.to_arrays(), walls=walls(self.case))
        n = int(self.case.hold_time / self.sim.dt)
        self._begin(n)
        self._steps(n)
        self.log.stage("hold", n)

    def _after(self, fresh: bool) -> None:
        if fresh:
            self.avg = np.zeros((self.case.average_steps, self.sim.walls.n_panels, 3))
        self.sigma_after = self._average()
        self.avg = None
        self.log.stage("after", self.case.average_steps)
        self.frames["after"] = dem3d.frame(self.sim)
        if self.on_frame is not None:
            self.on_frame(self.frames["after"], centre_drop(self.sim) / self.kept["H"])

    # ------------------------------------------------------------------ checkpoint
    def state(self) -> dict:
        """Everything the remaining stages need, as a dict of numpy arrays."""
        wall, cpu = _time.perf_counter(), _time.process_time()
        out = {f"sim/{k}": v for k, v in self.sim.to_arrays().items()}
        out |= {"heap/key": np.array(self.key), "heap/stage": np.array(self.stage), "heap/done": np.array(self.done),
                "heap/log": np.array(json.dumps(self.log.stages)),
                "heap/stage_s": np.array([wall - self.log.tic, cpu - self.log.cpu]),
                "heap/seconds": np.array([self.before_resume[0] + wall - self.clock[0],
                                          self.before_resume[1] + cpu - self.clock[1]])}
        out |= {f"kept/{k}": np.array(v, copy=True) for k, v in self.kept.items()}
        h = self.hist
        out |= {"sub/disp_over_H": np.array(h.disp_over_H, float), "sub/step": np.array(h.step, np.int64),
                "sub/time": np.array(h.time, float), "sub/centre": np.array(h.centre, float),
                "sub/peak": np.array(h.peak, float),
                "sub/sigma": np.array(h.sigma, float).reshape(len(h.sigma), self.case.bins)}
        if self.avg is not None:
            out["avg/force"] = self.avg[:self.done].copy()
        for name, fr in self.frames.items():
            out |= {f"frame/{name}/{f}": np.array(v, copy=True) for f, v in fr._asdict().items() if v is not None}
        return out

    def _restore(self, state: dict) -> None:
        if str(state.get("heap/key", "")) != self.key:
            raise InvalidParameter("resume", "a checkpoint of another run", "a checkpoint of this case",
                                   "a resumed run keeps the settings it started with")
        self.stage, self.done = int(state["heap/stage"]), int(state["heap/done"])
        # 0-d arrays back to the Python numbers they were (float64 and int64 exactly)
        self.kept = {k: (v.item() if v.ndim == 0 else np.array(v, copy=True))
                     for k, v in _prefixed(state, "kept/").items()}
        self.sim = dem3d.Simulation.from_arrays(_prefixed(state, "sim/"), walls=self._walls())
        self.log.stages = json.loads(str(state["heap/log"]))
        wall, cpu = (float(t) for t in state["heap/stage_s"])
        self.log.tic, self.log.cpu = _time.perf_counter() - wall, _time.process_time() - cpu
        self.before_resume = tuple(float(t) for t in state["heap/seconds"])
        self.hist = Subsidence(state["sub/disp_over_H"].tolist(), state["sub/step"].tolist(),
                               state["sub/time"].tolist(), state["sub/centre"].tolist(),
                               state["sub/peak"].tolist(), [np.array(r, copy=True) for r in state["sub/sigma"]])
        if "avg/force" in state:
            self.avg = np.zeros((self.case.average_steps, self.sim.walls.n_panels, 3))
            self.avg[:self.done] = state["avg/force"]
        names = sorted({k.split("/")[1] for k in state if k.startswith("frame/")})
        for name in names:
            f = _prefixed(state, f"frame/{name}/")
            self.frames[name] = dem3d.Frame(**{k: (int(v) if k == "step" else float(v) if k == "time"
                                                   else np.array(v, copy=True)) for k, v in f.items()})
