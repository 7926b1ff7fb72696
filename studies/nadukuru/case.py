"""Nadukuru & Michalowski (2012): the case. The backfill recipe (``studies.granular``:
grains, contacts, raining), the 3.1 m wall of 6 segments and its movement, the seed
(``NadukuruCase``), and the paper's values (``paper_values``)."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

from analytic.errors import InvalidParameter
from analytic.schema import check_fields, seed_param

from ..granular.recipe import SpecimenRecipe
from ..granular.wall import Movement, WallSetup, check_backfill_case, most_steps


@dataclass(frozen=True)
class NadukuruCase:
    """One wall-movement run: the backfill recipe, the wall and box, the movement, the seed."""

    specimen: SpecimenRecipe = field(default_factory=SpecimenRecipe)
    wall: WallSetup = field(default_factory=WallSetup)
    movement: Movement = field(default_factory=Movement)
    seed: int = seed_param(1)

    def __post_init__(self):
        check_fields(self)
        check_backfill_case(self)

    def most_steps(self) -> tuple[float, float, float]:
        """(time steps of the preparation at most, of the movement, the time step [s])."""
        return most_steps(self)


def rough_or_smooth(wall: str) -> float:
    if wall == "rough":
        return 0.35
    if wall == "smooth":
        return 0.0
    raise InvalidParameter("wall", wall, "rough | smooth")


#: Tables 1-3 and the specimen description, with their source (shipped with the package)
REFERENCE = json.loads((Path(__file__).parent / "reference.json").read_text())


def paper_values(mode: str, wall: str) -> dict:
    """The paper's DEM (Tables 1-2) and Fang & Ishibashi (Table 1) for a mode and wall."""
    row = REFERENCE.get(wall, {}).get(mode, {})
    out = {"K": row.get("K"), "resultant_height_over_H": row.get("resultant_height_over_H"),
           "source": f"Nadukuru & Michalowski (2012) Table {'1' if wall == 'rough' else '2'}"}
    if "FI_K" in row:
        out["fang_ishibashi"] = {"K": row["FI_K"], "resultant_height_over_H": row["FI_resultant_height_over_H"],
                                 "source": "Fang & Ishibashi (1986), interpolated to phi = 39 deg (Table 1)"}
    return out
