"""Provenance: a run folder's manifest names the code the run imported, i.e. the git
revision when the run started, not whatever HEAD is when a long run ends."""

import json
from pathlib import Path

import studies.runfolder as runfolder


def test_manifest_git_is_taken_at_start(tmp_path, monkeypatch):
    monkeypatch.setattr(runfolder, "git_revision", lambda repo=None: "aaaaaaa")
    rf = runfolder.RunFolder("case", 3, root=tmp_path)
    monkeypatch.setattr(runfolder, "git_revision", lambda repo=None: "bbbbbbb")   # HEAD moved on
    man = json.loads(rf.write_manifest(particles=10).read_text())
    assert man["git"] == "aaaaaaa" and man["seed"] == 3 and man["particles"] == 10


def test_manifest_keeps_the_machine_load_at_start_and_end(tmp_path, monkeypatch):
    """Wall times are only comparable with the load they ran under (a second job on the
    two cores slowed runs 2-3x): the manifest records the 1-min load average."""
    loads = iter([(1.5, 1.0, 1.0), (0.25, 0.5, 0.5)])
    monkeypatch.setattr(runfolder.os, "getloadavg", lambda: next(loads))
    rf = runfolder.RunFolder("case", 1, root=tmp_path)
    man = json.loads(rf.write_manifest().read_text())
    assert man["load_average_1min"] == {"start": 1.5, "end": 0.25}


def test_runs_started_in_the_same_second_get_their_own_folders(tmp_path, monkeypatch):
    """Two runs of a sweep launched together (same case, seed and second) once wrote into
    one folder, each overwriting the other's config and results."""
    monkeypatch.setattr(runfolder.time, "strftime", lambda fmt: "20261123-021751")
    a = runfolder.RunFolder("case", 1, root=tmp_path)
    b = runfolder.RunFolder("case", 1, root=tmp_path)
    assert a.path.name == "20261123-021751-seed1" and b.path.name == "20261123-021751-seed1-2"
    named = runfolder.RunFolder("case", 1, root=tmp_path, name="mine")
    again = runfolder.RunFolder("case", 1, root=tmp_path, name="mine")  # an explicit name is reused
    assert named.path == again.path


def test_a_run_folder_is_written_by_one_process_at_a_time(tmp_path):
    """A second process opening a run folder that another is running is refused in one
    line naming the folder (two processes resuming one validate run would overwrite each
    other's checkpoints); once the holder has finished (runner.finish releases the folder),
    or has died, the folder opens again."""
    import subprocess
    import sys

    import pytest

    from analytic.errors import InvalidParameter
    from studies.runfolder import RunFolder, release

    folder = tmp_path / "seismic" / "validate-5Hz-x"
    folder.mkdir(parents=True)
    (folder / "config.toml").write_text("")
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time\nfrom studies.runfolder import RunFolder\n"
                               f"RunFolder.existing({str(folder)!r})\nprint('held', flush=True)\ntime.sleep(60)"],
                              stdout=subprocess.PIPE, text=True, cwd=Path(__file__).parents[2])
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(InvalidParameter) as err:
            RunFolder.existing(folder)
        assert str(folder) in str(err.value) and "\n" not in str(err.value)
        with pytest.raises(InvalidParameter):
            RunFolder("seismic", 1, root=tmp_path, name="validate-5Hz-x")
    finally:
        holder.kill()
        holder.wait()
    again = RunFolder.existing(folder)              # the holder died: the system let the lock go
    assert RunFolder.existing(folder).path == again.path    # the same process may open it again
    release(folder)
