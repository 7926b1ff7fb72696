"""Everyday design earth pressure: c-phi soils, a water table, layered backfill and
surface loads, with the soil, surcharge and water parts kept apart.

Vertical effective stress (total stress minus pore pressure; e.g. Craig's Soil Mechanics,
ch. 3 and 11):

    sigma'_v(z) = q + sum over the soil above z of gamma_i dz   (gamma_i above the water
                  table, gamma_sat,i - gamma_w below it)
    u(z)        = gamma_w (z - z_w) below the water table z_w, 0 above it

Normal effective stress on the back face, per layer i (coefficient K_i for that layer):

    rankine:     sigma'_n = K_i sigma'_v -+ 2 c_i sqrt(K_i)                 (Bell 1915)
    coulomb:     sigma'_n = K_i cos(delta) sigma'_v -+ c_i K_ac,i,  K_ac = 2 sqrt(K_n (1 + a/c))
                 capped at 2.56 sqrt(K_n) with K_n = K_i cos(delta)          (EN 1997-1 C.1)
    ec7-annex-c: sigma'_n = K_gamma,i (sigma'_v - s_i) + K_q,i s_i -+ K_c,i c_i,
                 s_i = sigma'_v at the top of layer i (the layers above act as its surcharge)
                 (EN 1997-1 Annex C.2, eqs. C.6-C.9)

(- active, + passive). In the active case the negative (tension) part near the top is
not counted as load: sigma'_n is cut at zero and the depth where it first becomes
positive is reported as the tension-crack depth (Craig, sec. 11.3; no water in the crack).
Water pressure u is added normal to the face; its thrust is reported apart, and a water
level in front of the wall gives a front pressure reported apart too (acting the other
way). Line and strip loads add the elastic stresses of ``surcharge.py``.

The stresses are exact piecewise-linear functions between break points (layer
interfaces, the water table, the crack depth), so thrusts and heights are integrated
exactly; line and strip loads by their closed-form resultants and adaptive quadrature
for their heights.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import quad

from .classical import _surcharge_factor, coulomb_coefficient, rankine_coefficient
from .ec7 import annex_c_coefficients
from .errors import InvalidParameter, NotApplicable
from .constants import GAMMA_WATER
from .inputs import Wall, require_number, require_vertical_level
from .profile import Profile
from .surcharge import LineLoad, StripLoad
from .wedge import cohesive_wedge

METHODS = ("rankine", "coulomb", "ec7-annex-c")
_SOURCES = {
    "rankine": "Rankine (1857) with Bell's (1915) cohesion term; effective stresses, water apart",
    "coulomb": "Coulomb (1776), Mueller-Breslau K per layer; cohesion and adhesion by EN 1997-1 C.1 K_ac",
    "ec7-annex-c": "EN 1997-1:2004 Annex C.2 (C.6-C.9) per layer",
}


@dataclass(frozen=True)
class Layer:
    """One backfill layer, from the top down.

    thickness:        [m], > 0
    phi_deg:          effective friction angle [deg], 0 < phi < 90; or 0 for an undrained
                      clay in total stress (then ``cohesion`` is c_u > 0)
    unit_weight:      gamma above the water table [N/m^3], > 0
    cohesion:         effective cohesion c' [Pa], >= 0 (c_u when phi = 0)
    unit_weight_sat:  gamma_sat below the water table [N/m^3], >= gamma_w; default: unit_weight
    """

    thickness: float
    phi_deg: float
    unit_weight: float
    cohesion: float = 0.0
    unit_weight_sat: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "thickness", require_number("layer thickness", self.thickness, 0.0, None, unit="m"))
        object.__setattr__(self, "phi_deg", require_number("phi", self.phi_deg, 0.0, 90.0, lo_open=False,
                                                           unit="deg"))
        object.__setattr__(self, "unit_weight", require_number("gamma", self.unit_weight, 0.0, None, unit="N/m^3"))
        object.__setattr__(self, "cohesion", require_number("c", self.cohesion, 0.0, None, lo_open=False, unit="Pa"))
        if self.phi_deg == 0.0 and self.cohesion <= 0.0:
            raise InvalidParameter("c", self.cohesion, "> 0 with phi = 0", "phi = 0 is the undrained case: give c_u")
        if self.unit_weight_sat is not None:
            object.__setattr__(self, "unit_weight_sat",
                               require_number("gamma_sat", self.unit_weight_sat, GAMMA_WATER, None,
                                              lo_open=False, unit="N/m^3"))

    @property
    def gamma_sat(self) -> float:
        return self.unit_weight if self.unit_weight_sat is None else self.unit_weight_sat


@dataclass(frozen=True)
class Ground:
    """The backfill: layers from the wall top down, and the water levels.

    water_depth:        depth of the water table behind the wall below the wall top [m],
                        >= 0; None = dry; below the base is accepted (no water on the wall)
    water_depth_front:  the same in front of the wall; None = no water in front
    unit_weight_water:  gamma_w [N/m^3]
    """

    layers: tuple
    water_depth: float | None = None
    water_depth_front: float | None = None
    unit_weight_water: float = GAMMA_WATER

    def __post_init__(self):
        layers = tuple(self.layers)
        if not layers or not all(isinstance(x, Layer) for x in layers):
            raise InvalidParameter("layers", len(layers), "one or more Layer records")
        object.__setattr__(self, "layers", layers)
        for name in ("water_depth", "water_depth_front"):
            v = getattr(self, name)
            if v is not None:
                object.__setattr__(self, name, require_number(name.replace("_", "-"), v, 0.0, None,
                                                              lo_open=False, unit="m"))

    @classmethod
    def uniform(cls, H: float, phi_deg: float, unit_weight: float, cohesion: float = 0.0,
                unit_weight_sat: float | None = None, **kw) -> "Ground":
        """One layer over the whole height H."""
        return cls((Layer(H, phi_deg, unit_weight, cohesion, unit_weight_sat),), **kw)

    def check_height(self, H: float) -> None:
        total = math.fsum(x.thickness for x in self.layers)
        if abs(total - H) > 1e-9 * max(H, 1.0):
            raise InvalidParameter("layers", total, f"thicknesses adding up to H = {H:g} m",
                                   "the layers must fill the wall height")

    def tops(self) -> np.ndarray:
        """Depth of the top of each layer [m]."""
        return np.concatenate([[0.0], np.cumsum([x.thickness for x in self.layers])[:-1]])

    def breaks(self, H: float) -> list[float]:
        """Depths where a stress can change slope or jump: interfaces and water tables."""
        pts = {0.0, H, *[float(t) for t in self.tops()]}
        for zw in (self.water_depth, self.water_depth_front):
            if zw is not None and 0.0 < zw < H:
                pts.add(zw)
        return sorted(pts)

    def pore_pressure(self, z, front: bool = False) -> np.ndarray:
        """Hydrostatic pore pressure [Pa] at depths z [m] behind (or in front of) the wall."""
        zw = self.water_depth_front if front else self.water_depth
        z = np.asarray(z, dtype=float)
        if zw is None:
            return np.zeros_like(z)
        return self.unit_weight_water * np.maximum(z - zw, 0.0)

    def vertical_effective_stress(self, z, q: float = 0.0) -> np.ndarray:
        """sigma'_v [Pa] at depths z [m] under a uniform surcharge q [Pa] (module docstring)."""
        z = np.asarray(z, dtype=float)
        out = np.full_like(z, q, dtype=float)
        zw = math.inf if self.water_depth is None else self.water_depth
        for top, layer in zip(self.tops(), self.layers):
            bot = top + layer.thickness
            dry = np.clip(np.minimum(z, zw), top, bot) - top          # dry thickness above z
            wet = np.clip(z, max(top, zw), max(bot, zw)) - max(top, zw) if zw < bot else 0.0
            out += layer.unit_weight * dry + (layer.gamma_sat - self.unit_weight_water) * wet
        return out

    def layer_index(self, z: float, below: bool = True) -> int:
        """Index of the layer at depth z; at an interface the one below (or above)."""
        edges = np.cumsum([x.thickness for x in self.layers])
        i = int(np.searchsorted(edges, z, side="right" if below else "left"))
        return min(i, len(self.layers) - 1)


