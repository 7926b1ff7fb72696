"""``validate <study> --seeds`` (studies/seeds.py): the seed list, the statistics and
verdicts of one figure against hand values, the command line, and a tiny Nadukuru
validation (1,000 spheres, rough wall, translation only) over 2 seeds on a 2-worker
LocalCluster whose mean, sd, min and max equal, bit for bit, those of the same two
validations run one by one in this process."""

import json
import math
from pathlib import Path

import pytest

import cli
from analytic.errors import InvalidParameter
from studies import get
from studies.seeds import figure, figure_summary, parse_seeds, run_seeds, spread_line, within
from studies.sweep import stats


def test_seed_lists_and_ranges():
    assert parse_seeds("1..3") == [1, 2, 3]
    assert parse_seeds("1,2,5") == [1, 2, 5]
    assert parse_seeds("1..2,7") == [1, 2, 7]
    for bad in ("0..2", "3..1", "1,1", "x", "1.5", "-1,2", ""):
        with pytest.raises(InvalidParameter, match="--seeds"):
            parse_seeds(bad)


def test_windows_include_their_ends_and_may_be_open():
    assert within(0.214, 0.184, 0.244) and within(0.184, 0.184, 0.244)
    assert within(1.2, None, 1.0) is False and within(0.5, None, 1.0)
    assert within(0.3, None, None) is None and within(None, 0, 1) is None


def test_one_figure_over_three_seeds_against_hand_values():
    """Paper 0.214 +- 0.03 (Nadukuru Table 1, rough T); seeds 0.20, 0.22, 0.25: mean
    0.22333..., sd sqrt(((-0.02333)^2 + (-0.00333)^2 + 0.02667^2) / 2) = 0.025166."""
    target = figure("rough.T.K", None, reference=0.214, lo=0.184, hi=0.244, target="paper 0.214 +- 0.03")
    values = {1: 0.20, 2: 0.22, 3: 0.25}
    s = stats(list(values.values()))
    group = {f"rough.T.K_{k}": s[k] for k in ("mean", "sd", "min", "max")}
    f = figure_summary(target, values, group)
    assert f["mean"] == pytest.approx(0.67 / 3, abs=1e-15) and f["sd"] == pytest.approx(0.025166114784235836, rel=1e-12)
    assert (f["min"], f["max"], f["n"]) == (0.20, 0.25, 3)
    assert f["mean_within_target"] is True and f["seeds_within_target"] == 2          # 0.25 > 0.244
    assert f["reference_within_mean_sd"] is True                                      # 0.1982 <= 0.214 <= 0.2485
    assert f["reference_within_min_max"] is True
    assert "paper 0.214 lies within mean +- sd and within min..max" in spread_line(f)
    far = figure_summary(target | {"reference": 0.26}, values, group)
    assert far["reference_within_mean_sd"] is False and far["reference_within_min_max"] is False
    assert "outside the seed spread (above every seed)" in spread_line(far)


@pytest.mark.parametrize("argv", [["--seeds", "0..2"], ["--seeds", "1..2", "--seed", "3"], ["--workers", "2"]])
def test_cli_refuses_bad_seeds_in_one_line(argv, capsys, tmp_path):
    try:
        code = cli.main(["validate", "khosravi", *argv, "--out", str(tmp_path), "--docs", str(tmp_path)])
    except SystemExit as stop:              # a value argparse refuses (its type): the same one line
        code = stop.code
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and err.startswith("wallsim")


def test_a_command_without_figures_takes_no_seeds(capsys, tmp_path):
    with pytest.raises(SystemExit):             # compare has no --seeds
        cli.main(["compare", "khosravi", "--seeds", "1..2"])
    with pytest.raises(InvalidParameter, match="figures"):
        run_seeds("khosravi", [1, 2], verb="compare", out=tmp_path)


TINY = {"flags": {"specimen.particles": 1000},
        "options": {"walls": ["rough"], "modes": ["T"], "no_triaxial": True, "no_rate_check": True}}


@pytest.mark.slow
def test_seeds_give_the_statistics_of_the_runs_one_by_one(client, tmp_path):
    study = get("nadukuru")
    report = run_seeds("nadukuru", [1, 2], flags=TINY["flags"], options=TINY["options"] | {"docs": str(tmp_path / "docs")},
                       out=tmp_path / "runs", client=client)
    one_by_one = []
    for seed in (1, 2):
        rep = study.run(study.case("validate", seed=seed, particles=1000), "validate", out=str(tmp_path / "serial"),
                        docs=str(tmp_path / f"serial_docs{seed}"), **TINY["options"])
        one_by_one.append({f["name"]: f["value"] for f in study.command("validate").figures(rep)})
    names = ["rough.K_at_rest", "rough.T.K", "rough.T.resultant_height_over_H"]
    assert [f["name"] for f in report["figures"]] == names
    assert one_by_one[0]["rough.T.K"] != one_by_one[1]["rough.T.K"]           # two specimens, not one copied
    for f in report["figures"]:
        values = [run[f["name"]] for run in one_by_one]
        s = stats(values)
        assert list(f["values"].values()) == values
        assert (f["mean"], f["sd"], f["min"], f["max"]) == (s["mean"], s["sd"], s["min"], s["max"])
        assert f["reference_within_min_max"] == (s["min"] <= f["reference"] <= s["max"])
    assert report["finished_seeds"] == [1, 2] and all(p["status"] == "done" for p in report["points"])
    on_disk = json.loads((tmp_path / "docs" / "nadukuru_seeds.json").read_text())
    assert on_disk["figures"] == json.loads(json.dumps(report["figures"]))
    md = (tmp_path / "docs" / "nadukuru_seeds.md").read_text()
    assert "rough.T.K: paper 0.214 lies" in md and "| rough.T.K | paper 0.214 +- 0.03 |" in md
    for p in report["points"]:              # each seed's own report, log and options in its folder
        folder = Path(p["run_folder"])
        assert (folder / "nadukuru.md").is_file() and (folder / "validate.json").is_file()
        assert "point finished" in (folder / "run.log").read_text().splitlines()[-1]
        assert json.loads((folder / "run_options.json").read_text())["docs"] == str(folder)
    again = run_seeds("nadukuru", [1, 2], flags=TINY["flags"], options=TINY["options"] | {"docs": str(tmp_path / "docs")},
                      out=tmp_path / "runs", client=client)
    assert [p["status"] for p in again["points"]] == ["skipped", "skipped"]
    assert [f["mean"] for f in again["figures"]] == [f["mean"] for f in report["figures"]]
    assert not math.isnan(report["figures"][1]["sd"])
