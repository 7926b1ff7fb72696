"""``wallsim calibrate wall``: the phi card of the wall backfill. One triaxial test
(``studies.triaxial.lab.calibrate_triaxial``, the test of ``wallsim calibrate
triaxial``) per point of the card's path (``card.PATH``), each keeping its own
calibration card; a point whose card exists for the same size, seed and set-up is
reused, so an interrupted calibration goes on where it stopped. The points are collated
into ``phi_card.json`` in the run folder (``card.collate``); the shipped card is one
such file copied into the package."""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field
from pathlib import Path

from analytic.schema import check_fields, param, seed_param

from ..elements.triaxial import TriaxialSetup
from ..granular.recipe import SpecimenRecipe
from ..store import atomic_write
from .card import PATH, collate


@dataclass(frozen=True)
class CardCase:
    """The card's tests: spheres per test, the triaxial set-up, the seed."""

    particles: int = param(8200, lo=50, hi=1_000_000, meaning="spheres per triaxial test (the Nadukuru "
                                                              "triaxial's 8,200)")
    setup: TriaxialSetup = field(default_factory=TriaxialSetup)
    seed: int = seed_param(1)

    def __post_init__(self):
        check_fields(self)


def point_recipe(particles: int, friction: float, rolling: float) -> SpecimenRecipe:
    """The wall backfill's recipe at one point of the path."""
    return dataclasses.replace(SpecimenRecipe(), particles=particles, particle_friction=friction,
                               rolling_friction=rolling)


def make_card(case: CardCase, *, root: Path, progress=None) -> tuple[dict, Path, Path]:
    """Run (or reuse) the triaxial test at each point of the path and collate the card.
    Returns (card, its path, the run folder)."""
    from ..runner import finish, open_run_folder
    from ..triaxial.lab import TriaxialCase, calibrate_triaxial, card_path

    folder = open_run_folder("wall", case, root, name=None)
    cards = []
    for friction, rolling in PATH:
        rec = point_recipe(case.particles, friction, rolling)
        existing = _reusable(card_path(root, rec, case.seed), case)
        if existing is None:
            existing, _ = calibrate_triaxial(TriaxialCase(specimen=rec, setup=case.setup, seed=case.seed),
                                             case.setup, particles=case.particles, root=root, progress=progress)
        cards.append(existing)
    card = collate(cards)
    path = atomic_write(folder.file("phi_card.json"), json.dumps(card, indent=1).encode())
    finish(folder, card | {"card": str(path)}, particles=case.particles, seed=case.seed)
    return card, path, folder.path


def _reusable(path: Path, case: CardCase) -> dict | None:
    """The calibration card at ``path`` if it was made at this size, seed and set-up."""
    if not path.is_file():
        return None
    card = json.loads(path.read_text())
    same = (card.get("seed") == case.seed and card.get("confining_kPa") == case.setup.confining / 1e3
            and card.get("strain_rate_per_s") == case.setup.strain_rate
            and card.get("recipe", {}).get("particles") == case.particles)
    return card if same else None
