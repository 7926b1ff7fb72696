"""Verification formats: EN 1997-1 DA1 (combinations 1 and 2), DA2, DA3, EQU, the
classical factors of safety ('fs') and the EN 1998-5 seismic situation.

``verify(case, factors, fmt)`` evaluates each combination of the format (factors from
``factors.py``) and keeps, for each check, the worst combination. Conventions:
* permanent actions: each favourable or unfavourable by its own effect on the check
  (``checks.unfavourable``); with ``method.single_source`` every permanent action takes
  the unfavourable factor (EN 1997-1 2.4.2(9)P Note 1), except in EQU, which by
  definition separates destabilising and stabilising actions;
* favourable variable actions (surcharge over the heel in sliding/overturning) x 0;
* bearing is checked twice, all actions unfavourable and with the sliding
  classification (weights favourable), and the worse is reported;
* EQU checks overturning only (2.4.7.2); the GEO formats check overturning as a moment
  balance with their own factors as well;
* seismic: k_h = alpha S / r, k_v = +-0.5 or +-0.33 k_h (EN 1998-5 7.3.2.2), both signs
  tried, Mononobe-Okabe thrust, inertia of the wall and of the fill over the heel;
* eccentricity limit: B/6 (middle third) for 'fs', B/3 (middle two thirds, EN 1997-1
  6.5.4) otherwise.
"""

from __future__ import annotations

import math

from ..errors import InvalidParameter
from .actions import passive_force, thrust_for, wall_forces
from .case import DesignCase
from .checks import eccentricity, factor_of, make_check, overturning_moments, resultant
from .factors import Combination, Factors
from .results import CombinationResult, FormatResult, bearing_checks   # noqa: F401 - the format's records


def _forces_factors(forces, combo, check, tan_db, ss):
    return [factor_of(f, combo, check, tan_db, ss) for f in forces]


def evaluate(case: DesignCase, combo: Combination, *, kh: float = 0.0, kv: float = 0.0,
             ecc_limit: float = 1 / 3) -> CombinationResult:
    """The checks of a cantilever or gravity wall for one combination (module docstring).
    ecc_limit: the allowed e as a fraction of B (1/6 middle third, 1/3 two thirds)."""
    mats, res, fnd = combo.materials, combo.resistances, case.foundation
    ss = case.method.single_source and combo.name != "EQU"
    forces = wall_forces(case, mats, kh, kv)
    tan_db = math.tan(math.radians(fnd.delta_b)) / mats["phi"]
    B = case.wall.B
    out = CombinationResult(combo.name, B=B, K=thrust_for(case, mats, kh, kv).K, kh=kh, kv=kv)
    g_o = _forces_factors(forces, combo, "overturning", tan_db, ss)
    dst, stb = overturning_moments(forces, g_o, net=case.method.thrust_moment == "net")
    out.checks["overturning"] = make_check("overturning", dst, stb, "moments about the toe")
    if combo.name == "EQU":
        out.V_d, out.H_d, M = resultant(forces, g_o)      # the actions EQU weighed, with its factors
        out.e = eccentricity(out.V_d, M, B)
        return out
    g_s = _forces_factors(forces, combo, "sliding", tan_db, ss)
    V, H, M = resultant(forces, g_s)
    R = (max(V, 0.0) * tan_db + fnd.base_adhesion / mats["c"] * B) / res["sliding"]
    pp = passive_force(case, mats)
    if pp is not None:
        R += -pp.Fh / res["passive"]
    out.checks["sliding"] = make_check("sliding", H, R, "drained, V tan(delta_b,d)"
                                       + (" + passive" if pp is not None else ""))
    worst = None
    for check in ("bearing", "sliding"):
        g = _forces_factors(forces, combo, check, tan_db, ss)
        Vb, Hb, Mb = resultant(forces, g)
        e = eccentricity(Vb, Mb, B)
        bchecks, q_ult, B_eff = bearing_checks(case, combo, Vb, Hb, e)
        u = max(c.utilisation for c in bchecks)
        if worst is None or u > worst[0]:
            worst = (u, Vb, Hb, e, bchecks, q_ult, B_eff)
    _, out.V_d, out.H_d, out.e, bchecks, out.q_ult, out.B_eff = worst
    for c in bchecks:
        out.checks[c.name] = c
    if fnd.cu is not None:
        out.checks["sliding (undrained)"] = make_check("sliding (undrained)", out.H_d,
                                                       out.B_eff * fnd.cu / mats["cu"] / res["sliding"],
                                                       "A' c_u,d (EN 1997-1 eq. 6.4a)")
    lim = ecc_limit * B
    out.checks["eccentricity"] = make_check("eccentricity", abs(out.e), lim,
                                            "middle third (B/6)" if ecc_limit < 0.2 else "middle two thirds (B/3)")
    return out


