"""The seismic run as stages (specimen.py builds, measures.py reads):

``prepare`` -> the static state (deposit, wall, excavation, settled under N g) and the
two free-field columns, cached in a ``Store`` under a content key of every case field
that shapes them (all frequencies start from the same state);
``shake`` -> the dynamic stage, sampled every ``record_every`` prototype seconds;
resumable: ``checkpoint(state)`` is handed everything the loop needs to go on (the
engines of the main model and of both columns, the free-field segments' velocities, the
readings and snapshots so far) and ``shake(..., resume=state)`` continues from it bit
for bit.
"""

from __future__ import annotations

import dataclasses
import math
import time
from pathlib import Path
from typing import Callable, NamedTuple

import numpy as np

from analytic.errors import InvalidParameter
from dem3d import Periodic, Simulation, Specimen, Wall, plane, settle
from dem3d.freefield import FreeFieldBoundary, column_free_field, step_coupled

from ..store import Store, content_key, to_plain
from . import specimen as M
from .case import SeismicCase
from .measures import WallReading, wall_reading

#: case fields that do not shape the static state (the dynamic stage and its sampling)
DYNAMIC_FIELDS = ("frequency", "amplitude_g", "rest_s", "ramp_s", "hold_s", "decay_s", "end_s", "record_every",
                  "free_field_every", "segment_mass_grains")

#: Poisson's ratio of the soil skeleton for the P-wave dashpot, C_p = C_s sqrt(2(1 - nu)/(1 - 2 nu)) [A]
SKELETON_POISSON = 0.25
#: low-strain shear-wave speed of the deposit [m/s] (paper's Table 1; same in model and prototype) [F]
VS = 210.0

#: a checkpoint of the shaking is handed over every this many seconds of wall time ...
CHECKPOINT_EVERY_S = 300.0
#: ... and each time another this fraction of the motion is done (a short run
#: interrupted before 300 s would otherwise start its shaking over); only between readings
CHECKPOINT_EVERY_FRACTION = 0.1


def static_key(case: SeismicCase) -> str:
    d = to_plain(case, for_key=True)
    return content_key({k: v for k, v in d.items() if k not in DYNAMIC_FIELDS} | {"scale": case.scale, "v": 5})


class Prepared(NamedTuple):
    """The static state: main model arrays (``Simulation.to_arrays``), the Model record,
    each column's arrays, and what preparing took (info: porosity, steps, seconds)."""

    main: dict
    model: M.Model
    columns: tuple
    info: dict


