"""Issue 38: an interrupted heap run resumed from its checkpoint ends exactly as the run
would have without the interruption, bit for bit, and checkpointing does not perturb
the run. At test_heap.py's RESUME_SIZE (600 spheres on a 1.2 m base, a 0.5 s flow,
springs 25x softer: all eight stages, ~4.4 s of CPU a run on the 2-vCPU VM)."""

import contextlib
import io
import json
import re
from pathlib import Path

import numpy as np
import pytest

import cli
from studies.heap import run as M
from studies.heap.compare import CHECKPOINT, compare_heap
from studies.runner import named_run, recorded_options
from studies.store import load_npz, npz_bytes
from tests.studies.test_heap import RESUME_SIZE

#: the tables a run folder holds
TABLES = ("base_stress.csv", "subsidence.csv", "surface.csv")
#: RESUME_SIZE as the command line gives it
SETS = [f"{k}={v!r}" for k, v in RESUME_SIZE.items()]
#: wall and CPU times (result and stage log) differ between any two runs
_TIMING = re.compile(r"(^|_)(cpu|wall)(_time)?_s$")


def _not_again(*args, **kwargs):
    raise AssertionError("a resumed run started over")


def _via_file(state: dict) -> dict:
    """The checkpoint as a resume reads it: through the bytes of an .npz."""
    with np.load(io.BytesIO(npz_bytes(state)), allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


def _same(a, b, where="run") -> None:
    """Equal bit for bit: arrays (dtype too), numbers (type too; NaN equals NaN), and
    records of them (HeapRun, Shape, Subsidence, Frame, dicts, lists); wall and CPU
    times left out."""
    if isinstance(a, dict):
        keys = [k for k in a if not _TIMING.search(str(k))]
        assert keys == [k for k in b if not _TIMING.search(str(k))], where
        for k in keys:
            _same(a[k], b[k], f"{where}.{k}")
    elif hasattr(a, "_fields") or hasattr(a, "__dataclass_fields__"):
        names = a._fields if hasattr(a, "_fields") else list(a.__dataclass_fields__)
        for f in names:
            if f != "before_resume_s":
                _same(getattr(a, f), getattr(b, f), f"{where}.{f}")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), where
        for k, (u, v) in enumerate(zip(a, b)):
            _same(u, v, f"{where}[{k}]")
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), where
    else:
        assert type(a) is type(b) and (a == b or (a != a and b != b)), f"{where}: {a!r} != {b!r}"


