"""The records a design format returns (``CombinationResult``, ``FormatResult``) and the
bearing checks of one design resultant, below both the format dispatcher
(``formats``) and the dry-stone block walls (``blocks``) that fill them."""

from __future__ import annotations

from dataclasses import dataclass, field

from .bearing import bearing_resistance, bearing_undrained
from .case import GAMMA_W, DesignCase, design_angle
from .checks import Check, make_check
from .factors import Combination


@dataclass
class CombinationResult:
    """One combination's design values: V_d, H_d [kN/m], e, B, B' [m], q_ult [kPa],
    K of the thrust, and its checks."""

    name: str
    V_d: float = 0.0
    H_d: float = 0.0
    e: float = 0.0
    B: float = 0.0
    B_eff: float = 0.0
    q_ult: float = 0.0
    K: float = 0.0
    kh: float = 0.0
    kv: float = 0.0
    checks: dict = field(default_factory=dict)

    @property
    def governing(self) -> Check:
        return max(self.checks.values(), key=lambda c: c.utilisation)


@dataclass
class FormatResult:
    """All combinations of a format and, per check, the worst (with its combination)."""

    format: str
    combinations: list
    worst: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)
    fs_required: dict = field(default_factory=dict)

    @property
    def governing(self) -> tuple[str, str, float]:
        """(check, combination, utilisation) of the highest utilisation."""
        name, (combo, chk) = max(self.worst.items(), key=lambda kv: kv[1][1].utilisation)
        return name, combo, chk.utilisation

    @property
    def lead(self) -> CombinationResult:
        """The combination whose values head the output: the one governing bearing (or
        the worst overall)."""
        key = "bearing" if "bearing" in self.worst else self.governing[0]
        label = self.worst[key][0]
        for r in self.combinations:
            if label.startswith(r.name) and (r.kv == 0 or f"{r.kv:+.4f}" in label):
                return r
        return self.combinations[0]


def bearing_checks(case: DesignCase, combo: Combination, V: float, H: float, e: float):
    """Drained (and undrained, with cu) bearing checks for one design resultant. With
    water in front above the base underside the drained check uses effective stresses:
    q' = gamma D - gamma_w min(h_w, D) and gamma' = gamma - gamma_w below the base (the
    uplift is already among the actions); water behind a cantilever or gravity wall
    (uplift under the base) also takes gamma' below the base."""
    f, m, r = case.foundation, combo.materials, combo.resistances
    B = case.wall.B
    out = []
    if V <= 0:
        return [make_check("bearing", 1.0, 0.0, f"bearing fails: V_d = {V:.4g} kN/m, no downward load on the "
                                                 f"base")], 0.0, 0.0
    if abs(e) >= B / 2:
        return [make_check("bearing", V, 0.0, f"bearing fails: the resultant is outside the base, |e| = "
                                              f"{abs(e):.4g} m >= B/2 = {B / 2:.4g} m")], 0.0, 0.0
    g, hw = f.gamma / m["gamma"], case.water.front
    q0 = g * f.embedment - GAMMA_W * min(hw, f.embedment)        # effective overburden q'
    wet = hw > 0 or (case.water.behind > 0 and case.wall.kind != "blocks")
    g_eff = g - GAMMA_W if wet else g                             # submerged below a flooded base
    b = bearing_resistance(phi=design_angle(f.phi, m["phi"]), c=f.c / m["c"], gamma=max(g_eff, 1e-9),
                           q=max(q0, 0.0), B=B, V=V, H=abs(H), e=e)
    out.append(make_check("bearing", V, b.R / r["bearing"], b.fails or f"EN 1997-1 D.4, B' = {b.B_eff:.3f} m"))
    if f.cu is not None:
        u = bearing_undrained(cu=f.cu / m["cu"], q=max(q0, 0.0), B=B, V=V, H=abs(H), e=e)
        out.append(make_check("bearing (undrained)", V, u.R / r["bearing"], u.fails or "EN 1997-1 D.3"))
    return out, b.q_ult, b.B_eff
