"""Every closed-form and arching method evaluated for one wall: the "theory" half of
each theory-vs-DEM comparison."""

from __future__ import annotations

from dataclasses import dataclass

from .arching import handy, khosravi, paik_salgado
from .classical import coulomb, jaky, janssen, rankine
from .errors import NotApplicable
from .inputs import Soil, Wall
from .profile import Profile
from .seismic import mononobe_okabe, seed_whitman


@dataclass(frozen=True)
class MethodRow:
    """One method's result, or why it does not apply (``profile`` is None)."""

    name: str
    profile: Profile | None
    reason: str = ""


def theory_table(soil: Soil, wall: Wall, *, kh: float = 0.0, kv: float = 0.0,
                 passive: bool = False, width: float | None = None,
                 ps_exponent: str = "iii") -> list[MethodRow]:
    """Evaluate every method for (soil, wall). Methods whose assumptions the geometry
    breaks come back as n/a rows; inputs with no solution (beta > phi, |delta| > phi,
    an inertia angle beyond phi - beta) raise ``InvalidParameter``.

    width: backfill width B [m] for Janssen's slot; defaults to H.
    """
    B = wall.height if width is None else width
    active_only = "active/at-rest theory (drop --passive)"
    plan = [
        ("rankine", lambda: rankine(soil, wall, passive)),
        ("coulomb", lambda: coulomb(soil, wall, passive)),
        ("jaky", (lambda: jaky(soil, wall)) if not passive else active_only),
        ("mononobe-okabe", lambda: mononobe_okabe(soil, wall, kh, kv, passive)),
    ]
    if kh > 0 and not passive:
        plan.append(("seed-whitman", lambda: seed_whitman(soil, wall, kh)))
    for name, fn in (("handy", lambda: handy(soil, wall)),
                     ("paik-salgado", lambda: paik_salgado(soil, wall, ps_exponent)),
                     ("khosravi", lambda: khosravi(soil, wall)),
                     ("janssen", lambda: janssen(soil, wall, B))):
        plan.append((name, fn if not passive else active_only))
    rows = []
    for name, fn in plan:
        if isinstance(fn, str):
            rows.append(MethodRow(name, None, fn))
            continue
        try:
            rows.append(MethodRow(name, fn()))
        except NotApplicable as err:
            rows.append(MethodRow(name, None, err.why or str(err)))
    return rows
