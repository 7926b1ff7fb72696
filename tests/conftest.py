"""Shared fixtures. Reference numbers live in tests/data/*.json, each with its source."""

import contextlib
import json
import os
import signal
import subprocess
from pathlib import Path

import pytest

import reproducibility

DATA = Path(__file__).parent / "data"


def pytest_configure(config):
    """The suite runs in the portable mode (reproducibility.py): the pinned numbers, and
    every chaotic trajectory a physics test reads, are then the same on any x86-64 CPU.
    A pytest started without the mode's settings re-starts itself with them, once (its
    output capture is stopped first, so the new process writes to the terminal).
    WALLSIM_REPRODUCIBILITY=native keeps the native mode; the pin tests then skip."""
    if os.environ.get("PYTEST_XDIST_WORKER"):
        _one_numba_thread()
    if reproducibility.requested_mode() != "portable" or reproducibility.has_portable_settings():
        return
    capture = config.pluginmanager.getplugin("capturemanager")
    if capture is not None:
        capture.stop_global_capturing()
    reproducibility.enter_requested_mode()


def _one_numba_thread() -> None:
    """In a pytest-xdist worker (``make test`` runs two, one per core) numba runs its
    parallel loops on one thread by default: two workers with two threads each would
    wait at every parallel loop for a core. A test that asks for more threads still gets
    them (NUMBA_NUM_THREADS is untouched), e.g. the thread-count determinism checks.
    Setting the count launches numba's threads, which fixes the threading layer for the
    process: dem3d.kernels is imported first so that its OpenMP-first order applies."""
    import numba

    import dem3d.kernels
    dem3d.kernels.prefer_openmp()
    numba.set_num_threads(1)


portable_only = pytest.mark.skipif(
    reproducibility.requested_mode() != "portable",
    reason="pins are recorded in the portable mode; this suite runs native (WALLSIM_REPRODUCIBILITY=native)")


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


@pytest.fixture(scope="session")
def seismic_static_cache(tmp_path_factory):
    """A function ``(case, root) -> Prepared``: the static state of a seismic ``case``,
    prepared once per test run and copied into ``root/seismic/cache`` (the folder that
    ``compare_seismic`` and ``frequency_run`` under ``root`` read), so the tests that
    shake the same small model do not each rain and settle it again (~10 s apiece).
    The run's workers share one cache: under pytest-xdist each worker's base temp
    lies in one folder of this run. The store writes atomically, so two workers that
    prepare the same case at once both write the same state; the seed test compares a
    fresh preparation with the cached one bit for bit."""
    import shutil

    from studies.seismic.run import prepare
    base = tmp_path_factory.getbasetemp()
    shared = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "seismic-static-cache"

    def prepared(case, root=None):
        prep = prepare(case, shared)
        if root is not None:
            shutil.copytree(shared, Path(root) / "seismic" / "cache", dirs_exist_ok=True)
        return prep
    return prepared
