"""Serial runs repeat bit for bit for a seed (threads = 1, seeded shuffled insertion)."""

import numpy as np

from dem2d.params import Solver
from dem2d.pluviation import Pluviation
from studies.khosravi.run import KhosraviRun
from studies.khosravi.case import KhosraviCase

TINY = KhosraviCase(H=0.06, particles_scale=4.0, seed=3, solver=Solver(dt=2e-4),
                    pluviation=Pluviation(layer_thickness=0.03, max_layer_time=0.1, final_settle_time=0.1))


def checkpoint_after_layer(case, layer: int) -> bytes:
    """The snapshot a fill of ``case`` takes once ``layer`` is done (then abandoned)."""
    part = KhosraviRun(case)
    for s in part.fill():
        if s.done and s.layer == layer:
            return part.sim.snapshot()
    raise AssertionError(f"the fill never finished layer {layer}")


def _fill(case):
    run = KhosraviRun(case)
    for _ in run.fill():
        pass
    return run.sim.state()


def test_same_seed_same_bits_other_seed_other_packing():
    a, b = _fill(TINY), _fill(TINY)
    assert np.array_equal(a.position, b.position)
    assert np.array_equal(a.velocity, b.velocity)
    c = _fill(TINY.__class__(**{**TINY.__dict__, "seed": 4}))
    assert c.position.shape != a.position.shape or not np.array_equal(c.position, a.position)


def test_pluviation_resumes_from_a_mid_fill_checkpoint():
    # an interrupted fill restored from the snapshot taken between layers finishes the
    # box: same height and (within a few grains per layer) the same grain count
    from dem2d.sim import restore

    case = TINY.__class__(**{**TINY.__dict__, "H": 0.09})
    full = KhosraviRun(case)
    for _ in full.fill():
        pass
    resumed = KhosraviRun(case, sim=restore(checkpoint_after_layer(case, 2)))
    layers = [s.layer for s in resumed.fill() if s.done]
    assert layers == [3]                           # layers 1-2 were skipped, not refilled
    assert abs(resumed.backfill.H - full.backfill.H) < 0.01
    assert abs(resumed.backfill.n_grains - full.backfill.n_grains) <= 0.05 * full.backfill.n_grains
