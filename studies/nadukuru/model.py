"""Nadukuru & Michalowski (2012): a 3.1 m wall of 6 segments, rained backfill of spheres
and two-sphere clumps, four modes of wall movement. The case builder over dem3d.

Stages (each a function; the CLI strings them together):

1. ``prepare_specimen``: generate bodies loosely above the box, rain them under gravity
   (optionally with a lower "deposition" friction, a standard way to densify), trim to
   the wall height, restore the particle friction, settle; report porosity, at-rest K,
   the resultant's height and the wall load. The settled state is cached so all modes
   start from it.
2. ``move_wall``: translate or rotate the wall quasi-statically to Delta/H; yields the
   load history (K, resultant_height_over_H, segment stresses) and frames for the recording.
3. ``theory_rows``: Coulomb, Rankine, DSM for the mode, the paper's DEM, Fang & Ishibashi.

Geometry: wall face at x = 0 (normal +x, backfill at x > 0), floor z = 0, far wall at
x = L, periodic along y (width w) or, with ``WallSetup.side_friction`` set, between two
side walls at y = 0 and y = w (the paper's "box with smooth side walls"). Wall movement is away from the backfill (-x).
K follows eq. 6: K = F_n / (0.5 rho (1 - n) g H^2 w), F_n the normal force on the wall,
n the measured porosity of the specimen (the paper used n = 0.36).
"""

from __future__ import annotations

import dataclasses
import json
import math
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace
from typing import Iterator, Literal

import numpy as np

import dem3d
from analytic.errors import InvalidParameter
from analytic.inputs import MAX_HEIGHT_M
from analytic.schema import check_fields, param, seed_param
from dem3d import measure

from analytic.constants import G

from ..config import with_current_names
from ..granular import CLUMP_VOLUME_FACTOR, MOST_PARTICLE_STEPS, SpecimenRecipe, contact_law, time_step
from ..measures import steady_displacement
from ..report import theory_row
from ..store import Store, atomic_write, content_key, load_npz, npz_bytes
from ..progress import step_with_progress

MODES = ("T", "RB", "RT", "mixed")
MODE_TITLES = {"T": "translation", "RB": "rotation about the base", "RT": "rotation about the top",
               "mixed": "rotation about a point H/2 above the top"}


@dataclass(frozen=True)
class WallSetup:
    """The wall and the box behind it (the paper's 3.1 m wall of 6 segments)."""

    # the particle count, not the box, sets memory and time (grain_scale sizes the grains to
    # fill the box; NadukuruCase refuses a box the count cannot fill with grains of H / 10);
    # above 100 m the theories beside the DEM refuse the wall (analytic.inputs.MAX_HEIGHT_M);
    # the box's other sides as far
    height: float = param(3.1, unit="m", lo=0, hi=MAX_HEIGHT_M, lo_open=True, meaning="wall height H (paper 3.1)")
    width: float = param(0.5, unit="m", lo=0, hi=100, lo_open=True,
                         meaning="width w of the backfill slab along the wall (0.5; a reduced run widens it to "
                                 "3.4 grain diameters)")
    # one wall panel each, read every step: 100 add nothing measurable
    segments: int = param(6, lo=1, hi=100, meaning="equal wall segments whose stresses are read, bottom to top "
                                                   "(paper 6)")
    friction: float = param(0.35, lo=0, meaning="wall friction coefficient: 0.35 rough or 0 smooth (paper)")
    backfill_length: float = param(3.3, unit="m", lo=0, hi=100, lo_open=True,
                                   meaning="backfill length L from the wall to the far wall (3.3)")
    side_friction: float | None = param(
        None, lo=0, meaning="none: periodic along the width; a number: two side walls at y = 0 and y = w with this "
                            "friction (0 = the paper's smooth side walls)")

    def __post_init__(self):
        check_fields(self)


@dataclass(frozen=True)
class Movement:
    """How the wall moves away from the backfill (quasi-statically, to Delta/H)."""

    mode: Literal["T", "RB", "RT", "mixed"] = param(
        "T", unit="", meaning="how the wall moves: T translation, RB rotation about the base, RT about the top, "
                              "mixed about a point H/2 above the top")
    wall_disp_over_H: float = param(0.008, lo=0, hi=0.1, lo_open=True, hi_open=True,
                                    meaning="Delta/H at the end, Delta at the edge opposite the pivot (paper 0.008)")
    # the run's length (NadukuruCase, MOST_PARTICLE_STEPS) bounds a slow movement
    speed: float = param(0.02, unit="m/s", lo=0, hi=1.0, lo_open=True, hi_open=True,
                         meaning="speed of the edge opposite the pivot once ramped up (0.02)")
    # 10 s: 4e5 steps of the paper-scale 2.6e-5 s, ~1 h at 30,000 spheres
    ramp: float = param(0.05, unit="s", lo=0, hi=10, meaning="time over which the speed ramps up from 0 (0.05)")
    # a sample's panel history is held in memory: 1e5 steps x (segments + 4) panels x 48 B,
    # 500 MB at 100 segments
    record_every: int = param(50, lo=1, hi=100_000, meaning="time steps averaged into one load sample (50)")
    # the paper does not say; PFC3D's default, 0.7, acts in every cycle unless the user
    # turns it off (`--set movement.local_damping=0.7` to run that way)
    local_damping: float = param(0.0, lo=0, hi=1, hi_open=True,
                                 meaning="PFC local damping while the wall moves (0: viscous contact damping only)")

    def __post_init__(self):
        check_fields(self)


