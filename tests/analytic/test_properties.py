"""Properties every closed form must have, for any valid input (hypothesis).

Sources of the identities: Ka < K0 < Kp and Ka falling with phi (any textbook);
Coulomb with delta = beta = omega = 0 is Rankine, and Rankine(beta) = Coulomb(delta = beta)
(analytic-formulas.md section 2); M-O with kh = kv = 0 is Coulomb (section 8); the
closed forms equal an independent planar trial wedge (section 11); a profile's integral
is its thrust and its first moment its resultant height (definition)."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from analytic import InvalidParameter, Soil, Wall, coulomb, jaky, janssen, rankine, trial_wedge
from analytic.arching import handy, khosravi, paik_salgado
from analytic.seismic import mononobe_okabe, seed_whitman

phis = st.floats(15.0, 45.0)
gammas = st.floats(10e3, 22e3)
heights = st.floats(0.5, 12.0)
fractions = st.floats(0.0, 1.0)


@given(phis, fractions)
def test_ka_below_k0_below_kp(phi, frac):
    s, w = Soil(phi, 18e3), Wall(3.0, frac * phi)
    ka, k0, kp = coulomb(s, w).Kh, jaky(s, w).K, coulomb(s, w, passive=True).Kh
    assert ka < k0 < kp
    assert rankine(s, Wall(3.0)).K < k0 < rankine(s, Wall(3.0), passive=True).K


@given(phis, gammas, heights)
def test_coulomb_smooth_vertical_level_is_rankine(phi, gamma, H):
    s, w = Soil(phi, gamma), Wall(H)
    for passive in (False, True):
        assert math.isclose(coulomb(s, w, passive).K, rankine(s, w, passive).K, rel_tol=1e-12)
        assert math.isclose(coulomb(s, w, passive).thrust, rankine(s, w, passive).thrust, rel_tol=1e-12)


@given(phis, st.floats(-1.0, 1.0))
def test_rankine_sloping_equals_coulomb_with_delta_beta(phi, beta_frac):
    beta = beta_frac * phi * 0.98
    s = Soil(phi, 1.0)
    assert math.isclose(rankine(s, Wall(1.0, beta_deg=beta)).K,
                        coulomb(s, Wall(1.0, delta_deg=beta, beta_deg=beta)).K, rel_tol=1e-10)


@given(phis, fractions, st.floats(-20.0, 20.0), st.floats(-0.5, 0.5), st.booleans())
def test_mononobe_okabe_without_shaking_is_coulomb(phi, frac, omega, beta_frac, passive):
    s = Soil(phi, 18e3)
    w = Wall(3.0, frac * phi, omega, beta_frac * phi)
    try:
        c = coulomb(s, w, passive)
    except InvalidParameter:
        assume(False)
    m = mononobe_okabe(s, w, 0.0, 0.0, passive)
    assert math.isclose(m.K, c.K, rel_tol=1e-12) and math.isclose(m.height, c.height, rel_tol=1e-12)


@settings(max_examples=40, deadline=None)
@given(phis, fractions, st.floats(-15.0, 15.0), st.floats(-0.6, 0.6), st.floats(0.0, 0.2),
       st.floats(-0.1, 0.1))
def test_closed_forms_equal_trial_wedge(phi, frac, omega, beta_frac, kh, kv):
    s = Soil(phi, 18e3)
    w = Wall(3.0, frac * phi, omega, beta_frac * phi)
    try:
        m = mononobe_okabe(s, w, kh, kv)
    except InvalidParameter:
        assume(False)
    K_trial, _ = trial_wedge(s, w, kh=kh, kv=kv)
    assert math.isclose(m.K, K_trial, rel_tol=1e-6)


def _all_profiles(phi, gamma, H, frac, q):
    s, w = Soil(phi, gamma), Wall(H, frac * phi, surcharge=q)
    out = [rankine(s, w), coulomb(s, w), jaky(s, w), janssen(s, w, 0.7 * H), paik_salgado(s, w),
           paik_salgado(s, w, "i"), handy(s, w), khosravi(s, w), mononobe_okabe(s, w, 0.1, 0.05),
           seed_whitman(s, w, 0.1), coulomb(s, w, passive=True)]
    return out


@settings(max_examples=25, deadline=None)
@given(phis, gammas, heights, fractions, st.sampled_from([0.0, 5e3, 20e3]))
def test_profile_integrates_to_thrust(phi, gamma, H, frac, q):
    """int sigma_h dz = horizontal thrust and the first moment gives the stored height.
    (Profiles are tabulated on 201-401 points; trapezoid error is O(h^2), so 2e-3 for
    the arching profiles whose slope is infinite at the heel when a < 1.)"""
    for p in _all_profiles(phi, gamma, H, frac, q):
        assert math.isclose(p.normal_force(), p.thrust_h, rel_tol=2e-3), p.method
        assert abs(p.centroid_height() - p.height) <= 2e-3 * H, p.method


@given(st.floats(15.0, 44.0), st.floats(0.2, 1.0), fractions)
def test_ka_falls_as_phi_rises(phi, dphi, frac):
    lo, hi = Soil(phi, 1.0), Soil(phi + dphi, 1.0)
    w = Wall(1.0, frac * phi)
    assert coulomb(hi, w).K < coulomb(lo, w).K
    assert rankine(hi, w).K < rankine(lo, w).K
    assert paik_salgado(hi, w).Kh < paik_salgado(lo, w).Kh


@pytest.mark.parametrize("build, name", [
    (lambda: Soil(0.0, 18e3), "phi"), (lambda: Soil(90.0, 18e3), "phi"), (lambda: Soil(-5, 18e3), "phi"),
    (lambda: Soil(30, -1.0), "gamma"), (lambda: Soil("abc", 18e3), "phi"), (lambda: Soil(float("nan"), 18e3), "phi"),
    (lambda: Wall(0.0), "H"), (lambda: Wall(-3.0), "H"), (lambda: Wall(3.0, surcharge=-1), "q"),
    (lambda: Wall(None), "H"), (lambda: Wall(3.0, beta_deg=True), "beta"),
    (lambda: coulomb(Soil(30, 1.0), Wall(1.0, 31.0)), "delta"),
    (lambda: rankine(Soil(30, 1.0), Wall(1.0, beta_deg=31.0)), "beta"),
    (lambda: coulomb(Soil(30, 1.0), Wall(1.0, beta_deg=31.0)), "beta"),
    (lambda: mononobe_okabe(Soil(30, 1.0), Wall(1.0), kh=0.7), "kh"),
    (lambda: mononobe_okabe(Soil(30, 1.0), Wall(1.0), kh=0.1, kv=1.5), "kv"),
    (lambda: janssen(Soil(30, 1.0), Wall(1.0, 10), width=0.0), "width"),
])
def test_invalid_inputs_raise_one_line_error(build, name):
    with pytest.raises(InvalidParameter) as err:
        build()
    assert isinstance(err.value, ValueError)
    assert err.value.name == name
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith(name) and ("valid range" in msg or "not valid; expected" in msg)


def test_no_silent_nan_anywhere():
    """Across 0 < phi < 90 every method returns finite numbers or raises InvalidParameter
    (e.g. the planar passive wedge has no finite solution once
    sin(phi + delta) sin(phi + beta) >= cos(delta - omega) cos(beta - omega))."""
    import warnings
    s_of = lambda phi: Soil(phi, 18e3)
    calls = [lambda s, w: rankine(s, w), lambda s, w: rankine(s, w, True), lambda s, w: coulomb(s, w),
             lambda s, w: coulomb(s, w, True), lambda s, w: jaky(s, w), lambda s, w: janssen(s, w, 2.0),
             lambda s, w: paik_salgado(s, w), lambda s, w: paik_salgado(s, w, "i"), lambda s, w: handy(s, w),
             lambda s, w: khosravi(s, w), lambda s, w: mononobe_okabe(s, w, 0.1, 0.05),
             lambda s, w: mononobe_okabe(s, w, 0.1, 0.05, True), lambda s, w: seed_whitman(s, w, 0.1)]
    finite = refused = 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a numpy overflow/divide warning is a silent NaN in waiting
        for phi in np.linspace(0.5, 89.5, 60):
            for frac in (0.0, 0.5, 1.0):
                for call in calls:
                    try:
                        p = call(s_of(float(phi)), Wall(3.0, frac * phi))
                    except InvalidParameter:
                        refused += 1
                        continue
                    assert np.all(np.isfinite(p.sigma_h)) and math.isfinite(p.K) and math.isfinite(p.height)
                    finite += 1
    assert finite > 10 * refused
