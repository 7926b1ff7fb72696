"""Pure formatting of design results: the JSON dict and the text report (no printing).

Every output states the conventions it followed (``conventions``)."""

from __future__ import annotations

import math

from .actions import uses_virtual_back
from .case import DesignCase
from .formats import FormatResult, factors_of_safety


def _num(x: float):
    """JSON-safe number: non-finite values become null."""
    return float(x) if math.isfinite(x) else None


def conventions(case: DesignCase, fmt: str) -> list[str]:
    """The conventions a result followed, one sentence each."""
    m, fnd = case.method, case.foundation
    out = []
    blocks = getattr(case.wall, "kind", "") == "blocks"
    if blocks:
        out.append("block wall: sliding along and toppling about the outer edge of every bed joint; "
                   "loads on the moving part's inner face only; no uplift in dry joints; "
                   + (f"toppling lines also step through head joints up to atan({case.wall.stair_slope:g})"
                      if case.wall.stair_slope > 0 else "no stepped toppling lines (stair_slope = 0)"))
        if case.backfill is not None:
            out.append("fill: Coulomb on the inner face above each joint, delta = wall_friction or 2/3 phi")
    else:
        out.append(f"earth pressure: {m.earth_pressure}, on the "
                   + ("virtual back through the heel (fill above the heel moves with the wall)"
                      if uses_virtual_back(case) else "real back"))
        out += _ground_conventions(case)
    out.append("permanent actions: " + ("single source, every one x gamma_G,unfav (EN 1997-1 2.4.2(9)P Note 1)"
                                        if m.single_source else "each favourable or unfavourable by its own "
                                        "effect on the check"))
    out.append("passive resistance in front: " + (f"on, x {m.passive_mobilisation:g} mobilised, sliding only"
                                                   + (", static (not reduced by the earthquake)"
                                                      if fmt == "seismic" else "") if m.passive else "off"))
    out.append("overturning: moments about the toe; " + ("each force's net moment" if m.thrust_moment == "net"
                                                          else "the vertical thrust component restores"))
    if fnd is not None:
        out.append("bearing: EN 1997-1 Annex D, B' = B - 2e, load inclined along B, no depth factors "
                   "(Annex D has none)" + ("; the base's counter-slope neglected" if blocks else "")
                   + ("; effective q' and gamma' under water" if case.water.front > 0 else "")
                   + ("; gamma' below the base (uplift from the water behind)"
                      if case.water.behind > 0 and case.water.front == 0 and not blocks else ""))
        out.append("eccentricity: " + ("middle third, e <= B/6" if fmt == "fs" else
                                       "middle two thirds, e <= B/3 (EN 1997-1 6.5.4)"))
    if fmt == "seismic":
        s = case.seismic
        out.append(f"seismic (EN 1998-5 7.3.2.2): kh = alpha S / r = {s.kh:.4g}, kv = +-{s.kv:.4g}; "
                   f"Mononobe-Okabe, dynamic increment at {s.increment_height:g} H, static part at H/3")
        if case.water.behind > 0 and case.backfill is not None:
            out.append(f"submerged fill: EN 1998-5 {'E.6 (impervious)' if s.fill_permeability == 'impervious' else 'E.7 (pervious)'}"
                       ", gamma* = gamma_sat - gamma_w and tan(psi) scaled by "
                       + ("gamma_sat" if s.fill_permeability == "impervious" else "gamma (as gamma_d)")
                       + " / gamma*" + ("; hydrodynamic 7/12 kh gamma_w H^2 at 0.4 H" if s.fill_permeability == "pervious"
                                        else "") + "; the fill carried by the wall moves with its pore water")
        if case.water.front > 0 or (case.backfill is None and case.water.behind > 0):
            out.append("free water: EN 1998-5 E.8 hydrodynamic pull 7/8 kh gamma_w sqrt(h z), toward the front")
    if fnd is not None:
        out.append(f"base friction delta_b = {fnd.delta_b:.4g} deg, tan(delta_b,d) = tan(delta_b) / gamma_phi")
    return out


def _ground_conventions(case: DesignCase) -> list[str]:
    """Sentences on cohesion and water behind a cantilever or gravity wall."""
    out = []
    if case.backfill.cohesive:
        out.append("cohesion: c'_d = c' / gamma_c'; " + (
            "Rankine-Bell, the tension crack (negative active stress) not counted"
            if case.method.earth_pressure == "rankine-virtual-back" else
            "EN 1997-1 C.1 K_ac = 2 sqrt(K cos delta) (no adhesion), tension not counted"
            if case.method.earth_pressure == "coulomb" else
            "EN 1997-1 Annex C K_c, tension not counted"))
    if case.backfill.layers:
        out.append(f"layered fill: {len(case.backfill.layers)} layer(s) over the [backfill] soil, K per layer, "
                   "sigma'_v continuous across the interfaces, K printed: the top layer's")
    if case.water.behind > 0:
        out.append(f"water table in the fill {case.water.behind:g} m above the base underside: effective "
                   "stresses (gamma_sat - gamma_w) below it, the water thrust a separate permanent action, "
                   "fill over the heel at gamma_sat, uplift linear from the toe to the heel")
    return out


