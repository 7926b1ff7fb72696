"""Wall geometry (rectangular panels) and wall motion (drivers), kept apart.

A *panel* is a planar rectangle with its own friction coefficient; a *wall* is a named
group of panels moved rigidly by one *motion* (LIGGGHTS mesh movers; HOOMD keeps wall
geometry apart from wall interaction). The interaction is the particle contact law with
the wall's mass and radius infinite (dem3d.kernels.gather_and_move).

Conventions
-----------
* A panel's ``normal`` = e1 x e2 points from the wall INTO the particles. Spheres interact
  only with the front side.
* Force on a panel is the force exerted BY the particles ON the panel, so particles
  pressing on it give ``force . normal < 0``; the normal stress on it (compression
  positive) is ``-force . normal / area``.
* A panel's moment is taken about the panel's current centre.
* Infinite extents (``np.inf``) make an unbounded plane; such a panel reports corners and
  area with its ``nominal_half`` extent instead (e.g. half the periodic length, so a
  periodic slab's wall has the area of one period).

Motion (pure functions of time; the engine integrates them):
a wall's pivot P moves with velocity V(t); the wall turns about the axis a through P at
angular speed omega(t) (right-handed). A point q of the wall moves at
V + omega a x (q - P). Over a step the pose is advanced with the mid-step values
(rotation about P by omega(t + dt/2) dt, then translation by V(t + dt/2) dt), which is
exact for schedules linear in time. A translation may instead be given by its
displacement history D(t) (``history``, ``shaking``): the pivot then advances by
D(t + dt) - D(t) over each step, so the wall sits at P + D(t) at every step to round-off
(any V(t), e.g. a sinusoid, is reproduced exactly, not to the midpoint rule's O(dt^2)),
and the velocity the contacts see is the step's mean velocity (D(t + dt) - D(t)) / dt,
consistent with the spheres' half-step (leapfrog) velocities: with V(t + dt) instead,
a shaken base would load its contacts' tangential springs by a spurious V dt / 2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from analytic.errors import InvalidParameter

from .state import Panels

Vector = Sequence[float]


@dataclass(frozen=True)
class Panel:
    """One rectangular panel: centre [m], unit in-plane axes e1, e2, half extents [m]
    (np.inf = unbounded), friction mu, shared edges (-e1, +e1, -e2, +e2), and the nominal
    half extents used for corners/area where an extent is unbounded."""

    centre: tuple
    e1: tuple
    e2: tuple
    half: tuple
    mu: float = 0.0
    shared: tuple = (False, False, False, False)
    nominal_half: tuple = (1.0, 1.0)

    @property
    def normal(self) -> np.ndarray:
        return np.cross(self.e1, self.e2)


def rectangle(centre: Vector, e1: Vector, e2: Vector, half_extents: Vector, mu: float = 0.0) -> Panel:
    """A finite panel; ``e1``, ``e2`` must be orthogonal (they are normalised); the normal
    e1 x e2 must point towards the particles."""
    u = _unit("e1", e1)
    v = _unit("e2", e2)
    if abs(float(np.dot(u, v))) > 1e-12:
        raise InvalidParameter("e1.e2", float(np.dot(u, v)), "0 (orthogonal axes)")
    a, b = (float(h) for h in half_extents)
    if not (a > 0 and b > 0):
        raise InvalidParameter("half_extents", (a, b), "> 0 m")
    return Panel(tuple(map(float, centre)), tuple(u), tuple(v), (a, b), float(mu),
                 nominal_half=(a if math.isfinite(a) else 1.0, b if math.isfinite(b) else 1.0))


def plane(point: Vector, normal: Vector, mu: float = 0.0, nominal_half: Vector = (1.0, 1.0)) -> Panel:
    """An unbounded plane through ``point`` whose ``normal`` points towards the particles."""
    n = _unit("normal", normal)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(helper, n)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    return Panel(tuple(map(float, point)), tuple(e1), tuple(e2), (np.inf, np.inf), float(mu),
                 nominal_half=tuple(map(float, nominal_half)))


def segmented_wall(base_centre: Vector, normal: Vector, up: Vector, width: float, height: float,
                   n_segments: int, mu: float = 0.0, *, unbounded_width: bool = False) -> list[Panel]:
    """A flat wall of ``n_segments`` equal panels stacked along ``up`` from ``base_centre``
    (the middle of its bottom edge). ``normal`` points into the backfill.

    Adjacent panels share their edges (no edge contact, half-open ownership), so a sphere
    pressing on the wall is counted on exactly one panel. ``unbounded_width`` makes the
    panels infinite across the wall (use it when the width direction is periodic); the
    nominal width still sets the area.
    """
    n = _unit("normal", normal)
    e2 = _unit("up", up)
    if abs(float(np.dot(n, e2))) > 1e-12:
        raise InvalidParameter("up.normal", float(np.dot(n, e2)), "0 (up must lie in the wall)")
    if int(n_segments) < 1:
        raise InvalidParameter("n_segments", n_segments, ">= 1")
    e1 = np.cross(e2, n)           # so that e1 x e2 = n
    h = float(height) / int(n_segments)
    a = np.inf if unbounded_width else 0.5 * float(width)
    panels = []
    for k in range(int(n_segments)):
        c = np.asarray(base_centre, float) + (k + 0.5) * h * e2
        shared = (False, False, k > 0, k < n_segments - 1)
        panels.append(Panel(tuple(c), tuple(e1), tuple(e2), (a, 0.5 * h), float(mu), shared,
                            nominal_half=(0.5 * float(width), 0.5 * h)))
    return panels


BOX_FACES = ("floor", "x-", "x+", "y-", "y+", "top")


def box(lo: Vector, hi: Vector, mu: float = 0.0, *, top: bool = False, periodic_axis: int = -1,
        omit: Sequence[str] = ()) -> list[Panel]:
    """The inner faces of an axis-aligned box [lo, hi] (normals inward), in the order
    floor (z = lo), x- (x = lo), x+, y-, y+, and the lid ("top") if ``top``. Faces named in
    ``omit`` are left out (e.g. ("x-",) where a segmented wall takes its place), as are
    faces normal to ``periodic_axis``; the others are unbounded along that axis (nominal
    extent = the box length)."""
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    for name in omit:
        if name not in BOX_FACES:
            raise InvalidParameter("omit", name, ", ".join(BOX_FACES))
    mid = 0.5 * (lo + hi)
    halfw = 0.5 * (hi - lo)
    panels = []
    faces = [("floor", 2, lo[2], +1.0), ("x-", 0, lo[0], 1.0), ("x+", 0, hi[0], -1.0),
             ("y-", 1, lo[1], 1.0), ("y+", 1, hi[1], -1.0)]
    if top:
        faces.append(("top", 2, hi[2], -1.0))
    for name, ax, value, sign in faces:
        if ax == periodic_axis or name in omit:
            continue
        n = np.zeros(3)
        n[ax] = sign
        others = [d for d in range(3) if d != ax]
        e1 = np.zeros(3)
        e1[others[0]] = 1.0
        e2 = np.cross(n, e1)
        c = mid.copy()
        c[ax] = value
        half = []
        nominal = []
        for e in (e1, e2):
            d = int(np.argmax(np.abs(e)))
            nominal.append(float(halfw[d]))
            half.append(np.inf if d == periodic_axis else float(halfw[d]))
        panels.append(Panel(tuple(c), tuple(e1), tuple(e2), tuple(half), float(mu),
                            nominal_half=tuple(nominal)))
    return panels


# --------------------------------------------------------------------------------------
# motion
# --------------------------------------------------------------------------------------

def _zero_speed(t: float) -> float:
    return 0.0


def _zero_velocity(t: float) -> tuple:
    return (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Motion:
    """Rigid motion of a wall (see the module docstring).

    pivot:          point P at t = 0 [m]; it moves with the translation
    axis:           unit rotation axis
    angular_speed:  omega(t) [rad/s], right-handed about ``axis``
    velocity:       V(t) [m/s] (3,)
    displacement:   None, or D(t) [m] (3,) with D' = V: the translation then follows D
                    exactly (module docstring)
    """

    pivot: tuple = (0.0, 0.0, 0.0)
    axis: tuple = (0.0, 0.0, 1.0)
    angular_speed: Callable[[float], float] = _zero_speed
    velocity: Callable[[float], Vector] = _zero_velocity
    displacement: Callable[[float], Vector] | None = None

    @property
    def is_fixed(self) -> bool:
        return (self.angular_speed is _zero_speed and self.velocity is _zero_velocity
                and self.displacement is None)


FIXED = Motion()


def translation(velocity: Vector | Callable[[float], Vector]) -> Motion:
    """Translation at a constant velocity [m/s] or a schedule V(t)."""
    if callable(velocity):
        return Motion(velocity=velocity)
    v = tuple(float(c) for c in velocity)
    return Motion(velocity=_Constant(v))


def rotation(pivot: Vector, axis: Vector, angular_speed: float | Callable[[float], float],
             velocity: Vector | Callable[[float], Vector] | None = None) -> Motion:
    """Rotation about ``axis`` through ``pivot`` at a constant angular speed [rad/s] or a
    schedule omega(t); optionally combined with a translation of the pivot."""
    speed = angular_speed if callable(angular_speed) else _Constant(float(angular_speed))
    vel = _zero_velocity if velocity is None else (
        velocity if callable(velocity) else _Constant(tuple(float(c) for c in velocity)))
    return Motion(tuple(map(float, pivot)), tuple(_unit("axis", axis)), speed, vel)


def history(displacement: Callable[[float], Vector], velocity: Callable[[float], Vector]) -> Motion:
    """Translation following a displacement history D(t) [m] exactly; ``velocity`` is
    V(t) = D'(t) [m/s] (kept for callers; the contacts see the step's mean velocity, see
    the module docstring); e.g. base shaking."""
    return Motion(velocity=velocity, displacement=displacement)


def shaking(table: "AccelerationTable") -> Motion:
    """A wall driven by an acceleration history (base shaking): translation by the
    table's exact double integral D(t), velocity V(t)."""
    return history(table.displacement, table.velocity)


