"""Specimen generation, settling and measurements."""

import math

import numpy as np
import pytest

from dem3d import Periodic, Simulation, Specimen, Wall, box, frame, linear
from dem3d import measure, prep


def test_random_specimen_has_no_overlaps_and_the_requested_clumps():
    rng = np.random.default_rng(9)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.5, 0.3, 0.6])
    spec = prep.random_specimen(rng, lo, hi, 400, 0.03, 0.05, clump_fraction=0.25, clump_overlap=1.0)
    labels = spec.clump
    n_clumps = len(set(labels[labels >= 0]))
    assert n_clumps == 100
    assert len(spec.radii) == 400 + 100
    assert np.all(spec.positions - spec.radii[:, None] >= lo - 1e-12)
    assert np.all(spec.positions + spec.radii[:, None] <= hi + 1e-12)
    assert np.all((spec.radii >= 0.015) & (spec.radii <= 0.025))
    d = np.linalg.norm(spec.positions[:, None] - spec.positions[None], axis=2)
    touch = spec.radii[:, None] + spec.radii[None]
    mates = (labels[:, None] == labels[None]) & (labels[:, None] >= 0)
    np.fill_diagonal(mates, True)
    assert np.all(d[~mates] >= touch[~mates])
    # clump mates overlap by one radius: centre distance = r
    i = np.nonzero(labels >= 0)[0][::2]
    np.testing.assert_allclose(np.linalg.norm(spec.positions[i] - spec.positions[i + 1], axis=1),
                               spec.radii[i], rtol=1e-12)


def test_same_seed_same_specimen():
    a = prep.random_specimen(np.random.default_rng(1), (0, 0, 0), (0.3, 0.3, 0.3), 50, 0.03, 0.04,
                             clump_fraction=0.5)
    b = prep.random_specimen(np.random.default_rng(1), (0, 0, 0), (0.3, 0.3, 0.3), 50, 0.03, 0.04,
                             clump_fraction=0.5)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.clump, b.clump)


@pytest.mark.parametrize("clump_fraction", [0.0, 1.0])
def test_porosity_counts_every_grain_once(clump_fraction):
    """Grains wholly inside the measuring box: porosity = 1 - V_solid / V_box exactly, with
    V_solid = sum 4/3 pi r^3 for spheres, and 2 (4/3 pi r^3) - V_lens per two-sphere clump
    with overlap of one radius (d = r: V_lens = 5 pi r^3 / 12, MathWorld Sphere-Sphere
    Intersection). The grid error of one sphere is ~ (h/r)^1.5 ~ 4 % at 8 cells per radius
    (lattice-point counting) and averages out over the 100-200 spheres to ~4e-3 of the solid
    volume, i.e. ~5e-4 in porosity (solid fraction ~0.1); tolerance 2e-3."""
    rng = np.random.default_rng(12)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.3, 0.25, 0.3])
    spec = prep.random_specimen(rng, lo, hi, 100, 0.03, 0.04, clump_fraction=clump_fraction)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5), dt=1e-5, gravity=(0, 0, 0))
    r = spec.radii
    if clump_fraction:
        first = r[::2]
        solid = float(np.sum(2 * 4 / 3 * np.pi * first ** 3 - 5 * np.pi * first ** 3 / 12))
    else:
        solid = float(np.sum(4 / 3 * np.pi * r ** 3))
    expected = 1 - solid / np.prod(hi - lo)
    assert measure.porosity(sim, lo, hi) == pytest.approx(expected, abs=2e-3)


