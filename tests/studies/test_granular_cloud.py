"""The loose cloud every rained specimen starts from (studies.granular.cloud): random
sequential addition of equal spheres jams at a solid fraction of ~0.384 (Torquato, Uche &
Stillinger 2006, Phys. Rev. E 74, 061308), so a box asked to hold them at 0.5 must jam
and the next, looser box be used; at 0.2 they fit."""

import math

import numpy as np
import pytest

from analytic.errors import InvalidParameter
from studies.granular.cloud import loose_cloud

N, D, SIDE = 300, 0.01, 0.1
RSA_JAMMING = 0.384


def box_top(fraction: float) -> np.ndarray:
    """The corner of a SIDE x SIDE base box that holds N spheres at ``fraction``."""
    return np.array([SIDE, SIDE, N * math.pi / 6.0 * D ** 3 / fraction / SIDE ** 2])


def test_a_box_above_the_jamming_fraction_gives_way_to_the_next():
    assert 0.5 > RSA_JAMMING > 0.2
    spec, fraction = loose_cloud(np.random.default_rng(1), (0.0, 0.0, 0.0), box_top, (0.5, 0.2), N, D, D,
                                 density=2650.0)
    assert fraction == 0.2
    x, r = spec.positions, spec.radii
    assert len(r) == N
    assert np.all(x - r[:, None] >= 0.0) and np.all(x + r[:, None] <= box_top(0.2))
    gaps = [np.linalg.norm(x[i] - x[j]) - D for i in range(N) for j in range(i)]   # centre gap - 2 radii
    assert min(gaps) >= 0.0                                  # no two spheres overlap


def test_only_a_box_above_the_jamming_fraction_is_refused_naming_the_parameter():
    with pytest.raises(InvalidParameter) as err:
        loose_cloud(np.random.default_rng(1), (0.0, 0.0, 0.0), box_top, (0.5,), N, D, D, density=2650.0,
                    what=("particles", N))
    assert err.value.name == "particles" and "0.5" in err.value.why
