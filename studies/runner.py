"""The run envelope: what every command does around a study's own stages.

``command_envelope`` wraps one command (CLI or Python API): it knows the run folders
the command opens, where each setting came from, and the reduced-size note; an
interrupt or an error inside it names only folders that exist, and a bad input leaves
no folder behind. Inside it a study opens its run folder (``open_run_folder``: a new
one with the resolved case in config.toml, or the interrupted run's own to resume),
its Rerun recording, and ends with ``finish``: the one writer of result.json, written
once and last, with the wall time, CPU time and peak memory of the run."""

from __future__ import annotations

import json
import shutil
import time
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import reproducibility

from .runfolder import RunFolder, claim, claimed_unless_finished, lock_file, unclaim


@dataclass
class Envelope:
    """One command's run state.

    sources:  where each non-default setting came from (config.toml's notes)
    note:     result -> the reduced-size line of the command's main run, or None
    opened:   (folder, created by this command) of every run folder opened, in order
    claims:   the locks of the named and resumed run folders it opened (``runfolder.claim``)
    """

    sources: dict[str, str] = field(default_factory=dict)
    note: Callable[[dict], str | None] | None = None
    opened: list[tuple[Path, bool]] = field(default_factory=list)
    claims: list = field(default_factory=list)
    clocks: tuple[float, float] = field(default_factory=lambda: (time.perf_counter(), time.process_time()))

    @property
    def last_folder(self) -> Path | None:
        """The folder the command opened last, if it still exists."""
        for path, _ in reversed(self.opened):
            if path.is_dir():
                return path
        return None

    def discard_empty(self) -> None:
        """Remove the folders this command created that hold no run (only its config):
        after an error the user is told about, nothing half-made stays behind."""
        for path, created in self.opened:
            if created and path.is_dir() and {p.name for p in path.iterdir()} <= _SETUP_FILES:
                shutil.rmtree(path, ignore_errors=True)


#: what a run folder holds before its first stage has done anything
_SETUP_FILES = {"config.toml", "run_options.json"}

_envelope: ContextVar[Envelope | None] = ContextVar("wallsim_envelope", default=None)