def prepare(case: SeismicCase, cache: Path | None, *, log: Callable[[str], None] = lambda s: None) -> Prepared:
    """The static state, from ``cache`` when made before."""
    store = Store(cache) if cache is not None else None
    key = static_key(case)
    if store is not None and (found := store.load_arrays(key)) is not None:
        arrays, info = found
        return _unpack(arrays, info)
    t0 = time.perf_counter()
    rng = np.random.default_rng(case.seed)
    t = 2.0 * case.wall_ball
    log("raining the deposit")
    dep = M.rain_deposit(case, rng, (-case.front, 0.0), (t + case.behind, case.width), case.retained_height, 1)
    model = M.install_wall(case, dep)
    log(f"deposit: {len(dep.radii)} grains, porosity {dep.porosity:.3f}; wall installed")
    sim = M.build_main(case, model)
    # the wall is held while the soil closes on it (an installed, propped wall), so the
    # gaps left by its installation do not push it either way; it is let go at excavation
    engine = np.empty(sim.n_spheres, np.int64)
    engine[sim.original_index] = np.arange(sim.n_spheres)
    sim.lock(engine[model.wall], translation=True, rotation=True)
    budget = int(0.5 * case.static_time / sim.dt)
    bound = M.settle_energy(case, len(model.radii), case.settle_energy)
    before = settle(sim, ratio=case.settle_ratio, energy=bound, max_steps=budget, min_steps=min(2000, budget),
                    check_every=500)
    x_before = _specimen(sim, sim.spheres.x)
    model = M.excavate(case, model, x_before)
    log("front excavated")
    # a new simulation (the bonds start unloaded at the deformed shape: the wall carried
    # almost no bending with soil level on both sides)
    sim = M.build_main(case, model)
    # the ratio is a mean over every grain, so it is low at once after excavating; the
    # wall needs a few of its own periods to deflect and come to rest
    swing = int(3 * M.wall_period(case) / sim.dt)
    res = settle(sim, ratio=case.settle_ratio, energy=M.settle_energy(case, len(model.radii), case.settle_energy),
                 max_steps=max(budget, swing), min_steps=min(swing, budget), check_every=500)
    log(f"static state: {res.steps} steps, ratio {res.ratio:.3g}")
    cols, col_info = [], []
    for name, height in (("L", case.front_height), ("R", case.retained_height)):
        col, n_col = _column(case, rng, height)
        cols.append(col.to_arrays())
        col_info.append(n_col)
        log(f"free-field column {name}: porosity {n_col:.3f}")
    info = {"deposit_grains": int(len(dep.radii)), "porosity": float(dep.porosity),
            "deposit_steps": int(dep.steps), "deposit_converged": [bool(r.converged) for r in dep.settling],
            "installed_steps": int(before.steps), "installed_ratio": float(before.ratio),
            "static_steps": int(res.steps), "static_ratio": float(res.ratio), "static_converged": bool(res.converged),
            "column_porosity": col_info, "prepare_s": time.perf_counter() - t0,
            "dt_s": float(sim.dt), "x_wall_before_excavation": model.positions[model.wall].tolist()}
    prepared = Prepared(sim.to_arrays(), model, tuple(cols), info)
    if store is not None:
        store.save_arrays(key, _pack(prepared), info)
    return prepared


def _specimen(sim: Simulation, a: np.ndarray) -> np.ndarray:
    out = np.empty_like(a)
    out[sim.original_index] = a
    return out


def _column(case: SeismicCase, rng, height: float) -> tuple[Simulation, float]:
    """A free-field column of ``column_length`` mean diameters along x (periodic), the
    slab's width in y between frictionless walls [A], settled under N g on a rough base."""
    length = case.column_length * case.d_mean
    dep = M.rain_deposit(case, rng, (0.0, 0.0), (length, case.width), height, 0)
    sim = _column_sim(case, dep.positions, dep.radii, length)
    settle(sim, ratio=case.settle_ratio, energy=M.settle_energy(case, len(dep.radii), case.settle_energy),
           max_steps=20_000, min_steps=500, check_every=500)
    return sim, float(dep.porosity)


def _column_walls(case: SeismicCase, motion=None) -> list[Wall]:
    import dem3d
    return [Wall("base", plane((0, 0, 0), (0, 0, 1), mu=case.boundary_friction), motion or dem3d.FIXED),
            Wall("y_lo", plane((0, 0, 0), (0, 1, 0), mu=0.0)),
            Wall("y_hi", plane((0, case.width, 0), (0, -1, 0), mu=0.0))]


def _column_sim(case: SeismicCase, x, r, length) -> Simulation:
    law = M.contact_law(case, local_damping=0.7)
    spec = Specimen(x, r, -np.ones(len(r), np.int64), case.grain_density)
    sim = Simulation(spec, law, dt=M.time_step(case, law), walls=_column_walls(case),
                     periodic=Periodic(0, 0.0, length), gravity=(0.0, 0.0, -case.gravity),
                     direct_sums=case.direct_sums)
    sim.attach_to_wall(np.nonzero(x[:, 2] - r < 0.1 * case.d_mean)[0], "base")
    return sim


def _pack(p: Prepared) -> dict:
    out = {f"main/{k}": v for k, v in p.main.items()}
    for c, arrays in enumerate(p.columns):
        out |= {f"col{c}/{k}": v for k, v in arrays.items()}
    out |= {f"model/{k}": np.asarray(v) for k, v in p.model._asdict().items()}
    return out


def _unpack(arrays: dict, info: dict) -> Prepared:
    main = {k[5:]: v for k, v in arrays.items() if k.startswith("main/")}
    cols = tuple({k[5:]: v for k, v in arrays.items() if k.startswith(f"col{c}/")} for c in range(2))
    model = M.Model(**{f: arrays[f"model/{f}"] for f in M.Model._fields})
    return Prepared(main, model, cols, info)


