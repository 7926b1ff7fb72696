"""`wallsim design` and `wallsim bearing`: the JSON keys of issue 29 and one-line errors."""

import json

import pytest

from cli import main

WALL = """
[wall]
type = "cantilever"
height = 6.0
stem_top = 0.5
stem_base = 0.5
toe = 1.2
heel = 3.0
base_thickness = 0.7
unit_weight = 24
[backfill]
gamma = 18
phi = 32
c = 0
beta = 0
[foundation]
gamma = 18
phi = 30
c = 0
base_friction_ratio = 0.6667
embedment = 0.7
[loads]
surcharge = 0
surcharge_permanent = false
[method]
earth_pressure = "rankine-virtual-back"
"""


def write(tmp_path, text=WALL, name="wall.toml"):
    f = tmp_path / name
    f.write_text(text)
    return str(f)


def test_design_fs_json_keys(tmp_path, capsys):
    assert main(["design", write(tmp_path), "--format", "fs", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"fs", "V_kN_per_m", "H_kN_per_m", "e_m", "B_eff_m", "q_ult_kPa", "Ka"} <= set(out)
    assert {"sliding", "overturning", "bearing"} <= set(out["fs"])
    assert out["V_kN_per_m"] == pytest.approx(428.76, rel=1e-9)   # 78.96 + 63.6 + 286.2 (weights by hand)


@pytest.mark.parametrize("fmt", ["DA1", "DA2", "DA3", "EQU", "seismic"])
def test_design_approach_json_keys(tmp_path, capsys, fmt):
    text = WALL + ("\n[seismic]\nalpha = 0.1\nS = 1.2\nr = 1.5\n" if fmt == "seismic" else "")
    assert main(["design", write(tmp_path, text), "--format", fmt, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"V_d_kN_per_m", "H_d_kN_per_m", "checks"} <= set(out)
    wanted = {"overturning"} if fmt == "EQU" else {"sliding", "overturning", "bearing"}
    assert wanted <= set(out["checks"])
    for c in out["checks"].values():
        assert {"E_d", "R_d", "utilisation"} <= set(c)


def test_design_all_text_and_plot(tmp_path, capsys):
    png = tmp_path / "wall.png"
    assert main(["design", write(tmp_path), "--format", "all", "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert "DA1-2" in out and "conventions" in out and "no depth factors" in out
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_design_solve_heel(tmp_path, capsys):
    assert main(["design", write(tmp_path), "--format", "DA1", "--solve", "heel", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["governing"]["utilisation"] == pytest.approx(1.0, abs=1e-3)


def test_bearing_json(capsys):
    assert main(["bearing", "--phi", "30", "--c", "0", "--gamma", "18", "--q", "18", "--B", "2", "--L", "inf",
                 "--e", "0.25", "--V", "300", "--H", "60", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"q_ult_kPa", "R_kN", "B_eff_m", "factors"} <= set(out)
    assert out["q_ult_kPa"] == pytest.approx(350.86, abs=0.01)   # hand calculation in test_design_published
    assert main(["bearing", "--phi", "30", "--gamma", "18", "--B", "2", "--L", "4", "--V", "300",
                 "--method", "vesic", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["factors"]["Ngamma"] == pytest.approx(22.40, abs=0.01)


BAD = [
    ("gravity base narrower than the wall", '[wall]\ntype = "gravity"\nheight = 3\ncrest = 1.0\nbase = 0.8\n'
     '[backfill]\ngamma = 18\nphi = 30\n[foundation]\nphi = 30\n', "wall.base"),
    ("cantilever base narrower than the stem", WALL.replace("heel = 3.0", "base = 1.0"), "wall.base"),
    ("heel that does not fit", WALL.replace("heel = 3.0", "heel = 3.0\nbase = 4.0"), "wall.heel"),
    ("phi above 50", WALL.replace("phi = 32", "phi = 55"), "backfill.phi"),
    ("phi zero", WALL.replace("phi = 30", "phi = 0"), "foundation.phi"),
    ("negative toe", WALL.replace("toe = 1.2", "toe = -1.2"), "wall.toe"),
    ("unknown key", WALL.replace("c = 0\nbeta", "cohesion = 0\nbeta"), "backfill.cohesion"),
    ("unknown table", WALL + "[extra]\na = 1\n", "extra"),
    ("negative backfill cohesion", WALL.replace("c = 0\nbeta", "c = -5\nbeta"), "backfill.c"),
    ("unknown earth-pressure method", WALL.replace('"rankine-virtual-back"', '"log-spiral"'), "earth_pressure"),
    ("gamma_sat below gamma_w", WALL.replace("c = 0\nbeta", "c = 0\ngamma_sat = 9\nbeta"), "backfill.gamma_sat"),
    ("water above the fill", WALL + "[water]\nbehind = 7.0\n", "water.behind"),
    ("cohesion on a sloping Rankine fill", WALL.replace("c = 0\nbeta = 0", "c = 5\nbeta = 10"), "earth_pressure"),
    ("not a boolean", WALL.replace("surcharge_permanent = false", 'surcharge_permanent = "no"'),
     "surcharge_permanent"),
    ("missing key", WALL.replace("gamma = 18\nphi = 32", "phi = 32"), "backfill.gamma"),
    ("bad TOML", WALL + "[[[", "WALL.toml"),
]


@pytest.mark.parametrize("why,text,name", BAD, ids=[b[0] for b in BAD])
def test_design_bad_input_one_line(tmp_path, capsys, why, text, name):
    assert main(["design", write(tmp_path, text)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and name in err[0] and ("valid range" in err[0] or "not valid; expected" in err[0]), err


def test_design_unreadable_file(tmp_path, capsys):
    assert main(["design", str(tmp_path / "missing.toml")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "WALL.toml" in err[0]


def test_bearing_bad_phi(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["bearing", "--phi", "60", "--gamma", "18", "--B", "2", "--V", "100"])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "phi" in err[0] and "(0, 50]" in err[0]


BLOCKS = """
[wall]
type = "blocks"
height = 3.0
base = 1.2
back_batter = 5
courses = 10
joint_slope = 5
joint_friction = 25
unit_weight = 22
[water]
behind = 2.0
"""


def test_design_block_wall_critical_water_height(tmp_path, capsys):
    """Same closed form as test_block_wall_sliding_water_height_matches_closed_form
    (drystone-walls.md 5.4), through the command line."""
    import math
    t = math.tan(math.radians(5))
    x_h = 1.2 / (1 - t * t)
    y_h = -x_h * t
    W = 22 * ((1.2 + 1.2 - 3 * t) / 2 * 3 + 0.5 * 1.2 * abs(y_h))
    T = math.tan(math.radians(30))
    hw = y_h + math.sqrt(2 * W * T / (9.81 * (1 - t * T)))
    assert main(["design", write(tmp_path, BLOCKS), "--format", "fs", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["critical_mechanism"] == "sliding" and out["critical_joint_z_m"] == 0.0
    assert out["critical_water_height_m"] == pytest.approx(hw, abs=1e-5)
    assert len(out["joints"]) == 10 and out["e_m"] is None


def test_design_block_wall_too_narrow(tmp_path, capsys):
    text = BLOCKS.replace("base = 1.2", "base = 0.2").replace("back_batter = 5", "back_batter = 5\nfront_batter = 5")
    assert main(["design", write(tmp_path, text)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "wall.base" in err[0]


def test_design_replaced_factors(tmp_path, capsys):
    """A national annex's table: R2 sliding 1.0 instead of 1.1 divides the DA2 sliding
    utilisation by 1.1 exactly."""
    from importlib import resources
    text = resources.files("analytic.design").joinpath("factors/ec7.toml").read_text()
    assert text.count("sliding = 1.1\n") == 1
    fac = write(tmp_path, text.replace("sliding = 1.1\n", "sliding = 1.0\n"), "na.toml")
    wall = write(tmp_path)
    assert main(["design", wall, "--format", "DA2", "--json"]) == 0
    u0 = json.loads(capsys.readouterr().out)["checks"]["sliding"]["utilisation"]
    assert main(["design", wall, "--format", "DA2", "--factors", fac, "--json"]) == 0
    u1 = json.loads(capsys.readouterr().out)["checks"]["sliding"]["utilisation"]
    assert u1 == pytest.approx(u0 / 1.1, rel=1e-12)
    bad = write(tmp_path, text.replace("[combinations.DA2]", "[combinations.XX]"), "bad.toml")
    assert main(["design", wall, "--format", "DA2", "--factors", bad]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_design_cohesive_fill_and_water_table(tmp_path, capsys):
    """A cohesive fill with a water table through the command line: the numbers of the
    API (checked by hand in tests/analytic/design/test_design_ground.py) and the
    conventions it followed."""
    from analytic.design import factors_of_safety, load_factors, verify
    from analytic.design.config import case_from_dict
    import tomllib
    text = (WALL.replace("c = 0\nbeta", "c = 5\ngamma_sat = 20\nbeta")
            .replace('"rankine-virtual-back"', '"ec7-annex-c"') + "[water]\nbehind = 2.7\n")
    assert main(["design", write(tmp_path, text), "--format", "fs", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    fs = factors_of_safety(verify(case_from_dict(tomllib.loads(text)), load_factors(), "fs"))
    assert out["fs"]["sliding"] == pytest.approx(fs["sliding"], rel=1e-12)
    assert any("water table in the fill 2.7 m" in c for c in out["conventions"])
    assert any("Annex C K_c" in c for c in out["conventions"])


def test_design_layered_fill_toml(tmp_path, capsys):
    """[[backfill.layers]] from the top, the [backfill] soil below them: the numbers of
    test_cantilever_layered_fill_factors_of_safety_by_hand (FS sliding 2.0793)."""
    text = WALL.replace("c = 0\nbeta = 0", "c = 5\nbeta = 0") + (
        "[[backfill.layers]]\nthickness = 2.0\ngamma = 16\nphi = 28\n")
    assert main(["design", write(tmp_path, text), "--format", "fs", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["fs"]["sliding"] == pytest.approx(2.0793, abs=1e-4)
    bad = text.replace("thickness = 2.0", "thickness = -2.0")
    assert main(["design", write(tmp_path, bad)]) == 2
    assert "backfill.layers.thickness" in capsys.readouterr().err


def test_design_seismic_refuses_cohesive_fill(tmp_path, capsys):
    text = WALL.replace("c = 0\nbeta", "c = 5\nbeta") + "[seismic]\nalpha = 0.2\n"
    assert main(["design", write(tmp_path, text), "--format", "seismic"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "seismic.alpha" in err[0]


def test_seismic_format_without_a_seismic_table_is_refused_and_all_says_what_it_skipped(tmp_path, capsys):
    """Before, --format seismic ran a 'seismic' check at k_h = 0 and exit 0, and --format
    all dropped it without a word (issue 40)."""
    assert main(["design", write(tmp_path), "--format", "seismic"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "seismic" in err and "[seismic] table" in err
    assert main(["design", write(tmp_path), "--format", "all"]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith("formats run: DA1, DA2, DA3, EQU, fs; seismic skipped: no [seismic] table")
    assert main(["design", write(tmp_path), "--format", "all", "--json"]) == 0
    assert "no [seismic] table" in json.loads(capsys.readouterr().out)["skipped_formats"]["seismic"]


def test_equ_prints_the_actions_it_weighed(tmp_path, capsys):
    """EQU checks overturning only, but its line gave V_d = 0.00 H_d = 0.00 '(no foundation
    given)' for a file with a [foundation]: it now gives the actions under EQU's factors,
    whose moments are the check's E_d and R_d."""
    assert main(["design", write(tmp_path), "--format", "EQU", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["V_d_kN_per_m"] > 0 and out["H_d_kN_per_m"] > 0
    assert main(["design", write(tmp_path), "--format", "EQU"]) == 0
    text = capsys.readouterr().out
    assert "no foundation given" not in text and "EQU checks overturning about the toe only" in text


@pytest.mark.parametrize("change, name", [
    (("heel = ", "heel = 3000 #"), "wall.heel"),                    # a length in mm
    (("heel = ", "heel = 70 #"), "wall base width B"),              # 12 x the height
    (("embedment = ", "embedment = 9 #"), "foundation.embedment"),  # deeper than the wall is high
])
def test_wall_files_that_make_no_sense_are_refused(tmp_path, capsys, change, name):
    text = WALL.replace(*change, 1)
    assert text != WALL
    assert main(["design", write(tmp_path, text)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"wallsim: error: {name}")
