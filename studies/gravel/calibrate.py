"""``wallsim calibrate gravel``: the case-B gravel's local frictions from its global targets.

S-OET (docs/reference/drystone-walls.md 3.1) tuned two local values for PFC's soft
clump contacts: grain-grain 45 deg (biaxial peak 37.7 deg at 35 kPa, Colas's triaxial)
and grain-block 25 deg (global 37.7 deg in a constant-normal-load shear test). They do
not carry over to rigid capsules, so both are recalibrated against the same
*global* targets:

1. biaxial series (``studies.elements.gravel_biaxial``): peak and critical-state angle against the
   local grain friction; ours is the local value nearest to *both* targets, peak 37.7 deg
   and critical state 32 deg (Colas's angle of repose, S-OET's stand-in): the least
   squares of the two misfits [deg] on the seed means, linear between tested values
   (``choose_both``). The peak alone chose 72.8 deg for capsules, whose critical state
   was then 25 deg and could not hold the 32-deg re-cut slope of case B
   (gravel_calibration_discussion.md). The peak-only value is reported beside;
2. interface series (``studies.elements.interface``, the grains at our grain friction): global
   interface angle against the local fill-block friction; ours is the local value whose
   global angle is 37.7 deg. On a flat face tan(global) <= mu_local (Coulomb), so the
   local value cannot be below the target.

The run folder holds both series (CSV, PNG, result.json); ``--docs DIR`` also writes
``DIR/gravel_calibration.{md,json}`` and its figures in ``DIR/gravel_calibration/``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import Literal

import numpy as np

from analytic.errors import InvalidParameter
from analytic.schema import MAX_SEED, check_fields, param
from dem2d.blocks import BlockSolver
from dem2d.gravel import Gravel
from studies.elements.gravel_biaxial import GravelBiaxialCase
from studies.runner import test_recording
from studies.elements.interface import ShearCase

TESTS = ("both", "biaxial", "interface")
#: S-OET's local values (PFC2D soft clumps) and the global targets (Colas; S-OET 4.1)
PAPER_GRAIN_FRICTION_DEG, PAPER_INTERFACE_FRICTION_DEG = 45.0, 25.0
TARGET_PEAK_DEG, TARGET_CRITICAL_DEG, TARGET_INTERFACE_DEG = 37.7, 32.0, 37.7


@dataclass(frozen=True)
class GravelCalibration:
    """What ``calibrate gravel`` runs: the biaxial and interface series and their targets.
    ``biaxial`` and ``shear`` take their grains from ``gravel`` with each test's frictions
    (leave their own ``gravel`` at its default)."""

    tests: Literal["both", "biaxial", "interface"] = param(
        "both", unit="", meaning="which series to run: both, biaxial (grain friction) or interface (fill-block)")
    frictions_deg: tuple[float, ...] = param(
        (35.0, 40.0, 45.0, 50.0, 55.0), unit="deg", lo=0, hi=89,
        meaning="local grain frictions of the biaxial series, one test per friction and seed")
    seeds: tuple[int, ...] = param(
        (1, 2), lo=0, hi=MAX_SEED,
        meaning="random seeds of the specimens, one biaxial and one interface test per seed and friction")
    interface_frictions_deg: tuple[float, ...] = param(
        (37.7, 45.0, 60.0, 75.0, 89.0), unit="deg", lo=0, hi=89,
        meaning="local fill-block frictions of the interface series, one test per friction and seed")
    grain_friction_deg: float | None = param(
        None, unit="deg", lo=0, hi=89,
        meaning="grain friction of the interface series; none: the biaxial series' choice (else gravel's)")
    target_peak_deg: float = param(TARGET_PEAK_DEG, unit="deg", lo=0, hi=90, lo_open=True, hi_open=True,
                                   meaning="global biaxial peak friction angle to reach (Colas: 37.7)")
    target_critical_deg: float = param(TARGET_CRITICAL_DEG, unit="deg", lo=0, hi=90, lo_open=True, hi_open=True,
                                       meaning="global critical-state friction angle to reach (Colas: about 32)")
    target_interface_deg: float = param(TARGET_INTERFACE_DEG, unit="deg", lo=0, hi=90, lo_open=True, hi_open=True,
                                        meaning="global interface friction angle to reach (Colas: 37.7)")
    # rounded hexagon: the one shape near both biaxial targets (gravel_shape_probe.json)
    gravel: Gravel = Gravel(placement_friction_deg=45.0, shape="hexagon")
    biaxial: GravelBiaxialCase = GravelBiaxialCase(width=0.7, height=1.4)
    shear: ShearCase = ShearCase(speed_m_s=5e-3, displacement_m=0.02, solver=BlockSolver(dt=5e-4, iterations=40))

    def __post_init__(self):
        check_fields(self)
        for name in ("biaxial", "shear"):
            if getattr(self, name).gravel != Gravel():
                raise InvalidParameter(f"{name}.gravel", "set", "its default", "set the grains through gravel.*")

    @property
    def seed(self) -> int:
        return self.seeds[0]


def choose(xs, ys, target: float) -> dict:
    """The local value for a global ``target``: interpolated where two tests bracket it
    (``reached``), else the tested value whose global angle is closest (not reached)."""
    x = interpolate(xs, ys, target)
    if math.isfinite(x):        # to 0.1 deg: the seeds scatter by several tenths
        return {"value_deg": round(x, 1), "reached": True}
    k = int(np.argmin(np.abs(np.asarray(ys, float) - target)))
    return {"value_deg": float(xs[k]), "reached": False, "closest_global_deg": float(ys[k])}


def choose_both(xs, peaks, criticals, target_peak: float, target_critical: float, step: float = 0.1) -> dict:
    """The local value nearest to both biaxial targets: the minimum over ``xs``'s range
    (``step`` [deg]) of (peak - target_peak)^2 + (critical - target_critical)^2, both
    curves linear between the tested values (equal weights: both are angles of the same
    test, and neither is measured better than a degree). Also the misfits there."""
    order = np.argsort(xs)
    x, p, c = (np.asarray(v, float)[order] for v in (xs, peaks, criticals))
    grid = np.round(np.arange(x[0], x[-1] + step / 2, step), 6)
    pg, cg = np.interp(grid, x, p), np.interp(grid, x, c)
    k = int(np.argmin((pg - target_peak) ** 2 + (cg - target_critical) ** 2))
    return {"value_deg": round(float(grid[k]), 1), "reached": bool(abs(pg[k] - target_peak) < 0.5
                                                                  and abs(cg[k] - target_critical) < 0.5),
            "phi_peak_deg": float(pg[k]), "phi_cs_deg": float(cg[k]),
            "rule": "least squares of the peak and critical-state misfits"}


def interpolate(xs, ys, target: float) -> float:
    """x where y(x) = target, linear between the first two neighbouring points (sorted by
    x) that bracket it; NaN when none do."""
    pts = sorted(zip(xs, ys))
    for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
        if (y0 - target) * (y1 - target) <= 0 and y1 != y0:
            return float(x0 + (target - y0) * (x1 - x0) / (y1 - y0))
    return math.nan


def biaxial_test(plan: GravelCalibration, friction_deg: float, seed: int, tick=None, on_frame=None) -> dict:
    """One biaxial test at local grain friction ``friction_deg``: the summary, porosity
    (whole specimen and inner window) and the curves. ``on_frame(frame)``: the specimen
    when compacted and at every tenth of the shear strain."""
    from studies.elements.gravel_biaxial import GravelBiaxialTest

    case = dataclasses.replace(plan.biaxial, seed=seed,
                               gravel=dataclasses.replace(plan.gravel, friction_deg=friction_deg))
    t0, c0 = time.perf_counter(), time.process_time()
    test = GravelBiaxialTest(case)
    for _ in test.prepare(max_time=4.0):
        pass
    inner = test.inner_porosity()
    marks = [m * case.max_strain / 10 for m in range(1, 11)]
    if on_frame is not None:
        on_frame(test.sim.frame())
    for s in test.shear():
        if tick:
            tick(s.eps_axial / case.max_strain)
        if on_frame is not None and marks and s.eps_axial >= marks[0]:
            on_frame(test.sim.frame())
            while marks and s.eps_axial >= marks[0]:
                marks.pop(0)
    r = test.result()
    return {"friction_deg": friction_deg, "seed": seed, "phi_peak_deg": r.phi_peak_deg, "eps_peak": r.eps_peak,
            "phi_cs_deg": r.phi_cs_deg, "dilatancy_deg": r.dilatancy_deg,
            "dilatancy_peak_deg": r.dilatancy_peak_deg, "porosity": 1 - r.solid_fraction_0,
            "inner_porosity": inner, "n_grains": r.n_grains, "steps": test.sim.step_count,
            "inertial_number": case.inertial_number(), "wall_time_s": time.perf_counter() - t0,
            "cpu_time_s": time.process_time() - c0,
            "curve": {"eps_axial": [s.eps_axial for s in test.samples], "sigma_1": [s.sigma_1 for s in test.samples],
                      "sigma_3": [s.sigma_3 for s in test.samples], "eps_vol": [s.eps_vol for s in test.samples]}}


def interface_test(plan: GravelCalibration, grain_deg: float, local_deg: float, seed: int, recorder=None) -> dict:
    """One interface shear test: the global angle (forces averaged over the second half of
    the displacement: the angle is still rising at 6 mm in the full-size box) and the
    readings. ``recorder``: the box's grains, face and lid after every reading (--vtk)."""
    from studies.elements.interface import InterfaceShear

    g = dataclasses.replace(plan.gravel, friction_deg=grain_deg, interface_friction_deg=local_deg)
    case = dataclasses.replace(plan.shear, gravel=g, seed=seed)
    t0, c0 = time.perf_counter(), time.process_time()
    box = InterfaceShear(case).build()
    def on_reading(b):
        recorder.log_polygons(b.steps, b.steps * case.solver.dt, b.outlines(), kind="grains")
    readings = box.shear(readings=20, on_reading=on_reading if recorder is not None else None)
    late = [r for r in readings if r.displacement > case.displacement_m / 2 + 1e-12]
    T, N = float(np.mean([r.shear for r in late])), float(np.mean([r.normal for r in late]))
    return {"interface_friction_deg": local_deg, "grain_friction_deg": grain_deg, "seed": seed,
            "global_angle_deg": math.degrees(math.atan2(abs(T), N)), "normal_N_m": N,
            "applied_normal_N_m": box.applied_normal(), "n_grains": len(box.bodies), "steps": box.steps,
            "wall_time_s": time.perf_counter() - t0, "cpu_time_s": time.process_time() - c0,
            "readings": [r._asdict() for r in readings]}