def test_settle_reaches_the_unbalanced_force_ratio_and_the_pile_is_static():
    """settle() stops when PFC's ratio-average (mean |F_unbalanced| / mean |F_contact|)
    falls below the threshold. Then the vertical reactions of all panels balance the
    weight up to the summed unbalanced forces, which by that definition are at most
    ratio x mean contact force x number of bodies."""
    rng = np.random.default_rng(5)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.3, 0.2, 0.4])
    spec = prep.random_specimen(rng, lo, hi, 150, 0.03, 0.045, clump_fraction=0.3)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5, zeta_n=0.3, zeta_s=0.3), dt=4e-5,
                     walls=[Wall("box", box(lo, (0.3, 0.2, 1.0), mu=0.3, periodic_axis=1))],
                     periodic=Periodic(1, 0.0, 0.2))
    trace = []
    result = prep.settle(sim, ratio=1e-3, check_every=1000, max_steps=200_000, trace=trace)
    assert result.converged and result.ratio < 1e-3
    assert measure.unbalanced_force_ratio(sim) == result.ratio
    # the trace is every check: only its last ratio is below the threshold
    assert [row[0] for row in trace] == list(range(1000, result.steps + 1, 1000))
    assert trace[-1][1:] == (result.ratio, result.kinetic_energy)
    assert all(row[1] >= 1e-3 for row in trace[:-1])
    weight = 9.81 * sim.body_masses().sum()
    f = frame(sim)
    n_bodies = len(sim.body_masses())
    prs, wps = sim.pairs, sim.wall_pairs
    pair_f = np.linalg.norm(prs.pf[sim.pair_rows()[prs.active[:prs.start[-1]] > 0], :3], axis=1)
    wall_f = np.linalg.norm(wps.out[:wps.start[-1]][wps.active[:wps.start[-1]] > 0, :3], axis=1)
    mean_contact = float(np.mean(np.concatenate([pair_f, wall_f])))
    bound = result.ratio * n_bodies * mean_contact      # = sum over bodies of |F_unbalanced|
    assert abs(-f.panel_force[:, 2].sum() - weight) <= bound
    assert bound < 0.05 * weight


def test_settle_stops_on_the_kinetic_energy_bound_when_the_ratio_is_out_of_reach():
    """With ``energy`` settle() also stops at the first check where the kinetic energy
    (dem3d.measure.kinetic_energy) is below the bound, as a deposit whose rattlers hold
    the ratio up must: every earlier check was above it, the returned energy is the
    state's. Without the bound the same run does not converge (ratio 1e-12 is never met)."""
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.3, 0.2, 0.4])

    def pile():
        spec = prep.random_specimen(np.random.default_rng(5), lo, hi, 150, 0.03, 0.045)
        return Simulation(spec, linear(1e5, 4e4, 0.5, zeta_n=0.3, zeta_s=0.3), dt=4e-5,
                          walls=[Wall("box", box(lo, (0.3, 0.2, 1.0), mu=0.3, periodic_axis=1))],
                          periodic=Periodic(1, 0.0, 0.2))
    sim = pile()
    bound = 1e-4 * 150 * 2650 * math.pi / 6 * 0.0375 ** 3 * 9.81 * 0.0375      # 1e-4 N m g d [J]
    trace = []
    result = prep.settle(sim, ratio=1e-12, energy=bound, check_every=1000, max_steps=200_000, trace=trace)
    assert result.converged and result.kinetic_energy < bound
    assert result.kinetic_energy == measure.kinetic_energy(sim)
    assert all(row[2] >= bound for row in trace[:-1])
    capped = prep.settle(pile(), ratio=1e-12, check_every=1000, max_steps=result.steps)
    assert not capped.converged


def test_force_chains_keep_contacts_above_the_mean():
    rng = np.random.default_rng(1)
    a = rng.random((20, 3))
    b = a + 0.01
    f = rng.random(20)

    class F:
        contact_a, contact_b, contact_force = a, b, f
    sa, sb, sf = measure.force_chains(F, "mean")
    assert np.all(sf > f.mean()) and len(sf) == np.count_nonzero(f > f.mean())
    sa, sb, sf = measure.force_chains(F, 0.5)
    assert len(sf) == np.count_nonzero(f > 0.5)
