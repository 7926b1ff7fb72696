"""Energy conservation without damping or friction, and PFC local damping in free fall."""

import math

import numpy as np
import pytest

from dem3d import Simulation, Wall, box, linear, with_local_damping

from conftest import single_specimen, sphere_mass

R = 0.01
RHO = 2650.0
KN = 1e5


def dense_packing(rng, n_side=6, squeeze=0.01):
    """A jittered cubic lattice of spheres pressed together by ~1 % of a diameter inside
    a closed box, with random velocities: a dense packing with ~3 contacts per sphere."""
    a = 2 * R * (1 - squeeze)
    g = R + np.arange(n_side) * a
    x = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    x += rng.normal(0.0, 0.002 * R, x.shape)
    radii = R * (1 + rng.uniform(-0.01, 0.01, len(x)))
    v = rng.normal(0.0, 0.05, x.shape)
    hi = g[-1] + R * (1 - squeeze)
    return single_specimen(x, radii, RHO, velocities=v), hi


def total_energy(sim, v_before, v_after, pe):
    """Kinetic energy at time t from the synchronous velocity (v(t-dt/2) + v(t+dt/2))/2
    (leapfrog), plus the elastic energy at t."""
    v = 0.5 * (v_before + v_after)
    m = 1.0 / sim.spheres.inv_m
    return 0.5 * float(np.sum(m * np.sum(v * v, axis=1))) + pe


def test_energy_drift_below_1e3_over_1e4_steps_without_damping_or_friction():
    """Leapfrog is symplectic: with conservative forces (linear springs, mu = 0, no
    damping) the energy error stays bounded at O((omega dt)^2) and does not drift. The issue
    sets the bar: |E(1e4 steps) - E(0)| / E(0) < 1e-3."""
    rng = np.random.default_rng(7)
    spec, hi = dense_packing(rng)
    m = sphere_mass(R, RHO)
    dt = 0.05 * math.sqrt(m / KN)
    sim = Simulation(spec, linear(KN, 0.4 * KN, 0.0), dt=dt, gravity=(0, 0, 0),
                     walls=[Wall("box", box((0, 0, 0), (hi, hi, hi), top=True))])
    energies = []
    for block in range(11):
        pe = sim.contact_energy()
        v_before = sim.spheres.v.copy()
        sim.step(1)
        energies.append(total_energy(sim, v_before, sim.spheres.v, pe))
        if block < 10:
            sim.step(999)
    energies = np.array(energies)
    assert sim.step_count == 10_001
    assert sim.contact_energy() > 0.1 * energies[0]          # dense: springs hold energy
    assert abs(energies[-1] - energies[0]) / energies[0] < 1e-3
    assert np.max(np.abs(energies - energies[0])) / energies[0] < 1e-3


def test_local_damping_free_fall_accelerates_at_one_minus_alpha_g():
    """PFC local damping reduces the unbalanced force by alpha |F| sign(v): a body falling
    from rest (v and F both downward) accelerates at (1 - alpha) g."""
    alpha = 0.7
    spec = single_specimen([[0.0, 0.0, 1.0]], R, RHO)
    dt = 5e-5
    sim = Simulation(spec, with_local_damping(linear(KN, 0.4 * KN, 0.5), alpha), dt=dt)
    sim.step(1)           # first step: v = 0, sign(v) = 0, full g
    v1 = sim.spheres.v[0, 2]
    sim.step(1000)
    accel = (sim.spheres.v[0, 2] - v1) / (1000 * dt)
    assert v1 == pytest.approx(-9.81 * dt, rel=1e-12)
    assert accel == pytest.approx(-(1 - alpha) * 9.81, rel=1e-12)
