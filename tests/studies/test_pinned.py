"""Regression pins of every registered study at reduced size (tests/data/pinned_studies.json,
recorded before the study layer existed, at git 9d8b6f6): the commands must give the
same numbers, bit for bit. Physics is checked by the other tests; these check that
moving code between layers changed nothing."""

import json
import math
from pathlib import Path

import pytest

import cli

PINS = json.loads((Path(__file__).parents[1] / "data" / "pinned_studies.json").read_text())


def _flat(obj, prefix=""):
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _flat(v, f"{prefix}.{k}" if prefix else k)
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _flat(v, f"{prefix}[{i}]")
    else:
        yield prefix, obj


def _same(a, b) -> bool:
    return a == b or (isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b))


def _dotted(result: dict, key: str):
    node = result
    for part in key.split("."):
        node = node[part]
    return node


@pytest.mark.slow
@pytest.mark.parametrize("study", ["nadukuru", "khosravi", "triaxial", "biaxial"])
def test_study_numbers_are_pinned(study, tmp_path, capsys):
    pin = PINS[study]
    assert cli.main(pin["argv"] + ["--json", "--quiet", "--out", str(tmp_path)]) == 0
    result = json.loads(capsys.readouterr().out)
    got = {k: _dotted(result, k) for k in pin["values"]}
    want, have = dict(_flat(pin["values"])), dict(_flat(got))
    changed = [f"{k}: {want[k]!r} -> {have.get(k, '<absent>')!r}" for k in want if not _same(want[k], have.get(k))]
    assert changed == [], "\n".join(changed[:20])
