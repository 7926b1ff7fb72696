"""Closed forms against published numbers (tests/data/analytic_published.json)."""

import math

import numpy as np
import pytest
from scipy.integrate import trapezoid

from analytic import Soil, Wall, coulomb, jaky, janssen, rankine
from analytic.classical import janssen_vertical_stress
from analytic.seismic import mononobe_okabe
from tests.conftest import load_reference

REF = load_reference("analytic_published.json")


def _close(value, case, key="K"):
    if "atol" in case:
        return abs(value - case[key]) <= case["atol"]
    return math.isclose(value, case[key], rel_tol=case["rtol"])


@pytest.mark.parametrize("case", REF["coulomb_active"], ids=lambda c: f"phi{c['phi']}-d{c['delta']}")
def test_coulomb_active_matches_published(case):
    p = coulomb(Soil(case["phi"], 18e3), Wall(1.0, case["delta"], case["omega"], case["beta"]))
    assert _close(p.K, case), (p.K, case["source"])


@pytest.mark.parametrize("case", REF["coulomb_passive"], ids=lambda c: f"phi{c['phi']}-d{c['delta']}")
def test_coulomb_passive_matches_published(case):
    p = coulomb(Soil(case["phi"], 18e3), Wall(1.0, case["delta"], case["omega"], case["beta"]), passive=True)
    assert _close(p.K, case), (p.K, case["source"])


@pytest.mark.parametrize("case", REF["jaky"], ids=lambda c: f"phi{c['phi']}")
def test_jaky_matches_published(case):
    assert math.isclose(jaky(Soil(case["phi"], 18e3), Wall(1.0)).K, case["K0"], rel_tol=case["rtol"])


def test_rankine_khosravi_case():
    case = REF["rankine"][0]
    assert math.isclose(rankine(Soil(case["phi"], 1.0), Wall(1.0)).K, case["K"], rel_tol=case["rtol"])


def test_issue_acceptance_numbers():
    """Issue 2: phi 34, delta 24.7, H 3.1, gamma 16.7 -> Coulomb 0.2542 (+-0.0005),
    Jaky 0.4408, Rankine 0.2827 (Das-form closed forms; Nadukuru & Michalowski 2012)."""
    s, w = Soil(34, 16.7e3), Wall(3.1, 24.7)
    assert abs(coulomb(s, w).K - 0.2542) <= 5e-4
    assert abs(jaky(s, w).K - 0.4408) <= 5e-5
    assert abs(rankine(s, w).K - 0.2827) <= 5e-5


def test_coulomb_critical_wedge_angle():
    """analytic-formulas.md section 2: phi 34, delta 24.7 -> slip plane at 58.07 deg from horizontal."""
    p = coulomb(Soil(34, 1.0), Wall(1.0, 24.7))
    assert abs(p.extra["wedge_angle_deg"] - 58.07) < 0.01


def test_mononobe_okabe_en1998_example():
    """EN 1998-5 worked example (eurocodeapplied.com via xcfem): K_ad = 0.4856177, K_pd = 2.6."""
    m = REF["mononobe_okabe"]
    s, w = Soil(m["phi"], 1.0), Wall(1.0, m["delta"])
    act = mononobe_okabe(s, w, m["kh"], m["kv_ec8"])
    pas = mononobe_okabe(s, w, m["kh"], m["kv_ec8"], passive=True)
    assert math.isclose(act.extra["K_E"], m["K_ad"], rel_tol=m["K_ad_rtol"])
    assert math.isclose(pas.extra["K_E"], m["K_pd"], rel_tol=m["K_pd_rtol"])


def test_janssen_and_jaky_against_xcfem_quantity():
    """xcfem/xc test_k_janssen_01: -trapezoid(z_i, sigma_h) on a 0.25 m grid."""
    j = REF["janssen_xcfem"]
    gamma = j["rho"] * j["g"]
    s = Soil(j["phi"], gamma)
    w = Wall(j["H"], j["phi"] * j["delta_over_phi"])
    zi = np.append(np.arange(0.0, j["H"], j["grid_step"]), j["H"])
    pj = janssen(s, w, j["B"])
    # evaluate on the xcfem grid through the same closed form the profile uses
    sig_j = pj.extra["k"] * janssen_vertical_stress(zi, gamma, 0.0, pj.extra["lambda"])
    assert math.isclose(-trapezoid(-zi, sig_j), j["janssen_quantity"], rel_tol=j["rtol"])
    sig_k = jaky(s, Wall(j["H"])).K * gamma * zi
    assert math.isclose(-trapezoid(-zi, sig_k), j["jaky_quantity"], rel_tol=j["rtol"])


# ---- worked examples of Das's textbooks, as transcribed in the FOSSEE Python Textbook
# ---- Companion (sources, inputs and printed figures in analytic_published.json)
def _ground(case, **kw):
    from analytic.ground import Ground, Layer
    layers = tuple(Layer(x["thickness"], x["phi"], x["gamma"] * 1e3, x.get("c", 0.0) * 1e3,
                         x["gamma_sat"] * 1e3 if "gamma_sat" in x else None) for x in case["layers"])
    return Ground(layers, water_depth=case["water_depth"], unit_weight_water=case["gamma_w"] * 1e3, **kw)


def _at(profile, z):
    """The soil stresses [kPa] tabulated at depth z (above, below when z is an interface)."""
    return profile.sigma_soil[np.isclose(profile.z, z)] / 1e3


