"""`wallsim dsm`: JSON keys and Table 3 figures through the command line."""

import json

from cli import main


def test_dsm_json_translation(capsys):
    """Table 3 translation: K 0.254, centroid 0.363 (Nadukuru & Michalowski 2012)."""
    assert main(["dsm", "--mode", "T", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) >= {"mode", "K", "resultant_height_over_H", "theta_r_deg", "paper"}
    assert out["paper"] == {"K": 0.254, "resultant_height_over_H": 0.363, "source": out["paper"]["source"]}
    assert abs(out["K"] - 0.254) <= 0.003 and abs(out["resultant_height_over_H"] - 0.363) <= 0.005
    assert abs(out["theta_r_deg"] - 31.93) < 0.01


def test_dsm_plot(tmp_path, capsys):
    f = tmp_path / "fig8.png"
    assert main(["dsm", "--mode", "RB", "--plot", str(f)]) == 0
    assert f.read_bytes()[:4] == b"\x89PNG"


def test_dsm_bad_theta(capsys):
    assert main(["dsm", "--theta-r", "95"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "theta-r" in err[0]
