"""The validation report accumulates partial reruns (one wall or some modes per
invocation, each an hour at paper scale) without losing what it does not redo."""

import json
from pathlib import Path

from studies.nadukuru.validate import _keep_other_walls, markdown


def _row(K, h):
    return {"K": K, "resultant_height_over_H": h, "wall_disp_over_H_steady": 0.001, "wall_time_s": 60.0,
            "paper": {"K": 0.2, "resultant_height_over_H": 0.4}}


def _report(git, modes, rate=None):
    entry = {"specimen": {"particles": 10, "bodies": 8, "seed": 1, "dt_s": 1e-5, "porosity": 0.35,
                          "K_at_rest": 0.39, "resultant_height_over_H_at_rest": 0.33, "thrust_at_rest_kN_per_0.5m": 16.0},
             "modes": modes}
    if rate is not None:
        entry["rate_check"] = rate
    return {"git": git, "versions": {}, "wall_time_s": 100.0, "walls": {"rough": entry}}


def test_rerun_of_one_mode_keeps_the_others_with_their_revision(tmp_path):
    old = _keep_other_walls(_report("aaa", {m: _row(0.2, 0.4) for m in ("T", "RB", "RT", "mixed")}),
                            tmp_path / "none.json")
    (tmp_path / "nadukuru.json").write_text(json.dumps(old))
    new = _keep_other_walls(_report("bbb", {"T": _row(0.25, 0.41)},
                                    rate={"speed_m_per_s": 0.01, "K": 0.252, "dK": 0.002}),
                            tmp_path / "nadukuru.json")
    modes = new["walls"]["rough"]["modes"]
    assert list(modes) == ["T", "RB", "RT", "mixed"]
    assert modes["T"]["K"] == 0.25 and modes["T"]["git"] == "bbb"
    assert modes["RT"]["git"] == "aaa"
    assert new["walls"]["rough"]["rate_check"]["git"] == "bbb"
    assert new["wall_time_s"] == 200.0
    text = markdown(new)
    assert "| T | 0.250 |" in text and "| bbb |" in text and "| aaa |" in text


def test_figure_data_keeps_the_curve_ends_and_the_segments_top_down():
    """Figs. 4 and 5 drawn again from the report: 1,000 readings kept as 200 evenly spaced
    ones with the first and last, and the active segment stresses (stored bottom up)
    reversed and divided by gamma H."""
    import numpy as np

    from studies.nadukuru.validate import CURVE_POINTS, figure_data
    x = np.linspace(0.0, 0.008, 1000)
    hist = {"wall_disp_over_H": x, "K": 0.4 - 20.0 * x, "segment_stress_active": np.array([6.0, 4.0, 2.0])}
    d = figure_data(hist, 2.0, 0.008)
    assert len(d["K"]) == CURVE_POINTS == 200
    assert d["wall_disp_over_H"][0] == 0.0 and d["wall_disp_over_H"][-1] == 0.008
    assert d["K"][-1] == 0.4 - 20.0 * 0.008
    assert d["segment_stress_over_gamma_H"] == [1.0, 2.0, 3.0]


def test_the_report_is_rewritten_with_its_figures_from_its_own_data(tmp_path):
    """``rewrite``: nothing run, Figs. 4 and 5 drawn from ``figure_data``, and the
    Markdown names the scorecard's totals of the JSON it wrote."""
    from studies.nadukuru.validate import rewrite
    data = {"wall_disp_over_H": [0.0, 0.004, 0.008], "K": [0.39, 0.25, 0.22],
            "segment_stress_over_gamma_H": [0.1, 0.2, 0.3, 0.3, 0.2, 0.1], "segments_read_at_wall_disp_over_H": 0.008}
    rep = _report("aaa", {m: _row(0.2, 0.4) | {"figure_data": data} for m in ("T", "RB", "RT", "mixed")})
    (tmp_path / "nadukuru.json").write_text(json.dumps(rep))
    out = rewrite(tmp_path)
    assert (tmp_path / "nadukuru_fig4_rough.png").stat().st_size > 0
    assert (tmp_path / "nadukuru_fig5_rough.png").stat().st_size > 0
    t = out["scorecard"]["totals"]
    md = (tmp_path / "nadukuru.md").read_text()
    assert f"{sum(t.values())} statements of the paper: {t['matches']} matches" in md


