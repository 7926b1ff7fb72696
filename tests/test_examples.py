"""The examples double as regression tests (scikit-fem style): each runs as a user
would run it and one number is pinned. The DEM pins are those of the same cases run
through the CLI (tests/data/pinned_studies.json, recorded in the portable mode); the
theory pin is the closed form."""

import importlib.util
import json
import math
from pathlib import Path

import pytest

from tests.conftest import portable_only

ROOT = Path(__file__).resolve().parents[1]
PINS = json.loads((ROOT / "tests" / "data" / "pinned_studies.json").read_text())


def _example(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "examples" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_theory_table_example():
    rows = {r.name: r.profile for r in _example("theory_table").run()}
    # Rankine, vertical wall, level fill: Ka = tan^2(45 - phi/2) at phi = 34 deg
    assert rows["rankine"].K == pytest.approx(math.tan(math.radians(45 - 17)) ** 2, rel=1e-12)


@portable_only
@pytest.mark.slow
def test_nadukuru_example_gives_the_pinned_K(tmp_path):
    r = _example("nadukuru_translation").run(out=tmp_path)
    assert r["dem"]["K"] == PINS["nadukuru"]["values"]["dem"]["K"]


@portable_only
@pytest.mark.slow
def test_khosravi_example_gives_the_pinned_K_at_rest(tmp_path):
    r = _example("khosravi_small_box").run(out=tmp_path)
    pin = PINS["khosravi"]["values"]       # the same case as `compare khosravi` pinned there
    assert r["particles"] == pin["particles"]
    assert r["dem"]["K_at_rest_upper_half"] == pin["dem"]["K_at_rest_upper_half"]