def _check_json(label: str, c) -> dict:
    return {"E_d": _num(c.E_d), "R_d": _num(c.R_d), "utilisation": _num(c.utilisation),
            "combination": label, "note": c.note}


def design_json(case: DesignCase, result: FormatResult, fs_required: dict | None = None) -> dict:
    """The JSON of one format (the keys the design output documents; 'fs' adds the factors of safety)."""
    lead = result.lead
    out = {"format": result.format, "wall": case.wall.kind, "B_m": lead.B}
    if result.format == "fs":
        fs = factors_of_safety(result)
        out["fs"] = {k: _num(v) for k, v in fs.items()}
        out.update({"V_kN_per_m": lead.V_d, "H_kN_per_m": lead.H_d})
        if fs_required:
            out["fs_required"] = fs_required
    base = "bearing" in result.worst
    out.update({"V_d_kN_per_m": lead.V_d, "H_d_kN_per_m": lead.H_d, "e_m": _num(lead.e) if base else None,
                "B_eff_m": lead.B_eff if base else None, "q_ult_kPa": lead.q_ult if base else None,
                "Ka": lead.K if lead.K else None})
    out["checks"] = {k: _check_json(label, c) for k, (label, c) in result.worst.items()}
    name, combo, u = result.governing
    out["governing"] = {"check": name, "combination": combo, "utilisation": _num(u), "passes": u <= 1.0}
    joints = getattr(lead, "joints", None)
    if joints:
        out["joints"] = [{"z_m": r["z"], "y_I_m": r["y_I"], "sliding": _num(r["sliding"].utilisation),
                          "overturning": _num(r["overturning"].utilisation)} for r in joints]
    out.update(result.extra)
    out["conventions"] = conventions(case, result.format)
    return out


def design_text(case: DesignCase, result: FormatResult) -> str:
    """A plain-text table of the checks, the governing one and the conventions."""
    lead = result.lead
    if "bearing" in result.worst:
        where = f"  e = {lead.e:.3f} m  B' = {lead.B_eff:.3f} m  q_ult = {lead.q_ult:.1f} kPa  K = {lead.K:.4f}"
    elif result.format == "EQU":
        where = (f"  e = {lead.e:.3f} m  K = {lead.K:.4f}  (EQU's factors; EQU checks overturning about the toe "
                 f"only, EN 1997-1 2.4.7.2)")
    else:
        where = "  (at the base joint; no foundation given)"
    lines = [f"{case.wall.kind} wall, B = {lead.B:.3f} m, format {result.format}",
             f"  V_d = {lead.V_d:.2f} kN/m  H_d = {lead.H_d:.2f} kN/m" + where,
             f"  {'check':22s} {'E_d':>10s} {'R_d':>10s} {'util.':>7s}  combination"]
    for k, (label, c) in result.worst.items():
        lines.append(f"  {k:22s} {c.E_d:10.2f} {c.R_d:10.2f} {c.utilisation:7.3f}  {label}")
    for k, (label, c) in result.worst.items():
        if c.R_d <= 0 < c.E_d and c.note:        # no resistance at all: say why
            lines.append(f"  {c.note} ({label})" if c.note.startswith(k) else f"  {k} ({label}): {c.note}")
    if result.format == "fs":
        fs = factors_of_safety(result)
        lines.append("  factors of safety: " + ", ".join(
            f"{k} {v:.3f} (required {result.fs_required.get(k.split(' ')[0], 1.0):g})" for k, v in fs.items()))
    if result.extra.get("critical_mechanism"):
        x = result.extra
        lines.append(f"  limit equilibrium (factors 1): critical water height {x['critical_water_height_m']:.3f} m, "
                     f"{x['critical_mechanism']} at the joint z = {x['critical_joint_z_m']:.3f} m")
    name, combo, u = result.governing
    lines.append(f"  governing: {name} ({combo}), utilisation {u:.3f} -> {'passes' if u <= 1 else 'FAILS'}")
    lines += ["  conventions:"] + [f"   - {c}" for c in conventions(case, result.format)]
    return "\n".join(lines)


def bearing_json(b) -> dict:
    """JSON of ``wallsim bearing``."""
    f = {k: (_num(v) if isinstance(v, float) else v) for k, v in b.factors.items()}
    return {"q_ult_kPa": b.q_ult, "R_kN": b.R, "B_eff_m": b.B_eff, "L_eff_m": _num(b.L_eff),
            "method": b.method, "H_limit_kN": _num(b.H_limit), "fails": b.fails, "factors": f}