class Shaken(NamedTuple):
    """The dynamic stage's record (model units; ``samples`` one row per reading).

    time:      (k,) model time since shaking began [s]
    base:      (k,) base displacement along x [m]
    readings:  list of measures.WallReading, the first at the start of shaking
    final:     the main simulation's final arrays (to_arrays)
    steps:     steps taken; seconds: wall time
    snapshots: list of Snapshot, at the asked prototype times the run reached
    rest:      the shaking model at rest before the base moved (``Rest``)
    """

    time: np.ndarray
    base: np.ndarray
    readings: list
    final: dict
    steps: int
    seconds: float
    snapshots: tuple = ()
    rest: "Rest | None" = None


class Rest(NamedTuple):
    """The shaking model left at rest for ``case.rest_s`` (prototype) before the base
    moves: the static stage settled with rigid side walls and local damping, and the
    model that is shaken (free-field boundaries, viscous damping) moves on from there
    before it stands; its static reading is the one at the end of the rest.

    readings: measures.WallReading every ``record_every`` (the first as the static stage
              left the wall, the last the shaking's first reading)
    start:    (n, 3) sphere positions when the base starts to move, specimen order [m]
              (model units): the reference of settlement and shear strain
    """

    readings: list
    start: np.ndarray


class Snapshot(NamedTuple):
    """Sphere positions at one asked time of the shaking.

    asked_s:   the time asked, prototype [s] since shaking began
    time_s:    the reading's time (the nearest, within half of ``record_every``), prototype [s]
    step:      the engine's step count then
    positions: (n, 3) specimen order [m] (model units)
    """

    asked_s: float
    time_s: float
    step: int
    positions: np.ndarray


def coupled(case: SeismicCase, prepared: Prepared, state: dict | None = None):
    """(main, columns, boundaries, table): the static state restored with the base
    shaken from now on (model time), the columns on the same motion, and the two
    free-field boundaries (L front, R behind) tied to them. With ``state`` (a checkpoint
    of ``shake``) the main model, the columns and the segments are those of the
    checkpoint, on the motions that started when the shaking did."""
    if state is None:
        main_arrays, col_arrays = prepared.main, prepared.columns
    else:
        main_arrays = _prefixed(state, "main/")
        col_arrays = tuple(_prefixed(state, f"col{c}/") for c in range(len(prepared.columns)))
    # the motions start at each engine's clock of the static state plus the rest
    # (from the prepared state also when resuming, so both runs start them on the same bits)
    rest_time = rest_steps(case, float(prepared.main["dt"])) * float(prepared.main["dt"])
    motion, table = M.base_motion(case, float(prepared.main["time"]) + rest_time)
    main = Simulation.from_arrays(main_arrays, walls=M.boundary_walls(case, motion))
    law = M.contact_law(case, local_damping=0.0)
    if state is None:
        main.set_params(law, allow_unsafe_dt=True)          # the bonds' step is checked in time_step
    columns = []
    for c, arrays in enumerate(col_arrays):
        m_c, _ = M.base_motion(case, float(prepared.columns[c]["time"]) + rest_time)
        col = Simulation.from_arrays(arrays, walls=_column_walls(case, m_c))
        if state is None:
            col.set_params(law, allow_unsafe_dt=True)
            col.dt = main.dt
        columns.append(col)
    rho = case.grain_density * (1.0 - float(prepared.info["porosity"]))
    cp = VS * math.sqrt(2.0 * (1.0 - SKELETON_POISSON) / (1.0 - 2.0 * SKELETON_POISSON))
    mass = case.segment_mass_grains * M.grain_mass(case)
    bnds = [FreeFieldBoundary(main, [w for w in main.walls.names if w[0] == side and w[1:].isdigit()], rho=rho,
                              cp=cp, cs=VS, segment_mass=mass) for side in ("L", "R")]
    if state is not None:
        for k, b in enumerate(bnds):
            _restore_boundary(b, _prefixed(state, f"bnd{k}/"))
    return main, columns, bnds, table


