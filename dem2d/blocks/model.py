"""The wall in pymunk: its settings (``Masonry``, ``BlockSolver``), the pair frictions,
and ``BlockWall``, the blocks on their fixed foundation with the hydrostatic water on
the inner face."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pymunk

from analytic.constants import G
from analytic.inputs import require_number
from analytic.schema import check_fields, param

from ..sim import sigint_between_steps
from .geometry import area_centroid, bed_axes, course_pieces, section_polygon
from .water import BodyBatch, face_loads

#: collision types: every block, and the fixed foundation under the first course
BLOCK_TYPE, FOUNDATION_TYPE = 21, 22


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
            area, c = area_centroid(piece)
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
        was built ("fixed"). ``water.face_loads``."""
        if not self._wetted():
            return None
        blocks = self._wet_arrays[4]
        pos = np.array([tuple(self.bodies[i].position) for i in blocks])
        ang = np.array([self.bodies[i].angle for i in blocks])
        return (blocks, *self._face_loads(pos, ang, *self._new_loads()))

    def advance(self, seconds: float) -> None:
        """Step for ``seconds``, re-applying the water load every step (pymunk clears
        forces after each step). Ctrl-C is honoured between steps."""
        n = max(int(round(seconds / self.solver.dt)), 1)
        dt = self.solver.dt
        batch = BodyBatch(self.space, [self.bodies[i] for i in self._wet_arrays[4]]) if self._wetted() else None
        loads = self._new_loads() if batch is not None else None
        with sigint_between_steps() as marks:
            for _ in range(n):
                if batch is not None:
                    batch.write(*self._face_loads(*batch.read(), *loads))
                self.space.step(dt)
                if marks:
                    raise KeyboardInterrupt
        self.time += n * dt
        self.steps += n

    def _wetted(self) -> bool:
        """Water stands against the wall (and the wet-face arrays are made)."""
        if self.water_height <= 0 or not self.wet:
            return False
        if self._wet_arrays is None:
            self._wet_arrays = _wet_arrays(self.wet)
        return True

    def _new_loads(self) -> tuple[np.ndarray, np.ndarray]:
        """Arrays for the wet blocks' forces (q,2) and torques (q,)."""
        q = len(self._wet_arrays[4])
        return np.zeros((q, 2)), np.zeros(q)

    def _face_loads(self, pos: np.ndarray, ang: np.ndarray, force: np.ndarray, torque: np.ndarray):
        """``force`` (q,2) and ``torque`` (q,) on the wet blocks at positions ``pos``,
        angles ``ang``, filled in and returned."""
        _, a, b, n0, _, slot = self._wet_arrays
        face_loads(pos, ang, a, b, n0, slot, float(self.water_height), self.direction == "normal", force, torque)
        return force, torque

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
    e_u, e_v = bed_axes(section.joint_slope_deg)
    u_hi = float(poly[1] @ e_u)
    pts = [(-1.0) * e_u, (u_hi + 1.0) * e_u, (u_hi + 1.0) * e_u - 0.5 * e_v, (-1.0) * e_u - 0.5 * e_v]
    shape = pymunk.Poly(space.static_body, [tuple(p) for p in pts])
    shape.collision_type = FOUNDATION_TYPE
    shape.friction = friction
    space.add(shape)
