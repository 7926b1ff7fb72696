"""Bitwise reproducibility: repeated runs, thread counts, and checkpoint/resume."""

import io
import subprocess
import sys

import numba
import numpy as np
import pytest

from dem3d import Periodic, Simulation, Wall, box, linear, rotation, segmented_wall
from dem3d import prep


def build(seed=2, spheres_per_thread=4000, sort_every=50):
    """Spheres and clumps falling in a periodic box onto a floor, against a segmented wall
    that rotates about its base: every code path (pairs, walls, clumps, motion, wrap)."""
    rng = np.random.default_rng(seed)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.4, 0.2, 0.4])
    spec = prep.random_specimen(rng, lo, hi, 150, 0.03, 0.045, clump_fraction=0.3)
    spec = spec._replace(velocities=rng.normal(0.0, 1.0, (len(spec.radii), 3)))   # collide at once
    walls = [Wall("box", box(lo, (0.4, 0.2, 1.0), mu=0.2, periodic_axis=1)),
             Wall("wall", segmented_wall((0.0, 0.1, 0.0), (1, 0, 0), (0, 0, 1), 0.2, 0.4, 4, mu=0.4,
                                         unbounded_width=True),
                  rotation((0.0, 0.1, 0.0), (0, 1, 0), -0.5))]
    return Simulation(spec, linear(1e5, 4e4, 0.5, zeta_n=0.3, zeta_s=0.2), dt=3e-5, walls=walls,
                      periodic=Periodic(1, 0.0, 0.2), spheres_per_thread=spheres_per_thread,
                      sort_every=sort_every)


def state(sim):
    return sim.to_arrays()


def assert_same(a, b):
    assert a.keys() == b.keys()
    for k in a:
        assert np.array_equal(a[k], b[k]), k


def test_two_runs_are_bitwise_equal_and_independent_of_thread_count():
    """Every per-sphere sum is gathered in a fixed order (no shared accumulators), so the
    result does not depend on the run or on how many threads share the work."""
    runs = []
    for threads in (1, 1, min(2, numba.config.NUMBA_NUM_THREADS)):
        numba.set_num_threads(threads)
        sim = build(spheres_per_thread=1, sort_every=5)   # every thread, and re-sorting
        sim.step(1500)
        assert sim.n_rebuilds > 0 and np.count_nonzero(sim.pairs.active) > 5
        runs.append(state(sim))
    assert_same(runs[0], runs[1])
    assert_same(runs[0], runs[2])


def test_checkpoint_and_resume_equals_one_run():
    """A run split by a checkpoint (to_arrays -> .npz -> from_arrays, with the wall motion
    re-attached) ends bitwise where the unbroken run ends."""
    whole = build(sort_every=5)        # re-sorts along the way too
    whole.step(1500)
    first = build(sort_every=5)
    first.step(700)
    buf = io.BytesIO()
    np.savez(buf, **first.to_arrays())
    buf.seek(0)
    loaded = dict(np.load(buf))
    resumed = Simulation.from_arrays(loaded, walls=build().walls.walls)
    resumed.step(800)
    assert_same(state(whole), state(resumed))


def test_sorting_by_cell_changes_only_the_order_of_sums():
    """sort_by_cell permutes bodies and carries contact histories: the motion equals the
    unsorted run's up to round-off of the reordered force sums (compared after mapping
    each sphere back to its specimen index; 150 steps are too few for chaos to amplify
    1e-16 into anything visible at 1e-9 m)."""
    plain = build(sort_every=0)
    plain.step(400)
    sorted_ = build(sort_every=0)
    sorted_.step(250)
    new_to_old = sorted_.sort_by_cell()
    assert not np.array_equal(new_to_old, np.arange(sorted_.n_spheres))     # it did reorder
    sorted_.step(150)
    a = np.empty_like(plain.spheres.x)
    a[plain.original_index] = plain.spheres.x
    b = np.empty_like(sorted_.spheres.x)
    b[sorted_.original_index] = sorted_.spheres.x
    np.testing.assert_allclose(b, a, rtol=0, atol=1e-9)
    # clumps stay contiguous and whole
    for c, (s, e) in enumerate(sorted_.clumps.members):
        assert np.all(sorted_.spheres.clump[s:e] == c) and np.all(sorted_.spheres.body_id[s:e] == s)