class AccelerationTable:
    """A translation driven by an acceleration history a(t) [m/s^2] (3,), piecewise
    linear through samples (t_k, a_k), zero before t_0 and after the last sample; starting
    at rest at t_0. Velocity and displacement are the exact integrals of that piecewise-
    linear a (on [t_k, t_k+1], tau = t - t_k, s = (a_k+1 - a_k) / h):
        v = v_k + a_k tau + s tau^2 / 2,   d = d_k + v_k tau + a_k tau^2 / 2 + s tau^3 / 6,
    so a wall moved by ``shaking(table)`` reproduces them exactly (to round-off).

    times: (m,) increasing [s]; accel: (m,) along ``direction`` or (m, 3) [m/s^2].
    """

    def __init__(self, times, accel, direction: Vector = (1.0, 0.0, 0.0)):
        t = np.asarray(times, float).reshape(-1)
        a = np.asarray(accel, float)
        if a.ndim == 1:
            a = a[:, None] * _unit("direction", direction)[None, :]
        if t.shape[0] < 2 or a.shape != (t.shape[0], 3) or not np.all(np.diff(t) > 0):
            raise InvalidParameter("times", t.shape[0], ">= 2 increasing samples with one acceleration each")
        h = np.diff(t)[:, None]
        slope = np.diff(a, axis=0) / h
        v = np.zeros_like(a)
        d = np.zeros_like(a)
        v[1:] = np.cumsum(a[:-1] * h + 0.5 * slope * h ** 2, axis=0)
        for k in range(len(h)):
            d[k + 1] = d[k] + v[k] * h[k] + 0.5 * a[k] * h[k] ** 2 + slope[k] * h[k] ** 3 / 6.0
        self.times, self.accel, self.slope, self.v, self.d = t, a, slope, v, d

    @classmethod
    def sampled(cls, accel: Callable[[float], float], t_end: float, samples: int,
                direction: Vector = (1.0, 0.0, 0.0)) -> "AccelerationTable":
        """A table of a(t) [m/s^2] (a function of time, scalar along ``direction`` or
        a 3-vector) sampled at ``samples`` equal steps on [0, t_end] [s]: the motion is
        then that piecewise-linear interpolant, integrated exactly."""
        t = np.linspace(0.0, float(t_end), int(samples) + 1)
        a = np.array([accel(float(tk)) for tk in t], float)
        return cls(t, a, direction)

    def _segment(self, t: float):
        k = int(np.searchsorted(self.times, t, side="right")) - 1
        return min(k, len(self.times) - 1)

    def acceleration(self, t: float) -> tuple:
        if t < self.times[0] or t >= self.times[-1]:
            return (0.0, 0.0, 0.0)
        k = self._segment(t)
        return tuple(self.accel[k] + self.slope[k] * (t - self.times[k]))

    def velocity(self, t: float) -> tuple:
        if t <= self.times[0]:
            return (0.0, 0.0, 0.0)
        k = self._segment(t)
        tau = t - self.times[k]
        if k == len(self.times) - 1:
            return tuple(self.v[k])
        return tuple(self.v[k] + self.accel[k] * tau + 0.5 * self.slope[k] * tau ** 2)

    def displacement(self, t: float) -> tuple:
        if t <= self.times[0]:
            return (0.0, 0.0, 0.0)
        k = self._segment(t)
        tau = t - self.times[k]
        if k == len(self.times) - 1:
            return tuple(self.d[k] + self.v[k] * tau)
        return tuple(self.d[k] + self.v[k] * tau + 0.5 * self.accel[k] * tau ** 2
                     + self.slope[k] * tau ** 3 / 6.0)


