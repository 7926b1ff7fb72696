"""The wall-speed check of the Khosravi study (``studies.khosravi.speed_check``) on a
run folder whose thrust is known exactly."""

import json

import numpy as np
import pytest

from studies.khosravi.speed_check import speed_record, thrust_series, wall_speed_check


def _folder(tmp_path, name, speed, end):
    """Two panels below the surface and one above it; their summed stress falls linearly
    from 10 to 5 kPa over Dis/H 0-0.001, then stays at 5 (the panel above the surface
    reads 7 kPa throughout and must not count)."""
    f = tmp_path / name
    f.mkdir()
    rows = ["wall_disp_over_H,panel,depth_m,sigma_h_kPa,tau_kPa"]
    for d in np.round(np.arange(0.0, end + 1e-12, 1e-4), 6):
        total = 10.0 - 5.0 * min(d, 0.001) / 0.001
        rows += [f"{d},0,0.15,{0.6 * total},0", f"{d},1,0.05,{0.4 * total},0", f"{d},2,-0.01,7.0,0"]
    (f / "panels_vs_displacement.csv").write_text("\n".join(rows) + "\n")
    (f / "result.json").write_text(json.dumps({"H_m": 0.2, "particles": 100, "seed": 1}))
    (f / "manifest.json").write_text(json.dumps({"cpu_time_s": 12.5, "wall_time_s": 13.0, "git": "abc"}))
    (f / "config.toml").write_text(f"H = 0.2\nwall_speed = {speed}\nwall_disp_over_H_max = {end}\n")
    return f


def test_the_thrust_counts_only_the_panels_below_the_surface(tmp_path):
    dis, thrust = thrust_series(_folder(tmp_path, "a", 0.004, 0.002))
    assert dis[0] == 0.0 and thrust[0] == pytest.approx(10.0)
    assert thrust[-1] == pytest.approx(5.0)


def test_ninety_percent_of_a_linear_drop_by_hand(tmp_path):
    """Drop 10 -> 5 over Dis/H 0-0.001 in steps of 1e-4, read through the measure's
    3-point running mean (the first reading padded with itself): start (10 + 10 + 9.5) / 3
    = 9.8333, end 5, so 90 % of the drop is at 5 + 0.1 x 4.8333 = 5.4833; the smoothed
    thrust is 5.5 at 0.0009 (above) and (5.5 + 5 + 5) / 3 = 5.1667 at 0.001: reached at
    0.001. A run that stops at 0.005 has no record at 0.01."""
    rec = speed_record(_folder(tmp_path, "b", 0.001, 0.005), (0.005, 0.01))
    assert rec["by_end"]["0.005"]["wall_disp_over_H_90"] == pytest.approx(0.001, abs=1e-12)
    assert rec["by_end"]["0.005"]["thrust_end_over_at_rest"] == pytest.approx(0.5)
    assert "0.01" not in rec["by_end"]
    assert rec["wall_speed_m_per_s"] == 0.001 and rec["cpu_time_s"] == 12.5


def test_runs_are_listed_slowest_first(tmp_path):
    got = wall_speed_check([_folder(tmp_path, "fast", 0.004, 0.01), _folder(tmp_path, "slow", 0.001, 0.005)])
    assert [r["wall_speed_m_per_s"] for r in got["runs"]] == [0.001, 0.004]


def test_a_run_stopped_early_is_read_from_its_snapshot_series(tmp_path):
    """A run stopped at Dis/H 0.006 (read from its snapshot) has a record at 0.005, the
    same as a finished folder's with the same readings, and none at 0.01."""
    dis, thrust = thrust_series(_folder(tmp_path, "c", 0.002, 0.006))
    got = wall_speed_check([], stopped=[{"wall_speed_m_per_s": 0.002, "dis": dis.tolist(), "thrust": thrust.tolist(),
                                         "stopped_at": "snapshot"}])
    rec = got["runs"][0]
    assert rec["by_end"]["0.005"]["wall_disp_over_H_90"] == pytest.approx(0.001, abs=1e-12)
    assert "0.01" not in rec["by_end"] and rec["stopped_at"] == "snapshot"
