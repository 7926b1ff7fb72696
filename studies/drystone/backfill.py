"""Dry-stone case B: a gravel backfill (grains of ``Gravel.shape``) placed in layers against a ``BlockWall``.

S-OET (docs/reference/drystone-walls.md 3.1) load Colas's walls with their gravel:
10 cm layers in a 2.5 m wide container, the slope re-cut to 32 deg before each stage,
the fill continued above the crest against a formwork column, until the wall's
kinetic energy stays above 0.1 J/m (10 checks). Here:

* the wall is ``blocks.BlockWall`` (first course free on the fixed foundation, foundation
  friction = block-block: ``Masonry(first_course_fixed=False)``);
* the container is static: a floor at the heel's level from the inner face to
  ``container_m`` inward and a back wall there (``CONTAINER_TYPE``);
* the formwork column stands on the line of the inner face from just above the crest.
  By default (``formwork="crest"``) it is S-OET's: "a column of disks created at the
  top-right part of the wall and fixed to the inward wall face" (S-OET 5.2; reference
  3.1): a capsule shape added to the body of the innermost top-course block, so it
  moves with that block and the fill above the crest loads the wall through it (the
  paper: "the load transfer to the wall was more direct" than on site). It is
  massless [A] (its weight is unknown; wooden planks on site) and takes the fill-block
  friction, BLOCK_TYPE. ``formwork="fixed"`` keeps a static column instead (ours
  before; it carries the fill above the crest itself, as the site's formwork held by
  the side formworks did, so walls may not fail above the crest);
* a stage raises the fill surface by ``layer_m`` at the inner face: the band between the
  present surface and the new one, y_s(x) = H_b + (x - x_face) tan(beta) (rising away
  from the wall: reference 3.3 [A]), is filled by a column-wise cloud of grains (per
  column as many grains as its share of the band holds at ``porosity``, times
  ``overfill``) dropped just above the present surface, at the placement friction; once
  it has settled the local friction is restored, grains above y_s are cut away (the
  re-cut slope) and the fill settles again;
* failure as case A (``LoadingPlan``: the window kinetic energy of the blocks above
  ``failure_energy_J_m`` on ``failure_readings`` successive readings, or the crest
  moving ``runaway_fraction`` of h), checked through every stage;
* friction per pair of materials: the many fill contacts take shape values (fill-fill
  exact, fill-block and fill-container exact), block-block and block-foundation
  contacts, a few hundred, are set in a pre-solve handler (``pair_friction`` would call
  Python on every fill contact, since the four values are not a product table);
* optional hold: grains deeper than ``hold_depth_m`` below the surface and further than
  ``hold_distance_m`` from the inner face are made static once settled (outside the
  wall's failure wedge; the Khosravi fill's device), so they leave the solver.

Measured per stage: the fill's force on the wall (horizontal thrust, its vertical part,
the height of the horizontal resultant above the toe level), the vertical reactions of
the container and of the wall on the fill, the fill's weight, the crest displacement.

Pure engine: no files, no printing. SI units, per metre of wall; x inward from the outer
toe, y up (as ``blocks``).
"""

from __future__ import annotations

import math
import pickle
import time
from dataclasses import dataclass, field

import numpy as np
import pymunk
from pymunk._chipmunk_cffi import lib

from analytic.constants import G
from analytic.errors import InvalidParameter
from analytic.inputs import require_number

from dem2d.blocks import (BLOCK_TYPE, FOUNDATION_TYPE, BlockSolver, BlockWall, LoadingPlan, Masonry,
                     window_energy, new_block_space, pair_friction, section_polygon)
from dem2d.contact_cache import touching_contacts, warm_start
from dem2d.gravel import FILL_TYPE, Gravel, add_grains, grain_area

CONTAINER_TYPE = 24
#: where the formwork column above the crest is held (``FillPlan.formwork``)
FORMWORKS = ("crest", "fixed")