def _evaluate_any(case, combo, **kw):
    if getattr(case.wall, "kind", "") == "blocks":
        from .blocks import evaluate_blocks
        return evaluate_blocks(case, combo, **kw)
    return evaluate(case, combo, **kw)


def verify(case: DesignCase, factors: Factors, fmt: str) -> FormatResult:
    """Evaluate a format ('DA1', 'DA2', 'DA3', 'EQU', 'fs', 'seismic') and keep the
    worst combination of each check. 'seismic' needs a [seismic] table: without one the
    case has no seismic situation to check (it is refused, never run at k_h = 0)."""
    if fmt == "seismic" and not case.seismic.given:
        raise InvalidParameter("seismic", "missing", "a [seismic] table (alpha, S, r; EN 1998-5 7.3.2.2) for "
                               "--format seismic", "without it there is no seismic situation to check")
    results = []
    for combo in factors.format(fmt):
        if combo.name == "SEISMIC" or fmt == "seismic":
            kh, kv = case.seismic.kh, case.seismic.kv
            runs = [_evaluate_any(case, combo, kh=kh, kv=s * kv) for s in ((1, -1) if kv > 0 else (1,))]
            results.extend(runs)
        else:
            results.append(_evaluate_any(case, combo, ecc_limit=1 / 6 if fmt == "fs" else 1 / 3))
    if fmt == "fs":
        for r in results:
            r.checks = _allowable(r.checks, factors.fs)
    worst = {}
    for r in results:
        label = r.name if r.kv == 0 else f"{r.name} (kv = {r.kv:+.4f})"
        for name, c in r.checks.items():
            if name not in worst or c.utilisation > worst[name][1].utilisation:
                worst[name] = (label, c)
    out = FormatResult(fmt, results, worst, fs_required=dict(factors.fs) if fmt == "fs" else {})
    if getattr(case.wall, "kind", "") == "blocks" and case.backfill is None and "FS" in factors.combinations:
        from .blocks import critical_water_height
        hw, mech, z = critical_water_height(case, factors.combinations["FS"])
        out.extra = {"critical_water_height_m": hw if math.isfinite(hw) else None,
                     "critical_mechanism": mech or None, "critical_joint_z_m": z if math.isfinite(z) else None}
    return out


def _allowable(checks: dict, required: dict) -> dict:
    """'fs' format: each resistance divided by its required factor of safety (sliding
    1.5, overturning 2.0, bearing 3.0 by default), so utilisation = FS_required / FS and
    the check passes at FS >= FS_required. The undrained variants take their drained
    check's factor."""
    from dataclasses import replace
    out = {}
    for name, c in checks.items():
        fs = required.get(name.split(" ")[0])
        out[name] = c if fs is None else replace(make_check(c.name, c.E_d, c.R_d / fs, c.note),
                                                 note=f"{c.note}; R / FS_required {fs:g}".lstrip("; "))
    return out


def factors_of_safety(result: FormatResult) -> dict:
    """Classical factors of safety R/E [-] of a result (inf when nothing acts); for the
    'fs' format the division by the required factors is undone."""
    req = result.fs_required
    return {name: (c.R_d * req.get(name.split(" ")[0], 1.0) / c.E_d if c.E_d > 0 else math.inf)
            for name, (_, c) in result.worst.items() if name != "eccentricity"}