@dataclass(frozen=True)
class Part:
    """One part of the load on the wall: normal force N [N/m] (per metre of wall, along the
    face normal), its horizontal component [N/m] and height above the base [m] (None when
    the part is zero)."""

    N: float
    horizontal: float
    height: float | None

    def as_dict(self) -> dict:
        return {"normal_kN_per_m": self.N / 1e3, "horizontal_kN_per_m": self.horizontal / 1e3,
                "height_m": self.height}


@dataclass(frozen=True)
class DesignProfile:
    """Earth pressure with its parts apart (compression positive, depth z below the top).

    z:             (n,) depths [m], break points repeated (value above, then below)
    sigma_soil:    (n,) normal effective soil stress without the uniform surcharge [Pa]
    sigma_q:       (n,) added by the uniform surcharge q (effective, through K) [Pa]
    sigma_loads:   (n,) added by line and strip loads (elastic, horizontal) [Pa]
    u:             (n,) water pressure behind the wall [Pa]
    u_front:       (n,) water pressure in front of the wall (acts the other way) [Pa]
    direction_deg: inclination of the soil stress to the face normal (delta, or beta for
                   Rankine), shear down the face when active
    parts:         {"soil", "surcharge", "water", "water_front"} -> Part
    K_layers:      the method's coefficient per layer, along its own thrust direction
    tension_crack_depth: [m], 0 when there is none (active only)
    """

    method: str
    passive: bool
    H: float
    z: np.ndarray
    sigma_soil: np.ndarray
    sigma_q: np.ndarray
    sigma_loads: np.ndarray
    u: np.ndarray
    u_front: np.ndarray
    direction_deg: float
    parts: dict
    K_layers: tuple
    tension_crack_depth: float
    source: str
    notes: str = ""
    extra: dict = field(default_factory=dict)

    @property
    def sigma_total(self) -> np.ndarray:
        """Normal stress on the back face, soil + surcharge + loads + water [Pa]."""
        return self.sigma_soil + self.sigma_q + self.sigma_loads + self.u

    def horizontal_thrust(self, *names: str) -> float:
        """Sum of the horizontal components of the named parts (all but the front water by
        default) [N/m]."""
        names = names or ("soil", "surcharge", "water")
        return math.fsum(self.parts[n].horizontal for n in names)

    def as_profile(self) -> Profile:
        """The record the theory table prints: sigma_h the total normal stress on the back
        face, tau the shear of the effective soil and uniform-surcharge stresses, K the
        method's coefficient of the top layer along its own thrust (Kh its horizontal part),
        thrust the magnitude of the resultant of the soil, surcharge and water parts (the
        front water is left out: it is in ``extra['parts']``), height that of their
        normal forces."""
        d = math.radians(self.direction_deg)
        omega = math.radians(self.extra["omega_deg"])
        names = ("soil", "surcharge", "water")
        N = math.fsum(self.parts[n].N for n in names)
        T = (self.parts["soil"].N + self.extra["N_q_uniform"]) * math.tan(d)
        height = (math.fsum(self.parts[n].N * self.parts[n].height for n in names if self.parts[n].N > 0) / N
                  if N > 0 else self.H / 3)
        K = self.K_layers[0]
        return Profile(method=self.method, z=self.z, sigma_h=self.sigma_total,
                       tau=(self.sigma_soil + self.sigma_q) * math.tan(d), thrust=math.hypot(N, T),
                       thrust_h=self.horizontal_thrust(), height=height, K=K, Kh=K * math.cos(d + omega),
                       H=self.H, omega_deg=self.extra["omega_deg"], source=self.source, notes=self.notes,
                       extra={"passive": self.passive, "design": self,
                              "parts": {k: v.as_dict() for k, v in self.parts.items()},
                              "K_layers": list(self.K_layers),
                              "tension_crack_depth_m": self.tension_crack_depth})


