"""Clump mass properties against closed forms and an independent Monte Carlo estimate."""

import math

import numpy as np
import pytest

from dem3d.clumps import grid_properties, two_sphere_properties

RHO = 2650.0


def monte_carlo(centres, radii, n=2_000_000, seed=1):
    """Mass, centroid and inertia tensor of the union of balls by uniform sampling of the
    bounding box (independent of the engine's formulas), with their standard errors."""
    rng = np.random.default_rng(seed)
    centres = np.asarray(centres, float)
    radii = np.asarray(radii, float)
    lo = (centres - radii[:, None]).min(axis=0)
    hi = (centres + radii[:, None]).max(axis=0)
    p = lo + rng.random((n, 3)) * (hi - lo)
    inside = np.zeros(n, bool)
    for c, r in zip(centres, radii):
        inside |= np.sum((p - c) ** 2, axis=1) <= r * r
    box = float(np.prod(hi - lo))
    frac = inside.mean()
    q = p[inside]
    c = q.mean(axis=0)
    c_se = q.std(axis=0) / math.sqrt(len(q))
    d = np.where(inside[:, None], p - c, 0.0)
    # per-sample contribution to I_ab = rho int (|d|^2 delta_ab - d_a d_b) dV
    contrib = RHO * box * (np.sum(d * d, axis=1)[:, None, None] * np.eye(3) - d[:, :, None] * d[:, None, :])
    inertia = contrib.mean(axis=0)
    inertia_se = contrib.std(axis=0) / math.sqrt(n)
    mass_se = RHO * box * math.sqrt(frac * (1 - frac) / n)
    return (frac * box * RHO, mass_se), (c, c_se), (inertia, inertia_se)


def lens_volume(r1, r2, d):
    """Volume of the intersection of two balls (Wolfram MathWorld, Sphere-Sphere Intersection):
    pi (r1 + r2 - d)^2 (d^2 + 2 d r2 - 3 r2^2 + 2 d r1 + 6 r1 r2 - 3 r1^2) / (12 d)."""
    return math.pi * (r1 + r2 - d) ** 2 * (d * d + 2 * d * r2 - 3 * r2 ** 2 + 2 * d * r1 + 6 * r1 * r2
                                            - 3 * r1 ** 2) / (12 * d)


def test_separate_spheres_follow_the_parallel_axis_theorem():
    """Two equal balls (mass m, radius r) a distance d apart: I_axis = 2 (2/5 m r^2),
    I_perp = 2 (2/5 m r^2 + m (d/2)^2)."""
    r, d = 0.02, 0.05
    p = two_sphere_properties([0, 0, 0], r, [d, 0, 0], r, RHO)
    m = RHO * 4 / 3 * math.pi * r ** 3
    assert p.mass == pytest.approx(2 * m, rel=1e-14)
    np.testing.assert_allclose(p.centre, [d / 2, 0, 0], atol=1e-15)
    np.testing.assert_allclose(np.diag(p.inertia), [0.8 * m * r * r, 0.8 * m * r * r + 0.5 * m * d * d,
                                                    0.8 * m * r * r + 0.5 * m * d * d], rtol=1e-13)


@pytest.mark.parametrize("r1, r2, d", [(0.02, 0.02, 0.02), (0.03, 0.018, 0.025), (0.02, 0.02, 0.039)])
def test_overlapping_spheres_mass_is_union_volume(r1, r2, d):
    """Mass = rho (V1 + V2 - V_lens) with the closed-form lens volume; the overlap is
    counted once. The case (0.02, 0.02, 0.02) is Nadukuru & Michalowski's "overlap of one
    radius"."""
    p = two_sphere_properties([0, 0, 0], r1, [d, 0, 0], r2, RHO)
    union = 4 / 3 * math.pi * (r1 ** 3 + r2 ** 3) - lens_volume(r1, r2, d)
    assert p.mass == pytest.approx(RHO * union, rel=1e-12)


