"""``Sim``: one pymunk space with its grains, panel walls, pressure cells and clock.

Pure state and stepping; no files, no printing. ``snapshot()`` returns bytes that a
caller may store; ``restore`` turns them back into a running ``Sim``.

Why not pymunk's own pickling of the Space (measured here on pymunk 7.3.1):

* it is O(bodies x contacts): ``_arbiter_to_dict`` rebuilds a dict of every body and
  shape for every cached arbiter (100 s for a 15k-disk pile; hours at 50k);
* the unpickled space stepped 2.5x slower than the original (its arbiters live in
  Python-allocated memory);
* without the cached contact impulses (warm start) a settled pile is *not* settled in
  a fresh space: with 10 solver iterations the weight needs tens of steps to reach the
  floor, and the pile falls and shakes (mean grain speed 6 cm/s after restart, 15k disks).

So a snapshot holds the bodies and shapes (pickled one by one, without the space), the
``Sim`` around them, and the accumulated normal and tangential impulse of every
touching pair read through ``pymunk.batch`` (body ids -> indices). ``restore`` adds the
bodies to a fresh space, sets the space's previous time step (so Chipmunk's warm-start
factor dt/prev_dt is 1, not 0) and, during the first step only, writes the saved
impulses into each new arbiter in a ``pre_solve`` callback and marks it as not new, so
Chipmunk applies them as cached impulses. This uses private fields of the cffi arbiter
(``contacts[i].jnAcc/jtAcc``, ``state``), checked on pymunk 7.3.1 only; it is exact for
one-point contacts (disk-disk, disk-wall), and polygon pairs (two points) restart cold.
The continuation is close to, not bit-for-bit, the uninterrupted run; two restores of
the same bytes continue identically.
"""

from __future__ import annotations

