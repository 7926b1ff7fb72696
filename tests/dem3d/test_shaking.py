"""External force per sphere and walls driven by a displacement / acceleration history
(base shaking), against exact solutions: the leapfrog's free fall, the prescribed
history itself, and Newmark's sliding-block threshold a_peak = mu g."""

import math

import numpy as np
import pytest

from dem3d import (AccelerationTable, Simulation, Wall, history, linear, plane, rectangle, shaking,
                   sine_envelope, sine_ramp)

from conftest import single_specimen, sphere_mass

R = 0.01
RHO = 2650.0
G = 9.81


def test_external_force_adds_to_gravity_in_free_fall():
    """A free sphere under gravity g and F_ext = m a falls with g + a. The leapfrog from
    rest (v(-dt/2) = 0) gives exactly x_n = x_0 + (g + a) dt^2 n (n + 1) / 2. A two-sphere
    clump with F_ext on one member accelerates as a whole at F_ext / M."""
    m = sphere_mass(R, RHO)
    a = np.array([1.5, -0.5, 3.0])
    g = np.array([0.0, 0.0, -G])
    spec = single_specimen([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0 + 1.5 * R, 0.0, 0.0]], R, RHO,
                           clump=[-1, 0, 0])
    sim = Simulation(spec, linear(1e5, 4e4, 0.5), dt=5e-5, gravity=g, sort_by_cell=False)
    m_clump = 1.0 / sim.clumps.inv_m[0]
    f = np.zeros((3, 3))
    f[0] = m * a
    f[1] = m_clump * a            # on one member only: the clump's centre accelerates at a
    sim.set_external_force(f)
    x0 = sim.spheres.x[0].copy()
    c0 = sim.clumps.x[0].copy()
    n = 300
    sim.step(n)
    expect = (g + a) * sim.dt ** 2 * n * (n + 1) / 2
    np.testing.assert_allclose(sim.spheres.x[0] - x0, expect, rtol=1e-12)
    np.testing.assert_allclose(sim.clumps.x[0] - c0, expect, rtol=1e-10)
    sim.clear_external_force()
    v = sim.spheres.v[0].copy()
    sim.step(10)
    np.testing.assert_allclose(sim.spheres.v[0] - v, 10 * sim.dt * g, rtol=1e-12, atol=1e-15)


def test_acceleration_table_integrates_exactly():
    """Piecewise-linear a(t): v and d are its exact integrals. a = 2 t on [0, 1] gives
    v = t^2, d = t^3 / 3; a = 2 (2 - t) on [1, 2] gives v = 4 t - t^2 - 2, v(2) = 2,
    d = 1/3 + [2 t^2 - t^3 / 3 - 2 t] from 1 to t, d(2) = 2; after the table a = 0 and
    the base coasts, d(3) = 4."""
    tab = AccelerationTable([0.0, 1.0, 2.0], [0.0, 2.0, 0.0], direction=(0, 0, 1))
    for t in (0.25, 0.5, 1.0):
        assert tab.velocity(t)[2] == pytest.approx(t * t, rel=1e-14)
        assert tab.displacement(t)[2] == pytest.approx(t ** 3 / 3, rel=1e-14)
    t = 1.5
    assert tab.velocity(t)[2] == pytest.approx(4 * t - t * t - 2, rel=1e-14)
    assert tab.displacement(t)[2] == pytest.approx(1 / 3 + (2 * t * t - t ** 3 / 3 - 2 * t) - (2 - 1 / 3 - 2),
                                                   rel=1e-14)
    assert tab.velocity(2.0)[2] == pytest.approx(2.0, rel=1e-14)
    assert tab.displacement(2.0)[2] == pytest.approx(2.0, rel=1e-14)
    assert tab.displacement(3.0)[2] == pytest.approx(4.0, rel=1e-14)
    assert tab.acceleration(0.5)[2] == 1.0 and tab.acceleration(2.5)[2] == 0.0
    # a function, sampled: a = sin t on [0, pi] gives v(pi) = 2 to the trapezoid rule's
    # error pi h^2 / 12 (h = pi / 1000)
    fn = AccelerationTable.sampled(math.sin, math.pi, 1000)
    assert fn.velocity(math.pi)[0] == pytest.approx(2.0, abs=math.pi * (math.pi / 1000) ** 2 / 12 * 1.01)


def test_sine_ramp_envelope_and_baseline():
    """env rises linearly over t_up, holds, falls over t_down; the sampled sine has the
    stated peak, and the baseline correction leaves the base at rest at the end."""
    env = sine_envelope([0.0, 0.5, 1.0, 2.0, 3.5, 4.0, 5.0], 1.0, 2.0, 1.0)
    np.testing.assert_allclose(env, [0, 0.5, 1, 1, 0.5, 0, 0], atol=1e-15)
    tab = sine_ramp(2.0, 5.0, 0.4, 0.8, 0.2)
    assert np.abs(tab.accel[:, 0]).max() == pytest.approx(2.0, rel=1e-3)
    assert abs(tab.velocity(1.4)[0]) < 1e-12


