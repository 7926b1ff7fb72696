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
from analytic.inputs import MAX_PRESSURE_KPA
from analytic.schema import check_fields, param

from ..granular import CLUMP_VOLUME_FACTOR, SpecimenRecipe, contact_law, frictional_law, time_step
from ..granular.cloud import loose_cloud


@dataclass
class ServoVelocity:
    """A velocity schedule the servo rewrites between chunks of steps (m/s, (3,))."""

    value: tuple = (0.0, 0.0, 0.0)

    def __call__(self, t: float):
        return self.value


@dataclass(frozen=True)
class TriaxialSetup:
    """The cubical triaxial cell: confining stress, compaction, shearing and the servo."""

    # 10 MPa (analytic.inputs.MAX_PRESSURE_KPA: no wall's soil sees more); there a 6 cm grain
    # overlaps its neighbours by ~7 % of its diameter at the paper's kn
    confining: float = param(200e3, unit="Pa", lo=0, hi=MAX_PRESSURE_KPA * 1e3, lo_open=True,
                             meaning="confining stress sigma_3 (paper 200 kPa)")
    # 0 gives the densest packing, the nearest to the rained fill's porosity (~0.35; the
    # paper does not state its triaxial specimen's porosity); at 8,200 spheres 0.1 left
    # porosity 0.387 and peak phi 29.5 deg
    compaction_friction: float | None = param(
        0.0, lo=0, meaning="particle friction while the platens compact the cloud to the confining stress (none: "
                           "the recipe's deposition friction)")
    # the test's length (TriaxialCase, MOST_PARTICLE_STEPS) bounds a slow shear
    strain_rate: float = param(0.04, unit="1/s", lo=0, hi=1.0, lo_open=True, hi_open=True,
                               meaning="axial strain rate of the top platen while shearing (0.04)")
    max_strain: float = param(0.10, lo=0, hi=0.5, lo_open=True, hi_open=True,
                              meaning="axial strain at which shearing ends (0.10)")
    servo_speed: float = param(0.5, unit="m/s", lo=0, lo_open=True,
                               meaning="speed limit of the servo-driven platens while compacting (the lateral "
                                       "ones may move at up to 4x the axial platen while shearing)")
    # the compaction runs 400,000 // chunk chunks and the re-balance 2000 // chunk
    chunk: int = param(20, lo=1, hi=2000, meaning="time steps between two servo updates of the platen speeds (20)")

    def __post_init__(self):
        check_fields(self)


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


#: the six platens of the cubical cell: x-, x+, y-, y+, z- (the fixed floor platen), z+;
#: normals point into the specimen, points are platen centres as fractions of the side
_PLATEN_NORMALS = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]


_PLATEN_POINTS = [(0, .5, .5), (1, .5, .5), (.5, 0, .5), (.5, 1, .5), (.5, .5, 0), (.5, .5, 1)]


#: platens the servo drives: all but the floor (isotropic stages), the four lateral (shearing)
ALL_BUT_FLOOR = (True, True, True, True, False, True)


LATERAL = (True, True, True, True, False, False)


def run_triaxial(rec: SpecimenRecipe, setup: TriaxialSetup = TriaxialSetup(), *, seed: int = 1,
                 particles: int = 8200, progress=None, on_frame=None) -> TriaxialResult:
    """Build, compact and shear a cubical specimen of ``particles`` spheres (incl. clump
    members) with the grains of ``rec``; see the module docstring. ``on_frame(frame)``:
    the specimen when compacted and at every tenth of the shear strain."""
    rng = np.random.default_rng(seed)
    spec, side0 = _loose_cube(rec, particles, rng)
    servo = [ServoVelocity() for _ in range(6)]
    walls = platen_walls(side0, servo)
    dt = time_step(rec)
    mu_compact = mu_compact_of(setup, rec)
    sim = dem3d.Simulation(spec, contact_law(rec, mu_compact, rec.local_damping), dt=dt, walls=walls,
                           gravity=(0.0, 0.0, 0.0))
    cell = ServoCell(sim, servo, rec.kn, 0.5 * (rec.d_min + rec.d_max), dt)
    target = np.full(6, setup.confining)
    compaction_steps = _compact(cell, target, setup, progress)
    dims0, porosity0 = _rebalance(cell, rec, target, setup)
    eps_a, eps_v, s1, s3 = _shear(cell, rec, target, setup, dims0, progress, on_frame)
    res = TriaxialResult(np.array(eps_a), np.array(eps_v), np.array(s1), np.array(s3), porosity0,
                         sim.n_spheres, float(dims0[0]))
    res.steps = {"compaction": compaction_steps, "total": sim.step_count, "dt": dt}
    return res


