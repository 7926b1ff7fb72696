"""Rolling resistance (ContactParams.mu_roll): the elastic-plastic rolling spring of
Ai et al. (2011, model C; LIGGGHTS epsd2), k_r = 2.25 k_n mu_r^2 R*^2 capped at
mu_r R* F_n, against its closed forms: the plastic spin-down and the elastic rocking."""

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
def test_spin_down_at_the_cap_then_rocking_on_the_rolling_spring(two_materials):
    """A spin w0 about an axis normal to the contact normal winds the rolling spring up
    to its cap M = mu_r R* F_n (R* = R/2 for equal spheres) within ~1e-4 s, then falls
    linearly at M / I until it stops at t* ~ w0 I / M; then the sphere rocks on the
    spring (no dashpot): spin amplitude M / sqrt(k_r I), period 2 pi sqrt(I / k_r),
    k_r = 2.25 kn mu_r^2 R*^2."""
    inertia = 0.4 * sphere_mass(R, RHO) * R ** 2
    cap = MU_R * (R / 2) * F0                                 # N m
    k_r = 2.25 * KN * MU_R ** 2 * (R / 2) ** 2                # N m / rad
    omega0 = 0.6 * cap / inertia * 0.05                       # stops at t* = 0.03 s
    sim = pressed_pair(np.array([0.0, 0.0, omega0]), two_materials=two_materials)
    sim.step(int(0.005 / sim.dt))
    t1, w1 = sim.time, spin_of_a(sim)[2]
    sim.step(int(0.015 / sim.dt))
    rate = (w1 - spin_of_a(sim)[2]) / (sim.time - t1)
    assert rate == pytest.approx(cap / inertia, rel=2e-3)
    sim.step(int(0.015 / sim.dt))                             # to 0.035 s, past t*
    times, spins = [], []
    for _ in range(int(4 * 2 * math.pi * math.sqrt(inertia / k_r) / sim.dt)):
        sim.step(1)
        times.append(sim.time)
        spins.append(spin_of_a(sim)[2])
    spins = np.array(spins)
    assert np.max(np.abs(spins)) == pytest.approx(cap / math.sqrt(k_r * inertia), rel=0.02)
    up = np.nonzero((spins[:-1] < 0) & (spins[1:] >= 0))[0]
    period = (times[up[-1]] - times[up[0]]) / (len(up) - 1)
    assert period == pytest.approx(2 * math.pi * math.sqrt(inertia / k_r), rel=0.02)


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
    assert old.pairs.ut.shape[1] == 3          # no rolling: the plain 3-wide history


def test_the_rolling_moment_survives_a_neighbour_list_rebuild():
    """The moment is contact history: re-sorting the spheres (a list rebuild that
    carries histories, the pair possibly listed the other way round) mid-rocking must
    leave the motion as it was (to round-off), not reset the spring."""
    runs = []
    for resort in (False, True):
        sim = pressed_pair(np.array([0.0, 0.0, 60.0]))
        sim.step(3000)
        if resort:
            sim.sort_by_cell()
        sim.step(500)
        runs.append(spin_of_a(sim)[2])
    assert abs(runs[0]) > 1.0 and runs[1] == pytest.approx(runs[0], rel=1e-9)
