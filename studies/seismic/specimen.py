"""The seismic sheet-pile model over dem3d (model units; coordinates in ``case``).

Stages:

1. ``rain_deposit``: grains generated loosely (random sequential addition) in a box,
   rained and packed under N g with softened moduli, ``deposition_friction`` and heavy
   contact damping (a larger time step; the porosity is set by the friction), then the
   moduli raised step by step to the grains' and settled, each step ended by an
   unbalanced-force or kinetic-energy criterion; grains above the surface trimmed. Used for
   the main deposit (periodic across y, rigid ends in x) and for each free-field column
   (periodic along x, frictionless side walls in y [A]).
2. ``install_wall``: the sheet pile wished in place: grains overlapping its volume are
   removed and two sheets of balls (square array, diameter D, ``case.wall_ball``) are put
   in, bonded (parallel bonds calibrated by ``dem3d.cantilever.calibrate_strip`` to the
   paper's EI per width); the soil in front above the dredge line is excavated.
3. ``static_stage``: the wall and soil settle under N g (local damping 0.7), the lateral
   boundaries held still: the wall deflects toward the excavation.
4. ``dynamic_stage``: the base is shaken by the prototype motion in model units (a
   sine ramp, ``dem3d.sine_ramp``), the free-field columns on the same base, the lateral
   boundaries tied to them by ``dem3d.freefield`` (Lysmer-Kuhlemeyer dashpots plus the
   free-field stress).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

import dem3d
from dem3d import Periodic, Simulation, Specimen, Wall, hertz_mindlin, plane, settle
from dem3d.cantilever import calibrate_strip
from dem3d.freefield import free_field_walls

from ..granular.cloud import loose_cloud
from .case import SeismicCase, wall_ball_density, wall_youngs_effective

#: solid fraction of the loose random generation (random sequential addition jams ~0.38)
_GENERATION_SOLIDS = 0.22


def contact_law(case: SeismicCase, *, friction: float | None = None, local_damping: float = 0.0):
    """Hertz-Mindlin with the grains' G and nu [A], viscous damping ``damping_ratio``."""
    youngs = 2.0 * case.shear_modulus * (1.0 + case.poisson)
    mu = case.friction if friction is None else friction
    return hertz_mindlin(youngs, case.poisson, mu, zeta_n=case.damping_ratio, zeta_s=case.damping_ratio,
                         local_damping=local_damping, mu_roll=case.rolling_resistance)


def mean_grain_volume(case: SeismicCase) -> float:
    """E[pi d^3 / 6] for d uniform in [d_min, d_max] [m^3]."""
    a, b = case.grains
    return math.pi / 6.0 * (b ** 4 - a ** 4) / (4.0 * (b - a)) if b > a else math.pi / 6.0 * a ** 3


def grain_mass(case: SeismicCase) -> float:
    return case.grain_density * mean_grain_volume(case)


def settle_energy(case: SeismicCase, n_grains: int, fraction: float) -> float:
    """``fraction`` x N m g d_mean [J]: the kinetic-energy bound of a settling stage
    (each of N grains' energy of a drop of one mean diameter at N g, times fraction)."""
    return fraction * n_grains * grain_mass(case) * case.gravity * case.d_mean


def time_step(case: SeismicCase, law, *, bonds: bool = True) -> float:
    """dt_fraction x the smallest critical step: the grains' Hertz (Rayleigh) step and,
    with ``bonds``, the wall bonds' step with the wall balls' own density."""
    r_min = 0.5 * case.grains[0]
    m_min = case.grain_density * 4.0 / 3.0 * math.pi * r_min ** 3
    crit = dem3d.critical_time_step(law, m_min, r_min, case.grain_density)
    return case.dt_fraction * (min(crit, bond_critical_step(case)) if bonds else crit)


def wall_period(case: SeismicCase) -> float:
    """First-mode period [s] of the wall as a free cantilever of its whole length:
    T = 2 pi / 1.875^2 sqrt(m L^4 / EI), m and EI per width (the paper's 12 kg/m^2 and
    416.7 N m^2/m). The embedded wall is stiffer, so this bounds its period from above."""
    ei = wall_youngs_effective(case) * (2.0 * case.wall_ball) ** 3 / 12.0
    return 2.0 * math.pi / 1.875 ** 2 * math.sqrt(case.wall_mass_per_area * case.wall_length ** 4 / ei)