@dataclass(frozen=True)
class NadukuruCase:
    """One wall-movement run: the backfill recipe, the wall and box, the movement, the seed."""

    specimen: SpecimenRecipe = field(default_factory=SpecimenRecipe)
    wall: WallSetup = field(default_factory=WallSetup)
    movement: Movement = field(default_factory=Movement)
    seed: int = seed_param(1)

    def __post_init__(self):
        check_fields(self)
        rec = self.specimen
        if rec.dt is not None:
            safe = time_step(dataclasses.replace(rec, dt=None), grain_scale(rec, self.wall)[0])
            if rec.dt > safe * (1 + 1e-9):
                raise InvalidParameter("dt", rec.dt, f"(0, {safe:.4g}] s", "0.2 x the critical step of the "
                                       "lightest grain at these particles; the default takes it")
        least = fewest_particles(self.specimen, self.wall)
        if self.specimen.particles < least:
            raise InvalidParameter("particles", self.specimen.particles, f">= {least} for this wall",
                                   f"fewer would need grains over H/{_GRAINS_PER_HEIGHT:g} to fill the box")
        preparation, movement, dt = self.most_steps()
        work = rec.particles * (preparation + movement)
        if work > MOST_PARTICLE_STEPS:
            raise InvalidParameter("particles x time steps", work, f"<= {MOST_PARTICLE_STEPS:g}",
                                   f"up to {preparation:.3g} steps to prepare and {movement:.3g} to move the wall, "
                                   f"of {dt:.3g} s: ~{work / 4e6 / 86400:.3g} days on 2 cores")

    def most_steps(self) -> tuple[float, float, float]:
        """(time steps of the preparation at most, of the movement, the time step [s]):
        ``prepare_specimen``'s stages at their caps (fall from the tallest cloud, pack,
        stiffen, friction on, load to g, at rest) and ``move_wall``'s."""
        rec, wall = self.specimen, self.wall
        dt = time_step(rec, grain_scale(rec, wall)[0])
        dt_soft = dt * math.sqrt(rec.deposition_softening)
        top = (1.0 - rec.target_porosity) * wall.height * _OVERFILL / _GENERATION_FRACTIONS[-1]
        fall = 1.2 * math.sqrt(2.0 * top / (G * rec.deposition_gravity)) / dt_soft + 1.0 / dt_soft
        settle = (1.0 + 2.0 + 2.0) / dt + 2000 + 5000 + 2000
        return fall + settle, _movement_duration(self.movement, wall.height) / dt, dt


#: the coarsest grains a reduced specimen may use: d_max x grain scale <= H / this
_GRAINS_PER_HEIGHT = 10.0


def fewest_particles(rec: SpecimenRecipe, wall: WallSetup) -> int:
    """The smallest particle count whose scaled grains stay at most H / 10 across (the
    grains grow as the count falls, ``grain_scale``): 878 for the paper's wall."""
    def too_coarse(n: int) -> bool:
        scale, _ = grain_scale(dataclasses.replace(rec, particles=n), wall)
        return scale * rec.d_max > wall.height / _GRAINS_PER_HEIGHT

    lo, hi = 1, max(rec.particles, 2)
    while too_coarse(hi):
        lo, hi = hi, hi * 2
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if too_coarse(mid) else (lo, mid)
    return hi


def rough_or_smooth(wall: str) -> float:
    if wall == "rough":
        return 0.35
    if wall == "smooth":
        return 0.0
    raise InvalidParameter("wall", wall, "rough | smooth")


# ----------------------------------------------------------------------------- geometry
def grain_scale(rec: SpecimenRecipe, wall: WallSetup) -> tuple[float, float]:
    """(factor on the paper's diameters, periodic width [m]) so that the bodies fill
    L x w x H at the target porosity (factor ~1.0 at 30,000 particles). With few
    particles the grains grow; once the width would hold fewer than ~3 cells of the
    neighbour grid (3.4 d_max, the engine's minimum periodic length) the width grows
    instead and the grains less, so a reduced run keeps the wall height and backfill length."""
    n_bodies = rec.particles / (1.0 + rec.clump_fraction)
    a, b = rec.d_min, rec.d_max
    mean_d3 = (b**4 - a**4) / (4.0 * (b - a)) if b > a else a**3
    v_body = math.pi / 6.0 * mean_d3 * (1.0 + rec.clump_fraction * (CLUMP_VOLUME_FACTOR - 1.0))
    solid_per_width = (1.0 - rec.target_porosity) * wall.backfill_length * wall.height * _OVERFILL
    s = (solid_per_width * wall.width / (n_bodies * v_body)) ** (1.0 / 3.0)
    min_width = _MIN_CELLS * b
    if min_width * s <= wall.width:
        return s, wall.width
    # width = min_width * s  ->  solid_per_width * min_width * s = n v s^3
    s = math.sqrt(solid_per_width * min_width / (n_bodies * v_body))
    return s, min_width * s