def test_displacement_fields_are_scored_by_their_order():
    """The Fig. 3 row: T and RB more nearly parallel than RT on each wall matches; an RT
    field as parallel as translation's misses; a wall without fields is not reproduced."""
    from studies.nadukuru.case import REFERENCE
    from studies.nadukuru.scorecard import scorecard_rows

    def report(rt_smooth):
        walls = {}
        for wall, rt in (("rough", 0.6), ("smooth", rt_smooth)):
            modes = {m: _row(0.2, 0.4) | {"displacement_field": {"resultant_length": r, "spread_deg": 10.0}}
                     for m, r in (("T", 0.95), ("RB", 0.9), ("RT", rt))}
            walls[wall] = _report("aaa", modes)["walls"]["rough"]
        return {"walls": walls}

    def row(rep):
        return next(r for r in scorecard_rows(rep, REFERENCE) if r.statement.startswith("translation and rotation"))

    assert row(report(0.7)).verdict == "matches"
    assert row(report(0.97)).verdict == "misses"
    assert row({"walls": {}}).verdict == "not reproduced"


def test_displacement_fields_fall_back_on_the_reduced_size_check_and_say_so():
    """Without fields in the report the Fig. 3 row reads the supporting file, every seed
    and wall: one specimen whose RT is as parallel as its T makes it a miss."""
    from studies.nadukuru.case import REFERENCE
    from studies.nadukuru.scorecard import scorecard_rows

    def fields(rt):
        return {m: {"resultant_length": r, "spread_deg": 10.0} for m, r in (("T", 0.98), ("RB", 0.98), ("RT", rt))}

    def row(rt_last):
        data = {"particles": [2800, 2900], "runs": {"1": {"rough": fields(0.96), "smooth": fields(0.96)},
                                                     "2": {"rough": fields(0.96), "smooth": fields(rt_last)}}}
        rep = {"walls": {"rough": _report("aaa", {"T": _row(0.2, 0.4)})["walls"]["rough"]}}
        rows = scorecard_rows(rep, REFERENCE, {"nadukuru_fields_reduced.json": data})
        return next(r for r in rows if r.statement.startswith("translation and rotation"))

    assert row(0.96).verdict == "matches" and "reduced size (2,800-2,900 spheres)" in row(0.96).ours
    assert row(0.99).verdict == "misses" and "3 of 4 specimens" in row(0.99).ours


def test_the_rt_stress_peak_is_read_on_the_segment_with_the_largest_stress():
    """Segments listed from the base up: a peak in the fifth of six is centred at
    4.5 / 6 = 0.75 H (the paper's 3/4: matches); in the second, 0.25 H (misses)."""
    from studies.nadukuru.case import REFERENCE
    from studies.nadukuru.scorecard import scorecard_rows
    s = next(x for x in REFERENCE["statements"] if x["kind"] == "peak_height")

    def row(peak):
        seg = [0.1] * 6
        seg[peak] = 0.3
        data = json.loads(Path("docs/validation/nadukuru_rt_checks.json").read_text())
        for name in s["runs"]:
            data["runs"][name]["segment_stress_over_rho_g_1mn_H"] = seg
        rep = {"walls": {"rough": _report("aaa", {"T": _row(0.2, 0.4)})["walls"]["rough"]}}
        rows = scorecard_rows(rep, REFERENCE, {s["file"]: data})
        return next(r for r in rows if r.statement == s["statement"])

    assert row(4).verdict == "matches" and "0.75, 0.75" in row(4).ours
    assert row(1).verdict == "misses"


def test_a_full_rerun_does_not_add_the_replaced_reports_time(tmp_path):
    modes = ("T", "RB", "RT", "mixed")
    old = _keep_other_walls(_report("aaa", {m: _row(0.2, 0.4) for m in modes}), tmp_path / "none.json")
    (tmp_path / "nadukuru.json").write_text(json.dumps(old))
    new = _keep_other_walls(_report("bbb", {m: _row(0.21, 0.41) for m in modes}), tmp_path / "nadukuru.json")
    assert new["wall_time_s"] == 100.0          # nothing of the old report is kept, nor its time
    # the header gives the runs' own times: four movements of 60 s each
    assert "wall movements 4.0 min" in markdown(new)
