"""Materials per pair: the pair's contact parameters against the mixing rule's closed
forms (springs in series; Johnson 1985 for Hertz), and the one-material table path
bitwise equal to the single-material path."""

import math

import numpy as np
import pytest

from dem3d import Simulation, Wall, hertz_mindlin, linear, material_table, mix, pair_params, plane

from conftest import single_specimen

R1, R2 = 0.02, 0.03
RHO = 2650.0


def pressed_pair(params, materials, delta, wall_gap=None):
    """Two spheres (materials 0 and 1) overlapping by ``delta`` along x, at rest, no
    gravity; optionally a floor of material 1 overlapping sphere 0 by ``wall_gap``."""
    pos = [[0.0, 0.0, 0.5], [R1 + R2 - delta, 0.0, 0.5]]
    walls = []
    if wall_gap is not None:
        walls = [Wall("floor", plane((0.0, 0.0, 0.5 - R1 + wall_gap), (0, 0, 1), mu=0.9))]
    spec = single_specimen(pos, [R1, R2], RHO)
    return Simulation(spec, params, dt=1e-7, gravity=(0, 0, 0), walls=walls, materials=materials,
                      sphere_material=[0, 1], wall_material={"floor": 1} if walls else None)


def test_linear_pair_stiffness_is_the_two_springs_in_series():
    """kn_a = 1e5, kn_b = 4e5 N/m (each the contact stiffness between two grains of one
    material): kn_ab = 2 kn_a kn_b / (kn_a + kn_b) = 1.6e5 N/m, F = kn_ab delta."""
    a = linear(1e5, 4e4, 0.5)
    b = linear(4e5, 1.6e5, 0.3)
    delta = 1e-4
    sim = pressed_pair(a, [a, b], delta)
    f, _ = sim.evaluate_forces()
    fi = f[np.argsort(sim.original_index)]
    assert fi[0, 0] == pytest.approx(-1.6e5 * delta, rel=1e-10)
    assert fi[1, 0] == pytest.approx(1.6e5 * delta, rel=1e-10)
    p = pair_params(sim.mtab, 0, 1)
    assert p.ks == pytest.approx(2 * 4e4 * 1.6e5 / 2e5, rel=1e-14) and p.mu == 0.3


def test_hertz_pair_modulus_is_johnsons_for_spheres_and_walls():
    """E_a = 70 GPa, nu_a = 0.25; E_b = 200 GPa, nu_b = 0.3:
    1/E* = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b, F = 4/3 E* sqrt(R*) delta^1.5 with
    R* = r1 r2 / (r1 + r2) between the spheres and R* = r1 against a floor of material b."""
    a = hertz_mindlin(70e9, 0.25, 0.5)
    b = hertz_mindlin(200e9, 0.3, 0.4)
    e_star = 1.0 / ((1 - 0.25 ** 2) / 70e9 + (1 - 0.3 ** 2) / 200e9)
    g_a, g_b = 70e9 / 2.5, 200e9 / 2.6
    g_star = 1.0 / ((2 - 0.25) / g_a + (2 - 0.3) / g_b)
    p = mix(a, b)
    assert p.e_star == pytest.approx(e_star, rel=1e-13) and p.g_star == pytest.approx(g_star, rel=1e-13)
    assert mix(a, a) == pytest.approx(a)
    delta, d_wall = 2e-6, 1e-6
    sim = pressed_pair(a, [a, b], delta, wall_gap=d_wall)
    f, _ = sim.evaluate_forces()
    fi = f[np.argsort(sim.original_index)]
    f_pair = 4.0 / 3.0 * e_star * math.sqrt(R1 * R2 / (R1 + R2)) * delta ** 1.5
    f_wall = 4.0 / 3.0 * e_star * math.sqrt(R1) * d_wall ** 1.5
    # delta is recovered from centres ~0.05 m apart: rounding of ~1e-17 m in 2e-6 m
    assert fi[1, 0] == pytest.approx(f_pair, rel=1e-9)
    assert fi[0, 0] == pytest.approx(-f_pair, rel=1e-9)
    assert fi[0, 2] == pytest.approx(f_wall, rel=1e-9)


def test_explicit_pair_parameters_override_the_rule():
    a = linear(1e5, 4e4, 0.5)
    b = linear(4e5, 1.6e5, 0.3)
    special = linear(2e5, 8e4, 0.1)
    table = material_table([a, b], {(1, 0): special})
    assert pair_params(table, 0, 1) == special and pair_params(table, 1, 0) == special
    assert pair_params(table, 1, 1) == b


def test_one_material_table_is_bitwise_the_single_material_path():
    """The lookup rebuilds the same ContactParams, so a run with materials=[params]
    (panel friction = the law's) is bitwise the run without materials."""
    from dem3d import Periodic, Wall, box, prep
    runs = []
    for materials in (None, "table"):
        rng = np.random.default_rng(5)
        lo, hi = np.zeros(3), np.array([0.3, 0.2, 0.3])
        spec = prep.random_specimen(rng, lo, hi, 80, 0.03, 0.045, clump_fraction=0.3)
        spec = spec._replace(velocities=rng.normal(0.0, 2.0, (len(spec.radii), 3)))
        law = hertz_mindlin(7e7, 0.25, 0.5, zeta_n=0.1, zeta_s=0.1)
        sim = Simulation(spec, law, dt=2e-5, walls=[Wall("box", box(lo, (0.3, 0.2, 1.0), mu=0.5, periodic_axis=1))],
                         periodic=Periodic(1, 0.0, 0.2), gravity=(0, 0, -100.0),
                         materials=None if materials is None else [law])
        sim.step(800)
        assert np.count_nonzero(sim.pairs.active) > 5
        runs.append(sim.to_arrays())
    for k in ("spheres.x", "spheres.v", "spheres.w", "spheres.f", "pairs.ut", "panel_force"):
        assert np.array_equal(runs[0][k], runs[1][k]), k


def test_checkpoint_keeps_the_material_table_and_ids():
    """to_arrays / from_arrays carry the table and the sphere and panel material ids:
    a split two-material run ends bitwise where the unbroken one ends."""
    from dem3d import Wall, box, prep

    def build():
        rng = np.random.default_rng(8)
        lo, hi = np.zeros(3), np.array([0.3, 0.3, 0.3])
        spec = prep.random_specimen(rng, lo, hi, 60, 0.03, 0.045)
        spec = spec._replace(velocities=rng.normal(0.0, 2.0, (len(spec.radii), 3)))
        a = linear(1e5, 4e4, 0.5, zeta_n=0.2)
        b = linear(3e5, 1e5, 0.3, zeta_n=0.2)
        return Simulation(spec, a, dt=2e-5, walls=[Wall("box", box(lo, hi, mu=0.5))], materials=[a, b],
                          sphere_material=np.arange(len(spec.radii)) % 2, wall_material={"box": 1})

    whole = build()
    whole.step(1000)
    first = build()
    first.step(400)
    resumed = Simulation.from_arrays(first.to_arrays(), walls=build().walls.walls)
    resumed.step(600)
    a, b = whole.to_arrays(), resumed.to_arrays()
    assert a.keys() == b.keys() and "materials" in a
    for k in a:
        assert np.array_equal(a[k], b[k]), k
