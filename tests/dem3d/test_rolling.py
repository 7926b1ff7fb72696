"""Rolling resistance (ContactParams.mu_roll): the constant directional torque
mu_r R* F_n of Ai et al. (2011, model A), against its closed-form spin-down."""

import math

import numpy as np
import pytest

from dem3d import Simulation, linear

from conftest import single_specimen, sphere_mass

R = 0.02
RHO = 2650.0
KN = 1e6
F0 = 50.0           # N pressing A onto B
MU_R = 0.1


def pressed_pair(omega0, mu_roll=MU_R, two_materials=False):
    """Sphere A pressed by a constant external force F0 onto sphere B (locked in
    translation and rotation), frictionless (mu = 0: no tangential force, so the
    rolling torque is A's only torque), A spinning at ``omega0`` (rad/s, (3,)).
    Zero gravity; the normal transient is damped (zeta_n = 0.7)."""
    overlap = F0 / KN
    spec = single_specimen([[2 * R - overlap, 0.0, 0.0], [0.0, 0.0, 0.0]], R, RHO)
    m = sphere_mass(R, RHO)
    law = linear(KN, 0.4 * KN, 0.0, zeta_n=0.7, mu_roll=mu_roll)
    # two materials: A rough in rolling, B not; the pair takes the pair table's value
    mats = dict(materials=[law, law._replace(mu_roll=2 * mu_roll)], material_pairs={(0, 1): law},
                sphere_material=[0, 1]) if two_materials else {}
    sim = Simulation(spec, law, dt=0.05 * math.sqrt(m / KN), walls=[], gravity=(0.0, 0.0, 0.0), **mats)
    sim.lock([1], translation=True, rotation=True)
    sim.set_external_force(np.array([[-F0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    sim.spheres.w[np.argsort(sim.original_index)[0]] = omega0
    return sim


def spin_of_a(sim):
    return sim.spheres.w[np.argsort(sim.original_index)[0]].copy()


@pytest.mark.parametrize("two_materials", [False, True])
def test_rolling_spin_decelerates_at_mu_r_r_star_fn_over_i_and_stops(two_materials):
    """Model A: I dw/dt = -mu_r R* F_n with R* = R/2 for equal spheres, so a spin w0
    about an axis normal to the contact normal falls linearly and stops at
    t* = w0 I / (mu_r R* F_n); then it stays at rest (no sign flipping)."""
    inertia = 0.4 * sphere_mass(R, RHO) * R ** 2
    rate = MU_R * (R / 2) * F0 / inertia                      # rad/s^2
    omega0 = 0.6 * rate * 0.05                                # stops at t* = 0.03 s
    sim = pressed_pair(np.array([0.0, 0.0, omega0]), two_materials=two_materials)
    n = int(0.02 / sim.dt)
    sim.step(n)
    # F_n = F0 to within the damped normal transient (its kick shows in the first steps)
    assert spin_of_a(sim)[2] == pytest.approx(omega0 - rate * sim.time, rel=2e-3)
    sim.step(n)                                               # to 0.04 s, past t*
    assert np.all(np.abs(spin_of_a(sim)) < 1e-12)


def test_twist_about_the_normal_meets_no_rolling_torque():
    """Only the rolling part of the relative spin is resisted (model A has no twisting
    term): a spin about the contact normal is kept."""
    sim = pressed_pair(np.array([3.0, 0.0, 0.0]))
    sim.step(2000)
    assert spin_of_a(sim)[0] == pytest.approx(3.0, rel=1e-12)


def test_no_rolling_resistance_keeps_the_spin():
    """mu_r = 0: the frictionless pair exerts no torque at all."""
    sim = pressed_pair(np.array([0.0, 0.0, 3.0]), mu_roll=0.0)
    sim.step(2000)
    assert spin_of_a(sim)[2] == pytest.approx(3.0, rel=1e-12)


def test_a_state_saved_before_rolling_resistance_loads_without_it():
    """States written before ContactParams.mu_roll existed (no ``params.mu_roll``, an
    11-slot material table) load with mu_r = 0, so cached runs stay usable."""
    from dem3d import material_table
    sim = pressed_pair(np.zeros(3))
    arrays = sim.to_arrays()
    del arrays["params.mu_roll"]
    arrays["materials"] = material_table([sim.params])[:, :, :11]
    old = Simulation.from_arrays(arrays, walls=[])
    assert old.params.mu_roll == 0.0 and old.mtab.shape == (1, 1, 12) and old.mtab[0, 0, 11] == 0.0