def machine_memory() -> float | None:
    """This machine's memory [bytes] (Linux /proc/meminfo MemTotal; None elsewhere)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemTotal:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    return None


#: memory of a dem3d run besides its spheres: Python, numpy, numba's compiled kernels [bytes]
BASE_MEMORY = 0.5e9
#: dem3d memory a sphere: engine arrays, double-buffered neighbour pairs, a checkpoint copy
#: (~4 KB, studies/granular.py)
MEMORY_PER_SPHERE = 4096.0
#: pymunk memory a packed disk (measured: 200k disks, 0.84 GB; studies/khosravi/case.py)
MEMORY_PER_DISK = 4200.0


class RunInterrupted(KeyboardInterrupt):
    """Ctrl-C inside a command, carrying the folder its finished files are in (or None)."""

    def __init__(self, folder: Path | None):
        super().__init__()
        self.folder = folder


@contextmanager
def command_envelope(sources: dict[str, str] | None = None, note: Callable[[dict], str | None] | None = None,
                     *, vtk: bool = False):
    """Run one command inside: a bad input or an error removes the folders it created
    that hold nothing yet; Ctrl-C becomes ``RunInterrupted`` naming the folder that
    holds what finished (None when nothing was written). ``vtk`` (``--vtk``): every run
    folder the command opens keeps it in run_options.json, and its recording writes VTK
    files beside the Rerun one (``open_recording``)."""
    from analytic.errors import InvalidParameter

    env = Envelope(sources or {}, note)
    token = _envelope.set(env)
    options = _options.set({**(_options.get() or {}), "vtk": True}) if vtk else None
    try:
        yield env
    except KeyboardInterrupt:
        env.discard_empty()
        raise RunInterrupted(env.last_folder) from None
    except (InvalidParameter, OSError, MemoryError):
        env.discard_empty()
        raise
    finally:
        for key in env.claims:
            unclaim(key)
        if options is not None:
            _options.reset(options)
        _envelope.reset(token)

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
    """Within this block a new run folder keeps ``options`` in run_options.json, over
    those of an enclosing block (a sweep's point keeps the sweep's and the study's)."""
    token = _options.set({**(_options.get() or {}), **options})
    try:
        yield
    finally:
        _options.reset(token)


def run_root_and_options(opts, kept: dict) -> tuple[Path, dict]:
    """Where a command's run goes and the run options it keeps: ``opts.out`` and ``kept``,
    or, with ``--resume``, the interrupted run's root (its specimen caches are under it)
    and the options it started with, which win over today's defaults (it records as it
    did)."""
    if not getattr(opts, "resume", None):
        return Path(opts.out), kept
    return Path(opts.resume).resolve().parents[1], kept | saved_options(opts.resume)


def refuse_new_recording(resume: str | Path, vtk: bool) -> None:
    """A resumed run records as it started: ``--vtk`` on a run started without it is
    refused (it would silently write no VTK)."""
    if vtk and not saved_options(resume).get("vtk"):
        from analytic.errors import InvalidParameter
        raise InvalidParameter("--vtk", f"on the interrupted run {resume}", "the settings that run started with",
                               "it started without --vtk; a resumed run records as it started")


def saved_options(run_dir: str | Path) -> dict:
    """The run options an interrupted run started with ({} for runs before they were kept)."""
    p = Path(run_dir) / "run_options.json"
    return json.loads(p.read_text()) if p.is_file() else {}


def open_run_folder(study: str, case, root: str | Path, *, resume: str | Path | None = None,
                    name: str | None = None, seed: int | None = None) -> RunFolder:
    """A new run folder with the resolved case in config.toml, or, with ``resume``, the
    interrupted run's own folder (its config.toml is the case, kept as it was).
    ``seed``: the case's seed when it is not ``case.seed``."""
    name = name if name is not None else _run_name.get()
    seed = seed if seed is not None else getattr(case, "seed", None)
    env = _envelope.get()
    if env is not None and (resume is not None or name is not None):
        # a folder found again by name or resumed: one process at a time (the command's)
        env.claims.append(claim(Path(resume) if resume is not None else Path(root) / study / name))
    if resume is not None:
        refuse_new_recording(resume, bool((_options.get() or {}).get("vtk")))
        folder = RunFolder.existing(resume, seed=seed)
    else:
        created = name is None or not (Path(root) / study / name).is_dir()
        folder = RunFolder(study, seed, root=root, name=name)
        folder.write_config(case, sources=env.sources if env else None)
        if _options.get() is not None:
            folder.write_json("run_options.json", _options.get())
    if env is not None:
        if not env.opened:          # the command's first run: its time counts from the command's start
            folder.start_clocks(*env.clocks)
        env.opened.append((folder.path, resume is None and created))
    return folder


def open_recording(path: Path | None, *, study: str, recording_id: str, dim: int, layout=None,
                   spawn: bool = False, folder: RunFolder | Path | None = None, part: str | None = None):
    """The run's Rerun recording (``path`` None and no viewer: none), and its VTK files in
    ``folder``/vtk when the run was started with ``--vtk`` (its run_options.json says so,
    so a resumed run writes them as the interrupted one did); ``part``: a subfolder of
    vtk/ for one of several tests of a run (each with its own clock). With neither, a
    recorder that does nothing."""
    from viz.recorder import Recorder
    vtk = None
    if folder is not None:
        run_dir = Path(getattr(folder, "path", folder))
        if saved_options(run_dir).get("vtk"):
            from viz.vtk import VtkSeries
            vtk = VtkSeries(run_dir / VTK_FOLDER / (part or ""))
    return Recorder(path, app_id=f"wallsim {study}", recording_id=recording_id, dim=dim, every=1,
                    spawn=spawn, enabled=path is not None or spawn, layout=layout, vtk=vtk)


@contextmanager
def test_recording(folder: RunFolder | Path | None, *, study: str, label: str, dim: int = 2):
    """The recording of one test of a calibration that runs several (``--vtk``: its frames
    in vtk/<label>/, each test with its own clock): yields the recorder, or None when the
    run records nothing (or there is no run ``folder``)."""
    if folder is None:
        yield None
        return
    run_dir = Path(getattr(folder, "path", folder))
    rec = open_recording(None, study=study, recording_id=f"{run_dir.name}-{label}", dim=dim, folder=folder,
                         part=label)
    try:
        yield rec if rec.enabled else None
    finally:
        rec.close()


#: where a run's VTK files go in its folder (``--vtk``)
VTK_FOLDER = "vtk"


def finish(folder: RunFolder, result: dict, *, main: bool = True, **manifest) -> None:
    """The end of a run: the reduced-size note (``main``: the command's own run, not a
    specimen it prepared), what the run used beyond its config (config.toml's notes),
    the manifest (provenance), and last result.json (what ``--json`` prints), written
    here only, once, so a folder with a result.json holds a finished run. The result
    records the reproducibility mode and the resources of the run."""
    env = _envelope.get()
    if main and env is not None and env.note is not None:
        note = env.note(result)
        if note:
            result["scale_note"] = note
    result["resources"] = folder.resources()
    result["reproducibility"] = reproducibility.describe()
    if (folder.path / VTK_FOLDER).is_dir():
        from viz.vtk import summary
        result["vtk"] = summary(folder.path / VTK_FOLDER)
    folder.note_used(used_settings(result))
    folder.write_manifest(**manifest)
    folder.write_json("result.json", result)
    if env is not None and (key := lock_file(folder.path)) in env.claims:
        env.claims.remove(key)      # finished: read from now on, by any process
        unclaim(key)


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


def drop_checkpoint(run_dir: str | Path, name: str) -> None:
    """Remove a finished run's checkpoint ``name`` (e.g. "checkpoints/shake.npz") and its
    folder when nothing else is left in it: a run with its result has nothing to resume."""
    path = Path(run_dir) / name
    path.unlink(missing_ok=True)
    if path.parent.is_dir() and not any(path.parent.iterdir()):
        path.parent.rmdir()


def reusing_line(run_dir: str | Path) -> str:
    """What a validation says when it reads a finished run instead of running it again;
    under --vtk it says when that run has no VTK files (it was run without --vtk)."""
    line = f"reusing finished run {run_dir}"
    if (_options.get() or {}).get("vtk") and not (Path(run_dir) / VTK_FOLDER).is_dir():
        line += " (run without --vtk: it has no VTK files; remove the folder to run it again with them)"
    return line


def finished_result(run_dir: str | Path) -> dict | None:
    """The result of a run folder that holds a finished run (result.json), else None."""
    p = Path(run_dir) / "result.json"
    return json.loads(p.read_text()) if p.is_file() else None


def run_once(folder: Path, run: Callable[[Path | None], object], *, resumable: Callable[[Path], bool] | None = None,
             log=print) -> dict | None:
    """The result.json of the named run in ``folder``, run by one process at a time
    (``claimed_unless_finished``): read when the folder holds a finished run; resumed,
    ``run(folder)``, when ``resumable(folder)`` says it holds an interrupted one; else
    run afresh, ``run(None)``, whatever the folder held removed first (a run that cannot
    go on from it would mix with it). ``resumable`` None: the run cannot resume."""
    folder = Path(folder)
    with claimed_unless_finished(folder):
        done = finished_result(folder)
        if done is not None:
            log(reusing_line(folder))
            return done
        if resumable is not None and resumable(folder):
            log(f"resuming interrupted run {folder}")
            run(folder)
        else:
            if folder.exists():
                shutil.rmtree(folder)
            run(None)
        return finished_result(folder)


def has_config(folder: Path) -> bool:
    """Whether an unfinished run folder can be resumed: its config.toml was written."""
    return (Path(folder) / "config.toml").is_file()


def interrupted_line(resume_command: str | None, folder: Path | None, *, reruns: bool = False) -> str:
    """One line for an interrupted run: where its finished files are (only a folder
    that exists) and, when the command can resume, how (``reruns``: the same command
    again reuses the runs that finished, as a validate does)."""
    stamp = time.strftime("%H:%M:%S")
    if folder is None or not folder.is_dir():
        return f"interrupted at {stamp}; nothing was written"
    if resume_command:
        return f"interrupted at {stamp}; resume with: {resume_command} --resume {folder}"
    if reruns:
        return (f"interrupted at {stamp}; the same command again reuses the runs that finished (under "
                f"{folder.parent}) and continues")
    return f"interrupted at {stamp}; what finished is in {folder} (this command does not resume)"


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


def closing_line(result: dict, folder) -> str:
    """The line(s) a study command prints last: its reduced-size note, if any (in
    result.json too, written by ``finish``), and the run folder."""
    note = result.get("scale_note")
    return f"{note}\nrun folder: {folder}" if note else f"run folder: {folder}"
