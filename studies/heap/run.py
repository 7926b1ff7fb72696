"""A heap run (``run_heap``) through ``STAGES``: rain, slump, arrest, subsidence and the
hold after it. It hands over checkpoints between engine calls (every 300 s and every
10 % of a stage) and resumes from one bit for bit; the engine is called
``chunk_steps`` steps at a time, so Ctrl-C acts within about a second."""

from __future__ import annotations

import dataclasses
import json
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

import dem3d
from analytic.errors import InvalidParameter
from analytic.constants import G
from dem3d import measure
from studies.store import content_key

from ..granular.cloud import loose_cloud

from .case import (GENERATION_FRACTIONS, HeapCase, contact, fill_height, subsidence_duration, subsidence_motion,
                   time_step, walls, base_ids)
from .measures import (Shape, base_stress, centre_drop, centre_over_peak, heap_porosity, heap_shape, heap_speed,
                       heap_weight, on_base)


# ----------------------------------------------------------------------------- stages
@dataclass
class StageLog:
    """Steps, wall and CPU time [s] of each stage (CPU counts every thread)."""

    stages: dict = field(default_factory=dict)
    tic: float = field(default_factory=_time.perf_counter)
    cpu: float = field(default_factory=_time.process_time)

    def stage(self, name: str, steps: int, **extra) -> None:
        self.stages[name] = {"steps": int(steps), "wall_s": round(_time.perf_counter() - self.tic, 1),
                             "cpu_s": round(_time.process_time() - self.cpu, 1), **extra}
        self.tic, self.cpu = _time.perf_counter(), _time.process_time()


#: particle-steps in one call of the engine (~0.5 s of 2 cores at 4e6 particle-steps/s):
#: a run returns to Python that often, so Ctrl-C acts within about a second at any size
CHUNK_PARTICLE_STEPS = 2e6


