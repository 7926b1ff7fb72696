"""Bearing under a strongly inclined load: never a negative resistance (issue 40).

EN 1997-1 Annex D.4's inclination factors, by hand for a strip (B'/L' = 0, m = 2),
phi' = 30 deg, c' = 10 kPa, B = 2 m, V = 100 kN/m:
    N_q = e^(pi tan 30) tan^2 60 = 18.401, N_c = (N_q - 1) cot 30 = 30.140,
    V + A' c' cot phi' = 100 + 2 x 10 x 1.7321 = 134.64 kN/m,
    i_c = i_q - (1 - i_q)/(N_c tan phi') reaches 0 at i_q = 1/N_q, i.e. at
    H_lim = 134.64 (1 - 18.401^(-1/2)) = 103.25 kN/m.
Past H_lim the factors would be negative (the issue's q_ult = -17.3 kPa at H = 150):
the bearing fails instead. Undrained (D.3): i_c = (1 + sqrt(1 - H/(A' c_u)))/2 is real
up to H_lim = A' c_u.
"""

import math
import re
import tomllib
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cli
from analytic.design import bearing_resistance, bearing_undrained
from analytic.design.config import case_from_dict
from analytic.design.factors import load_factors
from analytic.design.formats import verify

ROOT = Path(__file__).resolve().parents[3]
NQ = math.exp(math.pi * math.tan(math.radians(30))) * math.tan(math.radians(60)) ** 2
CARRIED = 100 + 2 * 10 / math.tan(math.radians(30))
H_LIM = CARRIED * (1 - NQ ** -0.5)


def test_the_issues_leaning_load_fails_with_its_limit_instead_of_a_negative_resistance():
    for method in ("ec7", "vesic"):
        b = bearing_resistance(phi=30, c=10, gamma=18, q=0, B=2, V=100, H=150, method=method)
        assert b.q_ult == 0.0 and b.R == 0.0
        assert b.H_limit == pytest.approx(H_LIM, rel=1e-12) and b.H_limit == pytest.approx(103.2536, abs=1e-4)
        assert b.fails.startswith("bearing fails: H = 150 kN/m >= H_lim = 103.3 kN/m")


def test_below_the_limit_the_factors_are_annex_ds_and_stay_in_range():
    """H = 50 kN/m: i_q = (1 - 50/134.64)^2 = 0.39520, i_gamma = 0.24844,
    i_c = 0.39520 - 0.60480/(30.140 tan 30) = 0.36044; q_ult = c N_c i_c + 0.5 gamma B N_gamma i_gamma
    with N_gamma = 2 (N_q - 1) tan 30 = 20.093: 108.64 + 89.84 = 198.5 kPa."""
    b = bearing_resistance(phi=30, c=10, gamma=18, q=0, B=2, V=100, H=50)
    base = 1 - 50 / CARRIED
    assert b.factors["iq"] == pytest.approx(base ** 2, rel=1e-12) and b.factors["iq"] == pytest.approx(0.39520, abs=1e-5)
    assert b.factors["ic"] == pytest.approx(0.36044, abs=1e-5)
    assert b.q_ult == pytest.approx(198.5, abs=0.05) and b.fails is None
    just_below = bearing_resistance(phi=30, c=10, gamma=18, q=0, B=2, V=100, H=H_LIM * (1 - 1e-9))
    assert just_below.fails is None and 0 <= just_below.factors["ic"] < 1e-8 and just_below.q_ult > 0


def test_without_cohesion_the_limit_is_V():
    """c' = 0: i_q = (1 - H/V)^m reaches 0 at H = V (the issue's H = 400 > V = 300 gave
    q_ult = 0 with a negative i_c)."""
    b = bearing_resistance(phi=30, c=0, gamma=18, q=18, B=2, V=300, H=400)
    assert b.H_limit == 300 and b.q_ult == b.R == 0.0 and "H_lim = 300 kN/m = V" in b.fails
    assert bearing_resistance(phi=30, c=0, gamma=18, q=18, B=2, V=300, H=299).q_ult > 0


def test_undrained_bearing_fails_once_the_base_slides():
    """D.3 with c_u = 50 kPa, B = 2 m: H_lim = A' c_u = 100 kN/m; at H = 100, i_c = 0.5
    and q_ult = (pi + 2) 50 x 0.5 + q."""
    at = bearing_undrained(cu=50, q=10, B=2, V=200, H=100)
    assert at.fails is None and at.factors["ic"] == 0.5
    assert at.q_ult == pytest.approx((math.pi + 2) * 25 + 10, rel=1e-12)
    past = bearing_undrained(cu=50, q=10, B=2, V=200, H=120)
    assert past.q_ult == past.R == 0.0 and "H_lim = 100 kN/m = A' c_u" in past.fails


@settings(max_examples=300, deadline=None)
@given(phi=st.floats(1, 50), c=st.floats(0, 100), q=st.floats(0, 200), B=st.floats(0.2, 10),
       V=st.floats(1, 5000), H=st.floats(0, 10000), e_frac=st.floats(-0.49, 0.49), method=st.sampled_from(["ec7", "vesic"]))
def test_no_input_gives_a_negative_bearing_resistance(phi, c, q, B, V, H, e_frac, method):
    b = bearing_resistance(phi=phi, c=c, gamma=18, q=q, B=B, V=V, H=H, e=e_frac * B, method=method)
    assert b.q_ult >= 0 and b.R >= 0
    assert (b.fails is not None) == (H >= b.H_limit)
    assert all(0 <= b.factors[k] <= 1 for k in ("iq", "ic", "igamma"))


def _cantilever(**changes) -> dict:
    d = tomllib.loads((ROOT / "docs" / "examples" / "cantilever.toml").read_text())
    for key, value in changes.items():
        table, name = key.split(".")
        d[table][name] = value
    return d


def test_design_reports_the_failed_bearing_with_its_reason():
    """The example cantilever with a 1 m heel on a c' = 5 kPa foundation: in DA1-1 the
    design H exceeds Annex D's limit, so bearing fails (R_d = 0, the reason in the check),
    and no check anywhere has a negative resistance."""
    case = case_from_dict(_cantilever(**{"wall.heel": 1.0, "foundation.c": 5.0}))
    factors = load_factors()
    r = verify(case, factors, "DA1")
    label, bearing = r.worst["bearing"]
    assert bearing.R_d == 0 and bearing.utilisation == math.inf and "H_lim" in bearing.note
    for fmt in ("DA1", "DA2", "DA3", "EQU", "fs"):
        assert all(c.R_d >= 0 for _, c in verify(case, factors, fmt).worst.values())


def test_design_text_says_why_bearing_fails(tmp_path, capsys):
    import tomli_w
    wall = tmp_path / "wall.toml"
    wall.write_text(tomli_w.dumps(_cantilever(**{"wall.heel": 1.0, "foundation.c": 5.0})))
    assert cli.main(["design", str(wall), "--format", "DA1"]) == 0
    out = capsys.readouterr().out
    assert "bearing fails: H = " in out and "H_lim" in out
    table = out.split("combination\n")[1].split("\n  governing")[0].splitlines()
    rows = [line for line in table if line.split()[-1].startswith("DA1")]
    assert rows and not any(re.search(r"\s-\d", line) for line in rows)          # no negative number
