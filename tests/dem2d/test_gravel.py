"""Elongated gravel grains (dem2d.gravel, issue 24) against numbers from theory / S-OET:

* the grading: widths linear by mass between 10 and 16 mm (S-OET, reference 3.1): the
  Grading's d_min / d_max are the bounds, and a sample's mass median is (10 + 16) / 2;
* a capsule's area and mass: pi w^2/4 + (AR - 1) w^2 against pymunk's own segment area;
* the pair frictions on live contacts: fill-fill tan 45 deg, fill-block tan 25 deg after
  placement (S-OET's local values), tan 15.6 deg while placing;
* statics: a settled fill in a rigid box is carried by the box, vertical reaction =
  weight within 1 % and horizontal reaction ~0 (Newton, issue 24's "carries its weight").
"""

import math

import numpy as np
import pytest
import pymunk

from analytic.errors import InvalidParameter
from dem2d.blocks import BLOCK_TYPE
from dem2d.grading import mass_percentile
from dem2d.gravel import FILL_TYPE, Gravel, GravelBox, capsule_area, set_fill_friction


def test_width_grading_is_linear_by_mass_10_to_16_mm():
    g = Gravel().grading
    assert g.d_min == pytest.approx(0.010, rel=1e-12)
    assert g.d_max == pytest.approx(0.016, rel=1e-12)
    w = g.sample(20000, np.random.default_rng(3))
    # linear passing by mass: median by mass at the mid width, D10 at 10.6 mm
    assert mass_percentile(w, 0.5) == pytest.approx(0.013, rel=0.01)
    assert mass_percentile(w, 0.1) == pytest.approx(0.0106, rel=0.01)


def test_capsule_area_matches_pymunk_segment_area():
    w, ar = 0.012, 2.5
    half = (ar - 1) * w / 2
    assert capsule_area(w, ar) == pytest.approx(pymunk.area_for_segment((-half, 0), (half, 0), w / 2), rel=1e-12)


def test_bad_gravel_names_the_parameter():
    with pytest.raises(InvalidParameter, match="aspect_ratio"):
        Gravel(aspect_ratio=0.5)


def _arbiter_frictions(box):
    seen = {}

    def visit(arb):
        types = tuple(sorted(s.collision_type for s in arb.shapes))
        seen.setdefault(types, set()).add(round(arb.friction, 9))
    for b in box.bodies:
        b.each_arbiter(visit)
    return seen


@pytest.fixture(scope="module")
def box():
    b = GravelBox(Gravel(), 0.30, 0.20, seed=1)
    b.place()
    return b


def test_live_contacts_carry_the_table_frictions(box):
    seen = _arbiter_frictions(box)
    assert seen[(FILL_TYPE, FILL_TYPE)] == {round(math.tan(math.radians(45.0)), 9)}
    assert seen[(FILL_TYPE, BLOCK_TYPE)] == {round(math.tan(math.radians(25.0)), 9)}
    set_fill_friction(box.space, box.gravel, 15.6)
    box.settle(0.001)
    assert _arbiter_frictions(box)[(FILL_TYPE, FILL_TYPE)] == {round(math.tan(math.radians(15.6)), 9)}
    set_fill_friction(box.space, box.gravel)
    box.settle(0.001)


def test_settled_fill_is_carried_by_the_box(box):
    fx, fy = box.box_reaction(0.1)
    w = box.weight()
    assert fy == pytest.approx(w, rel=0.01)
    assert abs(fx) < 0.01 * w


@pytest.mark.parametrize("shape", ["capsule", "clump3", "hexagon"])
def test_grain_shapes_fill_the_AR_envelope_with_their_area_and_inertia(shape):
    """Every shape of the probe spans AR w x w (issue 24: AR 2.5), and its body's mass and
    moment are those of its outline (density x area; sum of r^2 dm), counted here by
    Monte Carlo on pymunk's own point queries (independent of ``grain_area``): within 1 %."""
    from dem2d.gravel import add_grains, grain_area
    g, w = Gravel(shape=shape), 0.013
    space = pymunk.Space()
    body = add_grains(space, [(0.0, 0.0)], [0.0], [w], g, 1.0)[0]
    bbs = [s.cache_bb() for s in body.shapes]
    assert max(b.right for b in bbs) - min(b.left for b in bbs) == pytest.approx(g.aspect_ratio * w, rel=1e-9)
    assert max(b.top for b in bbs) - min(b.bottom for b in bbs) == pytest.approx(w, rel=1e-9)
    rng = np.random.default_rng(0)
    p = rng.uniform([-g.aspect_ratio * w / 2, -w / 2], [g.aspect_ratio * w / 2, w / 2], (40000, 2))
    inside = np.array([any(s.point_query(tuple(q)).distance <= 0 for s in body.shapes) for q in p])
    box = g.aspect_ratio * w * w
    area = inside.mean() * box
    assert float(grain_area(w, g.aspect_ratio, shape)) == pytest.approx(area, rel=0.01)
    assert body.mass == pytest.approx(g.density * area, rel=0.01)
    moment = g.density * box * (p[inside] ** 2).sum() / len(p)
    if shape == "capsule":
        # pymunk's moment_for_segment is that of the L x w rectangle, (L^2 + w^2) / 12 per
        # unit mass: 15 % above the capsule's own at AR 2.5 (kept: the calibration ran on it)
        assert body.moment == pytest.approx(body.mass * (g.aspect_ratio ** 2 + 1) * w * w / 12, rel=1e-9)
        assert body.moment == pytest.approx(1.15 * moment, rel=0.01)
    else:
        assert body.moment == pytest.approx(moment, rel=0.01)


def test_clump_needs_overlapping_circles():
    with pytest.raises(InvalidParameter, match="aspect_ratio"):
        Gravel(shape="clump3", aspect_ratio=3.0)
    with pytest.raises(InvalidParameter, match="shape"):
        Gravel(shape="star")
