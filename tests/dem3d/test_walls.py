"""Wall panels: loads, sign convention, shared edges, and driven motion."""

import math

import numpy as np
import pytest

from dem3d import Periodic, Ramp, Simulation, Wall, box, frame, linear, plane, rectangle, rotation, translation
from dem3d import measure, prep, with_local_damping
from dem3d.walls import rotation_matrix

from conftest import single_specimen, sphere_mass

R = 0.02
RHO = 2650.0
G = 9.81


def floor_panel(mu=0.5):
    return rectangle((0, 0, 0), (1, 0, 0), (0, 1, 0), (0.5, 0.5), mu)


def test_sphere_resting_on_a_panel_loads_it_with_its_weight():
    """Static equilibrium: the panel carries m g. Force BY the sphere ON the panel is
    (0, 0, -m g), i.e. along -normal; its moment about the panel centre is
    (c - centre) x F = (y, x offsets) x (0, 0, -m g) = (-y m g, x m g, 0)."""
    kn = 1e5
    m = sphere_mass(R, RHO)
    dt = 0.05 * math.sqrt(m / kn)
    spec = single_specimen([[0.1, 0.05, R]], R, RHO)
    sim = Simulation(spec, linear(kn, 0.4 * kn, 0.5, zeta_n=0.5, zeta_s=0.5), dt=dt,
                     walls=[Wall("floor", floor_panel())])
    sim.step(4000)   # normal oscillation decays as exp(-zeta omega t) = e^-100
    f = frame(sim)
    weight = m * G
    assert f.panel_force[0, 2] == pytest.approx(-weight, rel=1e-6)
    assert abs(f.panel_force[0, 0]) < 1e-9 * weight and abs(f.panel_force[0, 1]) < 1e-9 * weight
    assert np.dot(f.panel_force[0], f.panel_normal[0]) < 0
    np.testing.assert_allclose(f.panel_moment[0], [-0.05 * weight, 0.1 * weight, 0.0], rtol=1e-6, atol=1e-9)
    assert measure.panel_normal_stress(f)[0] == pytest.approx(weight / 1.0, rel=1e-6)   # area 1 m^2


def test_panel_force_is_the_spring_force_along_minus_normal():
    """Sign convention, undamped: a sphere moving into a wall panel (normal +x, into the
    particles) pushes it with kn delta along -normal at every step, delta = r - x."""
    kn = 1e5
    m = sphere_mass(R, RHO)
    dt = 0.02 * math.sqrt(m / kn)
    spec = single_specimen([[R + 1e-5, 0.3, 0.2]], R, RHO, velocities=[[-0.2, 0, 0]])
    wall = rectangle((0, 0.3, 0.2), (0, 1, 0), (0, 0, 1), (0.5, 0.5))   # e1 x e2 = +x
    sim = Simulation(spec, linear(kn, 0.4 * kn, 0.0), dt=dt, gravity=(0, 0, 0), walls=[Wall("w", wall)])
    xs = []
    loads = []
    for _ in range(600):
        xs.append(sim.spheres.x[0, 0])
        force, _ = sim.step(1, record_panels=True)
        loads.append(force[0, 0])
    xs = np.array(xs)
    loads = np.array(loads)
    delta = np.maximum(R - xs, 0.0)
    assert delta.max() > 1e-4                       # the sphere did press on the panel
    np.testing.assert_allclose(loads[:, 0], -kn * delta, rtol=1e-12, atol=1e-12 * kn * delta.max())
    assert np.all(loads[delta > 0, 0] < 0)


def test_shared_edge_counts_each_sphere_on_one_panel():
    """A floor of two panels with a shared edge at x = 0: spheres resting at x = -0.01,
    0 and +0.01 load the panels with 1 and 2 weights (half-open ownership [-a, a)),
    never twice (no extra edge contact)."""
    kn = 1e5
    m = sphere_mass(R, RHO)
    dt = 0.05 * math.sqrt(m / kn)
    left = rectangle((-0.25, 0, 0), (1, 0, 0), (0, 1, 0), (0.25, 0.5))
    right = rectangle((0.25, 0, 0), (1, 0, 0), (0, 1, 0), (0.25, 0.5))
    left = left.__class__(**{**left.__dict__, "shared": (False, True, False, False)})
    right = right.__class__(**{**right.__dict__, "shared": (True, False, False, False)})
    spec = single_specimen([[-0.01, -0.2, R], [0.0, 0.0, R], [0.01, 0.2, R]], R, RHO)
    sim = Simulation(spec, linear(kn, 0.4 * kn, 0.5, zeta_n=0.5, zeta_s=0.5), dt=dt,
                     walls=[Wall("floor", [left, right])])
    sim.step(4000)
    assert sim.panel_force[0, 2] == pytest.approx(-m * G, rel=1e-6)
    assert sim.panel_force[1, 2] == pytest.approx(-2 * m * G, rel=1e-6)