@dataclass(frozen=True)
class FillPlan:
    """How the backfill is placed (S-OET 3.1; [A] where the reference says assumed).

    layer_m:          rise of the surface at the inner face per stage [m] (S-OET: 0.10)
    slope_deg:        surface slope beta, re-cut each stage [deg] (S-OET: 32; rising away
                      from the wall [A], reference 3.3)
    container_m:      fill width from the inner face at the heel [m] (S-OET: 2.5 m container)
    formwork_m:       height of the formwork column above the crest [m] [A]
    formwork:         "crest": the column is part of the innermost top-course block (S-OET,
                      the default); "fixed": a static column (the site's, carried by
                      the side formworks) (module docstring)
    container_friction_deg: fill-container friction [deg] [A: None = the fill-block one]
    porosity:         sizes the grains of each band [-] (S-OET: n0 = 0.22)
    overfill:         grains dropped per band / grains it holds at ``porosity`` (the cut
                      trims the excess)
    max_stage_s:      settling time allowed per stage, each of its two settlings [s]
    ke_per_grain_J_m: the fill is settled when its kinetic energy per grain is below this [J/m]
    hold_depth_m, hold_distance_m: the hold (module docstring); None: no hold
    """

    layer_m: float = 0.10
    slope_deg: float = 32.0
    container_m: float = 2.5
    formwork_m: float = 1.0
    formwork: str = "crest"
    container_friction_deg: float | None = None
    porosity: float = 0.22
    overfill: float = 1.15
    max_stage_s: float = 1.5
    ke_per_grain_J_m: float = 1e-5
    hold_depth_m: float | None = None
    hold_distance_m: float = 1.5

    def __post_init__(self):
        require_number("layer", self.layer_m, 0.0, 2.0, unit="m")
        require_number("slope", self.slope_deg, 0.0, 60.0, lo_open=False, hi_open=False, unit="deg")
        require_number("container", self.container_m, 0.0, 50.0, unit="m")
        require_number("formwork", self.formwork_m, 0.0, 20.0, lo_open=False, unit="m")
        if self.formwork not in FORMWORKS:
            raise InvalidParameter("formwork", self.formwork, " | ".join(FORMWORKS))
        if self.container_friction_deg is not None:
            require_number("container_friction", self.container_friction_deg, 0.0, 89.0, lo_open=False,
                           hi_open=False, unit="deg")
        require_number("porosity", self.porosity, 0.0, 0.9, unit="")
        require_number("overfill", self.overfill, 0.5, 3.0, lo_open=False, unit="")
        require_number("max_stage", self.max_stage_s, 0.0, 100.0, unit="s")
        require_number("ke_per_grain", self.ke_per_grain_J_m, 0.0, None, unit="J/m")
        if self.hold_depth_m is not None:
            require_number("hold_depth", self.hold_depth_m, 0.0, 100.0, unit="m")
            require_number("hold_distance", self.hold_distance_m, 0.0, 100.0, unit="m")


class StageReading(dict):
    """One stage (a dict, JSON-ready): ``backfill_height_m`` (surface at the inner face
    above the toe level), ``thrust_N_m`` (horizontal force of the fill on the wall,
    toward the outside positive), ``thrust_vertical_N_m`` (downward positive),
    ``thrust_height_m`` (height of the horizontal resultant above the toe level),
    ``formwork_thrust_N_m`` (horizontal force of the fill on the formwork column alone:
    part of ``thrust_N_m`` when the column is on the crest block, not when it is fixed),
    ``container_vertical_N_m``, ``wall_vertical_N_m`` (upward reactions on the fill),
    ``fill_weight_N_m``, ``grains``, ``held``, ``crest_displacement_m``, ``settled``,
    ``time_s``, ``steps``; per phase (``_PhaseClock``) ``cpu_<phase>_s`` and
    ``steps_<phase>`` for drop, place, settle, read; per block (the wall's order)
    ``block_fill_force_N_m`` (the fill's force on it: [horizontal toward the outside,
    vertical downward]) and ``block_outlines_m`` (its corners then), the field of
    Oetomo et al.'s Fig. 20."""


