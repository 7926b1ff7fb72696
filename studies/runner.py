"""What every study's run does around its own stages: open the run folder (or reopen
one to resume), record the resolved case, open the Rerun recording, and at the end
write ``result.json`` and the manifest. A study module supplies only its stages."""

from __future__ import annotations

import time
from pathlib import Path

from .runfolder import RunFolder


def open_run_folder(study: str, case, root: str | Path, *, resume: str | Path | None = None,
                    name: str | None = None) -> RunFolder:
    """A new run folder with the resolved case in config.toml, or, with ``resume``, the
    interrupted run's own folder (its config.toml is the case, kept as it was)."""
    if resume is not None:
        return RunFolder.existing(resume, seed=getattr(case, "seed", -1))
    folder = RunFolder(study, getattr(case, "seed", -1), root=root, name=name)
    folder.write_config(case)
    return folder


def open_recording(path: Path | None, *, study: str, recording_id: str, dim: int, blueprint=None,
                   spawn: bool = False):
    """The run's Rerun recording (``path`` None and no viewer: a recorder that does nothing)."""
    from viz.recorder import Recorder
    return Recorder(path, app_id=f"wallsim {study}", recording_id=recording_id, dim=dim, every=1,
                    spawn=spawn, enabled=path is not None or spawn, blueprint=blueprint)


def finish(folder: RunFolder, result: dict, **manifest) -> None:
    """result.json (what ``--json`` prints) and the manifest (provenance), written last
    so a folder with a result.json holds a finished run."""
    folder.write_json("result.json", result)
    folder.write_manifest(**manifest)


class Stopwatch:
    """Wall time of each named stage [s]: ``with clock("movement"): ...``."""

    def __init__(self):
        self.seconds: dict[str, float] = {}
        self.t0 = time.perf_counter()

    def __call__(self, stage: str):
        return _Lap(self, stage)

    @property
    def total(self) -> float:
        return time.perf_counter() - self.t0


class _Lap:
    def __init__(self, watch: Stopwatch, stage: str):
        self.watch, self.stage = watch, stage

    def __enter__(self):
        self.t = time.perf_counter()

    def __exit__(self, *exc):
        self.watch.seconds[self.stage] = time.perf_counter() - self.t