def sine_envelope(t, t_up: float, t_hold: float, t_down: float):
    """Trapezoidal envelope [-]: 0 -> 1 linearly over t_up, 1 for t_hold, 1 -> 0 over
    t_down, 0 after (the seismic study's 3 s ramp, 4 s hold, 1 s decay, prototype)."""
    t = np.asarray(t, float)
    up = np.clip(t / t_up, 0.0, 1.0) if t_up > 0 else (t >= 0).astype(float)
    t2 = t_up + t_hold
    down = np.clip(1.0 - (t - t2) / t_down, 0.0, 1.0) if t_down > 0 else (t < t2).astype(float)
    return np.where(t < 0, 0.0, np.minimum(up, down))


def sine_ramp(amplitude: float, frequency: float, t_up: float, t_hold: float, t_down: float, *,
              direction: Vector = (1.0, 0.0, 0.0), samples_per_period: int = 400,
              zero_final_velocity: bool = True) -> AccelerationTable:
    """Base acceleration a(t) = amplitude env(t) sin(2 pi f t) [m/s^2] (``sine_envelope``),
    sampled ``samples_per_period`` times per period into an AccelerationTable that ends
    with the envelope. With ``zero_final_velocity`` a constant acceleration -V_end / T
    over the motion's duration T is added (baseline correction) so the base ends at rest
    rather than drifting; it is of order amplitude / (2 pi f T) and is stated by
    ``table.accel`` itself."""
    amplitude = float(amplitude)
    frequency = float(frequency)
    if not (frequency > 0 and samples_per_period >= 8):
        raise InvalidParameter("frequency", frequency, "> 0 Hz with >= 8 samples per period")
    duration = t_up + t_hold + t_down
    m = int(math.ceil(duration * frequency * samples_per_period)) + 1
    t = np.linspace(0.0, duration, m)
    a = amplitude * sine_envelope(t, t_up, t_hold, t_down) * np.sin(2.0 * math.pi * frequency * t)
    table = AccelerationTable(t, a, direction)
    if zero_final_velocity:
        e = _unit("direction", direction)
        v_end = float(np.dot(table.v[-1], e))
        table = AccelerationTable(t, a - v_end / duration, direction)
    return table


