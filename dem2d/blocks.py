"""Dry-stone walls of rigid polygon blocks on pymunk, loaded by water to failure.

Oetomo et al. (S-OET, docs/reference/drystone-walls.md 2.1) model Villemus's walls
as courses of 0.30 x 0.125 m blocks with staggered joints, bed joints dipping toward
the fill by alpha, head joints perpendicular to them, the first course fixed, and raise
hydrostatic water on the inner face by 1 % of h per increment until the wall's kinetic
energy stays above 1e-3 J/m for 10 readings. Here the blocks are rigid pymunk polygons
(impulse contact solver: no contact stiffness, so displacements before failure are
numerical, not physical).

Coordinates: x inward from the outer toe (the fill is at +x), y up, per metre of wall.
The section is ``analytic.drystone.WallSection``; its base is the bed plane through the
outer toe dipping inward at alpha (reference 5.3), water height ``h_w`` is measured from
the toe level.

* ``course_pieces``     the section cut into courses and blocks (pure geometry)
* ``BlockWall``         the pymunk space: blocks, foundation, pair friction, water load
* ``load_to_failure``   water increments, settling, failure test, mechanism
* ``classify_mechanism`` sliding along a bed joint or toppling about a course's toe
* ``tilt_slide_angle`` / ``topple_angle``  the tilt calibration (block on block)

Pure engine: no files, no printing. Units SI; angles in degrees at the interface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pymunk

from analytic.constants import G, GAMMA_WATER
from analytic.errors import InvalidParameter
from analytic.inputs import require_number
from analytic.schema import check_fields, param

from .sim import _sigint_between_steps

#: collision types: every block, and the fixed foundation under the first course
BLOCK_TYPE, FOUNDATION_TYPE = 21, 22


# ---------------------------------------------------------------------------- settings
@dataclass(frozen=True)
class Masonry:
    """Blocks and joints.

    unit_weight_kN_m3:  gamma_m, unit weight of the masonry with its voids [kN/m^3]
                        (blocks are solid polygons of density gamma_m / g)
    friction_deg:       phi_b, block-block friction angle [deg] (tilt-test value, S-OET Table 2)
    foundation_friction_deg: block-foundation friction [deg] (None: = phi_b, as S-OET case B)
    block_length_m:     block length along the bed joint [m] (S-OET: 0.30)
    block_height_m:     course height [m] (S-OET: 0.125)
    first_course_fixed: the first course is fixed (S-OET case A, "as on site"); False:
                        free on a fixed foundation (S-OET case B)
    friction_handler:   set the pair friction on every contact in a collision handler even
                        where shape values give it exactly (``pair_friction``)
    """

    unit_weight_kN_m3: float = 20.0
    friction_deg: float = 36.0
    foundation_friction_deg: float | None = None
    block_length_m: float = 0.30
    block_height_m: float = 0.125
    first_course_fixed: bool = True
    friction_handler: bool = False

    def __post_init__(self):
        require_number("unit_weight", self.unit_weight_kN_m3, 0.0, 100.0, unit="kN/m^3")
        require_number("friction", self.friction_deg, 0.0, 89.0, lo_open=False, hi_open=False, unit="deg")
        if self.foundation_friction_deg is not None:
            require_number("foundation_friction", self.foundation_friction_deg, 0.0, 89.0, lo_open=False,
                           hi_open=False, unit="deg")
        require_number("block_length", self.block_length_m, 0.01, 5.0, unit="m")
        require_number("block_height", self.block_height_m, 0.01, 5.0, unit="m")

    @property
    def density(self) -> float:
        """Mass per m^2 of section (per metre of wall) [kg/m^3]."""
        return self.unit_weight_kN_m3 * 1e3 / G


@dataclass(frozen=True)
class BlockSolver:
    """pymunk settings for rigid blocks (a probe of the settings: slop 1e-4 m, 10-40 iterations,
    dt <= 5e-4 s for a converged critical height)."""

    # 5e-6 s: the halved step (``halved``, the convergence check) of the cases' 1e-5 s
    # floor; a case-A wall (~40 blocks, ~4e4 steps at 5e-4 s, 2.7e5 block-steps per CPU-s)
    # then takes ~4e6 steps, ~10 min of one core
    dt: float = param(5e-4, unit="s", lo=5e-6, hi=0.01, hi_open=True, meaning="time step of the block solver")
    # 1000: the doubled sweeps (``halved``) of the cases' 500
    iterations: int = param(20, lo=1, hi=1000, meaning="Gauss-Seidel sweeps of the contact solver per step")
    collision_slop: float = param(1e-4, unit="m", lo=0, hi=0.01, hi_open=True,
                                  meaning="overlap left uncorrected (pymunk's default 0.1 m is a whole course)")
    overlap_time: float = param(0.02, unit="s", lo=0, lo_open=True,
                                meaning="time constant of the overlap correction (sets pymunk's collision_bias)")

    def __post_init__(self):
        check_fields(self)

    def halved(self) -> "BlockSolver":
        """dt / 2 and twice the iterations (the validation's convergence check)."""
        return BlockSolver(self.dt / 2, self.iterations * 2, self.collision_slop, self.overlap_time)


@dataclass(frozen=True)
class LoadingPlan:
    """Water raised in increments; settling and failure tests (S-OET 2.1 in the reference).

    increment_fraction:  water added per increment, as a fraction of h (S-OET: 0.01)
    start_height_m:      water height of the first increment [m] (0: from the toe)
    reading_interval_s:  time between readings [s] (S-OET: 500 steps of 2e-4 s = 0.1 s)
    failure_energy_J_m:  failure when the window kinetic energy exceeds this ... [J/m] (1e-3)
    failure_readings:    ... on this many successive readings (S-OET: 10)
    equilibrium_energy_J_m: settled when the window kinetic energy is below this ... [J/m]
    equilibrium_readings:   ... on this many successive readings
    max_settle_s:        at most this long per increment [s]; then the next increment
    runaway_fraction:    failure at once when the crest has moved this fraction of h
    direction:           "normal" (pressure normal to the current face) or "fixed" (its
                         initial normal: S-OET's conservative choice)

    The *window* kinetic energy uses each block's mean velocity over a reading interval
    (displacement / interval), not the instantaneous one: the solver's contact jitter
    (1-4 mm/s, zero mean; a probe of the settings) then does not read as motion.
    """

    increment_fraction: float = 0.01
    start_height_m: float = 0.0
    reading_interval_s: float = 0.1
    failure_energy_J_m: float = 1e-3
    failure_readings: int = 10
    equilibrium_energy_J_m: float = 1e-5
    equilibrium_readings: int = 2
    max_settle_s: float = 3.0
    runaway_fraction: float = 0.02
    direction: str = "normal"

    def __post_init__(self):
        require_number("increment_fraction", self.increment_fraction, 0.0, 0.2, unit="")
        require_number("start_height", self.start_height_m, 0.0, None, lo_open=False, unit="m")
        require_number("reading_interval", self.reading_interval_s, 0.0, 10.0, unit="s")
        require_number("failure_energy", self.failure_energy_J_m, 0.0, None, unit="J/m")
        require_number("equilibrium_energy", self.equilibrium_energy_J_m, 0.0, self.failure_energy_J_m,
                       unit="J/m")
        for name in ("failure_readings", "equilibrium_readings"):
            v = getattr(self, name)
            if not (isinstance(v, int) and 1 <= v <= 1000):
                raise InvalidParameter(name, v, "an integer in [1, 1000]")
        require_number("max_settle", self.max_settle_s, self.reading_interval_s, None, lo_open=False, unit="s")
        require_number("runaway_fraction", self.runaway_fraction, 0.0, 1.0, unit="")
        if self.direction not in ("normal", "fixed"):
            raise InvalidParameter("water_direction", self.direction, "normal | fixed")


# ---------------------------------------------------------------------------- geometry
def _clip(poly: np.ndarray, normal: np.ndarray, offset: float) -> np.ndarray:
    """The part of convex ``poly`` (k,2) where normal . p <= offset (Sutherland-Hodgman)."""
    out = []
    k = len(poly)
    for i in range(k):
        p, q = poly[i], poly[(i + 1) % k]
        fp, fq = normal @ p - offset, normal @ q - offset
        if fp <= 0:
            out.append(p)
        if fp * fq < 0:
            out.append(p + (q - p) * (fp / (fp - fq)))
    return np.array(out) if len(out) >= 3 else np.zeros((0, 2))


def _area_centroid(poly: np.ndarray) -> tuple[float, np.ndarray]:
    x, y = poly[:, 0], poly[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cross = x * y1 - x1 * y
    a = cross.sum() / 2
    c = np.array([((x + x1) * cross).sum(), ((y + y1) * cross).sum()]) / (6 * a)
    return a, c


def section_polygon(section) -> np.ndarray:
    """The wall section (4,2), counter-clockwise: outer toe, heel, inner crest, outer crest.
    The base is the bed plane through the toe dipping inward at alpha (reference 5.3)."""
    h, b = section.height_m, section.base_width_m
    t1 = math.tan(math.radians(section.batter_outer_deg))
    t2 = math.tan(math.radians(section.batter_inner_deg))
    ta = math.tan(math.radians(section.joint_slope_deg))
    x_heel = b / (1 - ta * t2)
    return np.array([[0.0, 0.0], [x_heel, -x_heel * ta], [b - h * t2, h], [h * t1, h]])


def _bed_axes(alpha_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors along the bed joints (inward, dipping by alpha) and normal to them."""
    a = math.radians(alpha_deg)
    return np.array([math.cos(a), -math.sin(a)]), np.array([math.sin(a), math.cos(a)])


def bed_joint_level(section, course: int, block_height: float) -> float:
    """Height above the toe [m] where the bed joint under ``course`` meets the outer face."""
    e_u, e_v = _bed_axes(section.joint_slope_deg)
    t1 = math.tan(math.radians(section.batter_outer_deg))
    # outer face point (y t1, y) with e_v . p = course * block_height
    return course * block_height / (t1 * e_v[0] + e_v[1])


def course_pieces(section, block_length: float = 0.30, block_height: float = 0.125,
                  stagger: float = 0.5) -> list[tuple[int, np.ndarray]]:
    """The section cut into blocks: ``[(course, polygon (k,2) ccw), ...]``, courses from
    the base. Bed joints at v = k t (v normal to the beds), head joints every
    ``block_length`` along the bed, shifted by ``stagger`` of a block on odd courses; a
    cut closer than 0.4 block to a face is dropped (the face block is longer instead of
    a sliver), so face blocks are trimmed to the batter."""
    poly = section_polygon(section)
    e_u, e_v = _bed_axes(section.joint_slope_deg)
    v_top = float((poly @ e_v).max())
    pieces = []
    k = 0
    while k * block_height < v_top - 1e-9:
        band = _clip(_clip(poly, -e_v, -k * block_height), e_v, (k + 1) * block_height)
        k_course = k
        k += 1
        if len(band) < 3:
            continue
        v_mid = (k_course + 0.5) * block_height
        mid = _clip(_clip(band, -e_v, -(v_mid - 1e-6)), e_v, v_mid + 1e-6)
        ref = mid if len(mid) >= 3 else band
        u_lo, u_hi = float((ref @ e_u).min()), float((ref @ e_u).max())
        shift = (stagger * block_length) if k_course % 2 else 0.0
        j0 = math.floor((u_lo - shift) / block_length)
        cuts = [shift + j * block_length for j in range(j0, j0 + int((u_hi - u_lo) / block_length) + 3)]
        cuts = [c for c in cuts if u_lo + 0.4 * block_length < c < u_hi - 0.4 * block_length]
        edges = [u_lo - 1.0] + cuts + [u_hi + 1.0]
        for a, b in zip(edges[:-1], edges[1:]):
            piece = _clip(_clip(band, -e_u, -a), e_u, b)
            if len(piece) >= 3 and _area_centroid(piece)[0] > 0.02 * block_length * block_height:
                pieces.append((k_course, piece))
    return pieces


# ---------------------------------------------------------------------------- the wall
def pair_friction(space: pymunk.Space, table: dict[tuple[int, int], float], *,
                  handler: bool = False) -> dict[int, float]:
    """Friction per pair of materials (collision types). pymunk multiplies the two shapes'
    frictions (a probe found 34.3 deg from the product rule where 25 deg was meant).

    When the table is a product table (f_a f_b = mu_ab for every pair, as with one block
    material on one foundation) the returned shape values give every pair exactly, and
    no callback is needed; otherwise, or with ``handler=True``, a pre-solve collision
    handler sets each arbiter's friction to its pair's value every step (exact in all
    cases; it costs a Python call per contact per step, about a third of a wall's run).
    Returns the friction to give each collision type's shapes."""
    values = {} if handler else _product_split(table)
    if values:
        return values
    for (ta, tb), mu in table.items():
        def pre_solve(arbiter, space_, data, mu=mu):
            arbiter.friction = mu
        space.on_collision(ta, tb, pre_solve=pre_solve)
    return {t: 1.0 for pair in table for t in pair}


def _product_split(table: dict[tuple[int, int], float]) -> dict[int, float]:
    """Shape values f with f_a f_b = mu_ab for every pair of ``table``, or {} if there are none."""
    f: dict[int, float] = {}
    for (a, b), mu in table.items():
        if a == b and mu > 0:
            f[a] = math.sqrt(mu)
    for _ in range(len(table)):
        for (a, b), mu in table.items():
            if a in f and b not in f and f[a] > 0:
                f[b] = mu / f[a]
            elif b in f and a not in f and f[b] > 0:
                f[a] = mu / f[b]
    ok = all(a in f and b in f and math.isclose(f[a] * f[b], mu, rel_tol=1e-12, abs_tol=1e-15)
             for (a, b), mu in table.items())
    return f if ok else {}


def new_block_space(solver: BlockSolver) -> pymunk.Space:
    """A pymunk space with ``solver``'s sweeps, slop and overlap time, gravity G down, no
    sleeping and no global damping (blocks and gravel alike)."""
    space = pymunk.Space()
    space.gravity = (0.0, -G)
    space.iterations = solver.iterations
    space.collision_slop = solver.collision_slop
    space.collision_bias = math.exp(-1.0 / solver.overlap_time)
    space.sleep_time_threshold = math.inf
    space.damping = 1.0
    return space


@dataclass
class WetFace:
    """One block edge on the inner face: body index, its end points in the body frame,
    and the initial unit normal pointing into the block (the fixed water direction)."""

    body: int
    a: tuple
    b: tuple
    n0: tuple


@dataclass
class BlockWall:
    """A dry-stone wall section of rigid blocks in a pymunk space.

    bodies:   one pymunk Body per block, in ``course_pieces`` order (static ones included)
    course:   (n,) course index of each block (0 = base)
    dynamic:  (n,) False for fixed blocks (the first course when fixed)
    outlines: block polygons in the body frame, (k,2) each
    """

    section: object
    masonry: Masonry
    solver: BlockSolver
    space: pymunk.Space
    bodies: list
    course: np.ndarray
    dynamic: np.ndarray
    outlines: list
    wet: list
    mass: np.ndarray
    inertia: np.ndarray
    water_height: float = 0.0
    direction: str = "normal"
    time: float = 0.0
    steps: int = 0
    _crest: np.ndarray = field(default=None, repr=False)
    _wet_arrays: tuple | None = field(default=None, repr=False)

    @classmethod
    def build(cls, section, masonry: Masonry = Masonry(), solver: BlockSolver = BlockSolver()) -> "BlockWall":
        """The wall of ``section`` in a new space, blocks at rest on their beds."""
        space = new_block_space(solver)
        mu_bb = math.tan(math.radians(masonry.friction_deg))
        phi_f = masonry.friction_deg if masonry.foundation_friction_deg is None else masonry.foundation_friction_deg
        fr = pair_friction(space, {(BLOCK_TYPE, BLOCK_TYPE): mu_bb,
                                   (BLOCK_TYPE, FOUNDATION_TYPE): math.tan(math.radians(phi_f))},
                           handler=masonry.friction_handler)
        pieces = course_pieces(section, masonry.block_length_m, masonry.block_height_m)
        poly = section_polygon(section)
        t2 = math.tan(math.radians(section.batter_inner_deg))
        bodies, courses, dyn, outlines, wet, mass, inertia = [], [], [], [], [], [], []
        for i, (k, piece) in enumerate(pieces):
            area, c = _area_centroid(piece)
            local = piece - c
            fixed = masonry.first_course_fixed and k == 0
            m = masonry.density * area
            if fixed:
                body = pymunk.Body(body_type=pymunk.Body.STATIC)
            else:
                body = pymunk.Body(m, pymunk.moment_for_poly(m, [tuple(p) for p in local]))
            body.position = tuple(c)
            shape = pymunk.Poly(body, [tuple(p) for p in local])
            shape.collision_type = BLOCK_TYPE
            shape.friction = fr[BLOCK_TYPE]
            shape.elasticity = 0.0
            space.add(body, shape)
            bodies.append(body)
            courses.append(k)
            dyn.append(not fixed)
            outlines.append(local)
            mass.append(m)
            inertia.append(body.moment if not fixed else 0.0)
            if not fixed:
                wet += _wet_faces(i, piece, c, section.base_width_m, t2)
        _add_foundation(space, poly, section, fr[FOUNDATION_TYPE])
        wall = cls(section, masonry, solver, space, bodies, np.array(courses), np.array(dyn), outlines, wet,
                   np.array(mass), np.array(inertia))
        top = wall.course[wall.dynamic].max() if wall.dynamic.any() else 0
        wall._crest = np.flatnonzero(wall.dynamic & (wall.course >= top - 1))
        return wall

    # -------------------------------------------------------------- state
    def positions(self) -> np.ndarray:
        return np.array([tuple(b.position) for b in self.bodies])

    def angles(self) -> np.ndarray:
        return np.array([b.angle for b in self.bodies])

    def velocities(self) -> np.ndarray:
        return np.array([tuple(b.velocity) for b in self.bodies])

    def world_outlines(self) -> list[np.ndarray]:
        """Every block polygon in world coordinates (k,2)."""
        out = []
        for b, loc in zip(self.bodies, self.outlines):
            c, s = math.cos(b.angle), math.sin(b.angle)
            out.append(loc @ np.array([[c, s], [-s, c]]) + np.array(tuple(b.position)))
        return out

    def crest_displacement(self, x0: np.ndarray) -> float:
        """Outward (-x) displacement of the top two courses since positions ``x0`` [m]."""
        x = self.positions()
        return float(-(x[self._crest, 0] - x0[self._crest, 0]).mean())

    @property
    def block_count(self) -> int:
        return len(self.bodies)

    # -------------------------------------------------------------- water and stepping
    def water_force(self) -> tuple[float, float]:
        """Total water force on the wall now (x, y) [N/m] (what ``advance`` applies)."""
        loads = self.water_loads()
        return (float(loads[1][:, 0].sum()), float(loads[1][:, 1].sum())) if loads is not None else (0.0, 0.0)

    def water_loads(self):
        """The hydrostatic pressure gamma_w (h_w - y) on every wetted face, integrated along
        the face and put at its centre of pressure, summed per block: (block indices (q,),
        forces (q,2) [N/m], torques about the block centroids (q,) [N m/m]); None when dry.
        Direction: into the block, normal to the face as it is now ("normal") or as it
        was built ("fixed")."""
        hw = self.water_height
        if hw <= 0 or not self.wet:
            return None
        if self._wet_arrays is None:
            self._wet_arrays = _wet_arrays(self.wet)
        body, a, b, n0, blocks, slot = self._wet_arrays
        bods = [self.bodies[i] for i in blocks]
        pos = np.array([tuple(bd.position) for bd in bods])
        ang = np.array([bd.angle for bd in bods])
        c, s = np.cos(ang)[slot], np.sin(ang)[slot]
        rot = lambda v: np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]])  # noqa: E731
        A, B = pos[slot] + rot(a), pos[slot] + rot(b)
        d = B - A
        n = np.column_stack([-d[:, 1], d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None] if self.direction == "normal" \
            else rot(n0) * 0 + n0
        pa, pb = GAMMA_WATER * (hw - A[:, 1]), GAMMA_WATER * (hw - B[:, 1])
        # clip each face at the water line (pressure linear along it, zero at the surface)
        t = np.where((pa < 0) != (pb < 0), pa / np.where(pa != pb, pa - pb, 1.0), 0.0)
        A = np.where(((pa < 0) & (pb > 0))[:, None], A + t[:, None] * d, A)
        B = np.where(((pb < 0) & (pa > 0))[:, None], A + t[:, None] * d, B)
        pa, pb = np.maximum(pa, 0.0), np.maximum(pb, 0.0)
        d = B - A
        length = np.hypot(d[:, 0], d[:, 1])
        force = length * (pa + pb) / 2
        wet = force > 0
        s_cp = np.where(wet, (pa + 2 * pb) / (3 * np.where(wet, pa + pb, 1.0)), 0.0)  # trapezoid centre from A
        F = force[:, None] * n
        P = A + s_cp[:, None] * d
        r = P - pos[slot]
        torque = r[:, 0] * F[:, 1] - r[:, 1] * F[:, 0]
        Fb = np.zeros((len(blocks), 2))
        Tb = np.zeros(len(blocks))
        np.add.at(Fb, slot, F)
        np.add.at(Tb, slot, torque)
        return blocks, Fb, Tb

    def advance(self, seconds: float) -> None:
        """Step for ``seconds``, re-applying the water load every step (pymunk clears
        forces after each step). Ctrl-C is honoured between steps."""
        n = max(int(round(seconds / self.solver.dt)), 1)
        dt = self.solver.dt
        with _sigint_between_steps() as marks:
            for _ in range(n):
                loads = self.water_loads()
                if loads is not None:
                    for i, F, T in zip(loads[0].tolist(), loads[1].tolist(), loads[2].tolist()):
                        body = self.bodies[i]
                        body.force = F
                        body.torque = T
                self.space.step(dt)
                if marks:
                    raise KeyboardInterrupt
        self.time += n * dt
        self.steps += n

    def contact_forces(self) -> tuple[np.ndarray, np.ndarray]:
        """Contact points (m,2) [m] and normal force magnitudes (m,) [N/m] of every
        touching block pair and block-foundation contact (impulse / dt, last step)."""
        pts, fs = [], []
        dt = self.solver.dt
        seen = set()
        for body in self.bodies:
            def visit(arb, out=(pts, fs)):
                key = tuple(sorted((id(arb.shapes[0]), id(arb.shapes[1]))))
                if key in seen:
                    return
                seen.add(key)
                j = arb.total_impulse
                f = math.hypot(j.x, j.y) / dt
                for cp in arb.contact_point_set.points:
                    out[0].append(tuple(cp.point_a))
                    out[1].append(f / max(len(arb.contact_point_set.points), 1))
            body.each_arbiter(visit)
        return np.array(pts).reshape(-1, 2), np.array(fs)


def _wet_faces(i: int, piece: np.ndarray, c: np.ndarray, b: float, t2: float) -> list[WetFace]:
    """Edges of ``piece`` on the inner face x + y tan(lambda2) = b (body frame)."""
    out = []
    k = len(piece)
    for j in range(k):
        p, q = piece[j], piece[(j + 1) % k]
        on = [abs(v[0] + v[1] * t2 - b) < 1e-7 * max(b, 1.0) for v in (p, q)]
        if all(on) and np.hypot(*(q - p)) > 1e-6:
            d = q - p
            n0 = np.array([-d[1], d[0]]) / np.hypot(*d)
            out.append(WetFace(i, tuple(p - c), tuple(q - c), tuple(n0)))
    return out


def _wet_arrays(wet: list[WetFace]):
    """The wetted faces as arrays: body index, end points a, b (body frame), initial
    normal, the distinct blocks, and each face's slot among them."""
    body = np.array([f.body for f in wet])
    blocks, slot = np.unique(body, return_inverse=True)
    return (body, np.array([f.a for f in wet]), np.array([f.b for f in wet]), np.array([f.n0 for f in wet]),
            blocks, slot)


def _add_foundation(space: pymunk.Space, poly: np.ndarray, section, friction: float) -> None:
    """A fixed slab under the base plane, wider than the wall on both sides."""
    e_u, e_v = _bed_axes(section.joint_slope_deg)
    u_hi = float(poly[1] @ e_u)
    pts = [(-1.0) * e_u, (u_hi + 1.0) * e_u, (u_hi + 1.0) * e_u - 0.5 * e_v, (-1.0) * e_u - 0.5 * e_v]
    shape = pymunk.Poly(space.static_body, [tuple(p) for p in pts])
    shape.collision_type = FOUNDATION_TYPE
    shape.friction = friction
    space.add(shape)


# ---------------------------------------------------------------------------- mechanism
@dataclass(frozen=True)
class Mechanism:
    """How the wall moved between two states (``classify_mechanism``).

    mode:         "sliding" (the part above a bed joint translates) or "toppling"
                  (it rotates outward about a point of the outer face)
    course:       the lowest course of the moving part (its bed joint, or the course
                  whose outer toe is the pivot)
    level_m:      height of that bed joint at the outer face, above the toe [m]
    rotation_deg: rotation of the top courses, outward positive [deg]
    crest_displacement_m: outward displacement of the top courses [m]
    pivot:        instantaneous centre of the top courses' motion (x, y) [m] (None when
                  they translate)
    """

    mode: str
    course: int
    level_m: float
    rotation_deg: float
    crest_displacement_m: float
    pivot: tuple | None


@dataclass(frozen=True)
class RigidFit:
    """One planar rigid motion fitted to many blocks' displacements (``rigid_motion_fit``).

    rotation_deg: rotation, counter-clockwise positive (outward toppling in the wall's
                  frame, x inward from the outer toe) [deg]
    pivot:        the point the motion leaves in place (x, y) [m]; None without rotation
    rms_residual_m, max_residual_m: how far the blocks' displacements depart from the
                  one motion (root mean square, largest) [m]
    worst:        index of the block that departs most
    """

    rotation_deg: float
    pivot: tuple | None
    rms_residual_m: float
    max_residual_m: float
    worst: int


def rigid_motion_fit(x0: np.ndarray, x1: np.ndarray) -> RigidFit:
    """Least-squares rigid motion x1 ~ c + T + R(w)(x0 - c) of points (n, 2) [m], with
    c their centroid: linearised in w (small rotations), d = T + w k x (x0 - c), whose
    fixed point is the pivot. A whole part of the wall rotating as one body leaves
    residuals far below its movement; a single block's slip stands out as ``worst``.
    Unlike ``classify_mechanism``'s top-two-course mean, which a lone slipping crest
    block can pull anywhere, every block given weighs the same."""
    x0, d = np.asarray(x0, float), np.asarray(x1, float) - np.asarray(x0, float)
    r = x0 - x0.mean(axis=0)
    a = np.zeros((2 * len(x0), 3))
    a[0::2, 0], a[1::2, 1] = 1.0, 1.0
    a[0::2, 2], a[1::2, 2] = -r[:, 1], r[:, 0]
    (tx, ty, w), *_ = np.linalg.lstsq(a, d.reshape(-1), rcond=None)
    res = np.hypot(*(d.reshape(-1) - a @ np.array([tx, ty, w])).reshape(-1, 2).T)
    c = x0.mean(axis=0)
    pivot = (float(c[0] - ty / w), float(c[1] + tx / w)) if abs(w) > 1e-12 else None
    return RigidFit(math.degrees(w), pivot, float(np.sqrt((res ** 2).mean())), float(res.max()), int(res.argmax()))


def classify_mechanism(section, block_height: float, course: np.ndarray, dynamic: np.ndarray,
                       x0: np.ndarray, a0: np.ndarray, x1: np.ndarray, a1: np.ndarray) -> Mechanism:
    """Sliding or toppling, from block kinematics between states 0 and 1.

    The top two courses are fitted with one rigid motion (mean translation T of their
    centroid c, mean rotation w); its centre (pivot) is the point that motion leaves in
    place. The
    wall topples when that centre lies near the outer face within the wall's height and
    the rotation accounts for at least half the crest movement (w x lever >= |T| / 2);
    the pivot's bed joint is the level. Otherwise it slides, on the lowest bed joint
    above which every course has most of its blocks moving with the crest (|d - T| <
    |T| / 2).
    """
    d = x1 - x0
    w_all = a1 - a0
    top = course[dynamic].max()
    crest = dynamic & (course >= top - 1)
    T = d[crest].mean(axis=0)
    w = float(w_all[crest].mean())
    c = x0[crest].mean(axis=0)
    moved = float(np.hypot(*T))
    e_u, e_v = _bed_axes(section.joint_slope_deg)
    t1 = math.tan(math.radians(section.batter_outer_deg))
    pivot = None
    if abs(w) > 1e-12:
        # the fixed point of the finite rigid motion x -> c + T + R(w) (x - c)
        R = np.array([[math.cos(w), -math.sin(w)], [math.sin(w), math.cos(w)]])
        pivot = np.linalg.solve(np.eye(2) - R, c + T - R @ c)
        lever = float(np.hypot(*(c - pivot)))
        x_face = pivot[1] * t1
        near_face = abs(pivot[0] - x_face) < 0.35 * section.base_width_m
        inside = -block_height <= pivot[1] <= section.height_m - block_height
        if near_face and inside and abs(w) * lever >= 0.5 * moved and w > 0:
            k = int(max(round(float(pivot @ e_v) / block_height), 0))
            k = max(k, int(course[dynamic].min()))
            return Mechanism("toppling", k, bed_joint_level(section, k, block_height), math.degrees(w), -T[0],
                             tuple(pivot))
    with_crest = np.hypot(*(d - T).T) < 0.5 * max(moved, 1e-12)
    k_slide = top
    for k in range(int(top), int(course[dynamic].min()) - 1, -1):
        sel = dynamic & (course == k)
        if sel.any() and with_crest[sel].mean() >= 0.5:
            k_slide = k
        else:
            break
    return Mechanism("sliding", k_slide, bed_joint_level(section, k_slide, block_height), math.degrees(w), -T[0],
                     None if pivot is None else tuple(pivot))


# ---------------------------------------------------------------------------- loading
@dataclass
class LoadingResult:
    """Water loading to failure.

    water_height_m, crest_displacement_m, settled, time_s: one row per increment (the
        state at the end of it; crest displacement outward since the start [m])
    critical_height_m:   water height of the increment at which the wall failed [m]
                         (NaN: it stood to the crest)
    last_stable_height_m: the last water height the wall settled under [m]
    failed:              the failure test fired (energy or runaway)
    mechanism:           kinematics at failure (between the last settled state and the
                         first reading with the crest 5 mm further out, or the last)
    velocities:          (n,2) block velocities at that reading [m/s]
    outlines:            block polygons in world coordinates at that reading
    reference_outlines:  the same at the last settled state
    steps, simulated_s:  solver steps and simulated time
    """

    water_height_m: list
    crest_displacement_m: list
    settled: list
    time_s: list
    critical_height_m: float
    last_stable_height_m: float
    failed: bool
    mechanism: Mechanism | None
    velocities: np.ndarray
    outlines: list
    reference_outlines: list
    steps: int
    simulated_s: float


def _window_energy(wall: BlockWall, x0, a0, x1, a1, interval: float) -> float:
    """Kinetic energy of the mean block velocities over a reading interval [J/m]."""
    v = (x1 - x0) / interval
    om = (a1 - a0) / interval
    dyn = wall.dynamic
    return float(0.5 * (wall.mass[dyn] * (v[dyn] ** 2).sum(axis=1)).sum() + 0.5 * (wall.inertia[dyn] * om[dyn] ** 2).sum())


def _settle(wall: BlockWall, plan: LoadingPlan, x_start: np.ndarray, on_reading=None) -> tuple[str, dict]:
    """Readings every ``plan.reading_interval_s`` until settled, failed or out of time.
    Returns ("settled" | "failed" | "unsettled", the kinematics at failure)."""
    runaway = plan.runaway_fraction * wall.section.height_m
    x_ref, a_ref = wall.positions(), wall.angles()
    xp, ap = x_ref, a_ref
    calm = loud = 0
    caught = None
    n_max = int(math.ceil(plan.max_settle_s / plan.reading_interval_s))
    for _ in range(n_max):
        wall.advance(plan.reading_interval_s)
        x, a = wall.positions(), wall.angles()
        e = _window_energy(wall, xp, ap, x, a, plan.reading_interval_s)
        xp, ap = x, a
        crest = wall.crest_displacement(x_start)
        if on_reading is not None:
            on_reading(wall, e, crest)
        if caught is None and wall.crest_displacement(x_ref) > 0.005:
            caught = {"x": x, "a": a, "v": wall.velocities(), "outlines": wall.world_outlines()}
        calm = calm + 1 if e < plan.equilibrium_energy_J_m else 0
        loud = loud + 1 if e > plan.failure_energy_J_m else 0
        if loud >= plan.failure_readings or crest > runaway:
            if caught is None:
                caught = {"x": x, "a": a, "v": wall.velocities(), "outlines": wall.world_outlines()}
            caught |= {"x_ref": x_ref, "a_ref": a_ref}
            return "failed", caught
        if calm >= plan.equilibrium_readings:
            return "settled", {}
    return "unsettled", {}


def load_to_failure(wall: BlockWall, plan: LoadingPlan = LoadingPlan(), *, progress=None,
                    on_reading=None) -> LoadingResult:
    """Raise the water by ``plan.increment_fraction`` of h per increment, settling
    after each, until the wall fails or the water reaches the crest.

    progress:    called as progress(water_height_m, crest_displacement_m) per increment
    on_reading:  called as on_reading(wall, window_energy, crest_displacement) per reading
    """
    h = wall.section.height_m
    wall.direction = plan.direction
    wall.water_height = 0.0
    wall.advance(plan.reading_interval_s)             # seat the blocks under their weight
    x_start = wall.positions()
    ref_outlines = wall.world_outlines()
    rows = ([], [], [], [])
    dh = plan.increment_fraction * h
    hw = plan.start_height_m
    last_stable = 0.0
    n_inc = int(math.ceil((h - hw) / dh - 1e-9))
    for i in range(n_inc + 1):
        wall.water_height = min(hw + i * dh, h)
        state, caught = _settle(wall, plan, x_start, on_reading)
        crest = wall.crest_displacement(x_start)
        for r, v in zip(rows, (wall.water_height, crest, state == "settled", wall.time)):
            r.append(v)
        if progress is not None:
            progress(wall.water_height, crest)
        if state == "failed":
            mech = classify_mechanism(wall.section, wall.masonry.block_height_m, wall.course, wall.dynamic,
                                      caught["x_ref"], caught["a_ref"], caught["x"], caught["a"])
            return LoadingResult(*rows, wall.water_height, last_stable, True, mech, caught["v"],
                                 caught["outlines"], ref_outlines, wall.steps, wall.time)
        if state == "settled":
            last_stable = wall.water_height
            ref_outlines = wall.world_outlines()
    return LoadingResult(*rows, math.nan, last_stable, False, None, wall.velocities(), wall.world_outlines(),
                         ref_outlines, wall.steps, wall.time)


# ---------------------------------------------------------------------------- tilt tests
def _tilt_pair(lower: tuple[float, float], upper: tuple[float, float], friction_deg: float,
               solver: BlockSolver, handler: bool, density: float = 2000.0):
    """A fixed block ``lower`` (length, height) and a free block ``upper`` on it, centred."""
    space = new_block_space(solver)
    mu = math.tan(math.radians(friction_deg))
    fr = pair_friction(space, {(BLOCK_TYPE, BLOCK_TYPE): mu}, handler=handler)
    L0, H0 = lower
    base = pymunk.Poly(space.static_body, [(-L0 / 2, -H0), (L0 / 2, -H0), (L0 / 2, 0), (-L0 / 2, 0)])
    base.collision_type = BLOCK_TYPE
    base.friction = fr[BLOCK_TYPE]
    L1, H1 = upper
    m = density * L1 * H1
    body = pymunk.Body(m, pymunk.moment_for_box(m, (L1, H1)))
    body.position = (0.0, H1 / 2)
    top = pymunk.Poly.create_box(body, (L1, H1))
    top.collision_type = BLOCK_TYPE
    top.friction = fr[BLOCK_TYPE]
    space.add(base, body, top)
    return space, body


def _tilt_until(friction_deg, lower, upper, solver, moved, start_deg, step_deg, hold_s, stop_deg, handler):
    """Tilt (by turning gravity) in steps until ``moved(body, x0)``; the angle [deg] or NaN."""
    space, body = _tilt_pair(lower, upper, friction_deg, solver, handler)
    n = max(int(round(hold_s / solver.dt)), 1)
    beta = start_deg
    space.gravity = (G * math.sin(math.radians(beta)), -G * math.cos(math.radians(beta)))
    for _ in range(n):
        space.step(solver.dt)
    x0 = tuple(body.position)
    while beta <= stop_deg:
        space.gravity = (G * math.sin(math.radians(beta)), -G * math.cos(math.radians(beta)))
        with _sigint_between_steps() as marks:
            for _ in range(n):
                space.step(solver.dt)
                if marks:
                    raise KeyboardInterrupt
        if moved(body, x0):
            return beta
        beta += step_deg
    return math.nan


def tilt_slide_angle(friction_deg: float, *, block=(0.30, 0.125), solver: BlockSolver = BlockSolver(),
                     resolution_deg: float = 0.05, handler: bool = False) -> float:
    """Tilt angle [deg] at which a block on an identical fixed block starts to slide
    (tilt test; rigid Coulomb contact: tan(angle) = mu, so angle = ``friction_deg``).
    Gravity is turned in steps of 1 deg, then of ``resolution_deg`` from 1 deg below the
    first slip, each held 0.05 s; slip = the block moved 10 um down the slope (below the
    friction angle the rigid contact holds it to ~1e-12 m; just above, the acceleration
    g (sin - mu cos) is so small that a mm threshold would lag by about a degree)."""
    def slid(body, x0):
        return body.position.x - x0[0] > 1e-5
    coarse = _tilt_until(friction_deg, block, block, solver, slid, 0.0, 1.0, 0.05, 89.0, handler)
    if math.isnan(coarse):
        return coarse
    return _tilt_until(friction_deg, block, block, solver, slid, max(coarse - 1.0, 0.0), resolution_deg, 0.05,
                       coarse + 1.0, handler)


def topple_angle(width: float, height: float, *, friction_deg: float = 60.0,
                 solver: BlockSolver = BlockSolver(), resolution_deg: float = 0.05, handler: bool = False) -> float:
    """Tilt angle [deg] at which a slender block (``width`` x ``height``) on a wide fixed
    block tips over (its weight passes the downhill corner: atan(width / height), when
    the friction holds it from sliding: friction_deg > that). Tipped = rotated 0.01 deg
    (below the angle the rigid contact holds it to ~1e-12 rad)."""
    def tipped(body, x0):
        return abs(body.angle) > math.radians(0.01)
    lower = (4 * max(width, height), 0.125)
    coarse = _tilt_until(friction_deg, lower, (width, height), solver, tipped, 0.0, 1.0, 0.1, 89.0, handler)
    if math.isnan(coarse):
        return coarse
    return _tilt_until(friction_deg, lower, (width, height), solver, tipped, max(coarse - 1.0, 0.0),
                       resolution_deg, 0.1, coarse + 1.0, handler)