#: solid fractions of the loose cloud, tried in turn (0.22 first: every earlier specimen)
CLOUD_FRACTIONS = (0.22, 0.18, 0.15)


def _loose_cube(rec: SpecimenRecipe, particles: int, rng) -> tuple[dem3d.Specimen, float]:
    """The bodies placed at random (``granular.cloud.loose_cloud``) in a cube at solid
    fraction 0.22, and the cube's side [m]; where random placement jams there (3,000
    spheres with seed 2 did) a looser cube, drawn on from the same generator."""
    n_bodies = int(round(particles / (1.0 + rec.clump_fraction)))
    a, b = rec.d_min, rec.d_max
    mean_d3 = (b**4 - a**4) / (4.0 * (b - a)) if b > a else a**3
    v_body = math.pi / 6.0 * mean_d3 * (1.0 + rec.clump_fraction * (CLUMP_VOLUME_FACTOR - 1.0))

    def side(fraction: float) -> float:
        return (n_bodies * v_body / fraction) ** (1.0 / 3.0)

    spec, fraction = loose_cloud(rng, (1e-3,) * 3, lambda f: (side(f) - 1e-3,) * 3, CLOUD_FRACTIONS, n_bodies, a, b,
                                 density=rec.density, clump_fraction=rec.clump_fraction,
                                 clump_overlap=rec.clump_overlap, what=("particles", particles))
    return spec, side(fraction)


def platen_walls(side0: float, servo: list[ServoVelocity]) -> list:
    """The six frictionless platens around a cube of side ``side0`` [m]; the floor (z-) is
    fixed, the others move at the velocity their ``servo`` schedule holds."""
    walls = []
    for k in range(6):
        p = tuple(side0 * c for c in _PLATEN_POINTS[k])
        motion = dem3d.FIXED if k == 4 else dem3d.translation(servo[k])
        walls.append(dem3d.Wall(f"face{k}", [_plane(p, _PLATEN_NORMALS[k], (0.5 * side0, 0.5 * side0))], motion))
    return walls


class ServoCell:
    """The specimen between its six platens: box dimensions [m], platen stresses [Pa]
    and the servo that drives the platens towards target stresses."""

    def __init__(self, sim, servo: list[ServoVelocity], kn: float, d_mean: float, dt: float):
        self.sim, self.servo, self.kn, self.d_mean, self.dt = sim, servo, kn, d_mean, dt
        self.normal = np.array(_PLATEN_NORMALS, float)

    def box(self) -> np.ndarray:
        """(x, y, z) distances between opposite platens [m]."""
        c = self.sim.walls.panels.centre
        return np.array([c[1, 0] - c[0, 0], c[3, 1] - c[2, 1], c[5, 2] - c[4, 2]])

    def stresses(self) -> np.ndarray:
        """Normal stress on each platen [Pa], compression positive."""
        dims = self.box()
        areas = np.array([dims[1] * dims[2]] * 2 + [dims[0] * dims[2]] * 2 + [dims[0] * dims[1]] * 2)
        f = self.sim.panel_force
        return -np.einsum("pd,pd->p", f, self.normal) / areas

    def servo_step(self, targets, active, v_max: float, n: int) -> np.ndarray:
        """PFC-style servo: move each active platen so that, with the contact stiffness
        of a platen (about one contact per d_mean^2 of area, kn each), half of its stress
        error closes in one chunk; speed capped at v_max [m/s]. Then run ``n`` steps.
        Returns the stresses [Pa] the speeds were set from."""
        sig = self.stresses()
        dims = self.box()
        areas = np.array([dims[1] * dims[2]] * 2 + [dims[0] * dims[2]] * 2 + [dims[0] * dims[1]] * 2)
        k_platen = 0.5 * areas / self.d_mean**2 * self.kn      # N/m per platen (~0.5 contact per d^2)
        for k in range(6):
            if not active[k]:
                continue
            v = 0.8 * (targets[k] - sig[k]) * areas[k] / k_platen[k] / (n * self.dt)   # + inward
            v = max(-v_max, min(v_max, v))
            self.servo[k].value = tuple(v * self.normal[k])
        self.sim.step(n)
        return sig


