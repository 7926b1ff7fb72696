"""Serial runs repeat bit for bit for a seed (threads = 1, seeded shuffled insertion)."""

import numpy as np

from dem2d.params import Solver
from dem2d.pluviation import Pluviation
from dem2d.run import KhosraviRun
from dem2d.scenarios import KhosraviCase

TINY = KhosraviCase(H=0.06, particles_scale=4.0, seed=3, solver=Solver(dt=2e-4),
                    pluviation=Pluviation(layer_thickness=0.03, max_layer_time=0.1, final_settle_time=0.1))


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
