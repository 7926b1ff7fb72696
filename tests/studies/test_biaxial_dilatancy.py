"""The biaxial summary's dilatancy angles on a curve built from their definition:
sin(psi) = -d eps_v / d gamma with gamma = eps_1 - eps_3 and eps_v = eps_1 + eps_3 in 2D
(compression positive; Vermeer & de Borst 1984, Bolton 1986). A volumetric strain that
dilates at a known angle around the stress peak and holds its volume over the last third
must give that angle at the peak and zero there."""

import math

import numpy as np
import pytest

from studies.elements.biaxial import BiaxialCase, BiaxialSample, summarize

PSI_PEAK_DEG = 8.0       # S-OET 4.1's gravel: 8 deg at 35 kPa


def _rate_in_axial_strain(psi_deg: float) -> float:
    """d eps_v / d eps_1 for a dilatancy angle psi: with gamma = 2 eps_1 - eps_v,
    eps_v' = -sin(psi) (2 - eps_v'), so eps_v' = -2 s / (1 - s)."""
    s = math.sin(math.radians(psi_deg))
    return -2.0 * s / (1.0 - s)


def _samples() -> list[BiaxialSample]:
    eps = np.linspace(0.0, 0.2, 801)
    # contracting to 0.02, dilating at PSI_PEAK_DEG from 0.03 to 0.07 (the peak at 0.05),
    # then slowing, at constant volume from 0.12 (critical state over the last third)
    rate = np.interp(eps, [0.0, 0.02, 0.03, 0.07, 0.12, 0.2],
                     [0.5, 0.0, _rate_in_axial_strain(PSI_PEAK_DEG), _rate_in_axial_strain(PSI_PEAK_DEG), 0.0, 0.0])
    ev = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(eps))])
    s3 = 35e3
    ratio = 1.0 + 2.0 * np.exp(-((eps - 0.05) / 0.02) ** 2) + 2.2 * (1 - np.exp(-eps / 0.01))
    return [BiaxialSample("shear", float(k), float(e), float(v), float(s3 * q), s3, 0.1, 0.2, 0.8, 0.0)
            for k, (e, v, q) in enumerate(zip(eps, ev, ratio))]


def test_dilatancy_at_the_peak_and_at_critical_state_follow_the_definition():
    r = summarize(_samples(), [], 100, BiaxialCase(), np.array([0.001]), smooth_strain=0.01)
    assert r.eps_peak == pytest.approx(0.05, abs=0.005)
    assert r.dilatancy_peak_deg == pytest.approx(PSI_PEAK_DEG, abs=1e-6)
    assert r.dilatancy_deg == pytest.approx(0.0, abs=1e-6)


def test_too_few_samples_near_the_peak_give_no_angle():
    s = _samples()[::200]            # five samples, 0.05 apart: none but the peak within 0.01
    r = summarize(s, [], 100, BiaxialCase(), np.array([0.001]), smooth_strain=0.01)
    assert math.isnan(r.dilatancy_peak_deg)
