"""Progress on stderr for long runs: a live bar on a terminal, a plain line at most every
``interval`` seconds when stderr is a file (nohup, batch jobs), nothing when asked to be quiet."""

from __future__ import annotations

import os
import sys
import time
from contextlib import contextmanager

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


class _Lines:
    """rich.Progress's task interface, written as one line per task every ``interval`` s
    (and when a task completes) so a log file shows where a long run is."""

    def __init__(self, stream=sys.stderr, interval: float = 30.0):
        self.stream, self.interval, self.tasks = stream, interval, {}

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
    dt/dt_crit) on stderr when stderr is a terminal.
    """
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
    """One line for stderr when the numba threads of this run will compete with other
    work (the 1-min load average leaves fewer idle cores than threads), else None.

    Why: numba's TBB layer waits at every parallel loop for a thread that has no core;
    beside one other job a 2-thread specimen preparation ran 3.5x slower than on 1
    thread (docs/validation/nadukuru.md, "Time")."""
    import numba

    threads = int(numba.config.NUMBA_NUM_THREADS)
    cores = os.cpu_count() or 1
    try:
        load = os.getloadavg()[0]
    except (OSError, AttributeError):
        return None
    if threads < 2 or load <= cores - threads + 0.8:
        return None
    return (f"note: the machine is busy (1-min load {load:.1f} on {cores} cores) and this run uses {threads} "
            f"numba threads; beside other jobs NUMBA_NUM_THREADS=1 is usually several times faster")
