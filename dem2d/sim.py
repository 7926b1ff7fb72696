"""``Sim``: one pymunk space with its grains, panel walls, pressure cells and clock.

Pure state and stepping; no files, no printing. ``snapshot()`` returns bytes (a pickle
of the space and everything that refers into it) that a caller may store; ``restore``
turns them back into a ``Sim``.

What a restored ``Sim`` is and is not:

* pymunk's own unpickling gives a space that stepped 2x slower than the original on a
  6.5k-disk pile (measured here, persistent over 1000 steps; moving the same bodies
  into a new space removes the slow-down). ``restore`` therefore moves every body and
  shape into a fresh space with the solver settings re-applied. The cached contact
  impulses (warm start) are lost: the first steps rebuild them, during which grains
  move by about g dt^2 per step (1e-7 m); a short re-settling should follow.
* The continuation is not bit-for-bit the same as the uninterrupted run (it never is
  after pickling: ../shared/STACK.md 1.8), but two restores of the same bytes continue
  identically. Use snapshots to branch runs from one settled specimen.
"""

from __future__ import annotations

import pickle
from dataclasses import dataclass, field

import numpy as np
import pymunk

from .build import Grains
from .frames import BodyState, Frame, body_state, make_frame
from .params import Solver
from .probes import PanelProbe
from .walls import Driver, PanelWall


@dataclass
class Sim:
    """A running 2D DEM model.

    space:   the pymunk space
    grains:  registry of dynamic bodies (creation order)
    walls:   panel walls by name, in the order their panels appear in probe/frame arrays
    solver:  settings in force
    step_count, time: clock [-, s]
    rng:     the model's random generator (pluviation draws from it)
    """

    space: pymunk.Space
    grains: Grains
    walls: dict
    solver: Solver
    rng: np.random.Generator
    step_count: int = 0
    time: float = 0.0
    drivers: dict = field(default_factory=dict)
    hooks: list = field(default_factory=list)
    meta: dict = field(default_factory=dict)
    _probe: PanelProbe | None = None

    @property
    def probe(self) -> PanelProbe:
        """Pressure cells on every panel of every wall (created on first use)."""
        if self._probe is None:
            self._probe = PanelProbe(self.space, list(self.walls.values()))
        return self._probe

    @property
    def dt(self) -> float:
        return self.solver.dt

    def drive(self, name: str, driver: Driver | None) -> None:
        """Attach a motion driver to a wall (None: hold it still)."""
        if driver is None:
            self.drivers.pop(name, None)
            self.walls[name].set_motion((0.0, 0.0), 0.0)
        else:
            self.drivers[name] = driver

    def run(self, n_steps: int) -> None:
        """Advance ``n_steps`` steps of dt, applying the wall drivers and the hooks
        (callables ``hook(sim)``, e.g. a servo setting a wall's force) before each step,
        and counting each step into the open probe window."""
        space, dt = self.space, self.solver.dt
        probe = self._probe
        hooks = self.hooks
        for _ in range(n_steps):
            for name, drv in self.drivers.items():
                self.walls[name].drive(drv, self.time)
            for h in hooks:
                h(self)
            space.step(dt)
            self.step_count += 1
            self.time += dt
            if probe is not None and probe.active:
                probe.record_step(dt)

    def state(self) -> BodyState:
        """Grain positions, angles, velocities, spins (creation order)."""
        return body_state(self.space, self.grains)

    def masses(self) -> np.ndarray:
        return self.grains.masses()

    def frame(self, with_contacts: bool = True) -> Frame:
        """A ``Frame`` with the panel forces of the current probe window."""
        walls = list(self.walls.values())
        pf = self.probe.force() if self._probe is not None else None
        return make_frame(self.space, self.grains, self.step_count, self.time, self.solver.dt,
                          walls, pf, with_contacts)

    def set_solver(self, solver: Solver) -> None:
        """Change dt / iterations / slop / bias in place (e.g. for a sensitivity check).
        The broad phase is not changed."""
        r_min = self.meta.get("r_min")
        self.space.iterations = solver.iterations
        self.space.collision_bias = solver.collision_bias
        if r_min is not None:
            self.space.collision_slop = solver.slop_fraction * r_min
        self.solver = solver

    # ------------------------------------------------------------------ snapshots
    def snapshot(self) -> bytes:
        """Pickle of the whole model (probe callbacks are switched off first)."""
        if self._probe is not None:
            self._probe.stop()
        probe, self._probe = self._probe, None
        drivers, self.drivers = self.drivers, {}
        hooks, self.hooks = self.hooks, []
        try:
            return pickle.dumps(self, protocol=pickle.HIGHEST_PROTOCOL)
        finally:
            self._probe = probe
            self.drivers = drivers
            self.hooks = hooks


def restore(blob: bytes) -> Sim:
    """Inverse of ``Sim.snapshot``, in a fresh space (module docstring)."""
    sim = pickle.loads(blob)
    if not isinstance(sim, Sim):
        raise TypeError("not a dem2d snapshot")
    old = sim.space
    new = pymunk.Space(threaded=sim.solver.threads > 1)
    if sim.solver.threads > 1:
        new.threads = sim.solver.threads
    new.gravity = old.gravity
    new.damping = old.damping
    new.sleep_time_threshold = old.sleep_time_threshold
    bodies = list(old.bodies)
    shapes = list(old.shapes)
    old.remove(*shapes)
    old.remove(*bodies)
    sim.space = new
    sim.set_solver(sim.solver)
    if sim.solver.spatial_hash and "d_max" in sim.meta:
        new.use_spatial_hash(sim.meta["d_max"], max(4 * len(shapes), 1000))
    objs = []
    for b in bodies:
        objs.append(b)
        objs.extend(b.shapes)
    new.add(*objs)
    sim.grains._ids_sorted = None
    return sim
