"""The CLI end to end on a tiny box (H = 0.1 m, grains 8x coarser): run folder, JSON
keys, specimen reuse, and one-line errors with exit code 2."""

import json
from pathlib import Path

import pytest

import cli

TINY = ["compare", "khosravi", "--H", "0.1", "--particles-scale", "8", "--set", "wall_disp_over_H_max=0.001",
        "--quiet", "--json"]


def test_bad_overrides_exit_2_with_one_line(capsys, tmp_path):
    for extra in (["--set", "friction=-1"], ["--set", "no_such_key=1"], ["--H", "0.5"],
                  ["--set", "reading_iterations=0"]):
        with pytest.raises(SystemExit) as e:
            rc = cli.main(TINY + ["--out", str(tmp_path)] + extra)
            raise SystemExit(rc)
        assert e.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "error" in err[0]


def test_compare_khosravi_writes_the_run_folder_and_reuses_the_specimen(capsys, tmp_path):
    assert cli.main(TINY + ["--out", str(tmp_path)]) == 0
    res = json.loads(capsys.readouterr().out)
    for key in ("K_at_rest_upper_half", "active_thrust_over_rankine", "wall_disp_over_H_steady", "phi_biaxial"):
        assert key in res["dem"]
    assert res["specimen_reused"] is False
    runs = [p for p in (tmp_path / "khosravi").iterdir() if not p.name.startswith("_")]
    assert len(runs) == 1
    names = {p.name for p in runs[0].iterdir()}
    for f in ("config.toml", "manifest.json", "result.json", "at_rest_panels.csv", "readings_vs_displacement.csv",
              "panels_vs_displacement.csv",
              "fig10_at_rest.png", "fig11_corner_chains.png", "fig12_pressure_vs_displacement.png", "fig13_profiles.png"):
        assert f in names
    # config.toml says where each setting came from and what the run used (as TOML
    # comments, so --config <run>/config.toml still repeats the run)
    config = (runs[0] / "config.toml").read_text()
    for line in ("H: flag --H", "particles_scale: flag --particles-scale", "wall_disp_over_H_max: --set",
                 f"particles reached: {res['particles']}"):
        assert line in config
    # coarse grains: one line says so and sets the run beside the full-size validation
    assert res["scale_note"].startswith("reduced size: grains 8 x the paper's")
    assert "at full size (61120 disks) 0.99 and 0.77" in res["scale_note"]
    man = json.loads((runs[0] / "manifest.json").read_text())
    for key in ("seed", "versions", "n_grains", "dt", "iterations", "friction", "wall_time_s"):
        assert key in man
    # same seed and specimen settings: the settled specimen is reused
    assert cli.main(TINY + ["--out", str(tmp_path)]) == 0
    res2 = json.loads(capsys.readouterr().out)
    assert res2["specimen_reused"] is True
    assert res2["particles"] == res["particles"]
    # the run that filled the box went on from the bytes it stored: the reuse repeats it
    for key in ("K_at_rest_upper_half", "active_thrust_over_rankine"):
        assert res2["dem"][key] == res["dem"][key]
    # no card holds a biaxial test at this grain size: the first run measured phi and
    # saved the test, the second reads it back instead of repeating it
    assert res["phi_biaxial_source"] == "biaxial test run for this comparison"
    assert res2["phi_biaxial_source"].startswith("calibration card")
    assert res2["dem"]["phi_biaxial"] == res["dem"]["phi_biaxial"]


def test_held_fill_marks_the_cells_it_cannot_read(capsys, tmp_path):
    """Khosravi Fig. 9 reads every cell below the surface after each layer. The
    held-layer fill (the default, 3.8x cheaper) cannot read cells under grains held
    static, and marks exactly those as not read (NaN: deeper than hold_depth below the
    surface), never a made-up value. (A free fill reads them all: the next test.)"""
    import csv

    out = tmp_path / "held"
    assert cli.main(TINY + ["--out", str(out), "--no-cache"]) == 0
    capsys.readouterr()
    folder = next(p for p in (out / "khosravi").iterdir() if not p.name.startswith("_"))
    held = [r for r in csv.DictReader((folder / "backfilling.csv").open())
            if float(r["panel_centre_height_m"]) < float(r["surface_m"])]
    unread = [r for r in held if r["sigma_h_kPa"] in ("nan", "")]
    assert unread and all(float(r["panel_centre_height_m"]) < float(r["surface_m"]) - 0.02 for r in unread)


def test_validation_reads_fig9_from_a_free_fill(tmp_path):
    """The held-layer fill cannot read the cells beside held grains, so the validation
    draws Khosravi Fig. 9 from a free fill of the same box: every cell below each
    layer's surface read (none NaN), reported with its own run folder."""
    import csv
    import json

    from studies.khosravi import backfilling as bf_mod
    from studies.khosravi.case import KhosraviCase
    from studies.khosravi.compare import validate_khosravi

    case = KhosraviCase(H=0.1, particles_scale=8, wall_disp_over_H_max=0.001)
    assert case.pluviation.hold_depth > 0  # the study's default holds deep layers
    report = validate_khosravi(out_dir=tmp_path / "docs", root=tmp_path / "runs", quiet=True, case=case)
    bf = report["backfilling"]
    assert bf["hold_depth_m"] == 0.0 and bf["unread_cells_below_surface"] == 0
    rows = list(csv.DictReader((tmp_path / "docs" / "khosravi" / "backfilling.csv").open()))
    below = [r for r in rows if float(r["panel_centre_height_m"]) < float(r["surface_m"])]
    assert below and all(r["sigma_h_kPa"] not in ("nan", "") for r in below)
    saved = json.loads((tmp_path / "docs" / "khosravi.json").read_text())
    assert Path(saved["backfilling"]["run_folder"]).name.startswith("backfilling-")     # keyed by its case
    assert "free fill" in (tmp_path / "docs" / "khosravi.md").read_text()
    assert bf_mod.unread_cells([(1, 0.02, [1.0, float("nan"), 3.0])], 0.01) == 1