def _layer_coefficients(method: str, layer: Layer, wall: Wall, passive: bool, adhesion_ratio: float):
    """(K along the thrust, K_weight normal, K_surcharge normal, cohesion coefficient) for one
    layer: sigma'_n = K_w (sigma'_v - s) + K_s s -+ K_c c with s the layer-top stress."""
    phi, c = layer.phi_deg, layer.cohesion
    if method == "rankine":
        K = rankine_coefficient(math.radians(phi), wall.beta, passive)
        kn = K * math.cos(wall.beta)        # Rankine's stress is parallel to the surface
        return K, kn, kn, 2 * math.sqrt(kn)
    if method == "coulomb":
        K = coulomb_coefficient(math.radians(phi), wall.delta, wall.omega, wall.beta, passive)
        if not math.isfinite(K):
            raise InvalidParameter("delta", wall.delta_deg, "a range where the Coulomb wedge has a finite solution")
        kn = K * math.cos(wall.delta) * math.cos(wall.omega)
        kac = 2 * math.sqrt(kn * (1 + adhesion_ratio)) if c > 0 else 0.0
        return K, kn, kn, min(kac, 2.56 * math.sqrt(kn))
    co = annex_c_coefficients(phi, wall.delta_deg, wall.beta_deg, wall.omega_deg, passive)
    return co.K_gamma / (math.cos(wall.delta) * math.cos(wall.omega)), co.K_gamma, co.K_q, co.K_c


