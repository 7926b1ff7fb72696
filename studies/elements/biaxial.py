"""Numerical biaxial test (Khosravi et al. §2, Figs. 2-4): the friction calibration.

Specimen: disks of the backfill's grading in a rectangle of about 70 mm x 200 mm,
no gravity, frictionless rigid walls:

* ``bottom`` and ``left``: fixed;
* ``top``: a kinematic platen; a velocity servo during preparation, then constant
  axial strain rate;
* ``right``: a dynamic, non-rotating piston pushed with F = sigma_3 x h(t) (h the current
  specimen height) -- a stress-controlled boundary. An impulse solver has no contact
  stiffness, so a PFC-style stiffness-based wall servo has nothing to act on; a piston
  with an applied force is the exact stress boundary for rigid grains.

Preparation: a loose cloud is compacted isotropically to sigma_0 = sigma_3 with the
grain friction set to ``prep_friction`` (lower = denser; used to match the porosity of
the pluviated backfill). Then friction is set to ``friction`` and the top platen moves
down at a constant strain rate (quasi-static: inertial number I = rate d50 /
sqrt(sigma_3 / rho_s) ~ 1e-4 at the defaults).

Results (2D, per metre): sigma_1 = F_top / w, sigma_3 = F_right / h, axial strain
eps_1 = (h_0 - h) / h_0, volumetric strain eps_v = 1 - A / A_0 (compression positive),
mobilised friction sin(phi) = (sigma_1 - sigma_3) / (sigma_1 + sigma_3). The shear band
angle from the major principal plane (horizontal) follows from the incremental strain
field (``shear_band_angle``); Khosravi et al. read beta ~ 55 deg and
beta = 45 + phi/2 -> phi ~ 20 deg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterator, NamedTuple

import numpy as np
import pymunk

from analytic.errors import InvalidParameter
from analytic.inputs import MAX_PRESSURE_KPA
from analytic.schema import check_fields, param, seed_param

from dem2d.build import Grains, add_disks, friction_split, new_space
from dem2d.grading import Grading
from dem2d.params import Material, Solver
from dem2d.pluviation import cloud
from dem2d.sim import Sim
from dem2d.walls import PANEL_TYPE_BASE, panel_wall

RHO_WATER = 1000.0


#: a friction coefficient beyond any grain (atan 10 = 84 deg); 1e300 ran without end
MAX_FRICTION = 10.0
#: 10 MPa, the theories' bound on a stress (analytic.inputs.MAX_PRESSURE_KPA): 1e15 Pa ran
#: without end (the rigid disks' solver never met the servo target)
MAX_CONFINING_PA = MAX_PRESSURE_KPA * 1e3


@dataclass(frozen=True)
class BiaxialCase:
    """Biaxial test settings (module docstring)."""

    # the specimen sets the disk count, width height target_fraction / mean disk area (12.7k at
    # 70 x 200 mm of the paper's grains, ~10 min a test at 80 sweeps): 1 m x 0.2 m is ~180k disks,
    # 0.07 m x 2 m ~130k; the product with the grain size is bounded below (1e6 disks)
    width: float = param(0.07, unit="m", lo=0, hi=1, lo_open=True,
                         meaning="target specimen width after compaction (sizes the grain count; paper ~70 mm)")
    height: float = param(0.20, unit="m", lo=0, hi=2, lo_open=True,
                          meaning="target specimen height after compaction (sizes the grain count; paper ~200 mm)")
    # below 0.25 x the paper's D50 the paper's specimen holds > 16 x its 12.7k disks
    d50: float = param(1.16e-3, unit="m", lo=2.5e-4, meaning="median disk diameter by mass, as the backfill (1.16 mm)")
    cu: float = param(1.55, lo=1, hi=6, hi_open=True,
                      meaning="uniformity coefficient D60 / D10 of the linear-by-mass grading, as the backfill (1.55)")
    # 0.25: 16 x the paper's disks, ~200k in its specimen
    particles_scale: float = param(1.0, lo=0.25, meaning="multiply every diameter by this (coarser grains, same "
                                                          "specimen; 1 = ~12.7k disks)")
    gs: float = param(2.65, lo=0, hi=20, lo_open=True, meaning="specific gravity of the grains, as the backfill (2.65)")
    friction: float = param(0.5, lo=0, hi=MAX_FRICTION, meaning="particle-particle coefficient during shearing")
    prep_friction: float = param(0.25, lo=0, hi=MAX_FRICTION,
                                 meaning="particle-particle coefficient during compaction (lower = denser)")
    confining: float = param(4000.0, unit="Pa", lo=0, hi=MAX_CONFINING_PA, lo_open=True,
                             meaning="confining stress sigma_3 (Khosravi: 4 kPa; also 2, 3, 5)")
    target_fraction: float = param(0.82, lo=0, hi=0.907, lo_open=True, hi_open=True,
                                   meaning="expected solid fraction after compaction (sizes the grain count)")
    # steps = max_strain / (strain_rate dt): at 1e-3 /s a 0.1-strain test is 5e5 steps, ~8 h at
    # 12.7k disks (~60 ms a step at 80 sweeps); below it days a test
    strain_rate: float = param(0.2, unit="1/s", lo=1e-3,
                               meaning="axial strain rate (inertial number ~2e-4 at 0.2 /s and 4 kPa: quasi-static)")
    max_strain: float = param(0.10, lo=0, hi=0.5, lo_open=True, hi_open=True, meaning="axial strain that ends the test")
    piston_mass_fraction: float = param(0.05, lo=0, hi=1, lo_open=True,
                                        meaning="mass of the lateral piston / mass of the specimen")
    compaction_rate: float = param(1.5, unit="1/s", lo=0, hi=10, lo_open=True,
                                   meaning="piston speed limit while compacting / current specimen size")
    # a test is at least sample_every steps a sample: 10,000 are 2 s at 2e-4 s, ~10 min at 12.7k disks
    sample_every: int = param(50, lo=1, hi=10_000, meaning="steps between samples of the stresses")
    seed: int = seed_param(1, meaning="random seed of the specimen: grain sizes, cloud positions, insertion order")
    # dt 2e-4 s, 80 sweeps a step, as the Khosravi readings it calibrates (with 10 the
    # full-size specimen over-compacts to a solid fraction of 0.91 and phi reads ~3 deg high
    # at mu 0.3; from 40 to 80 the peak at mu 0.43 falls from 20.7 to 19.5 deg, the critical
    # state stays at 18.0; docs/dem2d.md)
    solver: Solver = field(default_factory=lambda: Solver(dt=2e-4, iterations=80))

    def __post_init__(self):
        check_fields(self)
        # ~4.2 kB a packed disk in pymunk (4 GB at 1e6) and ~20 s a step at 80 sweeps: ~3 days a test
        disks = self.width * self.height * self.target_fraction / self.grading.mean_area()
        if disks > 1_000_000:
            least = self.particles_scale * math.sqrt(disks / 1_000_000)
            raise InvalidParameter("particles_scale", self.particles_scale, f">= {least:.3g}",
                                   f"~{disks:,.0f} disks, more than 1,000,000: coarser grains or a smaller specimen")

    @property
    def grading(self) -> Grading:
        return Grading(self.d50, self.cu).scaled(self.particles_scale)

    def material(self, friction: float) -> Material:
        return Material(density=self.gs * RHO_WATER, friction=friction, wall_friction=0.0)

    def inertial_number(self) -> float:
        """I = strain_rate d50 / sqrt(sigma_3 / rho_s) [-] (quasi-static below ~1e-3)."""
        return self.strain_rate * self.grading.d50 / math.sqrt(self.confining / (self.gs * RHO_WATER))


class BiaxialSample(NamedTuple):
    """One sample: stage ("compact"/"shear"), time [s], axial strain [-], volumetric
    strain [-], sigma_1, sigma_3 [Pa], width w and height h [m], solid fraction [-],
    mobilised friction angle [deg]."""

    stage: str
    time: float
    eps_axial: float
    eps_vol: float
    sigma_1: float
    sigma_3: float
    width: float
    height: float
    solid_fraction: float
    phi_mob: float


@dataclass(frozen=True)
class BiaxialResult:
    """Summary of one biaxial test.

    phi_peak_deg, eps_peak:   largest mobilised friction angle (smoothed) and its strain
    phi_cs_deg:               critical state: mean phi over the last third of the strain
    eps_cs:                   strain at which sin(phi) first reaches 95 % of sin(phi_cs)
    band_angle_deg:           shear band angle from the major principal plane
    phi_from_band_deg:        2 (beta - 45), the paper's reading of the band angle (NaN for a band
                              flatter than 45 deg, which has no Mohr-Coulomb reading)
    solid_fraction_0:         after compaction; porosity = 1 - solid_fraction_0
    n_grains, dilatancy_deg:  grain count; mean dilatancy angle over the last third
    dilatancy_peak_deg:       dilatancy angle at the peak: the mean rate over the axial
                              strains within ``smooth_strain`` of eps_peak (the width the
                              peak itself is read over), the angle a triaxial reports
                              beside its peak friction (Bolton 1986)
    """

    phi_peak_deg: float
    eps_peak: float
    phi_cs_deg: float
    eps_cs: float
    band_angle_deg: float
    phi_from_band_deg: float
    solid_fraction_0: float
    n_grains: int
    dilatancy_deg: float
    confining: float
    friction: float
    dilatancy_peak_deg: float = float("nan")


class BiaxialTest:
    """Builds the specimen and runs preparation and shearing as generators.

    Usage: ``t = BiaxialTest(case); for s in t.prepare(): ...; for s in t.shear(): ...;
    t.result()``. ``t.sim`` is the model; ``t.samples`` the shear samples.
    """

    #: strain over which the stresses are smoothed before the peak is read [-]
    smooth_strain = 0.005

    def __init__(self, case: BiaxialCase):
        self.case = case
        n = self._grain_count()
        f_cloud = 0.5
        expand = math.sqrt(case.target_fraction / f_cloud)
        w0, h0 = case.width * expand, case.height * expand
        space = self._new_space(n)
        rng = np.random.default_rng(case.seed)
        # the cloud is drawn first (numpy only): a taller cloud needs taller side walls
        cloud_ = self._cloud(n, w0, f_cloud, rng)
        # the cloud may be taller than h0 if the lattice is coarser than planned
        h_cloud = cloud_[-1]
        big_w, big_h = 2 * w0, self._wall_height(h0, h_cloud)
        m = 0.02 * big_w
        t = PANEL_TYPE_BASE
        bottom = panel_wall(space, "bottom", (-m, 0.0), (big_w, 0.0), 1, friction=0.0,
                            into=(0.0, 1.0), first_type=t)
        left = panel_wall(space, "left", (0.0, -m), (0.0, big_h), 1, friction=0.0,
                          into=(1.0, 0.0), first_type=t + 1)
        grains = Grains()
        self._add_grains(space, grains, cloud_, rng)
        self.mass = float(math.fsum(b.mass for b in grains.bodies))
        piston = self.mass * case.piston_mass_fraction
        right = panel_wall(space, "right", (w0, -m), (w0, big_h), 1, friction=0.0,
                           into=(0.0, 0.0), pivot=(w0, 0.0), first_type=t + 3, mass=piston)
        h_top = max(h0, h_cloud + 1e-4)
        top = panel_wall(space, "top", (-m, h_top), (big_w, h_top), 1, friction=0.0,
                         into=(0.0, 0.0), pivot=(0.0, h_top), first_type=t + 2, mass=piston)
        self.sim = Sim(space=space, grains=grains,
                       walls={"bottom": bottom, "left": left, "top": top, "right": right},
                       solver=case.solver, rng=rng)
        gr = case.grading
        self.sim.meta.update(r_min=gr.d_min / 2, d_max=gr.d_max, case="biaxial")
        self.solid_area = self._solid_area(grains)
        self.samples: list[BiaxialSample] = []
        self._h0 = None
        self._a0 = None
        self._pos_marks: list[tuple[float, np.ndarray]] = []
        self.sim.hooks.append(self._push_piston)

    # ------------------------------------------------------------------ grains (disks)
    # A grain shape other than disks overrides these five (``studies.elements.gravel_biaxial``).
    def _grain_count(self) -> int:
        """Grains that fill width x height at ``target_fraction``."""
        c = self.case
        return int(round(c.width * c.height * c.target_fraction / c.grading.mean_area()))

    def _new_space(self, n: int) -> pymunk.Space:
        gr = self.case.grading
        return new_space(self.case.solver, gravity=(0.0, 0.0), r_min=gr.d_min / 2, d_max=gr.d_max,
                         expected_shapes=n)

    def _cloud(self, n: int, w0: float, f_cloud: float, rng: np.random.Generator) -> tuple:
        """A loose cloud over [0, w0]: (centres, radii, its top [m])."""
        centres, radii = cloud(n, self.case.grading, rng, 0.0, w0 * 0.999, 0.0, f_cloud)
        return centres, radii, float((centres[:, 1] + radii).max())

    def _wall_height(self, h0: float, h_cloud: float) -> float:
        """Length of the side walls [m]."""
        return 2 * h0

    def _add_grains(self, space: pymunk.Space, grains: Grains, cloud_: tuple, rng: np.random.Generator) -> None:
        """The cloud's grains into the space at the preparation friction."""
        add_disks(space, grains, cloud_[0], cloud_[1], self.case.material(self.case.prep_friction), rng)

    def _solid_area(self, grains: Grains) -> float:
        """Solid area of the grains [m^2 per m] (porosity = 1 - solid area / specimen area)."""
        return float(np.sum(np.pi * grains.circle_radius**2))

    # ------------------------------------------------------------------ geometry
    def width(self) -> float:
        return float(self.sim.walls["right"].bodies[0].position.x)

    def height(self) -> float:
        return float(self.sim.walls["top"].bodies[0].position.y)

    def _push_piston(self, sim: Sim) -> None:
        """Stress-controlled pistons: F = -sigma_3 h (x) on the right piston and, while
        the top is still a piston (compaction), F = -sigma_0 w (y) on the top. Speeds
        are capped at ``compaction_rate`` times the current width / height, so both
        directions compact at the same strain rate and loose grains are not swept."""
        w, h = self.width(), self.height()
        body = sim.walls["right"].bodies[0]
        body.force = (-self.case.confining * h, 0.0)
        vmax = self.case.compaction_rate * w
        body.velocity = (min(max(body.velocity.x, -vmax), vmax), 0.0)
        top = sim.walls["top"].bodies[0]
        if top.body_type == pymunk.Body.DYNAMIC:
            top.force = (0.0, -self.case.confining * w)
            vmax = self.case.compaction_rate * h
            top.velocity = (0.0, min(max(top.velocity.y, -vmax), vmax))

    def _stresses(self) -> tuple[float, float]:
        p = self.sim.probe
        f_top = p.force("top")[0]
        f_right = p.force("right")[0]
        return float(f_top[1]) / self.width(), float(f_right[0]) / self.height()

    def _sample(self, stage: str) -> BiaxialSample:
        s1, s3 = self._stresses()
        w, h = self.width(), self.height()
        area = w * h
        eps_a = 0.0 if self._h0 is None else (self._h0 - h) / self._h0
        eps_v = 0.0 if self._a0 is None else 1.0 - area / self._a0
        sphi = (s1 - s3) / (s1 + s3) if (s1 + s3) > 0 else 0.0
        return BiaxialSample(stage, self.sim.time, eps_a, eps_v, s1, s3, w, h,
                             self.solid_area / area, math.degrees(math.asin(max(min(sphi, 1.0), -1.0))))

    # ------------------------------------------------------------------ stages
    def prepare(self, max_time: float = 2.0, tolerance: float = 0.05) -> Iterator[BiaxialSample]:
        """Isotropic compaction to sigma_0 = confining with ``prep_friction``: the top and
        right pistons push with sigma_0 times the current width / height. Done when both
        measured stresses are within ``tolerance`` of sigma_0 and both pistons move
        at strain rates below 1 % of ``compaction_rate`` for 5 consecutive samples."""
        c, sim = self.case, self.sim
        probe = sim.probe
        ok = 0
        probe.start()
        while sim.time < max_time:
            probe.reset()
            sim.run(c.sample_every)
            s = self._sample("compact")
            yield s
            r_top = abs(sim.walls["top"].bodies[0].velocity.y) / s.height
            r_right = abs(sim.walls["right"].bodies[0].velocity.x) / s.width
            good = (abs(s.sigma_1 / c.confining - 1) < tolerance and abs(s.sigma_3 / c.confining - 1) < tolerance
                    and max(r_top, r_right) < 0.01 * c.compaction_rate)
            ok = ok + 1 if good else 0
            if ok >= 5:
                break
        probe.stop()

    def shear(self) -> Iterator[BiaxialSample]:
        """Set the shearing friction, then compress axially at ``strain_rate`` to
        ``max_strain`` while the piston holds sigma_3."""
        c, sim = self.case, self.sim
        f_grain, _ = friction_split(c.friction, 0.0)
        for b in sim.grains.bodies:
            for sh in b.shapes:
                sh.friction = f_grain
        top = sim.walls["top"].bodies[0]
        top.body_type = pymunk.Body.KINEMATIC  # from piston to strain-controlled platen
        self._h0 = self.height()
        self._a0 = self.width() * self._h0
        v = c.strain_rate * self._h0
        sim.walls["top"].set_motion((0.0, -v), 0.0)
        probe = sim.probe
        probe.start()
        marks = np.linspace(0.0, c.max_strain, 11)
        k = 0
        while True:
            probe.reset()
            sim.run(c.sample_every)
            s = self._sample("shear")
            self.samples.append(s)
            while k < len(marks) and s.eps_axial >= marks[k]:
                self._pos_marks.append((s.eps_axial, sim.state().position.copy()))
                k += 1
            yield s
            if s.eps_axial >= c.max_strain:
                break
        sim.walls["top"].set_motion((0.0, 0.0), 0.0)
        probe.stop()

    # ------------------------------------------------------------------ results
    @property
    def position_marks(self) -> list[tuple[float, np.ndarray]]:
        """(axial strain, grain positions (n,2) [m]) at every tenth of the shear strain."""
        return list(self._pos_marks)

    def result(self) -> BiaxialResult:
        """Summarise the shear samples (``BiaxialResult``)."""
        if not self.samples:
            raise RuntimeError("run shear() first")
        return summarize(self.samples, self._pos_marks, len(self.sim.grains), self.case,
                         self.sim.grains.circle_radius, smooth_strain=self.smooth_strain)


