"""A case field added after runs were made without it (``param(absent_means=...)``):
those runs keep their folders, caches and report records, and an interrupted one
resumes as it started. Checked on the seismic case's ``direct_sums`` (added in issue 42;
the runs before it gathered the second sphere's rows, ``direct_sums`` false) against the
run-folder names that docs/validation/seismic.json records for the medium 1 and 5 Hz
runs, made before the field existed."""

import dataclasses
import json
from pathlib import Path

from analytic.schema import param
from studies import get
from studies.runfolder import config_toml
from studies.seismic.case import SeismicCase
from studies.seismic.validate import run_name
from studies.store import content_key

REPORT = Path(__file__).parents[2] / "docs" / "validation" / "seismic.json"


def test_runs_made_before_the_field_keep_their_folder_names():
    """The medium records' run folders (named by the content key of every case field
    then) are the names of today's case with ``direct_sums`` false (the default); true
    names other folders."""
    medium = json.loads(REPORT.read_text())["other_resolutions"]["medium"]["frequencies"]
    for f in ("1", "5"):
        folder = Path(medium[f]["extra"]["run_folder"]).name
        case = SeismicCase(resolution="medium", frequency=float(f))
        assert run_name(case) == folder
        assert run_name(dataclasses.replace(case, direct_sums=True)) != folder


@dataclasses.dataclass(frozen=True)
class Before:
    height: float = param(3.1, unit="m", meaning="wall height")


@dataclasses.dataclass(frozen=True)
class After:
    height: float = param(3.1, unit="m", meaning="wall height")
    fast: bool = param(True, unit="", absent_means=False, meaning="added later")


def test_the_key_leaves_an_added_field_out_only_at_its_earlier_value():
    assert content_key(After(fast=False)) == content_key(Before())
    assert content_key(After()) != content_key(Before())
    assert content_key({"case": After(height=2.0, fast=False)}) == content_key({"case": Before(height=2.0)})


def test_a_config_written_before_the_field_resumes_as_it_started(tmp_path):
    """An interrupted run's config.toml without the field reads as ``absent_means``
    (false; the default too since the direct sums' static states were found to differ,
    so the key test above is what tells the two apart): the resumed run is the one
    that started."""
    started = SeismicCase(resolution="medium", frequency=3.0, direct_sums=False)
    text = "\n".join(line for line in config_toml(started).splitlines() if not line.startswith("direct_sums"))
    assert "direct_sums" not in text
    folder = tmp_path / "seismic" / run_name(started)
    folder.mkdir(parents=True)
    (folder / "config.toml").write_text(text + "\n")
    case = get("seismic").command().resolve(resume=str(folder), study="seismic")
    assert case == started


def test_the_report_says_how_each_resolution_summed_its_contacts():
    """seismic.json (written before the field: every block read as rows) rendered as if
    its default resolution had been run with direct sums: the header says so and the
    resolution section says the two also differ in the order of sums."""
    from studies.seismic import validate as V

    rep = json.loads(REPORT.read_text())
    assert "contact_sums" not in rep and V.block_sums(rep) == "rows"
    assert V.SUMS_TEXT["rows"] in V.report_markdown(rep)
    assert "The two also sum contact forces in another order" not in V.report_markdown(rep)
    rep["contact_sums"] = V.contact_sums(SeismicCase(direct_sums=True))
    md = V.report_markdown(rep)
    assert V.SUMS_TEXT["direct"] in md
    assert "coarse: direct, medium: rows" in md


def test_the_report_keeps_the_other_order_of_sums_beside_the_new_runs():
    """seismic.json's coarse runs summed by rows; a report of the case with direct
    sums at the same resolution and rest keeps them as ``other_sums`` and sets each
    frequency run both ways side by side; a case summing by rows keeps the report's own
    other-sums block; another resolution keeps nothing."""
    from studies.seismic import validate as V

    old = json.loads(REPORT.read_text())
    kept = V.other_sums_block(old, SeismicCase(direct_sums=True))
    assert kept["contact_sums"] == "rows" and kept["frequencies"] == old["frequencies"]
    # a report summing by rows keeps the direct-sums runs the report holds beside it
    assert V.other_sums_block(old, SeismicCase(direct_sums=False)) == old.get("other_sums")
    assert V.other_sums_block(old, SeismicCase(resolution="medium", direct_sums=True)) is None
    rep = json.loads(REPORT.read_text()) | {"contact_sums": "direct", "other_sums": kept}
    rep["frequencies"]["5"]["top_displacement_m"] = 1.25 * old["frequencies"]["5"]["top_displacement_m"]
    md = "\n".join(V.sum_order_lines(rep))
    assert "## How the results move with the order of sums: direct vs rows" in md
    assert "| top_displacement_m |" in md and "-20 %" in md          # rows = direct / 1.25
    again = V.other_sums_block(rep, SeismicCase(direct_sums=True))    # a later direct report keeps the rows' block
    assert again is kept
