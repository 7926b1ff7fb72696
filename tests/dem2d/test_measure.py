"""Pure measurement functions against closed forms."""

import math

import numpy as np
import pytest

from dem2d.measure import panel_stresses, readings, stress_in_bands, weight_normalised_unbalance
from studies.measures import k_upper_half, normal_thrust
from studies.measures import steady_displacement


def test_k_upper_half_of_a_linear_profile_is_its_K():
    # sigma = K gamma z sampled at 10 mm panel centres: the force-weighted K is exact
    H, ph, g, K = 0.3, 0.01, 2.0e4, 0.62
    centres_from_base = (np.arange(40) + 0.5) * ph
    z = H - centres_from_base
    sigma = np.where(z > 0, K * g * z, 0.0)
    assert k_upper_half(sigma, z, ph, g, H) == pytest.approx(K, rel=1e-12)
    # thrust of the same profile: K gamma H^2 / 2 (midpoint rule is exact for linear)
    assert normal_thrust(sigma, z, ph) == pytest.approx(K * g * H**2 / 2, rel=1e-12)


def test_steady_displacement_of_an_exponential_drop():
    # F = F_end + (F0 - F_end) exp(-d / d0): 90 % of the drop at d = d0 ln 10
    d = np.linspace(0, 0.003, 301)
    d0 = 2e-4
    F = 400 + 200 * np.exp(-d / d0)
    assert steady_displacement(d, F, 0.9, smooth=1) == pytest.approx(d0 * math.log(10), abs=2e-5)
    assert math.isnan(steady_displacement(d, np.full_like(d, 5.0)))


def test_panel_stress_signs_and_readings():
    corners = np.array([[[0, 0], [0, 0.01]], [[0, 0.01], [0, 0.02]]], float)
    normal = np.array([[1.0, 0.0], [1.0, 0.0]])
    force = np.array([[-10.0, -2.0], [-20.0, 1.0]])  # pushed along -n; dragged down / up
    sig, tau = panel_stresses(force, normal, corners, np.array([0.01, 0.01]))
    assert sig == pytest.approx([1000.0, 2000.0])
    assert tau == pytest.approx([200.0, -100.0])
    starts, means = readings(np.arange(10.0), 4)
    assert list(starts) == [0, 4] and means == pytest.approx([1.5, 5.5])


def test_unbalanced_ratio_is_one_in_free_fall_and_zero_at_rest():
    m = np.array([1.0, 2.0])
    v0 = np.zeros((2, 2))
    dt = 1e-3
    assert weight_normalised_unbalance(v0, v0 + [0, -9.81 * dt], dt, m) == pytest.approx(1.0)
    assert weight_normalised_unbalance(v0, v0, dt, m) == 0.0


def test_love_stress_of_a_vertical_chain():
    # two disks stacked, contact force W: sigma_yy = W l / A over the band, others zero
    pos = np.array([[0.0, 0.0], [0.0, 0.002]])
    W, dt = 3.0, 1e-4
    J_on_a = np.array([[0.0, -W * dt]])  # the lower disk is pushed down by the upper one
    s = stress_in_bands(pos, np.array([0]), np.array([1]), J_on_a, dt, -0.01, 0.01, np.array([-0.01, 0.01]))
    assert s[0, 1, 1] == pytest.approx(W * 0.002 / (0.02 * 0.02))
    assert s[0, 0, 0] == 0.0 and s[0, 0, 1] == 0.0


def test_resultant_height_of_a_linear_profile():
    """sigma proportional to depth on N panels of height L = H/N, each force at its centre
    z_i = (i + 1/2) L: h/H = 1 - sum z^2 / (H sum z) = 1/3 + 1/(6 N^2) (the midpoint rule
    of the continuous 1/3), and panels above the surface carry nothing."""
    from studies.measures import resultant_height_over_H

    N, H = 30, 0.3
    L = H / N
    depth = (np.arange(N) + 0.5) * L
    above = np.array([-0.5 * L, -1.5 * L])              # two panels above the fill surface
    sigma = np.concatenate([depth, [5.0, 5.0]])
    got = resultant_height_over_H(sigma, np.concatenate([depth, above]), L, H)
    assert got == pytest.approx(1.0 / 3.0 + 1.0 / (6 * N**2), rel=1e-12)


def test_dem_profile_is_the_theory_record():
    """A Rankine-like linear profile sigma = Ka gamma z on fine panels gives back Ka as
    K = Kh = 2 F / (gamma H^2) (midpoint rule: exact for a linear profile), the
    resultant at 1/3 + 1/(6 N^2) of H, and the analytic Profile's own normal force."""
    from studies.measures import dem_profile

    N, H, gamma, Ka = 40, 0.4, 15e3, 0.3
    L = H / N
    depth = (np.arange(N) + 0.5) * L
    p = dem_profile(depth, Ka * gamma * depth, np.zeros(N), L, H, gamma)
    assert p.K == pytest.approx(Ka, rel=1e-12) and p.Kh == p.K
    assert p.height_over_H == pytest.approx(1 / 3 + 1 / (6 * N**2), rel=1e-12)
    assert p.as_dict()["name"] == "dem" and p.status == "measured"
