"""Progress on stderr for long runs: a live bar on a terminal, a plain line at most every
``interval`` seconds when stderr is a file (nohup, batch jobs), nothing when asked to be quiet."""

from __future__ import annotations

import os
import sys
import time
from contextlib import contextmanager
from contextvars import ContextVar

from rich.console import Console
from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TextColumn,
                           TimeElapsedColumn, TimeRemainingColumn)


class _Silent:
    def add_task(self, *a, **k):
        return 0

    def update(self, *a, **k):
        pass

    def advance(self, *a, **k):
        pass

    def log(self, *a, **k):
        pass


#: where the progress of the run in this thread goes instead of stderr (``logging_to``):
#: a sweep point's run.log
_log: ContextVar = ContextVar("wallsim_progress_log", default=None)


@contextmanager
def logging_to(stream, interval: float = 30.0):
    """Within this block (this thread) ``progress`` writes timestamped lines to ``stream``
    (at most every ``interval`` s per task) whether or not the run was asked to be quiet,
    and ``log_stream`` is ``stream``: a sweep point keeps its progress in its own log,
    not on the worker's stderr."""
    token = _log.set((stream, interval))
    try:
        yield stream
    finally:
        _log.reset(token)


def log_stream():
    """Where a run's messages go: the point's log inside ``logging_to``, else stderr."""
    return _log.get()[0] if _log.get() is not None else sys.stderr


class _Lines:
    """rich.Progress's task interface, written as one line per task every ``interval`` s
    (and when a task completes) so a log file shows where a long run is."""

    def __init__(self, stream=None, interval: float = 30.0):
        self.stream, self.interval, self.tasks = stream or sys.stderr, interval, {}

    def add_task(self, description, total=None, completed=0, **fields):
        tid = len(self.tasks)
        self.tasks[tid] = {"description": description, "total": total, "completed": completed,
                           "status": fields.get("status", ""), "start": time.monotonic(), "printed": time.monotonic()}
        return tid

    def update(self, task_id, *, advance=None, **fields):
        t = self.tasks[task_id]
        if advance is not None:
            t["completed"] += advance
        for key in ("description", "total", "completed", "status"):
            if key in fields:
                t[key] = fields[key]
        self._maybe_print(t)

    def advance(self, task_id, advance=1):
        self.update(task_id, advance=advance)

    def log(self, *a, **k):
        print(*a, file=self.stream, flush=True)

    def _maybe_print(self, t):
        now = time.monotonic()
        done = t["total"] is not None and t["completed"] >= t["total"]
        if t.get("finished") or (now - t["printed"] < self.interval and not done):
            return
        t["printed"], t["finished"] = now, done     # a finished task prints once
        of = f"/{t['total']:.0f} ({100 * t['completed'] / t['total']:.0f} %)" if t["total"] else ""
        print(f"[{time.strftime('%H:%M:%S')}] {t['description']}: {t['completed']:.0f}{of}, "
              f"{now - t['start']:.0f} s {t['status']}".rstrip(), file=self.stream, flush=True)


@contextmanager
def progress(quiet: bool = False):
    """Yield an object with rich.Progress's ``add_task``/``update``/``advance``.

    Shows step, stage and a free-text status field (e.g. unbalanced-force ratio,
    dt/dt_crit) on stderr when stderr is a terminal; inside ``logging_to`` plain lines
    in that log instead (``quiet`` or not).
    """
    if _log.get() is not None:
        yield _Lines(*_log.get())
        return
    if quiet:
        yield _Silent()
        return
    if not sys.stderr.isatty():
        yield _Lines()
        return
    cols = (TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
            TimeElapsedColumn(), TimeRemainingColumn(), TextColumn("{task.fields[status]}"))
    with Progress(*cols, console=Console(stderr=True), transient=False) as bar:
        yield bar


def busy_machine_note() -> str | None:
    """One line for stderr when the numba threads of this run would compete with other
    work (fewer idle cores than threads, measured over 0.3 s while this process sleeps),
    else None. When the thread count is numba's default (NUMBA_NUM_THREADS not set) the
    run is put on one thread, and the line says so; a count the user set is kept, and
    the line says what it costs. The bits do not depend on the thread count. The 1-min
    load average is not used: it still reads ~1 for a minute after the previous job.

    Why: numba's TBB layer waits at every parallel loop for a thread that has no core;
    beside one other job a 2-thread specimen preparation ran 3.5x slower than on 1
    thread (docs/validation/nadukuru.md, "Time")."""
    import numba

    threads = int(numba.get_num_threads())
    cores = os.cpu_count() or 1
    if threads < 2:
        return None
    busy = busy_cores()
    if busy is None or cores - busy >= threads - 0.5:
        return None
    if "NUMBA_NUM_THREADS" not in os.environ:
        numba.set_num_threads(1)
        return (f"note: the machine is busy ({busy:.1f} of {cores} cores in use by other work): this run uses 1 "
                f"numba thread instead of {threads} (beside other jobs that is usually several times faster; the "
                f"numbers are the same); NUMBA_NUM_THREADS={threads} keeps {threads}")
    return (f"note: the machine is busy ({busy:.1f} of {cores} cores in use by other work) and NUMBA_NUM_THREADS="
            f"{threads} was asked for: beside other jobs 1 thread is usually several times faster")


def busy_cores(interval: float = 0.3) -> float | None:
    """Cores kept busy by other processes over ``interval`` seconds while this one sleeps
    (Linux /proc/stat; None elsewhere)."""
    def snapshot():
        with open("/proc/stat") as fh:
            ticks = [int(x) for x in fh.readline().split()[1:]]
        return sum(ticks), ticks[3] + ticks[4]          # all, idle + iowait

    try:
        total0, idle0 = snapshot()
        time.sleep(interval)
        total1, idle1 = snapshot()
    except (OSError, ValueError, IndexError):
        return None
    if total1 <= total0:
        return None
    return (1.0 - (idle1 - idle0) / (total1 - total0)) * (os.cpu_count() or 1)


def step_with_progress(sim, n_steps: int, progress=None, label: str = "", chunk: int = 1000) -> int:
    """Advance a dem3d ``sim`` by ``n_steps`` in chunks, showing a bar named ``label`` on
    ``progress`` (none without a label). Returns the steps taken."""
    task = progress.add_task(label, total=n_steps, status="") if progress is not None and label else None
    done = 0
    while done < n_steps:
        k = min(chunk, n_steps - done)
        sim.step(k)
        done += k
        if task is not None:
            progress.update(task, advance=k, status=f"t = {sim.time:.2f} s")
    return done
