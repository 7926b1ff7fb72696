"""Issue 38: an interrupted seismic run resumed from its checkpoint ends exactly as the
run would have without the interruption, bit for bit, and checkpointing does not
perturb the run. At the reduced size of test_seismic.py (TINY: ~850 spheres, 8434 steps
of shaking, 21 readings; ~5 s of one core a shaking)."""

import io
import json

import numpy as np
import pytest

from studies.runfolder import SESSIONS
from studies.runner import named_run
from studies.seismic.case import SeismicCase
from studies.seismic.compare import CHECKPOINT, compare_seismic
from studies.seismic.run import shake
from studies.store import load_npz, npz_bytes
from tests.studies.test_seismic import TINY

#: snapshot (strain map) times, prototype [s]: one before the interruption, one after
SNAPSHOTS = (0.04, 0.16)
#: the tables a run folder holds
TABLES = ("series.csv", "pressure_profiles.csv", "settlement.csv", "strain_field.csv")
#: result keys that are times, paths or resources (differ between any two runs)
NOT_PHYSICS = ("wall_time_s", "stage_seconds", "run_folder", "resources", "shake_seconds", "steps_per_s")


@pytest.fixture(scope="module")
def tiny(tmp_path_factory, seismic_static_cache):
    """The case, and a root whose static-state cache holds it (every run below starts
    from the same static state, prepared once for the test run)."""
    case = SeismicCase(**TINY)
    root = tmp_path_factory.mktemp("seismic_resume")
    return case, seismic_static_cache(case, root), root


def _same_shaking(a, b) -> None:
    """Two Shaken records are the same bit for bit: times, base, every reading, the
    snapshots and the main model's final state (every array of to_arrays)."""
    assert a.steps == b.steps
    assert np.array_equal(a.time, b.time) and np.array_equal(a.base, b.base)
    assert len(a.readings) == len(b.readings)
    for r, s in zip(a.readings, b.readings):
        for f in r._fields:
            assert np.array_equal(getattr(r, f), getattr(s, f)), f
    assert [s[:3] for s in a.snapshots] == [s[:3] for s in b.snapshots]
    assert all(np.array_equal(s.positions, t.positions) for s, t in zip(a.snapshots, b.snapshots))
    assert a.final.keys() == b.final.keys()
    assert [k for k in a.final if not np.array_equal(a.final[k], b.final[k])] == []


def _same_state(a: dict, b: dict) -> None:
    """Two checkpoints hold the same state (main model, both columns, the free-field
    segments, readings, snapshots) bit for bit, the wall time aside."""
    assert a.keys() == b.keys()
    differ = [k for k in a if k != "shake/seconds"
              and not (np.array_equal(a[k], b[k]) and a[k].dtype == b[k].dtype)]
    assert differ == []