import pickle
import signal
import threading
from contextlib import contextmanager
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
        with sigint_between_steps() as interrupted:
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
                if interrupted:
                    raise KeyboardInterrupt

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

    # ------------------------------------------------------------------ holding grains
    def _stable_bodies(self) -> list:
        """Grains in creation order, then every wall panel body in wall order: an
        indexing of the bodies that survives snapshots (pymunk's own order does not)."""
        return list(self.grains.bodies) + [b for w in self.walls.values() for b in w.bodies]

    def held(self) -> np.ndarray:
        """(n,) True for grains held static by ``hold``."""
        return np.array([b.body_type == pymunk.Body.STATIC for b in self.grains.bodies], bool)

    def hold(self, index: np.ndarray, tag: float = float("nan")) -> int:
        """Hold grains ``index`` (creation indices) static where they are: a static body
        leaves the solver and the per-step rehash of the broad phase, so a settled deposit
        under the layer that is falling costs almost nothing per step. Contacts between
        two held grains, or a held grain and a wall, are dropped by Chipmunk (two bodies
        of infinite mass); their accumulated impulses are kept here so ``release_all``
        can warm-start them; each saved contact keeps ``tag`` (the caller's note of
        when it was saved, e.g. the surface height). Returns the number newly held."""
        bodies = self._stable_bodies()
        held = self.held()
        new = np.zeros(len(bodies), bool)
        idx = np.asarray(index, dtype=np.int64)
        idx = idx[~held[idx]]
        if len(idx) == 0:
            return 0
        new[idx] = True
        still = np.zeros(len(bodies), bool)  # non-dynamic after this call
        still[:len(held)] = held
        still[len(held):] = True  # wall panels (kinematic)
        still |= new
        c = _contact_impulses(self.space, bodies)
        keep = (new[c["a"]] | new[c["b"]]) & still[c["a"]] & still[c["b"]]
        c["tag"] = np.full(len(c["a"]), float(tag))
        saved = self.meta.setdefault("held_contacts", _no_contacts())
        for k in ("a", "b", "impulse", "tag"):
            saved[k] = np.concatenate([saved[k], c[k][keep]])
        mm = self.meta.setdefault("held_mass", {})
        for i in idx.tolist():
            b = self.grains.bodies[i]
            mm[i] = (b.mass, b.moment)
            b.body_type = pymunk.Body.STATIC
        return len(idx)

    def held_contacts(self) -> dict:
        """The contacts ``hold`` dropped: a, b (m,) grain indices, impulse (m,2) on a
        [N s/m] when saved, tag (m,)."""
        return self.meta.get("held_contacts", _no_contacts())

    def release_all(self, factor: np.ndarray | None = None, rebuild: bool = False) -> int:
        """Make every held grain dynamic again (mass and moment as before) and arm the
        next step to give the contacts dropped while they were held their saved
        impulses (the warm start of ``restore``), each times ``factor`` (m,) if given:
        the load on a held contact grew while more grains were laid above it, and a
        warm start at the old load lets the deposit sink until the solver, ten contacts
        per step, has carried the difference down. ``rebuild``: also rebuild the space
        from a snapshot (``restore``): moving bodies between Chipmunk's static and
        dynamic arrays scrambles their order in memory, and insertion order changes
        the cost of a step (docs/dem2d.md); the rebuilt space has the grains in
        creation order. Returns the number released."""
        mm = self.meta.pop("held_mass", {})
        for i, (m, moment) in mm.items():
            b = self.grains.bodies[i]
            b.body_type = pymunk.Body.DYNAMIC
            b.mass, b.moment = m, moment
        c = self.meta.pop("held_contacts", None)
        if c is not None and factor is not None:
            c = {**c, "impulse": c["impulse"] * np.asarray(factor, float)[:, None]}
        if rebuild:
            fresh = restore(self.snapshot(extra_contacts=c))
            self.__dict__.update(fresh.__dict__)
        elif c is not None and len(c["a"]):
            _warm_start(self.space, self._stable_bodies(), c, self.solver.dt)
        return len(mm)

    # ------------------------------------------------------------------ snapshots
    def snapshot(self, extra_contacts: dict | None = None) -> bytes:
        """Bytes that ``restore`` turns back into this model (module docstring). Bodies
        are stored grains first, in creation order (layer by layer, so a restored space
        has its bodies in memory roughly in spatial order), then the wall panels.
        ``extra_contacts`` (a, b, impulse as in ``held_contacts``, indices in that same
        order) are warm-started too."""
        if self._probe is not None:
            self._probe.stop()
        space = self.space
        bodies = self._stable_bodies()
        known = set(bodies)
        bodies += [b for b in space.bodies if b not in known]
        shapes = list(space.shapes)
        contacts = _contact_impulses(space, bodies)
        if extra_contacts is not None and len(extra_contacts["a"]):
            contacts = {k: np.concatenate([contacts[k], extra_contacts[k]]) for k in ("a", "b", "impulse")}
        state = {k: v for k, v in self.__dict__.items() if k not in ("space", "_probe", "drivers", "hooks")}
        payload = {"format": "wallsim-dem2d-snapshot-1", "sim": state, "bodies": bodies, "shapes": shapes,
                   "gravity": tuple(space.gravity), "damping": space.damping,
                   "sleep_time_threshold": space.sleep_time_threshold, "contacts": contacts}
        return pickle.dumps(payload, protocol=pickle.HIGHEST_PROTOCOL)


@contextmanager
def sigint_between_steps():
    """Ctrl-C while chipmunk steps would raise inside a post-solve callback (cffi), where
    Python prints "Exception ignored from cffi callback" and the run carries on. Inside
    this block SIGINT only marks the list it yields; the step loop raises
    KeyboardInterrupt after the step. Outside the main thread signals cannot be caught,
    and nothing changes."""
    marks: list = []
    if threading.current_thread() is not threading.main_thread() or signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        yield marks               # no handler to defer (or Ctrl-C deliberately ignored): leave it be
        return
    previous = signal.signal(signal.SIGINT, lambda signum, frame: marks.append(signum))
    try:
        yield marks
    finally:
        signal.signal(signal.SIGINT, previous if previous is not None else signal.default_int_handler)


def _no_contacts() -> dict:
    """An empty record of saved contacts (the layout ``Sim.hold`` keeps)."""
    return {"a": np.zeros(0, np.int64), "b": np.zeros(0, np.int64), "impulse": np.zeros((0, 2)),
            "tag": np.zeros(0)}


