"""Arching methods. theta_w and K_an (Paik & Salgado 2003) are checked against the
independent implementation tabulated in docs/reference/analytic-values.txt and
against exact limits; the flat-element profiles are reconstructions (analytic/arching.py
says which), so they are checked against their closed-form properties and the
reference table of the same reconstruction, never presented as the papers' numbers."""

import math

import numpy as np
import pytest

from analytic import Soil, Wall, coulomb, rankine
from analytic.arching import (arch_stress_across, handy, handy_coefficient, khosravi, paik_salgado,
                              paik_salgado_coefficient, principal_rotation_at_wall)
from analytic.errors import InvalidParameter

R = math.radians


# analytic-values.txt section 2: th_w (deg) and Kan
@pytest.mark.parametrize("phi,delta,theta_w,K_an", [
    (20.7, 20.7, 55.35, 0.6851), (20.7, 20.7 * 2 / 3, 75.68, 0.5151), (30, 20, 78.42, 0.3635),
    (30, 30, 60.00, 0.5294), (34, 34 * 2 / 3, 79.55, 0.3087), (39, 26, 80.92, 0.2483)])
def test_paik_salgado_rotation_and_coefficient(phi, delta, theta_w, K_an):
    assert abs(math.degrees(principal_rotation_at_wall(R(phi), R(delta))) - theta_w) < 0.006
    assert abs(paik_salgado_coefficient(R(phi), R(delta)) - K_an) < 6e-5


def test_theta_w_limits():
    """theta_w = 90 deg at delta = 0 and 45 + phi/2 at delta = phi (exact)."""
    assert principal_rotation_at_wall(R(30), 0.0) == math.pi / 2
    # the discriminant cancels to 0 at delta = phi, so rounding enters through a square
    # root: sqrt(machine eps) ~ 1e-8 is the attainable relative accuracy
    assert math.isclose(principal_rotation_at_wall(R(30), R(30)), R(45 + 15), rel_tol=1e-7)


def test_handy_coefficient_reference():
    """analytic-values.txt: Kw = 0.5300 (phi 30), 0.6853 (20.7), 0.3929 (39); within 1 % of
    the exact catenary factor 0.531825 at phi 30."""
    assert abs(handy_coefficient(R(30)) - 0.5300) < 5e-5
    assert abs(handy_coefficient(R(20.7)) - 0.6853) < 5e-5
    assert abs(handy_coefficient(R(39)) - 0.3929) < 5e-5
    assert abs(handy_coefficient(R(30)) / 0.531825 - 1) < 0.01


def test_arch_average_equals_mean_vertical_stress():
    """Averaging the arch's sigma_v across the element recovers sigma_v_avg, and its wall
    value gives K_an (the two definitions of Paik & Salgado's arch must agree)."""
    x = np.linspace(0, 1, 200001)
    st = arch_stress_across(R(30), R(20), x, sigma_v_avg=1.0)
    assert abs(np.trapezoid(st["sigma_v"], x) - 1.0) < 1e-6
    assert math.isclose(st["sigma_h"][0], paik_salgado_coefficient(R(30), R(20)), rel_tol=1e-12)
    assert abs(st["tau_xz"][-1]) < 1e-12  # sigma_1 vertical at the slip surface


@pytest.mark.parametrize("method", [paik_salgado, handy, khosravi])
def test_smooth_wall_limit_is_rankine_for_ps_and_khosravi(method):
    """delta = 0: theta_w = 90 deg, K_an = Ka and a = 0 -> Rankine, resultant at H/3.
    Handy's K_w = 0.53 ignores delta (rough-wall arch), but its form-(i) exponent keeps the
    thrust equal to the Coulomb force on the 45 + phi/2 plane, i.e. Rankine's, with the
    resultant raised above H/3 by the arch."""
    s, w = Soil(30, 18e3), Wall(4.0, 0.0)
    p = method(s, w)
    if method is handy:
        assert math.isclose(p.Kh, rankine(s, w).K, rel_tol=1e-9)
        assert p.height_over_H > 0.4
        return
    assert math.isclose(p.Kh, rankine(s, w).K, rel_tol=1e-9)
    assert math.isclose(p.height_over_H, 1 / 3, rel_tol=1e-7)


# analytic-values.txt section 4, forms (i), (ii), (iii): Kh and h/H
@pytest.mark.parametrize("phi,delta,form,Kh,hH", [
    (20.7, 20.7, "i", 0.3788, 0.4293), (20.7, 20.7, "iii", 0.4984, 0.3859),
    (30, 20, "i", 0.2755, 0.3792), (30, 20, "iii", 0.2957, 0.3676),
    (30, 30, "i", 0.2500, 0.4528), (30, 30, "iii", 0.3462, 0.4031),
    (39, 26, "iii", 0.1980, 0.3709)])
def test_paik_salgado_profile_forms(phi, delta, form, Kh, hH):
    p = paik_salgado(Soil(phi, 1.0), Wall(1.0, delta), exponent=form)
    assert abs(p.Kh - Kh) < 6e-5 and abs(p.height_over_H - hH) < 6e-5


@pytest.mark.parametrize("phi,delta,Kh,hH", [(20.7, 20.7, 0.4777, 0.3928), (30, 20, 0.2935, 0.3688)])
def test_khosravi_reconstruction_is_form_ii(phi, delta, Kh, hH):
    """The Khosravi reconstruction is the flat element with the arch stress on the slip
    surface: form (ii) of analytic-values.txt section 4."""
    p = khosravi(Soil(phi, 1.0), Wall(1.0, delta))
    assert abs(p.Kh - Kh) < 6e-5 and abs(p.height_over_H - hH) < 6e-5


def test_form_i_thrust_equals_coulomb_force_on_rankine_plane():
    """analytic-formulas.md 5.2: with form (i) the horizontal thrust equals the Coulomb wedge
    force on the 45 + phi/2 plane, W / (tan delta + cot(theta - phi)), whatever K_an is."""
    for phi, delta in ((30, 20), (20.7, 20.7), (34, 24.7)):
        p = paik_salgado(Soil(phi, 1.0), Wall(1.0, delta), exponent="i")
        th = R(45 + phi / 2)
        W = 0.5 / math.tan(th)  # gamma = H = 1
        assert math.isclose(p.thrust_h, W / (math.tan(R(delta)) + 1 / math.tan(th - R(phi))), rel_tol=1e-9)


def test_paik_salgado_peak_below_mid_height():
    """Closed form: d sigma/dz = 0 at z/H = 1 - a^(1/(1-a)); at phi = delta = 20.7, form (iii)
    peaks at z/H = 0.79 with sigma/(gamma H) = 0.380 (research note, section 1.4)."""
    p = paik_salgado(Soil(20.7, 1.0), Wall(1.0, 20.7))
    k = int(np.argmax(p.sigma_h))
    a = p.extra["a"]
    assert abs(p.z[k] - (1 - a ** (1 / (1 - a)))) < 2.5e-3
    assert abs(p.sigma_h[k] - 0.3804) < 5e-4


def test_arching_rejects_passive_geometry_and_strong_interface():
    with pytest.raises(InvalidParameter, match="delta"):
        paik_salgado(Soil(30, 1.0), Wall(1.0, 31))
    with pytest.raises(InvalidParameter, match="beta"):
        khosravi(Soil(30, 1.0), Wall(1.0, 20, beta_deg=10))
