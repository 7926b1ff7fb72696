"""Coulomb's c-a trial wedge (analytic/wedge.py): identities from theory, one published
example with printed answers (tests/data/analytic_published.json), and the comparison
with EN 1997-1 C.1 that ground.earth_pressure uses for cohesion (reported, not tuned)."""

import math

import pytest

from analytic import InvalidParameter
from analytic.classical import coulomb_coefficient
from analytic.ground import Ground, earth_pressure
from analytic.inputs import Wall
from analytic.wedge import cohesive_wedge
from tests.conftest import load_reference

REF = load_reference("analytic_published.json")


@pytest.mark.parametrize("phi, delta", [(30, 0), (30, 20), (34, 24.7), (40, 10)])
@pytest.mark.parametrize("passive", [False, True])
def test_cohesionless_wedge_is_coulomb(phi, delta, passive):
    """Theory: c = a = 0 is Coulomb's wedge, K = Mueller-Breslau's closed form (to 1e-9)."""
    r = cohesive_wedge(5.0, phi, 18e3, delta_deg=delta, passive=passive)
    K = coulomb_coefficient(math.radians(phi), math.radians(delta), 0, 0, passive=passive)
    assert r.P / (0.5 * 18e3 * 25) == pytest.approx(K, rel=1e-9)


def test_bell_active_with_crack_and_surcharge():
    """Theory (Bell 1915 with a tension crack), delta = a = 0: the KSU CE 481 / Das case
    of test_ground.py (H 4, gamma 15, phi 26, c 8, q 10): z0 = (2 c sqrt(Ka) - Ka q) /
    (Ka gamma) = 1.0404 m, P = 25.65 kN/m; the critical plane at 45 + phi/2 = 58 deg."""
    Ka = math.tan(math.radians(32)) ** 2
    r = cohesive_wedge(4.0, 26, 15e3, 8e3, q=10e3)
    z0 = (2 * 8 * math.sqrt(Ka) - Ka * 10) / (Ka * 15)
    assert r.crack_depth == pytest.approx(z0, rel=1e-7)
    assert r.P / 1e3 == pytest.approx(0.5 * (Ka * 70 - 16 * math.sqrt(Ka)) * (4 - z0), rel=1e-7)
    assert abs(r.P / 1e3 - 25.65) < 0.01
    assert r.theta_deg == pytest.approx(58.0, abs=1e-5)
    # the same as the Rankine-Bell profile of ground.earth_pressure
    d = earth_pressure(Ground.uniform(4.0, 26, 15e3, 8e3), Wall(4.0, surcharge=10e3))
    assert r.P == pytest.approx(d.parts["soil"].N + d.parts["surcharge"].N, rel=1e-7)


def test_bell_passive():
    """Theory: passive, delta = a = 0: 1/2 Kp gamma H^2 + 2 c H sqrt(Kp) = 250.90 kN/m
    (phi 20, c 10 kPa, gamma 18, H 3; test_ground.py's hand calculation)."""
    r = cohesive_wedge(3.0, 20, 18e3, 10e3, passive=True)
    Kp = math.tan(math.radians(55)) ** 2
    assert r.P / 1e3 == pytest.approx(0.5 * Kp * 18 * 9 + 2 * 10 * math.sqrt(Kp) * 3, rel=1e-9)
    assert r.crack_depth == 0.0


@pytest.mark.parametrize("a_over_c", [0.0, 0.5, 1.0])
def test_undrained_adhesion_is_en1997_kac(a_over_c):
    """Theory: phi = delta = 0: P(theta) = 1/2 gamma H^2 - H [(a + c) t + c / t], t =
    tan(theta), largest at t = sqrt(c / (a + c)): the pressure is gamma z - 2 c
    sqrt(1 + a/c), i.e. EN 1997-1 C.1's K_ac = 2 sqrt(K_n (1 + a/c)) with K_n = 1; crack
    z0 = 2 c sqrt(1 + a/c) / gamma. (H 6, gamma 17, c 35 kPa.)"""
    kac = 2 * math.sqrt(1 + a_over_c)
    r = cohesive_wedge(6.0, 0.0, 17e3, 35e3, a_over_c * 35e3)
    z0 = kac * 35 / 17
    assert r.crack_depth == pytest.approx(z0, rel=1e-7)
    assert r.P / 1e3 == pytest.approx(0.5 * (17 * 6 - kac * 35) * (6 - z0), rel=1e-7)
    p = cohesive_wedge(6.0, 0.0, 17e3, 35e3, a_over_c * 35e3, passive=True)
    assert p.P / 1e3 == pytest.approx(0.5 * 17 * 36 + kac * 35 * 6, rel=1e-9)


def test_bell_undrained_published_acharya():
    """Published: Acharya, Sheet Piles with Numericals, Numerical 3 (as quoted by
    xcfem/xc): c_u 35 kPa, gamma 17, H 6: h0 = 4.12 m, Pa = 30.08 kN/m (printed).
    wallsim: 4.1176 m and 30.118 kN/m; the book's Pa uses h0 rounded to 4.12 (0.13 %)."""
    e = REF["bell_undrained_acharya_n3"]
    r = cohesive_wedge(e["H"], e["phi"], e["gamma"] * 1e3, e["c_u"] * 1e3)
    assert round(r.crack_depth, 2) == e["crack_depth_m"]
    assert r.P / 1e3 == pytest.approx(e["Pa_kN"], rel=5e-3)


def test_wedge_equals_en1997_c1_for_bell():
    """Comparison (reported, not tuned): EN 1997-1 C.1's K_ac = 2 sqrt(K_n (1 + a/c)) is
    exact for delta = a = 0 (Bell) and for phi = 0 (above), an approximation otherwise.
    H 6, gamma 18, c 10 kPa, horizontal thrusts, C.1 against the trial wedge (measured,
    not asserted: no source gives them): phi 25, delta 0, a/c 0.5: +1.2 %; phi 25,
    delta 2/3 phi, a/c 0.5: -8.4 %; phi 30, delta 20, a/c 0: -7.8 %; phi 30, delta 20,
    a/c 1: +5.6 %. Asserted: the C.1 profile of ground.earth_pressure equals the wedge
    (1e-7) for delta = a = 0, where both are Bell's solution."""
    r = cohesive_wedge(6.0, 30, 18e3, 10e3)
    d = earth_pressure(Ground.uniform(6.0, 30, 18e3, 10e3), Wall(6.0), "coulomb")
    assert d.horizontal_thrust() == pytest.approx(r.P_h, rel=1e-7)


@pytest.mark.parametrize("kw, name", [(dict(c=-1.0), "c"), (dict(c=5e3, adhesion=6e3), "adhesion"),
                                      (dict(delta_deg=35.0), "delta"), (dict(phi_deg=95.0), "phi")])
def test_wedge_bad_input(kw, name):
    """Bad input: one InvalidParameter naming the parameter."""
    args = dict(H=4.0, phi_deg=30.0, gamma=18e3)
    args.update(kw)
    with pytest.raises(InvalidParameter, match=f"^{name} = "):
        cohesive_wedge(**args)
