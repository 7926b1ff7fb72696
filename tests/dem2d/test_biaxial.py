"""Biaxial test at reduced size (grains 4x coarser, ~800 disks) and the shear-band
reader on a synthetic field.

References: the stress boundary holds sigma_3 (the test's definition); frictionless
disks have a small macroscopic friction (sin phi ~ 0.1: Peyneau & Roux 2008 for
spheres, Azema & Radjai for 2D), and friction raises it; a displacement jump across a
line of known inclination gives back that inclination.
"""

import math

import numpy as np
import pytest

from studies.elements.biaxial import BiaxialCase, BiaxialTest, shear_band_angle


def _run(mu: float):
    t = BiaxialTest(BiaxialCase(particles_scale=4.0, friction=mu, prep_friction=0.25, max_strain=0.06, seed=2))
    for _ in t.prepare():
        pass
    for _ in t.shear():
        pass
    return t


@pytest.fixture(scope="module")
def tests_by_mu():
    return {mu: _run(mu) for mu in (0.0, 0.5)}


def test_piston_holds_the_confining_stress(tests_by_mu):
    t = tests_by_mu[0.5]
    s3 = np.array([s.sigma_3 for s in t.samples[5:]])
    assert np.mean(s3) == pytest.approx(t.case.confining, rel=0.02)
    assert np.all(np.abs(s3 / t.case.confining - 1) < 0.15)
    assert t.samples[-1].eps_axial >= t.case.max_strain


def test_friction_angle_of_frictionless_and_frictional_disks(tests_by_mu):
    r0 = tests_by_mu[0.0].result()
    r5 = tests_by_mu[0.5].result()
    assert r0.phi_cs_deg < 10.0                # sin phi ~ 0.1 for frictionless grains
    assert r5.phi_cs_deg > r0.phi_cs_deg + 5.0
    assert r5.phi_peak_deg >= r5.phi_cs_deg


def _synthetic_band(beta: float):
    """Grains in a 70 x 200 mm specimen (x0 (6000,2) [m]) and their displacements u: those
    on one side of a band through (0.035, 0.1) m at ``beta`` deg from the x axis slide
    along it by 1 mm, smeared over a 6 mm band. Returns (x0, u, band normal)."""
    x0 = np.random.default_rng(0).uniform([0, 0], [0.07, 0.2], size=(6000, 2))
    th = math.radians(beta)
    t = np.array([math.cos(th), math.sin(th)])
    n = np.array([-t[1], t[0]])
    u = np.outer(np.clip((x0 - [0.035, 0.1]) @ n / 0.006 + 0.5, 0, 1) * 1e-3, t)
    return x0, u, n


def test_band_angle_of_a_synthetic_shear_band():
    for beta in (55.0, 125.0):
        x0, u, _ = _synthetic_band(beta)
        got = shear_band_angle(x0, x0 + u, cell=0.006)
        assert got == pytest.approx(beta if beta <= 90 else 180 - beta, abs=3.0)


def test_the_band_is_drawn_where_a_synthetic_band_lies(tmp_path):
    """The band figure's line (``studies.biaxial.figures.band_line``) on the strain map
    of the synthetic band above: at its inclination (55 or 125 deg from the x axis, the
    angle read being 55 both times) and through it (the line passes within one cell of
    the band's centre, (0.035, 0.1) m). The figure is written."""
    from studies.biaxial.figures import band_line
    from studies.elements.biaxial import strain_field
    from viz.figures import plot_cell_map
    for beta in (55.0, 125.0):
        x0, u, n = _synthetic_band(beta)
        centres, gamma = strain_field(x0, x0 + u, 0.006)
        (cx, cy), angle = band_line(centres, gamma, 55.0, 0.006)
        assert angle == beta
        assert abs((np.array([cx, cy]) - [0.035, 0.1]) @ n) < 0.006
        assert plot_cell_map(centres, gamma, tmp_path / f"band{beta:g}.png", cell=0.006, label="strain",
                             lines=[((cx, cy), angle, "band")]).stat().st_size > 0
