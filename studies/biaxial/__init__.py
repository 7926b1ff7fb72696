"""Khosravi et al.'s biaxial test (section 2) on dem2d: phi per particle friction and the
friction that gives a target phi, written to a calibration card (``cards/`` holds the
committed ones the Khosravi study looks phi up in). The study record is ``STUDY``."""

from __future__ import annotations

import math
from types import SimpleNamespace

from analytic.inputs import MAX_PRESSURE_KPA

from ..options import VTK, kpa_to_pa, number, number_list, output_file
from ..study import Command, Option, Study


def _default_plan():
    from .calibrate import CalibrationPlan
    return CalibrationPlan()


def _calibrate(plan, opts: SimpleNamespace) -> tuple[dict, str]:
    from .calibrate import calibrate
    result, rf = calibrate(plan, root=opts.out, quiet=opts.quiet, card=opts.card)
    return result, f"run folder: {rf.path}"


def _text(result: dict):
    from rich.console import Group
    from rich.table import Table

    t = Table(title=f"Biaxial calibration (target phi {result['target_phi_deg']:g} deg)", title_justify="left")
    for col in ("friction", "sigma_3 kPa", "phi peak", "eps peak", "phi cs", "eps to cs", "band deg", "n", "grains"):
        t.add_column(col, justify="right")
    for r in result["tests"]:
        t.add_row(f"{r['friction']:.3f}", f"{r['confining'] / 1e3:g}", f"{r['phi_peak_deg']:.2f}",
                  f"{r['eps_peak']:.4f}", f"{r['phi_cs_deg']:.2f}", f"{r['eps_cs']:.4f}",
                  f"{r['band_angle_deg']:.0f}", f"{1 - r['solid_fraction_0']:.3f}", str(r["n_grains"]))
    return Group(t, _calibrated_line(result))


def _calibrated_line(result: dict) -> str:
    """The calibrated friction, or why there is none (phi of every test below or above
    the target: interpolation needs two tests that bracket it)."""
    mu, target = result["calibrated_friction"], result["target_phi_deg"]
    if mu is not None and math.isfinite(mu):
        return f"calibrated friction for phi = {target:g} deg: {mu:.4f}"
    phis = [t["phi_cs_deg"] for t in result["tests"]]
    return (f"no calibrated friction: the critical-state phi of the tests ({min(phis):.2f}-{max(phis):.2f} deg) "
            f"does not bracket {target:g} deg; test frictions on both sides of it")


CALIBRATE = Command(
    verb="calibrate", help="biaxial tests over frictions; the friction giving a target phi",
    description="Khosravi et al. section 2: 70 x 200 mm specimen, servo lateral stress, axial compression. "
                "Example: wallsim calibrate biaxial --friction 0.3,0.5,0.7 --pressures 2,3,5 --particles-scale 2",
    default_case=_default_plan, run=_calibrate, text=_text, seed_key="case.seed",
    options=(
        Option("--friction", "particle friction coefficients to test (0.3,0.5,0.7)", key="frictions"),
        Option("--confining", "confining stress for the friction sweep [kPa] (4)", key="case.confining",
               parse=number("confining", 0, MAX_PRESSURE_KPA, hi_open=False, unit="kPa"), to_case=kpa_to_pa),
        Option("--pressures", "extra confining stresses [kPa] at the calibrated friction, e.g. 2,3,5 (none)",
               key="pressures", parse=number_list("pressures", lo=0.0, hi=MAX_PRESSURE_KPA, unit="kPa"),
               to_case=lambda kpa: tuple(map(kpa_to_pa, kpa))),
        Option("--target-phi", "friction angle to calibrate for [deg] (20.7)", key="target_phi"),
        Option("--particles-scale", "multiply every grain diameter (1 = D50 1.16 mm, ~12.7k disks) (1)",
               key="case.particles_scale"),
        Option("--card", "also write the calibration card here", metavar="FILE.json",
               parse=output_file("card", (".json",))),
        VTK,
    ))

STUDY = Study(name="biaxial", title="Biaxial test of the Khosravi backfill (friction for a target phi)",
              commands=(CALIBRATE,))
