"""Walls made of panels (pressure cells) and the drivers that move them.

Geometry, motion and interaction are kept apart:

* ``PanelWall``: N straight panels between two points. Each panel is its own KINEMATIC
  body with one ``Segment`` shape and its own collision type, so the force on each
  panel can be read separately (``probes.py``). All panel bodies share one origin,
  the wall's *pivot*, so giving them the same (velocity, angular velocity) moves the
  wall as one rigid body: translation, rotation about the pivot, or both.
* Drivers (``Fixed``, ``Translate``, ``RotateAbout``, ``Schedule``) are pure functions of
  time returning (pivot velocity [m/s], angular velocity [rad/s], CCW positive).
* Kinematic walls are moved by velocity, never by assigning positions
  ; a kinematic body has infinite mass and ignores gravity.
  A wall at rest is a kinematic body with zero velocity.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import pymunk

#: first collision type used for panels (grains use build.GRAIN_TYPE = 1)
PANEL_TYPE_BASE = 1000

#: walls never touch each other (a dynamic piston would otherwise collide with the
#: kinematic walls it crosses); they touch every grain (grains keep pymunk's default
#: filter: all categories, all masks)
WALL_FILTER = pymunk.ShapeFilter(categories=0b10, mask=0b01)


@dataclass
class PanelWall:
    """A straight wall of ``n`` equal panels from ``a`` to ``b`` (world, m).

    name:    label ("wall", "floor", ...)
    bodies:  (n,) kinematic bodies, origin at ``pivot``
    shapes:  (n,) Segment shapes, panel 0 at ``a``
    normal0: unit normal from the wall into the backfill at t = 0
    pivot0:  the pivot at t = 0 [m]
    types:   (n,) collision types of the panels
    """

    name: str
    bodies: list
    shapes: list
    normal0: np.ndarray
    pivot0: np.ndarray
    types: list
    local_ends: np.ndarray  # (n,2,2) endpoints in the body frame

    def __len__(self) -> int:
        return len(self.shapes)

    @property
    def angle(self) -> float:
        """Rotation of the wall since t = 0 [rad], CCW positive."""
        return float(self.bodies[0].angle)

    @property
    def pivot(self) -> np.ndarray:
        """Current pivot position [m]."""
        p = self.bodies[0].position
        return np.array([p.x, p.y])

    def displacement(self) -> np.ndarray:
        """Pivot displacement since t = 0 [m]."""
        return self.pivot - self.pivot0

    def corners(self) -> np.ndarray:
        """(n,2,2) current panel endpoints [m] (world)."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        R = np.array([[c, -s], [s, c]])
        return self.local_ends @ R.T + self.pivot

    def normals(self) -> np.ndarray:
        """(n,2) current unit normals from the wall into the backfill."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        n = np.array([c * self.normal0[0] - s * self.normal0[1], s * self.normal0[0] + c * self.normal0[1]])
        return np.tile(n, (len(self), 1))

    def lengths(self) -> np.ndarray:
        """(n,) panel lengths [m] (per metre of wall: panel areas)."""
        e = self.local_ends
        return np.linalg.norm(e[:, 1] - e[:, 0], axis=1)

    def centres(self) -> np.ndarray:
        """(n,2) current panel midpoints [m]."""
        return self.corners().mean(axis=1)

    def set_motion(self, velocity, angular_velocity: float = 0.0) -> None:
        """Give every panel body the same pivot velocity [m/s] and angular velocity [rad/s]."""
        v = (float(velocity[0]), float(velocity[1]))
        for b in self.bodies:
            b.velocity = v
            b.angular_velocity = float(angular_velocity)

    def drive(self, driver: "Driver", t: float) -> None:
        """Apply a driver's motion at time t [s]."""
        v, w = driver(t)
        self.set_motion(v, w)


def panel_wall(space: pymunk.Space, name: str, a, b, n_panels: int, *, friction: float,
               into, pivot=None, first_type: int, radius: float = 0.0,
               mass: float | None = None) -> PanelWall:
    """Create a wall of ``n_panels`` equal segments from ``a`` to ``b`` [m].

    friction:   *shape* friction of the panels (see build.friction_split)
    into:       a point (or direction from the wall) on the backfill side; fixes the normal
    pivot:      body origin for rotations [m] (default: ``a``)
    first_type: collision type of panel 0 (panel i has first_type + i)
    radius:     segment thickness radius [m]
    mass:       None: kinematic panels (moved by drivers). A number: one DYNAMIC panel
                of that mass [kg/m] that cannot rotate (a piston for stress-controlled
                boundaries: push it with ``body.force``); needs n_panels = 1.
    """
    if mass is not None and n_panels != 1:
        raise ValueError("a dynamic (force-controlled) wall has a single panel")
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    t = (b - a) / np.linalg.norm(b - a)
    n = np.array([-t[1], t[0]])
    if np.dot(np.asarray(into, float) - a, n) < 0:
        n = -n
    pivot = a.copy() if pivot is None else np.asarray(pivot, float)
    pts = a + np.outer(np.linspace(0.0, 1.0, n_panels + 1), b - a)
    local = np.stack([pts[:-1], pts[1:]], axis=1) - pivot
    bodies, shapes, types, objs = [], [], [], []
    for i in range(n_panels):
        if mass is None:
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        else:
            body = pymunk.Body(float(mass), math.inf)
        body.position = (float(pivot[0]), float(pivot[1]))
        seg = pymunk.Segment(body, tuple(local[i, 0]), tuple(local[i, 1]), radius)
        seg.friction = friction
        seg.elasticity = 0.0
        seg.collision_type = first_type + i
        seg.filter = WALL_FILTER
        # collinear neighbours: no catching on the joints between panels
        prev = tuple(local[i - 1, 0]) if i > 0 else tuple(local[i, 0])
        nxt = tuple(local[i + 1, 1]) if i < n_panels - 1 else tuple(local[i, 1])
        seg.set_neighbors(prev, nxt)
        bodies.append(body)
        shapes.append(seg)
        types.append(first_type + i)
        objs += (body, seg)
    space.add(*objs)
    return PanelWall(name, bodies, shapes, n, pivot.copy(), types, local)


# ----------------------------------------------------------------------------- drivers
Driver = Callable[[float], tuple[tuple[float, float], float]]


@dataclass(frozen=True)
class Fixed:
    """No motion."""

    def __call__(self, t: float):
        return (0.0, 0.0), 0.0


@dataclass(frozen=True)
class Translate:
    """Constant translation: pivot velocity (vx, vy) [m/s]."""

    velocity: tuple[float, float]

    def __call__(self, t: float):
        return self.velocity, 0.0


@dataclass(frozen=True)
class RotateAbout:
    """Constant rotation about the wall's pivot: omega [rad/s], CCW positive."""

    omega: float

    def __call__(self, t: float):
        return (0.0, 0.0), self.omega


@dataclass(frozen=True)
class Schedule:
    """Any velocity schedule: fn(t) -> ((vx, vy), omega), e.g. a ramp or a hold."""

    fn: Callable[[float], tuple[tuple[float, float], float]] = field(default=lambda t: ((0.0, 0.0), 0.0))

    def __call__(self, t: float):
        return self.fn(t)
