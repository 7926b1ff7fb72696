"""Time-step refusal and blow-up detection."""

import math

import numpy as np
import pytest

from analytic.errors import InvalidParameter
from dem3d import DT_SAFETY, BlowUp, Simulation, linear

from conftest import single_specimen, sphere_mass


def lattice(n_side=4, r=0.01, overlap=0.02):
    """Simple cubic lattice of spheres pressed together by ``overlap`` (fraction of 2r)."""
    a = 2 * r * (1 - overlap)
    g = np.arange(n_side) * a
    x = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    return single_specimen(x, r)


def test_dt_above_safety_fraction_is_refused_in_one_line():
    """The critical step is sqrt(m_min / k_max) (PFC3D manual); dt above DT_SAFETY times it
    is refused with a one-line InvalidParameter naming dt and the allowed range."""
    spec = lattice()
    kn = 1e5
    crit = math.sqrt(sphere_mass(0.01, 2650.0) / kn)
    with pytest.raises(InvalidParameter) as err:
        Simulation(spec, linear(kn, 0.4 * kn, 0.5), dt=1.01 * DT_SAFETY * crit, gravity=(0, 0, 0))
    msg = str(err.value)
    assert "\n" not in msg
    assert msg.startswith("dt = ")
    assert f"{DT_SAFETY * crit:.4g}" in msg
    # at the limit it is accepted
    Simulation(spec, linear(kn, 0.4 * kn, 0.5), dt=0.99 * DT_SAFETY * crit, gravity=(0, 0, 0))


def test_unsafe_dt_with_override_blows_up_with_a_clear_message():
    """Leapfrog is unstable for omega dt > 2; two pressed spheres have omega = sqrt(2 kn / m),
    so dt = 3 sqrt(m / kn) (omega dt = 4.2) must diverge and be stopped."""
    spec = lattice()
    kn = 1e5
    crit = math.sqrt(sphere_mass(0.01, 2650.0) / kn)
    sim = Simulation(spec, linear(kn, 0.4 * kn, 0.5), dt=3.0 * crit, gravity=(0, 0, 0),
                     allow_unsafe_dt=True)
    with pytest.raises(BlowUp) as err:
        sim.step(2000)
    msg = str(err.value)
    assert "\n" not in msg
    assert "blew up at step" in msg
    assert err.value.step < 2000
