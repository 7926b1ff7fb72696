"""The validation report accumulates partial reruns (one wall or some modes per
invocation, each an hour at paper scale) without losing what it does not redo."""

import json

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
