"""Partial-factor sets and design combinations, read from a replaceable data file.

``load_factors()`` is the one place in ``analytic/`` that reads a file: the package's own
``factors/ec7.toml`` (EN 1997-1 Annex A recommended values). A national annex's table is
a dict of the same shape, read by the caller and passed to ``Factors.from_dict``.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from importlib import resources

from ..errors import InvalidParameter


@dataclass(frozen=True)
class Combination:
    """One set of partial factors: actions (geotechnical and structural), materials and
    resistances, as dicts of factor name -> value (see factors/ec7.toml)."""

    name: str
    actions: dict
    structural_actions: dict
    materials: dict
    resistances: dict


@dataclass(frozen=True)
class Factors:
    """All combinations, the formats (lists of combination names) and the classical
    factors of safety."""

    combinations: dict
    formats: dict
    fs: dict

    @classmethod
    def from_dict(cls, data: dict) -> "Factors":
        """Build from the data-file layout; a missing set or factor is one-line error."""
        try:
            combos = {}
            for name, c in data["combinations"].items():
                combos[name] = Combination(
                    name, _set(data, "actions", c["actions"]),
                    _set(data, "actions", c.get("structural_actions", c["actions"])),
                    _set(data, "materials", c["materials"]), _set(data, "resistances", c["resistances"]))
            formats = {k: list(v) for k, v in data["formats"].items()}
            fs = dict(data["factors_of_safety"])
        except KeyError as err:
            raise InvalidParameter("factors", str(err), "a table with actions, materials, resistances, "
                                   "combinations, formats and factors_of_safety (see factors/ec7.toml)") from None
        for f, names in formats.items():
            for n in names:
                if n not in combos:
                    raise InvalidParameter(f"factors.formats.{f}", n, ", ".join(combos))
        return cls(combos, formats, fs)

    def format(self, name: str) -> list[Combination]:
        """The combinations a verification format checks (e.g. DA1 -> DA1-1, DA1-2)."""
        if name not in self.formats:
            raise InvalidParameter("format", name, " | ".join(self.formats))
        return [self.combinations[n] for n in self.formats[name]]


_KEYS = {"actions": ("G_unfav", "G_fav", "Q_unfav", "Q_fav"), "materials": ("phi", "c", "cu", "gamma"),
         "resistances": ("bearing", "sliding", "passive")}


def _set(data: dict, group: str, name: str) -> dict:
    values = data[group][name]
    out = {}
    for k in _KEYS[group]:
        v = values[k]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v < 0:
            raise InvalidParameter(f"factors.{group}.{name}.{k}", v, ">= 0")
        if group != "actions" and v <= 0:
            raise InvalidParameter(f"factors.{group}.{name}.{k}", v, "> 0")
        out[k] = float(v)
    return out


def load_factors() -> Factors:
    """The package's own EN 1997-1 Annex A table (analytic/design/factors/ec7.toml)."""
    text = resources.files("analytic.design").joinpath("factors/ec7.toml").read_text()
    return Factors.from_dict(tomllib.loads(text))
