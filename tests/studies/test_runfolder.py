"""Run folders: the manifest names the code the run imported (the git
revision when the run started, not whatever HEAD is when a long run ends), and one
process at a time runs a named or resumed folder."""

import json
from pathlib import Path

import studies.runfolder as runfolder


def test_manifest_git_is_taken_at_start(tmp_path, monkeypatch):
    monkeypatch.setattr(runfolder, "git_revision", lambda repo=None: "aaaaaaa")
    rf = runfolder.RunFolder("case", 3, root=tmp_path)
    monkeypatch.setattr(runfolder, "git_revision", lambda repo=None: "bbbbbbb")   # HEAD moved on
    man = json.loads(rf.write_manifest(particles=10).read_text())
    assert man["git"] == "aaaaaaa" and man["seed"] == 3 and man["particles"] == 10


def test_a_process_keeps_the_revision_it_started_on(tmp_path):
    """A validation that ran for an hour recorded, in the folders it opened after a
    commit, the new commit rather than the code it had imported."""
    import subprocess

    def git(*args):
        subprocess.run(["git", "-C", str(tmp_path), "-c", "user.name=t", "-c", "user.email=t@t", *args],
                       check=True, capture_output=True)

    git("init", "-q")
    (tmp_path / "a.txt").write_text("1")
    git("add", "a.txt")
    git("commit", "-q", "-m", "first")
    first = runfolder.git_revision(tmp_path)
    (tmp_path / "a.txt").write_text("2")
    git("commit", "-q", "-am", "second")
    assert first != "unknown" and "+dirty" not in first
    assert runfolder.git_revision(tmp_path) == first
    assert runfolder._read_revision(tmp_path.resolve()) != first       # HEAD did move


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


def _holder(folder: Path):
    """A second process that claims ``folder`` and waits (killed by the caller)."""
    import subprocess
    import sys
    p = subprocess.Popen([sys.executable, "-c", "import time\nfrom studies.runfolder import claim\n"
                          f"claim({str(folder)!r})\nprint('held', flush=True)\ntime.sleep(120)"],
                         stdout=subprocess.PIPE, text=True, cwd=Path(__file__).parents[2])
    assert p.stdout.readline().strip() == "held"
    return p


def test_a_run_folder_is_run_by_one_process_at_a_time(tmp_path):
    """While another process runs a named validation run (it holds the folder's lock),
    the same validation started again is refused in one line naming the folder, before
    it removes or resumes anything (the seismic driver removes a folder without a
    config.toml: here it must not); once the holder is gone (killed: the system lets the
    lock go) the folder is claimed again, and one process may claim it twice."""
    import pytest

    from analytic.errors import InvalidParameter
    from studies.runfolder import claim, lock_file, unclaim
    from studies.seismic.case import SeismicCase
    from studies.seismic.validate import frequency_run, run_name
    from tests.studies.test_seismic import TINY

    case = SeismicCase(**TINY)
    folder = tmp_path / "seismic" / run_name(case)
    folder.mkdir(parents=True)
    (folder / "partial.txt").write_text("the other process's work")
    holder = _holder(folder)
    try:
        with pytest.raises(InvalidParameter) as err:
            frequency_run(case, root=tmp_path, log=lambda s: None)
        assert str(folder) in str(err.value) and "\n" not in str(err.value)
        assert (folder / "partial.txt").is_file()
    finally:
        holder.kill()
        holder.wait()
    first, second = claim(folder), claim(folder)
    assert first == second == lock_file(folder).absolute()
    unclaim(first)
    unclaim(second)
    holder = _holder(folder)         # let go: another process takes it
    holder.kill()
    holder.wait()


def test_a_finished_run_is_read_while_another_process_holds_its_lock(tmp_path, monkeypatch):
    """A folder with result.json is read, never written again: a validation finds it
    even while the command that ran it is still at work on other runs (and holds the
    lock); and a folder typed as a relative path takes the same lock as its full path."""
    from studies.runfolder import lock_file
    from studies.seismic.case import SeismicCase
    from studies.seismic.validate import frequency_run, run_name
    from tests.studies.test_seismic import TINY

    case = SeismicCase(**TINY)
    folder = tmp_path / "seismic" / run_name(case)
    folder.mkdir(parents=True)
    (folder / "result.json").write_text("{}")
    holder = _holder(folder)
    try:
        assert frequency_run(case, root=tmp_path, log=lambda s: None) == folder
    finally:
        holder.kill()
        holder.wait()
    monkeypatch.chdir(folder.parent)
    assert lock_file(Path(folder.name)) == lock_file(folder) == tmp_path / ".locks" / "seismic" / folder.name


def test_a_named_run_is_read_resumed_or_run_afresh(tmp_path):
    """``run_once``, the one path of every validation's named runs: a folder holding
    result.json is read and nothing runs; an interrupted one that can resume is handed
    to the run as it is; one that cannot (no config.toml, or a run without resume) is
    removed before the run starts afresh in it, so nothing of the old run mixes in."""
    from studies.runner import has_config, run_once

    calls = []

    def run(resume):
        calls.append(resume)
        folder.mkdir(parents=True, exist_ok=True)
        assert not (folder / "partial.txt").exists() or resume is not None
        (folder / "result.json").write_text(json.dumps({"resumed": resume is not None}))

    folder = tmp_path / "study" / "validate-x"
    folder.mkdir(parents=True)
    (folder / "result.json").write_text('{"old": 1}')
    lines = []
    assert run_once(folder, run, resumable=has_config, log=lines.append) == {"old": 1}
    assert calls == [] and lines == [f"reusing finished run {folder}"]

    (folder / "result.json").unlink()
    (folder / "config.toml").write_text("")
    (folder / "partial.txt").write_text("")
    assert run_once(folder, run, resumable=has_config, log=lines.append) == {"resumed": True}
    assert calls == [folder] and (folder / "partial.txt").is_file()

    (folder / "result.json").unlink()
    assert run_once(folder, run, log=lines.append) == {"resumed": False}     # cannot resume
    assert calls == [folder, None] and not (folder / "partial.txt").exists()