def bond_critical_step(case: SeismicCase) -> float:
    """sqrt(m / (kn A)) and sqrt(I / (kn I_b)) of one wall bond (dem3d's bond rule) [s]."""
    prm = calibrate_strip(wall_youngs_effective(case), 2.0 * case.wall_ball)
    r = prm.ball_radius
    m = wall_ball_density(case) * 4.0 / 3.0 * math.pi * r ** 3
    area = math.pi * r * r
    inertia = 0.25 * math.pi * r ** 4
    return min(math.sqrt(m / (prm.kn * area)), math.sqrt(0.4 * m * r * r / (prm.kn * 2.0 * inertia)))


class Deposit(NamedTuple):
    """A settled deposit: specimen arrays (positions, radii), its box and what settling took."""

    positions: np.ndarray
    radii: np.ndarray
    lo: tuple
    hi: tuple
    porosity: float
    steps: int
    settling: tuple            # dem3d.SettleResult of the softened and the real stage


def rain_deposit(case: SeismicCase, rng: np.random.Generator, lo, hi, height: float, periodic_axis: int,
                 *, progress=None) -> Deposit:
    """Grains filling the box [lo, hi] (x, y) to ``height`` at the case's porosity
    (stage 1 of the module docstring). ``periodic_axis`` 1 (main model: walls at x lo/hi)
    or 0 (column: walls at y lo/hi).

    Three steps, each ended by a criterion rather than a fixed duration (rattlers keep
    bouncing at N g, so the unbalanced-force ratio alone may never converge; a bound on
    the kinetic energy per grain, in units of m g d_mean, ends a step as well):
    (a) rain: moduli / ``softening``, ``deposition_friction``, contact damping
        ``deposition_damping`` and no local damping (local damping would slow the free
        fall itself), until the kinetic energy is below ``rain_energy`` m g d per grain;
    (b) stiffen: the moduli raised to the grains' in ``_STIFFEN_STAGES`` geometric steps,
        each one shear-wave transit of the deposit long, local damping 0.7 (a single jump
        would release the soft overlaps' elastic energy at once and loosen the packing);
    (c) settle at the real contact law until the ratio is below ``settle_ratio`` or the
        kinetic energy below ``settle_energy`` m g d per grain."""
    lo = np.array([lo[0], lo[1], 0.0])
    hi = np.array([hi[0], hi[1], height])
    volume = float(np.prod(hi - lo))
    n = int(round(1.04 * (1.0 - case.porosity) * volume / mean_grain_volume(case)))   # 4 % trimmed off the top
    spec, gen_hi = _generate(case, rng, lo, hi, n, height)
    ax = periodic_axis
    side = 1 - ax                     # the walled horizontal axis
    walls = [Wall("base", plane((0, 0, 0), (0, 0, 1), mu=case.boundary_friction)),
             Wall("side_lo", plane(tuple(lo), tuple(np.eye(3)[side]), mu=0.0)),
             Wall("side_hi", plane(tuple(hi), tuple(-np.eye(3)[side]), mu=0.0))]
    rain = _deposition_law(case, case.softening, case.deposition_friction, 0.0)
    period = Periodic(ax, float(lo[ax]), float(hi[ax] - lo[ax]))
    g = (0.0, 0.0, -case.gravity)
    sim = Simulation(spec, rain, dt=time_step(case, rain, bonds=False), walls=walls, periodic=period, gravity=g,
                     direct_sums=case.direct_sums)
    fall = math.sqrt(2.0 * gen_hi[2] / case.gravity) / sim.dt        # steps of a free fall from the top
    res1 = settle(sim, ratio=case.settle_ratio, energy=settle_energy(case, n, case.rain_energy),
                  max_steps=int(4 * fall),
                  min_steps=int(fall), check_every=500)
    stiffen = 0
    for k in range(1, _STIFFEN_STAGES + 1):
        law = _deposition_law(case, case.softening ** (1.0 - k / _STIFFEN_STAGES), case.friction, 0.7)
        sim.dt = time_step(case, law, bonds=False)
        sim.set_params(law)
        todo = int(math.ceil(height / _VS_NOMINAL / sim.dt))
        sim.step(todo)
        stiffen += todo
    firm = contact_law(case, local_damping=0.7)
    sim.dt = time_step(case, firm, bonds=False)
    sim.set_params(firm)
    res2 = settle(sim, ratio=case.settle_ratio, energy=settle_energy(case, n, case.settle_energy),
                  max_steps=int(2 * fall),
                  min_steps=500, check_every=500)
    x = sim.spheres.x[np.argsort(sim.original_index)]
    r = sim.spheres.r[np.argsort(sim.original_index)]
    keep = x[:, 2] <= height
    x, r = x[keep], r[keep]
    box_lo, box_hi = lo.copy(), hi.copy()
    box_hi[2] = height - case.d_mean           # a layer clear of the trimmed surface
    n_box = _porosity(x, r, box_lo, box_hi, ax, float(hi[ax] - lo[ax]))
    return Deposit(x, r, tuple(lo), tuple(hi), n_box, res1.steps + stiffen + res2.steps, (res1, res2))


