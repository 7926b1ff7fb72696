"""Actions on a cantilever or gravity wall, as forces with points of application.

``wall_forces(case, materials, kh, kv)`` lists every force for one set of material
factors (the thrust depends on phi_d) and seismic coefficients: self-weight of each
part, the fill moving with the wall (gamma_sat below the water table behind), the
earth thrust parts (``earth.design_thrust``: soil, surcharge and water behind apart),
surcharge on the fill over the heel, water in front (and its EN 1998-5 E.8
hydrodynamic pull when kh > 0), uplift, wall and fill inertia, and passive resistance
in front (only if switched on; it enters sliding only). With water behind, the free body (wall and the fill it carries) takes total weights and the water
pressures on its boundary: the water thrust on the back, water in front and the uplift
under the base, linear from gamma_w h_front at the toe to gamma_w h_behind at the heel
(hydrostatic on each side; the seepage under the wall is not modelled).

Signs (per metre run): Fh > 0 pushes the wall toward the front, Fv > 0 acts downward;
(x, y) from the toe and the base underside [m]. ``kind``: 'G' permanent, 'Q' variable,
'E' seismic inertia (never factored), 'P' passive resistance (factored as a resistance).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .case import GAMMA_W, DesignCase, design_angle
from .earth import Backfill, FillLayer, Thrust, design_thrust, passive_resistance, with_measured
from .geometry import area_centroid, clip_above
from .walls import Part, WallBack


@dataclass(frozen=True)
class Force:
    """One force [kN/m] at (x, y) [m]; kind 'G', 'Q', 'E' or 'P'; source 'structural' or
    'geotechnical' (DA3 factors them with A1 and A2)."""

    name: str
    kind: str
    source: str
    Fh: float
    Fv: float
    x: float
    y: float


def design_backfill(fill: Backfill, materials: dict) -> Backfill:
    """The fill with phi_d = atan(tan phi / gamma_phi'), c'_d = c' / gamma_c',
    gamma / gamma_gamma and gamma_sat / gamma_gamma (EN 1997-1 2.4.6.2, Table A.4); an
    undrained soil (phi = 0) takes c_u,d = c_u / gamma_cu."""
    g = materials["gamma"]

    def design(x) -> dict:
        c_factor = materials["cu"] if x.phi == 0 else materials["c"]
        return {"gamma": x.gamma / g, "phi": design_angle(x.phi, materials["phi"]), "c": x.c / c_factor,
                "gamma_sat": None if x.gamma_sat is None else x.gamma_sat / g}
    layers = tuple(FillLayer(x.thickness, **design(x)) for x in fill.layers)
    return Backfill(beta=fill.beta, layers=layers, **design(fill))


def thrust_for(case: DesignCase, materials: dict, kh: float = 0.0, kv: float = 0.0) -> Thrust:
    """The thrust on the wall's virtual back ('rankine-virtual-back', or 'coulomb' /
    'ec7-annex-c' on a cantilever or polygon wall) or real back ('coulomb' or
    'ec7-annex-c' on a trapezoidal gravity wall), with the water table ``water.behind``."""
    fill = design_backfill(case.backfill, materials)
    back, delta = back_and_delta(case, fill)
    thrust = design_thrust(fill, back, case.method.earth_pressure, q=case.loads.surcharge, delta=delta, kh=kh,
                           kv=kv, increment_height=case.seismic.increment_height, water_level=case.water.behind,
                           permeability=case.seismic.fill_permeability)
    if case.measured_thrust is None:
        return thrust
    unfactored = {k: 1.0 for k in materials}
    return with_measured(thrust, thrust_for(replace(case, measured_thrust=None), unfactored), case.measured_thrust)


def back_and_delta(case: DesignCase, fill: Backfill) -> tuple[WallBack, float | None]:
    """The back the thrust acts on and the wall friction angle on it [deg] by the file's
    convention: ``method.wall_friction`` (at most phi on a real back), else 2/3 phi on a
    real back and none on a virtual one (``design_thrust`` takes beta there)."""
    wall, m = case.wall, case.method
    real = not uses_virtual_back(case)
    back = wall.real_back() if real else wall.virtual_back(fill.beta)
    delta = m.wall_friction
    if delta is None and real:
        delta = 2.0 / 3.0 * fill.phi
    elif delta is not None and real:
        delta = min(delta, fill.phi)
    return back, delta


def uses_virtual_back(case: DesignCase) -> bool:
    """False for 'coulomb' or 'ec7-annex-c' on a trapezoidal gravity wall (real back)."""
    w = case.wall
    return not (case.method.earth_pressure in ("coulomb", "ec7-annex-c") and w.kind == "gravity"
                and w.polygon is None)


def wall_forces(case: DesignCase, materials: dict, kh: float = 0.0, kv: float = 0.0) -> list[Force]:
    """Every force on a cantilever or gravity wall (see the module docstring)."""
    wall, fill = case.wall, case.backfill
    solids = list(wall.parts())
    if uses_virtual_back(case):
        dfill = design_backfill(fill, materials)
        bands = _weight_bands(dfill, wall.virtual_back(fill.beta).height, case.water.behind)
        solids += _split(wall.fill_parts(fill.beta, dfill.gamma), bands)
    out = []
    for p in solids:
        (x, y), W = p.centroid, p.weight
        out.append(Force(p.name, "G", p.source, 0.0, W, x, y))
        if kh > 0 or kv != 0:
            out.append(Force(p.name + " inertia", "E", p.source, kh * W, -kv * W, x, y))
    out += thrust_forces(thrust_for(case, materials, kh, kv), case.loads.surcharge_permanent)
    out += _surcharge_on_heel(case, "G" if case.loads.surcharge_permanent else "Q")
    out += _water(case)
    if kh > 0 and case.water.front > 0:
        out.append(_hydrodynamic_front(case.water.front, kh))
    return out


def _hydrodynamic_front(h: float, kh: float) -> Force:
    """EN 1998-5 Annex E.8: free water of depth h [m] in front of the wall adds
    q(z) = +-7/8 kh gamma_w sqrt(h z) (Westergaard 1933), resultant 7/12 kh gamma_w h^2
    at 0.4 h above the bottom. Taken with the unfavourable sign: toward the front, the
    water's pull as the wall moves away from the fill."""
    return Force("hydrodynamic water in front (EN 1998-5 E.8)", "E", "geotechnical",
                 7.0 / 12.0 * kh * GAMMA_W * h * h, 0.0, 0.0, 0.4 * h)