class Steady:
    """A velocity schedule that is the same at every time of the steps it is asked for:
    ``Walls.schedule`` reads it once per call, not at every step."""


@dataclass(frozen=True)
class _Constant(Steady):
    value: object

    def __call__(self, t: float):
        return self.value


@dataclass(frozen=True)
class Ramp:
    """A schedule rising linearly from 0 at t = 0 to ``value`` at ``t_ramp``, then constant
    (scalar or vector ``value``); smooth starts avoid a velocity jump on the backfill."""

    value: object
    t_ramp: float

    def __call__(self, t: float):
        s = 1.0 if t >= self.t_ramp else max(t, 0.0) / self.t_ramp
        if np.ndim(self.value) == 0:
            return s * float(self.value)
        return tuple(s * float(c) for c in self.value)


@dataclass(frozen=True)
class Wall:
    """A named group of panels moved together by one motion."""

    name: str
    panels: tuple
    motion: Motion = FIXED

    def __init__(self, name: str, panels, motion: Motion = FIXED):
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "panels", tuple([panels] if isinstance(panels, Panel) else panels))
        object.__setattr__(self, "motion", motion)


class WallSet:
    """The engine's wall state: panel arrays (a ``Panels`` record, updated in place), the
    current pivot of each wall, and the reference pose for the Verlet skin test."""

    def __init__(self, walls: Sequence[Wall]):
        self.walls = tuple(walls)
        panels = [p for w in self.walls for p in w.panels]
        n = len(panels)
        self.wall_of_panel = np.array([k for k, w in enumerate(self.walls) for _ in w.panels], np.int64)
        self.names = [w.name for w in self.walls]
        self.panels = Panels(
            centre=np.array([p.centre for p in panels], float).reshape(n, 3),
            e1=np.array([p.e1 for p in panels], float).reshape(n, 3),
            e2=np.array([p.e2 for p in panels], float).reshape(n, 3),
            normal=np.array([p.normal for p in panels], float).reshape(n, 3),
            half=np.array([p.half for p in panels], float).reshape(n, 2),
            mu=np.array([p.mu for p in panels], float).reshape(n),
            shared=np.array([p.shared for p in panels], np.uint8).reshape(n, 4),
            vel=np.zeros((n, 3)),
            omega=np.zeros((n, 3)),
            mat=np.zeros(n, np.int32),
        )
        self.nominal_half = np.array([p.nominal_half for p in panels], float).reshape(n, 2)
        self.pivot = np.array([w.motion.pivot for w in self.walls], float).reshape(len(self.walls), 3)
        self.axis = np.array([w.motion.axis for w in self.walls], float).reshape(len(self.walls), 3)
        self.mark_reference()

    @property
    def n_panels(self) -> int:
        return self.panels.centre.shape[0]

    def panel_ids(self, name: str) -> np.ndarray:
        """Indices of the panels of the wall called ``name`` (bottom to top for segmented walls)."""
        k = self.names.index(name)
        return np.nonzero(self.wall_of_panel == k)[0]

    def set_velocities(self, t: float) -> None:
        """Panel centre velocity and angular velocity at time t from each wall's motion."""
        pan = self.panels
        for k, w in enumerate(self.walls):
            if w.motion.is_fixed:
                continue
            ids = self.wall_of_panel == k
            om = float(w.motion.angular_speed(t)) * self.axis[k]
            vel = np.asarray(w.motion.velocity(t), float)
            pan.omega[ids] = om
            pan.vel[ids] = vel + np.cross(om, pan.centre[ids] - self.pivot[k])

    def schedule(self, t0: float, dt: float, n_steps: int):
        """Motion samples for the next ``n_steps`` steps from time t0: angular speed and
        pivot velocity at each step's mid time and end time,
        (om_mid (n, nw), v_mid (n, nw, 3), om_end (n, nw), v_end (n, nw, 3)).
        Times are accumulated t += dt exactly as the engine does."""
        nw = len(self.walls)
        om_mid = np.zeros((n_steps, nw))
        v_mid = np.zeros((n_steps, nw, 3))
        om_end = np.zeros((n_steps, nw))
        v_end = np.zeros((n_steps, nw, 3))
        movers = []
        for k, w in enumerate(self.walls):
            m = w.motion
            if m.is_fixed:
                continue
            if m.angular_speed is _zero_speed and m.displacement is None and isinstance(m.velocity, Steady):
                v_mid[:, k] = v_end[:, k] = m.velocity(t0)    # the same value at every time of the steps
            else:
                movers.append((k, m))
        if not movers:
            return om_mid, v_mid, om_end, v_end
        t = t0
        # D at each step's end is D at the next step's start: evaluated once
        d_end = {k: np.asarray(m.displacement(t), float) for k, m in movers if m.displacement is not None}
        for s in range(n_steps):
            tm = t + 0.5 * dt
            t = t + dt
            for k, m in movers:
                om_mid[s, k] = m.angular_speed(tm)
                if m.displacement is None:
                    v_mid[s, k] = m.velocity(tm)
                else:        # the step's mean velocity: the pivot advances by D(t) - D(t - dt)
                    d_start, d_end[k] = d_end[k], np.asarray(m.displacement(t), float)
                    v_mid[s, k] = (d_end[k] - d_start) / dt
                om_end[s, k] = m.angular_speed(t)
                # a history wall shows the contacts its mean velocity over the step just
                # taken, the same half-step velocity the spheres' leapfrog carries, so a
                # contact's tangential increment is exactly the wall's displacement
                v_end[s, k] = m.velocity(t) if m.displacement is None else v_mid[s, k]
        return om_mid, v_mid, om_end, v_end

    @property
    def moving(self) -> np.ndarray:
        """(nw,) uint8: 1 for walls with a motion."""
        return np.array([0 if w.motion.is_fixed else 1 for w in self.walls], np.uint8)

    def reset_pivots(self) -> None:
        """Pivots back to each wall's motion definition: for starting new motions on a
        state restored with ``Simulation.from_arrays`` (which restores the stored pivots,
        right for resuming the same motion)."""
        self.pivot[...] = np.array([w.motion.pivot for w in self.walls], float).reshape(len(self.walls), 3)

    def mark_reference(self) -> None:
        pan = self.panels
        self._ref = (pan.centre.copy(), pan.e1.copy(), pan.e2.copy())

    def max_displacement(self) -> float:
        """Upper bound of the displacement of any panel point since ``mark_reference`` [m]."""
        from .kernels import wall_displacement
        return float(wall_displacement(self.panels, *self._ref))

    def corners(self) -> np.ndarray:
        """(p, 4, 3) panel corners [m], counter-clockwise seen from the particles;
        unbounded extents use the nominal half extent."""
        pan = self.panels
        half = np.where(np.isfinite(pan.half), pan.half, self.nominal_half)
        a = half[:, 0:1] * pan.e1
        b = half[:, 1:2] * pan.e2
        c = pan.centre
        return np.stack([c - a - b, c + a - b, c + a + b, c - a + b], axis=1)

    def areas(self) -> np.ndarray:
        """(p,) panel areas [m^2] (nominal extent where unbounded)."""
        half = np.where(np.isfinite(self.panels.half), self.panels.half, self.nominal_half)
        return 4.0 * half[:, 0] * half[:, 1]


def rotation_matrix(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues: rotation by ``angle`` [rad] about the unit ``axis`` (right-handed)."""
    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    k = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def _unit(name: str, v: Vector) -> np.ndarray:
    a = np.asarray(v, float).reshape(3)
    norm = float(np.linalg.norm(a))
    if not (norm > 0 and math.isfinite(norm)):
        raise InvalidParameter(name, tuple(a), "a non-zero finite vector")
    return a / norm