_OVERFILL = 1.04     # fill 4 % above H, trimmed to H after deposition
_MIN_CELLS = 3.4     # periodic length >= 3 (2 r_max + skin): 3.4 d_max with skin 0.4 r_min


def _box_walls(wall: WallSetup, rec: SpecimenRecipe, motion=dem3d.FIXED) -> list:
    """The retaining wall (segmented, moving), the floor and the far wall (both fixed)."""
    L, w, H = wall.backfill_length, wall.width, wall.height
    face = dem3d.segmented_wall((0.0, 0.5 * w, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), w, H, wall.segments,
                                wall.friction, unbounded_width=True)
    floor = dem3d.plane((0.5 * L, 0.5 * w, 0.0), (0.0, 0.0, 1.0), rec.floor_friction, (0.5 * L, 0.5 * w))
    far = dem3d.plane((L, 0.5 * w, 0.5 * H), (-1.0, 0.0, 0.0), 0.0, (0.5 * w, 0.5 * H))
    box = [floor, far]
    if wall.side_friction is not None:
        box += [dem3d.plane((0.5 * L, 0.0, 0.5 * H), (0.0, 1.0, 0.0), wall.side_friction, (0.5 * L, 0.5 * H)),
                dem3d.plane((0.5 * L, w, 0.5 * H), (0.0, -1.0, 0.0), wall.side_friction, (0.5 * L, 0.5 * H))]
    return [dem3d.Wall("wall", face, motion), dem3d.Wall("box", box)]


def _guard_above_wall(wall: WallSetup, top: float) -> dem3d.Wall:
    """A fixed, frictionless panel from the wall top (z = H) up to ``top`` in the wall's
    plane, present only while the grains are rained from above H: without it grains
    pushed over the wall top fell in front of the wall (31 of 29,120 spheres at paper
    scale). Its bottom edge is 'shared' so it never touches grains below H; it is
    dropped with the grains above H (``_trim``)."""
    w, H = wall.width, wall.height
    half = 0.5 * (top - H)
    guard = dem3d.Panel((0.0, 0.5 * w, H + half), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (np.inf, half), 0.0,
                        shared=(False, False, True, False), nominal_half=(0.5 * w, half))
    return dem3d.Wall("guard", [guard])


# ----------------------------------------------------------------------------- specimen
@dataclass(frozen=True)
class Specimen:
    """A settled specimen and what it achieved."""

    state: dict                  # dem3d Simulation.to_arrays()
    porosity: float
    K_at_rest: float
    resultant_height_over_H_at_rest: float      # height of the resultant / H
    thrust_at_rest_kN: float          # total normal load on the wall [kN] (width w)
    stress_ratio: float          # sigma_h on the wall / sigma_v on the floor, same depth band
    n_spheres: int
    n_bodies: int
    grain_scale: float
    dt: float
    steps: int
    sim_time: float
    settle_ratio: float
    fill_height: float
    width: float                 # periodic width actually used [m]
    stages: dict = field(default_factory=dict)   # steps and wall time of each stage


#: bump when prepare_specimen changes, so cached specimens of the old procedure are not reused
PREPARATION_VERSION = 4


def specimen_key(case: NadukuruCase) -> str:
    """Hash of everything that shapes the settled specimen (not the movement)."""
    return content_key({"specimen": dataclasses.asdict(case.specimen),
                        # an unset optional field is left out, so adding one keeps older keys
                        "wall": {k: v for k, v in dataclasses.asdict(case.wall).items() if v is not None},
                        "seed": case.seed, "procedure": PREPARATION_VERSION})


def prepare_specimen(case: NadukuruCase, progress=None) -> Specimen:
    """Rain, trim to H and settle the backfill behind the fixed wall (module docstring).
    Stages A (rain and pack), B (trim and stiffen), C (load to g), then the at-rest
    measurement; each stage's steps, times and settle trace go to ``Specimen.stages``."""
    rec = case.specimen
    rng = np.random.default_rng(case.seed)
    s, w = grain_scale(rec, case.wall)
    wall = dataclasses.replace(case.wall, width=w)
    spec, gen_height = _loose_fill(rec, wall, s, rng)
    dt = time_step(rec, s)
    walls = _box_walls(wall, rec)
    log = _StageLog()
    sim, steps = _rain_and_pack(spec, rec, wall, walls, gen_height, s * rec.d_max, dt, progress, log)
    sim, more, res = _trim_and_stiffen(sim, rec, wall.height, walls, dt, log)
    steps += more
    if rec.rain_gravity != 1.0:
        more, res = _load_to_gravity(sim, rec, dt, log)
        steps += more
    return _measure_at_rest(sim, rec, wall, s, dt, steps, res.ratio, log.stages)


