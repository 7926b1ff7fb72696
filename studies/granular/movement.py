"""A wall moved away from its backfill (``move_wall``, ``run_modes``): translate or
rotate the wall quasi-statically to Delta/H from the settled specimen, with the load
history (K, resultant_height_over_H, segment stresses) and frames for the recording,
resumable from its checkpoints bit for bit. K follows Nadukuru & Michalowski's eq. 6: K = F_n / (0.5 rho (1 - n)
g H^2 w), F_n the normal force on the wall, n the measured porosity of the specimen (the
paper used n = 0.36).
"""

from __future__ import annotations

import dataclasses
import math
import time as _time
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace
from typing import Callable, Iterator

import numpy as np

import dem3d

from ..config import with_current_names
from .recipe import frictional_law
from ..measures import steady_displacement
from ..store import atomic_write, load_npz, npz_bytes

from .wall import MODE_TITLES, Movement, WallCase, WallSetup, movement_duration
from .load import load_coefficient, wall_load
from .specimen import Specimen, box_walls


def wall_motion(movement: Movement, H: float) -> tuple[dem3d.Motion, float]:
    """The wall's motion for a mode, and the distance [m] from the pivot to the edge whose
    displacement defines Delta (1 for translation). Speeds ramp up over ``ramp``."""
    v = movement.speed
    s = -1.0 if movement.direction == "passive" else 1.0      # passive: every motion mirrored, into the fill
    y_axis = (0.0, s, 0.0)
    if movement.mode == "T":
        return dem3d.translation(dem3d.Ramp((-s * v, 0.0, 0.0), movement.ramp)), 1.0
    if movement.mode == "RB":      # pivot at the base, top moves -x: axis -y
        return dem3d.rotation((0.0, 0.0, 0.0), (0.0, -s, 0.0), dem3d.Ramp(v / H, movement.ramp)), H
    if movement.mode == "RT":      # pivot at the top, base moves -x: axis +y
        return dem3d.rotation((0.0, 0.0, H), y_axis, dem3d.Ramp(v / H, movement.ramp)), H
    arm = 1.5 * H                  # mixed: pivot H/2 above the top, Delta at the base
    return dem3d.rotation((0.0, 0.0, 1.5 * H), y_axis, dem3d.Ramp(v / arm, movement.ramp)), arm


def _ramp_distance(speed: float, ramp: float, t: float) -> float:
    """Distance covered by an edge whose speed ramps linearly to ``speed`` over ``ramp``."""
    if t <= ramp:
        return 0.5 * speed * t * t / ramp
    return 0.5 * speed * ramp + speed * (t - ramp)


@dataclass(frozen=True)
class LoadSample:
    wall_disp_over_H: float
    time: float
    step: int
    K: float
    resultant_height_over_H: float              # height of the resultant / H
    thrust_kN: float
    segment_stress: np.ndarray   # (segments,) Pa, bottom to top
    shear_kN: float = float("nan")   # force along the wall, + downward on the wall (width w)