def _check_method_geometry(method: str, ground: Ground, wall: Wall) -> None:
    cohesive = any(x.cohesion > 0 for x in ground.layers)
    if method == "ec7-annex-c" and any(x.phi_deg == 0 for x in ground.layers):
        raise NotApplicable("phi", 0.0, "> 0", "Annex C's K_c = (K_n - 1) cot phi has no value at phi = 0 "
                            "(undrained: rankine, K = 1 and 2 c_u)")
    if method == "rankine":
        require_vertical_level("Rankine", wall, level=cohesive)
    elif method == "coulomb" and cohesive:
        require_vertical_level("Coulomb with cohesion (EN 1997-1 C.1 K_ac)", wall)
    for x in ground.layers:
        if method != "ec7-annex-c" and abs(wall.beta_deg) > x.phi_deg:
            raise InvalidParameter("beta", wall.beta_deg, f"[-phi, phi] = [{-x.phi_deg:g}, {x.phi_deg:g}] deg")
        if method != "rankine" and abs(wall.delta_deg) > x.phi_deg + 1e-12:
            raise InvalidParameter("delta", wall.delta_deg, f"[-phi, phi] = [{-x.phi_deg:g}, {x.phi_deg:g}] deg")


def _linear_force(z0, z1, s0, s1):
    """Force [N/m] and moment about the top [N] of a stress varying linearly from s0 at z0
    to s1 at z1 (exact)."""
    L = z1 - z0
    F = 0.5 * (s0 + s1) * L
    M = L * (s0 * (2 * z0 + z1) + s1 * (z0 + 2 * z1)) / 6.0
    return F, M


def _integrate(z, s):
    """Exact force and moment of a piecewise-linear stress tabulated at z (repeated depths
    carry jumps)."""
    F = M = 0.0
    for i in range(len(z) - 1):
        if z[i + 1] > z[i]:
            f, m = _linear_force(z[i], z[i + 1], s[i], s[i + 1])
            F, M = F + f, M + m
    return F, M


def _part(F, M, H, horizontal_factor) -> Part:
    return Part(N=F, horizontal=F * horizontal_factor, height=H - M / F if F > 0 else None)