def _loose_fill(rec: SpecimenRecipe, wall: WallSetup, scale: float, rng) -> tuple[dem3d.Specimen, float]:
    """The bodies placed at random (the only draws from ``rng``) in L x w x gen_height,
    and gen_height [m]: tall enough for a solid fraction of 0.2, since random addition
    jams near 0.25-0.38. ``scale`` multiplies the recipe's diameters (``grain_scale``)."""
    L, H, w = wall.backfill_length, wall.height, wall.width
    n_bodies = int(round(rec.particles / (1.0 + rec.clump_fraction)))
    for fraction in _GENERATION_FRACTIONS:
        gen_height = (1.0 - rec.target_porosity) * H * _OVERFILL / fraction
        lo = np.array([0.0, 0.0, 0.0]) + 1e-3
        hi = np.array([L, w, gen_height]) - 1e-3
        try:
            spec = dem3d.random_specimen(rng, lo, hi, n_bodies, scale * rec.d_min, scale * rec.d_max,
                                         clump_fraction=rec.clump_fraction, clump_overlap=rec.clump_overlap,
                                         density=rec.density)
            return spec, gen_height
        except InvalidParameter:
            # coarse grains in a narrow box jam before 0.2 (800 and 1,000 particles did):
            # a taller, looser cloud, drawn on from the same generator
            continue
    raise InvalidParameter("particles", rec.particles, "a count whose grains fit the generation box",
                           f"random placement jammed even at a solid fraction of {_GENERATION_FRACTIONS[-1]}")


#: solid fractions of the loose cloud, tried in turn (0.2 first: every earlier specimen)
_GENERATION_FRACTIONS = (0.20, 0.15, 0.10)


class _StageLog:
    """Per preparation stage: steps, wall and CPU time [s] since the previous stage ended,
    and the settle trace (step, unbalanced-force ratio, kinetic energy at each check),
    kept in ``Specimen.stages`` to show where the preparation spends its time."""

    def __init__(self):
        self.stages: dict = {}
        self.trace: list = []       # filled by dem3d.settle(trace=...), emptied by each stage
        self.tic, self.cpu = _time.perf_counter(), _time.process_time()

    def stage(self, name: str, n: int) -> None:
        # cpu_s counts every thread: cpu_s / wall_s is the number of cores the stage used
        self.stages[name] = {"steps": int(n), "wall_s": round(_time.perf_counter() - self.tic, 1),
                             "cpu_s": round(_time.process_time() - self.cpu, 1),
                             "trace": [[int(k), float(f"{r:.4g}"), float(f"{e:.4g}")] for k, r, e in self.trace]}
        self.trace.clear()
        self.tic, self.cpu = _time.perf_counter(), _time.process_time()


def _rain_and_pack(spec, rec: SpecimenRecipe, wall: WallSetup, walls: list, gen_height: float, d_max: float,
                   dt: float, progress, log: _StageLog) -> tuple[dem3d.Simulation, int]:
    """Stage A, deposition: the bodies fall and pack behind the wall (with the guard above
    it) under ``deposition_gravity``, at the deposition friction, with springs softened by
    ``deposition_softening`` (a larger stable step: the frictionless packing does not
    depend on the stiffness) and viscous damping only while falling (local damping
    would slow the fall to 0.3 g). Returns the simulation and its steps."""
    soft = rec.deposition_softening
    dt_soft = dt * math.sqrt(soft)
    sim = dem3d.Simulation(spec, contact_law(rec, rec.deposition_friction, 0.0, soft), dt=dt_soft,
                           walls=walls + [_guard_above_wall(wall, gen_height + d_max)],
                           periodic=dem3d.Periodic(1, 0.0, wall.width) if wall.side_friction is None else None)
    g_dep = G * rec.deposition_gravity
    sim.gravity = np.array([0.0, 0.0, -g_dep])
    steps = step_with_progress(sim, int(1.2 * math.sqrt(2.0 * gen_height / g_dep) / dt_soft), progress, "raining")
    log.stage("fall", steps)
    sim.set_params(contact_law(rec, rec.deposition_friction, rec.local_damping, soft))
    res = dem3d.settle(sim, ratio=5 * rec.settle_ratio, check_every=500, max_steps=int(1.0 / dt_soft),
                       trace=log.trace)
    steps += res.steps
    log.stage("pack", res.steps)
    return sim, steps


def _trim_and_stiffen(sim, rec: SpecimenRecipe, H: float, walls: list, dt: float, log: _StageLog):
    """Stage B: unload to the lock-in gravity ``rain_gravity`` (overlaps shrink), trim to
    H [m] (drops the guard), settle at the paper's stiffness with the deposition friction,
    then with the particle friction. Returns (the new simulation, its steps counted
    here, the last settle result)."""
    g_low = G * rec.rain_gravity
    sim.gravity = np.array([0.0, 0.0, -g_low])
    steps = step_with_progress(sim, 2000, None, "")
    log.stages["in_front_of_wall"] = int(np.sum(sim.spheres.x[:, 0] < 0.0))   # removed by the trim; 0 with the guard
    sim = _trim(sim, H, walls, rec, dt)      # paper stiffness, still the deposition friction
    sim.gravity = np.array([0.0, 0.0, -g_low])
    res = dem3d.settle(sim, ratio=rec.settle_ratio, check_every=500, max_steps=int(1.0 / dt), trace=log.trace)
    steps += res.steps
    log.stage("stiffen", res.steps)
    sim.set_params(contact_law(rec, rec.particle_friction, rec.local_damping))
    res = dem3d.settle(sim, ratio=rec.settle_ratio, check_every=500, max_steps=int(2.0 / dt), trace=log.trace)
    steps += res.steps
    log.stage("friction on", res.steps)
    return sim, steps, res


