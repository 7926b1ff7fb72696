"""Shared fixtures. Reference numbers live in tests/data/*.json, each with its source."""

import json
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"


def load_reference(name: str) -> dict:
    return json.loads((DATA / name).read_text())


@pytest.fixture(scope="session")
def published():
    return load_reference("analytic_published.json")
