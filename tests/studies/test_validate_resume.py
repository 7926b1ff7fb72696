"""Issue 38: a ``wallsim validate`` command that chains DEM runs, interrupted (Ctrl-C in
the middle of its second run) and then given again as it was, runs none of the runs
that finished again and writes the report of the command that was never interrupted,
its numbers bit for bit (times, paths and provenance aside).

Two of the five at reduced size, a few seconds of one core a run: drystone case A on two
walls with the limit-equilibrium band and no convergence repeat (one DEM run a wall),
and the heap on two seeds at test_heap.py's RESUME_SIZE."""

import re

import pytest

import cli
from studies.heap.case import HeapCase
from tests.studies.test_heap import RESUME_SIZE

#: what differs between any two commands: times, run folders, versions, dates
_TIME = re.compile(r"(^|_)(wall|cpu)(_time)?_s$")
_PROVENANCE = {"created", "git", "versions", "reproducibility", "timing", "resources", "run_folder", "run_folders"}


def _numbers(obj):
    """A report without its times, paths and provenance."""
    if isinstance(obj, dict):
        return {k: _numbers(v) for k, v in obj.items() if k not in _PROVENANCE and not _TIME.search(k)}
    if isinstance(obj, list):
        return [_numbers(v) for v in obj]
    return obj


def _validate(monkeypatch, folder, argv) -> int:
    """``wallsim <argv>`` with its report in ``folder``/docs and its runs in ``folder``/runs.
    Run from ``folder``: a study whose command does not hand --out on to its validation
    keeps the runs under ./runs, the same place."""
    folder.mkdir(exist_ok=True)
    monkeypatch.chdir(folder)
    return cli.main([*argv, "--docs", str(folder / "docs"), "--out", str(folder / "runs"), "--quiet"])


def _report(folder, name: str) -> dict:
    import json
    return json.loads((folder / "docs" / name).read_text())


def _counted(monkeypatch, module, name: str, key, interrupt=None) -> list:
    """Replace ``module.name`` (the function that runs one sub-run) by one that records
    ``key(case)`` of every call; at the second call ``interrupt(kwargs)`` changes its
    arguments so that the run raises KeyboardInterrupt part-way (the first has finished)."""
    real = getattr(module, name)
    calls = []

    def counted(case, *args, **kwargs):
        calls.append(key(case))
        if interrupt is not None and len(calls) == 2:
            interrupt(kwargs)
        return real(case, *args, **kwargs)

    monkeypatch.setattr(module, name, counted)
    return calls


def _ctrl_c_after(n: int):
    """A callable that raises KeyboardInterrupt at its ``n``-th call (Ctrl-C part-way)."""
    count = []

    def tick(*args, **kwargs):
        count.append(1)
        if len(count) >= n:
            raise KeyboardInterrupt
    return tick


@pytest.mark.slow
def test_an_interrupted_drystone_validation_goes_on_to_the_same_report(monkeypatch, tmp_path):
    """Case A, walls V1L and V2L: interrupted in V2L's run, the command again runs V2L
    alone (V1L read from its run folder, its figures too) and writes the uninterrupted
    command's drystone.json; once more, it runs nothing."""
    import studies.drystone.validate as V

    argv = ["validate", "drystone", "--walls", "V1L,V2L", "--band", "le", "--no-convergence", "--no-independence"]
    wall = lambda case: case.wall       # noqa: E731
    straight = _counted(monkeypatch, V, "run_dem", wall)
    assert _validate(monkeypatch, tmp_path / "straight", argv) == 0
    assert straight == ["V1L", "V2L"]

    def mid_run(kwargs):                 # Ctrl-C after 3 of V2L's water increments
        kwargs["on_increment"] = _ctrl_c_after(3)
    first = _counted(monkeypatch, V, "run_dem", wall, interrupt=mid_run)
    assert _validate(monkeypatch, tmp_path / "resumed", argv) == 130
    assert first == ["V1L", "V2L"]
    assert not (tmp_path / "resumed" / "docs" / "drystone.json").exists()
    again = _counted(monkeypatch, V, "run_dem", wall)
    assert _validate(monkeypatch, tmp_path / "resumed", argv) == 0
    assert again == ["V2L"]                                  # V1L not run again
    want = _numbers(_report(tmp_path / "straight", "drystone.json"))
    assert _numbers(_report(tmp_path / "resumed", "drystone.json")) == want
    assert (tmp_path / "resumed" / "docs" / "drystone" / "V1L_mechanism.png").is_file()
    runs = sorted(p.name for p in (tmp_path / "resumed" / "runs" / "drystone").iterdir())
    assert len(runs) == 2 and all(r.startswith("validate-wall-") for r in runs)
    once_more = _counted(monkeypatch, V, "run_dem", wall)
    assert _validate(monkeypatch, tmp_path / "resumed", argv) == 0
    assert once_more == [] and _numbers(_report(tmp_path / "resumed", "drystone.json")) == want


@pytest.mark.slow
def test_an_interrupted_heap_validation_goes_on_to_the_same_report(monkeypatch, tmp_path):
    """Seeds 1 and 2 at RESUME_SIZE: interrupted in seed 2's run, the command again runs
    seed 2 alone, in a clean folder (what an interrupted run left there removed first),
    and writes the uninterrupted command's heap.json."""
    import studies.heap.validate as V

    argv = ["validate", "heap", "--seeds", "1,2", *[w for k, v in RESUME_SIZE.items() for w in ("--set", f"{k}={v!r}")]]
    seed = lambda case: case.seed        # noqa: E731
    straight = _counted(monkeypatch, V, "compare_heap", seed)
    assert _validate(monkeypatch, tmp_path / "straight", argv) == 0
    assert straight == [1, 2]

    class Interrupting:                  # the progress bar, whose first update is a Ctrl-C
        add_task = staticmethod(lambda *args, **kwargs: 0)
        update = staticmethod(_ctrl_c_after(1))

    def mid_run(kwargs):
        kwargs["progress"] = Interrupting()
    first = _counted(monkeypatch, V, "compare_heap", seed, interrupt=mid_run)
    assert _validate(monkeypatch, tmp_path / "resumed", argv) == 130
    assert first == [1, 2]
    runs = tmp_path / "resumed" / "runs" / "heap"
    assert (runs / V.run_name(HeapCase(**RESUME_SIZE, seed=1)) / "result.json").is_file()
    # what an interrupted seed may leave: its config and a table written before the end
    unfinished = runs / V.run_name(HeapCase(**RESUME_SIZE, seed=2))
    unfinished.mkdir(exist_ok=True)
    (unfinished / "config.toml").write_text("# an interrupted run's\n")
    (unfinished / "stale.csv").write_text("x\n1\n")
    again = _counted(monkeypatch, V, "compare_heap", seed)
    assert _validate(monkeypatch, tmp_path / "resumed", argv) == 0
    assert again == [2]                                      # seed 1 not run again
    assert not (unfinished / "stale.csv").exists() and (unfinished / "result.json").is_file()
    assert _numbers(_report(tmp_path / "resumed", "heap.json")) == _numbers(_report(tmp_path / "straight", "heap.json"))