def earth_pressure(ground: Ground, wall: Wall, method: str = "rankine", passive: bool = False, *,
                   line_loads: tuple = (), strip_loads: tuple = (), adhesion_ratio: float = 0.0,
                   points_per_segment: int = 40, trial_wedge: bool = False,
                   crack_water: bool = False) -> DesignProfile:
    """Design earth pressure on the back face (module docstring for the equations).

    ground:          layers and water levels; the layers must add up to wall.height
    wall:            geometry, wall friction delta and uniform surcharge q = wall.surcharge
    method:          "rankine" | "coulomb" | "ec7-annex-c"
    adhesion_ratio:  a / c for the Coulomb cohesion coefficient (0 <= a/c <= 1)
    trial_wedge:     also work Coulomb's c-a trial wedge (``wedge.py``, ~0.1 s) where it
                     applies, into ``extra['trial_wedge']`` and the notes
    line_loads, strip_loads: ``surcharge.LineLoad`` / ``StripLoad`` (vertical wall only)
    crack_water:     the active tension crack full of water: gamma_w z on the wall down to
                     the crack depth, added to the water part (a short-term design case of
                     clay backfill; Craig sec. 11.3)

    Returns a ``DesignProfile`` whose ``parts`` give soil, surcharge (uniform q plus line
    and strip loads), water and front-water forces apart.
    """
    if method not in METHODS:
        raise InvalidParameter("method", method, " | ".join(METHODS))
    H = wall.height
    ground.check_height(H)
    a_c = require_number("adhesion ratio a/c", adhesion_ratio, 0.0, 1.0, lo_open=False, hi_open=False)
    _check_method_geometry(method, ground, wall)
    if (line_loads or strip_loads) and wall.omega_deg != 0.0:
        raise NotApplicable("omega", wall.omega_deg, "0 deg", "line and strip loads are set up for a vertical back")
    coeffs = [_layer_coefficients(method, x, wall, passive, a_c) for x in ground.layers]
    sign = 1.0 if passive else -1.0
    d = {"rankine": wall.beta, "coulomb": wall.delta, "ec7-annex-c": wall.delta}[method]
    direction = -d if passive else d
    # a soil force at `direction` to the face normal: horizontal / normal component
    horiz = math.cos(direction + wall.omega) / math.cos(direction)
    cos_o = math.cos(wall.omega)
    # Coulomb's wedge carries q over its horizontal extent: the same factor as classical.py
    q = wall.surcharge * (_surcharge_factor(wall) if method == "coulomb" else 1.0)

    # grid: each segment between break points sampled densely, break points repeated
    brk = ground.breaks(H)
    z_parts, idx = [], []
    for a, b in zip(brk[:-1], brk[1:]):
        z_parts.append(np.linspace(a, b, points_per_segment))
        idx.append(np.full(points_per_segment, ground.layer_index(0.5 * (a + b))))
    z, layer_of = np.concatenate(z_parts), np.concatenate(idx)
    tops = ground.tops()

    def normal_stress(q_surface):
        sv = ground.vertical_effective_stress(z, q_surface)
        s_top = ground.vertical_effective_stress(tops, q_surface)[layer_of]
        kw = np.array([c[1] for c in coeffs])[layer_of]
        ks = np.array([c[2] for c in coeffs])[layer_of]
        kc = np.array([c[3] for c in coeffs])[layer_of]
        coh = np.array([x.cohesion for x in ground.layers])[layer_of]
        return kw * (sv - s_top) + ks * s_top + sign * kc * coh

    raw0, raw_q = normal_stress(0.0), normal_stress(q)
    crack = 0.0
    if not passive:
        z, raw0, raw_q, layer_of, crack = _insert_zero_crossings(z, raw0, raw_q, layer_of)
    in_crack = np.zeros(len(z), bool)
    if crack_water and crack > 0:
        # the crack depth twice: the water pressure ends there in a jump
        k = int(np.searchsorted(z, crack, side="left")) + 1
        z, raw0, raw_q, layer_of = (np.insert(a, k, a[k - 1]) for a in (z, raw0, raw_q, layer_of))
        in_crack = np.arange(len(z)) < k
    s0 = np.maximum(raw0, 0.0) if not passive else raw0
    sq = (np.maximum(raw_q, 0.0) if not passive else raw_q) - s0
    u, u_front = ground.pore_pressure(z), ground.pore_pressure(z, front=True)
    u = np.maximum(u, np.where(in_crack, ground.unit_weight_water * z, 0.0))
    loads = sum((ld.sigma_h(z, H) for ld in (*line_loads, *strip_loads)), np.zeros_like(z))

    # per unit face length: a face element spans dz / cos(omega)
    F0, M0 = _integrate(z, s0)
    Fq, Mq = _integrate(z, sq)
    Fw, Mw = _integrate(z, u)
    Ff, Mf = _integrate(z, u_front)
    FL, ML = _elastic_resultant(line_loads, strip_loads, H)
    N_q_uniform = Fq / cos_o
    parts = {
        "soil": _part(F0 / cos_o, M0 / cos_o, H, horiz),
        "surcharge": Part(N=N_q_uniform + FL,
                          horizontal=N_q_uniform * horiz + FL,
                          height=H - (Mq / cos_o + ML) / (N_q_uniform + FL) if N_q_uniform + FL > 0 else None),
        "water": _part(Fw / cos_o, Mw / cos_o, H, math.cos(wall.omega)),
        "water_front": _part(Ff, Mf, H, 1.0),
    }
    notes = []
    if method == "coulomb" and passive and abs(wall.delta_deg) > min(x.phi_deg for x in ground.layers) / 2:
        notes.append("planar-wedge Kp is unconservative for rough walls (delta > phi/2)")
    extra = {"N_q_uniform": N_q_uniform, "omega_deg": wall.omega_deg}
    wedge = _trial_wedge(method, ground, wall, passive, a_c, line_loads or strip_loads) if trial_wedge else None
    if wedge is not None:
        extra["trial_wedge"] = wedge
        notes.append(f"c-a trial wedge: {wedge.P_h / 1e3:.2f} kN/m horizontal, crack {wedge.crack_depth:.3f} m "
                     "(the profile uses EN 1997-1 C.1)")
    if crack > 0:
        notes.append(f"tension crack to {crack:.3f} m: the negative active stress above it is not counted"
                     + ("; the crack full of water (in the water part)" if crack_water else ""))
    if any(x.phi_deg == 0 for x in ground.layers):
        notes.append("phi = 0: undrained, total stress (K = 1, the c term 2 c_u)")
    if ground.water_depth is not None and ground.water_depth >= H:
        notes.append("water table at or below the base: no water pressure on the wall")
    return DesignProfile(method=method, passive=passive, H=H, z=z, sigma_soil=s0, sigma_q=sq,
                         sigma_loads=loads, u=u, u_front=u_front, direction_deg=math.degrees(direction),
                         parts=parts, K_layers=tuple(c[0] for c in coeffs), tension_crack_depth=crack,
                         source=_SOURCES[method], notes="; ".join(notes), extra=extra)


