"""Wall sections and their self-weight: cantilever, gravity (trapezoid or polygon) and
block (dry-stone) walls.

Units: lengths in m, unit weights in kN/m3, angles in degrees; forces per metre run.
Coordinates (see ``geometry.py``): x from the toe toward the backfill, y up from the
underside of the base at the toe. ``B`` is the base width, the heel is at x = B.

The back a thrust acts on (``WallBack``) is the *virtual back* (the vertical plane
through the heel, from the underside of the base to the fill surface; the fill between
it and the wall moves with the wall and counts as weight) or the *real back* (the
wall's back face, gravity and block walls). See ``earth.py`` for the thrust itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InvalidParameter
from ..inputs import MAX_HEIGHT_M, MAX_UNIT_WEIGHT_KN_M3, require_number
from .geometry import Point, area_centroid, clip_above


@dataclass(frozen=True)
class WallBack:
    """A plane the backfill pushes on: bottom point (x0, y0) [m], vertical height
    ``height`` [m] up to the fill surface, inclination ``omega`` [deg] from vertical,
    positive when the bottom lies further into the fill than the top (the fill rests on
    the face; analytic/inputs.py convention). ``virtual`` marks the vertical plane
    through the heel."""

    x0: float
    y0: float
    height: float
    omega: float = 0.0
    virtual: bool = False

    def point_at(self, y: float) -> Point:
        """The point of the back at height y [m] above the base underside."""
        return self.x0 - (y - self.y0) * math.tan(math.radians(self.omega)), y


@dataclass(frozen=True)
class Part:
    """A solid part of the wall or of the fill that moves with it: its polygon [m],
    unit weight [kN/m3] and source ('structural' concrete/masonry, 'geotechnical' fill;
    EN 1997-1 DA3 factors the two differently)."""

    name: str
    polygon: tuple[Point, ...]
    unit_weight: float
    source: str

    @property
    def weight(self) -> float:
        """Weight [kN/m]."""
        return area_centroid(list(self.polygon))[0] * self.unit_weight

    @property
    def centroid(self) -> Point:
        a, x, y = area_centroid(list(self.polygon))
        return x, y


def _length(name: str, value, *, positive: bool = False) -> float:
    """A wall dimension [m], within physical sense (MAX_HEIGHT_M: no wall is 100 m high)."""
    return require_number(f"wall.{name}", value, 0.0, MAX_HEIGHT_M, lo_open=positive, hi_open=False, unit="m")


@dataclass(frozen=True)
class CantileverWall:
    """Reinforced-concrete cantilever wall: a stem on a base slab.

    height: underside of the base to the top of the stem [m]; stem_top, stem_base:
    stem thickness at top and at the top of the base [m]; back_batter: how much of the
    thickening is on the back face [m] (the rest is on the front face, as in Das's
    examples); toe, heel: base projections in front of and behind the stem [m];
    base_thickness [m]; unit_weight [kN/m3]; optional shear key under the base
    (key_depth, key_width [m], its front at key_x from the toe, default under the stem).
    """

    height: float
    stem_top: float
    stem_base: float
    toe: float
    heel: float
    base_thickness: float
    unit_weight: float = 24.0
    back_batter: float = 0.0
    key_depth: float = 0.0
    key_width: float = 0.0
    key_x: float | None = None
    kind = "cantilever"

    def __post_init__(self):
        H = _length("height", self.height, positive=True)
        tb = _length("base_thickness", self.base_thickness, positive=True)
        if tb >= H:
            raise InvalidParameter("wall.base_thickness", tb, f"(0, height = {H:g}) m")
        st = _length("stem_top", self.stem_top, positive=True)
        sb = _length("stem_base", self.stem_base, positive=True)
        if sb < st:
            raise InvalidParameter("wall.stem_base", sb, f">= stem_top = {st:g} m")
        bb = _length("back_batter", self.back_batter)
        if bb > sb - st + 1e-12:
            raise InvalidParameter("wall.back_batter", bb, f"[0, stem_base - stem_top = {sb - st:g}] m")
        _length("toe", self.toe)
        _length("heel", self.heel)
        require_number("wall.unit_weight", self.unit_weight, 0.0, MAX_UNIT_WEIGHT_KN_M3, hi_open=False, unit="kN/m3")
        _length("key_depth", self.key_depth)
        _length("key_width", self.key_width)
        if self.key_x is not None and not 0 <= self.key_x <= self.B - self.key_width:
            raise InvalidParameter("wall.key_x", self.key_x, f"[0, B - key_width = {self.B - self.key_width:g}] m")

    @property
    def B(self) -> float:
        """Base width toe + stem_base + heel [m]."""
        return self.toe + self.stem_base + self.heel

    @property
    def H(self) -> float:
        return self.height

    def _stem(self) -> tuple[Point, Point, Point, Point]:
        """Stem corners: front-bottom, back-bottom, back-top, front-top."""
        t, tb, H = self.toe, self.base_thickness, self.height
        front_top = t + (self.stem_base - self.stem_top - self.back_batter)
        return (t, tb), (t + self.stem_base, tb), (front_top + self.stem_top, H), (front_top, H)

    def parts(self) -> list[Part]:
        """Concrete parts: base slab, stem, shear key."""
        B, tb, g = self.B, self.base_thickness, self.unit_weight
        out = [Part("base", ((0, 0), (B, 0), (B, tb), (0, tb)), g, "structural"),
               Part("stem", self._stem(), g, "structural")]
        if self.key_depth > 0 and self.key_width > 0:
            x = self.toe + self.stem_base - self.key_width if self.key_x is None else self.key_x
            d = self.key_depth
            out.append(Part("key", ((x, -d), (x + self.key_width, -d), (x + self.key_width, 0), (x, 0)),
                            g, "structural"))
        return out

    def fill_top(self) -> Point:
        """Where the fill surface meets the wall: the top of the stem's back face."""
        return self._stem()[2]

    def fill_parts(self, beta_deg: float, gamma: float) -> list[Part]:
        """Fill between the stem's back face and the virtual back (with the wedge of a
        sloping surface), moving with the wall [kN/m3 -> Part]."""
        _, bb, bt, _ = self._stem()
        B = self.B
        top = bt[1] + (B - bt[0]) * math.tan(math.radians(beta_deg))
        return [Part("fill over heel", (bb, (B, bb[1]), (B, top), bt), gamma, "geotechnical")]

    def virtual_back(self, beta_deg: float) -> WallBack:
        """Vertical plane through the heel, from the base underside to the fill surface."""
        bt = self.fill_top()
        return WallBack(self.B, 0.0, bt[1] + (self.B - bt[0]) * math.tan(math.radians(beta_deg)),
                        virtual=True)

    def real_back(self) -> WallBack:
        raise InvalidParameter("method.earth_pressure", "coulomb on the real back of a cantilever",
                               "the virtual back (coulomb and rankine act there for cantilevers)")

    def with_dimension(self, name: str, value: float) -> "CantileverWall":
        """A copy with toe, heel or base (= toe and heel scaled together) changed [m]."""
        from dataclasses import replace
        if name == "base":
            s = value / (self.toe + self.heel) if self.toe + self.heel > 0 else 1.0
            return replace(self, toe=self.toe * s, heel=self.heel * s)
        return replace(self, **{name: value})