def biaxial_summary(tests: list[dict], target: float, target_critical: float = TARGET_CRITICAL_DEG) -> dict:
    """Per friction: seed means of peak, critical state, porosity; the chosen friction
    (``choose_both``) and, beside it, the one the peak alone would give."""
    rows = []
    for mu in sorted({t["friction_deg"] for t in tests}):
        ts = [t for t in tests if t["friction_deg"] == mu]
        rows.append({"friction_deg": mu, "seeds": [t["seed"] for t in ts],
                     **{k: float(np.mean([t[k] for t in ts])) for k in
                        ("phi_peak_deg", "phi_cs_deg", "dilatancy_deg", "dilatancy_peak_deg", "porosity",
                         "inner_porosity")},
                     "phi_peak_sd_deg": float(np.std([t["phi_peak_deg"] for t in ts])),
                     "phi_cs_sd_deg": float(np.std([t["phi_cs_deg"] for t in ts]))})
    mus = [r["friction_deg"] for r in rows]
    pick = choose_both(mus, [r["phi_peak_deg"] for r in rows], [r["phi_cs_deg"] for r in rows], target,
                       target_critical)
    chosen = pick["value_deg"]
    return {"rows": rows, "grain_friction_deg": chosen, "choice": pick, "phi_peak_at_chosen_deg": pick["phi_peak_deg"],
            "phi_cs_at_chosen_deg": pick["phi_cs_deg"],
            "peak_only": choose(mus, [r["phi_peak_deg"] for r in rows], target)}