def _trial_wedge(method, ground, wall, passive, a_c, loads):
    """Coulomb's c-a trial wedge (``wedge.py``) beside the C.1 profile, for the case it is
    set up for: one cohesive layer, no water on the wall, vertical back, level fill, no
    line or strip loads; None otherwise."""
    x = ground.layers[0]
    wet = ground.water_depth is not None and ground.water_depth < wall.height
    if (method != "coulomb" or len(ground.layers) != 1 or x.cohesion == 0.0 or wet or loads
            or wall.delta_deg < 0.0):
        return None
    return cohesive_wedge(wall.height, x.phi_deg, x.unit_weight, x.cohesion, a_c * x.cohesion,
                          wall.delta_deg, wall.surcharge, passive)


def _insert_zero_crossings(z, a, b, layer_of):
    """Insert the depths where the piecewise-linear stresses a or b cross zero, so cutting
    them at zero stays exact; returns the new arrays and the tension-crack depth of b
    (the stress with the surcharge)."""
    zs, As, Bs, Ls = [z[0]], [a[0]], [b[0]], [layer_of[0]]
    for i in range(len(z) - 1):
        z0, z1 = z[i], z[i + 1]
        if z1 > z0:
            cuts = []
            for s in (a, b):
                if s[i] * s[i + 1] < 0:
                    cuts.append(z0 + (z1 - z0) * s[i] / (s[i] - s[i + 1]))
            for zc in sorted(cuts):
                w = (zc - z0) / (z1 - z0)
                zs.append(zc)
                As.append(a[i] + w * (a[i + 1] - a[i]))
                Bs.append(b[i] + w * (b[i + 1] - b[i]))
                Ls.append(layer_of[i])
        zs.append(z1)
        As.append(a[i + 1])
        Bs.append(b[i + 1])
        Ls.append(layer_of[i + 1])
    z, a, b = np.array(zs), np.array(As), np.array(Bs)
    crack = 0.0
    if b[0] < 0:
        # the crack reaches the first depth below which b is no longer negative
        neg = b < -1e-9 * max(1.0, float(np.max(np.abs(b))))
        ends = np.nonzero(~neg)[0]
        crack = float(z[ends[0]]) if len(ends) else float(z[-1])
    return z, a, b, np.array(Ls), crack