@pytest.mark.slow
def test_a_resumed_heap_run_is_the_straight_one_bit_for_bit(monkeypatch):
    """run_heap with a checkpoint after every engine call is the run without
    checkpoints; resumed (through an .npz) from the middle of each of the eight stages
    (rain's fall and settling, the flow, the arrest, the averaging before, the
    subsidence, the hold, the averaging after) it gives the same heap, stresses,
    subsidence history, stage log and frames, bit for bit. Engine calls of 200 steps
    here (the straight run's are 1,000): how the steps are cut does not change them."""
    case = M.HeapCase(**RESUME_SIZE)
    straight = M.run_heap(case)
    monkeypatch.setattr(M, "CHUNK_PARTICLE_STEPS", 200 * case.particles)
    states = []
    checkpointed = M.run_heap(case, checkpoint=states.append, checkpoint_every_s=0.0)
    _same(straight, checkpointed)
    by_stage = {}
    for state in states:
        by_stage.setdefault(M.checkpoint_stage(state)[0], []).append(state)
    assert tuple(by_stage) == M.STAGES
    assert all(M.checkpoint_stage(s)[1] < case.average_steps for s in by_stage["after"])   # none at the end
    monkeypatch.setattr(M, "generate", _not_again)          # a resume places no cloud
    for stage, taken in by_stage.items():
        middle = taken[len(taken) // 2]
        resumed = M.run_heap(case, resume=_via_file(middle))
        _same(straight, resumed, f"resumed in {stage} at step {M.checkpoint_stage(middle)[1]}")
        assert resumed.before_resume_s[0] > 0


def test_a_checkpoint_of_another_case_is_refused():
    """A resume continues the run its checkpoint holds: another case's is refused."""
    from analytic.errors import InvalidParameter

    class Stop(Exception):
        pass

    def first(state):
        states.append(state)
        raise Stop

    states = []
    with pytest.raises(Stop):
        M.run_heap(M.HeapCase(**RESUME_SIZE), checkpoint=first, checkpoint_every_s=0.0)
    with pytest.raises(InvalidParameter, match="resume"):
        M.run_heap(M.HeapCase(**(RESUME_SIZE | {"seed": 2})), resume=states[0])


def _cli_result(argv: list[str]) -> dict:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert cli.main(argv + ["--json", "--quiet"]) == 0
    return json.loads(buf.getvalue())


class _CtrlC:
    """A progress bar that presses Ctrl-C half-way through the flow, once a checkpoint
    has been written."""

    def __init__(self, checkpoint):
        self.checkpoint, self.tasks = checkpoint, {}

    def add_task(self, label, total=None, completed=0, **fields):
        self.tasks[len(self.tasks)] = [label, total, completed]
        return len(self.tasks) - 1

    def update(self, task, advance=0, **fields):
        label, total, done = self.tasks[task]
        self.tasks[task][2] = done + advance
        if label == "slumping" and done + advance >= total // 2 and self.checkpoint.is_file():
            raise KeyboardInterrupt


@pytest.mark.slow
def test_an_interrupted_compare_resumes_on_the_command_line_to_the_straight_runs_numbers(tmp_path, monkeypatch):
    """compare_heap interrupted (Ctrl-C from the progress bar) half-way through the flow,
    after checkpoints were written, then resumed with ``wallsim compare heap --resume
    RUN_DIR``: the result's numbers and every table equal the uninterrupted command's
    bit for bit; the checkpoints are gone; the resume kept the run's recording options."""
    from studies import get

    straight = _cli_result(["compare", "heap", *sum((["--set", s] for s in SETS), []), "--no-rrd",
                            "--out", str(tmp_path / "straight")])
    straight_dir = Path(straight["run_folder"])
    assert not (straight_dir / "checkpoints").exists()

    case = get("heap").command().resolve(sets=SETS)
    assert case == M.HeapCase(**RESUME_SIZE)
    root = tmp_path / "resumed"
    folder = root / "heap" / "interrupted"
    with named_run("interrupted"), recorded_options({"rrd": None, "no_rrd": True}), \
            pytest.raises(KeyboardInterrupt):
        compare_heap(case, root=root, record=False, progress=_CtrlC(folder / CHECKPOINT), checkpoint_every_s=0.0)
    assert not (folder / "result.json").exists()
    stage, done = M.checkpoint_stage(load_npz(folder / CHECKPOINT))
    assert stage == "slump" and 0 < done < int(RESUME_SIZE["slump_time"] / M.time_step(case))

    monkeypatch.setattr(M, "generate", _not_again)          # the resume goes on from the flow
    resumed = _cli_result(["compare", "heap", "--resume", str(folder)])
    assert Path(resumed["run_folder"]).resolve() == folder.resolve()
    assert not (folder / "checkpoints").exists()
    assert not list(folder.glob("*.rrd"))                       # --no-rrd kept from the interrupted run
    assert (folder / "result.json").is_file()

    def physics(result):
        return json.dumps({k: v for k, v in result.items() if k not in ("run_folder", "resources")}, sort_keys=True)

    assert physics(_no_timings(resumed)) == physics(_no_timings(straight))
    for name in TABLES:
        assert (folder / name).read_bytes() == (straight_dir / name).read_bytes(), name


def _no_timings(obj):
    if isinstance(obj, dict):
        return {k: _no_timings(v) for k, v in obj.items() if not _TIMING.search(k)}
    if isinstance(obj, list):
        return [_no_timings(v) for v in obj]
    return obj
