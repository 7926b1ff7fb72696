"""``wallsim calibrate biaxial``: biaxial tests over frictions and confining pressures,
the friction that gives a target phi, and a calibration card other runs reuse.

The card (JSON) holds, for each test, the friction, the confining stress, phi at peak
and at critical state, the strains, the band angle, porosity and grain count; and the
calibrated friction for the target phi (linear interpolation of phi_cs in mu between
the two bracketing tests). ``phi_for_friction`` reads a card back for the Khosravi run.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence


from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param
from studies.elements.biaxial import MAX_CONFINING_PA, MAX_FRICTION, BiaxialCase, BiaxialTest
from dem2d.params import Solver
from studies.progress import progress
from studies.runfolder import RunFolder
from studies.runner import finish, open_run_folder, test_recording
from studies.store import atomic_write, to_plain
from studies.store import find_card_entry

#: the card committed with the validation report
DEFAULT_CARD = Path(__file__).resolve().parent / "cards" / "biaxial.json"
#: the cards a Khosravi run looks in: coarse grains (particles_scale 2), and full size at
#: 10 sweeps a step (the first calibration), at 40, and at 80 (the Khosravi readings')
DEFAULT_CARDS = (DEFAULT_CARD, DEFAULT_CARD.with_name("biaxial_full.json"),
                 DEFAULT_CARD.with_name("biaxial_full_it40.json"), DEFAULT_CARD.with_name("biaxial_full_it80.json"))


@dataclass(frozen=True)
class CalibrationPlan:
    """What ``calibrate biaxial`` runs: a friction series, then a pressure series."""

    frictions: tuple[float, ...] = param((0.3, 0.5, 0.7), lo=0, hi=MAX_FRICTION,
                                         meaning="particle friction coefficients to test at case.confining, one "
                                                 "biaxial test each")
    pressures: tuple[float, ...] = param((), unit="Pa", lo=0, hi=MAX_CONFINING_PA, lo_open=True, may_be_empty=True,
                                         meaning="extra confining stresses tested at the calibrated friction "
                                                 "(none by default)")
    target_phi: float = param(20.7, unit="deg", lo=0, hi=90, lo_open=True, hi_open=True,
                              meaning="friction angle the calibration aims at (Khosravi Table 1: 20.7)")
    # the biaxial test (its friction/confining are overridden per test)
    case: BiaxialCase = field(default_factory=BiaxialCase)

    def __post_init__(self):
        check_fields(self)
        # a test is ~10 min at the paper's grain size (12.7k disks, 80 sweeps): 100 are ~17 h
        if len(self.frictions) + len(self.pressures) > 100:
            raise InvalidParameter("frictions", f"{len(self.frictions)} values",
                                   f"a list of at most {100 - len(self.pressures)} values",
                                   "at most 100 tests with the pressures, ~10 min a test at the paper's grain size")


def run_one(case: BiaxialCase, bar=None, label: str = "", on_frame=None) -> tuple[dict, BiaxialTest, float]:
    """One biaxial test; returns (summary dict with the curves, the test, wall time [s]).
    ``on_frame(frame)``: the specimen when compacted and at every tenth of the shear strain."""
    t0 = time.perf_counter()
    test = BiaxialTest(case)
    task = bar.add_task(f"biaxial {label} compact", total=None, status="") if bar else None
    for s in test.prepare():
        if bar:
            bar.update(task, status=f"sigma1 {s.sigma_1 / 1e3:.2f} sigma3 {s.sigma_3 / 1e3:.2f} kPa")
    if bar:
        bar.update(task, description=f"biaxial {label} shear", total=case.max_strain * 1e4, completed=0)
    marks = [m * case.max_strain / 10 for m in range(1, 11)]
    if on_frame is not None:
        on_frame(test.sim.frame())
    for s in test.shear():
        if bar:
            bar.update(task, completed=s.eps_axial * 1e4, status=f"phi {s.phi_mob:.1f} deg")
        if on_frame is not None and marks and s.eps_axial >= marks[0]:
            on_frame(test.sim.frame())
            while marks and s.eps_axial >= marks[0]:
                marks.pop(0)
    res = test.result()
    wall = time.perf_counter() - t0
    out = {**dataclasses.asdict(res),
           "dt": case.solver.dt, "iterations": case.solver.iterations, "seed": case.seed,
           "strain_rate": case.strain_rate, "inertial_number": case.inertial_number(),
           "prep_friction": case.prep_friction, "particles_scale": case.particles_scale,
           "wall_time_s": wall,
           "curve": {"eps_axial": [s.eps_axial for s in test.samples],
                     "sigma_1": [s.sigma_1 for s in test.samples],
                     "sigma_3": [s.sigma_3 for s in test.samples],
                     "eps_vol": [s.eps_vol for s in test.samples]}}
    return out, test, wall


def interpolate_friction(tests: list[dict], target_phi: float, key: str = "phi_cs_deg") -> float:
    """Friction giving ``target_phi`` by linear interpolation of phi(mu) between the two
    tests that bracket it (nan when the tests do not bracket it)."""
    pts = sorted((t["friction"], t[key]) for t in tests)
    for (m0, p0), (m1, p1) in zip(pts, pts[1:]):
        if (p0 - target_phi) * (p1 - target_phi) <= 0 and p1 != p0:
            return float(m0 + (target_phi - p0) * (m1 - m0) / (p1 - p0))
    return float("nan")


def calibrate(plan: CalibrationPlan, *, root: str | Path = "runs", quiet: bool = False,
              card: str | Path | None = None) -> tuple[dict, RunFolder]:
    """Run the plan, write the run folder (config, CSV, PNG, card, manifest); also write
    the card to ``card`` if given. Returns (card dict, run folder)."""
    import viz.figures  # noqa: F401  (here, as before: a missing plotting stack fails before the tests run)

    rf = open_run_folder("biaxial", plan, root, seed=plan.case.seed)
    tests = []

    def save_card(mu_cal):  # after every test, so other runs can use finished tests
        if card is not None:
            Path(card).parent.mkdir(parents=True, exist_ok=True)
            atomic_write(card, (json.dumps(to_plain(_card(plan, tests, rf, mu_cal)), indent=2) + "\n").encode())

    with progress(quiet) as bar:
        mu_cal = _run_tests(plan, tests, bar, save_card, rf)
    _write_curves(rf, tests)
    result = _card(plan, tests, rf, mu_cal)
    result["calibrated_friction_peak"] = interpolate_friction(tests[:len(plan.frictions)], plan.target_phi,
                                                              key="phi_peak_deg")
    finished_card = to_plain(result)          # the card holds the tests, not this run's resources
    finish(rf, result, n_grains=[t["n_grains"] for t in tests], dt=plan.case.solver.dt,
           iterations=plan.case.solver.iterations, frictions=list(plan.frictions))
    if card is not None:
        atomic_write(card, (json.dumps(finished_card, indent=2) + "\n").encode())
        import shutil
        shutil.copy(rf.file("biaxial.png"), Path(card).with_suffix(".png"))
    return result, rf


def _card(plan: CalibrationPlan, tests: list[dict], rf: RunFolder, mu_cal: float) -> dict:
    """The calibration card so far: target phi [deg], calibrated friction (nan until the
    friction series is done), the tests without their curves, grading, run folder."""
    return {"target_phi_deg": plan.target_phi, "calibrated_friction": mu_cal,
            "source": "wallsim dem2d biaxial test (dem2d/biaxial.py), Khosravi et al. section 2",
            "tests": [{k: v for k, v in t.items() if k != "curve"} for t in tests],
            "grading": {"d50_m": plan.case.grading.d50, "cu": plan.case.cu},
            "run_folder": str(rf.path)}


def _run_tests(plan: CalibrationPlan, tests: list[dict], bar, save_card, folder=None) -> float:
    """The friction series at the plan's confining stress, then the pressure series at
    the calibrated friction; each test is appended to ``tests`` and ``save_card`` called
    after it; with ``folder`` (a run started with --vtk) each test's frames go to
    vtk/<test>/. Returns the calibrated friction (nan when the series does not bracket
    the target phi)."""
    def one(case, label: str, part: str) -> None:
        with test_recording(folder, study="biaxial", label=part) as rec:
            out, test, _ = run_one(case, bar, label, rec.log_frame if rec is not None else None)
        if folder is not None:
            from .figures import plot_shear_band
            plot_shear_band(test, case, out["band_angle_deg"], folder.file(f"band_{part}.png"))
        tests.append(out)

    for mu in plan.frictions:
        one(dataclasses.replace(plan.case, friction=float(mu)), f"mu={mu:g}", f"mu{mu:g}")
        save_card(float("nan"))
    mu_cal = interpolate_friction(tests, plan.target_phi)
    if not math.isfinite(mu_cal):
        # phi(mu) does not reach the target (free disks saturate): the pressure series
        # is run at the friction whose phi is closest to it instead
        mu_near = min(tests, key=lambda t: abs(t["phi_cs_deg"] - plan.target_phi))["friction"]
    else:
        mu_near = mu_cal
    for p in plan.pressures:
        one(dataclasses.replace(plan.case, friction=mu_near, confining=float(p)),
            f"mu={mu_near:.3f} p={p / 1e3:g}kPa", f"mu{mu_near:.3f}-p{p / 1e3:g}kPa")
        save_card(mu_cal)
    return mu_cal


def _write_curves(rf: RunFolder, tests: list[dict]) -> None:
    """Every test's stress-strain curve to ``biaxial_curves.csv`` (stresses in kPa) and
    ``biaxial.png`` in the run folder."""
    from viz.figures import plot_shear_test

    rows = []
    for t in tests:
        c = t["curve"]
        for e, s1, s3, ev in zip(c["eps_axial"], c["sigma_1"], c["sigma_3"], c["eps_vol"]):
            rows.append([t["friction"], t["confining"] / 1e3, e, s1 / 1e3, s3 / 1e3, ev])
    rf.write_csv("biaxial_curves.csv", ["friction", "confining_kPa", "eps_axial", "sigma_1_kPa",
                                        "sigma_3_kPa", "eps_vol"], rows)
    plot_shear_test({f"mu={t['friction']:.3g}, {t['confining'] / 1e3:g} kPa":
                  (t["curve"]["eps_axial"], t["curve"]["sigma_1"], t["curve"]["sigma_3"], t["curve"]["eps_vol"])
                  for t in tests}, rf.file("biaxial.png"),
                 title="Biaxial tests (Khosravi Fig. 4 style)")


def phi_for_friction(friction: float, cards: str | Path | Sequence[str | Path] = DEFAULT_CARDS,
                     confining: float = 4000.0, particles_scale: float = 1.0,
                     solver: Solver | None = None) -> dict | None:
    """The first test at this friction, confining stress and grain scale (each within
    1e-6), and when ``solver`` is given at its dt and iterations, in ``cards`` (one card
    or several, searched in order; missing files are skipped), with ``"card"`` set to
    the file it came from; None if no card has one.
    The grain scale matters: phi of free disks in a 70 mm wide specimen depends on how
    many grains span it (docs/dem2d.md); so do the solver's sweeps per step (an
    unconverged impulse solver makes the assembly soft; docs/dem2d.md)."""
    def same_test(t: dict) -> bool:
        return (abs(t["friction"] - friction) < 1e-6 and abs(t["confining"] - confining) < 1e-6
                and abs(t.get("particles_scale", 1.0) - particles_scale) < 1e-6
                and (solver is None or (t.get("iterations") == solver.iterations
                                        and abs(t.get("dt", 0.0) - solver.dt) < 1e-12)))

    found = find_card_entry(cards, same_test)
    return None if found is None else {**found[0], "card": str(found[1])}
