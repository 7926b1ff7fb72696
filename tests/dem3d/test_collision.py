"""Two spheres head-on: restitution and contact duration against closed forms."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from dem3d import Simulation, hertz_mindlin, linear

from conftest import single_specimen, sphere_mass

R = 0.01          # m
RHO = 2650.0      # kg/m^3


def collide(params, v_rel, dt, gap=1e-5):
    """Two equal spheres approaching at relative speed v_rel along x, no gravity.
    Returns (restitution, contact duration [s])."""
    spec = single_specimen([[0.0, 0.0, 0.0], [2 * R + gap, 0.0, 0.0]], R, RHO,
                           velocities=[[0.5 * v_rel, 0, 0], [-0.5 * v_rel, 0, 0]])
    sim = Simulation(spec, params, dt=dt, gravity=(0, 0, 0))
    touching = 0
    was_touching = False
    for _ in range(200_000):
        sim.step(1)
        now = bool(sim.pairs.active[0])
        touching += now
        if was_touching and not now:
            break
        was_touching = now
    v = sim.spheres.v
    return (v[1, 0] - v[0, 0]) / v_rel, touching * dt     # before impact v1 - v0 = -v_rel


def test_linear_restitution_and_duration_match_damped_oscillator():
    """Linear spring-dashpot, overlap obeys m* d'' + c d' + kn d = 0 while touching:
    e = exp(-zeta pi / sqrt(1 - zeta^2)), duration pi / omega_d with
    omega_d = sqrt(kn / m*) sqrt(1 - zeta^2) (e.g. Schwager & Poeschel 2007 eq. 3).
    Leapfrog error ~ omega dt ~ 1e-3 here; the duration is counted in whole steps (+-1 dt)."""
    kn, zeta = 1e5, 0.3
    m_eff = 0.5 * sphere_mass(R, RHO)
    omega_d = math.sqrt(kn / m_eff) * math.sqrt(1 - zeta ** 2)
    duration = math.pi / omega_d
    dt = duration / 4000
    e, t_c = collide(linear(kn, 0.4 * kn, 0.0, zeta_n=zeta), 1.0, dt)
    e_theory = math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2))
    assert e == pytest.approx(e_theory, rel=1e-3)
    assert abs(t_c - duration) <= 2 * dt


def test_undamped_linear_collision_is_elastic():
    """zeta = 0: the oscillator returns with the same speed, e = 1 (energy conservation)."""
    kn = 1e5
    duration = math.pi / math.sqrt(kn / (0.5 * sphere_mass(R, RHO)))
    e, t_c = collide(linear(kn, 0.4 * kn, 0.0), 1.0, duration / 2000)
    assert e == pytest.approx(1.0, abs=1e-5)
    assert abs(t_c - duration) <= 2 * duration / 2000


def test_hertz_collision_duration():
    """Undamped Hertz impact (Johnson 1985, Contact Mechanics 11.4): maximum compression
    delta* = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) and duration
    t = 2 (delta* / v) int_0^1 dx / sqrt(1 - x^(5/2)) (= 2.94 delta*/v), e = 1."""
    youngs, nu, v = 1e8, 0.3, 1.0
    params = hertz_mindlin(youngs, nu, 0.0)
    e_star = youngs / (2 * (1 - nu ** 2))
    m_eff = 0.5 * sphere_mass(R, RHO)
    r_eff = 0.5 * R
    delta_max = (15 * m_eff * v ** 2 / (16 * e_star * math.sqrt(r_eff))) ** 0.4
    integral, _ = quad(lambda x: 1.0 / math.sqrt(1.0 - x ** 2.5), 0.0, 1.0)
    duration = 2.0 * delta_max / v * integral
    dt = duration / 4000
    e, t_c = collide(params, v, dt)
    assert e == pytest.approx(1.0, abs=1e-4)
    assert abs(t_c - duration) <= 2 * dt