def test_frames_keep_the_specimen_order_across_resorting():
    """Frames list spheres in the specimen's order even when the engine re-sorts: the
    radii (fixed per grain) and each clump's body id stay where the specimen put them."""
    from dem3d import frame

    sim = build(sort_every=2)
    f0 = frame(sim)
    sim.step(600)
    assert sim.n_rebuilds >= 4
    f1 = frame(sim)
    assert np.array_equal(f0.radii, f1.radii)
    assert np.array_equal(f0.body_id, f1.body_id)
    assert not np.array_equal(sim.original_index, np.sort(sim.original_index))   # it did re-sort


def test_from_arrays_does_not_share_the_callers_state():
    """Two runs started from one stored state must not see each other's steps (a settled
    specimen is shared by several wall modes)."""
    import numpy as np

    import dem3d
    spec = dem3d.Specimen(np.array([[0.5, 0.5, 0.2], [0.5, 0.5, 0.5]]), np.array([0.05, 0.05]), None, 2650.0)
    sim = dem3d.Simulation(spec, dem3d.linear(1e6, 4e5, 0.5, zeta_n=0.2), dt=1e-5,
                           walls=[dem3d.Wall("floor", dem3d.plane((0, 0, 0), (0, 0, 1), 0.5))])
    state = sim.to_arrays()
    before = {k: v.copy() for k, v in state.items()}
    a = dem3d.Simulation.from_arrays(state, walls=[dem3d.Wall("floor", dem3d.plane((0, 0, 0), (0, 0, 1), 0.5))])
    a.step(2000)
    assert all(np.array_equal(state[k], before[k]) for k in state)


def test_from_arrays_refuses_a_wall_friction_the_state_would_override():
    """The stored panel friction is restored with the state; a different friction passed
    in ``walls`` would be silently ignored, so it is refused (one-line InvalidParameter)."""
    import dem3d
    from analytic.errors import InvalidParameter
    spec = dem3d.Specimen(np.array([[0.5, 0.5, 0.2]]), np.array([0.05]), None, 2650.0)
    sim = dem3d.Simulation(spec, dem3d.linear(1e6, 4e5, 0.5, zeta_n=0.2), dt=1e-5,
                           walls=[dem3d.Wall("floor", dem3d.plane((0, 0, 0), (0, 0, 1), 0.5))])
    state = sim.to_arrays()
    with pytest.raises(InvalidParameter, match="walls"):
        dem3d.Simulation.from_arrays(state, walls=[dem3d.Wall("floor", dem3d.plane((0, 0, 0), (0, 0, 1), 0.35))])
    state["panels.mu"] = np.array([0.35])
    restored = dem3d.Simulation.from_arrays(state, walls=[dem3d.Wall("floor", dem3d.plane((0, 0, 0), (0, 0, 1), 0.35))])
    assert restored.walls.panels.mu[0] == 0.35


def _has_openmp() -> bool:
    try:
        import numba.np.ufunc.omppool  # noqa: F401
    except ImportError:
        return False
    return True


#: where libgomp is missing numba falls back to TBB or its workqueue
needs_openmp = pytest.mark.skipif(not _has_openmp(), reason="no OpenMP runtime: numba uses TBB or its workqueue")


@needs_openmp
def test_the_parallel_loops_run_on_openmp_where_it_is_installed():
    """dem3d.kernels puts numba's OpenMP layer before TBB: under TBB a process that had
    run the kernels spent minutes in tbb::finalize at exit on a busy machine (numba
    #5983, #10556)."""
    build().step(1)
    assert numba.threading_layer() == "omp"


@needs_openmp
def test_openmp_stays_first_after_a_numba_variable_changes():
    """numba re-reads its config from the environment at a compile after any NUMBA_*
    variable changed (a notebook that sets NUMBA_NUM_THREADS after import; here an
    unused variable, so the test does not depend on the caller's), restoring TBB
    first; prefer_openmp, which the engine calls before launching threads, puts OpenMP
    back. A fresh process: the layer is chosen once per process."""
    code = ("import os, numba, dem3d.kernels as k\n"
            "os.environ['NUMBA_WALLSIM_PROBE'] = '1'\n"
            "numba.njit(lambda x: x + 1)(1)\n"
            "print(numba.config.THREADING_LAYER_PRIORITY[0])\n"
            "k.prefer_openmp()\n"
            "numba.get_num_threads()\n"
            "print(numba.threading_layer())\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["tbb", "omp"]        # numba's reset happened, and was undone