def _load_to_gravity(sim, rec: SpecimenRecipe, dt: float, log: _StageLog):
    """Stage C: raise gravity from ``rain_gravity`` to g in 10 steps of 500 time steps
    with the friction on, a 1D compression of the whole fill that sets the at-rest K;
    then settle. Returns (steps, the settle result)."""
    g_low = G * rec.rain_gravity
    steps = 0
    for k in range(1, 11):
        sim.gravity = np.array([0.0, 0.0, -(g_low + (G - g_low) * k / 10)])
        steps += step_with_progress(sim, 500, None, "")
    res = dem3d.settle(sim, ratio=rec.settle_ratio, check_every=500, max_steps=int(2.0 / dt), trace=log.trace)
    steps += res.steps
    log.stage("load to g", res.steps + 5000)
    return steps, res


def _measure_at_rest(sim, rec: SpecimenRecipe, wall: WallSetup, scale: float, dt: float, steps: int,
                     settle_ratio: float, stages: dict) -> Specimen:
    """The settled specimen with its at-rest figures, measured after 2000 steps with local
    damping off (the wall sees the true static state): porosity of the middle 80 % of the
    box, K0 by eq. 6, resultant height / H, wall load [kN], stress ratio."""
    L, H, w = wall.backfill_length, wall.height, wall.width
    sim.set_params(contact_law(rec, rec.particle_friction, 0.0))
    steps += step_with_progress(sim, 2000, None, "")
    f = dem3d.frame(sim)
    n = measure.porosity(sim, (0.1 * L, 0.0, 0.1 * H), (0.9 * L, w, 0.9 * H))
    load = wall_load(f, sim.walls.panel_ids("wall"), H)
    gamma = rec.density * (1.0 - n) * G
    K0 = load.normal / (0.5 * gamma * H**2 * w)
    ratio = _stress_ratio(sim, f, H, w, L)
    return Specimen(state=sim.to_arrays(), porosity=n, K_at_rest=K0, resultant_height_over_H_at_rest=load.height / H,
                    thrust_at_rest_kN=load.normal / 1e3, stress_ratio=ratio, n_spheres=sim.n_spheres,
                    n_bodies=int(len(np.unique(f.body_id))), grain_scale=scale, dt=dt, steps=steps,
                    sim_time=sim.time, settle_ratio=settle_ratio, fill_height=_fill_height(sim), width=w,
                    stages=stages)


def _fill_height(sim) -> float:
    x, r = sim.spheres.x, sim.spheres.r
    return float(np.percentile(x[:, 2] + r, 99.5))


def _trim(sim, H: float, walls, rec: SpecimenRecipe, dt: float):
    """A new Simulation (paper stiffness, deposition friction, local damping) with
    ``walls`` (no guard) and without the bodies that have any sphere centre above H or in
    front of the wall (contact history restarts; the caller settles again)."""
    sph = sim.spheres
    above = (sph.x[:, 2] > H) | (sph.x[:, 0] < 0.0)     # and any grain that got in front of the wall
    body = sph.body_id
    drop = np.isin(body, np.unique(body[above]))
    keep = ~drop
    labels = np.where(sph.clump >= 0, sph.clump, -1)[keep]
    # clump labels must be contiguous ids per clump; re-number them
    _, relabel = np.unique(labels[labels >= 0], return_inverse=True)
    new_labels = labels.copy()
    new_labels[labels >= 0] = relabel
    spec = dem3d.Specimen(sph.x[keep].copy(), sph.r[keep].copy(), new_labels, rec.density, sph.v[keep].copy())
    return dem3d.Simulation(spec, contact_law(rec, rec.deposition_friction, rec.local_damping), dt=dt, walls=walls,
                            periodic=sim.periodic)


def _stress_ratio(sim, f, H: float, w: float, L: float) -> float:
    """sigma_h on the wall over the weight-based vertical stress, over the middle third of
    the wall: sigma_v(z) = rho (1 - n) g (H - z) estimated from the actual mass above."""
    ids = sim.walls.panel_ids("wall")
    sig = measure.panel_normal_stress(f)[ids]
    zc = f.panel_corners[ids].mean(axis=1)[:, 2]
    mid = (zc > H / 3) & (zc < 2 * H / 3)
    mass = float(np.sum(sim.sphere_masses()))   # overlap of clump members ignored here
    # mean vertical stress at depth d from the weight above it (no wall friction): rho_b g d
    rho_b = _bulk_density(sim, H, w, L)
    sv = rho_b * G * (H - zc[mid])
    return float(np.mean(sig[mid] / sv)) if mid.any() and mass > 0 else float("nan")


def _bulk_density(sim, H, w, L) -> float:
    n = measure.porosity(sim, (0.1 * L, 0.0, 0.1 * H), (0.9 * L, w, 0.9 * H), cells_per_radius=4)
    return sim.density * (1.0 - n)


# ----------------------------------------------------------------------------- wall load
@dataclass(frozen=True)
class WallLoad:
    normal: float          # normal force on the wall [N] (compression +)
    height: float          # height of its line of action above the base [m]
    shear: float           # force along the wall, + downward on the wall [N]
    segment_stress: np.ndarray   # (segments,) normal stress [Pa], bottom to top


