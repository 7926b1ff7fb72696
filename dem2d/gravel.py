"""Elongated gravel grains for the dry-stone case B, on pymunk.

Colas's backfill as Oetomo et al. model it (S-OET, docs/reference/drystone-walls.md
3.1): grains of aspect ratio AR = 2.5, linear grading of widths 10-16 mm, local friction
45 deg, interface (fill-block) friction 25 deg, initial porosity n0 = 0.22 reached by
placing with a temporary local friction of 15.6 deg and then restoring it.

Grain shape: a **capsule** (a pymunk Segment with a radius: a rectangle w x (L - w) with
two half-disk caps, L = AR w). One shape per grain, and pymunk's segment-segment
collision is as cheap as circle-circle: a probe ran capsules at 112 steps per
CPU-second at 5k grains with the spatial hash against about half that for three-circle
clumps of the same outline. A capsule has a straight flank (no clump "bumps", so no
artificial interlocking that the clumps' overlap would set) and its contact normal is
well defined everywhere. S-OET used disk clumps in PFC2D; the outline is the same
elongated, rounded shape.

Friction is set through ``blocks.pair_friction`` (one table for fill-fill, fill-block
and, where blocks meet, block-block): ``FILL_TYPE`` is the grain collision type of
``build.GRAIN_TYPE``, blocks keep ``blocks.BLOCK_TYPE``.

Other shapes (``Gravel.shape``, for the grain-shape probe of
docs/validation/gravel_calibration_discussion.md), all in the same L x w = AR w x w envelope:

* ``"clump3"``: three overlapping circles of diameter w on one body, centres (AR - 1) w / 2
  apart along the axis (S-OET's grains are disk clumps; the waist between two circles is
  0.66 w wide at AR 2.5: the clump's "bumps"). Mass and moment from the union
  (``build.union_mass_properties``). Needs AR < 3 for the circles to overlap.
* ``"hexagon"``: an elongated hexagon (90 deg tips, flat flanks) rounded by a radius
  ``HEX_ROUND`` w (a pymunk Poly with a radius): angular, yet with a defined normal at
  the corners.

* ``Gravel``          the material (grading, AR, shape, density, frictions)
* ``capsule_area``    area of one capsule [m^2 per m]; ``grain_area`` of any shape
* ``add_capsules``    grains into a space, with the table's shape frictions; ``add_grains``
  any shape
* ``register_capsules`` capsules in a ``build.Grains`` registry (as their end circles, for
  frames); ``register_grains`` any shape
* ``set_fill_friction`` change the fill-fill friction (placement) through the table
* ``GravelBox``       a rigid box filled by placement at lowered friction, then restored
* ``porosity``        2D porosity of a window (centre-in-window area count)

Pure engine: no files, no printing. SI units, angles in degrees at the interface.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import pymunk

from analytic.errors import InvalidParameter
from analytic.inputs import require_number
from analytic.schema import check_fields, param

from analytic.constants import G

from .blocks import BLOCK_TYPE, BlockSolver, new_block_space, pair_friction
from .build import GRAIN_TYPE, Grains, union_mass_properties
from .grading import Grading

FILL_TYPE = GRAIN_TYPE
#: grain shapes (module docstring)
SHAPES = ("capsule", "clump3", "hexagon")
#: corner radius of the ``"hexagon"`` grain, as a fraction of its width [-]
HEX_ROUND = 0.1


@dataclass(frozen=True)
class Gravel:
    """The backfill gravel (S-OET, reference 3.1): grading, grain shape, density and local
    frictions."""

    # the grain count of a box goes as 1 / w^2: 1 mm grains put ~4e5 grains in the 0.7 x 1.4 m
    # biaxial specimen (~1.4 GB at ~3.4 KB a pymunk grain; ~1 h a test at 3.8e5 grain-steps
    # per CPU-s); the case-B fill bounds its own grains tighter (BackfillSettings)
    width_min_m: float = param(0.010, unit="m", lo=0.001, hi=1, hi_open=True,
                               meaning="smallest grain width of the linear grading by mass (S-OET: 10 mm)")
    width_max_m: float = param(0.016, unit="m", lo=0.001, hi=1, hi_open=True,
                               meaning="largest grain width of the grading, >= width_min_m (S-OET: 16 mm)")
    aspect_ratio: float = param(2.5, lo=1, hi=10, meaning="grain length / width (S-OET: 2.5; clump3 below 3)")
    # ASSUMPTION: 1947, so that the bulk unit weight at n = 0.22 is the measured loose 14.9 kN/m^3
    # (rho = 14900 / (g (1 - 0.22))); 2D grains have no 3D solid density
    density: float = param(14900.0 / (G * 0.78), unit="kg/m^3", lo=0, lo_open=True,
                           meaning="solid density per m of wall (ASSUMPTION 1947: the loose 14.9 kN/m^3 at n = 0.22)")
    # S-OET's 45 is calibrated for PFC's soft contacts; ours for rigid rounded hexagons, 50, is in
    # the case-B settings (docs/validation/gravel_calibration.md)
    friction_deg: float = param(45.0, unit="deg", lo=0, hi=89,
                                meaning="local fill-fill friction angle while shearing (S-OET: 45)")
    interface_friction_deg: float = param(25.0, unit="deg", lo=0, hi=89,
                                          meaning="local fill-block friction angle (S-OET: 25)")
    placement_friction_deg: float = param(15.6, unit="deg", lo=0, hi=89,
                                          meaning="fill-fill friction angle while the grains are placed (S-OET: 15.6)")
    shape: Literal["capsule", "clump3", "hexagon"] = param(
        "capsule", unit="", meaning="grain shape: capsule, clump3 (three circles) or hexagon (rounded; dem2d.gravel)")

    def __post_init__(self):
        check_fields(self)
        if self.shape == "clump3" and not self.aspect_ratio < 3.0:
            raise InvalidParameter("aspect_ratio", self.aspect_ratio, "[1, 3) for clump3",
                                   "three circles of diameter w overlap only below AR 3")
        if not self.width_max_m >= self.width_min_m:
            raise InvalidParameter("width_max_m", self.width_max_m, f"[{self.width_min_m:g}, 1) m",
                                   "the largest grain is at least the smallest")

    @property
    def grading(self) -> Grading:
        """Widths as a ``Grading`` (linear by mass; mass ~ w^2 at fixed AR, as a disk's):
        D50 = (w_min + w_max) / 2, Cu = (w_min + 0.6 dw) / (w_min + 0.1 dw)."""
        dw = self.width_max_m - self.width_min_m
        return Grading((self.width_min_m + self.width_max_m) / 2,
                       (self.width_min_m + 0.6 * dw) / (self.width_min_m + 0.1 * dw))

    def table(self, fill_friction_deg: float | None = None) -> dict[tuple[int, int], float]:
        """Pair-friction table (coefficients) for ``blocks.pair_friction``."""
        phi = self.friction_deg if fill_friction_deg is None else fill_friction_deg
        return {(FILL_TYPE, FILL_TYPE): math.tan(math.radians(phi)),
                (FILL_TYPE, BLOCK_TYPE): math.tan(math.radians(self.interface_friction_deg))}


def capsule_area(width, aspect_ratio: float = 2.5):
    """Area of a capsule of width w and length AR w [m^2]: pi w^2/4 + w (AR - 1) w."""
    w = np.asarray(width, dtype=float)
    return math.pi * w * w / 4 + (aspect_ratio - 1.0) * w * w


def _lens(d: float, r: float) -> float:
    """Area of the overlap of two circles of radius r whose centres are d apart [m^2]."""
    if d >= 2 * r:
        return 0.0
    return 2 * r * r * math.acos(d / (2 * r)) - d / 2 * math.sqrt(4 * r * r - d * d)


def hexagon_vertices(width: float, aspect_ratio: float) -> np.ndarray:
    """Core vertices (6,2) of the ``"hexagon"`` grain [m], before the rounding radius
    ``HEX_ROUND`` w: outline L = AR w by w, tips of 90 deg, flanks along the axis."""
    rho = HEX_ROUND * width
    a, c = aspect_ratio * width / 2 - rho, width / 2 - rho
    b = a - c
    return np.array([(a, 0.0), (b, c), (-b, c), (-a, 0.0), (-b, -c), (b, -c)])


def clump_offsets(width: float, aspect_ratio: float) -> np.ndarray:
    """Circle centres (3,2) of the ``"clump3"`` grain [m] (radius w/2 each)."""
    d = (aspect_ratio - 1.0) * width / 2
    return np.array([(-d, 0.0), (0.0, 0.0), (d, 0.0)])


def grain_area(width, aspect_ratio: float = 2.5, shape: str = "capsule"):
    """Area of one grain of width w [m^2] for each ``SHAPES`` (module docstring):
    capsule ``capsule_area``; clump3 3 pi w^2/4 - 2 lens(d = (AR - 1) w/2); hexagon the
    rounded hexagon (core area + perimeter rho + pi rho^2)."""
    w = np.asarray(width, dtype=float)
    if shape == "capsule":
        return capsule_area(w, aspect_ratio)
    if shape == "clump3":
        return (3 * math.pi / 4 - 2 * _lens((aspect_ratio - 1.0) / 2, 0.5)) * w * w
    return pymunk.area_for_poly([tuple(p) for p in hexagon_vertices(1.0, aspect_ratio)], HEX_ROUND) * w * w


@functools.lru_cache(maxsize=8)
def _hexagon_gyration(aspect_ratio: float, resolution: int = 800) -> float:
    """Squared radius of gyration of the rounded hexagon at width 1 [m^2] (rasterised:
    pymunk's moment_for_poly leaves the rounding radius out)."""
    v = hexagon_vertices(1.0, aspect_ratio)
    h = aspect_ratio / resolution
    X, Y = np.meshgrid(np.arange(-aspect_ratio / 2, aspect_ratio / 2, h) + h / 2, np.arange(-0.5, 0.5, h) + h / 2)
    P = np.c_[X.ravel(), Y.ravel()]
    inside = np.ones(len(P), bool)
    dist = np.full(len(P), np.inf)
    for a, b in zip(v, np.roll(v, -1, axis=0)):
        e = b - a
        inside &= (e[0] * (P[:, 1] - a[1]) - e[1] * (P[:, 0] - a[0])) >= 0     # ccw: left of every edge
        t = np.clip(((P - a) @ e) / (e @ e), 0.0, 1.0)
        dist = np.minimum(dist, np.hypot(*(P - a - t[:, None] * e).T))
    q = P[inside | (dist <= HEX_ROUND)]
    return float((q ** 2).sum(axis=1).mean())


@functools.lru_cache(maxsize=8)
def _clump_gyration(aspect_ratio: float) -> float:
    """Squared radius of gyration of the clump3 union at width 1 [m^2] (rasterised)."""
    m, i, _ = union_mass_properties(clump_offsets(1.0, aspect_ratio), np.full(3, 0.5), 1.0, resolution=600)
    return i / m


def grain_outline(gravel: Gravel, points: int = 12) -> np.ndarray:
    """Outline of a grain of width 1 in its body frame (k,2) [m per m of width], to be
    scaled by each grain's width: the hexagon's core vertices pushed out by the rounding
    radius along the corner bisectors, the capsule as its stadium, the clump3 as the hull
    of its end circles (a stadium as well). For drawing, not for physics."""
    ar = gravel.aspect_ratio
    if gravel.shape == "hexagon":
        v = hexagon_vertices(1.0, ar)
        mid = (np.roll(v, 1, axis=0) + np.roll(v, -1, axis=0)) / 2
        out = v - mid
        norm = np.hypot(*out.T)[:, None]
        return v + HEX_ROUND * out / np.where(norm > 0, norm, 1.0)
    half = (ar - 1.0) / 2          # end-circle centres at +-half, radius 1/2
    t = np.linspace(-math.pi / 2, math.pi / 2, points // 2)
    right = np.c_[half + 0.5 * np.cos(t), 0.5 * np.sin(t)]
    return np.vstack([right, -right])


def grain_outlines(positions: np.ndarray, angles: np.ndarray, widths: np.ndarray, gravel: Gravel) -> np.ndarray:
    """Every grain's outline in world coordinates (n,k,2) [m] (``grain_outline``)."""
    base = grain_outline(gravel)
    c, s = np.cos(angles), np.sin(angles)
    local = widths[:, None, None] * base[None]
    x = local[..., 0] * c[:, None] - local[..., 1] * s[:, None]
    y = local[..., 0] * s[:, None] + local[..., 1] * c[:, None]
    return np.stack([x, y], axis=-1) + positions[:, None, :]


def add_grains(space: pymunk.Space, centres: np.ndarray, angles: np.ndarray, widths: np.ndarray,
               gravel: Gravel, friction: float) -> list[pymunk.Body]:
    """``add_capsules`` for any ``gravel.shape``: one dynamic body per grain, mass from
    ``grain_area`` (overlaps of the clump counted once), the shapes at ``friction``."""
    if gravel.shape == "capsule":
        return add_capsules(space, centres, angles, widths, gravel, friction)
    bodies, objs = [], []
    ar = gravel.aspect_ratio
    for c, a, w in zip(np.asarray(centres, float), np.asarray(angles, float), np.asarray(widths, float)):
        m = gravel.density * float(grain_area(w, ar, gravel.shape))
        if gravel.shape == "clump3":
            body = pymunk.Body(m, m * w * w * _clump_gyration(ar))
            shapes = [pymunk.Circle(body, w / 2, offset=tuple(o)) for o in clump_offsets(w, ar)]
        else:
            verts = [tuple(p) for p in hexagon_vertices(w, ar)]
            body = pymunk.Body(m, m * w * w * _hexagon_gyration(ar))
            shapes = [pymunk.Poly(body, verts, radius=HEX_ROUND * w)]
        body.position = (float(c[0]), float(c[1]))
        body.angle = float(a)
        for sh in shapes:
            sh.friction, sh.elasticity, sh.collision_type = friction, 0.0, FILL_TYPE
        objs += [body, *shapes]
        bodies.append(body)
    space.add(*objs)
    return bodies


def register_grains(grains: Grains, bodies: list[pymunk.Body], widths: np.ndarray, gravel: Gravel) -> None:
    """``register_capsules`` for any shape: clumps as their circles, hexagons as polygons."""
    if gravel.shape == "capsule":
        return register_capsules(grains, bodies, widths, gravel)
    first = len(grains)
    w = np.asarray(widths, float)
    if gravel.shape == "clump3":
        off = np.concatenate([clump_offsets(x, gravel.aspect_ratio) for x in w]) if len(w) else np.zeros((0, 2))
        grains._extend(list(bodies), np.repeat(np.arange(first, first + len(bodies)), 3), off, np.repeat(w / 2, 3))
        return None
    for j, x in enumerate(w):
        grains.polys.append((first + j, hexagon_vertices(x, gravel.aspect_ratio)))
    grains._extend(list(bodies), [], np.zeros((0, 2)), [])
    return None


def add_capsules(space: pymunk.Space, centres: np.ndarray, angles: np.ndarray, widths: np.ndarray,
                 gravel: Gravel, friction: float) -> list[pymunk.Body]:
    """One dynamic capsule per grain: centre (n,2) [m], axis angle (n,) [rad], width (n,) [m];
    ``friction`` is the shape value that ``pair_friction`` returned for FILL_TYPE. The
    moment is pymunk's ``moment_for_segment``, that of the L x w rectangle: 15 % above
    the capsule's own at AR 2.5 (the calibration ran with it; the other shapes of
    ``add_grains`` take their outline's)."""
    bodies = []
    for c, a, w in zip(np.asarray(centres, float), np.asarray(angles, float), np.asarray(widths, float)):
        r = w / 2
        half = (gravel.aspect_ratio - 1.0) * w / 2      # half the segment between cap centres
        m = gravel.density * float(capsule_area(w, gravel.aspect_ratio))
        body = pymunk.Body(m, pymunk.moment_for_segment(m, (-half, 0.0), (half, 0.0), r))
        body.position = (float(c[0]), float(c[1]))
        body.angle = float(a)
        shape = pymunk.Segment(body, (-half, 0.0), (half, 0.0), r)
        shape.friction = friction
        shape.elasticity = 0.0
        shape.collision_type = FILL_TYPE
        space.add(body, shape)
        bodies.append(body)
    return bodies


def register_capsules(grains: Grains, bodies: list[pymunk.Body], widths: np.ndarray, gravel: Gravel) -> None:
    """Enter capsules in a ``build.Grains`` registry (frames, recordings) as their two end
    circles (radius w/2 at +-(AR - 1) w / 2 along the axis): the outline a frame draws.
    The registry's circle areas are not the capsule areas (``capsule_area`` is)."""
    w = np.asarray(widths, float)
    half = (gravel.aspect_ratio - 1.0) * w / 2
    first = len(grains)
    idx = np.repeat(np.arange(first, first + len(bodies)), 2)
    off = np.zeros((2 * len(bodies), 2))
    off[0::2, 0], off[1::2, 0] = -half, half
    grains._extend(list(bodies), idx, off, np.repeat(w / 2, 2))


def set_fill_friction(space: pymunk.Space, gravel: Gravel, fill_friction_deg: float | None = None, *,
                      handler: bool = False) -> dict[int, float]:
    """Give every shape of the space the shape friction of ``gravel.table(fill_friction_deg)``
    (placement at a lowered friction, then restored), through ``blocks.pair_friction``."""
    values = pair_friction(space, gravel.table(fill_friction_deg), handler=handler)
    for shape in space.shapes:
        if shape.collision_type in values:
            shape.friction = values[shape.collision_type]
    return values


def cloud(n: int, width: float, gravel: Gravel) -> tuple[np.ndarray, float]:
    """Centres (n,2) [m] of a sparse cloud over [0, width]: one grain per square cell of
    side 1.05 L_max (any orientation fits, none overlap), rows upward from y = 0; and the cell."""
    cell = 1.05 * gravel.aspect_ratio * gravel.width_max_m
    cols = max(int(width // cell), 1)
    i = np.arange(n)
    return np.c_[(i % cols + 0.5) * (width / cols), (i // cols + 0.5) * cell], cell


def _new_space(solver: BlockSolver, cell: float, n: int) -> pymunk.Space:
    space = new_block_space(solver)
    space.use_spatial_hash(cell, max(4 * n, 1000))
    return space


@dataclass
class GravelBox:
    """A rigid box (floor and two sides, static, BLOCK_TYPE: the fill-block friction) of
    inner width ``width_m`` filled with capsules up to about ``height_m``.

    ``place`` drops a sparse cloud of randomly oriented grains (one grain per cell of size
    1.05 L_max, so none overlap) at the placement friction, settles it, restores the local
    friction and settles again (S-OET's procedure).

    Measured (0.90 x 0.50 m, 962 grains, seed 1, dt 5e-4 s, 10 iterations, window one
    grain length in from the sides and floor): porosity 0.146 with S-OET's 15.6 deg
    placement friction, 0.218 placing at 45 deg (no lowering), 0.092 at 0 deg. Rigid
    contacts pack denser than PFC's soft ones at the same friction, so S-OET's 15.6 deg
    does not carry over: n0 = 0.22 needs a placement friction near 45 deg here."""

    gravel: Gravel
    width_m: float
    height_m: float
    solver: BlockSolver = field(default_factory=lambda: BlockSolver(dt=5e-4, iterations=10))
    seed: int = 0
    space: pymunk.Space = None
    bodies: list = field(default_factory=list)
    widths: np.ndarray = None
    time: float = 0.0
    steps: int = 0

    def __post_init__(self):
        require_number("width", self.width_m, 0.0, 100.0, unit="m")
        require_number("height", self.height_m, 0.0, 100.0, unit="m")

    def n_grains_for(self, porosity: float = 0.22) -> int:
        """Grains that fill width x height at ``porosity`` (mean area of the grading)."""
        w = self.gravel.grading.sample(20000, np.random.default_rng(12345))
        g = self.gravel
        return int(round(self.width_m * self.height_m * (1 - porosity) / grain_area(w, g.aspect_ratio, g.shape).mean()))

    def place(self, porosity: float = 0.22, settle_s: float = 1.0, restore_s: float = 0.5,
              ke_per_grain: float = 1e-5) -> None:
        """Fill the box (the number of grains for ``porosity``), settle at the placement
        friction, then at the local one. Settling stops early once the kinetic energy per
        grain is below ``ke_per_grain`` [J/m]."""
        g, rng = self.gravel, np.random.default_rng(self.seed)
        n = self.n_grains_for(porosity)
        xy, cell = cloud(n, self.width_m, g)
        self.space = _new_space(self.solver, cell, n)
        self._add_box(xy[:, 1].max() + cell + self.height_m)
        self.widths = g.grading.sample(n, rng)
        fr = set_fill_friction(self.space, g, g.placement_friction_deg)
        self.bodies = add_grains(self.space, xy, rng.uniform(0, math.pi, n), self.widths, g,
                                   fr.get(FILL_TYPE, 1.0))
        self.settle(settle_s, ke_per_grain)
        set_fill_friction(self.space, g)
        self.settle(restore_s, ke_per_grain)

    def _add_box(self, top: float) -> None:
        t = 0.05
        for a, b in (((-t, -t), (self.width_m + t, -t)), ((-t, -t), (-t, top)),
                     ((self.width_m + t, -t), (self.width_m + t, top))):
            s = pymunk.Segment(self.space.static_body, a, b, t)
            s.collision_type = BLOCK_TYPE
            s.elasticity = 0.0
            self.space.add(s)

    def kinetic_energy(self) -> float:
        """Total kinetic energy of the grains [J/m]."""
        return math.fsum(0.5 * b.mass * b.velocity.length_squared + 0.5 * b.moment * b.angular_velocity ** 2
                   for b in self.bodies)

    def settle(self, seconds: float, ke_per_grain: float = 0.0, check_s: float = 0.05) -> None:
        """Step up to ``seconds``; stop early when KE / grain < ``ke_per_grain`` [J/m]."""
        per = max(int(round(check_s / self.solver.dt)), 1)
        for _ in range(max(int(round(seconds / check_s)), 1)):
            for _ in range(per):
                self.space.step(self.solver.dt)
            self.steps += per
            self.time += per * self.solver.dt
            if self.kinetic_energy() / max(len(self.bodies), 1) < ke_per_grain:
                break

    def box_reaction(self, seconds: float = 0.1) -> np.ndarray:
        """(Fx, Fy) [N/m]: the force of the box on the grains, from the contact impulses of
        every grain-box arbiter, averaged over ``seconds`` of stepping (the impulse solver's
        step-to-step jitter averages out)."""
        n = max(int(round(seconds / self.solver.dt)), 1)
        total = np.zeros(2)
        for _ in range(n):
            self.space.step(self.solver.dt)
            total += _static_impulse(self.bodies)
        self.steps += n
        self.time += n * self.solver.dt
        return total / (n * self.solver.dt)

    def weight(self) -> float:
        """Weight of the grains [N/m]."""
        return G * math.fsum(b.mass for b in self.bodies)

    def positions(self) -> np.ndarray:
        """(n,2) grain centres [m]."""
        return np.array([tuple(b.position) for b in self.bodies]).reshape(-1, 2)

    def surface(self) -> float:
        """Fill surface [m]: the mean of the highest grain centres in each 1/8 of the width."""
        p = self.positions()
        k = np.clip((p[:, 0] / self.width_m * 8).astype(int), 0, 7)
        return float(np.mean([p[k == j, 1].max() for j in range(8) if (k == j).any()]))


def _static_impulse(bodies) -> np.ndarray:
    """Sum of the last step's contact impulses on ``bodies`` from static shapes [N s/m]."""
    out = np.zeros(2)

    def visit(arb):
        a, b = arb.shapes
        if a.body.body_type == pymunk.Body.STATIC or b.body.body_type == pymunk.Body.STATIC:
            j = arb.total_impulse       # on the first shape of the arbiter
            sign = 1.0 if a.body.body_type != pymunk.Body.STATIC else -1.0
            out[0] += sign * j.x
            out[1] += sign * j.y
    for body in bodies:
        body.each_arbiter(visit)
    return out


def porosity(centres: np.ndarray, widths: np.ndarray, aspect_ratio: float, window, shape: str = "capsule") -> float:
    """2D porosity of the window (x0, x1, y0, y1) [m]: 1 - (area of grains whose centre lies
    inside) / window area. Unbiased for a window many grains across (edge grains in and
    out cancel on average)."""
    x0, x1, y0, y1 = window
    if not (x1 > x0 and y1 > y0):
        raise InvalidParameter("window", window, "x1 > x0 and y1 > y0")
    c = np.asarray(centres, float)
    inside = (c[:, 0] >= x0) & (c[:, 0] < x1) & (c[:, 1] >= y0) & (c[:, 1] < y1)
    return float(1.0 - grain_area(np.asarray(widths)[inside], aspect_ratio, shape).sum() / ((x1 - x0) * (y1 - y0)))