#: geometric steps from the softened to the real moduli after raining
_STIFFEN_STAGES = 8
#: shear-wave speed [m/s] setting the length of each stiffening step (one transit of the
#: deposit height; the paper's low-strain Vs, Table 1)
_VS_NOMINAL = 210.0


def _deposition_law(case: SeismicCase, softening: float, friction: float, local_damping: float):
    """Hertz-Mindlin with the grains' moduli / ``softening`` and the deposition's contact
    damping (``deposition_damping`` of critical: the grains' landing energy goes there)."""
    youngs = 2.0 * case.shear_modulus / softening * (1.0 + case.poisson)
    return hertz_mindlin(youngs, case.poisson, friction, zeta_n=case.deposition_damping,
                         zeta_s=case.deposition_damping, local_damping=local_damping)


def _generate(case: SeismicCase, rng, lo, hi, n: int, height: float):
    """n grains placed at random (``granular.cloud.loose_cloud``) in a box of the deposit's
    plan over a height that puts them at ``_GENERATION_SOLIDS`` (a looser box when a
    narrow one jams); returns the specimen and the box's top corner."""
    def top_corner(solids: float) -> np.ndarray:
        gen_hi = hi.copy()
        gen_hi[2] = height * 1.04 * (1.0 - case.porosity) / solids
        return gen_hi

    spec, solids = loose_cloud(rng, lo, top_corner,
                               (_GENERATION_SOLIDS, 0.75 * _GENERATION_SOLIDS, 0.5 * _GENERATION_SOLIDS), n,
                               *case.grains, density=case.grain_density, what=("grain_scale", case.scale))
    return spec, top_corner(solids)


def _porosity(x, r, lo, hi, axis, length) -> float:
    """Porosity of [lo, hi] from a throwaway simulation of the grains (dem3d.measure)."""
    spec = Specimen(x, r, -np.ones(len(r), np.int64), 2650.0)
    law = dem3d.linear(1.0, 1.0, 0.0)
    sim = Simulation(spec, law, dt=1e-9, periodic=Periodic(axis, float(lo[axis]), length), gravity=(0, 0, 0))
    return dem3d.measure.porosity(sim, lo, hi, cells_per_radius=4)


class Model(NamedTuple):
    """The main model's specimen with the wall in place (stage 2), ready to simulate.

    positions, radii:  (n,) specimen arrays, soil first then wall balls
    wall:              specimen indices of the wall balls
    wall_row, wall_sheet: (nw,) row (along z, 0 at the toe) and sheet (0 front, 1 back) per wall ball
    base_layer:        specimen indices of grains glued to the base (a rough base [A])
    """

    positions: np.ndarray
    radii: np.ndarray
    wall: np.ndarray
    wall_row: np.ndarray
    wall_sheet: np.ndarray
    base_layer: np.ndarray


