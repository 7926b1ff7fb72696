"""Periodic boundary: particles wrap, none is lost, and momentum along the axis is conserved."""

import numpy as np

from dem3d import Periodic, Simulation, Wall, box, frame, linear
from dem3d import prep


def test_periodic_wrap_conserves_particle_count_and_momentum():
    """A frictional, damped gas of spheres and clumps streaming along the periodic y axis
    between frictionless walls (x, z): internal forces cancel pairwise and the walls push
    only along x and z, so the y momentum is conserved (to round-off) while spheres cross
    the boundary many times; every sphere stays in the periodic cell after wrapping."""
    rng = np.random.default_rng(4)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.3, 0.3, 0.3])
    spec = prep.random_specimen(rng, lo, hi, 150, 0.03, 0.04, clump_fraction=0.2)
    n = len(spec.radii)
    vel = rng.normal(0.0, 0.3, (n, 3)) + [0.0, 2.0, 0.0]
    spec = spec._replace(velocities=vel)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5, zeta_n=0.2, zeta_s=0.2), dt=2e-5, gravity=(0, 0, 0),
                     walls=[Wall("box", box(lo, hi, mu=0.0, top=True, periodic_axis=1))],
                     periodic=Periodic(1, 0.0, 0.3))

    def y_momentum():
        sph, clu = sim.spheres, sim.clumps
        free = sph.clump < 0
        return float(np.sum(sph.v[free, 1] / sph.inv_m[free]) + np.sum(clu.v[:, 1] / clu.inv_m))

    p0 = y_momentum()
    scale = float(np.sum(np.abs(sim.spheres.v[:, 1]) / sim.spheres.inv_m))
    travelled = np.zeros(n)
    for _ in range(20):
        y_before = frame(sim).positions[:, 1]        # specimen order: the engine may re-sort
        sim.step(500)
        dy = frame(sim).positions[:, 1] - y_before
        travelled += dy - 0.3 * np.round(dy / 0.3)        # unwrap the jumps of the wrap
    sim._rebuild()                                          # wrap everything now
    free = sim.spheres.clump < 0
    y = np.concatenate([sim.spheres.x[free, 1], sim.clumps.x[:, 1]])   # whole clumps wrap by centre
    assert sim.n_spheres == n
    assert np.all(np.isfinite(sim.spheres.x))
    assert np.all((y >= 0.0) & (y < 0.3))
    assert np.count_nonzero(np.abs(travelled) > 0.3) > n // 2      # most crossed at least once
    assert sim.n_rebuilds > 10
    assert abs(y_momentum() - p0) < 1e-12 * scale
