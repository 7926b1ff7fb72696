"""The Khosravi run: pluviation, at-rest reading, translation of the wall.

``KhosraviRun`` owns a ``Sim`` and exposes the three stages as generators, so a caller
(studies/khosravi.py, tests) decides what to draw, log or stop. Nothing here writes
files. Every pressure reading is a time average over ``case.window`` seconds of the
contact impulses on each 10 mm panel (``probes.py``).

Normalisation (Khosravi et al. Figs. 9-13): sigma / (gamma H) against z / H, with
gamma the unit weight of the deposited backfill, total grain weight / (box width x
surface height) [N/m^3] (eq. 1 with the measured porosity), and H the measured height
of the surface.
"""

from __future__ import annotations

import pickle
from dataclasses import dataclass, field
from typing import Iterator, NamedTuple

import numpy as np

from dem2d.frames import Frame
from dem2d.measure import panel_stresses, readings, solid_fraction
from analytic.constants import G
from dem2d.pluviation import LayerStatus, pluviate, surface_height
from .case import KhosraviCase, build_box
from dem2d.sim import Sim, restore
from dem2d.walls import Translate



class WallReading(NamedTuple):
    """Time-averaged wall load over one window.

    time:      window centre [s]
    dis:       wall displacement away from the backfill at the window centre [m]
    sigma:     (p,) normal stress on every wall panel [Pa], panel 0 at the bottom
    tau:       (p,) shear stress, positive when the grains drag the wall down [Pa]
    floor_fy:  vertical force on the floor by the grains [N/m] (negative = down)
    wall_fy, far_fy: vertical force on the retaining / far wall [N/m]
    contacts:  (p,) mean grain contacts per panel per step
    """

    time: float
    dis: float
    sigma: np.ndarray
    tau: np.ndarray
    floor_fy: float
    wall_fy: float
    far_fy: float
    contacts: np.ndarray


@dataclass
class Backfill:
    """What the pluviation produced: grain count, surface height H [m], unit weight
    gamma [N/m^3], porosity n, solid fraction of the interior, simulated time [s]."""

    n_grains: int
    H: float
    gamma: float
    porosity: float
    interior_porosity: float
    weight: float
    time: float
    steps: int
    layer_readings: list = field(default_factory=list)


