"""The backfill rained behind a wall (``prepare_specimen``; Nadukuru & Michalowski's procedure):
generate bodies loosely above the box, rain them under gravity (optionally with a lower
"deposition" friction, a standard way to densify), trim to the wall height, restore the
particle friction, settle; report porosity, at-rest K, the resultant's height and the
wall load. The settled state is kept by content key (``load_or_prepare``) so all modes
start from it.
"""

from __future__ import annotations

import dataclasses
import math
import time as _time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import dem3d
from analytic.constants import G
from dem3d import measure

from ..config import with_current_names
from .cloud import loose_cloud
from .recipe import SpecimenRecipe, contact_law, frictional_law, time_step
from ..store import Store, content_key
from ..progress import step_with_progress

from .wall import GENERATION_FRACTIONS, OVERFILL, WallCase, WallSetup, grain_scale
from .load import wall_load


def box_walls(wall: WallSetup, rec: SpecimenRecipe, motion=dem3d.FIXED) -> list:
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


def specimen_key(case: WallCase) -> str:
    """Hash of everything that shapes the settled specimen (not the movement)."""
    # a field added later is left out at its no-op value (rolling_friction 0, a wall's unset
    # option), so the keys of specimens made before it stay
    recipe = {k: v for k, v in dataclasses.asdict(case.specimen).items() if not (k == "rolling_friction" and v == 0)}
    return content_key({"specimen": recipe,
                        "wall": {k: v for k, v in dataclasses.asdict(case.wall).items() if v is not None},
                        "seed": case.seed, "procedure": PREPARATION_VERSION})


def prepare_specimen(case: WallCase, progress=None) -> Specimen:
    """Rain, trim to H and settle the backfill behind the fixed wall (module docstring).
    Stages A (rain and pack), B (trim and stiffen), C (load to g), then the at-rest
    measurement; each stage's steps, times and settle trace go to ``Specimen.stages``."""
    rec = case.specimen
    rng = np.random.default_rng(case.seed)
    s, w = grain_scale(rec, case.wall)
    wall = dataclasses.replace(case.wall, width=w)
    spec, gen_height = _loose_fill(rec, wall, s, rng)
    dt = time_step(rec, s)
    walls = box_walls(wall, rec)
    log = _StageLog()
    sim, steps = _rain_and_pack(spec, rec, wall, walls, gen_height, s * rec.d_max, dt, progress, log)
    sim, more, res = _trim_and_stiffen(sim, rec, wall, walls, dt, log)
    steps += more
    if rec.rain_gravity != 1.0:
        more, res = _load_to_gravity(sim, rec, dt, log)
        steps += more
    return _measure_at_rest(sim, rec, wall, s, dt, steps, res.ratio, log.stages)


def _loose_fill(rec: SpecimenRecipe, wall: WallSetup, scale: float, rng) -> tuple[dem3d.Specimen, float]:
    """The bodies placed at random (``cloud.loose_cloud``) in L x w x gen_height, and
    gen_height [m]: tall enough for a solid fraction of 0.2 (coarse grains in a narrow
    box jam before it: 800 and 1,000 particles did; then a taller, looser cloud).
    ``scale`` multiplies the recipe's diameters (``grain_scale``)."""
    L, H, w = wall.backfill_length, wall.rained_height, wall.width
    n_bodies = int(round(rec.particles / (1.0 + rec.clump_fraction)))

    def gen_height(fraction: float) -> float:
        return (1.0 - rec.target_porosity) * H * OVERFILL / fraction

    spec, fraction = loose_cloud(rng, np.array([0.0, 0.0, 0.0]) + 1e-3,
                                 lambda f: np.array([L, w, gen_height(f)]) - 1e-3, GENERATION_FRACTIONS, n_bodies,
                                 scale * rec.d_min, scale * rec.d_max, density=rec.density,
                                 clump_fraction=rec.clump_fraction, clump_overlap=rec.clump_overlap,
                                 what=("particles", rec.particles))
    return spec, gen_height(fraction)


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


def _trim_and_stiffen(sim, rec: SpecimenRecipe, wall: WallSetup, walls: list, dt: float, log: _StageLog):
    """Stage B: unload to the lock-in gravity ``rain_gravity`` (overlaps shrink), trim to
    the fill surface (drops the guard), settle at the paper's stiffness with the deposition friction,
    then with the particle friction. Returns (the new simulation, its steps counted
    here, the last settle result)."""
    g_low = G * rec.rain_gravity
    sim.gravity = np.array([0.0, 0.0, -g_low])
    steps = step_with_progress(sim, 2000, None, "")
    log.stages["in_front_of_wall"] = int(np.sum(sim.spheres.x[:, 0] < 0.0))   # removed by the trim; 0 with the guard
    sim = _trim(sim, wall, walls, rec, dt)      # paper stiffness, still the deposition friction
    sim.gravity = np.array([0.0, 0.0, -g_low])
    res = dem3d.settle(sim, ratio=rec.settle_ratio, check_every=500, max_steps=int(1.0 / dt), trace=log.trace)
    steps += res.steps
    log.stage("stiffen", res.steps)
    sim.set_params(frictional_law(rec, rec.local_damping))
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
    sim.set_params(frictional_law(rec, 0.0))
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


def _trim(sim, wall: WallSetup, walls, rec: SpecimenRecipe, dt: float):
    """A new Simulation (paper stiffness, deposition friction, local damping) with
    ``walls`` (no guard) and without the bodies that have any sphere centre above the
    fill surface (H, or the sloping plane) or in front of the wall (contact history
    restarts; the caller settles again)."""
    sph = sim.spheres
    top = wall.surface_height(sph.x[:, 0])
    above = (sph.x[:, 2] > top) | (sph.x[:, 0] < 0.0)     # and any grain that got in front of the wall
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


def load_or_prepare(case: WallCase, cache_dir: Path, progress=None) -> tuple[Specimen, bool]:
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
