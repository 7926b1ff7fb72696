"""Run folders: where every DEM run leaves its resolved config, provenance, data and plots.
Every file is written whole or not at all (``store.atomic_write``): an interrupted run
leaves no half-written table.

Layout (one folder per run)::

    runs/<case>/<YYYYmmdd-HHMMSS>-seed<seed>/
        config.toml      the fully resolved case (after --config and --set)
        manifest.json    what produced the result: versions, seed, host, wall time, ...
        result.json      the headline numbers (what --json prints)
        *.csv            tidy tables, units in every header
        *.png            figures
        recording.rrd    Rerun recording
        checkpoints/     state to resume an interrupted run
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import platform
import socket
import subprocess
import sys
import threading
import time
from contextlib import contextmanager, nullcontext
from pathlib import Path

import numpy as np
import tomli_w

try:
    import fcntl
except ImportError:             # not a POSIX system: runs are not guarded against each other
    fcntl = None

import reproducibility

from .store import atomic_write, to_plain


def package_versions() -> dict[str, str]:
    """Versions of wallsim and the packages that shape its numbers."""
    from importlib.metadata import PackageNotFoundError, version

    out = {"python": platform.python_version()}
    for pkg in ("wallsim", "numpy", "scipy", "numba", "pymunk", "rerun-sdk"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:
            out[pkg] = "not installed"
    return out


#: each checkout's revision as this process first read it (``git_revision``)
_REVISIONS: dict[Path, str] = {}


def git_revision(repo: Path | None = None) -> str:
    """Commit hash of the checkout (with '+dirty' when it has changes), or 'unknown', as
    at this process's first call: the code it runs was imported then, and a commit made
    or a report written while it runs (a validation runs for hours) does not change that
    code."""
    repo = (repo or Path(__file__).resolve().parents[1]).resolve()
    if repo not in _REVISIONS:
        _REVISIONS[repo] = _read_revision(repo)
    return _REVISIONS[repo]


def _read_revision(repo: Path) -> str:
    try:
        rev = subprocess.run(["git", "-C", str(repo), "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, timeout=5).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(repo), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=5).stdout.strip()
        return (rev + ("+dirty" if dirty else "")) if rev else "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def _toml_ready(obj):
    """TOML has no null: None is written as "none", which the case reader turns back
    into None (dropping it would let a field whose default is not None, such as
    Khosravi's reading_iterations, come back at its default)."""
    if obj is None:
        return "none"
    if isinstance(obj, dict):
        return {k: _toml_ready(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_toml_ready(v) for v in obj]
    return obj


def config_toml(config) -> str:
    """The resolved case as config.toml holds it (before the notes on where each setting
    came from, which are comments)."""
    return tomli_w.dumps(_toml_ready(to_plain(config)))


def _load_average() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except (OSError, AttributeError):      # not on every platform
        return None


def _numba_threads():
    numba = sys.modules.get("numba")       # a 2D-only run never imports it
    if numba is None:
        return os.environ.get("NUMBA_NUM_THREADS", "default")
    return int(numba.get_num_threads())        # what the run used (a busy machine lowers it)


def _new_folder(parent: Path, stem: str) -> Path:
    """Create and return parent/stem, or parent/stem-2, -3, ... if it exists: two runs
    started in the same second with the same seed (a parameter sweep launched at once)
    must not write into one folder. mkdir is atomic, so concurrent runs cannot collide."""
    parent.mkdir(parents=True, exist_ok=True)
    for k in range(1, 10_000):
        path = parent / (stem if k == 1 else f"{stem}-{k}")
        try:
            path.mkdir()
            return path
        except FileExistsError:
            continue
    raise FileExistsError(f"no free run folder name for {parent / stem}")


#: the start of config.toml's note on what the run used
_USED_HEADER = "# what the run used:"


#: a run's sessions so far, beside its checkpoints: a session stopped after a checkpoint
#: leaves its times there, and the session that resumes the run counts them
SESSIONS = "checkpoints/sessions.json"


def _earlier_sessions(folder: Path) -> list[dict]:
    """The sessions of an interrupted run: those its checkpoints recorded (``SESSIONS``),
    else those of its manifest (or, in a manifest from before sessions were kept, its
    command and times as one session)."""
    for name in (SESSIONS, "manifest.json"):
        path = folder / name
        if not path.is_file():
            continue
        try:
            old = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        if "sessions" in old:
            return list(old["sessions"])
        return [{"command": old.get("command", "?"), "started": old.get("created", "?"), "git": old.get("git", "?"),
                 "wall_time_s": old.get("wall_time_s", 0.0), "cpu_time_s": old.get("cpu_time_s", 0.0)}]
    return []


def _drop_sessions(folder: Path) -> None:
    """Remove ``SESSIONS`` and its folder when nothing else is left in it."""
    path = folder / SESSIONS
    path.unlink(missing_ok=True)
    if path.parent.is_dir() and not any(path.parent.iterdir()):
        path.parent.rmdir()


#: run-folder locks this process holds: lock file -> [descriptor, holds]
_CLAIMS: dict[Path, list] = {}
_CLAIMS_GUARD = threading.Lock()


def lock_file(folder: Path) -> Path:
    """The lock of run folder ``<root>/<study>/<name>``: ``<root>/.locks/<study>/<name>``,
    outside the folder (a folder removed and made again keeps its lock) and out of the
    study's listing. Never removed: a process opening it as another removed it could
    lock a file that a third then makes again."""
    folder = Path(folder).resolve()       # one lock however the path was typed (relative, "..", a link)
    return folder.parent.parent / ".locks" / folder.parent.name / folder.name


def claim(folder: Path) -> Path | None:
    """Take run folder ``folder`` for this process before reading, resuming or removing
    it: an exclusive lock (flock) on ``lock_file(folder)``, which the system lets go when
    the process ends, however it ends. Another process holding it: a one-line refusal
    (two processes on one run would overwrite each other's checkpoints and tables). The
    same process may claim it again (counted). Where no lock can be taken (no fcntl, a
    read-only place, a file system without locks) the run goes on unguarded. Returns the
    key to ``unclaim`` (None: nothing held)."""
    if fcntl is None:
        return None
    key = lock_file(folder)
    with _CLAIMS_GUARD:
        if key in _CLAIMS:
            _CLAIMS[key][1] += 1
            return key
        try:
            key.parent.mkdir(parents=True, exist_ok=True)
            fd = os.open(key, os.O_RDONLY | os.O_CREAT, 0o666)      # flock needs no write access
        except OSError:
            return None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            from analytic.errors import InvalidParameter
            raise InvalidParameter("run folder", str(folder), "a run no other process is running",
                                   "another wallsim process is running it now; let it finish or stop it") from None
        except OSError:
            os.close(fd)
            return None
        _CLAIMS[key] = [fd, 1]
        return key


def unclaim(key: Path | None) -> None:
    """Give back one hold of ``claim``'s ``key``; the last one lets the folder go."""
    if key is None:
        return
    with _CLAIMS_GUARD:
        held = _CLAIMS.get(key)
        if held is None:
            return
        held[1] -= 1
        if held[1] == 0:
            os.close(held[0])
            del _CLAIMS[key]


@contextmanager
def claimed(folder: Path):
    """``claim(folder)`` for the block."""
    key = claim(folder)
    try:
        yield
    finally:
        unclaim(key)


def claimed_unless_finished(folder: Path):
    """``claimed(folder)``, or nothing for a folder that holds a finished run (result.json:
    read, never written again, so a run finished in another process's command is read
    while that command goes on)."""
    return nullcontext() if (Path(folder) / "result.json").is_file() else claimed(folder)


class RunFolder:
    """A run's output folder. Created on construction; every writer returns the path."""

    def __init__(self, case: str, seed: int | None, root: str | Path = "runs", name: str | None = None):
        if name is not None:
            self.path = Path(root) / case / name
            self.path.mkdir(parents=True, exist_ok=True)
        else:
            stem = time.strftime('%Y%m%d-%H%M%S') + (f"-seed{seed}" if seed is not None else "")
            self.path = _new_folder(Path(root) / case, stem)
        self.case = case
        self.seed = seed
        self._start_clocks()
        self._earlier = []          # a new run: whatever a folder of that name held is not its past

    @classmethod
    def existing(cls, path: str | Path, seed: int | None = None) -> "RunFolder":
        """Re-open an existing run folder (to resume an interrupted run); ``seed`` is the
        resumed case's, so the manifest keeps the real one."""
        from analytic.errors import InvalidParameter
        path = Path(path)
        if not (path / "config.toml").exists():
            raise InvalidParameter("--resume", str(path), "a run folder with a config.toml")
        self = cls.__new__(cls)
        self.path = path
        self.case = path.parent.name
        self.seed = seed
        self._start_clocks()
        return self

    def start_clocks(self, wall: float, cpu: float) -> None:
        """Count the run's wall and CPU time from ``wall`` (perf_counter) and ``cpu``
        (process_time): the command's start, before the folder was opened."""
        self._t0, self._cpu0 = wall, cpu

    def _start_clocks(self) -> None:
        self._t0 = time.perf_counter()
        self._cpu0 = time.process_time()
        self.started = time.strftime("%Y-%m-%dT%H:%M:%S%z")
        self.git = git_revision()       # the code this process runs, even if HEAD moves on
        self.load_at_start = _load_average()
        self._earlier = _earlier_sessions(self.path)

    def session(self) -> dict:
        """This session so far: its command, start, git revision, wall and CPU time [s]
        and the process's peak resident memory [MB] (Linux reports ru_maxrss in kB)."""
        import resource
        return {"command": " ".join(sys.argv), "started": self.started, "git": self.git,
                "wall_time_s": round(self.wall_time, 3), "cpu_time_s": round(time.process_time() - self._cpu0, 3),
                "peak_memory_MB": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)}

    def resources(self) -> dict:
        """Wall and CPU time of the whole run [s], every session of a resumed one added
        (each stopped session up to its last checkpoint: what it did after that is done
        again and counted once, by the session that resumed it), the largest peak
        resident memory of a session [MB], and the number of sessions."""
        sessions = self._earlier + [self.session()]
        return {"wall_time_s": round(math.fsum(s["wall_time_s"] for s in sessions), 3),
                "cpu_time_s": round(math.fsum(s["cpu_time_s"] for s in sessions), 3),
                "peak_memory_MB": max(s.get("peak_memory_MB", 0.0) for s in sessions),
                "sessions": len(sessions)}

    def save_checkpoint(self, name: str, blob: bytes) -> Path:
        """Write checkpoint ``name`` (e.g. "checkpoints/shake.npz") and ``checkpointed()``."""
        path = atomic_write(self.file(name), blob)
        self.checkpointed()
        return path

    def checkpointed(self) -> None:
        """Record this session's times so far beside a checkpoint just saved (``SESSIONS``),
        so that a run stopped after it and resumed counts them in its ``resources()``."""
        self.write_json(SESSIONS, {"sessions": self._earlier + [self.session()]})

    def file(self, name: str) -> Path:
        p = self.path / name
        p.parent.mkdir(parents=True, exist_ok=True)
        return p

    def write_config(self, config, sources: dict[str, str] | None = None) -> Path:
        """config.toml: the resolved case, then (as comments, which --config ignores)
        where each setting came from."""
        from .config import sources_comment
        return atomic_write(self.file("config.toml"), (config_toml(config) + sources_comment(sources or {})).encode())

    def note_used(self, used: list[str]) -> None:
        """Add to config.toml's notes what the run used that its settings do not say
        (the particle count reached, the grains it scaled to); the notes already there,
        from the start of the run and of any earlier session, stay."""
        path = self.path / "config.toml"
        if not used or not path.is_file():
            return
        text = path.read_text().split(_USED_HEADER)[0].rstrip("\n") + "\n"
        atomic_write(path, (text + _USED_HEADER + "\n" + "".join(f"#   {u}\n" for u in used)).encode())

    def write_manifest(self, **extra) -> Path:
        """Provenance: package versions, git revision, host, seed, wall time. A resumed
        run keeps every session: ``sessions`` lists each one's command, start, git
        revision and times, and the totals add them up."""
        sessions = self._earlier + [self.session()]
        man = {
            "case": self.case,
            "seed": self.seed,
            "versions": package_versions(),
            "reproducibility": reproducibility.describe(),
            "git": self.git,
            "host": socket.gethostname(),
            "platform": platform.platform(),
            "cpu_count": os.cpu_count(),
            "numba_threads": _numba_threads(),
            # wall times mean little without it: other jobs on the cores slow a run 2-3x
            "load_average_1min": {"start": self.load_at_start, "end": _load_average()},
            "command": sessions[0]["command"],
            "created": sessions[0]["started"],
            "finished": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
            **to_plain(extra),
            "wall_time_s": math.fsum(s["wall_time_s"] for s in sessions),
            "cpu_time_s": math.fsum(s["cpu_time_s"] for s in sessions),
            "sessions": sessions,
        }
        path = self.write_json("manifest.json", man)
        _drop_sessions(self.path)           # the manifest holds them now
        return path

    def write_json(self, name: str, obj) -> Path:
        """JSON with NaN and inf as null (JSON has neither)."""
        return atomic_write(self.file(name), (json.dumps(to_plain(obj), indent=2) + "\n").encode())

    def write_csv(self, name: str, header: list[str], rows) -> Path:
        """Tidy CSV; put units in the header names (e.g. ``sigma_h_kPa``)."""
        buf = io.StringIO(newline="")
        w = csv.writer(buf)
        w.writerow(header)
        for row in rows:
            w.writerow([f"{v:.9g}" if isinstance(v, (float, np.floating)) else v for v in row])
        return atomic_write(self.file(name), buf.getvalue().encode())

    @property
    def wall_time(self) -> float:
        return time.perf_counter() - self._t0
