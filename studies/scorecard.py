"""The scorecard that opens a validation report: one row per quantitative statement of
the paper (a table value, a number in the text, a stated trend), where the paper says
it, our value, the tolerance, the verdict and whether the agreement is independent or
partly built in (the fitted input named). The markdown and the JSON are made from the
same rows, so the report cannot say one thing and its numbers another
(``tests/test_scorecards.py`` reads the one against the other). Names no study.

Verdicts:
* ``matches``: ours within the tolerance of the paper's value, or the trend holds;
* ``within the paper's scatter``: outside the tolerance, inside the spread the paper
  itself shows for that quantity (a range it gives);
* ``misses``: ours was measured and is outside both;
* ``not reproduced``: no run of ours gives the quantity yet.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

VERDICTS = ("matches", "within the paper's scatter", "misses", "not reproduced")


@dataclass(frozen=True)
class Row:
    """One statement of the paper and how ours compares.

    statement: what the paper states, in a few words; where: table, figure or section;
    paper: its value as text (a number, a range, a trend); ours: our value as text (''
    when not reproduced); tolerance: as text; verdict: one of ``VERDICTS``; agreement:
    'independent' or 'partly by construction: <the fitted input>'; note: the cause of
    a miss, or where our value comes from."""

    statement: str
    where: str
    paper: str
    ours: str
    tolerance: str
    verdict: str
    agreement: str = "independent"
    note: str = ""

    def __post_init__(self):
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict {self.verdict!r} not in {VERDICTS}")
        for name, value in asdict(self).items():
            if not isinstance(value, str):     # a number here would reach the Markdown unformatted
                raise TypeError(f"scorecard row {self.statement!r}: {name} = {value!r} is not text")


def number_verdict(ours: float | None, paper: float, tol: float, scatter: tuple[float, float] | None = None) -> str:
    """``matches`` when |ours - paper| <= tol, ``within the paper's scatter`` when ours
    lies in the paper's own range ``scatter``, ``not reproduced`` when ours is None,
    else ``misses``."""
    if ours is None:
        return "not reproduced"
    if abs(ours - paper) <= tol + 1e-12:
        return "matches"
    if scatter is not None and scatter[0] <= ours <= scatter[1]:
        return "within the paper's scatter"
    return "misses"


def trend_verdict(holds: bool | None) -> str:
    """A stated trend: ``matches`` when ours shows it, ``misses`` when it does not,
    ``not reproduced`` when no run of ours can say."""
    return "not reproduced" if holds is None else ("matches" if holds else "misses")


def totals(rows: list[Row]) -> dict[str, int]:
    """Rows per verdict, every verdict listed (0 included), in ``VERDICTS`` order."""
    return {v: sum(r.verdict == v for r in rows) for v in VERDICTS}


def scorecard_json(rows: list[Row]) -> dict:
    return {"totals": totals(rows), "rows": [asdict(r) for r in rows],
            "by_construction": sum(r.agreement != "independent" for r in rows)}


def totals_line(card: dict) -> str:
    """'N statements: a matches, b within the paper's scatter, c misses, d not reproduced;
    e of the agreements partly by construction' from ``scorecard_json``'s record."""
    t = card["totals"]
    n = sum(t.values())
    return (f"**{n} statements of the paper: " + ", ".join(f"{t[v]} {v}" for v in VERDICTS) + "**; "
            f"{card['by_construction']} of the rows agree partly by construction (the fitted input is named).")


def scorecard_markdown(card: dict, title: str = "Scorecard") -> list[str]:
    """The scorecard section of a report, from ``scorecard_json``'s record only."""
    lines = [f"## {title}", "", totals_line(card), "",
             "| statement | where | paper | ours | tolerance | verdict | agreement | note |",
             "|---|---|---|---|---|---|---|---|"]
    for r in card["rows"]:
        cells = [r["statement"], r["where"], r["paper"], r["ours"] or "-", r["tolerance"], r["verdict"],
                 r["agreement"], r["note"]]
        lines.append("| " + " | ".join(c.replace("|", "/") for c in cells) + " |")
    return lines + [""]
