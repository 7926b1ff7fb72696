"""Progress of a long run is readable in a log file (nohup / batch), once per interval."""

import io

from workflows.progress import _Lines


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