def run_calibration(plan: GravelCalibration, bar=None, folder=None) -> dict:
    """Both series (as ``plan.tests`` asks); the result without files (with ``folder``, a
    run started with --vtk, each test's frames in vtk/<test>/)."""
    out = {"grain_shape": plan.gravel.shape,
           "paper_local": {"grain_friction_deg": PAPER_GRAIN_FRICTION_DEG,
                           "interface_friction_deg": PAPER_INTERFACE_FRICTION_DEG},
           "targets": {"phi_peak_deg": plan.target_peak_deg, "phi_cs_deg": plan.target_critical_deg,
                       "interface_angle_deg": plan.target_interface_deg}}
    grain = plan.grain_friction_deg
    if plan.tests in ("both", "biaxial"):
        tests = []
        for mu in plan.frictions_deg:
            for seed in plan.seeds:
                with test_recording(folder, study="gravel", label=f"biaxial-{mu:g}deg-seed{seed}") as rec:
                    tests.append(biaxial_test(plan, mu, seed, _tick(bar, f"biaxial {mu:g} deg seed {seed}"),
                                              on_frame=rec.log_frame if rec is not None else None))
        out["biaxial"] = {"tests": tests, **biaxial_summary(tests, plan.target_peak_deg, plan.target_critical_deg)}
        if grain is None:
            grain = out["biaxial"]["grain_friction_deg"]
    if plan.tests in ("both", "interface"):
        grain = plan.gravel.friction_deg if grain is None else grain
        out["interface"] = _interface_series(plan, grain, bar, folder)
    return out


def _interface_series(plan: GravelCalibration, grain: float, bar, folder=None) -> dict:
    """Every local fill-block friction on every seed; per friction the seed mean and sd of
    the global angle; the chosen local value (``choose`` on the means)."""
    tests = []
    for mu in plan.interface_frictions_deg:
        for seed in plan.seeds:
            tick = _tick(bar, f"interface {mu:g} deg seed {seed}")
            with test_recording(folder, study="gravel", label=f"interface-{mu:g}deg-seed{seed}") as rec:
                tests.append(interface_test(plan, grain, mu, seed, recorder=rec))
            if tick:
                tick(1.0)
    rows = []
    for mu in plan.interface_frictions_deg:
        g = [t["global_angle_deg"] for t in tests if t["interface_friction_deg"] == mu]
        rows.append({"interface_friction_deg": mu, "global_angle_deg": float(np.mean(g)),
                     "global_angle_sd_deg": float(np.std(g)), "seeds": list(plan.seeds)})
    pick = choose([r["interface_friction_deg"] for r in rows], [r["global_angle_deg"] for r in rows],
                  plan.target_interface_deg)
    return {"tests": tests, "rows": rows, "grain_friction_deg": grain, "interface_friction_deg": pick["value_deg"],
            "choice": pick}


def _tick(bar, label: str):
    if bar is None:
        return None
    task = bar.add_task(label, total=100)
    return lambda frac: bar.update(task, completed=100 * min(frac, 1.0))
