"""Parallel bonds (Potyondy & Cundall 2004) against their closed forms: the stiffness of
one bond in tension, shear, bending and twisting; breakage at the tensile strength; a
cantilever of bonded balls against Euler-Bernoulli; bonds across the periodic boundary;
bond forces independent of the thread count."""

import math

import numba
import numpy as np
import pytest

from dem3d import Periodic, Simulation, linear
from dem3d.cantilever import calibrate_strip, cantilever_check

from conftest import single_specimen, sphere_mass

R = 0.01
RHO = 2650.0
KN = 1e10          # N/m^3
KS = 4e9
A = math.pi * R * R
I = 0.25 * math.pi * R ** 4
J = 2 * I


def bonded_pair(periodic=None, positions=((0.5, 0.5, 0.5), (0.5 + 2 * R, 0.5, 0.5))):
    spec = single_specimen(list(positions), R, RHO)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5), dt=1e-6, gravity=(0, 0, 0), periodic=periodic,
                     sort_by_cell=False)
    assert sim.make_bonds(1e-6 * R, kn=KN, ks=KS) == 1
    sim.evaluate_forces()                 # the bond's first evaluation: no increment
    return sim


@pytest.mark.parametrize("mode", ["axial", "shear", "bending", "twist"])
def test_one_bond_gives_the_parallel_bond_stiffnesses(mode):
    """Sphere 1 (at +x of sphere 0) is moved by a small increment over one step (its
    velocity times dt) and the bond's response is read:
    axial u:    F_1 = -kn A u x;            shear u (y): F_1 = -ks A u y, T_1 = a ks A u z
    bending th (about y): M_1 = -kn I th y; sphere 1's contact point (at -a x from its
                centre) also moves by a th z, so F_1 = -ks A a th z and in all
                T_1 = -(kn I + ks A a^2) th y
    twist th (about x):   T_1 = -ks J th x;  a = R (balls touching)."""
    sim = bonded_pair()
    u = 1e-7
    th = 1e-6
    dt = sim.dt
    if mode == "axial":
        sim.spheres.v[1] = (u / dt, 0, 0)
        f, t = sim.evaluate_forces()
        np.testing.assert_allclose(f[1], [-KN * A * u, 0, 0], rtol=1e-12, atol=1e-20)
        np.testing.assert_allclose(f[0], -f[1], rtol=1e-15)
        assert sim.bonds.fn[0] == pytest.approx(-KN * A * u, rel=1e-12)      # tension
    elif mode == "shear":
        sim.spheres.v[1] = (0, u / dt, 0)
        f, t = sim.evaluate_forces()
        np.testing.assert_allclose(f[1], [0, -KS * A * u, 0], rtol=1e-12, atol=1e-20)
        np.testing.assert_allclose(t[1], [0, 0, R * KS * A * u], rtol=1e-12, atol=1e-24)
        np.testing.assert_allclose(t[0], [0, 0, R * KS * A * u], rtol=1e-12, atol=1e-24)   # moment balance
    elif mode == "bending":
        sim.spheres.w[1] = (0, th / dt, 0)
        f, t = sim.evaluate_forces()
        np.testing.assert_allclose(sim.bonds.mb[0], [0, KN * I * th, 0], rtol=1e-12, atol=1e-24)
        np.testing.assert_allclose(t[1], [0, -(KN * I + KS * A * R * R) * th, 0], rtol=1e-12, atol=1e-24)
        np.testing.assert_allclose(f[1], [0, 0, -KS * A * R * th], rtol=1e-12, atol=1e-20)
    else:
        sim.spheres.w[1] = (th / dt, 0, 0)
        f, t = sim.evaluate_forces()
        np.testing.assert_allclose(t[1], [-KS * J * th, 0, 0], rtol=1e-12, atol=1e-24)
        np.testing.assert_allclose(t[0], [KS * J * th, 0, 0], rtol=1e-12, atol=1e-24)
        np.testing.assert_allclose(f[1], 0.0, atol=1e-20)


