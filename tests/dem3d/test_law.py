"""The contact law on its own: Hertz-Mindlin stiffnesses and the two Coulomb caps."""

import math

import pytest

from dem3d import hertz_mindlin, linear
from dem3d.kernels import contact_law


def test_hertz_normal_force_and_mindlin_tangential_stiffness():
    """Hertz: F_n = 4/3 E* sqrt(R*) delta^1.5; Mindlin (no slip): k_t = 8 G* sqrt(R* delta),
    so one increment u_t = v_t dt gives F_t = -k_t v_t dt (Johnson 1985, eqs 4.23, 7.35)."""
    youngs, nu = 7e7, 0.25
    prm = hertz_mindlin(youngs, nu, 0.9)
    e_star = youngs / (2 * (1 - nu ** 2))
    g_star = youngs / (4 * (2 - nu) * (1 + nu))
    delta, r_eff, vt, dt = 1e-4, 0.01, 0.01, 1e-6
    fx, fy, fz, fn, ux, uy, uz = contact_law(prm, prm.mu, delta, 0.0, 0.0, 1.0, vt, 0.0, 0.0,
                                             0.1, r_eff, 0.0, 0.0, 0.0, dt)
    assert fn == pytest.approx(4 / 3 * e_star * math.sqrt(r_eff) * delta ** 1.5, rel=1e-14)
    assert fz == pytest.approx(-fn, rel=1e-14)            # force on A points away from B
    assert fx == pytest.approx(-8 * g_star * math.sqrt(r_eff * delta) * vt * dt, rel=1e-14)
    assert ux == pytest.approx(vt * dt, rel=1e-14)


@pytest.mark.parametrize("coulomb", ["elastic", "total"])
def test_sliding_force_is_capped_by_mu_times_the_chosen_normal_force(coulomb):
    """A large tangential displacement saturates: |F_t| = mu F_e (PFC) or mu |F_e + c_n v_n|
    (LIGGGHTS), and the stored spring is scaled back to |u_t| = |F_t| / k_t (no tangential
    damping)."""
    kn, ks, mu, cn = 1e5, 4e4, 0.5, 30.0
    prm = linear(kn, ks, mu, c_n=cn, c_s=0.0, coulomb=coulomb)
    delta, vn = 1e-4, 0.2                                   # closing: viscous part adds
    fx, fy, fz, fn, ux, uy, uz = contact_law(prm, mu, delta, 0.0, 0.0, 1.0, 0.0, 0.0, vn,
                                             0.1, 0.01, 1.0, 0.0, 0.0, 1e-6)
    elastic = kn * delta
    assert fn == pytest.approx(elastic + cn * vn, rel=1e-14)
    cap = mu * (elastic if coulomb == "elastic" else elastic + cn * vn)
    assert abs(fx) == pytest.approx(cap, rel=1e-14)
    assert ux == pytest.approx(cap / ks, rel=1e-14)
