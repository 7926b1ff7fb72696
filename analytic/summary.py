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
                 adhesion_ratio: float = 0.0, crack_water: bool = False) -> list[MethodRow]:
    """Evaluate every method for (soil, wall). Methods whose assumptions the geometry
    breaks come back as n/a rows; inputs with no solution (beta > phi, |delta| > phi,
    an inertia angle beyond phi - beta) raise ``InvalidParameter``.

    width: backfill width B [m] for Janssen's slot; defaults to H.
    ground, line_loads, strip_loads: a c-phi, wet or layered backfill and surface loads
    (``ground.py``); when any is given the design methods (Rankine-Bell, Coulomb,
    EC7 Annex C) carry the table and the others come back n/a. adhesion_ratio: a/c for
    Coulomb with cohesion; crack_water: the tension crack full of water (ground.py).
    """
    if crack_water and not _is_design_case(soil, ground, line_loads, strip_loads):
        raise InvalidParameter("crack-water", True, "with a cohesive fill (c > 0)", "a cohesionless fill has no crack")
    if _is_design_case(soil, ground, line_loads, strip_loads):
        if kh or kv:
            # the design methods are static: refuse rather than drop the inertia silently
            raise InvalidParameter("kh" if kh else "kv", kh or kv, "0 with cohesion, water, layers or line/strip loads",
                                   "pseudo-static thrust is given for dry cohesionless fill only")
        return _design_table(soil, wall, passive, ground, line_loads, strip_loads, adhesion_ratio, crack_water)
    B = wall.height if width is None else width
    active_only = "active/at-rest theory (drop --passive)"
    plan = [
        ("rankine", lambda w: rankine(soil, w, passive)),
        ("coulomb", lambda w: coulomb(soil, w, passive)),
        ("ec7-annex-c", lambda w: ec7_annex_c(soil, w, passive)),
        ("log-spiral", (lambda w: log_spiral(soil, w)) if passive else "passive theory (add --passive)"),
        ("jaky", (lambda w: jaky(soil, w)) if not passive else active_only),
        ("mononobe-okabe", lambda w: mononobe_okabe(soil, w, kh, kv, passive)),
    ]
    if kh > 0 and not passive:
        plan.append(("seed-whitman", lambda w: seed_whitman(soil, w, kh)))
    for name, fn in (("handy", lambda w: handy(soil, w)),
                     ("paik-salgado", lambda w: paik_salgado(soil, w, ps_exponent)),
                     ("khosravi", lambda w: khosravi(soil, w)),
                     ("janssen", lambda w: janssen(soil, w, B))):
        plan.append((name, fn if not passive else active_only))
    runs = dict(plan)
    return [_soil_coefficient(row, runs[row.name], wall) for row in _evaluate(plan, wall)]


def _soil_coefficient(row: MethodRow, fn, wall: Wall) -> MethodRow:
    """One meaning of K in every row: the soil coefficient. A method whose K came out of
    the whole thrust with a surcharge (Mononobe-Okabe, Seed-Whitman, the arching
    theories) gets K and Kh of its own run without the surcharge, and the surcharge's
    thrust apart as extra['thrust_q'] = P(q) - P(0), as the linear methods give it."""
    p = row.profile
    if p is None or not wall.surcharge or "thrust_q" in p.extra:
        return row
    from dataclasses import replace
    bare = fn(replace(wall, surcharge=0.0))
    return replace(row, profile=replace(p, K=bare.K, Kh=bare.Kh, extra={**p.extra, "thrust_q": p.thrust - bare.thrust}))


def _is_design_case(soil: Soil, ground: Ground | None, line_loads, strip_loads) -> bool:
    """True when the backfill is not today's dry, uniform, cohesionless one."""
    if line_loads or strip_loads or soil.undrained:
        return True
    if ground is None:
        return False
    one = ground.layers[0]
    dry = ground.water_depth is None and ground.water_depth_front is None
    uniform = len(ground.layers) == 1 and one.phi_deg == soil.phi_deg and one.unit_weight == soil.unit_weight
    return not (dry and uniform and one.cohesion == 0.0)


def _design_table(soil, wall, passive, ground, line_loads, strip_loads, adhesion_ratio,
                  crack_water=False) -> list[MethodRow]:
    ground = ground or Ground.uniform(wall.height, soil.phi_deg, soil.unit_weight)
    why = "derived for a dry, uniform, cohesionless fill without line or strip loads"
    plan = [(m, (lambda w, m=m: earth_pressure(ground, w, m, passive, line_loads=line_loads,
                                            strip_loads=strip_loads, adhesion_ratio=adhesion_ratio,
                                            trial_wedge=True, crack_water=crack_water).as_profile()))
            for m in DESIGN_METHODS]
    plan.append(("log-spiral", why if passive else "passive theory (add --passive)"))
    plan += [(m, why) for m in ("jaky", "mononobe-okabe", "handy", "paik-salgado", "khosravi", "janssen")]
    return _evaluate(plan, wall)


def _evaluate(plan, wall: Wall) -> list[MethodRow]:
    """Each (name, fn(wall) or the reason it does not apply) of ``plan`` as a row."""
    rows = []
    for name, fn in plan:
        if isinstance(fn, str):
            rows.append(MethodRow(name, None, fn))
            continue
        try:
            rows.append(MethodRow(name, fn(wall)))
        except NotApplicable as err:
            rows.append(MethodRow(name, None, err.why or str(err)))
    return rows
