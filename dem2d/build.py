"""Building a ``pymunk.Space``: solver settings, grains (disks, clumps, polygon blocks).

Conventions (measured on pymunk 7.3.1):

* SI units; a 2D "density" is kg per m^2 of the plane = rho_s x 1 m of wall, so masses
  and forces are *per metre of wall*.
* Friction multiplies: the pair coefficient is ``shape_a.friction * shape_b.friction``.
  ``friction_split`` turns pair coefficients (mu_pp, mu_pw) into shape values.
* Insertion order matters: pymunk's bounding-box tree does not rebalance, and sorted
  insertion degenerates it. Every batch of grains is added in a seeded shuffled order
  (which also keeps serial runs bit-for-bit repeatable for a seed).
* Every dynamic body keeps the index it was created with (``Grains.bodies``); arrays
  read back through ``pymunk.batch`` are mapped to that order by body id
  (``frames.py``), never by pymunk's internal order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pymunk

from analytic.constants import G
from analytic.errors import InvalidParameter

from .params import Material, Solver

#: collision type of every grain shape; panels get their own types (walls.py)
GRAIN_TYPE = 1


def friction_split(mu_pp: float, mu_pw: float) -> tuple[float, float]:
    """Shape friction values (grain, wall) such that pymunk's product rule gives the
    pair coefficients: grain*grain = mu_pp and grain*wall = mu_pw.
    grain = sqrt(mu_pp), wall = mu_pw / sqrt(mu_pp)."""
    if mu_pp <= 0.0:
        if mu_pw > 0.0:
            raise InvalidParameter("wall_friction", mu_pw, "0 when friction = 0",
                                   "pymunk multiplies shape frictions")
        return 0.0, 0.0
    g = math.sqrt(mu_pp)
    return g, mu_pw / g


def new_space(solver: Solver, *, gravity: tuple[float, float] = (0.0, -G),
              r_min: float, d_max: float, expected_shapes: int = 10_000) -> pymunk.Space:
    """An empty space with the solver settings applied.

    r_min:  smallest grain radius [m] (sets collision_slop = slop_fraction r_min)
    d_max:  largest grain size [m] (cell size of the spatial hash)
    expected_shapes: capacity hint for the spatial hash
    """
    space = pymunk.Space(threaded=solver.threads > 1)
    if solver.threads > 1:
        space.threads = solver.threads
    space.gravity = gravity
    space.iterations = solver.iterations
    space.collision_slop = solver.slop_fraction * r_min
    space.collision_bias = solver.collision_bias
    space.sleep_time_threshold = math.inf  # sleeping freezes contact impulses: never while measuring
    space.damping = 1.0
    if solver.spatial_hash:
        space.use_spatial_hash(d_max, max(4 * expected_shapes, 1000))
    return space


@dataclass
class Grains:
    """Registry of the dynamic grains of a space, in creation order.

    bodies:       one pymunk Body per grain
    circle_body:  (c,) index of the owning body for every circle shape
    circle_offset:(c,2) circle centre in the body frame [m]
    circle_radius:(c,) circle radius [m]
    polys:        (body index, local vertices (k,2)) for polygon grains
    """

    bodies: list = field(default_factory=list)
    circle_body: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    circle_offset: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    circle_radius: np.ndarray = field(default_factory=lambda: np.zeros(0))
    polys: list = field(default_factory=list)
    _ids_sorted: np.ndarray | None = None
    _rows: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.bodies)

    def _extend(self, bodies, cb, off, rad) -> None:
        self.bodies.extend(bodies)
        self.circle_body = np.concatenate([self.circle_body, np.asarray(cb, dtype=np.int64)])
        self.circle_offset = np.vstack([self.circle_offset, np.asarray(off, dtype=float).reshape(-1, 2)])
        self.circle_radius = np.concatenate([self.circle_radius, np.asarray(rad, dtype=float)])
        self._ids_sorted = None

    def id_map(self) -> tuple[np.ndarray, np.ndarray]:
        """(sorted body ids, creation index of each sorted id): for mapping batch rows."""
        if self._ids_sorted is None:
            ids = np.array([b.id for b in self.bodies], dtype=np.uintp)
            order = np.argsort(ids, kind="stable")
            self._ids_sorted, self._rows = ids[order], order
        return self._ids_sorted, self._rows

    def masses(self) -> np.ndarray:
        """(n,) body masses [kg per m of wall]."""
        return np.array([b.mass for b in self.bodies])

    def __getstate__(self):
        d = dict(self.__dict__)
        d["_ids_sorted"] = None  # body ids are addresses: never valid after unpickling
        d["_rows"] = None
        return d


def _shuffled(n: int, rng: np.random.Generator) -> np.ndarray:
    order = np.arange(n)
    rng.shuffle(order)
    return order


def _grain_shape(shape, material, friction: float, *, with_density: bool = True):
    """Give a grain's shape its material: shape friction (see ``friction_split``),
    elasticity, the grain collision type and, unless ``with_density`` is False (clump
    members, whose body mass is set from the union), the density [kg/m^2]."""
    if with_density:
        shape.density = material.density
    shape.friction = friction
    shape.elasticity = material.elasticity
    shape.collision_type = GRAIN_TYPE
    return shape


def add_disks(space: pymunk.Space, grains: Grains, centres: np.ndarray, radii: np.ndarray,
              material: Material, rng: np.random.Generator,
              velocities: np.ndarray | None = None) -> np.ndarray:
    """Add disks (one body + one Circle each) in a seeded shuffled order.

    centres (n,2) [m], radii (n,) [m]; returns the grain indices of the new bodies in
    the order of ``centres``.
    """
    centres = np.asarray(centres, dtype=float)
    radii = np.asarray(radii, dtype=float)
    f_grain, _ = friction_split(material.friction, material.wall_friction)
    first = len(grains)
    order = _shuffled(len(radii), rng)
    objs, bodies = [], []
    for k in order:
        b = pymunk.Body()
        b.position = (float(centres[k, 0]), float(centres[k, 1]))
        if velocities is not None:
            b.velocity = (float(velocities[k, 0]), float(velocities[k, 1]))
        c = _grain_shape(pymunk.Circle(b, float(radii[k])), material, f_grain)
        objs += (b, c)
        bodies.append(b)
    space.add(*objs)
    grains._extend(bodies, np.arange(first, first + len(order)), np.zeros((len(order), 2)),
                   radii[order])
    index = np.empty(len(order), dtype=np.int64)
    index[order] = np.arange(first, first + len(order))
    return index


def union_mass_properties(offsets: np.ndarray, radii: np.ndarray, density: float,
                          resolution: int = 400) -> tuple[float, float, np.ndarray]:
    """(mass, moment about the centroid, centroid) of a union of circles, by rasterising
    the union (overlaps counted once; pymunk itself would count them twice).
    resolution: raster cells across the bounding box's longer side."""
    offsets = np.asarray(offsets, float).reshape(-1, 2)
    radii = np.asarray(radii, float)
    lo = (offsets - radii[:, None]).min(0)
    hi = (offsets + radii[:, None]).max(0)
    h = float((hi - lo).max()) / resolution
    xs = np.arange(lo[0] + h / 2, hi[0], h)
    ys = np.arange(lo[1] + h / 2, hi[1], h)
    X, Y = np.meshgrid(xs, ys)
    inside = np.zeros(X.shape, bool)
    for (ox, oy), r in zip(offsets, radii):
        inside |= (X - ox) ** 2 + (Y - oy) ** 2 <= r * r
    dA = h * h
    m = density * inside.sum() * dA
    cx, cy = X[inside].mean(), Y[inside].mean()
    I = density * dA * (((X[inside] - cx) ** 2 + (Y[inside] - cy) ** 2).sum())
    return float(m), float(I), np.array([cx, cy])