def chunk_steps(sim, most: int = 1000) -> int:
    """Steps of one engine call: ``CHUNK_PARTICLE_STEPS`` over the sphere count, 1 to ``most``."""
    return max(1, min(int(most), int(CHUNK_PARTICLE_STEPS // max(1, sim.n_spheres))))


def advance(sim, n_steps: int, *, record_panels: bool = False) -> np.ndarray | None:
    """``sim.step(n_steps)`` in engine calls of ``chunk_steps`` steps, the same bits (the
    engine keeps nothing between calls but its state, and its wall schedule accumulates
    time as the steps do); with ``record_panels`` the panel forces of every step
    (n_steps, panels, 3), as ``sim.step`` returns them."""
    hist = np.zeros((n_steps, sim.walls.n_panels, 3)) if record_panels else None
    done = 0
    while done < n_steps:
        k = min(chunk_steps(sim), n_steps - done)
        out = sim.step(k, record_panels=record_panels)
        if record_panels:
            hist[done:done + k] = out[0]
        done += k
    return hist


#: the stages of a run, in order (``_Run``); a checkpoint names the one it was taken in.
#: The stage log's "rain" is fall + settle
STAGES = ("fall", "settle", "slump", "arrest", "before", "subsidence", "hold", "after")


#: a checkpoint of the run is handed over every this many seconds of wall time ...
CHECKPOINT_EVERY_S = 300.0


#: ... and each time another this fraction of a stage's steps is done (a short run
#: interrupted before 300 s would otherwise start over); only between engine calls
CHECKPOINT_EVERY_FRACTION = 0.1


#: the steps between the base readings of the subsidence (``subside``)
RECORD_EVERY = 200


def generate(case: HeapCase, rng) -> tuple[dem3d.Specimen, float]:
    """Bodies placed at random over the base (``granular.cloud.loose_cloud``) up to a height
    for a solid fraction of 0.25 (0.2, 0.15 if that jams); returns the specimen and that
    height [m]."""
    half = 0.5 * case.base_length
    h = fill_height(case) * (1.0 - case.target_porosity)
    spec, fraction = loose_cloud(rng, (-half + 1e-3, 1e-3, 1e-3), lambda f: (half - 1e-3, case.width - 1e-3, h / f),
                                 GENERATION_FRACTIONS, case.bodies, case.d_min, case.d_max, density=case.density,
                                 clump_fraction=case.clump_fraction, clump_overlap=case.clump_overlap,
                                 what=("particles", case.particles))
    return spec, h / fraction


def rain(case: HeapCase, log: StageLog, progress=None) -> dem3d.Simulation:
    """Stage 1 (``STAGES`` fall, settle): the cloud falls into the box (end walls in
    place) at 2 g without local damping (it would slow the fall), then settles at g with
    local damping until the unbalanced-force ratio is below ``settle_ratio`` (checked
    every 500 steps, at most 1 s)."""
    run = _Run(case, log, progress=progress)
    run.run("fall", "settle")
    return run.sim


def rebuilt(case: HeapCase, sim, keep: np.ndarray | None = None) -> dem3d.Simulation:
    """A new simulation of the grains (all, or the bodies with a sphere in ``keep``), with
    the base and catch floor only: how the end walls are removed, and the spill on the
    catch floor dropped. Contact history restarts (PFC's would not); both happen while
    the grains move (the fill about to collapse, the heap still flowing)."""
    sph = sim.spheres
    body = np.isin(sph.body_id, np.unique(sph.body_id[keep])) if keep is not None else np.ones(sim.n_spheres, bool)
    labels = np.where(sph.clump >= 0, sph.clump, -1)[body]
    _, relabel = np.unique(labels[labels >= 0], return_inverse=True)   # clump ids contiguous again
    labels[labels >= 0] = relabel
    spec = dem3d.Specimen(sph.x[body].copy(), sph.r[body].copy(), labels, case.density, sph.v[body].copy())
    return dem3d.Simulation(spec, contact(case, case.local_damping), dt=sim.dt, walls=walls(case),
                            periodic=sim.periodic)


def slump(case: HeapCase, sim, log: StageLog, progress=None, on_frame=None) -> dem3d.Simulation:
    """Stage 2 (``STAGES`` slump, arrest): with the end walls gone the fill slumps off the
    base edges into a heap. The flow runs ``slump_time`` s without local damping (PFC's
    0.7 makes a 0.7 m face creep for seconds: measured at 1,500 spheres), a frame every
    0.25 s; the grains that fell off the base are dropped (``rebuilt``) and the heap is
    brought to rest with local damping until its rms speed is below ``rest_speed``
    (checked every 500 steps, at most ``arrest_time``). Returns the heap."""
    run = _Run(case, log, progress=progress, on_frame=on_frame)
    run.sim = sim
    run.run("slump", "arrest")
    return run.sim


def averaged_base_stress(sim, steps: int) -> np.ndarray:
    """The base stress averaged over the next ``steps`` steps (``base_stress``)."""
    return base_stress(sim, advance(sim, steps, record_panels=True))


@dataclass
class Subsidence:
    """The base profile along the subsidence: Delta/H, centre and peak stress [Pa] of each
    chunk of ``record_every`` steps (panel forces averaged over the chunk)."""

    disp_over_H: list = field(default_factory=list)
    step: list = field(default_factory=list)
    time: list = field(default_factory=list)
    centre: list = field(default_factory=list)
    peak: list = field(default_factory=list)
    sigma: list = field(default_factory=list)


def subside(case: HeapCase, sim, H: float, log: StageLog, *, record_every: int = RECORD_EVERY, on_frame=None,
            frame_every: int = 2000, progress=None):
    """Stage 3 (``STAGES`` subsidence, hold): both base halves turn about their outer
    edges until the centre is down by subsidence_over_H x H, the base stress read every
    ``record_every`` steps (averaged over them); the base is then held for ``hold_time``.
    Returns (the simulation, now with fixed walls, and the Subsidence history).
    ``on_frame(frame, disp_over_H)`` is called every ``frame_every`` steps."""
    run = _Run(case, log, progress=progress, on_frame=on_frame, record_every=record_every, frame_every=frame_every)
    run.sim = sim
    run.kept["H"] = H
    run.run("subsidence", "hold")
    return run.sim, run.hist


@dataclass
class HeapRun:
    """Everything a heap run measured (SI units; stresses in Pa, left to right)."""

    shape: Shape
    porosity: float
    sigma_before: np.ndarray
    sigma_after: np.ndarray
    history: Subsidence
    disp_over_H: float
    weight_N: float
    base_force_before_N: float
    frames: dict
    spheres: int          # rained (the case's particle count)
    bodies: int           # rained
    dt: float
    stages: dict
    #: wall and CPU time [s] the run had taken up to the checkpoint it was resumed from
    #: (0, 0 for a run in one go)
    before_resume_s: tuple = (0.0, 0.0)


def run_heap(case: HeapCase, *, on_frame=None, progress=None, checkpoint=None, resume: dict | None = None,
             checkpoint_every_s: float | None = None, checkpoint_every_fraction: float | None = None) -> HeapRun:
    """Rain, slump, measure the base before, subside, measure after (module docstring).
    ``on_frame(frame, Delta/H or None)`` gets the rained fill, the heap, frames along the
    subsidence and the end state.

    ``checkpoint(state)`` is called between engine calls every ``checkpoint_every_s`` of
    wall time (``CHECKPOINT_EVERY_S``) and each time another ``checkpoint_every_fraction``
    of a stage's steps is done (``CHECKPOINT_EVERY_FRACTION``; ``STAGES``), after the
    frame or reading of that point was handed over, never at the run's end; ``state`` is
    a dict of numpy arrays (save it with ``studies.store.npz_bytes``). ``resume=state``
    (as saved, or loaded back) continues that run: the result is the uninterrupted run's
    bit for bit (its stage times those of both parts), and ``on_frame`` gets the frames
    after the checkpoint only."""
    run = _Run(case, StageLog(), on_frame=on_frame, progress=progress, checkpoint=checkpoint, resume=resume,
               checkpoint_every_s=checkpoint_every_s, checkpoint_every_fraction=checkpoint_every_fraction)
    run.run()
    return run.result()


# ----------------------------------------------------------------------------- the run, resumable
def checkpoint_key(case: HeapCase, record_every: int = RECORD_EVERY) -> str:
    """What a checkpoint of ``run_heap`` belongs to: the case and the subsidence's
    sampling (a resume with any other would not continue the same run)."""
    return content_key({"case": dataclasses.asdict(case), "record_every": int(record_every), "v": 1})


def checkpoint_stage(state: dict) -> tuple[str, int]:
    """(stage, steps of that stage done) of a checkpoint of ``run_heap``."""
    return STAGES[int(state["heap/stage"])], int(state["heap/done"])


def _prefixed(arrays: dict, prefix: str) -> dict:
    return {k[len(prefix):]: v for k, v in arrays.items() if k.startswith(prefix)}


class _Run:
    """A heap run in progress: the stage it is in (``STAGES``), the steps of that stage
    done, the simulation, and what the later stages need: ``kept`` (the fall's length,
    the settle ratio, the arrest speed, the spheres and bodies rained, the heap's shape,
    porosity and weight, the base stress before, the subsidence's start time and frame
    counter), the subsidence history, the panel forces of an averaging window in
    progress and the frame before subsidence. ``state()`` is all of it as numpy arrays
    (the engine's by ``Simulation.to_arrays``, which resumes bit for bit); ``resume=``
    such a state continues from it. No random number is drawn after the cloud is placed,
    so no generator state is kept.

    Each stage's loop runs from ``done`` and decides only at the boundaries a straight
    run has (the settle checks, the arrest checks, the 0.25 s frames of the flow, the
    subsidence readings), so a run resumed at any checkpoint takes the same steps: one
    taken between engine calls inside such an interval goes on to its boundary, one at
    a boundary is taken after the decision there (``_tick``)."""

    def __init__(self, case: HeapCase, log: StageLog, *, on_frame=None, progress=None, checkpoint=None,
                 resume: dict | None = None, checkpoint_every_s: float | None = None,
                 checkpoint_every_fraction: float | None = None, record_every: int = RECORD_EVERY,
                 frame_every: int = 2000):
        self.case, self.log, self.on_frame, self.progress, self.checkpoint = case, log, on_frame, progress, checkpoint
        self.every_s = CHECKPOINT_EVERY_S if checkpoint_every_s is None else float(checkpoint_every_s)
        self.every_fraction = (CHECKPOINT_EVERY_FRACTION if checkpoint_every_fraction is None
                               else float(checkpoint_every_fraction))
        self.record_every, self.frame_every = int(record_every), int(frame_every)
        self.key = checkpoint_key(case, self.record_every)
        self.stage, self.done, self.sim = 0, 0, None
        self.kept: dict = {}
        self.hist = Subsidence()
        self.avg: np.ndarray | None = None          # panel forces of the averaging window in progress
        self.frames: dict = {}
        self.sigma_after: np.ndarray | None = None
        self.clock = (_time.perf_counter(), _time.process_time())
        self.before_resume = (0.0, 0.0)
        self.last_checkpoint = self.clock[0]
        self.mark = self.next_mark = 1
        self.resumed = resume is not None
        if resume is not None:
            self._restore(resume)

    # ------------------------------------------------------------------ driving
    def run(self, first: str = STAGES[0], last: str = STAGES[-1]) -> None:
        """The stages ``first`` to ``last``; a resumed run from its checkpoint's stage and step."""
        start = self.stage if self.resumed else STAGES.index(first)
        for k in range(start, STAGES.index(last) + 1):
            fresh = not (self.resumed and k == start)
            self.stage = k
            if fresh:
                self.done = 0
            getattr(self, "_" + STAGES[k])(fresh)

    def result(self) -> HeapRun:
        k = self.kept
        shape = Shape(k["H"], k["slope_deg"], k["surface_x"], k["surface_top"], k["heap_spheres"])
        return HeapRun(shape, k["porosity"], k["sigma_before"], self.sigma_after, self.hist,
                       centre_drop(self.sim) / shape.H, k["weight"], k["base_force_before"], self.frames,
                       k["spheres"], k["bodies"], self.sim.dt, self.log.stages, self.before_resume)

    def _begin(self, total: int) -> None:
        """The fraction marks of a stage of ``total`` steps, the next one after the steps done."""
        self.mark = max(1, int(self.every_fraction * total))
        self.next_mark = (self.done // self.mark + 1) * self.mark

    def _tick(self, final: bool = False) -> None:
        """A checkpoint when another fraction of the stage is done or ``every_s`` of wall
        time have passed since the last one (``final``: the run's end, none)."""
        if self.checkpoint is None or final:
            return
        if self.done >= self.next_mark or _time.perf_counter() - self.last_checkpoint > self.every_s:
            self.next_mark = (self.done // self.mark + 1) * self.mark
            self.checkpoint(self.state())
            self.last_checkpoint = _time.perf_counter()

    def _task(self, label: str, total: int):
        if self.progress is None:
            return None
        return self.progress.add_task(label, total=total, completed=self.done, status="")

    def _steps(self, until: int, task=None, *, tick: bool = True) -> None:
        """Advance the stage to ``until`` steps done, one engine call (``chunk_steps``) at
        a time; a checkpoint may follow each call but the last unless ``tick``
        (the caller decides something there first and then ticks itself)."""
        while self.done < until:
            k = min(chunk_steps(self.sim), until - self.done)
            self.sim.step(k)
            self.done += k
            if task is not None:
                self.progress.update(task, advance=k, status=f"t = {self.sim.time:.2f} s")
            if tick or self.done < until:
                self._tick()

    def _average(self) -> np.ndarray:
        """The base stress averaged over ``average_steps`` (the window ``self.avg``)."""
        total = self.case.average_steps
        self._begin(total)
        while self.done < total:
            k = min(chunk_steps(self.sim), total - self.done)
            self.avg[self.done:self.done + k] = self.sim.step(k, record_panels=True)[0]
            self.done += k
            self._tick(final=self.stage == len(STAGES) - 1 and self.done >= total)
        return base_stress(self.sim, self.avg)

    def _walls(self) -> list:
        """The walls of the current stage's simulation."""
        case, name = self.case, STAGES[self.stage]
        if name in ("fall", "settle"):
            return walls(case, ends=True)
        if name == "subsidence":
            H, t0 = self.kept["H"], self.kept["t0"]
            return walls(case, motions=(subsidence_motion(case, -1, H, t0), subsidence_motion(case, +1, H, t0)))
        return walls(case)

    # ------------------------------------------------------------------ stages
    def _fall(self, fresh: bool) -> None:
        case = self.case
        if fresh:
            spec, top = generate(case, np.random.default_rng(case.seed))
            dt = time_step(case)
            self.sim = dem3d.Simulation(spec, contact(case, 0.0), dt=dt, walls=walls(case, ends=True),
                                        periodic=dem3d.Periodic(1, 0.0, case.width))
            self.sim.gravity = np.array([0.0, 0.0, -2.0 * G])
            self.kept["fall_steps"] = int(1.2 * math.sqrt(top / G) / dt)
        total = self.kept["fall_steps"]
        self._begin(total)
        self._steps(total, self._task("raining", total))

    def _settle(self, fresh: bool) -> None:
        """dem3d.settle's loop (ratio checked every 500 steps, at most 1 s), resumable."""
        case = self.case
        if fresh:
            self.sim.gravity = np.array([0.0, 0.0, -G])
            self.sim.set_params(contact(case, case.local_damping))
            self.kept["ratio"] = math.inf
        most, every = int(1.0 / self.sim.dt), 500
        self._begin(most)
        while self.done < most and not self.kept["ratio"] < case.settle_ratio:
            self._steps(min(most, (self.done // every + 1) * every), tick=False)
            self.kept["ratio"] = measure.unbalanced_force_ratio(self.sim)
            self._tick()
        self.log.stage("rain", self.kept["fall_steps"] + self.done, ratio=self.kept["ratio"])
        self.kept["spheres"] = self.sim.n_spheres
        self.kept["bodies"] = int(len(np.unique(self.sim.spheres.body_id)))
        if self.on_frame is not None:
            self.on_frame(dem3d.frame(self.sim), None)

    def _slump(self, fresh: bool) -> None:
        case = self.case
        if fresh:
            self.sim = rebuilt(case, self.sim)
            self.sim.set_params(contact(case, 0.0))
        total = int(case.slump_time / self.sim.dt)
        every = max(1, int(0.25 / self.sim.dt))            # a frame every 0.25 s of the flow
        task = self._task("slumping", total)
        self._begin(total)
        while self.done < total:
            self._steps(min(total, (self.done // every + 1) * every), task, tick=False)
            if self.on_frame is not None:
                self.on_frame(dem3d.frame(self.sim), None)
            self._tick()
        self.log.stage("slump", total)

    def _arrest(self, fresh: bool) -> None:
        case = self.case
        if fresh:
            sim = self.sim
            self.sim = rebuilt(case, sim, on_base(case, sim.spheres.x, sim.spheres.r) & (sim.spheres.x[:, 2] > 0.0))
            self.kept["speed"] = math.inf
        most, every = int(case.arrest_time / self.sim.dt), 500
        self._begin(most)
        # the test of the loop at every 500 steps (a resume inside 500 steps goes on to its end)
        while self.done % every or (self.done < most and self.kept["speed"] > case.rest_speed):
            self._steps((self.done // every + 1) * every, tick=False)
            self.kept["speed"] = heap_speed(case, self.sim)
            self._tick()
        self.log.stage("arrest", self.done, rms_speed=self.kept["speed"])

    def _before(self, fresh: bool) -> None:
        case = self.case
        if fresh:
            shape = heap_shape(case, self.sim)
            self.kept |= {"H": shape.H, "slope_deg": shape.slope_deg, "surface_x": shape.x,
                          "surface_top": shape.top, "heap_spheres": shape.spheres,
                          "porosity": heap_porosity(case, self.sim, shape.H)}
            self.avg = np.zeros((case.average_steps, self.sim.walls.n_panels, 3))
        sigma = self._average()
        self.avg = None
        areas = self.sim.walls.areas()[base_ids(self.sim)]
        self.kept |= {"sigma_before": sigma, "weight": heap_weight(case, self.sim),
                      "base_force_before": float(np.sum(sigma * areas))}
        self.log.stage("before", case.average_steps)
        self.frames["before"] = dem3d.frame(self.sim)
        if self.on_frame is not None:
            self.on_frame(self.frames["before"], 0.0)

    def _subsidence(self, fresh: bool) -> None:
        case, H = self.case, self.kept["H"]
        if fresh:
            self.kept["t0"] = self.sim.time
            self.sim = dem3d.Simulation.from_arrays(self.sim.to_arrays(), walls=self._walls())
            self.sim.walls.reset_pivots()          # the stored pivots are those of the fixed base
            self.kept["since"] = 0
            self.hist = Subsidence()
        sim, hist = self.sim, self.hist
        n_total = int(math.ceil(subsidence_duration(case, H) / sim.dt))
        task = self._task("subsidence", n_total)
        self._begin(n_total)
        while self.done < n_total:
            m = min(self.record_every, n_total - self.done)
            hist_f = advance(sim, m, record_panels=True)
            self.done += m
            self.kept["since"] += m
            sigma = base_stress(sim, hist_f)
            c, p, _ = centre_over_peak(sigma)
            hist.disp_over_H.append(centre_drop(sim) / H)
            hist.step.append(sim.step_count)
            hist.time.append(sim.time)
            hist.centre.append(c)
            hist.peak.append(p)
            hist.sigma.append(sigma)
            if self.on_frame is not None and (self.kept["since"] >= self.frame_every or self.done >= n_total):
                self.kept["since"] = 0
                self.on_frame(dem3d.frame(sim), hist.disp_over_H[-1])
            if task is not None:
                self.progress.update(task, advance=m, status=f"Delta/H {hist.disp_over_H[-1]:.4f}  "
                                                             f"centre/peak {c / p:.2f}")
            self._tick()
        self.log.stage("subsidence", n_total)

    def _hold(self, fresh: bool) -> None:
        if fresh:                                  # the base stops
            self.sim = dem3d.Simulation.from_arrays(self.sim.to_arrays(), walls=walls(self.case))
        n = int(self.case.hold_time / self.sim.dt)
        self._begin(n)
        self._steps(n)
        self.log.stage("hold", n)

    def _after(self, fresh: bool) -> None:
        if fresh:
            self.avg = np.zeros((self.case.average_steps, self.sim.walls.n_panels, 3))
        self.sigma_after = self._average()
        self.avg = None
        self.log.stage("after", self.case.average_steps)
        self.frames["after"] = dem3d.frame(self.sim)
        if self.on_frame is not None:
            self.on_frame(self.frames["after"], centre_drop(self.sim) / self.kept["H"])

    # ------------------------------------------------------------------ checkpoint
    def state(self) -> dict:
        """Everything the remaining stages need, as a dict of numpy arrays."""
        wall, cpu = _time.perf_counter(), _time.process_time()
        out = {f"sim/{k}": v for k, v in self.sim.to_arrays().items()}
        out |= {"heap/key": np.array(self.key), "heap/stage": np.array(self.stage), "heap/done": np.array(self.done),
                "heap/log": np.array(json.dumps(self.log.stages)),
                "heap/stage_s": np.array([wall - self.log.tic, cpu - self.log.cpu]),
                "heap/seconds": np.array([self.before_resume[0] + wall - self.clock[0],
                                          self.before_resume[1] + cpu - self.clock[1]])}
        out |= {f"kept/{k}": np.array(v, copy=True) for k, v in self.kept.items()}
        h = self.hist
        out |= {"sub/disp_over_H": np.array(h.disp_over_H, float), "sub/step": np.array(h.step, np.int64),
                "sub/time": np.array(h.time, float), "sub/centre": np.array(h.centre, float),
                "sub/peak": np.array(h.peak, float),
                "sub/sigma": np.array(h.sigma, float).reshape(len(h.sigma), self.case.bins)}
        if self.avg is not None:
            out["avg/force"] = self.avg[:self.done].copy()
        for name, fr in self.frames.items():
            out |= {f"frame/{name}/{f}": np.array(v, copy=True) for f, v in fr._asdict().items() if v is not None}
        return out

    def _restore(self, state: dict) -> None:
        if str(state.get("heap/key", "")) != self.key:
            raise InvalidParameter("resume", "a checkpoint of another run", "a checkpoint of this case",
                                   "a resumed run keeps the settings it started with")
        self.stage, self.done = int(state["heap/stage"]), int(state["heap/done"])
        # 0-d arrays back to the Python numbers they were (float64 and int64 exactly)
        self.kept = {k: (v.item() if v.ndim == 0 else np.array(v, copy=True))
                     for k, v in _prefixed(state, "kept/").items()}
        self.sim = dem3d.Simulation.from_arrays(_prefixed(state, "sim/"), walls=self._walls())
        self.log.stages = json.loads(str(state["heap/log"]))
        wall, cpu = (float(t) for t in state["heap/stage_s"])
        self.log.tic, self.log.cpu = _time.perf_counter() - wall, _time.process_time() - cpu
        self.before_resume = tuple(float(t) for t in state["heap/seconds"])
        self.hist = Subsidence(state["sub/disp_over_H"].tolist(), state["sub/step"].tolist(),
                               state["sub/time"].tolist(), state["sub/centre"].tolist(),
                               state["sub/peak"].tolist(), [np.array(r, copy=True) for r in state["sub/sigma"]])
        if "avg/force" in state:
            self.avg = np.zeros((self.case.average_steps, self.sim.walls.n_panels, 3))
            self.avg[:self.done] = state["avg/force"]
        names = sorted({k.split("/")[1] for k in state if k.startswith("frame/")})
        for name in names:
            f = _prefixed(state, f"frame/{name}/")
            self.frames[name] = dem3d.Frame(**{k: (int(v) if k == "step" else float(v) if k == "time"
                                                   else np.array(v, copy=True)) for k, v in f.items()})