def test_bond_across_the_periodic_boundary():
    """Two balls on either side of the periodic boundary (y period 0.2 m) bond through it
    (minimum image) and respond as an interior pair: an axial stretch u along the short
    separation (-y from sphere 0 to sphere 1) gives F_1 = -kn A u (-y)."""
    period = Periodic(1, 0.0, 0.2)
    sim = bonded_pair(period, positions=((0.5, R * 0.5, 0.5), (0.5, 0.2 - 1.5 * R, 0.5)))
    u = 1e-7
    sim.spheres.v[1] = (0, -u / sim.dt, 0)
    f, _ = sim.evaluate_forces()
    np.testing.assert_allclose(f[1], [0, KN * A * u, 0], rtol=1e-9, atol=1e-20)


def test_ring_of_bonds_through_the_periodic_boundary_translates_unloaded():
    """Eight touching balls spanning the period 16 R along y make a closed ring of eight
    bonds (one across the boundary); a rigid translation through the boundary (many
    wraps) leaves every bond force at zero."""
    n = 8
    pos = [(0.5, (2 * k + 1) * R, 0.5) for k in range(n)]
    spec = single_specimen(pos, R, RHO, velocities=[[0.0, 3.0, 0.0]] * n)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5), dt=2e-6, gravity=(0, 0, 0),
                     periodic=Periodic(1, 0.0, 2 * n * R))
    assert sim.make_bonds(1e-3 * R, kn=KN, ks=KS) == n
    sim.step(20_000)                      # 0.12 m: 0.75 periods, several list rebuilds
    assert sim.n_rebuilds > 3
    assert np.abs(sim.bonds.out).max() < 1e-9 * KN * A * R


def test_bonded_bar_breaks_at_its_tensile_strength():
    """A bar of five bonded balls, the first clamped, the last pulled by an external
    force rising slowly (quasi-static, local damping 0.7): every bond carries F, so the
    bar breaks when F / A reaches sigma_c (P&C eq. 12 with no moment): F = sigma_c A."""
    sigma_c = 1e6
    n = 5
    spec = single_specimen([(0.5 + 2 * R * k, 0.5, 0.5) for k in range(n)], R, RHO)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5, local_damping=0.7), dt=1e-5, gravity=(0, 0, 0),
                     sort_by_cell=False)
    sim.make_bonds(1e-3 * R, kn=KN, ks=KS, sigma_c=sigma_c, tau_c=1e9)
    sim.lock([0], translation=True, rotation=True)
    f_break = sigma_c * A
    rate = 1.25 * f_break / 0.25            # N/s: reaches 1.25 F_break in 0.25 s
    f = np.zeros((n, 3))
    broke_at = None
    for k in range(2500):
        load = rate * sim.time
        f[-1, 0] = load
        sim.set_external_force(f)
        sim.step(10)
        if np.any(sim.bonds.state == 0):
            broke_at = load
            break
    assert broke_at is not None
    assert broke_at == pytest.approx(f_break, rel=0.02)
    assert np.count_nonzero(sim.bonds.state == 0) >= 1


def test_bond_forces_do_not_depend_on_the_thread_count():
    """A vibrating bonded strip evaluated on 1 and on 2 threads (one sphere per thread
    share): bond forces and the motion are bitwise equal."""
    from dem3d.cantilever import strip_specimen
    prm = calibrate_strip(40e9, 5e-3)
    runs = []
    for threads in (1, min(2, numba.config.NUMBA_NUM_THREADS)):
        numba.set_num_threads(threads)
        spec, row = strip_specimen(0.03, 5e-3)
        rng = np.random.default_rng(3)
        spec = spec._replace(velocities=rng.normal(0, 0.01, spec.positions.shape))
        sim = Simulation(spec, linear(1e4, 1e4, 0.5), dt=1e-12, gravity=(0, 0, 0), spheres_per_thread=1)
        sim.make_bonds(1e-4, kn=prm.kn, ks=prm.ks, sigma_c=3e5, tau_c=3e5)
        sim.dt = 0.2 * sim.dt_critical_bonds
        sim.step(3000)
        runs.append((sim.bonds.out.copy(), sim.bonds.state.copy(), sim.spheres.x.copy(), sim.spheres.w.copy()))
    for a, b in zip(*runs):
        assert np.array_equal(a, b)


def test_calibration_closed_form_for_two_sheets():
    """Two sheets, Rb = R: kn = E t^3 / (12 * 2 (pi R^2 R^2 + pi R^4 / 4)) = 32 E / (15 pi R)."""
    p = calibrate_strip(40e9, 5e-3)
    r = 5e-3 / 4
    assert p.kn == pytest.approx(32 * 40e9 / (15 * math.pi * r), rel=1e-13)
    assert p.ei_per_width == pytest.approx(416.7, rel=1e-3)     # the study's model EI [N m^2/m]


