"""``Simulation(direct_sums=True)``: each pair's force on its second sphere added to that
sphere in the contact pass, slab by slab (kernels ``pair_forces``, ``direct``).

What is checked, and against what:
- every pair's own force is the one the rows give, bit for bit (the same law on the same
  state), and each sphere's total differs only by the order of its sums: within
  1e-12 of the largest force (IEEE rounding of some tens of terms is ~1e-15);
- the result does not depend on the thread count (the slabs of one phase never write the
  same sphere), with clumps and walls, with Hertz-Mindlin and rolling resistance, and
  periodic along z with an odd number of cell layers (the last joins the one below);
- a run split by a checkpoint ends where the unbroken run ends, and the option switched
  on a running simulation moves the force rows with it.
The thread test cannot be relied on to catch a race on systems this small, so the
colouring's premise is checked on its own: every listed pair's second sphere lies in its
first sphere's slab or the next (cyclically), and no two slabs of one phase meet.
"""

import io

import numba
import numpy as np
import pytest

from dem3d import Periodic, Simulation, Wall, box, hertz_mindlin, linear, prep, rotation, segmented_wall


def walls_and_clumps(direct_sums, spheres_per_thread=4000):
    """Spheres and clumps, periodic along y, a wall rotating about its base (as
    test_determinism.build)."""
    rng = np.random.default_rng(2)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.4, 0.2, 0.4])
    spec = prep.random_specimen(rng, lo, hi, 150, 0.03, 0.045, clump_fraction=0.3)
    spec = spec._replace(velocities=rng.normal(0.0, 1.0, (len(spec.radii), 3)))
    walls = [Wall("box", box(lo, (0.4, 0.2, 1.0), mu=0.2, periodic_axis=1)),
             Wall("wall", segmented_wall((0.0, 0.1, 0.0), (1, 0, 0), (0, 0, 1), 0.2, 0.4, 4, mu=0.4,
                                         unbounded_width=True), rotation((0.0, 0.1, 0.0), (0, 1, 0), -0.5))]
    return Simulation(spec, linear(1e5, 4e4, 0.5, zeta_n=0.3, zeta_s=0.2), dt=3e-5, walls=walls,
                      periodic=Periodic(1, 0.0, 0.2), spheres_per_thread=spheres_per_thread, sort_every=5,
                      direct_sums=direct_sums)


def rolling_periodic_z(direct_sums, spheres_per_thread=4000):
    """Hertz-Mindlin with rolling resistance, periodic along z over 9 cell layers (0.52 m
    / (2 r_max + skin), r_max just under 0.0225 m, skin 0.01 m), walls on x and y, gravity
    along -x: a pile against x = 0 continuous across z = 0."""
    rng = np.random.default_rng(5)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.3, 0.3, 0.52])
    spec = prep.random_specimen(rng, lo, hi, 160, 0.03, 0.045)
    spec = spec._replace(velocities=rng.normal(0.0, 2.0, (len(spec.radii), 3)))
    walls = [Wall("box", box(lo, hi, mu=0.3, periodic_axis=2))]
    return Simulation(spec, hertz_mindlin(7e7, 0.25, 0.5, zeta_n=0.1, zeta_s=0.1, mu_roll=0.2), dt=2e-5,
                      walls=walls, periodic=Periodic(2, 0.0, 0.52), gravity=(-40.0, 0.0, 0.0), skin=0.01,
                      spheres_per_thread=spheres_per_thread, sort_every=5, direct_sums=direct_sums)


BUILDS = {"walls_and_clumps": walls_and_clumps, "rolling_periodic_z": rolling_periodic_z}


def assert_same(a, b):
    assert a.keys() == b.keys()
    for k in a:
        assert np.array_equal(a[k], b[k]), k


