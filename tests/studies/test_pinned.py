"""Regression pins of every registered study at reduced size (tests/data/pinned_studies.json):
the commands must give the same numbers, bit for bit, on any x86-64 CPU (recorded in the
portable mode, reproducibility.py). Physics is checked by the other tests; these check
that moving code between layers changed nothing."""

import json
import math
import re
from pathlib import Path

import pytest

import cli
from tests.conftest import portable_only

PINS_FILE = Path(__file__).parents[1] / "data" / "pinned_studies.json"
PINS = json.loads(PINS_FILE.read_text())
#: every pinned command, in the file's order (keys starting with "_" are notes)
STUDIES = [k for k in PINS if not k.startswith("_")]


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


def study_changes(study: str, out: str) -> list[str]:
    """Every pinned value of ``study`` that its command no longer gives: 'key: pin -> now'."""
    import contextlib
    import io

    pin = PINS[study]
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert cli.main(pin["argv"] + ["--json", "--quiet", "--out", str(out)]) == 0
    result = json.loads(buf.getvalue())
    got = {k: _dotted(result, k) for k in pin["values"]}
    want, have = dict(_flat(pin["values"])), dict(_flat(got))
    return [f"{k}: {want[k]!r} -> {have.get(k, '<absent>')!r}" for k in want if not _same(want[k], have.get(k))]


@portable_only
@pytest.mark.slow
@pytest.mark.parametrize("study", STUDIES)
def test_study_numbers_are_pinned(study, tmp_path):
    changed = study_changes(study, tmp_path)
    assert changed == [], "\n".join(changed[:20])


#: keys of wall and CPU times and of speeds per CPU second: wall_time_s, cpu_time_s, wall_s,
#: cpu_s, cpu_place_s, cpu_by_phase_s, steps_per_cpu_s, ... (not time_s, overlap_time_s,
#: wall_vertical_N_m: simulated time and physics)
_TIMING = re.compile(r"(^|_)(cpu|wall)(_time)?_s$|^cpu_")


def _without_timings(obj):
    """``obj`` without its wall and CPU times (they differ from run to run)."""
    if isinstance(obj, dict):
        return {k: _without_timings(v) for k, v in obj.items() if not _TIMING.search(k)}
    if isinstance(obj, list):
        return [_without_timings(v) for v in obj]
    return obj


def record(studies: list[str]) -> None:
    """Re-record the pinned values of ``studies`` (same keys, same commands) in the
    portable mode; only after the cause of a change is understood (issue 37)."""
    import contextlib
    import io
    import tempfile

    import reproducibility
    assert reproducibility.describe()["mode"] == "portable", "record pins in the portable mode (wallsim env)"
    for study in studies:
        pin = PINS[study]
        with tempfile.TemporaryDirectory() as out:
            buf = io.StringIO()
            with contextlib.redirect_stdout(buf):
                assert cli.main(pin["argv"] + ["--json", "--quiet", "--out", out]) == 0
        result = json.loads(buf.getvalue())
        pin["values"] = {k: _without_timings(_dotted(result, k)) for k in pin["values"]}
    PINS_FILE.write_text(json.dumps(PINS, indent=1) + "\n")


if __name__ == "__main__":      # python -m tests.studies.test_pinned nadukuru khosravi ...
    import sys
    record(sys.argv[1:] or STUDIES)