def move_wall(case: WallCase, specimen: Specimen, *, frame_every: int = 0, progress=None,
              resume: dict | None = None, checkpoint=None,
              checkpoint_every_s: float = 300.0,
              checkpoint_every_fraction: float = 0.1) -> Iterator[tuple[LoadSample, object | None]]:
    """Move the wall from the settled specimen to ``wall_disp_over_H``; yields
    (LoadSample averaged over ``record_every`` steps, Frame or None) pairs.

    ``checkpoint(state)`` is called every ``checkpoint_every_s`` of wall-clock time and
    each time another ``checkpoint_every_fraction`` of the movement is done (a short
    run interrupted before 300 s would otherwise restart its movement), with the engine
    state plus ``movement.t0`` (the time the movement started); passing that dict back
    as ``resume`` continues the movement exactly (dem3d resumes bitwise).
    """
    mv = case.movement
    wall = dataclasses.replace(case.wall, width=specimen.width)
    sim, t0 = _movement_simulation(case, specimen, wall, resume)
    n_total = int(math.ceil(movement_duration(mv, wall.height) / sim.dt))
    ids = sim.walls.panel_ids("wall")
    k = mv.record_every
    done = int(round((sim.time - t0) / sim.dt))
    task = progress.add_task(f"{MODE_TITLES[mv.mode]}", total=n_total, completed=done, status="") \
        if progress else None
    since_frame = 0
    last_checkpoint = _time.perf_counter()
    step_of_marks = max(1, int(checkpoint_every_fraction * n_total))
    next_mark = (done // step_of_marks + 1) * step_of_marks
    while done < n_total:
        m = min(k, n_total - done)
        hist_f, hist_m = sim.step(m, record_panels=True)
        done += m
        since_frame += m
        sample = _averaged_sample(sim, hist_f, hist_m, ids, m, t0, case, specimen, wall)
        emit = bool(frame_every) and (since_frame >= frame_every or done >= n_total or done == m)
        if emit:
            since_frame = 0
        if task is not None:
            progress.update(task, advance=m, status=f"Delta/H {sample.wall_disp_over_H:.4f}  K {sample.K:.3f}")
        yield sample, (dem3d.frame(sim) if emit else None)
        # after the consumer has taken this sample, so a checkpoint holds it too
        if checkpoint is not None and (_time.perf_counter() - last_checkpoint > checkpoint_every_s
                                       or next_mark <= done < n_total):
            next_mark = (done // step_of_marks + 1) * step_of_marks
            state = sim.to_arrays()
            state["movement.t0"] = np.array(t0)
            checkpoint(state)
            last_checkpoint = _time.perf_counter()


def _movement_simulation(case: WallCase, specimen: Specimen, wall: WallSetup,
                         resume: dict | None) -> tuple[dem3d.Simulation, float]:
    """The simulation that moves the wall, from the settled specimen or from a checkpoint
    (``resume``), and t0 [s], the simulation time at which the movement started. Motions
    are schedules from t = 0 while the specimen's clock stands at t0 after settling:
    they are shifted so the ramp starts when the wall starts to move."""
    rec, mv = case.specimen, case.movement
    motion, _ = wall_motion(mv, wall.height)
    if resume is None:
        t0 = float(specimen.state["time"])
        sim = dem3d.Simulation.from_arrays(specimen.state, walls=box_walls(wall, rec, _shifted(motion, t0)))
        sim.walls.reset_pivots()              # a new motion, not the stored (fixed) one
        sim.set_params(frictional_law(rec, mv.local_damping))
    else:
        t0 = float(resume["movement.t0"])
        sim = dem3d.Simulation.from_arrays({k: v for k, v in resume.items() if k != "movement.t0"},
                                           walls=box_walls(wall, rec, _shifted(motion, t0)))
    return sim, t0


def _averaged_sample(sim, hist_f, hist_m, ids, m: int, t0: float, case: WallCase, specimen: Specimen,
                     wall: WallSetup) -> LoadSample:
    """The load sample of the last ``m`` steps: panel forces and moments averaged over
    them (``hist_f``, ``hist_m`` from ``sim.step(record_panels=True)``), Delta/H at the
    middle of the chunk, K by eq. 6 with the specimen's porosity."""
    mv, H = case.movement, wall.height
    panels = SimpleNamespace(panel_force=hist_f.mean(axis=0), panel_moment=hist_m.mean(axis=0),
                             panel_normal=sim.walls.panels.normal, panel_corners=sim.walls.corners(),
                             panel_area=sim.walls.areas())
    load = wall_load(panels, ids, H)
    disp = _ramp_distance(mv.speed, mv.ramp, sim.time - t0 - 0.5 * m * sim.dt)
    return LoadSample(disp / H, sim.time, sim.step_count,
                      load_coefficient(load.normal, specimen.porosity, case.specimen, wall),
                      load.height / H, load.normal / 1e3, load.segment_stress, load.shear / 1e3)


def _shifted(motion: dem3d.Motion, t0: float) -> dem3d.Motion:
    """The same motion with its clock starting at t0 (schedules are functions of time)."""
    return dataclasses.replace(motion, angular_speed=lambda t, f=motion.angular_speed: f(t - t0),
                               velocity=lambda t, f=motion.velocity: f(t - t0))


def steady_disp_over_H(disp: np.ndarray, K: np.ndarray, window: float = 0.05) -> float:
    """Delta/H at which K has first completed 90 % of its drop from at rest to its final
    value (running mean over ``window`` of the record); the definition of the Khosravi
    case (``studies.measures.steady_displacement``). An earlier band of +-max(0.01,
    5 %) about the final K was set by noise at reduced size (K fluctuates by +-0.015
    there after the drop)."""
    return steady_displacement(disp, K, 0.9, smooth=max(3, int(window * len(K))))


def run_modes(case: WallCase, specimen: Specimen, *, on_sample=None, on_frame=None,
              frame_every: int = 0, progress=None, checkpoint_path: Path | None = None,
              checkpoint_every_s: float = 300.0, on_checkpoint: Callable[[], None] | None = None) -> dict:
    """Move the wall and collect the load history; returns arrays and the active-state
    figures (K and resultant_height_over_H averaged over the last 10 % of the movement).

    With ``checkpoint_path`` the engine state and the history so far are saved there
    every ``checkpoint_every_s`` seconds (``on_checkpoint()`` after each: the run folder
    records the session's times), and an existing checkpoint is resumed from: an
    interrupted run continues where it stopped instead of starting over."""
    samples: list[LoadSample] = []
    resume = None
    if checkpoint_path is not None and Path(checkpoint_path).exists():
        data = load_npz(checkpoint_path)
        resume = {k: v for k, v in data.items() if not k.startswith("hist.")}
        h = with_current_names({k[5:]: v for k, v in data.items() if k.startswith("hist.")})
        shear = h.get("shear", np.full(len(h["K"]), np.nan))      # absent from checkpoints made before it
        samples = [LoadSample(float(d), float(t), int(st), float(K), float(c), float(nk), seg, float(sh))
                   for d, t, st, K, c, nk, seg, sh in zip(h["disp"], h["time"], h["step"], h["K"],
                                                          h["resultant_height_over_H"], h["normal"], h["seg"], shear)]

    def save(state):
        hist = {"hist.disp": [s.wall_disp_over_H for s in samples], "hist.time": [s.time for s in samples],
                "hist.step": [s.step for s in samples], "hist.K": [s.K for s in samples],
                "hist.resultant_height_over_H": [s.resultant_height_over_H for s in samples],
                "hist.normal": [s.thrust_kN for s in samples], "hist.shear": [s.shear_kN for s in samples],
                "hist.seg": np.array([s.segment_stress for s in samples])}
        atomic_write(checkpoint_path, npz_bytes({**state, **{k: np.asarray(v) for k, v in hist.items()}}))
        if on_checkpoint is not None:
            on_checkpoint()

    for sample, frame in move_wall(case, specimen, frame_every=frame_every, progress=progress, resume=resume,
                                   checkpoint=save if checkpoint_path is not None else None,
                                   checkpoint_every_s=checkpoint_every_s):
        samples.append(sample)
        if on_sample is not None:
            on_sample(sample)
        if frame is not None and on_frame is not None:
            on_frame(frame, sample)
    disp = np.array([s.wall_disp_over_H for s in samples])
    K = np.array([s.K for s in samples])
    cen = np.array([s.resultant_height_over_H for s in samples])
    seg = np.array([s.segment_stress for s in samples])
    thrust = np.array([s.thrust_kN for s in samples])
    shear = np.array([s.shear_kN for s in samples])
    tail = disp >= 0.9 * disp[-1]
    return {"wall_disp_over_H": disp, "K": K, "resultant_height_over_H": cen, "segment_stress": seg,
            "thrust_kN": thrust, "shear_kN": shear,
            "thrust_kN_active": float(thrust[tail].mean()), "shear_kN_active": float(shear[tail].mean()),
            "time": np.array([s.time for s in samples]), "step": np.array([s.step for s in samples]),
            "K_active": float(K[tail].mean()), "resultant_height_over_H_active": float(cen[tail].mean()),
            "segment_stress_active": seg[tail].mean(axis=0),
            "wall_disp_over_H_steady": steady_disp_over_H(disp, K)}
