"""What every study's run does around its own stages: open the run folder (or reopen
one to resume), record the resolved case, open the Rerun recording, and at the end
write ``result.json`` and the manifest. A study module supplies only its stages."""

from __future__ import annotations

import json
import time
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path

import reproducibility

from .runfolder import RunFolder

#: the run folder of the command in progress in this process (what an interrupt and the
#: config notes refer to); the CLI clears it before each command
current_folder: Path | None = None

#: the folder name a sweep gives the run in this thread (``named_run``); None: date, time, seed
_run_name: ContextVar[str | None] = ContextVar("run_name", default=None)


@contextmanager
def named_run(name: str):
    """Runs opened in this block (this thread) go to ``<root>/<study>/<name>`` instead of
    a folder named by date and time, so a sweep finds a point's run again on a rerun."""
    token = _run_name.set(name)
    try:
        yield
    finally:
        _run_name.reset(token)


#: the run options of the command in progress (``recorded_options``), kept in the run
#: folder so a resume runs with the same recording and output settings
_options: ContextVar[dict | None] = ContextVar("wallsim_run_options", default=None)


@contextmanager
def recorded_options(options: dict):
    """Within this block a new run folder keeps ``options`` in run_options.json."""
    token = _options.set(options)
    try:
        yield
    finally:
        _options.reset(token)


def saved_options(run_dir: str | Path) -> dict:
    """The run options an interrupted run started with ({} for runs before they were kept)."""
    p = Path(run_dir) / "run_options.json"
    return json.loads(p.read_text()) if p.is_file() else {}


def open_run_folder(study: str, case, root: str | Path, *, resume: str | Path | None = None,
                    name: str | None = None, seed: int | None = None) -> RunFolder:
    """A new run folder with the resolved case in config.toml, or, with ``resume``, the
    interrupted run's own folder (its config.toml is the case, kept as it was).
    ``seed``: the case's seed when it is not ``case.seed``."""
    global current_folder
    name = name if name is not None else _run_name.get()
    seed = seed if seed is not None else getattr(case, "seed", None)
    if resume is not None:
        folder = RunFolder.existing(resume, seed=seed)
    else:
        folder = RunFolder(study, seed, root=root, name=name)
        folder.write_config(case)
        if _options.get() is not None:
            folder.write_json("run_options.json", _options.get())
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
    so a folder with a result.json holds a finished run. The result records the
    reproducibility mode that made it (``reproducibility.describe``)."""
    result["reproducibility"] = reproducibility.describe()
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


def used_settings(result: dict) -> list[str]:
    """What a run used that its config does not say: the particle count reached and the
    grains and box it was scaled to (from the result's provenance)."""
    prov = result.get("provenance", {})
    used = []
    if "particles" in result:
        used.append(f"particles reached: {result['particles']}")
    if "H_m" in result:
        used.append(f"fill height reached: {result['H_m']:.4g} m (the case's H is the target)")
    for key, text in (("grain_scale", "grain diameters x {:.4g} (the case's d_min, d_max)"),
                      ("width_m", "periodic width {:.4g} m"), ("dt_s", "time step {:.4g} s")):
        if key in prov:
            used.append(text.format(prov[key]))
    if "dt_s" in result and "dt_s" not in prov:
        used.append(f"time step {result['dt_s']:.4g} s")
    return used


def annotate_config(sources: dict[str, str], result: dict) -> None:
    """Append to the run's config.toml where each setting came from and what was used."""
    from .config import sources_comment
    if current_folder is None or not (current_folder / "config.toml").is_file():
        return
    path = current_folder / "config.toml"
    text = path.read_text().split("\n# where the settings came from")[0].rstrip("\n") + "\n"
    from .store import atomic_write
    atomic_write(path, (text + sources_comment(sources, used_settings(result))).encode())


def add_to_result(result: dict) -> None:
    """Rewrite the run folder's result.json with what the study added after the run
    (so result.json stays what ``--json`` prints)."""
    from .runfolder import to_plain
    from .store import atomic_write
    folder = result.get("run_folder")
    if folder and (Path(folder) / "result.json").is_file():
        atomic_write(Path(folder) / "result.json", (json.dumps(to_plain(result), indent=2) + "\n").encode())


def closing_line(result: dict, note: str | None, folder) -> str:
    """The line(s) a study command prints last: a reduced-size note (kept in result.json
    too) and the run folder."""
    if not note:
        return f"run folder: {folder}"
    result["scale_note"] = note
    add_to_result(result)
    return f"{note}\nrun folder: {folder}"
