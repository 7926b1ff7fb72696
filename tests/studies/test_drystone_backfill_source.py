"""The dry-stone scorecard's backfill rows read the tests made at the case-B runs' local
values (gravel_local_values.json) when there are such tests, and say what the
calibration's own tests read there; without them, the calibration's tests."""

from studies.drystone.case import reference
from studies.drystone.scorecard import _backfill

CASE_B = {"local_values": {"ours": {"grain_friction_deg": 50.0, "interface_friction_deg": 45.0,
                                    "placement_friction_deg": 45.0}},
          "settings": {"grain_shape": "hexagon"}}


def _record(peak: float, seeds, mode=None, dilatancy_peak=None) -> dict:
    tests = [{"friction_deg": 50.0, "seed": s, "phi_peak_deg": peak, "phi_cs_deg": 31.0, "porosity": 0.22,
              "dilatancy_deg": 2.0, **({} if dilatancy_peak is None else {"dilatancy_peak_deg": dilatancy_peak})}
             for s in seeds]
    row = {"friction_deg": 50.0, "seeds": list(seeds), "phi_peak_deg": peak, "phi_cs_deg": 31.0, "porosity": 0.22,
           "inner_porosity": 0.21, "dilatancy_deg": 2.0,
           **({} if dilatancy_peak is None else {"dilatancy_peak_deg": dilatancy_peak})}
    rec = {"grain_shape": "hexagon", "git": "abc",
           "biaxial": {"tests": tests, "rows": [row], "peak_only": {"value_deg": 53.2}},
           "interface": {"grain_friction_deg": 50.0, "tests": [],
                         "rows": [{"interface_friction_deg": 45.0, "global_angle_deg": 30.0,
                                   "global_angle_sd_deg": 1.0, "seeds": list(seeds)}]}}
    if mode:
        rec["reproducibility"] = {"mode": mode}
    return rec


def _rows(calibration, measured):
    return {r.statement.split(": ", 1)[1]: r for r in _backfill(CASE_B, reference(), calibration, measured)}


def test_rows_read_the_tests_at_the_runs_values_and_name_the_calibrations():
    rows = _rows(_record(36.7, (1, 2)), _record(34.9, (1, 2, 3, 4), "portable", dilatancy_peak=7.8))
    peak = rows["internal (peak) friction angle at 35 kPa"]
    assert peak.ours.startswith("34.9 deg") and peak.verdict == "misses"        # 37.7 +- 1.5 (reference.json)
    assert "4 seeds" in peak.note and "portable" in peak.note and "native mode, git abc: 36.7 deg" in peak.note
    assert rows["dilatancy angle at 35 kPa (at the peak)"].ours.startswith("7.8 deg")
    assert rows["dilatancy angle at 35 kPa (at the peak)"].verdict == "matches"     # 8 +- 1.5


def test_without_tests_at_the_runs_values_the_calibrations_are_read():
    rows = _rows(_record(36.7, (1, 2)), None)
    peak = rows["internal (peak) friction angle at 35 kPa"]
    assert peak.ours.startswith("36.7 deg") and peak.verdict == "matches"
    assert rows["dilatancy angle at 35 kPa (at the peak)"].verdict == "not reproduced"
