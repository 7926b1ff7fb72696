"""Measurements for the seismic study against exact results: section forces of a bonded
cantilever (statics), the best-fit strain of an affine deformation, the settlement of a
prescribed surface displacement."""

import numpy as np
import pytest

from dem3d import Simulation, linear
from dem3d.cantilever import calibrate_strip, strip_specimen
from dem3d.measure import max_shear_strain, section_forces, settlement_profile, strain_field


def test_section_forces_of_a_loaded_cantilever_are_the_beams():
    """A bonded strip clamped at z = 0, tip load F along x at z = L, relaxed (local
    damping): at a cut z_c the lower part acts on the upper one with -F x (shear) and
    moment -(L - z_c) F y about the cut's centre; no axial force."""
    prm = calibrate_strip(40e9, 5e-3)
    spec, row = strip_specimen(0.03, 5e-3)
    rows = row.max() + 1
    d = 2 * prm.ball_radius
    length = (rows - 1) * d
    k_ax = prm.kn * np.pi * prm.ball_radius ** 2
    sim = Simulation(spec, linear(k_ax, k_ax, 0.5, local_damping=0.7), dt=1e-12, gravity=(0, 0, 0),
                     sort_by_cell=False)
    sim.make_bonds(1e-4 * d, kn=prm.kn, ks=prm.ks)
    sim.dt = 0.2 * sim.dt_critical_bonds
    sim.lock(np.nonzero(row == 0)[0], translation=True, rotation=True)
    load = 2.0
    f = np.zeros((len(row), 3))
    f[row == rows - 1, 0] = load / 2
    sim.set_external_force(f)
    sim.step(60_000)
    cuts = d * (np.arange(rows - 1) + 0.5)
    sec = section_forces(sim, cuts)
    assert np.all(sec.n_bonds == 2)                   # the two sheets' bonds along z
    np.testing.assert_allclose(sec.force[:, 0], -load, rtol=1e-4)
    np.testing.assert_allclose(sec.force[:, 2], 0.0, atol=1e-4 * load)
    np.testing.assert_allclose(sec.moment[:, 1], -(length - cuts) * load, rtol=2e-3, atol=1e-4 * load * d)


def test_best_fit_strain_recovers_an_affine_deformation():
    """x1 = x0 + u0 + G (x0 - c) for random spheres: every cell's fit returns G to
    round-off; simple shear gamma gives a maximum shear strain gamma (3D and in x-z)."""
    rng = np.random.default_rng(4)
    x0 = rng.uniform(0, 1, (4000, 3))
    g = rng.normal(0, 1e-3, (3, 3))
    x1 = x0 + np.array([1e-3, -2e-3, 5e-4]) + (x0 - 0.5) @ g.T
    edges = [np.linspace(0, 1, 4)] * 3
    sf = strain_field(x0, x1, edges)
    assert np.all(sf.count >= 4)
    np.testing.assert_allclose(sf.grad, np.broadcast_to(g, sf.grad.shape), atol=1e-12)
    gamma = 0.02
    shear = x0.copy()
    shear[:, 0] += gamma * x0[:, 2]
    sf = strain_field(x0, shear, edges)
    np.testing.assert_allclose(max_shear_strain(sf.strain), gamma, rtol=1e-10)
    np.testing.assert_allclose(max_shear_strain(sf.strain, plane=(0, 2)), gamma, rtol=1e-10)


def test_settlement_profile_of_prescribed_surface_drops():
    """Grains lowered by s_k in bin k (x in [k, k+1) / 5 m) give the profile s_k."""
    rng = np.random.default_rng(2)
    x0 = rng.uniform(0, 1, (3000, 3))
    r = np.full(3000, 0.01)
    s = np.array([0.01, 0.008, 0.004, 0.001, 0.0])
    k = np.minimum((x0[:, 0] * 5).astype(int), 4)
    x1 = x0.copy()
    x1[:, 2] -= s[k]
    centre, settle = settlement_profile(x0, x1, r, np.linspace(0, 1, 6))
    np.testing.assert_allclose(centre, [0.1, 0.3, 0.5, 0.7, 0.9])
    np.testing.assert_allclose(settle, s, atol=1e-15)
