"""Sphere and two-sphere clump on an inclined wall panel: stick or slide (Coulomb)."""

import math

import numpy as np
import pytest

from dem3d import Simulation, Wall, linear, plane

from conftest import single_specimen, sphere_mass

R = 0.02
RHO = 2650.0
G = 9.81
MU = 0.4
KN = 1e6


def incline(theta, centres_along_slope, clump=None, lock_rotation=False):
    """An unbounded plane through the origin with normal n = (-sin t, 0, cos t), gravity
    -z, spheres touching it at the given downhill offsets. Returns (sim, downhill unit)."""
    n = np.array([-math.sin(theta), 0.0, math.cos(theta)])
    down = -np.array([math.cos(theta), 0.0, math.sin(theta)])   # gravity's in-plane direction
    pos = [R * n + s * down for s in centres_along_slope]
    spec = single_specimen(pos, R, RHO, clump=clump)
    m = sphere_mass(R, RHO)
    sim = Simulation(spec, linear(KN, 0.4 * KN, 0.9, zeta_n=0.5, zeta_s=0.5),
                     dt=0.05 * math.sqrt(m / KN), walls=[Wall("slope", plane((0, 0, 0), n, mu=MU))])
    if lock_rotation:
        sim.lock(rotation=True)
    return sim, down


def downhill_motion(sim, down, settle_steps=4000, measure_steps=4000):
    """(displacement, mean acceleration) of the centre of mass along ``down`` over the
    measuring window, after the normal transient has decayed (exp(-zeta omega t) = e^-100)."""
    sim.step(settle_steps)
    x0 = sim.spheres.x.mean(axis=0) @ down
    v0 = sim.spheres.v.mean(axis=0) @ down
    t0 = sim.time
    sim.step(measure_steps)
    return sim.spheres.x.mean(axis=0) @ down - x0, (sim.spheres.v.mean(axis=0) @ down - v0) / (sim.time - t0)


@pytest.mark.parametrize("case", ["locked sphere", "clump"])
def test_sticks_below_and_slides_above_the_friction_angle(case):
    """Coulomb: a non-rolling body on a plane of friction mu sticks if tan(theta) < mu and
    slides with a = g (sin theta - mu cos theta) if tan(theta) > mu. The clump (two spheres,
    overlap of one radius, axis downhill) cannot roll; the sphere has its rotation locked."""
    for ratio, sliding in ((0.9, False), (1.1, True)):
        theta = math.atan(ratio * MU)
        if case == "clump":
            sim, down = incline(theta, [0.0, R], clump=[0, 0])
        else:
            sim, down = incline(theta, [0.0], lock_rotation=True)
        moved, accel = downhill_motion(sim, down)
        if sliding:
            assert accel == pytest.approx(G * (math.sin(theta) - MU * math.cos(theta)), rel=1e-4)
        else:
            assert abs(moved) < 1e-9
            assert abs(accel) < 1e-6


def test_free_sphere_rolls_with_five_sevenths_g_sin_theta():
    """A free uniform sphere rolls without slipping when tan(theta) < 7/2 mu, with
    a = 5/7 g sin(theta) (I = 2/5 m r^2). The contact lever is r - delta/2, so the
    expected value holds to ~delta/r ~ 1e-4 here (delta = m g cos(theta) / kn)."""
    theta = math.atan(0.5 * 3.5 * MU)
    sim, down = incline(theta, [0.0])
    _, accel = downhill_motion(sim, down)
    assert accel == pytest.approx(5.0 / 7.0 * G * math.sin(theta), rel=1e-3)


def test_free_sphere_slips_above_seven_halves_mu():
    """Above tan(theta) = 7/2 mu friction cannot enforce rolling: the centre accelerates at
    g (sin theta - mu cos theta) and the spin at 5 mu g cos(theta) / (2 r)."""
    theta = math.atan(1.3 * 3.5 * MU)
    sim, down = incline(theta, [0.0])
    sim.step(4000)
    w0 = np.linalg.norm(sim.spheres.w[0])
    t0 = sim.time
    _, accel = downhill_motion(sim, down, settle_steps=0)
    alpha = (np.linalg.norm(sim.spheres.w[0]) - w0) / (sim.time - t0)
    assert accel == pytest.approx(G * (math.sin(theta) - MU * math.cos(theta)), rel=1e-4)
    assert alpha == pytest.approx(5 * MU * G * math.cos(theta) / (2 * R), rel=2e-3)