def _prefixed(arrays: dict, prefix: str) -> dict:
    return {k[len(prefix):]: v for k, v in arrays.items() if k.startswith(prefix)}


#: what a free-field boundary holds besides its main model: the segments' velocity over
#: the current half step (evolves), and what it fixed when it was made (the segments'
#: frame and area from the panels then, impedance, mass), kept so a resumed boundary
#: does not take them from panels that have moved since
_BOUNDARY_FIELDS = ("velocity", "frame", "area", "impedance", "mass")


def _boundary_arrays(b: FreeFieldBoundary) -> dict:
    return {f: np.array(getattr(b, f), copy=True) for f in _BOUNDARY_FIELDS}


def _restore_boundary(b: FreeFieldBoundary, arrays: dict) -> None:
    """The segments as the checkpoint left them: velocity (and the driven motions that
    carry it into the next step), frame and area as made at the start of the shaking."""
    if arrays["velocity"].shape != b.velocity.shape:
        raise InvalidParameter("checkpoint", f"{arrays['velocity'].shape[0]} free-field segments",
                               f"{b.velocity.shape[0]} (the case's)")
    b.velocity = np.array(arrays["velocity"], float, copy=True)
    b.frame = np.array(arrays["frame"], float, copy=True)
    b.area = np.array(arrays["area"], float, copy=True)
    b.impedance = np.array(arrays["impedance"], float, copy=True)
    b.mass = float(arrays["mass"])
    for s, m in enumerate(b.motions):
        m.velocity.value = b.velocity[s].copy()


def checkpoint_key(case: SeismicCase, fraction: float, snapshot_times) -> str:
    """What a checkpoint of ``shake`` belongs to: the case, the fraction of the motion and
    the snapshot times (a resume with any other would not continue the same run)."""
    return content_key({"case": case, "fraction": float(fraction),
                        "snapshots": sorted(float(t) for t in snapshot_times), "v": 2})


def checkpoint_samples(state: dict) -> int:
    """Readings a checkpoint holds after the one at the start of shaking."""
    return int(len(state["shake/times"])) - 1


#: WallReading fields that are one number per reading (the others are arrays)
_READING_SCALARS = ("thrust_front", "thrust_back")


def _readings_arrays(readings: list, prefix: str = "reading/") -> dict:
    return {f"{prefix}{f}": np.array([getattr(r, f) for r in readings]) for f in WallReading._fields}


def _readings_from(state: dict, prefix: str = "reading/") -> list:
    cols = {f: state[f"{prefix}{f}"] for f in WallReading._fields}
    return [WallReading(**{f: (float(cols[f][k]) if f in _READING_SCALARS else np.array(cols[f][k], copy=True))
                           for f in WallReading._fields}) for k in range(len(cols["z"]))]


def _snapshots_arrays(snaps: list, n: int) -> dict:
    return {"snap/asked_s": np.array([s.asked_s for s in snaps], float),
            "snap/time_s": np.array([s.time_s for s in snaps], float),
            "snap/step": np.array([s.step for s in snaps], np.int64),
            "snap/positions": (np.stack([s.positions for s in snaps]) if snaps else np.zeros((0, n, 3)))}


def _snapshots_from(state: dict) -> list:
    return [Snapshot(float(a), float(t), int(st), np.array(x, copy=True))
            for a, t, st, x in zip(state["snap/asked_s"], state["snap/time_s"], state["snap/step"],
                                   state["snap/positions"])]