def _weight_bands(fill: Backfill, top: float, level: float) -> list[tuple[float, float, float]]:
    """(y_lo, y_hi, unit weight [kN/m3]) of the fill moving with the wall: the strata of
    ``fill`` below the fill surface at the virtual back (y = ``top`` [m]), each at gamma
    above the water level y = ``level`` and gamma_sat below it; the top band reaches up
    and the bottom band down without end."""
    bands = []
    for z0, z1, soil in fill.strata(top):
        hi, lo = (math.inf if z0 == 0 else top - z0), (-math.inf if soil is fill else top - z1)
        cut = min(max(level, lo), hi) if level > 0 else lo
        bands += [(cut, hi, soil.gamma), (lo, cut, soil.gamma_wet)]
    return [b for b in bands if b[1] > b[0]]


def _split(parts: list[Part], bands: list[tuple[float, float, float]]) -> list[Part]:
    """Fill parts cut into the horizontal ``bands`` (total weights: the water pressures
    act on the free body's boundary). Unchanged for one band."""
    if len(bands) == 1:
        return [replace(p, unit_weight=bands[0][2]) for p in parts]
    out = []
    for p in parts:
        for lo, hi, g in bands:
            poly = list(p.polygon)
            if lo > -math.inf:
                poly = clip_above(poly, (0.0, lo), 0.0)
            if hi < math.inf:
                poly = [(x, -y) for x, y in clip_above([(x, -y) for x, y in poly], (0.0, -hi), 0.0)]
            if len(poly) >= 3 and area_centroid(poly)[0] > 1e-12:
                out.append(Part(f"{p.name} ({lo:.3g} to {hi:.3g} m)", tuple(poly), g, p.source))
    return out


def thrust_forces(thrust: Thrust, surcharge_permanent: bool) -> list[Force]:
    """The thrust parts as forces: soil and water 'G', surcharge 'Q' (or 'G'), seismic 'E'."""
    kinds = {"soil": "G", "water": "G", "surcharge": "G" if surcharge_permanent else "Q", "seismic": "E"}
    return [Force(t.name, kinds[t.kind], "geotechnical", t.Ph, t.Pv, t.x, t.y) for t in thrust.parts]


def _surcharge_on_heel(case: DesignCase, kind: str) -> list[Force]:
    """The surcharge over the fill that moves with the wall (virtual back only)."""
    q = case.loads.surcharge
    if q <= 0 or not uses_virtual_back(case):
        return []
    xt, yt = case.wall.fill_top()
    width = case.wall.B - xt
    if width <= 0:
        return []
    return [Force("surcharge on heel", kind, "geotechnical", 0.0, q * width, xt + width / 2, yt)]


def _water(case: DesignCase) -> list[Force]:
    """Water in front (hydrostatic, pushing back) and uplift under the base, linear from
    gamma_w h_front at the toe to gamma_w h_behind at the heel."""
    hf, hb, B = case.water.front, case.water.behind, case.wall.B
    out = []
    if hf > 0:
        out.append(Force("water in front", "G", "geotechnical", -0.5 * GAMMA_W * hf * hf, 0.0, 0.0, hf / 3))
    pf, pb = GAMMA_W * hf, GAMMA_W * hb
    if pf + pb > 0:
        U = 0.5 * (pf + pb) * B
        x = B * (pf + 2 * pb) / (3 * (pf + pb))
        out.append(Force("uplift", "G", "geotechnical", 0.0, -U, x, 0.0))
    return out


def passive_force(case: DesignCase, materials: dict) -> Force | None:
    """Passive resistance in front over the embedment (plus a shear key), with design
    phi_d and c_d, times the mobilisation factor; None when switched off."""
    m, f = case.method, case.foundation
    key = getattr(case.wall, "key_depth", 0.0)
    depth = f.embedment + key
    if not m.passive or depth <= 0:
        return None
    soil = Backfill(f.gamma / materials["gamma"], design_angle(f.phi, materials["phi"]), f.c / materials["c"])
    t = passive_resistance(soil, depth, 0.0)
    Pp = m.passive_mobilisation * math.fsum(p.P for p in t.parts)
    y = math.fsum(p.P * p.y for p in t.parts) / math.fsum(p.P for p in t.parts) - key
    return Force("passive resistance", "P", "geotechnical", -Pp, 0.0, 0.0, y)
