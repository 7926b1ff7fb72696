"""The scorecards that open the validation reports (``studies/scorecard.py``): each is
generated from the study's reference statements and its report's JSON, and the
Markdown says what the JSON says (no row, verdict or total typed by hand)."""

import json
import re
from pathlib import Path

import pytest

from studies.scorecard import VERDICTS, Row, number_verdict, scorecard_json, totals_line, trend_verdict

DOCS = Path(__file__).resolve().parents[1] / "docs" / "validation"


def test_verdicts_follow_the_tolerance():
    assert number_verdict(0.218, 0.214, 0.03) == "matches"
    assert number_verdict(0.286, 0.251, 0.03) == "misses"
    assert number_verdict(0.30, 0.25, 0.03, scatter=(0.2, 0.31)) == "within the paper's scatter"
    assert number_verdict(None, 0.25, 0.03) == "not reproduced"
    assert [trend_verdict(x) for x in (True, False, None)] == ["matches", "misses", "not reproduced"]
    with pytest.raises(ValueError):
        Row("s", "w", "p", "o", "t", "fine")


def _nadukuru_card_from_data():
    from studies.nadukuru.case import REFERENCE
    from studies.nadukuru.scorecard import scorecard_rows
    from studies.nadukuru.validate import SUPPORTING
    rep = json.loads((DOCS / "nadukuru.json").read_text())
    supporting = {n: json.loads((DOCS / n).read_text()) for n in SUPPORTING}
    return rep["scorecard"], scorecard_json(scorecard_rows(rep, REFERENCE, supporting))


def _drystone_card_from_data():
    from studies.drystone.case import reference
    from studies.drystone.scorecard import scorecard_rows
    rep = json.loads((DOCS / "drystone.json").read_text())
    return rep["scorecard"], scorecard_json(scorecard_rows(rep, reference()))


def _seismic_card_from_data():
    from studies.seismic.validate import scorecard
    rep = json.loads((DOCS / "seismic.json").read_text())
    return rep["scorecard"], scorecard(rep)


def _khosravi_card_from_data():
    from studies.khosravi.report import scorecard
    rep = json.loads((DOCS / "khosravi.json").read_text())
    ref = json.loads((Path(__file__).resolve().parents[1] / "studies" / "khosravi" / "reference.json").read_text())
    return rep["scorecard"], scorecard(rep, ref)


def _heap_card_from_data():
    from studies.heap.validate import scorecard
    rep = json.loads((DOCS / "heap.json").read_text())
    return rep["scorecard"], scorecard(rep)


REPORTS = {"nadukuru": _nadukuru_card_from_data, "drystone": _drystone_card_from_data,
           "seismic": _seismic_card_from_data, "khosravi": _khosravi_card_from_data, "heap": _heap_card_from_data}


@pytest.mark.parametrize("study", sorted(REPORTS))
def test_the_scorecard_is_generated_from_the_reference_and_the_results(study):
    """The committed scorecard is what the statements of reference.json give on the
    committed results today: one row per statement, totals that add up."""
    stored, recomputed = REPORTS[study]()
    assert stored == recomputed
    assert sum(stored["totals"].values()) == len(stored["rows"])
    assert set(stored["totals"]) == set(VERDICTS)


@pytest.mark.parametrize("study", sorted(REPORTS))
def test_the_report_text_says_what_its_json_says(study):
    """The totals line and every row's verdict in <study>.md are the JSON's."""
    stored, _ = REPORTS[study]()
    text = (DOCS / f"{study}.md").read_text()
    assert totals_line(stored) in text
    table = [line for line in text.splitlines() if line.startswith("| ") and line.count("|") == 9]
    for row in stored["rows"]:
        cells = [c.strip() for c in next(line for line in table if line.startswith(f"| {row['statement']} |"))
                 .strip("|").split("|")]
        assert cells[5] == row["verdict"] and cells[3] == (row["ours"] or "-"), row["statement"]
    n = int(re.search(r"\*\*(\d+) statements of the paper", text).group(1))
    assert n == len(stored["rows"])


def test_the_index_quotes_each_scorecard_s_totals():
    """docs/validation/README.md's totals line is each report's JSON totals (matches /
    scatter / misses / not reproduced of all)."""
    index = " ".join((DOCS / "README.md").read_text().split())
    names = {"nadukuru": "Nadukuru", "khosravi": "Khosravi", "drystone": "dry-stone", "seismic": "Sizkow",
             "heap": "heap"}
    for study, name in names.items():
        stored, _ = REPORTS[study]()
        t = stored["totals"]
        quoted = f"{name} " + " / ".join(str(t[v]) for v in VERDICTS) + f" of {len(stored['rows'])}"
        assert quoted in index, quoted


def test_a_partial_nadukuru_report_scores_what_it_ran():
    """A validation of one wall and one mode, without the triaxial or the supporting
    files (what `validate nadukuru --walls rough --modes T` writes): every other
    statement is 'not reproduced', and every row is text."""
    from studies.nadukuru.case import REFERENCE
    from studies.nadukuru.scorecard import scorecard_rows
    rep = json.loads((DOCS / "nadukuru.json").read_text())
    rep["walls"] = {"rough": rep["walls"]["rough"] | {"modes": {"T": rep["walls"]["rough"]["modes"]["T"]}}}
    rep.pop("triaxial")
    rows = scorecard_rows(rep, REFERENCE, {})
    verdicts = {r.statement: r.verdict for r in rows}
    assert verdicts["rough wall, T: active K"] == "matches"
    assert verdicts["smooth wall, T: active K"] == "not reproduced"
    assert verdicts["the final load depends on phi, not on the grain size (RT, K)"] == "not reproduced"
    assert sum(v == "not reproduced" for v in verdicts.values()) >= 15