@dataclasses.dataclass
class _Progress:
    """Where the shaking is: the main engine's clock when it began, the readings so far,
    the snapshot times still to take, the steps done and the wall time of earlier
    sessions [s] (a resumed run's)."""

    t0: float
    times: list
    base: list
    readings: list
    pending: list
    snaps: list
    done: int = 0
    before: float = 0.0

    @classmethod
    def fresh(cls, main, first, snapshot_times) -> "_Progress":
        """From the model as the rest left it; ``first``: its reading then."""
        return cls(main.time, [0.0], [0.0], [first], sorted(snapshot_times), [])

    @classmethod
    def resumed(cls, state: dict, total: int, every: int) -> "_Progress":
        if int(state["shake/total"]) != total or int(state["shake/every"]) != every:
            raise InvalidParameter("resume", f"{int(state['shake/total'])} steps",
                                   f"{total} steps (the same motion and time step)")
        return cls(float(state["shake/t0"]),
                   [float(t) for t in state["shake/times"]], [float(b) for b in state["shake/base"]],
                   _readings_from(state), [float(t) for t in state["shake/pending"]], _snapshots_from(state),
                   int(state["shake/done"]), float(state["shake/seconds"]))

    def take(self, main, table, case: SeismicCase, model) -> None:
        """A reading now, and the positions when an asked snapshot time is reached."""
        self.times.append(main.time - self.t0)
        self.base.append(table.displacement(main.time)[0])
        self.readings.append(wall_reading(main, case, model))
        t_proto = case.to_prototype_time(self.times[-1])
        while self.pending and t_proto >= self.pending[0] - 0.5 * case.record_every:
            self.snaps.append(Snapshot(self.pending.pop(0), t_proto, int(main.step_count),
                                       _specimen(main, main.spheres.x)))

    def arrays(self, key: str, total: int, every: int, seconds: float, n_spheres: int) -> dict:
        return {"shake/key": np.array(key), "shake/t0": np.array(self.t0),
                "shake/total": np.array(total),
                "shake/every": np.array(every), "shake/done": np.array(self.done),
                "shake/times": np.array(self.times, float), "shake/base": np.array(self.base, float),
                "shake/pending": np.array(self.pending, float), "shake/seconds": np.array(self.before + seconds)} \
            | _readings_arrays(self.readings) | _snapshots_arrays(self.snaps, n_spheres)


def rest_steps(case: SeismicCase, dt: float) -> int:
    """Steps of the rest before the base moves (``case.rest_s`` prototype, time step ``dt`` [s])."""
    return int(round(case.to_model_time(case.rest_s) / dt))


def record_steps(case: SeismicCase, dt: float) -> int:
    """Steps between two readings (``case.record_every`` prototype, time step ``dt`` [s])."""
    return max(1, int(round(case.to_model_time(case.record_every) / dt)))


def rest(case: SeismicCase, prepared: Prepared, main, columns, bnds, free_field) -> Rest:
    """The shaking model (``coupled``) stepped ``case.rest_s`` with the base still, a
    reading every ``record_every``: where the wall stands when the base starts to move."""
    total = rest_steps(case, main.dt)
    every = record_steps(case, main.dt)
    main.evaluate_forces()              # once: it advances the contacts' shear history
    readings = [wall_reading(main, case, prepared.model)]
    done = 0
    while done < total:
        k = min(every, total - done)
        step_coupled(main, bnds, k, free_field=free_field, columns=columns, every=case.free_field_every)
        done += k
        readings.append(wall_reading(main, case, prepared.model))
    return Rest(readings, _specimen(main, main.spheres.x))


def _rest_arrays(r: Rest) -> dict:
    return _readings_arrays(r.readings, "rest/") | {"rest/start": r.start}


def _rest_from(state: dict) -> Rest:
    return Rest(_readings_from(state, "rest/"), np.array(state["rest/start"], copy=True))


def _engine_arrays(main, columns, bnds) -> dict:
    out = {f"main/{k}": v for k, v in main.to_arrays().items()}
    for c, col in enumerate(columns):
        out |= {f"col{c}/{k}": v for k, v in col.to_arrays().items()}
    for k, b in enumerate(bnds):
        out |= {f"bnd{k}/{f}": v for f, v in _boundary_arrays(b).items()}
    return out


