"""Case-B fill against a block wall at reduced size (dem2d.backfill): a 0.48 m wall of
0.33 x 0.12 m blocks (4 courses) with a base of 0.8 m, coarse gravel (20-32 mm wide,
AR 2.5), a 0.6 m container, 6 stages of 0.1 m to 0.6 m at the inner face (above the
crest, against the formwork).

References: statics (the fill at rest carries its weight on the container and the wall:
sum of vertical reactions = weight; issue 24 asks for 1 %); Coulomb's active thrust
P = gamma (H_b - y_floor)^2 K / 2 grows with the square of the fill height, so from the
first stage (0.22 m of fill over the floor) to the last (0.72 m) it grows about tenfold
(the test asks for at least twice, the fill's own arching and placement aside); the
rigid-block limit equilibrium of the section (analytic.drystone.backfill_limit_equilibrium
with the reference's fill, 3.1: gamma_s 14.9, phi 37.7, delta 37.7, beta 32) puts its
critical backfill height at 2.48 m, four times the fill it gets here: the wall must
stand.
"""

import math

import pytest

from analytic.drystone import WallSection, backfill_limit_equilibrium
from dem2d.backfill import BackfilledWall, FillPlan
from dem2d.blocks import BlockSolver, Masonry
from dem2d.gravel import Gravel

SECTION = WallSection(0.48, 0.8, 8.53, 0.0, 8.53)
STAGES = 6


@pytest.fixture(scope="module")
def filled():
    g = Gravel(width_min_m=0.02, width_max_m=0.032, friction_deg=72.8, interface_friction_deg=37.7,
               placement_friction_deg=45.0)
    bw = BackfilledWall.build(SECTION, Masonry(friction_deg=25.0, block_length_m=0.33, block_height_m=0.12,
                                               first_course_fixed=False), g,
                              FillPlan(container_m=0.6, formwork_m=0.3), solver=BlockSolver(dt=5e-4, iterations=40),
                              seed=1)
    readings = [bw.stage() for _ in range(STAGES)]
    return bw, readings


def test_fill_carries_its_weight(filled):
    """Container + wall vertical reactions on the fill = its weight, within 1 % (statics)."""
    _, readings = filled
    for r in readings:
        total = r["container_vertical_N_m"] + r["wall_vertical_N_m"]
        assert total == pytest.approx(r["fill_weight_N_m"], rel=0.01), r["backfill_height_m"]


def test_thrust_rises_with_fill_height(filled):
    """Coulomb: P ~ (H_b - y_floor)^2, tenfold from the first stage to the last; at least twice here."""
    bw, readings = filled
    first, last = readings[0], readings[-1]
    coulomb_ratio = ((last["backfill_height_m"] - bw.y_floor) / (first["backfill_height_m"] - bw.y_floor)) ** 2
    assert coulomb_ratio > 9.0
    assert last["thrust_N_m"] > 2.0 * first["thrust_N_m"] > 0.0
    assert last["backfill_height_m"] == pytest.approx(STAGES * 0.1)


def test_wide_wall_does_not_fail(filled):
    """Limit equilibrium: 2.48 m critical height for this section; the DEM wall stands under 0.6 m."""
    bw, readings = filled
    le = backfill_limit_equilibrium(SECTION, 25.0, 20.0, 14.9, 37.7, 37.7, 32.0, course_height_m=0.12)
    assert le.critical_height_m > 4 * readings[-1]["backfill_height_m"]
    assert not bw.failed and not any(r["failed"] for r in readings)
    assert abs(readings[-1]["crest_displacement_m"]) < 0.02 * SECTION.height_m
    assert math.isfinite(readings[-1]["thrust_height_m"])
