"""Provenance: a run folder's manifest names the code the run imported, i.e. the git
revision when the run started, not whatever HEAD is when a long run ends."""

import json

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
