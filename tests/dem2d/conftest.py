"""Shared reduced-size specimens for the dem2d physics tests.

Reduced size = Khosravi et al.'s geometry (box 220 x 400 mm, 40 panels of 10 mm, H = 0.3 m)
with every grain 5 times coarser (D50 = 5.8 mm, ~2.4k disks), so one pluviation takes
well under a minute. The settled specimen is built once per session and handed out as
snapshot bytes; each test restores its own copy.
"""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from dem2d.params import Solver
from dem2d.pluviation import Pluviation
from studies.khosravi.run import KhosraviRun
from studies.khosravi.case import KhosraviCase

# reading_iterations=None: the readings run at ``solver``, so a test that changes the
# solver (the sensitivity checks) changes what the wall is read with
REDUCED = KhosraviCase(particles_scale=5.0, friction=0.5, seed=7,
                       solver=Solver(dt=2e-4, iterations=10), reading_iterations=None,
                       pluviation=Pluviation(layer_thickness=0.03))


@dataclass
class Settled:
    case: KhosraviCase
    blob: bytes
    backfill: object
    n_grains: int


@pytest.fixture(scope="session")
def settled_box() -> Settled:
    run = KhosraviRun(REDUCED)
    for _ in run.fill():
        pass
    run.sim.run(int(0.05 / REDUCED.solver.dt))
    return Settled(REDUCED, run.sim.snapshot(), run.backfill, len(run.sim.grains))
