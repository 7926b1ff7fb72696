"""studies.measures.max_shear_strain_field against exact kinematics (theory: the
Green-Lagrange strain of a homogeneous deformation x = F X is (F^T F - I) / 2 at every
point, and zero for any rigid motion)."""

import math

import numpy as np
import pytest

from studies.measures import max_shear_strain_field


def cloud(n=3000, seed=3):
    return np.random.default_rng(seed).uniform(0.0, 1.0, (n, 3))


def test_simple_shear_in_the_xz_plane():
    """Simple shear x += g z: E = [[0, g/2], [g/2, g^2/2]], so gamma_max =
    sqrt(g^4/4 + g^2) = g sqrt(1 + g^2/4) at every node with grains around it."""
    X = cloud()
    g = 0.05
    Y = X.copy()
    Y[:, 0] += g * X[:, 2]
    u, v, gamma = max_shear_strain_field(X, Y, cell=0.1)
    assert gamma.shape == (len(v), len(u))
    assert np.all(np.isfinite(gamma))
    assert gamma == pytest.approx(np.full_like(gamma, g * math.sqrt(1 + g * g / 4)), rel=1e-9)


def test_rigid_motion_is_strain_free():
    """A rotation of 20 deg about y plus a translation: gamma_max = 0."""
    X = cloud()
    t = math.radians(20)
    R = np.array([[math.cos(t), 0, -math.sin(t)], [0, 1, 0], [math.sin(t), 0, math.cos(t)]])
    _, _, gamma = max_shear_strain_field(X, X @ R.T + [0.3, 0.1, -2.0], cell=0.1)
    assert np.nanmax(gamma) < 1e-12


def test_a_shear_band_is_localised_and_empty_space_is_nan():
    """Grains only below z = 0.6; a band 0.4 < z < 0.6 sheared by g, the rest rigid:
    nodes deep in the rigid part read 0, nodes in the band's middle read the band's
    simple-shear value, nodes above the mass have no grains (NaN)."""
    X = cloud(6000)
    X = X[X[:, 2] < 0.6]
    g = 0.1
    Y = X.copy()
    Y[:, 0] += g * np.clip(X[:, 2] - 0.4, 0.0, None)
    u, v, gamma = max_shear_strain_field(X, Y, cell=0.05, radius=0.04)
    rows = {round(z, 2): gamma[i] for i, z in enumerate(v)}
    assert np.nanmax(rows[0.2]) < 1e-12
    assert np.nanmedian(rows[0.5]) == pytest.approx(g * math.sqrt(1 + g * g / 4), rel=1e-9)
    assert np.all(np.isnan(gamma[v > 0.65]))