def test_column_in_a_box_reactions_equal_total_weight():
    """Static equilibrium of the whole specimen: the vertical reactions of the base and
    of the (frictional) side walls together carry the total weight, to 1e-3. The side
    walls take part of it (Janssen's silo effect), which the sum must include."""
    rng = np.random.default_rng(11)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.09, 0.09, 0.6])
    spec = prep.random_specimen(rng, lo, hi, 40, 0.03, 0.036)
    params = with_local_damping(linear(1e5, 4e4, 0.5, zeta_n=0.3, zeta_s=0.3), 0.7)
    m_min = sphere_mass(0.015, RHO)
    sim = Simulation(spec, params, dt=0.1 * math.sqrt(m_min / 1e5),
                     walls=[Wall("box", box(lo, (0.09, 0.09, 1.0), mu=0.4))])
    result = prep.settle(sim, ratio=1e-5, check_every=2000, max_steps=400_000)
    assert result.converged, result
    weight = sim.body_masses().sum() * G
    f = frame(sim)
    base = -f.panel_force[0, 2]
    walls = -f.panel_force[1:, 2].sum()
    assert base + walls == pytest.approx(weight, rel=1e-3)
    assert walls > 0.01 * weight           # the side walls do carry part of it


def test_rotating_wall_follows_the_closed_form_rotation():
    """Driver kinematics: omega(t) = alpha t about the y axis through P gives the angle
    theta = alpha t^2 / 2; every corner is P + R_y(theta) (c0 - P), the panel normal
    R_y(theta) n0, and the panel centre moves at omega(t) y x (c - P)."""
    alpha = 50.0           # rad/s^2
    pivot = np.array([0.2, 0.0, -0.1])
    panel = rectangle((0.0, 0.5, 1.0), (0, 1, 0), (0, 0, 1), (0.25, 0.5))
    motion = rotation(pivot, (0, 1, 0), lambda t: alpha * t)
    spec = single_specimen([[5.0, 5.0, 5.0]], R, RHO)        # far away: no contact
    sim = Simulation(spec, linear(1e5, 4e4, 0.5), dt=1e-4, gravity=(0, 0, 0),
                     walls=[Wall("wall", panel, motion)])
    c0 = frame(sim).panel_corners[0].copy()
    n0 = frame(sim).panel_normal[0].copy()
    sim.step(1000)
    t = sim.time
    theta = 0.5 * alpha * t ** 2
    rot = rotation_matrix(np.array([0.0, 1.0, 0.0]), theta)
    f = frame(sim)
    np.testing.assert_allclose(f.panel_corners[0], pivot + (c0 - pivot) @ rot.T, atol=1e-12)
    np.testing.assert_allclose(f.panel_normal[0], rot @ n0, atol=1e-12)
    centre = f.panel_corners[0].mean(axis=0)
    np.testing.assert_allclose(sim.panels.vel[0], np.cross([0, alpha * t, 0], centre - pivot), atol=1e-12)


def test_translating_wall_with_a_ramp_schedule():
    """V(t) ramps linearly to v0 over t_r, then holds: displacement v0 t_r / 2 + v0 (t - t_r)."""
    v0, t_ramp = np.array([0.01, 0.0, 0.0]), 0.05
    panel = rectangle((0.0, 0.5, 1.0), (0, 1, 0), (0, 0, 1), (0.25, 0.5))
    spec = single_specimen([[5.0, 5.0, 5.0]], R, RHO)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5), dt=1e-4, gravity=(0, 0, 0),
                     walls=[Wall("wall", panel, translation(Ramp(tuple(v0), t_ramp)))])
    sim.step(1000)
    expected = v0 * (0.5 * t_ramp + (sim.time - t_ramp))
    np.testing.assert_allclose(sim.panels.centre[0] - [0.0, 0.5, 1.0], expected, atol=1e-14)


def test_finite_panel_along_the_periodic_axis_is_refused():
    """Coordinates along a periodic axis are defined modulo the period, so a panel
    cannot end inside it (one-line InvalidParameter)."""
    from analytic.errors import InvalidParameter

    spec = single_specimen([[0.1, 0.1, 0.1]], R, RHO)
    finite = rectangle((0.0, 0.25, 0.5), (0, 1, 0), (0, 0, 1), (0.25, 0.5))
    with pytest.raises(InvalidParameter, match="periodic axis"):
        Simulation(spec, linear(1e5, 4e4, 0.5), dt=1e-5, walls=[Wall("w", finite)], periodic=Periodic(1, 0.0, 0.5))