@dataclass
class BackfilledWall:
    """A ``BlockWall`` with its container and the fill placed so far (``build``, ``stage``)."""

    wall: BlockWall
    gravel: Gravel
    plan: FillPlan
    loading: LoadingPlan
    rng: np.random.Generator
    bodies: list = field(default_factory=list)
    widths: np.ndarray = field(default_factory=lambda: np.zeros(0))
    held: list = field(default_factory=list)
    backfill_height_m: float = 0.0
    x_start: np.ndarray = None
    formwork_shape: pymunk.Shape | None = None
    formwork_body: int | None = None
    failed: bool = False
    _loud: int = 0

    @classmethod
    def build(cls, section, masonry: Masonry, gravel: Gravel, plan: FillPlan = FillPlan(),
              solver: BlockSolver = BlockSolver(dt=5e-4, iterations=40),
              loading: LoadingPlan = LoadingPlan(failure_energy_J_m=0.1, failure_readings=10),
              seed: int = 0) -> "BackfilledWall":
        """The wall (seated under its weight), the container, no fill yet."""
        wall = BlockWall.build(section, masonry, solver)
        self = cls(wall, gravel, plan, loading, np.random.default_rng(seed))
        cell = 1.05 * gravel.aspect_ratio * gravel.width_max_m
        wall.space.use_spatial_hash(cell, 20000)
        self._frictions(masonry)
        self._container()
        wall.advance(0.1)
        self.x_start = wall.positions()
        self.backfill_height_m = self.y_floor
        return self

    # ------------------------------------------------------------------ snapshots
    def snapshot(self) -> bytes:
        """Bytes that ``restored`` turns back into this wall and its fill between stages:
        every body and shape (in the space's insertion order), the state of the wall and
        of the fill (random generator, held grains, counters) and the impulses of every
        touching contact (``contact_cache``)."""
        space = self.wall.space
        shapes = list(space.shapes)
        payload = {"format": "wallsim-dem2d-backfilled-wall-1",
                   "wall": {k: v for k, v in self.wall.__dict__.items() if k != "space"},
                   "fill": {k: v for k, v in self.__dict__.items() if k != "wall"},
                   "bodies": list(space.bodies), "shapes": shapes,
                   "on_static": [s.body is space.static_body for s in shapes],
                   # contact points are matched by feature hashes built from the shapes' ids
                   "hashids": [s._hashid for s in shapes], "next_hashid": lib.cpSpaceGetShapeIDCounter(space._space),
                   "contacts": touching_contacts(space, shapes)}
        return pickle.dumps(payload, protocol=pickle.HIGHEST_PROTOCOL)

    @classmethod
    def restored(cls, blob: bytes) -> "BackfilledWall":
        """The wall and fill ``snapshot`` saved, in a fresh space built as ``build`` builds
        one (solver, friction handlers, spatial hash), bodies and shapes added in their
        saved order, the contacts warm-started: a deterministic function of the bytes,
        so every run that goes on from them goes on alike. Each shape keeps the id it
        had (Chipmunk builds the contact points' hashes from it)."""
        payload = pickle.loads(blob)
        if not isinstance(payload, dict) or payload.get("format") != "wallsim-dem2d-backfilled-wall-1":
            raise TypeError("not a backfilled-wall snapshot")
        w = payload["wall"]
        masonry, solver = w["masonry"], w["solver"]
        space = new_block_space(solver)
        if masonry.friction_handler:            # as BlockWall.build registers them
            mu_f = masonry.friction_deg if masonry.foundation_friction_deg is None \
                else masonry.foundation_friction_deg
            pair_friction(space, {(BLOCK_TYPE, BLOCK_TYPE): math.tan(math.radians(masonry.friction_deg)),
                                   (BLOCK_TYPE, FOUNDATION_TYPE): math.tan(math.radians(mu_f))}, handler=True)
        wall = BlockWall.__new__(BlockWall)
        wall.__dict__.update(w, space=space)
        self = cls.__new__(cls)
        self.__dict__.update(payload["fill"], wall=wall)
        g = self.gravel
        space.use_spatial_hash(1.05 * g.aspect_ratio * g.width_max_m, 20000)
        self._frictions(masonry)
        shapes = payload["shapes"]
        for shape, static in zip(shapes, payload["on_static"]):
            if static:
                shape.body = space.static_body
        space.add(*payload["bodies"])
        for shape, hashid in zip(shapes, payload["hashids"]):
            lib.cpSpaceSetShapeIDCounter(space._space, hashid)    # each shape keeps its id
            space.add(shape)
        lib.cpSpaceSetShapeIDCounter(space._space, payload["next_hashid"])
        warm_start(space, shapes, payload["contacts"], solver.dt)
        return self

    # ------------------------------------------------------------------ geometry
    @property
    def x_face(self) -> float:
        """Inner face at the heel [m] (vertical inner faces: the heel's x)."""
        return float(section_polygon(self.wall.section)[1, 0])

    @property
    def y_floor(self) -> float:
        """Container floor: the heel's level [m] (the base dips inward at alpha)."""
        return float(section_polygon(self.wall.section)[1, 1])

    @property
    def x_back(self) -> float:
        return self.x_face + self.plan.container_m

    def face_x(self, y) -> np.ndarray:
        """x of the inner face at height y [m] (and of the formwork above the crest)."""
        s = self.wall.section
        t2 = math.tan(math.radians(s.batter_inner_deg))
        return s.base_width_m - np.minimum(np.asarray(y, float), s.height_m) * t2

    def surface_line(self, h_b: float, x) -> np.ndarray:
        """Target surface y_s(x) [m] for a fill height ``h_b`` at the inner face."""
        return h_b + (np.asarray(x, float) - float(self.face_x(h_b))) * math.tan(math.radians(self.plan.slope_deg))

    def _container(self) -> None:
        s, p = self.wall.section, self.plan
        r = 0.05
        top = self.surface_line(s.height_m + p.formwork_m, self.x_back) + 0.5
        fr = self._fr[CONTAINER_TYPE]
        segs = [((self.x_face - 0.5, self.y_floor - r), (self.x_back + r, self.y_floor - r)),
                ((self.x_back + r, self.y_floor), (self.x_back + r, top))]
        for a, b in segs:
            seg = pymunk.Segment(self.wall.space.static_body, a, b, r)
            seg.collision_type, seg.friction, seg.elasticity = CONTAINER_TYPE, fr, 0.0
            self.wall.space.add(seg)
        if p.formwork_m > 0:
            x = float(self.face_x(s.height_m)) - r      # its inner side on the inner face's line
            a, b = (x, s.height_m + 0.002 + r), (x, s.height_m + p.formwork_m)
            if p.formwork == "fixed":
                seg = pymunk.Segment(self.wall.space.static_body, a, b, r)
                seg.collision_type, seg.friction = CONTAINER_TYPE, fr
            else:
                i = self._crest_inner_block()
                body = self.wall.bodies[i]       # built at angle 0: local = world - position
                c = np.array(tuple(body.position))
                seg = pymunk.Segment(body, tuple(np.array(a) - c), tuple(np.array(b) - c), r)
                seg.collision_type, seg.friction = BLOCK_TYPE, self._fr[BLOCK_TYPE]
                self.formwork_body = i
            seg.elasticity = 0.0
            self.wall.space.add(seg)
            self.formwork_shape = seg

    def _crest_inner_block(self) -> int:
        """Index of the innermost block of the top course (the one whose outline reaches
        furthest inward at the crest): S-OET's "top-right part of the wall"."""
        w = self.wall
        top = int(w.course[w.dynamic].max())
        cand = np.flatnonzero(w.dynamic & (w.course == top))
        outl = w.world_outlines()
        return int(cand[np.argmax([outl[i][:, 0].max() for i in cand])])

    def _frictions(self, masonry: Masonry) -> None:
        """Shape values for the fill pairs, handlers for the block pairs (module docstring)."""
        g, p = self.gravel, self.plan
        tan = lambda d: math.tan(math.radians(d))  # noqa: E731
        f_fill = math.sqrt(tan(g.friction_deg))
        cont = g.interface_friction_deg if p.container_friction_deg is None else p.container_friction_deg
        self._fr = {FILL_TYPE: f_fill, BLOCK_TYPE: tan(g.interface_friction_deg) / f_fill,
                    CONTAINER_TYPE: tan(cont) / f_fill}
        self._f_place = math.sqrt(tan(g.placement_friction_deg))
        phi_f = masonry.friction_deg if masonry.foundation_friction_deg is None else masonry.foundation_friction_deg
        for pair, mu in (((BLOCK_TYPE, BLOCK_TYPE), tan(masonry.friction_deg)),
                         ((BLOCK_TYPE, FOUNDATION_TYPE), tan(phi_f))):
            def pre_solve(arbiter, space, data, mu=mu):
                arbiter.friction = mu
            self.wall.space.on_collision(*pair, pre_solve=pre_solve)
        for shape in self.wall.space.shapes:
            if shape.collision_type == BLOCK_TYPE:
                shape.friction = self._fr[BLOCK_TYPE]

    # ------------------------------------------------------------------ state
    def positions(self) -> np.ndarray:
        return np.array([tuple(b.position) for b in self.bodies]).reshape(-1, 2)

    def fill_weight(self) -> float:
        """Weight of every grain, held ones included [N/m]."""
        g = self.gravel
        return G * float(g.density * grain_area(self.widths, g.aspect_ratio, g.shape).sum())

    def kinetic_energy(self) -> float:
        """Kinetic energy of the free grains [J/m]."""
        return math.fsum(0.5 * b.mass * b.velocity.length_squared + 0.5 * b.moment * b.angular_velocity ** 2
                   for b in self.bodies if b.body_type == pymunk.Body.DYNAMIC)

    def angles(self) -> np.ndarray:
        return np.array([b.angle for b in self.bodies])

    def force_chains(self) -> tuple[np.ndarray, np.ndarray]:
        """Every touching pair of grains and blocks, and each with the container or the
        foundation: segments (m,2,2) from one body's centre to the other's (to the contact
        point for a static body) [m], and the contact force magnitude (m,) [N/m] (last
        step's impulse / dt). The force chains of the fill and of the wall in one set."""
        dt = self.wall.solver.dt
        segs, forces, seen = [], [], set()

        def visit(arb):
            a, b = arb.shapes
            key = (id(a), id(b)) if id(a) < id(b) else (id(b), id(a))
            if key in seen:
                return
            seen.add(key)
            pts = arb.contact_point_set.points
            if not pts:
                return
            j = arb.total_impulse
            ends = [tuple(s.body.position) if s.body.body_type == pymunk.Body.DYNAMIC else tuple(pts[0].point_a)
                    for s in (a, b)]
            segs.append(ends)
            forces.append(math.hypot(j.x, j.y) / dt)
        for body in self.wall.bodies + self.bodies:
            if body.body_type == pymunk.Body.DYNAMIC:
                body.each_arbiter(visit)
        return np.array(segs, float).reshape(-1, 2, 2), np.array(forces, float)

    def surface_at(self, x_edges: np.ndarray) -> np.ndarray:
        """Highest grain top in each column between ``x_edges`` (the floor where empty) [m]."""
        top = np.full(len(x_edges) - 1, self.y_floor)
        if self.bodies:
            p = self.positions()
            k = np.searchsorted(x_edges, p[:, 0]) - 1
            ok = (k >= 0) & (k < len(top))
            np.maximum.at(top, k[ok], p[ok, 1] + self.gravel.aspect_ratio * self.widths[ok] / 2)
        return top

    # ------------------------------------------------------------------ stages
    def stage(self, on_reading=None) -> StageReading:
        """Raise the fill by one layer at the inner face: drop, settle, restore the local
        friction, cut to the slope, settle, hold (if asked), read the forces. Stops early
        (``failed``) when the wall fails. ``on_reading(self, energy, crest)`` per reading."""
        p = self.plan
        k = int(round(max(self.backfill_height_m, 0.0) / p.layer_m))
        h_old, h_new = self.backfill_height_m, round((k + 1) * p.layer_m, 9)
        clock = _PhaseClock(self.wall)
        new = self._drop(h_old, h_new)
        clock.lap("drop")
        settled = self._settle(p.max_stage_s, on_reading)
        clock.lap("place")
        for b in new:
            for s in b.shapes:
                s.friction = self._fr[FILL_TYPE]
        self.backfill_height_m = h_new
        self._cut(h_new)
        if not self.failed:
            settled = self._settle(p.max_stage_s, on_reading) and settled
        clock.lap("settle")
        self._hold()
        r = self.read(settled=settled)
        clock.lap("read")
        r.update(clock.phases())
        return r

    def _drop(self, h_old: float, h_new: float) -> list:
        """A column-wise cloud for the band between the surface at ``h_old`` and at
        ``h_new``, just above the present grains (module docstring). Returns the bodies."""
        g, p = self.gravel, self.plan
        cell = 1.05 * g.aspect_ratio * g.width_max_m
        x0 = float(np.max(self.face_x([self.y_floor, h_new]))) + cell / 2
        cols = max(int((self.x_back - cell / 2 - x0) // cell), 1)
        edges = x0 - cell / 2 + cell * np.arange(cols + 1)
        xc = (edges[:-1] + edges[1:]) / 2
        old = np.maximum(self.surface_line(h_old, xc), self.y_floor) if h_old > self.y_floor else \
            np.full(cols, self.y_floor)
        band = np.clip(self.surface_line(h_new, xc) - old, 0.0, None) * cell
        mean = float(grain_area(g.grading.sample(20000, np.random.default_rng(12345)), g.aspect_ratio, g.shape).mean())
        n_col = np.round(band * (1 - p.porosity) / mean * p.overfill).astype(int)
        top = self.surface_at(edges)
        top = np.maximum(top, np.maximum(np.r_[top[1:], top[-1]], np.r_[top[0], top[:-1]]))
        xs = np.repeat(xc, n_col)
        ys = np.concatenate([t + cell / 2 + cell * np.arange(n) for t, n in zip(top, n_col)]) if n_col.sum() else \
            np.zeros(0)
        n = len(xs)
        widths = g.grading.sample(n, self.rng)
        bodies = add_grains(self.wall.space, np.c_[xs, ys], self.rng.uniform(0, math.pi, n), widths, g,
                              self._f_place)
        self.bodies += bodies
        self.widths = np.concatenate([self.widths, widths])
        return bodies

    def _cut(self, h_b: float) -> int:
        """Remove the free grains whose centre is above the slope y_s(x) for ``h_b``."""
        p = self.positions()
        if not len(p):
            return 0
        out = (p[:, 1] > self.surface_line(h_b, p[:, 0])) & \
            np.array([b.body_type == pymunk.Body.DYNAMIC for b in self.bodies])
        for i in np.flatnonzero(out):
            b = self.bodies[i]
            self.wall.space.remove(b, *b.shapes)
        keep = ~out
        self.bodies = [b for b, k in zip(self.bodies, keep) if k]
        self.widths = self.widths[keep]
        return int(out.sum())

    def _hold(self) -> None:
        """Make static the grains deep below the surface and far from the wall (``FillPlan``)."""
        p = self.plan
        if p.hold_depth_m is None or not self.bodies:
            return
        pos = self.positions()
        deep = (pos[:, 1] < self.surface_line(self.backfill_height_m, pos[:, 0]) - p.hold_depth_m) & \
            (pos[:, 0] > self.face_x(pos[:, 1]) + p.hold_distance_m)
        for i in np.flatnonzero(deep):
            b = self.bodies[i]
            if b.body_type == pymunk.Body.DYNAMIC:
                b.body_type = pymunk.Body.STATIC
                self.held.append(b)

    def _settle(self, seconds: float, on_reading=None) -> bool:
        """Readings every ``loading.reading_interval_s`` until the fill's kinetic energy per
        free grain is below ``ke_per_grain_J_m`` (True), ``seconds`` pass (False) or the
        wall fails (``failed``: window energy of the blocks above ``failure_energy_J_m``
        on ``failure_readings`` successive readings, or the crest runaway)."""
        w, lp = self.wall, self.loading
        xp, ap = w.positions(), w.angles()
        for _ in range(max(int(math.ceil(seconds / lp.reading_interval_s)), 1)):
            w.advance(lp.reading_interval_s)
            x, a = w.positions(), w.angles()
            e = window_energy(w, xp, ap, x, a, lp.reading_interval_s)
            xp, ap = x, a
            crest = w.crest_displacement(self.x_start)
            if on_reading is not None:
                on_reading(self, e, crest)
            self._loud = self._loud + 1 if e > lp.failure_energy_J_m else 0
            if self._loud >= lp.failure_readings or crest > lp.runaway_fraction * w.section.height_m:
                self.failed = True
                return False
            free = sum(1 for b in self.bodies if b.body_type == pymunk.Body.DYNAMIC)
            if self.kinetic_energy() / max(free, 1) < self.plan.ke_per_grain_J_m:
                return True
        return False

    # ------------------------------------------------------------------ readings
    def read(self, seconds: float = 0.05, settled: bool = True) -> StageReading:
        """Forces averaged over ``seconds`` of stepping (module docstring)."""
        w = self.wall
        dt = w.solver.dt
        n = max(int(round(seconds / dt)), 1)
        on_wall, moment, cont, form = np.zeros(2), 0.0, 0.0, 0.0
        per_block = np.zeros((len(w.bodies), 2))
        for _ in range(n):
            w.advance(dt)
            f, m = _fill_on_blocks(w.bodies, per_block)
            on_wall += f
            moment += m
            cont += _static_on_fill(w.space.static_body)
            form += _fill_on_shape(self.formwork_shape)
        on_wall, moment, cont, form = on_wall / (n * dt), moment / (n * dt), cont / (n * dt), form / (n * dt)
        return StageReading(
            block_fill_force_N_m=(-per_block / (n * dt)).tolist(),
            block_outlines_m=[o.tolist() for o in w.world_outlines()],
            backfill_height_m=self.backfill_height_m, thrust_N_m=float(-on_wall[0]),
            thrust_vertical_N_m=float(-on_wall[1]),
            thrust_height_m=float(moment / on_wall[0]) if on_wall[0] != 0 else math.nan,
            formwork_thrust_N_m=float(-form),
            container_vertical_N_m=float(cont), wall_vertical_N_m=float(-on_wall[1]),
            fill_weight_N_m=self.fill_weight(), grains=len(self.bodies), held=len(self.held),
            crest_displacement_m=w.crest_displacement(self.x_start), settled=bool(settled), failed=self.failed,
            time_s=w.time, steps=w.steps)


class _PhaseClock:
    """CPU time [s] and steps of the phases of a stage (where a case-B run's time goes):
    drop (the cloud created), place (settling at the placement friction), settle (cut and
    settling at the local friction), read (hold and the force readings)."""

    def __init__(self, wall: BlockWall):
        self.wall, self.t, self.n, self.out = wall, time.process_time(), wall.steps, {}

    def lap(self, name: str) -> None:
        t, n = time.process_time(), self.wall.steps
        self.out[f"cpu_{name}_s"], self.out[f"steps_{name}"] = t - self.t, n - self.n
        self.t, self.n = t, n

    def phases(self) -> dict:
        return dict(self.out)


def _fill_on_blocks(blocks, per_block: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """Last step's impulses of the fill on the blocks (x, y) [N s/m], and the sum of
    J_x y over the contact points (the moment that places the horizontal resultant);
    each block's own impulses are added to its row of ``per_block`` (n, 2) if given."""
    out = np.zeros(2)
    mom = [0.0]
    row = [0]

    def visit(arb):
        a, b = arb.shapes
        if b.collision_type != FILL_TYPE:
            return
        j = arb.total_impulse            # on the first shape: the block's
        out[0] += j.x
        out[1] += j.y
        if per_block is not None:
            per_block[row[0], 0] += j.x
            per_block[row[0], 1] += j.y
        pts = arb.contact_point_set.points
        for cp in pts:
            mom[0] += j.x / len(pts) * cp.point_a.y
    for k, body in enumerate(blocks):
        if body.body_type == pymunk.Body.DYNAMIC:
            row[0] = k
            body.each_arbiter(visit)
    return out, mom[0]


def _fill_on_shape(shape) -> float:
    """Last step's horizontal impulse of the fill on one shape (the formwork column) [N s/m]."""
    if shape is None:
        return 0.0
    out = [0.0]

    def visit(arb):
        a, b = arb.shapes
        if a is shape and b.collision_type == FILL_TYPE:
            out[0] += arb.total_impulse.x       # on the first shape: the column's
        elif b is shape and a.collision_type == FILL_TYPE:
            out[0] -= arb.total_impulse.x
    shape.body.each_arbiter(visit)
    return out[0]


def _static_on_fill(static_body: pymunk.Body) -> float:
    """Last step's vertical impulse of the container and foundation on the fill [N s/m]."""
    out = [0.0]

    def visit(arb):
        if arb.shapes[1].collision_type == FILL_TYPE:
            out[0] -= arb.total_impulse.y    # on the static shape; the fill gets minus it
    static_body.each_arbiter(visit)
    return out[0]
