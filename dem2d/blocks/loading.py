"""Water raised by increments until the wall fails (``load_to_failure``): each increment
settled, the failure test (kinetic energy above its threshold for 10 readings) and the
mechanism at failure."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic.errors import InvalidParameter
from analytic.inputs import require_number

from .mechanism import Mechanism, classify_mechanism
from .model import BlockWall


@dataclass(frozen=True)
class LoadingPlan:
    """Water raised in increments; settling and failure tests (S-OET 2.1 in the reference).

    increment_fraction:  water added per increment, as a fraction of h (S-OET: 0.01)
    start_height_m:      water height of the first increment [m] (0: from the toe)
    reading_interval_s:  time between readings [s] (S-OET: 500 steps of 2e-4 s = 0.1 s)
    failure_energy_J_m:  failure when the window kinetic energy exceeds this ... [J/m] (1e-3)
    failure_readings:    ... on this many successive readings (S-OET: 10)
    equilibrium_energy_J_m: settled when the window kinetic energy is below this ... [J/m]
    equilibrium_readings:   ... on this many successive readings
    max_settle_s:        at most this long per increment [s]; then the next increment
    runaway_fraction:    failure at once when the crest has moved this fraction of h
    direction:           "normal" (pressure normal to the current face) or "fixed" (its
                         initial normal: S-OET's conservative choice)

    The *window* kinetic energy uses each block's mean velocity over a reading interval
    (displacement / interval), not the instantaneous one: the solver's contact jitter
    (1-4 mm/s, zero mean; a probe of the settings) then does not read as motion.
    """

    increment_fraction: float = 0.01
    start_height_m: float = 0.0
    reading_interval_s: float = 0.1
    failure_energy_J_m: float = 1e-3
    failure_readings: int = 10
    equilibrium_energy_J_m: float = 1e-5
    equilibrium_readings: int = 2
    max_settle_s: float = 3.0
    runaway_fraction: float = 0.02
    direction: str = "normal"

    def __post_init__(self):
        require_number("increment_fraction", self.increment_fraction, 0.0, 0.2, unit="")
        require_number("start_height", self.start_height_m, 0.0, None, lo_open=False, unit="m")
        require_number("reading_interval", self.reading_interval_s, 0.0, 10.0, unit="s")
        require_number("failure_energy", self.failure_energy_J_m, 0.0, None, unit="J/m")
        require_number("equilibrium_energy", self.equilibrium_energy_J_m, 0.0, self.failure_energy_J_m,
                       unit="J/m")
        for name in ("failure_readings", "equilibrium_readings"):
            v = getattr(self, name)
            if not (isinstance(v, int) and 1 <= v <= 1000):
                raise InvalidParameter(name, v, "an integer in [1, 1000]")
        require_number("max_settle", self.max_settle_s, self.reading_interval_s, None, lo_open=False, unit="s")
        require_number("runaway_fraction", self.runaway_fraction, 0.0, 1.0, unit="")
        if self.direction not in ("normal", "fixed"):
            raise InvalidParameter("water_direction", self.direction, "normal | fixed")


@dataclass
class LoadingResult:
    """Water loading to failure.

    water_height_m, crest_displacement_m, settled, time_s: one row per increment (the
        state at the end of it; crest displacement outward since the start [m])
    critical_height_m:   water height of the increment at which the wall failed [m]
                         (NaN: it stood to the crest)
    last_stable_height_m: the last water height the wall settled under [m]
    failed:              the failure test fired (energy or runaway)
    mechanism:           kinematics at failure (between the last settled state and the
                         first reading with the crest 5 mm further out, or the last)
    velocities:          (n,2) block velocities at that reading [m/s]
    outlines:            block polygons in world coordinates at that reading
    reference_outlines:  the same at the last settled state
    steps, simulated_s:  solver steps and simulated time
    """

    water_height_m: list
    crest_displacement_m: list
    settled: list
    time_s: list
    critical_height_m: float
    last_stable_height_m: float
    failed: bool
    mechanism: Mechanism | None
    velocities: np.ndarray
    outlines: list
    reference_outlines: list
    steps: int
    simulated_s: float


def window_energy(wall: BlockWall, x0, a0, x1, a1, interval: float) -> float:
    """Kinetic energy of the mean block velocities over a reading interval [J/m]."""
    v = (x1 - x0) / interval
    om = (a1 - a0) / interval
    dyn = wall.dynamic
    return float(0.5 * (wall.mass[dyn] * (v[dyn] ** 2).sum(axis=1)).sum() + 0.5 * (wall.inertia[dyn] * om[dyn] ** 2).sum())


def _settle(wall: BlockWall, plan: LoadingPlan, x_start: np.ndarray, on_reading=None) -> tuple[str, dict]:
    """Readings every ``plan.reading_interval_s`` until settled, failed or out of time.
    Returns ("settled" | "failed" | "unsettled", the kinematics at failure)."""
    runaway = plan.runaway_fraction * wall.section.height_m
    x_ref, a_ref = wall.positions(), wall.angles()
    xp, ap = x_ref, a_ref
    calm = loud = 0
    caught = None
    n_max = int(math.ceil(plan.max_settle_s / plan.reading_interval_s))
    for _ in range(n_max):
        wall.advance(plan.reading_interval_s)
        x, a = wall.positions(), wall.angles()
        e = window_energy(wall, xp, ap, x, a, plan.reading_interval_s)
        xp, ap = x, a
        crest = wall.crest_displacement(x_start)
        if on_reading is not None:
            on_reading(wall, e, crest)
        if caught is None and wall.crest_displacement(x_ref) > 0.005:
            caught = {"x": x, "a": a, "v": wall.velocities(), "outlines": wall.world_outlines()}
        calm = calm + 1 if e < plan.equilibrium_energy_J_m else 0
        loud = loud + 1 if e > plan.failure_energy_J_m else 0
        if loud >= plan.failure_readings or crest > runaway:
            if caught is None:
                caught = {"x": x, "a": a, "v": wall.velocities(), "outlines": wall.world_outlines()}
            caught |= {"x_ref": x_ref, "a_ref": a_ref}
            return "failed", caught
        if calm >= plan.equilibrium_readings:
            return "settled", {}
    return "unsettled", {}


def load_to_failure(wall: BlockWall, plan: LoadingPlan = LoadingPlan(), *, progress=None,
                    on_reading=None) -> LoadingResult:
    """Raise the water by ``plan.increment_fraction`` of h per increment, settling
    after each, until the wall fails or the water reaches the crest.

    progress:    called as progress(water_height_m, crest_displacement_m) per increment
    on_reading:  called as on_reading(wall, window_energy, crest_displacement) per reading
    """
    h = wall.section.height_m
    wall.direction = plan.direction
    wall.water_height = 0.0
    wall.advance(plan.reading_interval_s)             # seat the blocks under their weight
    x_start = wall.positions()
    ref_outlines = wall.world_outlines()
    rows = ([], [], [], [])
    dh = plan.increment_fraction * h
    hw = plan.start_height_m
    last_stable = 0.0
    n_inc = int(math.ceil((h - hw) / dh - 1e-9))
    for i in range(n_inc + 1):
        wall.water_height = min(hw + i * dh, h)
        state, caught = _settle(wall, plan, x_start, on_reading)
        crest = wall.crest_displacement(x_start)
        for r, v in zip(rows, (wall.water_height, crest, state == "settled", wall.time)):
            r.append(v)
        if progress is not None:
            progress(wall.water_height, crest)
        if state == "failed":
            mech = classify_mechanism(wall.section, wall.masonry.block_height_m, wall.course, wall.dynamic,
                                      caught["x_ref"], caught["a_ref"], caught["x"], caught["a"])
            return LoadingResult(*rows, wall.water_height, last_stable, True, mech, caught["v"],
                                 caught["outlines"], ref_outlines, wall.steps, wall.time)
        if state == "settled":
            last_stable = wall.water_height
            ref_outlines = wall.world_outlines()
    return LoadingResult(*rows, math.nan, last_stable, False, None, wall.velocities(), wall.world_outlines(),
                         ref_outlines, wall.steps, wall.time)
