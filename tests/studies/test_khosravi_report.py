"""The Khosravi report's time item: the issue's goal (studies/khosravi/reference.json,
'case_wall_time_min_at_most' = 30 min for pluviation + translation at full size) is
judged on one run that filled its own box; a run that reused a specimen cannot say."""

import json

import numpy as np
import pytest

from studies.khosravi.compare import REFERENCE
from studies.khosravi.report import _time_check

GOAL = json.loads(REFERENCE.read_text())["targets"]["case_wall_time_min_at_most"]


def _result(pluviation_min, rest_min, translation_min, reused=False):
    return {"specimen_reused": reused,
            "timings_s": {"pluviation_s": 60 * pluviation_min, "at_rest_s": 60 * rest_min,
                          "translation_to_active_s": 60 * translation_min,
                          "translation_s": 60 * 3 * translation_min}}  # a validation run goes on


def test_time_item_sums_pluviation_rest_and_translation_to_the_active_reading():
    assert GOAL == 30
    ok = _time_check(_result(20.0, 1.0, 8.5), GOAL)
    assert ok["ok"] is True and ok["measured"].startswith("29.5 min")
    late = _time_check(_result(20.0, 1.0, 9.5), GOAL)
    assert late["ok"] is False and late["measured"].startswith("30.5 min")


def test_time_item_is_not_judged_on_a_reused_specimen():
    assert _time_check(_result(0.1, 1.0, 8.0, reused=True), GOAL)["ok"] is None


def test_ps0_against_the_straight_line_through_the_readings():
    # reference: arithmetic. On a Jaky-like line sigma = 0.65 z the trend at z = 0.98 is
    # 0.637; a PS0 of half that reads 0.5, and one reading alone gives no line
    from studies.khosravi.compare import _over_linear_trend
    z = np.array([0.93, 0.8, 0.67, 0.53, 0.4, 0.27, 0.13])
    assert _over_linear_trend(0.5 * 0.65 * 0.98, z, 0.65 * z, 0.98) == pytest.approx(0.5)
    assert _over_linear_trend(0.3, z[:1], z[:1], 0.98) is None


def test_profile_parts_read_rankine_exactly_on_readings_that_are_rankine():
    """Fig. 13(b)'s statements are scored on theory / DEM at each active reading. DEM
    readings on Rankine's line, sigma_h / (gamma H) = Ka z / H with Ka = tan^2(45 - phi/2)
    (phi 20 deg: Ka 0.4903), give Rankine a mean ratio of 1 and no scatter in both parts;
    Handy's arching profile is not that line (its ratio departs from 1)."""
    from studies.khosravi.scorecard import profile_parts
    z = np.array([0.93, 0.8, 0.67, 0.53, 0.4, 0.27, 0.13])
    ka = np.tan(np.radians(45.0 - 10.0)) ** 2
    assert ka == pytest.approx(0.4903, abs=1e-4)
    res = {"H_m": 0.3, "gamma_N_per_m3": 17000.0, "dem": {"phi_biaxial": 20.0},
           "readings": {"depth_over_H": z.tolist(), "active_over_gammaH": (ka * z).tolist()}}
    parts = profile_parts(res)
    for part in ("upper", "lower"):
        mean, rms = parts["rankine"][part]
        assert mean == pytest.approx(1.0, abs=1e-9) and rms == pytest.approx(0.0, abs=1e-9)
    assert parts["handy"]["upper"][1] > 0.01


def test_overturning_moments_of_readings_on_rankines_line():
    """The two overturning rows on DEM readings on Rankine's line (phi 20 deg), dense to
    the base: the DEM moment is Rankine's, Ka / 6 per gamma H^3 (a triangle's load times
    H/3), so Rankine / DEM is 1 to the trapezoid rule's error and the row reads 'not
    below 1'; an arch theory's moment over it is its own thrust times its resultant's
    height over Rankine's (the Profile's fields, not the integral)."""
    from studies.khosravi.scorecard import _arch_moment_row, _moment_ratio
    from studies.khosravi.theories import theories
    H, gamma, phi = 0.3, 17000.0, 20.0
    z = np.linspace(1.0, 0.0, 401)[:-1]
    ka = np.tan(np.radians(45.0 - phi / 2)) ** 2
    res = {"H_m": H, "gamma_N_per_m3": gamma, "dem": {"phi_biaxial": phi},
           "readings": {"depth_over_H": z.tolist(), "active_over_gammaH": (ka * z).tolist()}}
    assert _moment_ratio(res) == pytest.approx(1.0, rel=1e-4)
    row = _arch_moment_row(res)
    p = theories(phi, gamma, H)
    for name in ("handy", "paik-salgado", "khosravi"):
        want = p[name].thrust_h * p[name].height / (ka * gamma * H ** 3 / 6.0)
        assert f"{name} / DEM {want:.2f}" in row.ours
