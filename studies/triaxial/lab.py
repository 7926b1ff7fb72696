"""Numerical triaxial test on the backfill mixture (Nadukuru & Michalowski 2012: cylinder
1.2 m high and wide, ~8,200 particles, confining 200 kPa, peak phi = 39 deg).

dem3d has planar walls only, so the specimen is a cube between six rigid platens
(a "cubical triaxial" with sigma_2 = sigma_3, as in YADE's TriaxialTest): same grains,
the particle count of the paper's cylinder, aspect ratio 1. Gravity off. Stages:

1. generate loosely in a large cube, compact isotropically with servo-controlled platens
   to the confining stress, with the deposition friction (lower friction -> denser);
2. restore the particle friction, re-balance at the confining stress;
3. shear: the top platen moves down at a constant strain rate, the four lateral platens
   keep sigma_3 by servo control; record sigma_1, sigma_3, axial and volumetric strain.

phi = asin((sigma_1 - sigma_3) / (sigma_1 + sigma_3)) at the peak (and at the end, as
an estimate of the critical state).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

import dem3d
from analytic.inputs import require_number

from ..store import atomic_write, content_key
from ..nadukuru.model import SpecimenRecipe, _CLUMP_VOLUME_FACTOR, _contact


@dataclass
class ServoVelocity:
    """A velocity schedule the servo rewrites between chunks of steps (m/s, (3,))."""

    value: tuple = (0.0, 0.0, 0.0)

    def __call__(self, t: float):
        return self.value


@dataclass(frozen=True)
class TriaxialSetup:
    """confining [Pa], axial strain rate [1/s], final axial strain, servo speed limit during
    compaction [m/s] (the lateral platens may move at up to 4x the axial platen while shearing).

    compaction_friction: particle friction while the platens compact the cloud to the
    confining stress (None: the recipe's deposition friction). 0 gives the densest packing,
    the nearest to the rained fill's porosity (~0.35; the paper does not state its triaxial
    specimen's porosity). At 8,200 spheres, 0.1 left porosity 0.387 and peak phi 29.5 deg."""

    confining: float = 200e3
    compaction_friction: float | None = 0.0
    strain_rate: float = 0.04
    max_strain: float = 0.10
    servo_speed: float = 0.5
    chunk: int = 20

    def __post_init__(self):
        require_number("confining", self.confining, 0, None, unit="Pa")
        require_number("strain_rate", self.strain_rate, 0, 1.0, unit="1/s")
        require_number("max_strain", self.max_strain, 0, 0.5)


@dataclass(frozen=True)
class TriaxialCase:
    """``calibrate triaxial``: the backfill recipe (Nadukuru's, its card keyed by the
    grain and contact fields; ``specimen.particles`` is the test's sphere count, the
    paper's 8,200), the test set-up and the seed."""

    specimen: SpecimenRecipe = field(default_factory=lambda: SpecimenRecipe(particles=8200))
    setup: TriaxialSetup = field(default_factory=TriaxialSetup)
    seed: int = 1


@dataclass
class TriaxialResult:
    axial_strain: np.ndarray
    volumetric_strain: np.ndarray      # compression positive
    sigma_1: np.ndarray                # Pa
    sigma_3: np.ndarray                # Pa
    porosity_start: float
    n_spheres: int
    side: float
    phi_peak_deg: float = field(init=False)
    strain_at_peak: float = field(init=False)
    phi_end_deg: float = field(init=False)

    def __post_init__(self):
        ratio = (self.sigma_1 - self.sigma_3) / (self.sigma_1 + self.sigma_3)
        k = int(np.argmax(ratio))
        self.phi_peak_deg = math.degrees(math.asin(min(max(ratio[k], 0.0), 1.0)))
        self.strain_at_peak = float(self.axial_strain[k])
        tail = ratio[int(0.85 * len(ratio)):]
        self.phi_end_deg = math.degrees(math.asin(min(max(float(np.mean(tail)), 0.0), 1.0)))


def _plane(point, normal, half):
    return dem3d.plane(point, normal, 0.0, half)


def run_triaxial(rec: SpecimenRecipe, setup: TriaxialSetup = TriaxialSetup(), *, seed: int = 1,
                 particles: int = 8200, progress=None) -> TriaxialResult:
    """Build, compact and shear a cubical specimen of ``particles`` spheres (incl. clump
    members) with the grains of ``rec``; see the module docstring."""
    rng = np.random.default_rng(seed)
    n_bodies = int(round(particles / (1.0 + rec.clump_fraction)))
    a, b = rec.d_min, rec.d_max
    mean_d3 = (b**4 - a**4) / (4.0 * (b - a)) if b > a else a**3
    v_body = math.pi / 6.0 * mean_d3 * (1.0 + rec.clump_fraction * (_CLUMP_VOLUME_FACTOR - 1.0))
    side0 = (n_bodies * v_body / 0.22) ** (1.0 / 3.0)       # generated at solid fraction 0.22
    spec = dem3d.random_specimen(rng, (1e-3,) * 3, (side0 - 1e-3,) * 3, n_bodies, a, b,
                                 clump_fraction=rec.clump_fraction, clump_overlap=rec.clump_overlap,
                                 density=rec.density)
    servo = [ServoVelocity() for _ in range(6)]
    # faces: x-, x+, y-, y+, z- (fixed floor platen), z+ ; normals into the specimen
    normals = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    points = [(0, .5, .5), (1, .5, .5), (.5, 0, .5), (.5, 1, .5), (.5, .5, 0), (.5, .5, 1)]
    walls = []
    for k in range(6):
        p = tuple(side0 * c for c in points[k])
        motion = dem3d.FIXED if k == 4 else dem3d.translation(servo[k])
        walls.append(dem3d.Wall(f"face{k}", [_plane(p, normals[k], (0.5 * side0, 0.5 * side0))], motion))
    m_min = rec.density * math.pi / 6.0 * a**3
    dt = rec.dt or 0.2 * math.sqrt(m_min / max(rec.kn, rec.ks))
    mu_compact = mu_compact_of(setup, rec)
    sim = dem3d.Simulation(spec, _contact(rec, mu_compact, rec.local_damping), dt=dt, walls=walls,
                           gravity=(0.0, 0.0, 0.0))
    normal = np.array(normals, float)

    def box():
        c = sim.walls.panels.centre
        return np.array([c[1, 0] - c[0, 0], c[3, 1] - c[2, 1], c[5, 2] - c[4, 2]])

    def stresses():
        dims = box()
        areas = np.array([dims[1] * dims[2]] * 2 + [dims[0] * dims[2]] * 2 + [dims[0] * dims[1]] * 2)
        f = sim.panel_force
        return -np.einsum("pd,pd->p", f, normal) / areas

    d_mean = 0.5 * (a + b)

    def servo_step(targets, active, v_max, n):
        """PFC-style servo: move each active platen so that, with the contact stiffness
        of a platen (about one contact per d_mean^2 of area, kn each), half of its stress
        error closes in one chunk; speed capped at v_max."""
        sig = stresses()
        dims = box()
        areas = np.array([dims[1] * dims[2]] * 2 + [dims[0] * dims[2]] * 2 + [dims[0] * dims[1]] * 2)
        k_platen = 0.5 * areas / d_mean**2 * rec.kn      # N/m per platen (~0.5 contact per d^2)
        for k in range(6):
            if not active[k]:
                continue
            v = 0.8 * (targets[k] - sig[k]) * areas[k] / k_platen[k] / (n * dt)   # + inward
            v = max(-v_max, min(v_max, v))
            servo[k].value = tuple(v * normal[k])
        sim.step(n)
        return sig

    target = np.full(6, setup.confining)
    lateral = [True, True, True, True, False, True]
    # 1. isotropic compaction with the deposition friction
    task = progress.add_task("triaxial: compaction", total=None, status="") if progress else None
    for it in range(400_000 // setup.chunk):
        sig = servo_step(target, lateral, setup.servo_speed, setup.chunk)
        if it % 25 == 0:
            if task is not None:
                progress.update(task, status=f"sigma {np.mean(sig[[0, 1, 2, 3, 5]]) / 1e3:.0f} kPa")
            if np.all(np.abs(sig[[0, 1, 2, 3, 5]] / setup.confining - 1) < 0.02) and \
                    dem3d.measure.unbalanced_force_ratio(sim) < 5e-3:
                break
    compaction_steps = sim.step_count
    # 2. particle friction, re-balance
    sim.set_params(_contact(rec, rec.particle_friction, rec.local_damping))
    for it in range(2000 // setup.chunk):
        servo_step(target, lateral, 0.2 * setup.servo_speed, setup.chunk)
    dims0 = box()
    solid = _solid_volume(sim)
    porosity0 = 1.0 - solid / float(np.prod(dims0))
    # 3. shear: top platen at constant strain rate; lateral servo at sigma_3
    sim.set_params(_contact(rec, rec.particle_friction, 0.0))
    H0 = dims0[2]
    v_axial = setup.strain_rate * H0
    servo[5].value = tuple(v_axial * normal[5])
    n_steps = int(setup.max_strain / setup.strain_rate / dt)
    lateral_only = [True, True, True, True, False, False]
    eps_a, eps_v, s1, s3 = [], [], [], []
    V0 = float(np.prod(dims0))
    shear_task = progress.add_task("triaxial: shearing", total=n_steps, status="") if progress else None
    done = 0
    while done < n_steps:
        k = min(setup.chunk, n_steps - done)
        sig = servo_step(target, lateral_only, 4.0 * v_axial, k)
        done += k
        dims = box()
        eps_a.append(1.0 - dims[2] / H0)
        eps_v.append(1.0 - float(np.prod(dims)) / V0)
        s1.append(0.5 * (sig[4] + sig[5]))
        s3.append(float(np.mean(sig[:4])))
        if shear_task is not None:
            progress.update(shear_task, advance=k, status=f"eps {eps_a[-1]:.3f}")
    res = TriaxialResult(np.array(eps_a), np.array(eps_v), np.array(s1), np.array(s3), porosity0,
                         sim.n_spheres, float(dims0[0]))
    res.steps = {"compaction": compaction_steps, "total": sim.step_count, "dt": dt}
    return res


def mu_compact_of(setup: TriaxialSetup, rec: SpecimenRecipe) -> float:
    return rec.deposition_friction if setup.compaction_friction is None else setup.compaction_friction


def card_path(root, rec: SpecimenRecipe, seed: int):
    """Where the calibration card of a recipe lives: runs/nadukuru/calibration/, keyed by
    the grain and contact fields (not the particle count: one card serves every size)."""
    from pathlib import Path
    keys = ("clump_fraction", "clump_overlap", "d_min", "d_max", "kn", "ks", "particle_friction", "density",
            "deposition_friction", "damping_ratio")
    key = content_key({k: getattr(rec, k) for k in keys}, length=12)
    return Path(root) / "nadukuru" / "calibration" / f"triaxial-{key}.json"


def _solid_volume(sim) -> float:
    """Volume of all grains, clump overlaps counted once: sum of body volumes from masses."""
    return float(np.sum(sim.body_masses())) / sim.density


def calibrate_triaxial(case, setup: TriaxialSetup, *, particles: int, root, progress=None):
    """Run the triaxial test for the case's recipe and write its calibration card
    (JSON: phi at peak and at the end, strains, porosity, provenance) where
    ``compare nadukuru`` finds it. Returns (card, path)."""
    import dataclasses
    import json
    import time

    from ..runfolder import package_versions

    t0 = time.perf_counter()
    res = run_triaxial(case.specimen, setup, seed=case.seed, particles=particles, progress=progress)
    card = {
        "test": "cubical triaxial (six rigid platens, sigma_2 = sigma_3), gravity off",
        "phi_peak_deg": res.phi_peak_deg, "strain_at_peak": res.strain_at_peak, "phi_end_deg": res.phi_end_deg,
        "porosity": res.porosity_start, "particles": res.n_spheres, "side_m": res.side,
        "confining_kPa": setup.confining / 1e3, "strain_rate_per_s": setup.strain_rate,
        "compaction_friction": mu_compact_of(setup, case.specimen), "seed": case.seed,
        "recipe": dataclasses.asdict(case.specimen), "steps": res.steps, "wall_time_s": time.perf_counter() - t0,
        "versions": package_versions(),
        "curve": {"axial_strain": res.axial_strain[::10].tolist(), "volumetric_strain": res.volumetric_strain[::10].tolist(),
                  "sigma_1_kPa": (res.sigma_1[::10] / 1e3).tolist(), "sigma_3_kPa": (res.sigma_3[::10] / 1e3).tolist()},
        "paper": {"phi_deg": 39.0, "source": "Nadukuru & Michalowski (2012): cylinder 1.2 m, 8,200 particles, 200 kPa"},
    }
    path = atomic_write(card_path(root, case.specimen, case.seed), json.dumps(card, indent=1).encode())
    return card, path