def _elastic_resultant(line_loads, strip_loads, H):
    """Force [N/m] and moment about the top [N] of the line and strip loads' stresses:
    closed-form forces (``resultant``), moments by adaptive quadrature."""
    F = M = 0.0
    for ld in (*line_loads, *strip_loads):
        F += ld.resultant(H)
        M += quad(lambda s: float(ld.sigma_h(s, H)) * s, 0.0, H, epsabs=0, epsrel=1e-10, limit=200)[0]
    return F, M


def layers_from_table(table: dict) -> tuple[Layer, ...]:
    """Layers from a parsed TOML document with ``[[layer]]`` tables (engineering units):
    thickness [m], phi [deg], gamma [kN/m^3], c [kPa] (0), gamma_sat [kN/m^3] (gamma).
    Unknown keys and missing required keys are refused, naming the layer."""
    rows = table.get("layer") if isinstance(table, dict) else None
    if not isinstance(rows, list) or not rows:
        raise InvalidParameter("layers", "file", "[[layer]] tables with thickness, phi, gamma (and c, gamma_sat)")
    known = {"thickness", "phi", "gamma", "c", "gamma_sat"}
    out = []
    for i, row in enumerate(rows, 1):
        extra = set(row) - known if isinstance(row, dict) else {"?"}
        missing = {"thickness", "phi", "gamma"} - set(row) if isinstance(row, dict) else set()
        if extra or missing:
            bad = sorted(extra or missing)[0]
            raise InvalidParameter(f"layer {i} key", bad, ", ".join(sorted(known)),
                                   "unknown key" if extra else "missing key")
        gs = row.get("gamma_sat")
        out.append(Layer(row["thickness"], row["phi"], _kilo(row["gamma"], "gamma"),
                         _kilo(row.get("c", 0.0), "c"), None if gs is None else _kilo(gs, "gamma_sat")))
    return tuple(out)


def _kilo(value, name: str) -> float:
    """kN or kPa (as typed) to N or Pa, refusing what is not a number."""
    return require_number(name, value) * 1e3


def theory_ground(soil, H: float, *, c_kPa: float = 0.0, gamma_sat_kN: float | None = None,
                  water_depth: float | None = None, water_depth_front: float | None = None,
                  layers_table: dict | None = None) -> Ground | None:
    """The backfill the ``theory`` command describes, or None for today's dry, uniform,
    cohesionless fill. ``layers_table`` (a parsed ``[[layer]]`` TOML) replaces the
    uniform soil; cohesion is then given per layer."""
    water = {"water_depth": water_depth, "water_depth_front": water_depth_front}
    if layers_table is not None:
        if c_kPa:
            raise InvalidParameter("c", c_kPa, "0 with --layers", "give c per layer in the file")
        if gamma_sat_kN is not None:
            raise InvalidParameter("gamma-sat", gamma_sat_kN, "unset with --layers", "give gamma_sat per layer")
        ground = Ground(layers_from_table(layers_table), **water)
        ground.check_height(H)
        return ground
    if not c_kPa and gamma_sat_kN is None and water_depth is None and water_depth_front is None:
        return None
    gs = None if gamma_sat_kN is None else gamma_sat_kN * 1e3
    return Ground.uniform(H, soil.phi_deg, soil.unit_weight, c_kPa * 1e3, gs, **water)


def theory_loads(line_specs: list[str], strip_specs: list[str]) -> dict:
    """``--line-load Q,X`` [kN/m, m] and ``--strip-load Q,X1,X2`` [kPa, m, m] strings as
    {"line_loads": (LineLoad, ...), "strip_loads": (StripLoad, ...)} in N and Pa."""
    def numbers(name, text, n, form):
        parts = str(text).split(",")
        if len(parts) != n:
            raise InvalidParameter(name, text, form)
        return [require_number(name, p.strip()) for p in parts]

    lines = tuple(LineLoad(Q * 1e3, x) for Q, x in
                  (numbers("line-load", t, 2, "Q,X with Q in kN/m and X in m") for t in line_specs))
    strips = tuple(StripLoad(q * 1e3, x1, x2) for q, x1, x2 in
                   (numbers("strip-load", t, 3, "Q,X1,X2 with Q in kPa and 0 <= X1 < X2 in m")
                    for t in strip_specs))
    return {"line_loads": lines, "strip_loads": strips}
