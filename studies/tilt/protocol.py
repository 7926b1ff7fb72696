"""The tilt test of the rigid blocks (a free block on a fixed one, gravity turned in
steps): the angle at which a block slides (tan = the friction) and at which a slender
block topples (its weight passes the downhill corner). The protocol behind
``calibrate tilt``, over the engine's block model (dem2d.blocks)."""

from __future__ import annotations

import math

import pymunk

from analytic.constants import G
from dem2d.blocks import BLOCK_TYPE, BlockSolver, new_block_space, pair_friction
from dem2d.sim import sigint_between_steps


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


def outlines(space: pymunk.Space) -> list:
    """World outlines (k,2) [m] of every polygon in ``space`` (the blocks of a tilt test)."""
    return [[tuple(s.body.local_to_world(v)) for v in s.get_vertices()] for s in space.shapes
            if isinstance(s, pymunk.Poly)]


def _tilt_until(friction_deg, lower, upper, solver, moved, start_deg, step_deg, hold_s, stop_deg, handler,
                on_step=None):
    """Tilt (by turning gravity) in steps until ``moved(body, x0)``; the angle [deg] or NaN.
    ``on_step(space, steps)``: after every held angle."""
    space, body = _tilt_pair(lower, upper, friction_deg, solver, handler)
    n = max(int(round(hold_s / solver.dt)), 1)
    steps = 0
    beta = start_deg
    space.gravity = (G * math.sin(math.radians(beta)), -G * math.cos(math.radians(beta)))
    for _ in range(n):
        space.step(solver.dt)
    x0 = tuple(body.position)
    while beta <= stop_deg:
        space.gravity = (G * math.sin(math.radians(beta)), -G * math.cos(math.radians(beta)))
        with sigint_between_steps() as marks:
            for _ in range(n):
                space.step(solver.dt)
                if marks:
                    raise KeyboardInterrupt
        steps += n
        if on_step is not None:
            on_step(space, steps)
        if moved(body, x0):
            return beta
        beta += step_deg
    return math.nan


def tilt_slide_angle(friction_deg: float, *, block=(0.30, 0.125), solver: BlockSolver = BlockSolver(),
                     resolution_deg: float = 0.05, handler: bool = False, on_step=None) -> float:
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
                       coarse + 1.0, handler, on_step)


def topple_angle(width: float, height: float, *, friction_deg: float = 60.0,
                 solver: BlockSolver = BlockSolver(), resolution_deg: float = 0.05, handler: bool = False,
                 on_step=None) -> float:
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
                       resolution_deg, 0.1, coarse + 1.0, handler, on_step)
