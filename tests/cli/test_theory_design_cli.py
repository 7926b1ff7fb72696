"""`wallsim theory` with cohesion, water, layers and surface loads (issue 21), and the
K / surcharge columns of issue 20, against hand-computed values."""

import json
import math

import pytest

from cli import main


def run_main(capsys, *args):
    """main() in process (argparse errors exit through SystemExit): (code, stdout, stderr).
    An uncaught exception would fail the test, so no traceback can reach a user."""
    try:
        code = main(list(args))
    except SystemExit as stop:
        code = stop.code
    out, err = capsys.readouterr()
    return code, out, err


def theory_json(capsys, *args):
    assert main(["theory", *args, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    return out, {m["name"]: m for m in out["methods"]}


def test_passive_lists_log_spiral_and_ec7(capsys):
    """Required: --phi 30 --delta 20 --passive lists log-spiral and ec7-annex-c. Hand values:
    Annex C K_n = 4.6327 (tests/analytic/test_ec7_logspiral.py), so K = 4.6327 / cos 20 = 4.930;
    the log-spiral below Coulomb's 6.105."""
    _, by = theory_json(capsys, "--phi", "30", "--delta", "20", "--passive")
    assert {"log-spiral", "ec7-annex-c"} <= set(by)
    assert abs(by["ec7-annex-c"]["Kh"] - 4.6327) < 1e-4
    assert abs(by["ec7-annex-c"]["K"] - 4.6327 / math.cos(math.radians(20))) < 1e-3
    assert by["log-spiral"]["K"] < by["coulomb"]["K"]
    assert "Terzaghi" in by["log-spiral"]["source"]


def test_surcharge_keeps_K_the_soil_coefficient(capsys):
    """Issue 20, hand-computed: defaults (phi 34, H 3.1, gamma 16.7) with q = 10 kPa:
    Rankine K = tan^2(28) = 0.28271 (not 0.392), surcharge thrust Ka q H = 8.764 kN/m,
    total 0.5 * 16.7 * 3.1^2 * 0.28271 + 8.764 = 22.687 + 8.764 = 31.451 kN/m."""
    _, by = theory_json(capsys, "--q", "10")
    r = by["rankine"]
    assert abs(r["K"] - 0.28271) < 1e-5
    assert abs(r["thrust_q_kN_per_m"] - 8.764) < 1e-3
    assert abs(r["thrust_kN_per_m"] - 31.451) < 1e-3
    assert abs(by["coulomb"]["K"] - 0.2542) <= 5e-4          # issue 2's value, unchanged by q


def test_cohesion_water_parts_in_json(capsys):
    """Hand calculation (Rankine-Bell, Ka = 1/3): phi 30, c 5 kPa, gamma 18, gamma_sat 20,
    H 5, water at 2 m, gamma_w 9.81. sigma'_v = 36 at 2 m, 36 + 3 * 10.19 = 66.57 at 5 m;
    2 c sqrt(Ka) = 5.7735; crack 5.7735 * 3 / 18 = 0.9623 m; stress 6.2265 at 2 m,
    16.4165 at 5 m; soil 0.5 * 6.2265 * (2 - 0.9623) + 0.5 * (6.2265 + 16.4165) * 3 = 37.195
    kN/m; water 0.5 * 9.81 * 9 = 44.145 kN/m."""
    out, by = theory_json(capsys, "--phi", "30", "--delta", "0", "--c", "5", "--gamma", "18",
                          "--gamma-sat", "20", "--H", "5", "--water-depth", "2")
    parts = by["rankine"]["parts"]
    assert abs(parts["soil"]["horizontal_kN_per_m"] - 37.195) < 1e-3
    assert abs(parts["water"]["horizontal_kN_per_m"] - 44.145) < 1e-9
    assert by["jaky"]["K"] is None and "not_applicable" in by["jaky"]
    assert out["inputs"]["water_depth_m"] == 2.0 and out["inputs"]["layers"][0]["c_kPa"] == 5.0


def test_layers_file(tmp_path, capsys):
    """The layered case of tests/analytic/test_design.py through a TOML file: soil 54.5206
    kN/m (hand calculation there), water 44.145 kN/m."""
    f = tmp_path / "layers.toml"
    f.write_text("[[layer]]\nthickness = 2\nphi = 30\ngamma = 17\n\n"
                 "[[layer]]\nthickness = 4\nphi = 36\ngamma = 18\nc = 5\ngamma_sat = 20\n")
    _, by = theory_json(capsys, "--H", "6", "--delta", "0", "--layers", str(f), "--water-depth", "3")
    parts = by["rankine"]["parts"]
    assert abs(parts["soil"]["horizontal_kN_per_m"] - 54.5206) < 1e-4
    assert abs(parts["water"]["horizontal_kN_per_m"] - 44.145) < 1e-9


def test_line_and_strip_loads_in_surcharge_part(capsys):
    """Hand: line load 20 kN/m at 1 m on a 5 m wall (m = 0.2): 0.203 * 20 * (1/0.32 - 1/2.32)
    = 10.938 kN/m; strip 20 kPa over 1-3 m: Jarquio 20/90 * 5 * (30.964 - 11.310) = 21.838."""
    _, by = theory_json(capsys, "--H", "5", "--phi", "30", "--delta", "0", "--gamma", "18",
                        "--line-load", "20,1", "--strip-load", "20,1,3")
    sur = by["rankine"]["parts"]["surcharge"]["horizontal_kN_per_m"]
    assert abs(sur - (10.938 + 21.838)) < 2e-3
    assert abs(by["rankine"]["parts"]["soil"]["horizontal_kN_per_m"] - 75.0) < 1e-9   # 0.5*18*25/3


def test_water_below_base_accepted(capsys):
    _, by = theory_json(capsys, "--H", "3", "--water-depth", "10")
    assert by["rankine"]["parts"]["water"]["horizontal_kN_per_m"] == 0.0


def test_design_plot_writes_png(tmp_path, capsys):
    out = tmp_path / "design.png"
    assert main(["theory", "--c", "5", "--water-depth", "1", "--q", "10", "--plot", str(out)]) == 0
    assert out.stat().st_size > 10_000 and out.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("args, name", [
    (["--c", "-5"], "c"), (["--water-depth", "-1"], "water-depth"), (["--gamma-sat", "5"], "gamma-sat"),
    (["--line-load", "20"], "line-load"), (["--line-load", "20,-1"], "line-load x"),
    (["--strip-load", "20,3,1"], "strip-load x2"), (["--layers", "/nonexistent/l.toml"], "layers"),
    (["--adhesion-ratio", "2"], "adhesion-ratio"), (["--c", "5", "--kh", "0.1"], "kh"),
])
def test_bad_design_input_one_line_exit_2(capsys, args, name):
    code, out, err = run_main(capsys, "theory", *args)
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1
    assert f"{name} = " in lines[0] and ("valid range" in lines[0] or "not valid; expected" in lines[0])
    assert out == ""


def test_layers_not_adding_up_refused(tmp_path, capsys):
    f = tmp_path / "short.toml"
    f.write_text("[[layer]]\nthickness = 2\nphi = 30\ngamma = 17\n")
    code, out, err = run_main(capsys, "theory", "--H", "3", "--layers", str(f))
    assert code == 2 and err.count("\n") == 1 and out == ""
    assert "layers = 2 is outside the valid range thicknesses adding up to H = 3 m" in err


def test_cohesive_coulomb_row_names_the_trial_wedge(capsys):
    """Issue 21: with --c the coulomb row keeps the EN 1997-1 C.1 profile and names the
    c-a trial wedge's thrust beside it (phi 30, delta 20, c 10 kPa, H 6, gamma 18: 41.43
    kN/m horizontal, crack 1.936 m; tests/analytic/test_wedge.py)."""
    _, by = theory_json(capsys, "--phi", "30", "--delta", "20", "--c", "10", "--H", "6", "--gamma", "18")
    assert "c-a trial wedge: 41.43 kN/m horizontal, crack 1.936 m" in by["coulomb"]["notes"]
    assert "EN 1997-1 C.1" in by["coulomb"]["source"]
