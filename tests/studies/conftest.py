"""Fixtures of the study-layer tests that run on Dask."""

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def client():
    """A 2-worker LocalCluster whose workers import this checkout (PYTHONPATH), shared by
    the sweep and seeds tests (starting one costs seconds)."""
    from studies.sweep import dask_client
    old = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), old]))
    try:
        with dask_client(workers=2) as c:
            yield c
    finally:
        if old is None:
            os.environ.pop("PYTHONPATH")
        else:
            os.environ["PYTHONPATH"] = old