def test_das_pge_13_4_layered_backfill_with_water():
    """Published: Das PGE Example 13.4: 16 and 13.0 kPa either side of the interface,
    Pa = 117.15 kN/m at 1.78 m. wallsim: 16.000 / 13.008 kPa, 117.155 kN/m (73.010 soil +
    44.145 water) at 1.781 m."""
    from analytic.ground import earth_pressure
    c = REF["das_pge_13_4_layered_water"]
    d = earth_pressure(_ground(c), Wall(c["H"]))
    above, below = _at(d, 3.0)
    assert round(above, 1) == c["sigma_top_layer_3m_kPa"] and round(below, 1) == c["sigma_bottom_layer_3m_kPa"]
    N = d.parts["soil"].N + d.parts["water"].N
    h = (d.parts["soil"].N * d.parts["soil"].height + d.parts["water"].N * d.parts["water"].height) / N
    assert round(N / 1e3, 2) == c["Pa_kN"]
    assert round(h, 2) == c["height_m"]


def test_das_pfe_7_2_bell_c_phi_tension_crack():
    """Published: Das PFE Example 7.2 (c' 14.36 kPa, phi' 26, H 6): crack 2.64 m, Pa after
    the crack 38.32 kN/m at 1.12 m (companion, exact Ka); before the crack the book prints
    14.46 kN/m with Ka = 0.39 and sqrt(Ka) = 0.625 (122.16 - 107.70), the companion 14.62
    with the exact Ka: the rounding of two large terms moves their small difference by
    1.1 %. wallsim: 2.641 m, 38.317 kN/m at 1.120 m; before the crack 14.615 kN/m."""
    from analytic.ground import Ground, earth_pressure
    from analytic.wedge import cohesive_wedge
    c = REF["das_pfe_7_2_bell"]
    d = earth_pressure(Ground.uniform(c["H"], c["phi"], c["gamma"] * 1e3, c["c"] * 1e3), Wall(c["H"]))
    assert round(d.tension_crack_depth, 2) == c["crack_depth_m"]
    assert round(d.parts["soil"].N / 1e3, 2) == c["Pa_after_crack_kN"]
    assert round(d.parts["soil"].height, 2) == c["height_after_crack_m"]
    before = cohesive_wedge(c["H"], c["phi"], c["gamma"] * 1e3, c["c"] * 1e3, tension_crack=False)
    assert round(before.P / 1e3, 2) == c["Pa_before_crack_companion_kN"]
    # the book's 14.46 is the same expression with its rounded Ka (0.39) and sqrt(Ka)
    # (0.625), the base pressures rounded to 0.01 kPa first: 1/2 H (40.72) - H (17.95) =
    # 122.16 - 107.70; wallsim's exact Ka gives the companion's 14.62 (asserted above)


def test_das_pge_13_5_undrained_clay_crack():
    """Published: Das PGE Example 13.5 (phi = 0, c_u 10, gamma 16.5, H 6): 177.0 kN/m before
    the crack, 189.1 after, z_o 1.21 m. wallsim (c-a wedge, delta = a = 0, i.e. Bell with
    Ka = 1): 177.000, 189.121 kN/m, 1.2121 m."""
    from analytic.wedge import cohesive_wedge
    c = REF["das_pge_13_5_undrained"]
    args = (c["H"], c["phi"], c["gamma"] * 1e3, c["c_u"] * 1e3)
    assert round(cohesive_wedge(*args, tension_crack=False).P / 1e3, 1) == c["Pa_before_crack_kN"]
    after = cohesive_wedge(*args)
    assert round(after.P / 1e3, 1) == c["Pa_after_crack_kN"]
    assert round(after.crack_depth, 2) == c["crack_depth_m"]


def test_das_pfe_7_7_passive_layered_cohesive_with_water():
    """Published: Das PFE Example 7.7, Rankine-Bell passive: 94.32 kPa (sand) and 112.53 kPa
    (clay) at 2 m, 135.7 kPa at 3 m. wallsim: 94.320, 112.527, 135.704 kPa; water apart
    (9.81 kPa at 3 m)."""
    from analytic.ground import earth_pressure
    c = REF["das_pfe_7_7_passive_layered"]
    d = earth_pressure(_ground(c), Wall(c["H"]), passive=True)
    sand, clay = _at(d, 2.0)
    assert round(sand, 2) == c["sigma_p_2m_sand_kPa"] and round(clay, 2) == c["sigma_p_2m_clay_kPa"]
    assert round(d.sigma_soil[-1] / 1e3, 1) == c["sigma_p_3m_kPa"]
    assert d.u[-1] / 1e3 == pytest.approx(9.81, rel=1e-12)


def test_das_pge_14_1_passive_coulomb_and_log_spiral():
    """Published: Das PGE Example 14.1 (phi' 30, delta' 15): Coulomb Kp 4.977 (Table 13.9),
    Pp 351.6 kN/m: wallsim 4.9765, 351.6. Curved surfaces: Terzaghi & Peck chart 4.53,
    Zhu & Qian 4.56, Shields & Tolunay (method of slices) 4.13. wallsim's trial log-spiral
    4.615 is +1.9 % on the chart value (not within 0.5 %; reported in the JSON, not
    tuned); asserted only what must hold: between the method of slices and Coulomb."""
    from analytic.logspiral import terzaghi_log_spiral_kp
    c = REF["das_pge_14_1_passive_curved"]
    p = coulomb(Soil(c["phi"], c["gamma"] * 1e3), Wall(c["H"], c["delta"]), passive=True)
    assert round(p.K, 3) == c["Kp_coulomb"]
    assert round(p.thrust / 1e3, 1) == c["Pp_coulomb_kN"]
    K, _ = terzaghi_log_spiral_kp(c["phi"], c["delta"])
    assert c["Kp_shields_tolunay"] < K < c["Kp_coulomb"]
