"""Nadukuru & Michalowski (2012), Fig. 1: a prismatic heap whose base subsides at the
centre. The case builder over dem3d (the engine is used as it is).

Paper (section "Arching", Fig. 1; ../shared/seeds/nadukuru-michalowski-2012-arching.txt):
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
import time as _time
from dataclasses import dataclass, field

import numpy as np

import dem3d
from analytic.errors import InvalidParameter
from analytic.inputs import require_number
from dem3d import measure
from studies.progress import step_with_progress

G = 9.81
#: clump volume over one sphere's for two equal spheres overlapping by one radius
_CLUMP_VOLUME_FACTOR = 2.0 - (5.0 / 12.0) / (4.0 / 3.0)
_CATCH_DEPTH = 1.2        # m below the base: the spill pile stays clear of the base
_GENERATION_FRACTIONS = (0.25, 0.2, 0.15)


@dataclass(frozen=True)
class HeapCase:
    """Everything a heap run needs. Lengths in m, stiffness N/m, density kg/m^3, speed m/s.

    particles:        spheres incl. clump members (12,000; 15,000 if the paper counted bodies)
    clump_fraction:   fraction of bodies that are two-sphere clumps (paper 0.25)
    clump_overlap:    overlap of a clump's two spheres in radii (paper 1)
    d_min, d_max:     sphere diameters, uniform (paper radii 2.3-3.7 cm; module docstring)
    kn, ks:           linear contact stiffness [N/m] (assumed: the wall study's)
    particle_friction: grain friction (paper 0.65)
    base_friction:    friction of the base halves (assumed 0.65)
    density:          grain density [kg/m^3] (assumed: the wall study's 2650)
    damping_ratio:    viscous normal damping, fraction of critical (assumed 0.2, as the wall study)
    local_damping:    PFC local damping while raining settles and after the flow (PFC's 0.7)
    target_porosity:  porosity used to size the generation box and fill height
    hold_time:        time [s] the subsided base is held before the stresses are read
    base_length, width: the base L x w (paper 4.8 x 0.6); w is the periodic length
    bins:             base panels (stress bins), an even number, half on each half of the base
    subsidence_over_H: Delta/H at the centre (paper 0.0067)
    subsidence_speed: speed of the inner edges [m/s] once ramped up over ``ramp``
    ramp:             time [s] over which the subsidence speed ramps up from 0
    slump_time:       time [s] the fill flows without local damping once the end walls go
    settle_ratio:     unbalanced-force ratio that ends raining
    rest_speed:       rms speed [m/s] of the heap's grains at which it counts as at rest
    arrest_time:      the longest [s] the arrest (local damping on) may take
    average_steps:    steps over which the base stresses are averaged (before / after)
    """

    particles: int = 12_000
    clump_fraction: float = 0.25
    clump_overlap: float = 1.0
    d_min: float = 0.046
    d_max: float = 0.0736
    kn: float = 8.3e6
    ks: float = 3.32e6
    particle_friction: float = 0.65
    base_friction: float = 0.65
    density: float = 2650.0
    damping_ratio: float = 0.2
    local_damping: float = 0.7
    base_length: float = 4.8
    width: float = 0.6
    bins: int = 24
    target_porosity: float = 0.38
    subsidence_over_H: float = 0.0067
    subsidence_speed: float = 0.02
    ramp: float = 0.05
    settle_ratio: float = 5e-3
    slump_time: float = 2.5
    arrest_time: float = 1.0
    rest_speed: float = 2e-3
    hold_time: float = 0.1
    average_steps: int = 2000
    seed: int = 1

    def __post_init__(self):
        require_number("particles", self.particles, 50, None, lo_open=False)
        require_number("clump_fraction", self.clump_fraction, 0, 1, lo_open=False, hi_open=False)
        for name in ("kn", "ks", "density", "d_min", "base_length", "width", "subsidence_speed", "settle_ratio",
                     "slump_time", "hold_time", "arrest_time", "rest_speed"):
            require_number(name, getattr(self, name), 0, None)
        for name in ("particle_friction", "base_friction", "ramp"):
            require_number(name, getattr(self, name), 0, None, lo_open=False)
        require_number("damping_ratio", self.damping_ratio, 0, 1, lo_open=False)
        require_number("local_damping", self.local_damping, 0, 1, lo_open=False, hi_open=True)
        require_number("target_porosity", self.target_porosity, 0.2, 0.7)
        require_number("subsidence_over_H", self.subsidence_over_H, 0, 0.1)
        if not self.d_min <= self.d_max:
            raise InvalidParameter("d_min, d_max", f"{self.d_min:g}, {self.d_max:g}", "d_min <= d_max [m]")
        if not (isinstance(self.bins, int) and self.bins >= 4 and self.bins % 2 == 0):
            raise InvalidParameter("bins", self.bins, "an even whole number >= 4")
        if not (isinstance(self.average_steps, int) and self.average_steps >= 1):
            raise InvalidParameter("average_steps", self.average_steps, "a whole number >= 1")
        if self.width < 3.4 * self.d_max:
            raise InvalidParameter("width", self.width, f">= {3.4 * self.d_max:.3f} m",
                                   "the periodic length must hold 3 neighbour cells (3.4 d_max)")

    @property
    def bodies(self) -> int:
        return int(round(self.particles / (1.0 + self.clump_fraction)))


# ----------------------------------------------------------------------------- walls
def contact(case: HeapCase, local: float) -> dem3d.ContactParams:
    return dem3d.linear(case.kn, case.ks, case.particle_friction, zeta_n=case.damping_ratio, zeta_s=0.0,
                        local_damping=local)


def time_step(case: HeapCase) -> float:
    """0.2 x sqrt(m_min / k) of the lightest sphere [s] (the wall study's rule)."""
    m_min = case.density * math.pi / 6.0 * case.d_min ** 3
    return 0.2 * math.sqrt(m_min / max(case.kn, case.ks))


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


def fill_height(case: HeapCase) -> float:
    """Depth [m] of the rained fill at ``target_porosity``: the bodies' solid volume over
    the base area (uniform diameters: mean d^3 = (b^4 - a^4) / (4 (b - a)))."""
    a, b = case.d_min, case.d_max
    mean_d3 = (b**4 - a**4) / (4.0 * (b - a)) if b > a else a**3
    v_body = math.pi / 6.0 * mean_d3 * (1.0 + case.clump_fraction * (_CLUMP_VOLUME_FACTOR - 1.0))
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
    """Stage 1: the cloud falls into the box (end walls in place) at 2 g without local
    damping (it would slow the fall), then settles at g with local damping."""
    spec, top = loose_cloud(case, np.random.default_rng(case.seed))
    dt = time_step(case)
    sim = dem3d.Simulation(spec, contact(case, 0.0), dt=dt, walls=walls(case, ends=True),
                           periodic=dem3d.Periodic(1, 0.0, case.width))
    sim.gravity = np.array([0.0, 0.0, -2.0 * G])
    steps = step_with_progress(sim, int(1.2 * math.sqrt(top / G) / dt), progress, "raining")
    sim.gravity = np.array([0.0, 0.0, -G])
    sim.set_params(contact(case, case.local_damping))
    res = dem3d.settle(sim, ratio=case.settle_ratio, check_every=500, max_steps=int(1.0 / dt))
    log.stage("rain", steps + res.steps, ratio=res.ratio)
    return sim


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
    """Stage 2: with the end walls gone the fill slumps off the base edges into a heap.
    The flow runs ``slump_time`` s without local damping (PFC's 0.7 makes a 0.7 m face
    creep for seconds: measured at 1,500 spheres); the grains that fell off the base are
    dropped (``rebuilt``) and the heap is brought to rest with local damping until its
    rms speed is below ``rest_speed`` (at most ``arrest_time``). Returns the heap."""
    sim = rebuilt(case, sim)
    sim.set_params(contact(case, 0.0))
    total, steps = int(case.slump_time / sim.dt), 0
    chunk = int(0.25 / sim.dt)            # a frame every 0.25 s of the flow
    task = progress.add_task("slumping", total=total, status="") if progress is not None else None
    while steps < total:
        done = step_with_progress(sim, min(chunk, total - steps))
        steps += done
        if task is not None:
            progress.update(task, advance=done, status=f"t = {sim.time:.2f} s")
        if on_frame is not None:
            on_frame(dem3d.frame(sim), None)
    log.stage("slump", steps)
    sim = rebuilt(case, sim, on_base(case, sim.spheres.x, sim.spheres.r) & (sim.spheres.x[:, 2] > 0.0))
    steps, speed = 0, math.inf
    while steps < int(case.arrest_time / sim.dt) and speed > case.rest_speed:
        steps += step_with_progress(sim, 500)
        speed = heap_speed(case, sim)
    log.stage("arrest", steps, rms_speed=speed)
    return sim


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
    hist_f, _ = sim.step(steps, record_panels=True)
    return base_stress(sim, hist_f)


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


def subside(case: HeapCase, sim, H: float, log: StageLog, *, record_every: int = 200, on_frame=None,
            frame_every: int = 2000, progress=None):
    """Stage 3: both base halves turn about their outer edges until the centre is down by
    subsidence_over_H x H; returns (the simulation, now with fixed walls, and the
    Subsidence history). ``on_frame(frame, disp_over_H)`` is called every ``frame_every`` steps."""
    t0 = sim.time
    moving = walls(case, motions=(subsidence_motion(case, -1, H, t0), subsidence_motion(case, +1, H, t0)))
    sim = dem3d.Simulation.from_arrays(sim.to_arrays(), walls=moving)
    sim.walls.reset_pivots()          # the stored pivots are those of the fixed base
    n_total = int(math.ceil(subsidence_duration(case, H) / sim.dt))
    task = progress.add_task("subsidence", total=n_total, status="") if progress is not None else None
    hist, done, since = Subsidence(), 0, 0
    while done < n_total:
        m = min(record_every, n_total - done)
        hist_f, _ = sim.step(m, record_panels=True)
        done, since = done + m, since + m
        sigma = base_stress(sim, hist_f)
        c, p, _ = centre_over_peak(sigma)
        hist.disp_over_H.append(centre_drop(sim) / H)
        hist.step.append(sim.step_count)
        hist.time.append(sim.time)
        hist.centre.append(c)
        hist.peak.append(p)
        hist.sigma.append(sigma)
        if on_frame is not None and (since >= frame_every or done >= n_total):
            since = 0
            on_frame(dem3d.frame(sim), hist.disp_over_H[-1])
        if task is not None:
            progress.update(task, advance=m, status=f"Delta/H {hist.disp_over_H[-1]:.4f}  centre/peak {c / p:.2f}")
    log.stage("subsidence", n_total)
    fixed = dem3d.Simulation.from_arrays(sim.to_arrays(), walls=walls(case))    # the base stops
    steps = step_with_progress(fixed, int(case.hold_time / fixed.dt))
    log.stage("hold", steps)
    return fixed, hist


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


def run_heap(case: HeapCase, *, on_frame=None, progress=None) -> HeapRun:
    """Rain, slump, measure the base before, subside, measure after (module docstring).
    ``on_frame(frame, Delta/H or None)`` gets the rained fill, the heap, frames along the
    subsidence and the end state."""
    log = StageLog()
    sim = rain(case, log, progress)
    spheres, bodies = sim.n_spheres, int(len(np.unique(sim.spheres.body_id)))
    if on_frame is not None:
        on_frame(dem3d.frame(sim), None)
    sim = slump(case, sim, log, progress, on_frame)
    shape = heap_shape(case, sim)
    porosity = heap_porosity(case, sim, shape.H)
    sigma_before = averaged_base_stress(sim, case.average_steps)
    weight = heap_weight(case, sim)
    areas = sim.walls.areas()[base_ids(sim)]
    log.stage("before", case.average_steps)
    frames = {"before": dem3d.frame(sim)}
    if on_frame is not None:
        on_frame(frames["before"], 0.0)
    sim, hist = subside(case, sim, shape.H, log, progress=progress,
                        on_frame=on_frame)
    sigma_after = averaged_base_stress(sim, case.average_steps)
    log.stage("after", case.average_steps)
    frames["after"] = dem3d.frame(sim)
    if on_frame is not None:
        on_frame(frames["after"], centre_drop(sim) / shape.H)
    return HeapRun(shape, porosity, sigma_before, sigma_after, hist, centre_drop(sim) / shape.H, weight,
                   float(np.sum(sigma_before * areas)), frames, spheres, bodies, sim.dt, log.stages)
