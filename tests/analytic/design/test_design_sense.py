"""Wall files that make no sense are refused before anything is computed (issue 40),
each in one line that names the key and its valid range."""

import tomllib
from pathlib import Path

import pytest

from analytic.design.config import case_from_dict
from analytic.errors import InvalidParameter

ROOT = Path(__file__).resolve().parents[3]


def cantilever(**tables) -> dict:
    d = tomllib.loads((ROOT / "docs" / "examples" / "cantilever.toml").read_text())
    for table, values in tables.items():
        d.setdefault(table, {}).update(values)
    return d


def refused(d: dict) -> str:
    with pytest.raises(InvalidParameter) as err:
        case_from_dict(d)
    return str(err.value)


def test_the_example_wall_is_accepted():
    assert case_from_dict(cantilever()).wall.B == pytest.approx(4.7)


def test_a_base_in_millimetres_or_out_of_proportion_is_refused():
    """heel = 3000 made B = 3001.7 m beside a 6 m wall and ran: now past any wall
    dimension (100 m); a 70 m heel is within that but 12 x the wall's height."""
    assert refused(cantilever(wall={"heel": 3000.0})).startswith("wall.heel = 3000 is outside the valid range [0, 100] m")
    msg = refused(cantilever(wall={"heel": 70.0}))
    assert msg.startswith("wall base width B") and "60 m" in msg and "mm" in msg


def test_fill_layers_thicker_than_the_retained_height_are_refused():
    """The layers were cut at H in silence; the [backfill] soil fills what is below them."""
    layers = [{"thickness": 4.0, "gamma": 18, "phi": 30}, {"thickness": 3.0, "gamma": 19, "phi": 34}]
    msg = refused(cantilever(backfill={"layers": layers}))
    assert msg.startswith("backfill.layers") and "7 m in all" in msg and "6 m" in msg
    assert case_from_dict(cantilever(backfill={"layers": layers[:1]})).backfill.layers[0].thickness == 4.0


def test_water_above_the_wall_and_an_embedment_as_deep_as_it_are_refused():
    assert refused(cantilever(water={"behind": 6.5})).startswith("water.behind")
    assert refused(cantilever(water={"front": 7.0})).startswith("water.front")
    assert refused(cantilever(foundation={"embedment": 6.0})).startswith("foundation.embedment")


def test_a_gravity_polygon_and_a_height_must_agree():
    """A polygon 1 m tall beside height = 5: the height was ignored in silence."""
    wall = {"type": "gravity", "polygon": [[0, 0], [2, 0], [1.5, 1.0], [0.5, 1.0]], "unit_weight": 23}
    d = cantilever()
    d["wall"] = dict(wall, height=5.0)
    msg = refused(d)
    assert msg.startswith("wall.height") and "the polygon's top, 1 m" in msg
    d["wall"] = dict(wall, height=1.0)
    assert case_from_dict(d).wall.H == 1.0
    d["wall"] = dict(wall, crest=0.5)
    assert refused(d).startswith("wall.crest")
