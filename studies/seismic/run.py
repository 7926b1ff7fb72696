"""The seismic run as stages (model.py builds, measures.py reads):

``prepare`` -> the static state (deposit, wall, excavation, settled under N g) and the
two free-field columns, cached in a ``Store`` under a content key of every case field
that shapes them (all frequencies start from the same state);
``shake`` -> the dynamic stage, sampled every ``record_every`` prototype seconds.
"""

from __future__ import annotations

import dataclasses
import math
import time
from pathlib import Path
from typing import Callable, NamedTuple

import numpy as np

from dem3d import Periodic, Simulation, Specimen, Wall, plane, settle
from dem3d.freefield import FreeFieldBoundary, column_free_field, step_coupled

from ..store import Store, content_key
from . import model as M
from .case import SeismicCase
from .measures import wall_reading

#: case fields that do not shape the static state (the dynamic stage and its sampling)
DYNAMIC_FIELDS = ("frequency", "amplitude_g", "ramp_s", "hold_s", "decay_s", "end_s", "record_every",
                  "free_field_every", "segment_mass_grains")

#: Poisson's ratio of the soil skeleton for the P-wave dashpot, C_p = C_s sqrt(2(1 - nu)/(1 - 2 nu)) [A]
SKELETON_POISSON = 0.25
#: low-strain shear-wave speed of the deposit [m/s] (paper's Table 1; same in model and prototype) [F]
VS = 210.0


def static_key(case: SeismicCase) -> str:
    d = dataclasses.asdict(case)
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
                     periodic=Periodic(0, 0.0, length), gravity=(0.0, 0.0, -case.gravity))
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
    """

    time: np.ndarray
    base: np.ndarray
    readings: list
    final: dict
    steps: int
    seconds: float
    snapshots: tuple = ()


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


def coupled(case: SeismicCase, prepared: Prepared):
    """(main, columns, boundaries, table): the static state restored with the base
    shaken from now on (model time), the columns on the same motion, and the two
    free-field boundaries (L front, R behind) tied to them."""
    t0 = float(prepared.main["time"])
    motion, table = M.base_motion(case, t0)
    main = Simulation.from_arrays(prepared.main, walls=M.boundary_walls(case, motion))
    law = M.contact_law(case, local_damping=0.0)
    main.set_params(law, allow_unsafe_dt=True)          # the bonds' step is checked in time_step
    columns = []
    for arrays in prepared.columns:
        tc = float(arrays["time"])
        m_c, _ = M.base_motion(case, tc)
        col = Simulation.from_arrays(arrays, walls=_column_walls(case, m_c))
        col.set_params(law, allow_unsafe_dt=True)
        col.dt = main.dt
        columns.append(col)
    rho = case.grain_density * (1.0 - float(prepared.info["porosity"]))
    cp = VS * math.sqrt(2.0 * (1.0 - SKELETON_POISSON) / (1.0 - 2.0 * SKELETON_POISSON))
    mass = case.segment_mass_grains * M.grain_mass(case)
    bnds = [FreeFieldBoundary(main, [w for w in main.walls.names if w[0] == side and w[1:].isdigit()], rho=rho,
                              cp=cp, cs=VS, segment_mass=mass) for side in ("L", "R")]
    return main, columns, bnds, table


def shake(case: SeismicCase, prepared: Prepared, *, fraction: float = 1.0,
          on_sample: Callable | None = None, snapshot_times: tuple = ()) -> Shaken:
    """The dynamic stage over ``fraction`` of ``case.duration`` (a timing run uses a few
    per cent), a reading every ``record_every`` prototype seconds; the sphere positions
    kept at the readings nearest ``snapshot_times`` (prototype [s]; only those, so
    memory stays small; times the run does not reach are left out)."""
    wall_clock = time.perf_counter()
    main, columns, bnds, table = coupled(case, prepared)
    t0 = main.time
    edges = [M.lateral_edges(case, case.front_height), M.lateral_edges(case, case.retained_height)]
    area = case.column_length * case.d_mean * case.width

    def free_field():
        return [column_free_field(c, e, area) for c, e in zip(columns, edges)]

    total = int(round(fraction * case.duration / main.dt))
    every = max(1, int(round(case.to_model_time(case.record_every) / main.dt)))
    main.evaluate_forces()
    times, base, readings = [0.0], [0.0], [wall_reading(main, case, prepared.model)]
    pending, snaps = sorted(snapshot_times), []
    done = 0
    while done < total:
        k = min(every, total - done)
        step_coupled(main, bnds, k, free_field=free_field, columns=columns, every=case.free_field_every)
        done += k
        times.append(main.time - t0)
        base.append(table.displacement(main.time)[0])
        readings.append(wall_reading(main, case, prepared.model))
        t_proto = case.to_prototype_time(times[-1])
        while pending and t_proto >= pending[0] - 0.5 * case.record_every:
            snaps.append(Snapshot(pending.pop(0), t_proto, int(main.step_count), _specimen(main, main.spheres.x)))
        if on_sample is not None:
            on_sample(main, readings[-1], times[-1], base[-1], done, total)
    return Shaken(np.array(times), np.array(base), readings, main.to_arrays(), done,
                  time.perf_counter() - wall_clock, tuple(snaps))
