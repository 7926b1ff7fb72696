"""Every closed-form and arching method evaluated for one wall: the "theory" half of
each theory-vs-DEM comparison."""

from __future__ import annotations

from dataclasses import dataclass

from .arching import handy, khosravi, paik_salgado
from .classical import coulomb, jaky, janssen, rankine
from .ground import METHODS as DESIGN_METHODS, Ground, earth_pressure
from .ec7 import ec7_annex_c
from .errors import InvalidParameter, NotApplicable
from .inputs import Soil, Wall
from .logspiral import log_spiral
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
                 ps_exponent: str = "iii", ground: Ground | None = None,
                 line_loads: tuple = (), strip_loads: tuple = (),
                 adhesion_ratio: float = 0.0) -> list[MethodRow]:
    """Evaluate every method for (soil, wall). Methods whose assumptions the geometry
    breaks come back as n/a rows; inputs with no solution (beta > phi, |delta| > phi,
    an inertia angle beyond phi - beta) raise ``InvalidParameter``.

    width: backfill width B [m] for Janssen's slot; defaults to H.
    ground, line_loads, strip_loads: a c-phi, wet or layered backfill and surface loads
    (``ground.py``); when any is given the design methods (Rankine-Bell, Coulomb,
    EC7 Annex C) carry the table and the others come back n/a. adhesion_ratio: a/c for
    Coulomb with cohesion.
    """
    if _is_design_case(soil, ground, line_loads, strip_loads):
        if kh or kv:
            # the design methods are static: refuse rather than drop the inertia silently
            raise InvalidParameter("kh" if kh else "kv", kh or kv, "0 with cohesion, water, layers or line/strip loads",
                                   "pseudo-static thrust is given for dry cohesionless fill only")
        return _design_table(soil, wall, passive, ground, line_loads, strip_loads, adhesion_ratio)
    B = wall.height if width is None else width
    active_only = "active/at-rest theory (drop --passive)"
    plan = [
        ("rankine", lambda: rankine(soil, wall, passive)),
        ("coulomb", lambda: coulomb(soil, wall, passive)),
        ("ec7-annex-c", lambda: ec7_annex_c(soil, wall, passive)),
        ("log-spiral", (lambda: log_spiral(soil, wall)) if passive else "passive theory (add --passive)"),
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
    return _evaluate(plan)


def _is_design_case(soil: Soil, ground: Ground | None, line_loads, strip_loads) -> bool:
    """True when the backfill is not today's dry, uniform, cohesionless one."""
    if line_loads or strip_loads:
        return True
    if ground is None:
        return False
    one = ground.layers[0]
    dry = ground.water_depth is None and ground.water_depth_front is None
    uniform = len(ground.layers) == 1 and one.phi_deg == soil.phi_deg and one.unit_weight == soil.unit_weight
    return not (dry and uniform and one.cohesion == 0.0)


def _design_table(soil, wall, passive, ground, line_loads, strip_loads, adhesion_ratio) -> list[MethodRow]:
    ground = ground or Ground.uniform(wall.height, soil.phi_deg, soil.unit_weight)
    why = "derived for a dry, uniform, cohesionless fill without line or strip loads"
    plan = [(m, (lambda m=m: earth_pressure(ground, wall, m, passive, line_loads=line_loads,
                                            strip_loads=strip_loads,
                                            adhesion_ratio=adhesion_ratio, trial_wedge=True).as_profile()))
            for m in DESIGN_METHODS]
    plan.append(("log-spiral", why if passive else "passive theory (add --passive)"))
    plan += [(m, why) for m in ("jaky", "mononobe-okabe", "handy", "paik-salgado", "khosravi", "janssen")]
    return _evaluate(plan)


def _evaluate(plan) -> list[MethodRow]:
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
