"""Progress on stderr for long runs; silent when not a terminal or when asked to be quiet."""

from __future__ import annotations

import sys
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


@contextmanager
def progress(quiet: bool = False):
    """Yield an object with rich.Progress's ``add_task``/``update``/``advance``.

    Shows step, stage and a free-text status field (e.g. unbalanced-force ratio,
    dt/dt_crit) on stderr when stderr is a terminal.
    """
    if quiet or not sys.stderr.isatty():
        yield _Silent()
        return
    cols = (TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
            TimeElapsedColumn(), TimeRemainingColumn(), TextColumn("{task.fields[status]}"))
    with Progress(*cols, console=Console(stderr=True), transient=False) as bar:
        yield bar
