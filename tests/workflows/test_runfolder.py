"""Provenance: a run folder's manifest names the code the run imported, i.e. the git
revision when the run started, not whatever HEAD is when a long run ends."""

import json

import workflows.runfolder as runfolder


def test_manifest_git_is_taken_at_start(tmp_path, monkeypatch):
    monkeypatch.setattr(runfolder, "git_revision", lambda repo=None: "aaaaaaa")
    rf = runfolder.RunFolder("case", 3, root=tmp_path)
    monkeypatch.setattr(runfolder, "git_revision", lambda repo=None: "bbbbbbb")   # HEAD moved on
    man = json.loads(rf.write_manifest(particles=10).read_text())
    assert man["git"] == "aaaaaaa" and man["seed"] == 3 and man["particles"] == 10