def _via_file(state: dict) -> dict:
    """The checkpoint as a resume reads it: through the bytes of an .npz."""
    with np.load(io.BytesIO(npz_bytes(state)), allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


@pytest.mark.slow
def test_a_resumed_shaking_is_the_straight_one_bit_for_bit(tiny):
    """shake() with a checkpoint at every reading is the run without checkpoints; a
    resume from the checkpoint taken as the rest ends, and one from a checkpoint in the middle (through an .npz) gives the same readings,
    snapshots and final state, and at the end the same checkpoint state (columns and
    free-field segments included) as the run that was not interrupted."""
    case, prep, _ = tiny
    straight = shake(case, prep, snapshot_times=SNAPSHOTS)
    states = []
    checkpointed = shake(case, prep, snapshot_times=SNAPSHOTS, checkpoint=states.append, checkpoint_every_s=0.0)
    _same_shaking(straight, checkpointed)
    # one as the rest ends (the first reading), then at every reading but the last
    assert len(states) == len(straight.readings) - 1
    assert int(states[0]["shake/done"]) == 0
    _same_shaking(straight, shake(case, prep, snapshot_times=SNAPSHOTS, resume=_via_file(states[0])))
    middle = _via_file(states[len(states) // 2])
    assert len(middle["snap/asked_s"]) == 1                    # one snapshot before, one after
    later = []
    resumed = shake(case, prep, snapshot_times=SNAPSHOTS, resume=middle, checkpoint=later.append,
                    checkpoint_every_s=0.0)
    _same_shaking(straight, resumed)
    _same_state(states[-1], later[-1])


@pytest.mark.slow
def test_resuming_across_re_sorts_of_the_bonded_wall_is_exact(tiny):
    """The engine re-sorts its spheres every ``sort_every`` neighbour-list builds,
    renumbering the wall's bonds and the spheres glued to the base; with a re-sort at
    every second build (50 in the study, which the tiny run never reaches) the resumed
    run, whose spheres are re-sorted after the checkpoint, still ends bit for bit as the
    straight one."""
    case, prep, _ = tiny
    two = np.array(2)
    prep = prep._replace(main=prep.main | {"sort_every": two},
                         columns=tuple(c | {"sort_every": two} for c in prep.columns))
    states = []
    straight = shake(case, prep, checkpoint=states.append, checkpoint_every_s=0.0)
    middle = _via_file(states[len(states) // 3])
    assert int(straight.final["n_rebuilds"]) - int(middle["main/n_rebuilds"]) >= 2
    assert not np.array_equal(middle["main/original_index"], straight.final["original_index"])   # re-sorted
    _same_shaking(straight, shake(case, prep, resume=middle))


@pytest.mark.slow
def test_an_interrupted_compare_resumes_to_the_straight_runs_numbers(tiny):
    """compare_seismic interrupted (Ctrl-C from the progress callback) half-way through
    the shaking, after checkpoints were written, then resumed on its folder with the case
    its config.toml gives: the result's physics and every table equal the uninterrupted
    run's bit for bit; the checkpoints are gone; the resumed part's recording is
    recording-resumed.rrd beside the interrupted part's recording.rrd."""
    from studies import get

    case, _, root = tiny
    straight, straight_dir = compare_seismic(case, root=root, strain_times=SNAPSHOTS)
    assert not (straight_dir / "checkpoints").exists()

    def interrupt(done, total):
        if done >= total // 2 and (root / "seismic" / "interrupted" / CHECKPOINT).is_file():
            raise KeyboardInterrupt

    with named_run("interrupted"), pytest.raises(KeyboardInterrupt):
        compare_seismic(case, root=root, strain_times=SNAPSHOTS, progress=interrupt, record=True,
                        checkpoint_every_s=0.0)
    folder = root / "seismic" / "interrupted"
    assert not (folder / "result.json").exists()
    saved = load_npz(folder / CHECKPOINT)
    assert 0 < int(saved["shake/done"]) < int(saved["shake/total"])
    stopped = json.loads((folder / SESSIONS).read_text())["sessions"]
    assert len(stopped) == 1 and stopped[0]["cpu_time_s"] > 0
    again = get("seismic").command().resolve(resume=str(folder), study="seismic")
    assert again == case

    resumed, resumed_dir = compare_seismic(again, root=root, strain_times=SNAPSHOTS, resume=folder, record=True)
    assert resumed_dir == folder
    assert not (folder / "checkpoints").exists()
    assert (folder / "result.json").is_file()
    assert (folder / "recording.rrd").is_file() and (folder / "recording-resumed.rrd").is_file()
    assert _physics(resumed) == _physics(straight)
    for name in TABLES:
        assert (folder / name).read_bytes() == (straight_dir / name).read_bytes(), name
    assert json.loads((folder / "result.json").read_text())["steps"] == straight["steps"]
    # the run's CPU is both sessions': the stopped one's up to its last checkpoint, then the resumed one's
    manifest = json.loads((folder / "manifest.json").read_text())
    assert [s["cpu_time_s"] for s in manifest["sessions"]][:1] == [stopped[0]["cpu_time_s"]]
    assert resumed["resources"]["sessions"] == 2
    assert resumed["resources"]["cpu_time_s"] == pytest.approx(sum(s["cpu_time_s"] for s in manifest["sessions"]),
                                                               abs=0.5)


def _physics(result: dict) -> str:
    """The result without its times, paths and resources, as exact text (floats by repr,
    NaN compared as text)."""
    kept = {k: v for k, v in result.items() if k not in NOT_PHYSICS}
    kept["prepare"] = {k: v for k, v in kept["prepare"].items() if k != "prepare_s"}
    return json.dumps(kept, sort_keys=True)