def wall_balls(case: SeismicCase) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centres of the sheet pile's balls (square array: sheets at x = D/2, 3D/2, rows
    along z from the toe, columns along y), with row and sheet of each."""
    d = case.wall_ball
    rows = int(round(case.wall_length / d))
    cols = int(round(case.width / d))
    r_idx, c_idx, s_idx = np.meshgrid(np.arange(rows), np.arange(cols), np.arange(2), indexing="ij")
    x = (s_idx.ravel() + 0.5) * d
    y = (c_idx.ravel() + 0.5) * d
    z = case.toe + (r_idx.ravel() + 0.5) * d
    return np.stack([x, y, z], axis=1), r_idx.ravel(), s_idx.ravel()


def install_wall(case: SeismicCase, deposit: Deposit) -> Model:
    """Stage 2a: remove the grains overlapping the wall and put the wall balls in (the
    soil still level on both sides)."""
    x, r = deposit.positions, deposit.radii
    d = case.wall_ball
    t = 2.0 * d
    top = case.toe + int(round(case.wall_length / d)) * d
    in_wall = (x[:, 0] + r > 0.0) & (x[:, 0] - r < t) & (x[:, 2] + r > case.toe) & (x[:, 2] - r < top)
    x, r = x[~in_wall], r[~in_wall]
    wx, row, sheet = wall_balls(case)
    positions = np.concatenate([x, wx])
    radii = np.concatenate([r, np.full(len(wx), 0.5 * d)])
    wall = np.arange(len(x), len(positions))
    base_layer = np.nonzero(x[:, 2] - r < 0.1 * case.d_mean)[0]
    return Model(positions, radii, wall, row, sheet, base_layer)


def excavate(case: SeismicCase, model: Model, positions: np.ndarray) -> Model:
    """Stage 2b: the model at ``positions`` (specimen order) without the grains in front
    of the wall whose centres lie above the dredge line (``front_height``)."""
    n = len(model.radii)
    soil = np.ones(n, bool)
    soil[model.wall] = False
    gone = soil & (positions[:, 0] < 0.0) & (positions[:, 2] > case.front_height)
    keep = ~gone
    new_index = np.cumsum(keep) - 1
    return Model(positions[keep], model.radii[keep], new_index[model.wall], model.wall_row, model.wall_sheet,
                 new_index[model.base_layer[keep[model.base_layer]]])


def lateral_edges(case: SeismicCase, height: float) -> np.ndarray:
    """Slice edges [m] of a free-field boundary of soil height ``height``: slices of
    ``slice_grains`` mean diameters from the base, the top one reaching a grain above
    the surface."""
    h = case.slice_grains * case.d_mean
    k = max(1, int(round(height / h)))
    edges = np.linspace(0.0, height, k + 1)
    edges[-1] = height + case.d_mean
    return edges


def boundary_walls(case: SeismicCase, base_motion=None) -> list[Wall]:
    """Base (fixed or shaken) and the two stacks of free-field segments: "L<k>" at
    x = -front (soil height front_height), "R<k>" at x = t + behind (retained_height)."""
    t = 2.0 * case.wall_ball
    base = Wall("base", plane((0, 0, 0), (0, 0, 1), mu=case.boundary_friction),
                base_motion if base_motion is not None else dem3d.FIXED)
    left = free_field_walls("L", (-case.front, 0.0, 0.0), (1, 0, 0), lateral_edges(case, case.front_height),
                            case.width, mu=case.boundary_friction, unbounded_width=True)
    right = free_field_walls("R", (t + case.behind, 0.0, 0.0), (-1, 0, 0),
                             lateral_edges(case, case.retained_height), case.width, mu=case.boundary_friction,
                             unbounded_width=True)
    return [base] + left + right


def build_main(case: SeismicCase, model: Model, *, local_damping: float = 0.7, walls=None) -> Simulation:
    """The main simulation: soil and wall, the wall balls at their density and bonded,
    the base layer glued to the base, periodic across y, gravity N g."""
    law = contact_law(case, local_damping=local_damping)
    spec = Specimen(model.positions, model.radii, -np.ones(len(model.radii), np.int64), case.grain_density)
    sim = Simulation(spec, law, dt=time_step(case, law), walls=walls or boundary_walls(case),
                     periodic=Periodic(1, 0.0, case.width), gravity=(0.0, 0.0, -case.gravity),
                     direct_sums=case.direct_sums)
    sim.set_density(model.wall, wall_ball_density(case))
    prm = calibrate_strip(wall_youngs_effective(case), 2.0 * case.wall_ball)
    sim.make_bonds(1e-3 * case.wall_ball, kn=prm.kn, ks=prm.ks, spheres=model.wall)
    sim.dt = time_step(case, law)
    sim.attach_to_wall(model.base_layer, "base")
    return sim


def base_motion(case: SeismicCase, t0: float):
    """The base's shaking in model units starting at model time ``t0``: a(t) = N A_g g
    env(t) sin(2 pi N f t) (``dem3d.sine_ramp``, baseline-corrected), delayed by t0."""
    m = case.scale_N
    tab = dem3d.sine_ramp(case.model_amplitude, case.model_frequency, case.ramp_s / m, case.hold_s / m,
                          case.decay_s / m)
    if t0 <= 0.0:
        return dem3d.shaking(tab), tab
    # at rest until t0 (the baseline correction's constant starts with the motion)
    shifted = dem3d.AccelerationTable(np.concatenate([[0.0, t0 * (1.0 - 1e-9)], tab.times + t0]),
                                      np.concatenate([np.zeros((2, 3)), tab.accel]))
    return dem3d.shaking(shifted), shifted