@dataclass(frozen=True)
class GravityWall:
    """Mass-concrete or masonry gravity wall: a trapezoid with front and back batter,
    or any polygon.

    Trapezoid: height H [m], crest (top width) [m], base width [m], back_batter [m] =
    horizontal offset of the back face's top from the heel (positive: top nearer the
    front, fill resting on the face, omega > 0). The front batter is what remains:
    base - crest - back_batter >= 0. Polygon: vertices [m] with the toe at (0, 0) and the
    heel at (max x, 0); its thrust acts on the virtual back (vertical through the heel).
    """

    height: float
    crest: float = 0.0
    base: float = 0.0
    back_batter: float = 0.0
    unit_weight: float = 24.0
    polygon: tuple[Point, ...] | None = None
    kind = "gravity"

    def __post_init__(self):
        require_number("wall.unit_weight", self.unit_weight, 0.0, MAX_UNIT_WEIGHT_KN_M3, hi_open=False, unit="kN/m3")
        if self.polygon is not None:
            self._check_polygon()
            return
        _length("height", self.height, positive=True)
        _length("crest", self.crest, positive=True)
        b = _length("base", self.base, positive=True)
        bb = require_number("wall.back_batter", self.back_batter, -self.base, self.base, unit="m")
        if b < self.crest + max(bb, 0.0) - 1e-12:
            raise InvalidParameter("wall.base", b, f">= crest + back_batter = {self.crest + max(bb, 0):g} m",
                                   "a base narrower than the wall above it")

    def _check_polygon(self):
        pts = [(float(x), float(y)) for x, y in self.polygon]
        if len(pts) < 3 or area_centroid(pts)[0] <= 0:
            raise InvalidParameter("wall.polygon", len(pts), ">= 3 vertices enclosing an area")
        if min(p[1] for p in pts) < 0 or min(p[0] for p in pts) < 0:
            raise InvalidParameter("wall.polygon", "negative coordinate", "x >= 0 and y >= 0 m (toe at (0, 0))")
        top = max(p[1] for p in pts)
        if self.height and abs(self.height - top) > 1e-9:     # one geometry per wall
            raise InvalidParameter("wall.height", self.height, f"the polygon's top, {top:g} m, or left out",
                                   "a polygon and a height that disagree")
        for name in ("crest", "base", "back_batter"):
            if getattr(self, name):
                raise InvalidParameter(f"wall.{name}", getattr(self, name), "left out with a polygon",
                                       "the polygon is the whole geometry")

    @property
    def B(self) -> float:
        if self.polygon is not None:
            return max(p[0] for p in self.polygon if abs(p[1]) < 1e-9)
        return self.base

    @property
    def H(self) -> float:
        return max(p[1] for p in self.polygon) if self.polygon is not None else self.height

    def _corners(self) -> tuple[Point, ...]:
        B, H, bb = self.base, self.height, self.back_batter
        return (0.0, 0.0), (B, 0.0), (B - bb, H), (B - bb - self.crest, H)

    def parts(self) -> list[Part]:
        poly = tuple(self.polygon) if self.polygon is not None else self._corners()
        return [Part("wall", poly, self.unit_weight, "structural")]

    def fill_top(self) -> Point:
        if self.polygon is not None:
            top = max(p[1] for p in self.polygon)
            return max((p for p in self.polygon if abs(p[1] - top) < 1e-9), key=lambda p: p[0])
        return self._corners()[2]

    def fill_parts(self, beta_deg: float, gamma: float) -> list[Part]:
        """Fill between the back face (the polygon's boundary from the heel up to its
        highest back point) and the virtual back; none for a vertical back."""
        B, (xt, yt) = self.B, self.fill_top()
        if xt >= B - 1e-12:
            return []
        top = yt + (B - xt) * math.tan(math.radians(beta_deg))
        chain = self._back_chain() if self.polygon is not None else [(B, 0.0), (xt, yt)]
        return [Part("fill on back", tuple(chain) + ((B, top),), gamma, "geotechnical")]

    def _back_chain(self) -> list[Point]:
        """Polygon vertices from the heel (B, 0) up the back to the fill top, the way
        round that does not pass the toe."""
        pts = [(float(x), float(y)) for x, y in self.polygon]
        n = len(pts)
        i_h = pts.index(max((p for p in pts if abs(p[1]) < 1e-9), key=lambda p: p[0]))
        i_t = pts.index(self.fill_top())
        i_toe = pts.index(min((p for p in pts if abs(p[1]) < 1e-9), key=lambda p: p[0]))
        for step in (1, -1):
            path, i = [i_h], i_h
            while i != i_t:
                i = (i + step) % n
                path.append(i)
            if i_toe not in path:
                return [pts[k] for k in path]
        raise InvalidParameter("wall.polygon", "its vertices", "a toe at (0, 0), a heel at (B, 0) and a back "
                               "rising from the heel to the top")

    def virtual_back(self, beta_deg: float) -> WallBack:
        xt, yt = self.fill_top()
        return WallBack(self.B, 0.0, yt + max(self.B - xt, 0.0) * math.tan(math.radians(beta_deg)), virtual=True)

    def real_back(self) -> WallBack:
        xt, yt = self.fill_top()
        return WallBack(self.B, 0.0, yt, math.degrees(math.atan2(self.B - xt, yt)))

    def with_dimension(self, name: str, value: float) -> "GravityWall":
        """A copy with the base width changed (the front face moves) [m]."""
        from dataclasses import replace
        if name != "base" or self.polygon is not None:
            raise InvalidParameter("solve", name, "'base' for a trapezoidal gravity wall")
        return replace(self, base=value)