def wall_load(frame, ids: np.ndarray, H: float, base=None) -> WallLoad:
    """Resultant of the panel loads of the retaining wall: normal force, its height above
    the wall base (from the panel forces *and* moments, so not limited to segment
    centres), downward shear, and the stress on each segment (bottom to top)."""
    F = frame.panel_force[ids]
    M = frame.panel_moment[ids]
    n = frame.panel_normal[ids]
    c = frame.panel_corners[ids].mean(axis=1)
    normal_k = -np.einsum("pd,pd->p", F, n)          # compression on each panel
    N = float(normal_k.sum())
    corners = frame.panel_corners[ids]
    if base is None:
        base = 0.5 * (corners[0, 0] + corners[0, 1])    # middle of the bottom edge
    up = corners[0, 3] - corners[0, 0]
    up = up / np.linalg.norm(up)
    axis = np.cross(up, n[0])
    # moment about the base edge of the soil's push (-F is the wall's reaction; use the
    # push F and its panel moments M consistently): height = (arm x (-F) + (-M)) . axis / N
    mom = float(np.sum((np.cross(c - base, -F) - M) @ axis))
    height = mom / N if N != 0 else float("nan")
    shear = float(-np.sum(F @ up))                     # + when the soil drags the wall down
    sigma = normal_k / frame.panel_area[ids]
    return WallLoad(N, height, shear, sigma)


def load_coefficient(normal_force: float, porosity: float, rec: SpecimenRecipe, wall: WallSetup) -> float:
    """Eq. 6: K = F / (0.5 rho (1 - n) g H^2 w)."""
    return normal_force / (0.5 * rec.density * (1.0 - porosity) * G * wall.height**2 * wall.width)


# ----------------------------------------------------------------------------- movement
def wall_motion(movement: Movement, H: float) -> tuple[dem3d.Motion, float]:
    """The wall's motion for a mode, and the distance [m] from the pivot to the edge whose
    displacement defines Delta (1 for translation). Speeds ramp up over ``ramp``."""
    v = movement.speed
    y_axis = (0.0, 1.0, 0.0)
    if movement.mode == "T":
        return dem3d.translation(dem3d.Ramp((-v, 0.0, 0.0), movement.ramp)), 1.0
    if movement.mode == "RB":      # pivot at the base, top moves -x: axis -y
        return dem3d.rotation((0.0, 0.0, 0.0), (0.0, -1.0, 0.0), dem3d.Ramp(v / H, movement.ramp)), H
    if movement.mode == "RT":      # pivot at the top, base moves -x: axis +y
        return dem3d.rotation((0.0, 0.0, H), y_axis, dem3d.Ramp(v / H, movement.ramp)), H
    arm = 1.5 * H                  # mixed: pivot H/2 above the top, Delta at the base
    return dem3d.rotation((0.0, 0.0, 1.5 * H), y_axis, dem3d.Ramp(v / arm, movement.ramp)), arm


def _ramp_distance(speed: float, ramp: float, t: float) -> float:
    """Distance covered by an edge whose speed ramps linearly to ``speed`` over ``ramp``."""
    if t <= ramp:
        return 0.5 * speed * t * t / ramp
    return 0.5 * speed * ramp + speed * (t - ramp)


@dataclass(frozen=True)
class LoadSample:
    wall_disp_over_H: float
    time: float
    step: int
    K: float
    resultant_height_over_H: float              # height of the resultant / H
    thrust_kN: float
    segment_stress: np.ndarray   # (segments,) Pa, bottom to top


