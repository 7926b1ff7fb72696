"""Differential slice method against Nadukuru & Michalowski (2012) Table 3, Rankine's
exact solution, and the paper's stated property (total load independent of k_l)."""

import math
from dataclasses import replace

import numpy as np
import pytest

from analytic import InvalidParameter, Soil, Wall, coulomb, rankine
from analytic.slices import (DSMCase, SlipSurface, coulomb_angle_from_vertical, curved_surface, mode_case,
                             slip_coefficient, solve)

R = math.radians


@pytest.mark.parametrize("mode,K,h", [("T", 0.254, 0.363), ("RB", 0.312, 0.292)])
def test_table3_translation_and_base_rotation(mode, K, h):
    """Table 3 (DSM, rough wall delta = 24.7): T 0.254 / 0.363, RB 0.312 / 0.292.
    Issue 3 tolerances: K +-0.003, centroid +-0.005."""
    r = solve(mode_case(mode))
    assert abs(r.K - K) <= 0.003
    assert abs(r.resultant_height_over_H - h) <= 0.005


def test_translation_slip_plane_is_coulomb_critical():
    """analytic-formulas.md section 2: phi 34, delta 24.7 -> 31.93 deg from vertical."""
    assert abs(coulomb_angle_from_vertical(34, 24.7) - 31.93) < 0.01


@pytest.mark.parametrize("phi", [20.0, 30.0, 39.0])
def test_smooth_wall_gives_rankine(phi):
    """delta = 0, k_l = Ka, Rankine plane 45 - phi/2 -> sigma_z = gamma d exactly (Rankine):
    K = Ka and h = H/3 to 1e-4 (issue 3)."""
    ka = rankine(Soil(phi, 1.0), Wall(1.0)).K
    case = DSMCase(phi_deg=phi, delta_deg=0.0, H=3.0, gamma=18e3, k_wall=lambda u: ka,
                   phi_mob=lambda u: R(phi), surface=SlipSurface.planar(45 - phi / 2))
    r = solve(case)
    assert abs(r.K - ka) <= 1e-4 * ka
    assert abs(r.resultant_height_over_H - 1 / 3) <= 1e-4
    # and the stress itself is Rankine's: sigma_z = gamma d along the wall
    inner = r.d < 0.99 * 3.0
    assert np.allclose(r.sigma_l[inner], 18e3 * r.d[inner], rtol=1e-5, atol=1e-3)


def test_k_r_is_one_minus_sin_phi_on_the_rankine_plane():
    """Eq. 12 at theta_r = 45 - phi/2 gives 1 - sin(phi) (Mohr circle, analytic-formulas.md 7)."""
    for phi in (20, 34, 40):
        assert math.isclose(slip_coefficient(R(phi), R(45 - phi / 2)), 1 - math.sin(R(phi)), rel_tol=1e-12)


K_WALL_SHAPES = {
    "constant": lambda u: 0.254,
    "eq13": lambda u: 0.254 * (1 + 1.57 * (1 - u) ** 2),
    "linear": lambda u: 0.15 + 0.3 * u,
    "wavy": lambda u: 0.3 + 0.1 * math.sin(6 * u),
    "arched": lambda u: 0.2 + 0.6 * u * (1 - u),
}


@pytest.mark.parametrize("phi,delta", [(34.0, 24.7), (30.0, 15.0)])
def test_total_load_independent_of_k_l_when_phi_fully_mobilised(phi, delta):
    """Paper: with phi fully mobilised on a planar slip surface the total wall load does not
    depend on k_l(d) (issue 3: >= 4 functions, 1e-3). On the Coulomb plane it equals the
    Coulomb closed form (Mueller-Breslau), an independent number."""
    th = coulomb_angle_from_vertical(phi, delta)
    Ks = []
    for name, kl in K_WALL_SHAPES.items():
        case = DSMCase(phi_deg=phi, delta_deg=delta, H=1.0, gamma=1.0, k_wall=kl, phi_mob=lambda u: R(phi),
                       surface=SlipSurface.planar(th))
        Ks.append(solve(case).K)
    K_c = coulomb(Soil(phi, 1.0), Wall(1.0, delta)).K
    assert max(Ks) - min(Ks) <= 1e-3 * K_c
    assert all(abs(K - K_c) <= 1e-3 * K_c for K in Ks)


def test_load_distribution_does_depend_on_k_l():
    """...while the centroid moves: eq. 13 lifts it from H/3 (constant k_l) to 0.363 (Table 3)."""
    th = coulomb_angle_from_vertical(34, 24.7)
    h = [solve(DSMCase(34, 24.7, 1.0, 1.0, K_WALL_SHAPES[n], lambda u: R(34), SlipSurface.planar(th)))
         .resultant_height_over_H for n in ("constant", "eq13")]
    assert h[1] - h[0] > 0.02


def test_curved_family_contains_the_plane():
    """A 'curved' surface with equal top and heel angles is the plane: same K and centroid."""
    c = mode_case("T")
    th = math.degrees(c.surface.theta_r(0.0))
    a, b = solve(c), solve(replace(c, surface=curved_surface(th, th)))
    assert math.isclose(a.K, b.K, rel_tol=1e-7) and math.isclose(a.resultant_height_over_H,
                                                                 b.resultant_height_over_H, rel_tol=1e-7)


def test_rotation_about_top_ordering_and_maximum():
    """RT: resultant well above mid-height... Table 3 orders the centroids RB < T < RT
    (0.292 < 0.363 < 0.492; Fang & Ishibashi 0.28 < 0.41 < 0.56). The curved surface is
    chosen by maximum wall reaction, so it must carry at least the best plane's load."""
    rt, t, rb = (solve(mode_case(m)) for m in ("RT", "T", "RB"))
    assert rb.resultant_height_over_H < t.resultant_height_over_H < rt.resultant_height_over_H
    assert rt.resultant_height_over_H > 0.45
    best_plane = solve(mode_case("RT", theta_r_deg="max"))
    assert rt.K >= best_plane.K - 1e-6


def test_bad_mode_and_friction():
    with pytest.raises(InvalidParameter, match="mode"):
        mode_case("X")
    with pytest.raises(InvalidParameter, match="delta"):
        mode_case("T", delta_deg=40.0)
