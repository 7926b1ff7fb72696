"""What every study's run does around its own stages: open the run folder (or reopen
one to resume), record the resolved case, open the Rerun recording, and at the end
write ``result.json`` and the manifest. A study module supplies only its stages."""

from __future__ import annotations

import time
from pathlib import Path

from .runfolder import RunFolder

#: the run folder of the run in progress in this process (what an interrupt reports)
current_folder: Path | None = None


def open_run_folder(study: str, case, root: str | Path, *, resume: str | Path | None = None,
                    name: str | None = None) -> RunFolder:
    """A new run folder with the resolved case in config.toml, or, with ``resume``, the
    interrupted run's own folder (its config.toml is the case, kept as it was)."""
    global current_folder
    if resume is not None:
        folder = RunFolder.existing(resume, seed=getattr(case, "seed", -1))
    else:
        folder = RunFolder(study, getattr(case, "seed", -1), root=root, name=name)
        folder.write_config(case)
    current_folder = folder.path
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


def finished_result(run_dir: str | Path) -> dict | None:
    """The result of a run folder that holds a finished run (result.json), else None."""
    import json
    p = Path(run_dir) / "result.json"
    return json.loads(p.read_text()) if p.is_file() else None


def interrupted_line(resume_command: str | None) -> str:
    """One line for an interrupted run: where its finished files are and, when the
    command can resume, how."""
    stamp = time.strftime("%H:%M:%S")
    if current_folder is None:
        return f"interrupted at {stamp}; nothing was written"
    if resume_command:
        return f"interrupted at {stamp}; resume with: {resume_command} --resume {current_folder}"
    return f"interrupted at {stamp}; what finished is in {current_folder} (this command does not resume)"