def _smooth(y: np.ndarray, k: int) -> np.ndarray:
    if k <= 1 or len(y) < k:
        return y
    ker = np.ones(k) / k
    pad = np.concatenate([np.full(k // 2, y[0]), y, np.full(k - 1 - k // 2, y[-1])])
    return np.convolve(pad, ker, mode="valid")


def summarize(samples: list[BiaxialSample], marks, n_grains: int, case: BiaxialCase,
              radii: np.ndarray, smooth_strain: float = 0.005) -> BiaxialResult:
    """Peak and critical-state friction angles, strains, dilatancy and band angle; the
    stresses are smoothed over ``smooth_strain`` of axial strain before the peak is read."""
    eps = np.array([s.eps_axial for s in samples])
    s1 = np.array([s.sigma_1 for s in samples])
    s3 = np.array([s.sigma_3 for s in samples])
    ev = np.array([s.eps_vol for s in samples])
    # smooth the stresses (impulse noise) before taking ratios
    k = max(1, int(round(smooth_strain / max(np.median(np.diff(eps)), 1e-12))))
    s1s, s3s = _smooth(s1, k), _smooth(s3, k)
    sphi = (s1s - s3s) / (s1s + s3s)
    phi = np.degrees(np.arcsin(np.clip(sphi, -1, 1)))
    ipk = int(np.argmax(phi))
    last = eps >= eps[-1] * 2.0 / 3.0
    sphi_cs = float(np.mean(((s1 - s3) / (s1 + s3))[last]))
    phi_cs = math.degrees(math.asin(sphi_cs))
    reach = np.nonzero(sphi >= 0.95 * sphi_cs)[0]
    eps_cs = float(eps[reach[0]]) if len(reach) else float("nan")
    # dilatancy: sin(psi) = -d eps_v / d gamma, gamma = eps_1 - eps_3 (2D, eps_v = eps_1 + eps_3)
    e3 = ev - eps
    gam = eps - e3
    psi = _dilatancy_deg(gam[last], ev[last])
    psi_peak = _dilatancy_deg(gam, ev, np.abs(eps - eps[ipk]) <= smooth_strain)
    window = band_window(marks)
    band = float("nan") if window is None else shear_band_angle(*window, cell=band_cell(case))
    return BiaxialResult(phi_peak_deg=float(phi[ipk]), eps_peak=float(eps[ipk]), phi_cs_deg=phi_cs,
                         eps_cs=eps_cs, band_angle_deg=band,
                         phi_from_band_deg=2.0 * (band - 45.0) if math.isfinite(band) and band >= 45.0 else float("nan"),
                         solid_fraction_0=samples[0].solid_fraction, n_grains=n_grains,
                         dilatancy_deg=psi, confining=case.confining, friction=case.friction,
                         dilatancy_peak_deg=psi_peak)


def _dilatancy_deg(gamma: np.ndarray, eps_vol: np.ndarray, where: np.ndarray | None = None) -> float:
    """Dilatancy angle [deg] from sin(psi) = -d eps_v / d gamma (2D: gamma = eps_1 - eps_3,
    eps_v = eps_1 + eps_3, compression positive), the least-squares rate over the samples
    ``where`` selects (all by default); NaN with fewer than four."""
    if where is not None:
        gamma, eps_vol = gamma[where], eps_vol[where]
    if len(gamma) <= 3:
        return float("nan")
    return math.degrees(math.asin(float(np.clip(-_slope(gamma, eps_vol), -1, 1))))


def band_window(marks) -> tuple[np.ndarray, np.ndarray] | None:
    """The grain positions (start, end) the shear band is read between: the post-peak
    part of the test, from the mark at 40 % of the final strain to the last (None with
    fewer than 5 marks). ``marks``: (axial strain, positions (n,2)) at each tenth."""
    if len(marks) < 5:
        return None
    return marks[len(marks) * 2 // 5][1], marks[-1][1]


def band_cell(case: BiaxialCase) -> float:
    """The cell of the strain map the band is read on [m]: three median grains."""
    return 3 * case.grading.d50


def strain_field(x0: np.ndarray, x1: np.ndarray, cell: float):
    """Incremental deviatoric (maximum shear) strain on a square grid of ``cell`` [m]
    from grain displacements x1 - x0: in each cell a least-squares affine fit
    u = G x + c over the grains inside (at least 6); gamma = sqrt(((G00 - G11)/2)^2 +
    ((G01 + G10)/2)^2). Returns (cell centres (k,2), gamma (k,))."""
    u = x1 - x0
    lo = x0.min(0)
    ij = np.floor((x0 - lo) / cell).astype(int)
    nx, ny = ij.max(0) + 1
    key = ij[:, 0] * ny + ij[:, 1]
    order = np.argsort(key, kind="stable")
    key_s = key[order]
    starts = np.searchsorted(key_s, np.arange(nx * ny))
    ends = np.searchsorted(key_s, np.arange(nx * ny), side="right")
    centres, gam = [], []
    for c in range(nx * ny):
        idx = order[starts[c]:ends[c]]
        if len(idx) < 6:
            continue
        X = np.column_stack([x0[idx] - x0[idx].mean(0), np.ones(len(idx))])
        G, *_ = np.linalg.lstsq(X, u[idx], rcond=None)
        g = G[:2].T  # du_i/dx_j
        e = 0.5 * (g + g.T)
        gam.append(math.hypot((e[0, 0] - e[1, 1]) / 2.0, e[0, 1]))
        centres.append(x0[idx].mean(0))
    return np.array(centres), np.array(gam)


def _slope(x: np.ndarray, y: np.ndarray) -> float:
    """Least-squares slope of y on x, sum((x - mean x)(y - mean y)) / sum((x - mean x)^2),
    in numpy's own sums: np.polyfit's LAPACK call ends in other last bits with the
    OpenBLAS of another numpy release (2.4 vs 2.5), which the pins would see."""
    dx = x - np.mean(x)
    return float(np.sum(dx * (y - np.mean(y))) / np.sum(dx * dx))


def shear_band_angle(x0: np.ndarray, x1: np.ndarray, cell: float) -> float:
    """Angle [deg] between the dominant shear band and the horizontal (the major
    principal plane when sigma_1 is vertical), from 0 to 90.

    Cells within 1.5 cells of the specimen's edge are left out (wall effects). A
    discrete Radon transform of the incremental shear-strain map: for each trial
    band direction theta, cells are binned by their distance from a line of that
    direction (bins of one cell); the direction whose best bin collects the largest mean
    strain is the band. Both inclinations (+theta, 180 - theta) are tried."""
    c, g = strain_field(x0, x1, cell)
    if len(g) < 10:     # too few cells of 6 grains (a small specimen)
        return float("nan")
    # leave out a band of 1.5 cells along the walls (platen and piston effects)
    lo, hi = x0.min(0) + 1.5 * cell, x0.max(0) - 1.5 * cell
    inner = np.all((c >= lo) & (c <= hi), axis=1)
    c, g = c[inner], g[inner]
    if len(g) < 10:
        return float("nan")
    w = g - np.median(g)
    w = np.clip(w, 0, None)
    best, best_t = -1.0, float("nan")
    for t in np.arange(1.0, 180.0, 1.0):
        th = math.radians(t)
        nrm = np.array([-math.sin(th), math.cos(th)])
        s = c @ nrm
        b = np.floor((s - s.min()) / cell).astype(int)
        sums = np.bincount(b, weights=w)
        cnt = np.bincount(b)
        ok = cnt >= max(3, 0.3 * cnt.max())
        if not np.any(ok):
            continue
        val = float((sums[ok] / cnt[ok]).max())
        if val > best:
            best, best_t = val, t
    a = best_t if best_t <= 90 else 180.0 - best_t
    return float(a)
