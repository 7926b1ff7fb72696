"""The displacement-field measure of Nadukuru & Michalowski's Fig. 3 text ("all
displacement vectors tend to be parallel" in translation and rotation about the base)
against fields whose answer is known exactly."""

import numpy as np
import pytest

from studies.measures import displacement_parallelism


def test_a_wedge_sliding_along_a_plane_is_parallel_at_its_inclination():
    """Every grain of a wedge moved 10 mm along a plane 55 deg below the horizontal, away
    from the wall (-x), the rest at rest: R = 1 and the inclination is 55 deg."""
    rng = np.random.default_rng(1)
    start = rng.uniform(0.0, 3.0, (2000, 3))
    wedge = start[:, 2] > 1.4 * start[:, 0]
    a = np.radians(55.0)
    end = start.copy()
    end[wedge, 0] -= 0.01 * np.cos(a)
    end[wedge, 2] -= 0.01 * np.sin(a)
    got = displacement_parallelism(start, end)
    assert got["moving_grains"] == int(wedge.sum())
    assert got["resultant_length"] == pytest.approx(1.0, abs=1e-12)
    assert got["spread_deg"] == pytest.approx(0.0, abs=1e-4)
    assert got["inclination_deg"] == pytest.approx(55.0, abs=1e-9)


def test_a_rotation_about_the_centre_of_a_ring_has_no_common_direction():
    """Grains evenly round a ring turned rigidly about its centre move along the tangent:
    their unit vectors sum to nil (R = 0), where a wedge's give 1."""
    t = np.linspace(0.0, 2.0 * np.pi, 360, endpoint=False)
    start = np.column_stack([np.cos(t), np.zeros_like(t), np.sin(t)])
    turn = 0.01
    end = np.column_stack([np.cos(t + turn), np.zeros_like(t), np.sin(t + turn)])
    got = displacement_parallelism(start, end)
    assert got["moving_grains"] == 360
    assert got["resultant_length"] == pytest.approx(0.0, abs=1e-12)


def test_two_directions_either_side_of_a_plane_spread_by_their_half_angle():
    """Half the grains moved 45 deg below the horizontal, half 65: the mean direction is
    55 deg, R = cos 10 deg, and the circular standard deviation sqrt(-2 ln R) (Mardia &
    Jupp eq. 2.3.11) is 10.03 deg, near the half angle."""
    start = np.zeros((400, 3))
    start[:, 0] = np.arange(400.0)
    end = start.copy()
    for k, a in ((slice(0, 200), 45.0), (slice(200, 400), 65.0)):
        end[k, 0] -= 0.01 * np.cos(np.radians(a))
        end[k, 2] -= 0.01 * np.sin(np.radians(a))
    got = displacement_parallelism(start, end)
    r = np.cos(np.radians(10.0))
    assert got["resultant_length"] == pytest.approx(r, rel=1e-12)
    assert got["inclination_deg"] == pytest.approx(55.0, abs=1e-9)
    assert got["spread_deg"] == pytest.approx(np.degrees(np.sqrt(-2.0 * np.log(r))), rel=1e-9)
    assert got["spread_deg"] == pytest.approx(10.03, abs=0.005)
