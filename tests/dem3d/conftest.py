"""Fixtures for the dem3d tests.

Most systems here are tiny (1-500 spheres): a parallel launch costs more than the work,
and on a shared 2-core machine a second thread mostly waits for a core. Results do not
depend on the thread count (dem3d.kernels docstring; test_determinism checks it), so the
tests run on one thread unless a test asks for more.
"""

import numba
import numpy as np
import pytest

from dem3d import Simulation, Specimen, linear


@pytest.fixture(autouse=True)
def one_thread():
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(before)


def sphere_mass(r, rho):
    return rho * 4.0 / 3.0 * np.pi * r ** 3


def single_specimen(positions, radii, density=2650.0, velocities=None, clump=None):
    positions = np.atleast_2d(np.asarray(positions, float))
    n = positions.shape[0]
    radii = np.broadcast_to(np.asarray(radii, float), (n,)).copy()
    clump = -np.ones(n, np.int64) if clump is None else np.asarray(clump, np.int64)
    vel = None if velocities is None else np.atleast_2d(np.asarray(velocities, float))
    return Specimen(positions, radii, clump, density, vel)