def test_wall_follows_its_displacement_history_exactly():
    """A floor driven by a sinusoidal displacement D(t) = A sin(w t) (x) and by a sine-ramp
    acceleration table sits at P + D(t) after every step (to round-off), and its panel
    velocity (the contacts' wall velocity) is the mean over the last step,
    (D(t) - D(t - dt)) / dt, consistent with the spheres' leapfrog half-step velocities."""
    amp, w = 2e-3, 2 * math.pi * 7.0
    disp = lambda t: (amp * math.sin(w * t), 0.0, 0.0)                  # noqa: E731
    vel = lambda t: (amp * w * math.cos(w * t), 0.0, 0.0)               # noqa: E731
    tab = sine_ramp(3.0, 11.0, 0.05, 0.1, 0.05, direction=(0, 1, 0))
    walls = [Wall("sine", plane((0, 0, 0), (0, 0, 1)), history(disp, vel)),
             Wall("table", plane((0, 0, -1), (0, 0, 1)), shaking(tab))]
    spec = single_specimen([[0.0, 0.0, 0.5]], R, RHO)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5), dt=5e-5, walls=walls, gravity=(0, 0, 0))
    worst = 0.0
    for _ in range(40):
        sim.step(50)
        t = sim.time
        c = sim.walls.panels.centre
        worst = max(worst, abs(c[0, 0] - disp(t)[0]), abs(c[1, 1] - tab.displacement(t)[1]))
        t0 = t - sim.dt
        mean0 = (disp(t)[0] - disp(t0)[0]) / sim.dt
        mean1 = (tab.displacement(t)[1] - tab.displacement(t0)[1]) / sim.dt
        assert sim.walls.panels.vel[0, 0] == pytest.approx(mean0, rel=1e-9, abs=1e-12)
        assert sim.walls.panels.vel[1, 1] == pytest.approx(mean1, rel=1e-9, abs=1e-12)
        assert mean0 == pytest.approx(vel(t - 0.5 * sim.dt)[0], rel=1e-6, abs=1e-9)
    assert worst < 1e-15


@pytest.mark.parametrize("ratio, slides", [(0.95, False), (1.05, True)])
def test_block_on_a_shaken_rough_base_slides_above_mu_g(ratio, slides):
    """Newmark (1965): a rigid block on a base shaken at a(t) follows it while
    |a| < mu g and slides when the peak exceeds mu g. A sphere with its rotation locked
    (a block: it cannot roll) rests on a floor (mu = 0.3) shaken by a 5 Hz sine ramp of
    peak 0.95 mu g (relative displacement only the tangential spring's elastic
    m a / ks <= 0.95 mu m g / ks = 7.8e-7 m) and 1.05 mu g (slip > 20 times that)."""
    mu = 0.3
    m = sphere_mass(R, RHO)
    kn = 1e5
    tab = sine_ramp(ratio * mu * G, 5.0, 0.2, 0.6, 0.2)
    spec = single_specimen([[0.0, 0.0, R - m * G / kn]], R, RHO)
    sim = Simulation(spec, linear(kn, 0.4 * kn, mu, zeta_n=0.7, zeta_s=0.7), dt=5e-5,
                     walls=[Wall("base", plane((0, 0, 0), (0, 0, 1), mu=mu), shaking(tab))])
    sim.lock(rotation=True)
    sim.step(2000)                               # settle (still, the base starts at rest)
    x0 = sim.spheres.x[0, 0]
    d0 = tab.displacement(sim.time)[0]
    slip = 0.0
    for _ in range(200):
        sim.step(100)
        rel = sim.spheres.x[0, 0] - x0 - (tab.displacement(sim.time)[0] - d0)
        slip = max(slip, abs(rel))
    elastic = mu * m * G / (0.4 * kn)
    if slides:
        assert slip > 20 * elastic
    else:
        assert slip < 1.02 * ratio * elastic     # only the tangential spring m a / ks


def test_spheres_attached_to_a_shaken_base_follow_it_exactly():
    """Grains glued to the base (attach_to_wall) sit at x0 + D(t) after every step and
    carry the step's mean velocity; a free sphere resting on them is carried along
    below the slip threshold (a rough base)."""
    tab = sine_ramp(2.0, 8.0, 0.1, 0.2, 0.1)
    spec = single_specimen([[0.0, 0.0, R], [2 * R, 0.0, R], [R, 0.0, R + math.sqrt(3) * R + 1e-5]], R, RHO)
    sim = Simulation(spec, linear(1e5, 4e4, 0.8, zeta_n=0.5, zeta_s=0.5), dt=5e-5,
                     walls=[Wall("base", plane((0, 0, 0), (0, 0, 1), mu=0.0), shaking(tab))], sort_by_cell=False)
    sim.attach_to_wall([0, 1], "base")
    x0 = sim.spheres.x[:2].copy()
    for _ in range(80):
        sim.step(100)
        d = np.array(tab.displacement(sim.time))
        np.testing.assert_allclose(sim.spheres.x[:2], x0 + d, rtol=0, atol=1e-15)
    assert abs(sim.spheres.x[2, 0] - R - tab.displacement(sim.time)[0]) < 1e-5


def test_set_density_gives_the_balls_their_own_mass():
    """Two equal free spheres, one given density 4000 instead of 2650 (set_density): the
    same external force F accelerates them at F / m with m = rho 4/3 pi r^3 each; a
    locked sphere stays locked."""
    spec = single_specimen([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], R, RHO)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5), dt=5e-5, gravity=(0, 0, 0), sort_by_cell=False)
    sim.lock([2], translation=True, rotation=True)
    sim.set_density([1, 2], 4000.0)
    f = np.array([[1e-3, 0.0, 0.0]] * 3)
    sim.set_external_force(f)
    sim.step(1)
    assert sim.spheres.v[0, 0] == pytest.approx(1e-3 / sphere_mass(R, RHO) * sim.dt, rel=1e-12)
    assert sim.spheres.v[1, 0] == pytest.approx(1e-3 / sphere_mass(R, 4000.0) * sim.dt, rel=1e-12)
    assert sim.spheres.v[2, 0] == 0.0
