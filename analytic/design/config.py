"""A design case from the tables of a WALL.toml (already parsed into a dict by the
caller: analytic/ reads no files). Unknown tables or keys are refused, one line each.
Keys and units: see the README's design example (m, kN/m3, kPa, degrees)."""

from __future__ import annotations

from ..errors import InvalidParameter
from .blocks import BlockWall
from .case import DesignCase, Foundation, Loads, Method, Seismic, Water
from .earth import Backfill, FillLayer
from .walls import CantileverWall, GravityWall

WALL_KEYS = {
    "cantilever": {"height", "stem_top", "stem_base", "toe", "heel", "base", "base_thickness", "unit_weight",
                   "back_batter", "key_depth", "key_width", "key_x"},
    "gravity": {"height", "crest", "base", "back_batter", "unit_weight", "polygon"},
    "blocks": {"height", "base", "front_batter", "back_batter", "courses", "joint_slope", "joint_friction",
               "unit_weight", "stair_slope"},
}
TABLES = {"backfill": (Backfill, {"gamma", "phi", "c", "beta", "gamma_sat", "layers"}),
          "foundation": (Foundation, {"gamma", "phi", "c", "base_friction_ratio", "base_friction_angle",
                                      "base_adhesion", "embedment", "cu"}),
          "loads": (Loads, {"surcharge", "surcharge_permanent"}),
          "water": (Water, {"front", "behind"}),
          "method": (Method, {"earth_pressure", "wall_friction", "passive", "passive_mobilisation",
                              "single_source", "thrust_moment"}),
          "seismic": (Seismic, {"alpha", "S", "r", "vertical_ratio", "increment_height", "fill_permeability"})}


def _known(table: str, data, keys: set) -> dict:
    if not isinstance(data, dict):
        raise InvalidParameter(table, str(data), "a TOML table")
    for k in data:
        if k not in keys:
            raise InvalidParameter(f"{table}.{k}", "an unknown key", ", ".join(sorted(keys)))
    return dict(data)


def wall_from_dict(data: dict):
    """CantileverWall, GravityWall or BlockWall from the [wall] table."""
    data = dict(data)
    kind = data.pop("type", "cantilever")
    if kind not in WALL_KEYS:
        raise InvalidParameter("wall.type", kind, "cantilever | gravity | blocks")
    d = _known("wall", data, WALL_KEYS[kind])
    if kind == "gravity":
        if "polygon" in d:
            d["polygon"] = tuple(tuple(p) for p in d["polygon"])
            d.setdefault("height", 0.0)
        return _build(GravityWall, "wall", d)
    if kind == "blocks":
        return _build(BlockWall, "wall", d)
    return _build(CantileverWall, "wall", _cantilever_base(d))


def _cantilever_base(d: dict) -> dict:
    """``base`` may replace ``heel``; both given must agree (the heel must fit)."""
    base = d.pop("base", None)
    if base is None:
        return d
    toe, stem = float(d.get("toe", 0.0)), float(d.get("stem_base", 0.0))
    if base < toe + stem:
        raise InvalidParameter("wall.base", base, f">= toe + stem_base = {toe + stem:g} m",
                               "a base narrower than the stem")
    heel = base - toe - stem
    if "heel" in d and abs(float(d["heel"]) - heel) > 1e-9:
        raise InvalidParameter("wall.heel", d["heel"], f"base - toe - stem_base = {heel:g} m",
                               "the heel does not fit under the base")
    d["heel"] = heel
    return d


def _build(cls, table: str, d: dict):
    """cls(**d), a missing required key reported as one line."""
    import dataclasses
    required = [f.name for f in dataclasses.fields(cls)
                if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    for name in required:
        if name not in d:
            raise InvalidParameter(f"{table}.{name}", "missing", "a value (required key)")
    return cls(**d)


def _layers(rows) -> tuple:
    """``[[backfill.layers]]`` tables (thickness, gamma, phi, c, gamma_sat) from the top."""
    if not isinstance(rows, list):
        raise InvalidParameter("backfill.layers", str(rows), "an array of tables ([[backfill.layers]])")
    keys = {"thickness", "gamma", "phi", "c", "gamma_sat"}
    return tuple(_build(FillLayer, "backfill.layers", _known("backfill.layers", r, keys)) for r in rows)


def case_from_dict(data: dict) -> DesignCase:
    """The whole DesignCase from a parsed WALL.toml."""
    for k in data:
        if k not in TABLES and k != "wall":
            raise InvalidParameter(k, "an unknown table", "wall, " + ", ".join(TABLES))
    if "wall" not in data:
        raise InvalidParameter("wall", "missing", "a [wall] table")
    wall = wall_from_dict(data["wall"])
    made = {}
    for name, (cls, keys) in TABLES.items():
        if name in data:
            d = _known(name, data[name], keys)
            if name == "backfill" and "layers" in d:
                d["layers"] = _layers(d["layers"])
            made[name] = _build(cls, name, d)
    made.setdefault("backfill", None)
    made.setdefault("foundation", None)
    return DesignCase(wall, **made)