@pytest.mark.parametrize("r1, r2, d", [(0.02, 0.02, 0.02), (0.03, 0.018, 0.025)])
def test_overlapping_spheres_centre_and_inertia_match_monte_carlo(r1, r2, d):
    """Centre of mass and inertia tensor of the union against Monte Carlo sampling
    (2e6 points; tolerance 5 sigma of the sampling error)."""
    axis = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    c1, c2 = np.array([0.1, -0.2, 0.3]), np.array([0.1, -0.2, 0.3]) + d * axis
    p = two_sphere_properties(c1, r1, c2, r2, RHO)
    (mass, mass_se), (centre, centre_se), (inertia, inertia_se) = monte_carlo([c1, c2], [r1, r2])
    assert abs(p.mass - mass) < 5 * mass_se
    assert np.all(np.abs(p.centre - centre) < 5 * centre_se)
    assert np.all(np.abs(p.inertia - inertia) < 5 * inertia_se)
    # axisymmetric about the line of centres: the axis is a principal direction
    np.testing.assert_allclose(p.inertia @ axis, (axis @ p.inertia @ axis) * axis,
                               atol=1e-12 * np.abs(p.inertia).max())


def test_grid_quadrature_agrees_with_the_exact_two_sphere_formula():
    """The general (any number of spheres) grid quadrature converges to the exact slab
    formula; at 40 cells per radius its error is ~1e-3 (surface discretisation)."""
    c1, c2, r1, r2 = np.zeros(3), np.array([0.0, 0.0, 0.025]), 0.02, 0.015
    exact = two_sphere_properties(c1, r1, c2, r2, RHO)
    grid = grid_properties([c1, c2], [r1, r2], RHO, cells_per_radius=40)
    assert grid.mass == pytest.approx(exact.mass, rel=2e-3)
    np.testing.assert_allclose(grid.centre, exact.centre, atol=2e-3 * 0.02)
    np.testing.assert_allclose(grid.inertia, exact.inertia, atol=4e-3 * np.abs(exact.inertia).max())


def test_torque_free_clump_precesses_as_a_symmetric_top():
    """Free rotation of an axisymmetric rigid body (Landau & Lifshitz, Mechanics 33):
    L is constant, and the symmetry axis turns about L at the rate |L| / I_perp. A
    two-sphere clump spun off its principal axes must follow this; the quaternion
    integrator is second order, so the axis error after ~1 turn is ~(omega dt)^2."""
    from dem3d import Simulation, Specimen, linear
    from dem3d.walls import rotation_matrix

    r = 0.01
    pos = np.array([[0.0, 0.0, 0.0], [r, 0.0, 0.0]])      # overlap of one radius, axis along x
    sim = Simulation(Specimen(pos, np.full(2, r), np.array([0, 0]), RHO), linear(1e5, 4e4, 0.5), dt=1e-5,
                     gravity=(0, 0, 0))
    props = two_sphere_properties(pos[0], r, pos[1], r, RHO)
    i_perp = props.inertia[1, 1]
    omega0 = np.array([40.0, 30.0, 0.0])                    # rad/s, tilted from the axis
    ang_mom = props.inertia @ omega0
    sim.clumps.am[0] = ang_mom
    axis0 = pos[1] - pos[0]
    axis0 /= np.linalg.norm(axis0)
    steps = 10_000
    sim.step(steps)
    t = sim.time
    axis = sim.spheres.x[1] - sim.spheres.x[0]
    axis /= np.linalg.norm(axis)
    rate = np.linalg.norm(ang_mom) / i_perp
    expected = rotation_matrix(ang_mom / np.linalg.norm(ang_mom), rate * t) @ axis0
    assert rate * t > 3.0                                      # about half a turn or more
    np.testing.assert_allclose(sim.clumps.am[0], ang_mom, rtol=1e-14)
    np.testing.assert_allclose(axis, expected, atol=1e-6)