def move_wall(case: NadukuruCase, specimen: Specimen, *, frame_every: int = 0, progress=None,
              resume: dict | None = None, checkpoint=None,
              checkpoint_every_s: float = 300.0,
              checkpoint_every_fraction: float = 0.1) -> Iterator[tuple[LoadSample, object | None]]:
    """Move the wall from the settled specimen to ``wall_disp_over_H``; yields
    (LoadSample averaged over ``record_every`` steps, Frame or None) pairs.

    ``checkpoint(state)`` is called every ``checkpoint_every_s`` of wall-clock time and
    each time another ``checkpoint_every_fraction`` of the movement is done (a short
    run interrupted before 300 s would otherwise restart its movement), with the engine
    state plus ``movement.t0`` (the time the movement started); passing that dict back
    as ``resume`` continues the movement exactly (dem3d resumes bitwise).
    """
    mv = case.movement
    wall = dataclasses.replace(case.wall, width=specimen.width)
    sim, t0 = _movement_simulation(case, specimen, wall, resume)
    n_total = int(math.ceil(_movement_duration(mv, wall.height) / sim.dt))
    ids = sim.walls.panel_ids("wall")
    k = mv.record_every
    done = int(round((sim.time - t0) / sim.dt))
    task = progress.add_task(f"{MODE_TITLES[mv.mode]}", total=n_total, completed=done, status="") \
        if progress else None
    since_frame = 0
    last_checkpoint = _time.perf_counter()
    step_of_marks = max(1, int(checkpoint_every_fraction * n_total))
    next_mark = (done // step_of_marks + 1) * step_of_marks
    while done < n_total:
        m = min(k, n_total - done)
        hist_f, hist_m = sim.step(m, record_panels=True)
        done += m
        since_frame += m
        sample = _averaged_sample(sim, hist_f, hist_m, ids, m, t0, case, specimen, wall)
        emit = bool(frame_every) and (since_frame >= frame_every or done >= n_total or done == m)
        if emit:
            since_frame = 0
        if task is not None:
            progress.update(task, advance=m, status=f"Delta/H {sample.wall_disp_over_H:.4f}  K {sample.K:.3f}")
        yield sample, (dem3d.frame(sim) if emit else None)
        # after the consumer has taken this sample, so a checkpoint holds it too
        if checkpoint is not None and (_time.perf_counter() - last_checkpoint > checkpoint_every_s
                                       or next_mark <= done < n_total):
            next_mark = (done // step_of_marks + 1) * step_of_marks
            state = sim.to_arrays()
            state["movement.t0"] = np.array(t0)
            checkpoint(state)
            last_checkpoint = _time.perf_counter()


def _movement_simulation(case: NadukuruCase, specimen: Specimen, wall: WallSetup,
                         resume: dict | None) -> tuple[dem3d.Simulation, float]:
    """The simulation that moves the wall, from the settled specimen or from a checkpoint
    (``resume``), and t0 [s], the simulation time at which the movement started. Motions
    are schedules from t = 0 while the specimen's clock stands at t0 after settling:
    they are shifted so the ramp starts when the wall starts to move."""
    rec, mv = case.specimen, case.movement
    motion, _ = wall_motion(mv, wall.height)
    if resume is None:
        t0 = float(specimen.state["time"])
        sim = dem3d.Simulation.from_arrays(specimen.state, walls=_box_walls(wall, rec, _shifted(motion, t0)))
        sim.walls.reset_pivots()              # a new motion, not the stored (fixed) one
        sim.set_params(contact_law(rec, rec.particle_friction, mv.local_damping))
    else:
        t0 = float(resume["movement.t0"])
        sim = dem3d.Simulation.from_arrays({k: v for k, v in resume.items() if k != "movement.t0"},
                                           walls=_box_walls(wall, rec, _shifted(motion, t0)))
    return sim, t0


def _movement_duration(mv: Movement, H: float) -> float:
    """Time [s] for the edge that defines Delta to reach wall_disp_over_H * H [m] when its
    speed ramps linearly to ``speed`` over ``ramp`` (``_ramp_distance`` inverted)."""
    target = mv.wall_disp_over_H * H
    return mv.ramp / 2.0 + target / mv.speed if target / mv.speed > mv.ramp / 2 else \
        math.sqrt(2.0 * target * mv.ramp / mv.speed)


def _averaged_sample(sim, hist_f, hist_m, ids, m: int, t0: float, case: NadukuruCase, specimen: Specimen,
                     wall: WallSetup) -> LoadSample:
    """The load sample of the last ``m`` steps: panel forces and moments averaged over
    them (``hist_f``, ``hist_m`` from ``sim.step(record_panels=True)``), Delta/H at the
    middle of the chunk, K by eq. 6 with the specimen's porosity."""
    mv, H = case.movement, wall.height
    panels = SimpleNamespace(panel_force=hist_f.mean(axis=0), panel_moment=hist_m.mean(axis=0),
                             panel_normal=sim.walls.panels.normal, panel_corners=sim.walls.corners(),
                             panel_area=sim.walls.areas())
    load = wall_load(panels, ids, H)
    disp = _ramp_distance(mv.speed, mv.ramp, sim.time - t0 - 0.5 * m * sim.dt)
    return LoadSample(disp / H, sim.time, sim.step_count,
                      load_coefficient(load.normal, specimen.porosity, case.specimen, wall),
                      load.height / H, load.normal / 1e3, load.segment_stress)


def _shifted(motion: dem3d.Motion, t0: float) -> dem3d.Motion:
    """The same motion with its clock starting at t0 (schedules are functions of time)."""
    return dataclasses.replace(motion, angular_speed=lambda t, f=motion.angular_speed: f(t - t0),
                               velocity=lambda t, f=motion.velocity: f(t - t0))


# ----------------------------------------------------------------------------- reference
#: Tables 1-3 and the specimen description, with their source (shipped with the package)
REFERENCE = json.loads((Path(__file__).parent / "reference.json").read_text())


def paper_values(mode: str, wall: str) -> dict:
    """The paper's DEM (Tables 1-2) and Fang & Ishibashi (Table 1) for a mode and wall."""
    row = REFERENCE.get(wall, {}).get(mode, {})
    out = {"K": row.get("K"), "resultant_height_over_H": row.get("resultant_height_over_H"),
           "source": f"Nadukuru & Michalowski (2012) Table {'1' if wall == 'rough' else '2'}"}
    if "FI_K" in row:
        out["fang_ishibashi"] = {"K": row["FI_K"], "resultant_height_over_H": row["FI_resultant_height_over_H"],
                                 "source": "Fang & Ishibashi (1986), interpolated to phi = 39 deg (Table 1)"}
    return out


def theory_rows(mode: str, phi_deg: float, wall_friction: float, gamma: float, H: float,
                phi_source: str) -> list[dict]:
    """The theories beside the DEM, as the *normal* load coefficient on the wall
    (comparable with eq. 6, which uses the normal force): Coulomb Ka cos(delta),
    Rankine Ka, Jaky K0, and the DSM of the mode (Kh, resultant_height_over_H)."""
    from analytic import Soil, Wall, coulomb, jaky, rankine
    from analytic.slices import mode_case, solve

    delta = math.degrees(math.atan(wall_friction))
    soil, w = Soil(phi_deg, gamma), Wall(H, delta)
    note = f"phi {phi_deg:.1f}, delta {delta:.1f} deg"
    rows = [theory_row(name, prof, note) for name, prof in
            (("coulomb", coulomb(soil, w)), ("rankine", rankine(soil, Wall(H))), ("jaky (at rest)", jaky(soil, Wall(H))))]
    if mode in ("T", "RB", "RT"):
        res = solve(mode_case(mode, phi_deg=phi_deg, delta_deg=delta, H=H, gamma=gamma))
        rows.append(theory_row("dsm", res.profile, f"k_l, phi* shapes of eqs. 13/18/19 at phi {phi_deg:.1f}, "
                               f"delta {delta:.1f}" + ("; curved surface: wallsim reconstruction" if mode == "RT" else ""),
                               height_over_H=res.resultant_height_over_H))
    else:
        rows.append(theory_row("dsm", None, "no DSM preset for the mixed mode"))
    return rows


def steady_disp_over_H(disp: np.ndarray, K: np.ndarray, window: float = 0.05) -> float:
    """Delta/H at which K has first completed 90 % of its drop from at rest to its final
    value (running mean over ``window`` of the record); the definition of the Khosravi
    case (``studies.measures.steady_displacement``). An earlier band of +-max(0.01,
    5 %) about the final K was set by noise at reduced size (K fluctuates by +-0.015
    there after the drop)."""
    return steady_displacement(disp, K, 0.9, smooth=max(3, int(window * len(K))))


# ----------------------------------------------------------------------------- the comparison
def load_or_prepare(case: NadukuruCase, cache_dir: Path, progress=None) -> tuple[Specimen, bool]:
    """The settled specimen for (recipe, wall, seed): from ``cache_dir`` if it was made
    before (so every mode starts from the same state), else prepared and saved there."""
    store, key = Store(cache_dir), specimen_key(case)
    found = store.load_arrays(key)
    if found is not None:
        state, info = found
        return Specimen(state=state, **with_current_names(info)), True
    spec = prepare_specimen(case, progress)
    store.save_arrays(key, spec.state, {k: (float(v) if isinstance(v, (np.floating, float)) else v)
                                        for k, v in dataclasses.asdict(spec).items() if k != "state"})
    return spec, False


def run_modes(case: NadukuruCase, specimen: Specimen, *, on_sample=None, on_frame=None,
              frame_every: int = 0, progress=None, checkpoint_path: Path | None = None,
              checkpoint_every_s: float = 300.0) -> dict:
    """Move the wall and collect the load history; returns arrays and the active-state
    figures (K and resultant_height_over_H averaged over the last 10 % of the movement).

    With ``checkpoint_path`` the engine state and the history so far are saved there
    every ``checkpoint_every_s`` seconds, and an existing checkpoint is resumed from:
    an interrupted run continues where it stopped instead of starting over."""
    samples: list[LoadSample] = []
    resume = None
    if checkpoint_path is not None and Path(checkpoint_path).exists():
        data = load_npz(checkpoint_path)
        resume = {k: v for k, v in data.items() if not k.startswith("hist.")}
        h = with_current_names({k[5:]: v for k, v in data.items() if k.startswith("hist.")})
        samples = [LoadSample(float(d), float(t), int(st), float(K), float(c), float(nk), seg)
                   for d, t, st, K, c, nk, seg in zip(h["disp"], h["time"], h["step"], h["K"], h["resultant_height_over_H"],
                                                      h["normal"], h["seg"])]

    def save(state):
        hist = {"hist.disp": [s.wall_disp_over_H for s in samples], "hist.time": [s.time for s in samples],
                "hist.step": [s.step for s in samples], "hist.K": [s.K for s in samples],
                "hist.resultant_height_over_H": [s.resultant_height_over_H for s in samples],
                "hist.normal": [s.thrust_kN for s in samples],
                "hist.seg": np.array([s.segment_stress for s in samples])}
        atomic_write(checkpoint_path, npz_bytes({**state, **{k: np.asarray(v) for k, v in hist.items()}}))

    for sample, frame in move_wall(case, specimen, frame_every=frame_every, progress=progress, resume=resume,
                                   checkpoint=save if checkpoint_path is not None else None,
                                   checkpoint_every_s=checkpoint_every_s):
        samples.append(sample)
        if on_sample is not None:
            on_sample(sample)
        if frame is not None and on_frame is not None:
            on_frame(frame, sample)
    disp = np.array([s.wall_disp_over_H for s in samples])
    K = np.array([s.K for s in samples])
    cen = np.array([s.resultant_height_over_H for s in samples])
    seg = np.array([s.segment_stress for s in samples])
    tail = disp >= 0.9 * disp[-1]
    return {"wall_disp_over_H": disp, "K": K, "resultant_height_over_H": cen, "segment_stress": seg,
            "time": np.array([s.time for s in samples]), "step": np.array([s.step for s in samples]),
            "K_active": float(K[tail].mean()), "resultant_height_over_H_active": float(cen[tail].mean()),
            "segment_stress_active": seg[tail].mean(axis=0),
            "wall_disp_over_H_steady": steady_disp_over_H(disp, K)}
