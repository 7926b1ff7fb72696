"""Undrained (phi = 0, c_u) earth pressure in total stress, against hand calculations
(Rankine-Bell with K = 1: sigma_a = gamma z + q - 2 c_u, cut at 0 above the tension crack
z_c = (2 c_u - q) / gamma; sigma_p = gamma z + q + 2 c_u; Craig, Soil Mechanics, 11.3).

Theory case: H = 5 m, gamma = 18 kN/m3, c_u = 20 kPa.
    z_c = 40 / 18 = 2.2222 m, P_a = 0.5 x 18 x (5 - 2.2222)^2 = 69.444 kN/m at (5 - z_c)/3 = 0.9259 m;
    the crack full of water: + 0.5 x 9.81 x 2.2222^2 = 24.222 kN/m at 5 - 2/3 z_c = 3.5185 m;
    q = 10 kPa: z_c = 30 / 18 = 1.6667 m, P = 0.5 x 18 x 3.3333^2 = 100.0 kN/m, so P_q = 30.556;
    passive: 0.5 x 18 x 25 + 40 x 5 = 425 kN/m.
Design case: docs/examples/cantilever.toml (virtual back 6 m) with a clay fill phi = 0,
c_u = 30 kPa: DA1-1 (gamma_cu = 1) P = 0.5 x 18 x (6 - 60/18)^2 = 64.0 kN/m; DA1-2
(gamma_cu = 1.4, EN 1997-1 Table A.4) c_u,d = 21.429, P = 9 (6 - 42.857/18)^2 = 117.878 kN/m.
"""

import tomllib
from pathlib import Path

import pytest

import cli
from analytic import Wall
from analytic.design.actions import thrust_for
from analytic.design.config import case_from_dict
from analytic.design.factors import load_factors
from analytic.errors import InvalidParameter
from analytic.ground import Ground, earth_pressure

ROOT = Path(__file__).resolve().parents[2]
CLAY = Ground.uniform(5.0, 0.0, 18e3, 20e3)


def kN(x):
    return x / 1e3


def test_active_thrust_and_crack_by_hand():
    for method in ("rankine", "coulomb"):
        p = earth_pressure(CLAY, Wall(5.0), method)
        assert p.tension_crack_depth == pytest.approx(40 / 18, rel=1e-12)
        assert kN(p.parts["soil"].N) == pytest.approx(0.5 * 18 * (5 - 40 / 18) ** 2, rel=1e-9)
        assert p.parts["soil"].height == pytest.approx((5 - 40 / 18) / 3, rel=1e-9)


def test_water_in_the_crack_by_hand():
    p = earth_pressure(CLAY, Wall(5.0), "rankine", crack_water=True)
    zc = 40 / 18
    assert kN(p.parts["water"].N) == pytest.approx(0.5 * 9.81 * zc ** 2, rel=1e-9)
    assert p.parts["water"].height == pytest.approx(5 - 2 * zc / 3, rel=1e-9)
    assert kN(p.parts["soil"].N) == pytest.approx(0.5 * 18 * (5 - zc) ** 2, rel=1e-9)


def test_surcharge_and_passive_by_hand():
    p = earth_pressure(CLAY, Wall(5.0, surcharge=10e3), "rankine")
    assert p.tension_crack_depth == pytest.approx(30 / 18, rel=1e-12)
    assert kN(p.parts["soil"].N + p.parts["surcharge"].N) == pytest.approx(0.5 * 18 * (5 - 30 / 18) ** 2, rel=1e-9)
    pp = earth_pressure(CLAY, Wall(5.0), "rankine", passive=True)
    assert kN(pp.parts["soil"].N) == pytest.approx(425.0, rel=1e-9)


def test_phi_zero_needs_c_u_and_annex_c_says_why_not():
    with pytest.raises(InvalidParameter, match="undrained"):
        Ground.uniform(5.0, 0.0, 18e3, 0.0)
    assert cli.main(["theory", "--phi", "0", "--H", "5"]) == 2


def test_theory_prints_the_undrained_rows(capsys):
    assert cli.main(["theory", "--phi", "0", "--c", "20", "--H", "5", "--gamma", "18", "--json",
                     "--crack-water"]) == 0
    import json
    rows = {r["name"]: r for r in json.loads(capsys.readouterr().out)["methods"]}
    assert rows["rankine"]["K"] == 1.0
    assert rows["rankine"]["thrust_kN_per_m"] == pytest.approx(0.5 * 18 * (5 - 40 / 18) ** 2 + 0.5 * 9.81 * (40 / 18) ** 2,
                                                               rel=1e-9)
    assert rows["ec7-annex-c"]["K"] is None and "phi = 0" in rows["ec7-annex-c"]["not_applicable"]


def test_design_takes_the_clay_fill_in_total_stress():
    d = tomllib.loads((ROOT / "docs" / "examples" / "cantilever.toml").read_text())
    d["backfill"].update({"phi": 0.0, "c": 30.0})
    d["foundation"]["cu"] = 60.0
    case = case_from_dict(d)
    combos = {c.name: c for c in load_factors().format("DA1")}
    soil = {name: next(p for p in thrust_for(case, c.materials).parts if p.kind == "soil").P
            for name, c in combos.items()}
    assert soil["DA1-1"] == pytest.approx(0.5 * 18 * (6 - 60 / 18) ** 2, rel=1e-9)
    assert soil["DA1-2"] == pytest.approx(0.5 * 18 * (6 - 2 * 30 / 1.4 / 18) ** 2, rel=1e-9)
    d["backfill"]["c"] = 0.0
    with pytest.raises(InvalidParameter, match="backfill.c"):
        case_from_dict(d)