def _compact(cell: ServoCell, target: np.ndarray, setup: TriaxialSetup, progress) -> int:
    """Stage 1: isotropic compaction at the compaction friction until the five moving
    platens are within 2 % of the confining stress and the unbalanced-force ratio is
    below 5e-3 (checked every 25 chunks). Returns the step count at its end."""
    task = progress.add_task("triaxial: compaction", total=None, status="") if progress else None
    for it in range(400_000 // setup.chunk):
        sig = cell.servo_step(target, ALL_BUT_FLOOR, setup.servo_speed, setup.chunk)
        if it % 25 == 0:
            if task is not None:
                progress.update(task, status=f"sigma {np.mean(sig[[0, 1, 2, 3, 5]]) / 1e3:.0f} kPa")
            if np.all(np.abs(sig[[0, 1, 2, 3, 5]] / setup.confining - 1) < 0.02) and \
                    dem3d.measure.unbalanced_force_ratio(cell.sim) < 5e-3:
                break
    return cell.sim.step_count


def _rebalance(cell: ServoCell, rec: SpecimenRecipe, target: np.ndarray,
               setup: TriaxialSetup) -> tuple[np.ndarray, float]:
    """Stage 2: the particle friction on, 2000 // chunk chunks of servo at the confining stress.
    Returns the box dimensions [m] and porosity at the start of shearing."""
    cell.sim.set_params(frictional_law(rec, rec.local_damping))
    for it in range(2000 // setup.chunk):
        cell.servo_step(target, ALL_BUT_FLOOR, 0.2 * setup.servo_speed, setup.chunk)
    dims0 = cell.box()
    solid = _solid_volume(cell.sim)
    porosity0 = 1.0 - solid / float(np.prod(dims0))
    return dims0, porosity0


def _shear(cell: ServoCell, rec: SpecimenRecipe, target: np.ndarray, setup: TriaxialSetup,
           dims0: np.ndarray, progress, on_frame=None) -> tuple[list, list, list, list]:
    """Stage 3: the top platen moves down at the strain rate to ``max_strain`` (local
    damping off); the lateral platens hold sigma_3. Returns, per chunk, axial and
    volumetric strain (compression +) and sigma_1, sigma_3 [Pa]. ``on_frame``: called
    with the specimen's frame at the start and each time another tenth of
    ``max_strain`` is reached."""
    sim, servo, normal = cell.sim, cell.servo, cell.normal
    sim.set_params(frictional_law(rec, 0.0))
    H0 = dims0[2]
    v_axial = setup.strain_rate * H0
    servo[5].value = tuple(v_axial * normal[5])
    n_steps = int(setup.max_strain / setup.strain_rate / cell.dt)
    eps_a, eps_v, s1, s3 = [], [], [], []
    V0 = float(np.prod(dims0))
    shear_task = progress.add_task("triaxial: shearing", total=n_steps, status="") if progress else None
    marks = list(np.linspace(0.0, setup.max_strain, 11)[1:])
    if on_frame is not None:
        on_frame(dem3d.frame(sim))
    done = 0
    while done < n_steps:
        k = min(setup.chunk, n_steps - done)
        sig = cell.servo_step(target, LATERAL, 4.0 * v_axial, k)
        done += k
        dims = cell.box()
        eps_a.append(1.0 - dims[2] / H0)
        eps_v.append(1.0 - float(np.prod(dims)) / V0)
        s1.append(0.5 * (sig[4] + sig[5]))
        s3.append(float(np.mean(sig[:4])))
        if on_frame is not None and marks and (eps_a[-1] >= marks[0] or done >= n_steps):
            on_frame(dem3d.frame(sim))
            while marks and eps_a[-1] >= marks[0]:
                marks.pop(0)
        if shear_task is not None:
            progress.update(shear_task, advance=k, status=f"eps {eps_a[-1]:.3f}")
    return eps_a, eps_v, s1, s3


def mu_compact_of(setup: TriaxialSetup, rec: SpecimenRecipe) -> float:
    return rec.deposition_friction if setup.compaction_friction is None else setup.compaction_friction


def _solid_volume(sim) -> float:
    """Volume of all grains, clump overlaps counted once: sum of body volumes from masses."""
    return float(np.sum(sim.body_masses())) / sim.density