def test_cantilever_of_bonded_balls_follows_euler_bernoulli():
    """The seismic study's sheet pile (E 40 GPa, 5 mm, 13.5 cm, two sheets of 2.5 mm
    balls at 4000 kg/m^3): tip deflection within 2 % of F L^3 / (3 EI) and first
    frequency within 5 % of 1.875^2 sqrt(EI / (m L^4)) / (2 pi)."""
    res = cantilever_check()
    assert res.tip_deflection_over_beam == pytest.approx(1.0, abs=0.02)
    assert res.frequency_over_beam == pytest.approx(1.0, abs=0.05)


def test_checkpoint_with_bonds_external_forces_and_attached_spheres_resumes_bitwise():
    """to_arrays / from_arrays carry bonds, external forces and attached spheres: a split
    run ends bitwise where the unbroken run ends (materials: test_materials)."""
    from dem3d import Wall, plane, sine_ramp, shaking
    from dem3d.cantilever import strip_specimen

    prm = calibrate_strip(40e9, 5e-3)

    def build():
        spec, row = strip_specimen(0.02, 5e-3)
        spec = spec._replace(positions=spec.positions + [0.0, 0.0, 0.00126])
        a = linear(1e6, 1e6, 0.5, zeta_n=0.1)
        walls = [Wall("base", plane((0, 0, 0), (0, 0, 1), mu=0.5), shaking(sine_ramp(20.0, 50.0, 0.01, 0.01, 0.01)))]
        sim = Simulation(spec, a, dt=1e-12, walls=walls)
        sim.make_bonds(1e-4, kn=prm.kn, ks=prm.ks, sigma_c=2e6, tau_c=2e6)
        sim.dt = 0.2 * min(sim.dt_critical_bonds, sim.dt_critical)
        sim.attach_to_wall(np.nonzero(row == 0)[0], "base")
        sim.set_external_force((1e-3, 0.0, 0.0))
        return sim

    whole = build()
    whole.step(4000)
    first = build()
    first.step(1500)
    resumed = Simulation.from_arrays(first.to_arrays(), walls=build().walls.walls)
    resumed.step(2500)
    a, b = whole.to_arrays(), resumed.to_arrays()
    assert a.keys() == b.keys()
    for k in a:
        assert np.array_equal(a[k], b[k]), k
    assert np.abs(whole.bonds.fn).max() > 0


def test_a_spinning_bonded_pair_carries_only_the_centripetal_tension():
    """Objectivity of the incremental update: two bonded balls spinning rigidly at
    omega about their midpoint (no gravity) need the tension m omega^2 R (each ball on a
    circle of radius R): over one turn the bond's normal force oscillates about it (it
    starts unloaded) while its shear force stays < 1 % of it and no bending or twisting
    appears; spinning about the bond axis loads nothing."""
    m = sphere_mass(R, RHO)
    om = 20.0
    for axis, loaded in (((0.0, 0.0, 1.0), True), ((1.0, 0.0, 0.0), False)):
        w = om * np.array(axis)
        x = np.array([[0.5, 0.5, 0.5], [0.5 + 2 * R, 0.5, 0.5]])
        spec = single_specimen(x, R, RHO, velocities=np.cross(w, x - [0.5 + R, 0.5, 0.5]))
        sim = Simulation(spec, linear(1e5, 4e4, 0.5), dt=2e-6, gravity=(0, 0, 0), sort_by_cell=False)
        sim.make_bonds(1e-6 * R, kn=KN, ks=KS)
        sim.spheres.w[:] = w
        fn, fs, other = [], [], []
        for _ in range(100):
            sim.step(int(2 * math.pi / om / 100 / sim.dt))
            fn.append(sim.bonds.fn[0])
            fs.append(np.linalg.norm(sim.bonds.fs[0]))
            other.append(np.linalg.norm(sim.bonds.mb[0]) + abs(sim.bonds.mt[0]))
        tension = m * om ** 2 * R
        if loaded:
            assert -np.mean(fn) == pytest.approx(tension, rel=0.03)
            assert max(fs) < 0.01 * tension
        else:
            assert np.abs(fn).max() == 0.0 and max(fs) == 0.0
        assert max(other) == 0.0
