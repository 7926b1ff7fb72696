"""Shared fixtures. Reference numbers live in tests/data/*.json, each with its source."""

import contextlib
import json
import os
import signal
import subprocess
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"


def load_reference(name: str) -> dict:
    return json.loads((DATA / name).read_text())


@pytest.fixture(scope="session")
def published():
    return load_reference("analytic_published.json")


def _default_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@contextlib.contextmanager
def interruptible(args: list, **kwargs):
    """``subprocess.Popen(args, **kwargs)`` for a command a test will interrupt. SIGINT is
    put back to its default in the child: a shell that starts the tests in the background
    ignores SIGINT, the child inherits that, Python then installs no KeyboardInterrupt
    handler and the run goes on. On the way out the child (its whole session when
    ``start_new_session``) is killed if still running, so a failed test leaves no run behind."""
    proc = subprocess.Popen(args, preexec_fn=_default_sigint, **kwargs)
    try:
        yield proc
    finally:
        if proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                if kwargs.get("start_new_session"):
                    os.killpg(proc.pid, signal.SIGKILL)
                else:
                    proc.kill()
            proc.wait()
