"""Grading: the linear-by-mass curve reproduces Khosravi et al.'s Table 1 (D50 = 1.16 mm,
Cu = 1.55), in closed form and in a sample."""

import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

from analytic.errors import InvalidParameter
from dem2d.grading import Grading, mass_percentile, measured_d50_cu

REF = json.loads(Path(importlib.util.find_spec("studies.khosravi").submodule_search_locations[0], "reference.json").read_text())


def test_curve_passes_through_the_papers_d50_and_cu():
    # reference: Table 1 of Khosravi et al. (studies/khosravi/reference.json)
    d50, cu = REF["material"]["d50_m"], REF["material"]["cu"]
    g = Grading(d50, cu)
    w = g.d_max - g.d_min
    assert (g.d_min + g.d_max) / 2 == pytest.approx(d50, rel=1e-12)
    assert (g.d_min + 0.6 * w) / (g.d_min + 0.1 * w) == pytest.approx(cu, rel=1e-12)
    # hand calculation in the module docstring: 0.717 mm and 1.603 mm
    assert g.d_min == pytest.approx(0.717e-3, abs=1e-6)
    assert g.d_max == pytest.approx(1.603e-3, abs=1e-6)


def test_sample_has_the_papers_d50_and_cu():
    g = Grading(1.16e-3, 1.55)
    d = g.sample(200_000, np.random.default_rng(3))
    d50, cu = measured_d50_cu(d)
    assert d50 == pytest.approx(1.16e-3, rel=0.01)
    assert cu == pytest.approx(1.55, rel=0.01)
    assert d.min() >= g.d_min and d.max() <= g.d_max


def test_mean_area_matches_the_sample():
    # E[pi d^2 / 4] under n(d) ~ d^-2 is pi d_min d_max / 4 (exact): checks the sampler
    g = Grading(1.16e-3, 1.55)
    d = g.sample(400_000, np.random.default_rng(4))
    assert np.mean(math.pi * d**2 / 4) == pytest.approx(g.mean_area(), rel=0.005)


def test_scaling_keeps_cu_and_multiplies_sizes():
    g = Grading(1.16e-3, 1.55).scaled(2.0)
    assert g.d50 == pytest.approx(2.32e-3)
    assert g.d_max / g.d_min == pytest.approx(Grading(1.16e-3, 1.55).d_max / Grading(1.16e-3, 1.55).d_min)


def test_single_size_and_mass_percentile():
    g = Grading(1e-3, 1.0)
    d = g.sample(10, np.random.default_rng(0))
    assert np.all(d == 1e-3)
    assert mass_percentile(np.array([1.0, 1.0, 1.0]), 0.5) == pytest.approx(1.0)


@pytest.mark.parametrize("d50, cu", [(0.0, 1.5), (-1e-3, 1.5), (1e-3, 0.9), (1e-3, 6.0)])
def test_bad_grading_is_refused(d50, cu):
    with pytest.raises(InvalidParameter):
        Grading(d50, cu)
