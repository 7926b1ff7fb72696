"""The dry-stone study end to end on a small wall, and its user errors.

Sources: the limit equilibrium of the part above the fixed first course
(analytic.drystone, reference 5.4, sliding H = W tan(phi_b)) for the DEM's critical
height; docs/reference/drystone-walls.md 2.1 (S-OET Table 3) for the measured
values the result must carry; tests/cli/test_user_errors.py for the error contract.
"""

import json

import pytest

import cli
from studies import get

SMALL = {"height_m": 1.0, "base_width_m": 0.4, "increment_fraction": 0.02}


def test_compare_drystone_writes_its_outputs(tmp_path):
    study = get("drystone")
    case = study.case(**SMALL)
    r = study.run(case, out=str(tmp_path), quiet=True)
    folder = tmp_path / "drystone"
    run = next(folder.iterdir())
    for name in ("history.csv", "history.png", "mechanism.png", "comparison.csv", "result.json", "manifest.json",
                 "config.toml", "recording.rrd"):
        assert (run / name).is_file(), name
    # S-OET Table 3 / reference 2.1: V1L failed at 1.74 m by sliding
    assert r["measured"] == {"height_m": 1.74, "mode": "sliding"}
    fx = r["limit_equilibrium"]["above-fixed-course"]
    # the DEM fails at the first 2 % increment at or above the rigid-block limit equilibrium
    assert fx["critical_height_m"] - 1e-3 <= r["dem"]["critical_height_m"] <= fx["critical_height_m"] + 0.021
    assert r["dem"]["mode"] == fx["mode"] == "sliding"
    assert any("ASSUMED" in a for a in r["assumptions"]) and any("wall height 1 m" in a for a in r["assumptions"])
    assert "numerical, not physical" in r["note"]
    saved = json.loads((run / "result.json").read_text())
    assert saved["dem"]["critical_height_m"] == r["dem"]["critical_height_m"]
    from viz.readback import entity_paths
    assert {"/world/blocks", "/world/water", "/world/joint_forces", "/case"} <= entity_paths(run / "recording.rrd")
    header = (run / "history.csv").read_text().splitlines()[0]
    assert header == "water_height_m,crest_displacement_m,settled,time_s"


BAD = [
    ["compare", "drystone", "--wall", "V9X"],
    ["compare", "drystone", "--unit-weight", "-3"],
    ["compare", "drystone", "--set", "base_width_m=0.2"],      # crest width < 0 with a 15 deg batter
    ["compare", "drystone", "--set", "dt=1"],
    ["compare", "drystone", "--set", "wall=V6L"],
    ["compare", "drystone", "--geometry", "guess"],
    ["validate", "drystone", "--walls", "V1L,V7"],
    ["validate", "drystone", "--case", "C"],
    ["validate", "drystone", "--case", "B", "--walls", "V1L"],      # a case-A wall
    ["validate", "drystone", "--case", "B", "--backfill-seeds", "1,1"],
    ["calibrate", "tilt", "--friction", "95"],
    ["calibrate", "tilt", "--friction", "abc"],
]


@pytest.mark.parametrize("argv", BAD, ids=[" ".join(a) for a in BAD])
def test_bad_input_is_one_line_and_exit_2(argv, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as stop:
        raise SystemExit(cli.main(argv))
    err = capsys.readouterr().err
    assert stop.value.code == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []          # nothing written


@pytest.mark.parametrize("gamma,widths", [(18.0, (0.84, 0.74, 1.60, 0.82, 1.80)), (20.0, (0.78, 0.70, 1.49, 0.78, 1.67)),
                                          (22.0, (0.73, 0.67, 1.41, 0.75, 1.56))])
def test_the_back_fit_widths_are_reference_2_3s(gamma, widths):
    """docs/reference/drystone-walls.md 2.3: the base widths (V1L..V5S, 2 decimals) at
    which the yield-design limit equilibrium fails at the measured water height, at
    gamma_m 18, 20 (its table) and 22 kN/m3 (its sensitivity list); the independence runs
    fit them again the same way."""
    from dataclasses import replace

    from studies.drystone.case import DrystoneCase
    from studies.drystone.validate import refit_base_width
    got = [refit_base_width(replace(DrystoneCase(wall=w), unit_weight_kN_m3=gamma))
           for w in ("V1L", "V2L", "V3L", "V4L", "V5S")]
    assert got == pytest.approx(widths, abs=0.006)


def test_case_a_overall_rows_read_each_wall_against_the_site():
    """Section 5.1: the paper's DEM within 9 % of the site and above it except at V4L.
    Heights 2 % above the site everywhere but 2 % below at V4L match both; 2 % above at
    V4L too misses the second; 10 % above at V1L misses the first."""
    import json as _json
    from pathlib import Path as _Path

    from studies.drystone.scorecard import scorecard_rows
    ref = _json.loads(_Path("studies/drystone/reference.json").read_text())

    def rows(factors):
        walls = {w: {"critical_height_m": factors.get(w, 1.02) * v["measured_height_m"]["value"], "mode": "sliding"}
                 for w, v in ref["walls"].items()}
        got = scorecard_rows({"walls": walls}, ref)
        return {r.statement: r.verdict for r in got if r.statement.startswith("case A: the DEM's")}

    within, above = "case A: the DEM's critical heights within 9 % of the site's", \
        "case A: the DEM's critical heights above the site's, except V4L"
    assert rows({"V4L": 0.98}) == {within: "matches", above: "matches"}
    assert rows({})[above] == "misses"
    assert rows({"V1L": 1.10, "V4L": 0.98})[within] == "misses"
