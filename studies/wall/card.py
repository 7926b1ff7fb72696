"""The phi card: the peak friction angle the triaxial test (``studies.elements.triaxial``)
gives the wall backfill's recipe along one path of micro parameters, and its inverse.

The path raises the grain friction from 0.1 to the paper's 0.65 (rolling resistance off),
then the rolling resistance at friction 0.65, since friction alone levels off near the
mixture's 37 deg. ``match_phi`` interpolates the path linearly in phi between the two
card points that bracket the requested angle; the card's points come from ``wallsim
calibrate triaxial`` runs of the recipe (``collate``), which ``wallsim calibrate wall``
makes and the shipped ``phi_card.json`` holds.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from analytic.errors import InvalidParameter

#: the card shipped with wallsim (package data)
SHIPPED_CARD = Path(__file__).with_name("phi_card.json")

#: (grain friction, rolling resistance) along the path, in its order
#: (at 3,000 spheres friction 0 / 0.1 / 0.2 / 0.35 / 0.65 gave 8.4 / 19.3 / 25.5 / 31.1 / 36.4 deg,
#: rolling 0.05 at 0.65 38.7 deg: the path starts at 0.1 and is densest where phi turns)
PATH = ((0.1, 0.0), (0.15, 0.0), (0.2, 0.0), (0.3, 0.0), (0.45, 0.0), (0.65, 0.0),
        (0.65, 0.05), (0.65, 0.1), (0.65, 0.2), (0.65, 0.3))

#: micro parameters are rounded to this many decimals (a card point is matched exactly)
DECIMALS = 3


@dataclass(frozen=True)
class CardMatch:
    """The micro parameters for a requested phi [deg] (linear between the two card
    points that bracket it: (friction, rolling, phi) each), and the card."""

    phi_requested_deg: float
    particle_friction: float
    rolling_friction: float
    bracket: tuple
    source: str

    def as_dict(self) -> dict:
        return {"phi_requested_deg": self.phi_requested_deg, "particle_friction": self.particle_friction,
                "rolling_friction": self.rolling_friction,
                "bracket": [list(b) for b in self.bracket], "card": self.source}


def load_card(path: str | None = None) -> dict:
    """A phi card (JSON from ``collate``); ``None``: the shipped one."""
    p = Path(path) if path is not None else SHIPPED_CARD
    try:
        card = json.loads(p.read_text())
    except (OSError, ValueError) as err:
        raise InvalidParameter("phi_card", str(p), "a phi card from `wallsim calibrate wall`",
                               type(err).__name__) from None
    if not isinstance(card, dict) or not card.get("points"):
        raise InvalidParameter("phi_card", str(p), "a phi card from `wallsim calibrate wall`", "no points")
    return card


def match_phi(phi_deg: float, card: dict, source: str | None = None) -> CardMatch:
    """Grain friction and rolling resistance whose triaxial peak phi is ``phi_deg``:
    linear along the path between the card points that bracket it (``points`` in path
    order, phi rising). Outside the card's range: one line with the range."""
    pts = card["points"]
    phis = [p["phi_peak_deg"] for p in pts]
    lo, hi = phis[0], phis[-1]
    if not lo <= phi_deg <= hi:
        raise InvalidParameter("backfill.phi", phi_deg, f"[{lo:.1f}, {hi:.1f}] deg",
                               "the angles the DEM backfill's phi card spans")
    k = next(i for i in range(1, len(pts)) if phis[i] >= phi_deg)
    a, b = pts[k - 1], pts[k]
    t = (phi_deg - phis[k - 1]) / (phis[k] - phis[k - 1])

    def between(key: str) -> float:
        return round(a[key] + t * (b[key] - a[key]), DECIMALS)

    return CardMatch(phi_deg, between("particle_friction"), between("rolling_friction"),
                     ((a["particle_friction"], a["rolling_friction"], a["phi_peak_deg"]),
                      (b["particle_friction"], b["rolling_friction"], b["phi_peak_deg"])),
                     source or "shipped phi card (studies/wall/phi_card.json)")


def collate(cards: list[dict]) -> dict:
    """The phi card from triaxial calibration cards (``studies.triaxial.lab``) of one
    recipe that differ only in grain friction and rolling resistance: their points in
    path order, checked to rise in phi (a card whose phi falls along the path cannot be
    inverted: the seed scatter is larger than the step, and the step must grow)."""
    if not cards:
        raise InvalidParameter("cards", 0, "triaxial cards of the recipe at the path's points")
    varied = ("particle_friction", "rolling_friction")
    common = {k: v for k, v in cards[0]["recipe"].items() if k not in varied + ("particles",)}
    for c in cards:
        other = {k: v for k, v in c["recipe"].items() if k not in varied + ("particles",)}
        if other != common:
            raise InvalidParameter("cards", c.get("card", "?"), "cards of one recipe",
                                   "they differ in more than the grain friction and rolling resistance")
    order = {p: i for i, p in enumerate(PATH)}
    points = []
    for c in cards:
        key = (c["recipe"]["particle_friction"], c["recipe"].get("rolling_friction", 0.0))
        if key not in order:
            continue
        points.append({"particle_friction": key[0], "rolling_friction": key[1],
                       "phi_peak_deg": c["phi_peak_deg"], "phi_end_deg": c["phi_end_deg"],
                       "strain_at_peak": c["strain_at_peak"], "porosity": c["porosity"],
                       "particles": c["particles"], "seed": c["seed"], "wall_time_s": c["wall_time_s"]})
    points.sort(key=lambda p: order[(p["particle_friction"], p["rolling_friction"])])
    for a, b in zip(points, points[1:]):
        if not b["phi_peak_deg"] > a["phi_peak_deg"]:
            raise InvalidParameter("cards", f"phi {b['phi_peak_deg']:.2f} after {a['phi_peak_deg']:.2f}",
                                   "phi rising along the path",
                                   f"at friction {b['particle_friction']}, rolling {b['rolling_friction']}")
    first = cards[0]
    return {"test": first["test"], "confining_kPa": first["confining_kPa"],
            "strain_rate_per_s": first["strain_rate_per_s"], "recipe": common | {"particles": first["particles"]},
            "path": "grain friction 0.1 -> 0.65 (rolling 0), then rolling resistance at friction 0.65",
            "points": points, "versions": first.get("versions"), "reproducibility": first.get("reproducibility")}
