"""Single-grain checks of the engine against statics and Coulomb's friction law:
panel forces, their sign, the friction product rule, wall drivers, mass properties."""

import math

import numpy as np
import pytest

from dem2d.build import Grains, add_clumps, add_disks, add_polygons, friction_split, new_space, union_mass_properties
from dem2d.frames import Frame, make_frame
from dem2d.measure import panel_stresses
from dem2d.params import Material, Solver
from dem2d.probes import PanelProbe
from dem2d.walls import PANEL_TYPE_BASE, RotateAbout, Translate, panel_wall

G = 9.81
R = 0.5e-3


def _space(gravity=(0.0, -G), **kw):
    return new_space(Solver(dt=1e-4, **kw), gravity=gravity, r_min=R, d_max=2 * R)


def test_resting_disk_loads_the_panels_with_its_weight():
    # reference: statics, floor reaction = m g; the disk sits on the joint of two panels
    sp = _space()
    mat = Material(friction=0.25, wall_friction=0.25)
    _, fw = friction_split(0.25, 0.25)
    floor = panel_wall(sp, "floor", (0, 0), (0.01, 0), 4, friction=fw, into=(0, 1), first_type=PANEL_TYPE_BASE)
    g = Grains()
    add_disks(sp, g, np.array([[0.0025, R], [0.006, R]]), np.array([R, R]), mat, np.random.default_rng(0))
    probe = PanelProbe(sp, [floor])
    for _ in range(500):
        sp.step(1e-4)
    probe.start()
    for _ in range(1000):
        sp.step(1e-4)
        probe.record_step(1e-4)
    f = probe.force("floor")
    weight = g.masses().sum() * G
    assert f[:, 1].sum() == pytest.approx(-weight, rel=1e-9)
    assert f[:, 0] == pytest.approx(0.0, abs=1e-12 * weight)
    sig, _ = panel_stresses(f, floor.normals(), floor.corners(), floor.lengths())
    assert np.all(sig >= 0)  # compression positive
    assert g.masses()[0] == pytest.approx(2650 * math.pi * R * R, rel=1e-12)


def test_sign_of_normal_and_shear_stress_on_a_vertical_wall():
    # gravity towards the wall (-x) with a downward part: the disk pushes the wall
    # (sigma > 0) and, held by friction, drags it down (tau > 0, analytic/profile.py)
    sp = _space(gravity=(-G, -0.1 * G))
    mu = 0.5
    _, fw = friction_split(mu, mu)
    wall = panel_wall(sp, "wall", (0, 0), (0, 0.01), 1, friction=fw, into=(1, 0), first_type=PANEL_TYPE_BASE)
    g = Grains()
    add_disks(sp, g, np.array([[R, 0.005]]), np.array([R]), Material(friction=mu, wall_friction=mu),
              np.random.default_rng(0))
    probe = PanelProbe(sp, [wall])
    for _ in range(10):
        sp.step(1e-4)
    probe.start()
    for _ in range(400):  # the disk rolls down ~0.5 mm in this time: still on the panel
        sp.step(1e-4)
        probe.record_step(1e-4)
    m = g.masses()[0]
    sig, tau = panel_stresses(probe.force("wall"), wall.normals(), wall.corners(), wall.lengths())
    assert sig[0] * 0.01 == pytest.approx(m * G, rel=1e-6)
    # a disk can roll, so friction holds it only as much as rolling allows: tau > 0,
    # below the Coulomb limit mu * sigma
    assert 0 < tau[0] <= mu * sig[0] + 1e-9


def test_friction_product_rule_gives_the_pair_coefficient():
    # reference: Coulomb friction. A disk dropped on a floor that slides at 1 m/s is
    # accelerated by mu_pw g while it slips (slip lasts v / (3 mu g) ~ 0.1 s for a disk)
    mu_pp, mu_pw = 0.64, 0.3
    f_grain, f_wall = friction_split(mu_pp, mu_pw)
    assert f_grain * f_grain == pytest.approx(mu_pp) and f_grain * f_wall == pytest.approx(mu_pw)
    sp = _space()
    floor = panel_wall(sp, "floor", (-1, 0), (1, 0), 1, friction=f_wall, into=(0, 1), first_type=PANEL_TYPE_BASE)
    g = Grains()
    add_disks(sp, g, np.array([[0.0, R]]), np.array([R]), Material(friction=mu_pp, wall_friction=mu_pw),
              np.random.default_rng(0))
    for _ in range(100):
        sp.step(1e-4)
    floor.set_motion((1.0, 0.0))
    b = g.bodies[0]
    sp.step(1e-4)
    v0 = b.velocity.x
    for _ in range(200):
        sp.step(1e-4)
    a = (b.velocity.x - v0) / (200 * 1e-4)
    assert a == pytest.approx(mu_pw * G, rel=1e-3)