class _CheckpointsDue:
    """When the shaking hands over a checkpoint: ``every_s`` of wall time after the last
    one (``CHECKPOINT_EVERY_S``), or as the steps done pass another ``every_fraction`` of
    ``total`` (``CHECKPOINT_EVERY_FRACTION``)."""

    def __init__(self, every_s: float | None, every_fraction: float | None, total: int, done: int):
        self.every_s = CHECKPOINT_EVERY_S if every_s is None else float(every_s)
        fraction = CHECKPOINT_EVERY_FRACTION if every_fraction is None else float(every_fraction)
        self.step_of_marks = max(1, int(fraction * total))
        self.next_mark = (done // self.step_of_marks + 1) * self.step_of_marks
        self.last = time.perf_counter()

    def __call__(self, done: int) -> bool:
        """Whether one is due after ``done`` steps (if so, the next is counted from now)."""
        if time.perf_counter() - self.last <= self.every_s and done < self.next_mark:
            return False
        self.next_mark = (done // self.step_of_marks + 1) * self.step_of_marks
        self.last = time.perf_counter()
        return True


def shake(case: SeismicCase, prepared: Prepared, *, fraction: float = 1.0,
          on_sample: Callable | None = None, snapshot_times: tuple = (),
          checkpoint: Callable[[dict], None] | None = None, resume: dict | None = None,
          checkpoint_every_s: float | None = None, checkpoint_every_fraction: float | None = None) -> Shaken:
    """The dynamic stage over ``fraction`` of ``case.duration`` (a timing run uses a few
    per cent), a reading every ``record_every`` prototype seconds; the sphere positions
    kept at the readings nearest ``snapshot_times`` (prototype [s]; only those, so
    memory stays small; times the run does not reach are left out).

    ``checkpoint(state)`` is called between readings every ``checkpoint_every_s`` of
    wall time (``CHECKPOINT_EVERY_S``) and each time another ``checkpoint_every_fraction``
    of the motion is done (``CHECKPOINT_EVERY_FRACTION``), after ``on_sample`` has taken
    the reading, never after the last one, and once when the rest has ended (before the
    first step of shaking); ``state`` is a dict of numpy arrays (save it
    with ``studies.store.npz_bytes``). ``resume=state`` (as saved, or loaded back)
    continues that run: the result is the uninterrupted run's bit for bit, its
    ``seconds`` the wall time of both parts."""
    wall_clock = time.perf_counter()
    key = checkpoint_key(case, fraction, snapshot_times)
    if resume is not None and str(resume.get("shake/key", "")) != key:
        raise InvalidParameter("resume", "a checkpoint of another run", "a checkpoint of this case, fraction and "
                               "snapshot times", "a resumed run keeps the settings it started with")
    main, columns, bnds, table = coupled(case, prepared, resume)
    edges = [M.lateral_edges(case, case.front_height), M.lateral_edges(case, case.retained_height)]
    area = case.column_length * case.d_mean * case.width

    def free_field():
        return [column_free_field(c, e, area) for c, e in zip(columns, edges)]

    settled = rest(case, prepared, main, columns, bnds, free_field) if resume is None else _rest_from(resume)
    total = int(round(fraction * case.duration / main.dt))
    every = record_steps(case, main.dt)
    run = (_Progress.fresh(main, settled.readings[-1], snapshot_times) if resume is None
           else _Progress.resumed(resume, total, every))

    def state() -> dict:
        return (_engine_arrays(main, columns, bnds) | _rest_arrays(settled)
                | run.arrays(key, total, every, time.perf_counter() - wall_clock, main.n_spheres))

    if checkpoint is not None and resume is None:
        checkpoint(state())         # the rest is ~a tenth of the shaking's steps: kept by a run stopped later
    due = _CheckpointsDue(checkpoint_every_s, checkpoint_every_fraction, total, run.done)
    while run.done < total:
        k = min(every, total - run.done)
        step_coupled(main, bnds, k, free_field=free_field, columns=columns, every=case.free_field_every)
        run.done += k
        run.take(main, table, case, prepared.model)
        if on_sample is not None:
            on_sample(main, run.readings[-1], run.times[-1], run.base[-1], run.done, total)
        # after the consumer has taken this reading, so a checkpoint holds it too
        if checkpoint is not None and run.done < total and due(run.done):
            checkpoint(state())
    return Shaken(np.array(run.times), np.array(run.base), run.readings, main.to_arrays(), run.done,
                  run.before + time.perf_counter() - wall_clock, tuple(run.snaps), settled)