@pytest.mark.parametrize("name", list(BUILDS))
def test_the_same_forces_as_the_rows_to_rounding(name):
    sim = BUILDS[name](False)
    sim.step(8000)                     # the piles have formed
    arrays = sim.to_arrays()
    walls = BUILDS[name](False).walls.walls
    rows = Simulation.from_arrays(arrays, walls=walls)
    direct = Simulation.from_arrays(arrays, walls=walls)
    direct.direct_sums = True
    f_rows, t_rows = rows.evaluate_forces()
    f_direct, t_direct = direct.evaluate_forces()
    touching = rows.pairs.active[:rows.pairs.start[-1]] > 0
    assert touching.sum() > 20
    by_pair_rows = rows.pairs.pf[rows.pair_rows()[touching]][:, [0, 1, 2, 6]]
    by_pair_direct = direct.pairs.pf[direct.pair_rows()[touching]][:, [0, 1, 2, 6]]
    assert np.array_equal(by_pair_rows, by_pair_direct)
    assert np.abs(f_direct - f_rows).max() <= 1e-12 * np.abs(f_rows).max()
    assert np.abs(t_direct - t_rows).max() <= 1e-12 * np.abs(t_rows).max()


@pytest.mark.parametrize("name", list(BUILDS))
def test_a_pair_lies_in_one_slab_or_the_next(name):
    sim = BUILDS[name](True)
    for _ in range(6):
        sim.step(500)                  # rebuilds and re-sorts (sort_every 5) in between
        prs = sim.pairs
        n_slabs = prs.slab_start.shape[0] - 1
        slab = np.empty(sim.n_spheres, np.int64)
        slab[prs.slab_sphere] = np.repeat(np.arange(n_slabs), np.diff(prs.slab_start))
        i = np.repeat(np.arange(sim.n_spheres), np.diff(prs.start))
        step = (slab[prs.nbr[:prs.start[-1]]] - slab[i]) % n_slabs
        assert np.isin(step, (0, 1)).all()
        assert n_slabs % 2 == 0 or sim.periodic is None or sim.periodic.axis != 2
    if name == "rolling_periodic_z":
        assert ((slab[i] == n_slabs - 1) & (step == 1)).any()       # pairs across z = 0 exist


@pytest.mark.parametrize("name", list(BUILDS))
def test_independent_of_thread_count(name):
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("needs two numba threads")
    if name == "rolling_periodic_z":
        sim = BUILDS[name](True)
        layers = int(0.52 // (2.0 * sim.spheres.r.max() + sim.skin))
        assert layers % 2 == 1 and sim.pairs.slab_start.shape[0] - 1 == layers - 1    # the last joined
    runs = []
    for threads in (1, 2):
        numba.set_num_threads(threads)
        sim = BUILDS[name](True, spheres_per_thread=1)
        sim.step(1500)
        assert sim.n_rebuilds > 0 and np.count_nonzero(sim.pairs.active) > 5
        runs.append(sim.to_arrays())
    assert_same(runs[0], runs[1])


def test_checkpoint_and_resume_equals_one_run():
    whole = walls_and_clumps(True)
    whole.step(1500)
    first = walls_and_clumps(True)
    first.step(700)
    buf = io.BytesIO()
    np.savez(buf, **first.to_arrays())
    buf.seek(0)
    resumed = Simulation.from_arrays(dict(np.load(buf)), walls=walls_and_clumps(True).walls.walls)
    assert resumed.direct_sums
    resumed.step(800)
    assert_same(whole.to_arrays(), resumed.to_arrays())


def test_switching_moves_the_force_rows():
    """Switched both ways between steps, the measurements read the same forces, and a run
    that switches on and off again before its next step continues bit for bit."""
    sim = walls_and_clumps(False)
    sim.step(8000)
    twin = Simulation.from_arrays(sim.to_arrays(), walls=walls_and_clumps(False).walls.walls)
    touching = sim.pairs.active[:sim.pairs.start[-1]] > 0
    before = sim.pairs.pf[sim.pair_rows()[touching]][:, [0, 1, 2, 6]]
    sim.direct_sums = True
    assert np.array_equal(sim.pairs.pf[sim.pair_rows()[touching]][:, [0, 1, 2, 6]], before)
    sim.direct_sums = False
    assert np.array_equal(sim.pairs.pf[sim.pair_rows()[touching]][:, [0, 1, 2, 6]], before)
    sim.step(300)
    twin.step(300)
    assert_same(sim.to_arrays(), twin.to_arrays())