def test_rotation_and_translation_drivers_move_the_wall_rigidly():
    # reference: rigid-body kinematics, corners rotated by omega t about the pivot
    sp = _space()
    wall = panel_wall(sp, "wall", (0, 0), (0, 0.4), 40, friction=0.0, into=(1, 0), pivot=(0, 0),
                      first_type=PANEL_TYPE_BASE)
    c0 = wall.corners().copy()
    om, n, dt = math.radians(2.0), 1000, 1e-4
    for _ in range(n):
        wall.drive(RotateAbout(om), 0.0)
        sp.step(dt)
    th = om * n * dt
    Rm = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    assert np.allclose(wall.corners(), c0 @ Rm.T, atol=1e-12)
    assert np.allclose(wall.normals()[0], Rm @ np.array([1.0, 0.0]))
    wall.set_motion((0.0, 0.0), 0.0)
    c1 = wall.corners().copy()
    for _ in range(n):
        wall.drive(Translate((-2e-3, 0.0)), 0.0)
        sp.step(dt)
    assert np.allclose(wall.corners() - c1, [-2e-3 * n * dt, 0.0], atol=1e-12)
    assert wall.displacement()[0] == pytest.approx(-2e-4)


def test_union_mass_of_two_overlapping_circles_matches_the_lens_formula():
    # reference: area of the union of two circles = 2 pi r^2 - lens, lens =
    # 2 r^2 acos(d / 2r) - (d/2) sqrt(4 r^2 - d^2)
    r, d, rho = 1.0, 1.0, 2.0
    m, inertia, c = union_mass_properties([[0, 0], [d, 0]], [r, r], rho, resolution=800)
    lens = 2 * r * r * math.acos(d / (2 * r)) - d / 2 * math.sqrt(4 * r * r - d * d)
    assert m == pytest.approx(rho * (2 * math.pi * r * r - lens), rel=2e-3)
    assert c == pytest.approx([d / 2, 0.0], abs=1e-3)
    m1, i1, _ = union_mass_properties([[0, 0]], [r], rho, resolution=800)
    assert i1 == pytest.approx(0.5 * m1 * r * r, rel=3e-3)  # disk: I = m r^2 / 2


def test_frame_has_the_contract_fields_for_disks_clumps_and_blocks():
    sp = _space()
    mat = Material(friction=0.25, wall_friction=0.25)
    floor = panel_wall(sp, "floor", (-0.02, 0), (0.02, 0), 4, friction=0.5, into=(0, 1), first_type=PANEL_TYPE_BASE)
    g = Grains()
    rng = np.random.default_rng(0)
    add_disks(sp, g, np.array([[0.0, R], [2.2 * R, R]]), np.array([R, R]), mat, rng)
    add_clumps(sp, g, np.array([[0.006, 2 * R]]), np.array([0.3]), [[-0.5, 0], [0.5, 0]], [0.6, 0.6],
               np.array([R]), mat, rng)
    add_polygons(sp, g, [(-0.006, 2 * R)], [0.0], [np.array([[-R, -R], [R, -R], [R, R], [-R, R]])], mat, rng)
    for _ in range(300):
        sp.step(1e-4)
    fr = make_frame(sp, g, 300, 0.03, 1e-4, [floor])
    assert Frame._fields == ("step", "time", "positions", "radii", "velocities", "body_id", "contact_a",
                             "contact_b", "contact_force", "panel_corners", "panel_normal", "panel_force",
                             "panel_area", "block_outlines", "panel_moment", "particle_force", "material",
                             "contact_shear", "bond_a", "bond_b", "bond_force", "bond_shear")
    assert fr.panel_moment is None          # one record for both engines; 2D panels carry no moment
    assert fr.positions.shape == (4, 2) and fr.radii.shape == (4,)   # 2 disks + a clump of 2 circles
    assert list(fr.body_id) == [0, 1, 2, 2]
    assert fr.panel_corners.shape == (4, 2, 2) and fr.panel_normal.shape == (4, 2)
    assert fr.panel_force.shape == (4, 2) and fr.panel_area == pytest.approx([0.01] * 4)
    assert len(fr.block_outlines) == 1 and fr.block_outlines[0].shape == (4, 2)
    assert len(fr.contact_a) == len(fr.contact_b) == len(fr.contact_force)
    assert np.all(fr.contact_force >= 0)
    assert fr.contact_shear.shape == fr.contact_force.shape and np.all(fr.contact_shear >= 0)
    assert fr.particle_force.shape == (4, 2) and fr.material is None and fr.bond_a is None
    # a clump's two circles carry their body's force
    assert np.array_equal(fr.particle_force[2], fr.particle_force[3])
    # the clump's circles sit at +-0.5 R from its centre along its axis
    assert np.linalg.norm(fr.positions[2] - fr.positions[3]) == pytest.approx(R, rel=1e-9)