def _contact_impulses(space: pymunk.Space, bodies: list) -> dict:
    """Accumulated impulse of every touching one-point contact, keyed by body index in
    ``bodies``: arrays a, b (m,), impulse on a (m,2) [N s/m]."""
    from .frames import raw_arbiters

    ids = np.array([b.id for b in bodies], dtype=np.uintp)
    order = np.argsort(ids)
    ids_s = ids[order]
    aid, bid, count, J = raw_arbiters(space)
    ka = np.minimum(np.searchsorted(ids_s, aid), len(ids_s) - 1)
    kb = np.minimum(np.searchsorted(ids_s, bid), len(ids_s) - 1)
    ok = (count == 1) & (ids_s[ka] == aid) & (ids_s[kb] == bid)
    return {"a": order[ka[ok]], "b": order[kb[ok]], "impulse": J[ok]}


def restore(blob: bytes) -> Sim:
    """Inverse of ``Sim.snapshot``: a fresh space with the saved bodies, shapes and
    contact impulses (module docstring)."""
    payload = pickle.loads(blob)
    if not isinstance(payload, dict) or payload.get("format") != "wallsim-dem2d-snapshot-1":
        raise TypeError("not a dem2d snapshot")
    sim = Sim.__new__(Sim)
    sim.__dict__.update(payload["sim"])
    sim.drivers, sim.hooks, sim._probe = {}, [], None
    solver = sim.solver
    space = pymunk.Space(threaded=solver.threads > 1)
    if solver.threads > 1:
        space.threads = solver.threads
    space.gravity = payload["gravity"]
    space.damping = payload["damping"]
    space.sleep_time_threshold = payload["sleep_time_threshold"]
    sim.space = space
    sim.set_solver(solver)
    bodies, shapes = payload["bodies"], payload["shapes"]
    if solver.spatial_hash and "d_max" in sim.meta:
        space.use_spatial_hash(sim.meta["d_max"], max(4 * len(shapes), 1000))
    objs = []
    for b in bodies:
        objs.append(b)
        objs.extend(b.shapes)
    space.add(*objs)
    sim.grains._ids_sorted = None
    c = payload["contacts"]
    if len(c["a"]):
        _warm_start(space, bodies, c, solver.dt)
    return sim


def _warm_start(space: pymunk.Space, bodies: list, c: dict, dt: float) -> None:
    """Arm a one-step pre_solve that gives every new arbiter its saved impulse."""
    from pymunk._chipmunk_cffi import ffi, lib

    index = {b: k for k, b in enumerate(bodies)}
    saved = {}
    for a, b, J in zip(c["a"].tolist(), c["b"].tolist(), c["impulse"].tolist()):
        saved[(a, b)] = J
    normal_state = lib.CP_ARBITER_STATE_NORMAL

    def pre_solve(arbiter: pymunk.Arbiter, space_, data) -> None:
        arb = arbiter._arbiter
        if arb.count != 1:
            return
        b0, b1 = arbiter.bodies
        i0, i1 = index.get(b0), index.get(b1)
        if i0 is None or i1 is None:
            return
        # J on body i0 (the saved impulse is on the saved pair's first body)
        if (i0, i1) in saved:
            jx, jy = saved[(i0, i1)]
        elif (i1, i0) in saved:
            jx, jy = saved[(i1, i0)]
            jx, jy = -jx, -jy
        else:
            return
        # impulse on the struct's body_a is -rotate(n, (jn, jt))
        if arb.body_a != b0._body:
            jx, jy = -jx, -jy
        nx, ny = arb.n.x, arb.n.y
        con = arb.contacts[0]
        con.jnAcc = -(jx * nx + jy * ny)
        con.jtAcc = -(jx * -ny + jy * nx)
        arb.state = normal_state

    space.on_collision(None, None, pre_solve=pre_solve)
    lib.cpSpaceSetCurrentTimeStep(space._space, dt)

    def disarm(space_, key) -> None:
        space_.on_collision(None, None, pre_solve=pymunk.empty_callback)

    # removed after the first step's collision phase: post-step callbacks run at the end of step()
    space.add_post_step_callback(disarm, "wallsim-warm-start")
    del ffi