class KhosraviRun:
    """Khosravi et al.'s translation test on a pymunk backfill.

    run = KhosraviRun(case)            # empty box, or KhosraviRun(case, sim=restored)
    for s in run.fill(): ...           # layered pluviation (LayerStatus per check)
    rest = run.at_rest()               # WallReading at Dis = 0
    for r in run.translate(): ...      # WallReading per window up to Dis/H max
    """

    def __init__(self, case: KhosraviCase, sim: Sim | None = None):
        self.case = case
        self.sim = build_box(case) if sim is None else sim
        self.backfill: Backfill | None = self.sim.meta.get("backfill")
        self.rest: WallReading | None = None
        self.history: list[WallReading] = []

    # ------------------------------------------------------------------ stage 1
    def fill(self) -> Iterator[LayerStatus]:
        """Layered pluviation to case.H; after each settled layer, one pressure reading
        is kept in ``backfill.layer_readings`` (Khosravi Fig. 9)."""
        c, sim = self.case, self.sim
        layer_readings = list(sim.meta.get("layer_readings", []))
        sim.meta["layer_readings"] = layer_readings  # kept in snapshots taken mid-fill
        # a fill continued from a snapshot reads the layer it was taken after, as the
        # uninterrupted fill does when the next layer's first status comes
        last = sim.meta.get("fill_last")
        for s in pluviate(sim, c.grading, c.material, x0=0.0, x1=c.box_width, floor=0.0,
                          height=c.H, settings=c.pluviation):
            sim.meta["fill_last"] = s
            yield s
            if last is not None and s.layer != last.layer:
                sigma = self.reading(0.2 * c.window).sigma
                if c.pluviation.hold_depth > 0:
                    # below the held grains the cells see only the free strip along the wall
                    w = sim.walls["wall"]
                    sigma = np.where(w.centres()[:, 1] < last.surface - c.pluviation.hold_depth, np.nan, sigma)
                layer_readings.append((last.layer, last.surface, sigma))
            last = s
        sim.meta.pop("fill_last", None)
        self.backfill = self._describe(layer_readings)
        sim.meta["backfill"] = self.backfill

    def _describe(self, layer_readings) -> Backfill:
        c, sim = self.case, self.sim
        st = sim.state()
        r = sim.grains.circle_radius
        H = surface_height(st.position, r, np.ones(len(r), bool), 0.0, c.box_width, bins=20)
        weight = float(np.sum(sim.masses())) * G
        solids = float(np.sum(np.pi * r**2))
        n = 1.0 - solids / (c.box_width * H)
        inner = solid_fraction(st.position, r, 0.1 * c.box_width, 0.9 * c.box_width, 0.1 * H, 0.9 * H)
        return Backfill(len(r), H, weight / (c.box_width * H), n, 1.0 - inner, weight,
                        sim.time, sim.step_count, layer_readings)

    # ------------------------------------------------------------------ readings
    def reading(self, window: float | None = None) -> WallReading:
        """Run ``window`` seconds (default case.window) with the pressure cells on and
        return the time-averaged wall load."""
        sim = self.sim
        window = self.case.window if window is None else window
        n = max(1, int(round(window / sim.dt)))
        probe = sim.probe
        wall = sim.walls["wall"]
        d0 = -wall.displacement()[0]
        t0 = sim.time
        probe.start()
        sim.run(n)
        probe.stop()
        d1 = -wall.displacement()[0]
        sig, tau = panel_stresses(probe.force("wall"), wall.normals(), wall.corners(), wall.lengths())
        return WallReading(0.5 * (t0 + sim.time), 0.5 * (d0 + d1), sig, tau,
                           float(probe.force("floor")[:, 1].sum()), float(probe.force("wall")[:, 1].sum()),
                           float(probe.force("far")[:, 1].sum()), probe.contacts_per_step("wall"))

    def at_rest(self) -> WallReading:
        """Switch to the readings' solver (``case.reading_solver``), settle
        ``case.rest_time`` more, then read the wall at rest."""
        if self.backfill is None:
            self.backfill = self._describe([])
        self.sim.set_solver(self.case.reading_solver)  # the readings' sweeps from here on
        self.sim.run(max(0, int(round(self.case.rest_time / self.sim.dt))))
        self.rest = self.reading()
        return self.rest

    # ------------------------------------------------------------------ stage 3
    def translate(self) -> Iterator[WallReading]:
        """Move the wall away from the backfill at case.wall_speed to
        Dis/H = case.wall_disp_over_H_max (H = measured surface height), one reading per window."""
        c, sim = self.case, self.sim
        if self.rest is None:
            self.at_rest()
        H = self.backfill.H
        sim.drive("wall", Translate((-c.wall_speed, 0.0)))
        try:
            while True:
                r = self.reading()
                self.history.append(r)
                yield r
                if r.dis / H >= c.wall_disp_over_H_max:
                    break
        finally:
            sim.drive("wall", None)

    # ------------------------------------------------------------------ snapshots
    def snapshot(self) -> bytes:
        """Bytes that ``restored`` turns back into this run between readings: the model
        (``Sim.snapshot``: grains, walls, contact impulses, clock, random generator), the
        at-rest reading and the readings so far."""
        return pickle.dumps({"format": "wallsim-khosravi-run-1", "sim": self.sim.snapshot(), "rest": self.rest,
                             "history": self.history}, protocol=pickle.HIGHEST_PROTOCOL)

    @classmethod
    def restored(cls, case: KhosraviCase, blob: bytes) -> "KhosraviRun":
        """The run ``snapshot`` saved, going on in a fresh space (``case``: the one it ran)."""
        payload = pickle.loads(blob)
        if not isinstance(payload, dict) or payload.get("format") != "wallsim-khosravi-run-1":
            raise TypeError("not a Khosravi run snapshot")
        run = cls(case, sim=restore(payload["sim"]))
        run.rest, run.history = payload["rest"], list(payload["history"])
        return run

    def frame(self, with_contacts: bool = True) -> Frame:
        return self.sim.frame(with_contacts)

    # ------------------------------------------------------------------ derived
    def panel_depths(self) -> np.ndarray:
        """(p,) depth of every panel centre below the surface [m] (negative above it)."""
        w = self.sim.walls["wall"]
        return self.backfill.H - w.centres()[:, 1]

    def readings_of(self, r: WallReading) -> tuple[np.ndarray, np.ndarray, float]:
        """Khosravi's reading points for one WallReading: (depth of each 4-panel reading
        [m], its mean normal stress [Pa], PS0 = bottom panel alone [Pa]). Only groups
        wholly below the surface are read."""
        w = self.sim.walls["wall"]
        bottoms = w.corners()[:, :, 1].min(axis=1)
        starts, means = readings(r.sigma, 4, top=self.backfill.H, panel_bottoms=bottoms,
                                 panel_height=self.case.panel_height)
        depth = self.backfill.H - (bottoms[starts] + 2 * self.case.panel_height)
        return depth, means, float(r.sigma[0])
