"""Progress of a long run is readable in a log file (nohup / batch), once per interval."""

import io
import sys
import time

import pytest

from studies.progress import _Lines


def test_log_file_progress_prints_per_interval_and_once_at_the_end():
    out = io.StringIO()
    lines = _Lines(out, interval=3600.0)        # nothing is due before the hour is up ...
    task = lines.add_task("wall movement T", total=4, status="")
    for _ in range(4):
        lines.update(task, advance=1, status="K 0.21")
    lines.update(task, advance=0)               # ... except the completion, printed once
    text = out.getvalue().splitlines()
    assert len(text) == 1
    assert "wall movement T: 4/4 (100 %)" in text[0] and "K 0.21" in text[0]


def test_busy_machine_note_only_when_threads_exceed_the_idle_cores(monkeypatch):
    """2 numba threads on 2 cores beside a job that keeps a core busy: the run drops to 1
    thread and says so (it used to advise NUMBA_NUM_THREADS=1 and then run on 2); a
    count the user set is kept with a note; nothing on an idle machine or with 1 thread
    (docs/validation/nadukuru.md, "Time": a 2-thread preparation beside one job ran 3.5x
    slower than 1 thread)."""
    import numba

    from studies import progress

    threads = [2]
    monkeypatch.setattr(numba, "get_num_threads", lambda: threads[0])
    monkeypatch.setattr(numba, "set_num_threads", lambda n: threads.__setitem__(0, n))
    monkeypatch.setattr(progress.os, "cpu_count", lambda: 2)
    monkeypatch.delenv("NUMBA_NUM_THREADS", raising=False)
    monkeypatch.setattr(progress, "busy_cores", lambda: 1.0)
    note = progress.busy_machine_note()
    assert note is not None and "this run uses 1 numba thread instead of 2" in note and "1.0 of 2 cores" in note
    assert threads == [1]
    threads[0] = 2
    monkeypatch.setenv("NUMBA_NUM_THREADS", "2")
    note = progress.busy_machine_note()
    assert "NUMBA_NUM_THREADS=2 was asked for" in note and threads == [2]
    monkeypatch.setattr(progress, "busy_cores", lambda: 0.1)
    assert progress.busy_machine_note() is None
    threads[0] = 1
    monkeypatch.setattr(progress, "busy_cores", lambda: 2.0)
    assert progress.busy_machine_note() is None


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="busy_cores reads /proc/stat (Linux only)")
def test_busy_cores_sees_a_spinning_process():
    """One process spinning on a core while we sleep reads as about one busy core (this
    machine has 2; other work can only add to it). A fresh interpreter, not a fork: this
    test process may hold numba threads."""
    import subprocess

    from studies import progress

    idle = progress.busy_cores(0.3)
    spinner = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(0.3)
        loaded = progress.busy_cores(0.5)
    finally:
        spinner.kill()
        spinner.wait()
    assert loaded >= 0.8
    assert loaded >= idle + 0.5 or idle > 1.0     # a busy machine cannot show the difference