def add_clumps(space: pymunk.Space, grains: Grains, centres: np.ndarray, angles: np.ndarray,
               template_offsets: np.ndarray, template_radii: np.ndarray, scales: np.ndarray,
               material: Material, rng: np.random.Generator) -> np.ndarray:
    """Add compound grains: several Circles on one rigid body (e.g. elongated grains).

    template_offsets (k,2), template_radii (k,): the clump at scale 1, in its own frame
    (it is re-centred on the union's centroid); scales (n,): size factor per grain;
    centres (n,2) [m], angles (n,) [rad]. Mass and moment come from the union of the
    circles (``union_mass_properties``), so overlaps are not double-counted.
    """
    t_off = np.asarray(template_offsets, float).reshape(-1, 2)
    t_rad = np.asarray(template_radii, float)
    m1, I1, c1 = union_mass_properties(t_off, t_rad, material.density)
    t_off = t_off - c1
    f_grain, _ = friction_split(material.friction, material.wall_friction)
    first = len(grains)
    order = _shuffled(len(scales), rng)
    objs, bodies, cb, off, rad = [], [], [], [], []
    for j, k in enumerate(order):
        s = float(scales[k])
        b = pymunk.Body(m1 * s * s, I1 * s**4)  # 2D: mass ~ s^2, moment ~ s^4
        b.position = (float(centres[k, 0]), float(centres[k, 1]))
        b.angle = float(angles[k])
        objs.append(b)
        for o, r in zip(t_off, t_rad):
            c = _grain_shape(pymunk.Circle(b, float(r * s), offset=(float(o[0] * s), float(o[1] * s))),
                             material, f_grain, with_density=False)
            objs.append(c)
            cb.append(first + j)
            off.append(o * s)
            rad.append(r * s)
        bodies.append(b)
    space.add(*objs)
    grains._extend(bodies, cb, off, rad)
    index = np.empty(len(order), dtype=np.int64)
    index[order] = np.arange(first, first + len(order))
    return index


def add_polygons(space: pymunk.Space, grains: Grains, centres: np.ndarray, angles: np.ndarray,
                 vertices: list[np.ndarray], material: Material, rng: np.random.Generator,
                 bevel: float = 0.0) -> np.ndarray:
    """Add convex polygon grains or blocks (one body + one Poly each).

    vertices: list of (k,2) local vertex arrays about the body origin [m] (a concave
    list becomes its convex hull); bevel: corner radius [m]. Mass from density."""
    f_grain, _ = friction_split(material.friction, material.wall_friction)
    first = len(grains)
    order = _shuffled(len(vertices), rng)
    objs, bodies = [], []
    for j, k in enumerate(order):
        b = pymunk.Body()
        b.position = (float(centres[k][0]), float(centres[k][1]))
        b.angle = float(angles[k])
        v = [tuple(map(float, p)) for p in np.asarray(vertices[k], float)]
        s = _grain_shape(pymunk.Poly(b, v, radius=bevel), material, f_grain)
        objs += (b, s)
        bodies.append(b)
        grains.polys.append((first + j, np.asarray(vertices[k], float)))
    space.add(*objs)
    grains._extend(bodies, [], np.zeros((0, 2)), [])
    index = np.empty(len(order), dtype=np.int64)
    index[order] = np.arange(first, first + len(order))
    return index
