"""The bonded-ball sheet pile's calibration (Sizkow & El Shamy, model scale): the
parallel-bond stiffness that gives a two-sheet strip of balls the flexural rigidity
E t^3 / 12, checked by a DEM cantilever against Euler-Bernoulli (tip deflection and
first frequency). Engine: ``dem3d.cantilever``; data:
docs/reference/seismic-sheetpile.md (EI = 416.7 N m^2/m at model scale: E 40 GPa,
t 5 mm; the bond parameters are not published, so they are calibrated here)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace

from analytic.errors import InvalidParameter
from analytic.inputs import require_number
from analytic.schema import check_fields, param

from ..options import VTK
from ..study import Command, Option, Study


#: the longest check a case may ask for, in ball-steps (balls x time steps): ~6 days of one
#: core at the 4e6 particle-steps/s measured (110 balls x 469,136 steps in 11 s at the defaults)
MOST_BALL_STEPS = 2e12


@dataclass(frozen=True)
class CantileverCase:
    """The bonded strip and its cantilever check (Sizkow & El Shamy's wall at model scale)."""

    # 1e12 Pa: stiffer than any solid (diamond ~1.1e12)
    youngs: float = param(40e9, unit="Pa", lo=0, hi=1e12, lo_open=True,
                          meaning="target Young's modulus E of the wall (40 GPa, concrete-like)")
    # a thinner wall has smaller balls, more of them (below); 2 m leaves room for 5 thicknesses
    # in the longest strip
    thickness: float = param(5e-3, unit="m", lo=0, hi=2, lo_open=True,
                             meaning="wall thickness t at model scale (5 mm = 0.25 m / N, N = 50)")
    # the strip is layers x (length / (2 r) + 1) balls, r = thickness / (2 layers), and a
    # period of the beam lasts ~40 layers (length / thickness)^2 time steps (both measured),
    # so the time grows as (length / thickness)^3: --length 1e6 asked for 8e8 balls (24 GB,
    # killed). 10 m is more than a prototype sheet pile (0.135 m x N = 50 = 6.75 m); the run's
    # length (MOST_BALL_STEPS) then bounds length / thickness (<= ~2 m at 5 mm)
    length: float = param(0.135, unit="m", lo=0, hi=10, lo_open=True,
                          meaning="cantilever length from the clamped row to the loaded row, at least 5 thicknesses "
                                  "(13.5 cm)")
    # 1e5 kg/m^3: denser than any solid (osmium 22,600)
    density: float = param(4000.0, unit="kg/m^3", lo=0, hi=1e5, lo_open=True, meaning="ball density (4000)")
    # each layer adds a sheet of balls along the whole length (balls ~ layers^2)
    layers: int = param(2, lo=1, hi=8, meaning="sheets of balls across the thickness (2)")
    radius_multiplier: float = param(1.0, lo=0, lo_open=True, meaning="bond radius over ball radius (1)")
    shear_ratio: float = param(1.0, lo=0, lo_open=True, meaning="bond normal over shear stiffness, kn / ks (1)")

    def __post_init__(self):
        check_fields(self)
        require_number("length", self.length, 5 * self.thickness, None, lo_open=False, unit="m")
        balls, steps = self.most_steps()
        work = balls * steps
        if work > MOST_BALL_STEPS:
            longest = self.length * (MOST_BALL_STEPS / work) ** (1.0 / 3.0)
            raise InvalidParameter("balls x time steps", work, f"<= {MOST_BALL_STEPS:g}",
                                   f"{balls} balls, up to {steps:.3g} steps, ~{work / 4e6 / 86400:.3g} days: a "
                                   f"length of at most ~{longest:.3g} m with this thickness and these bonds")

    def most_steps(self) -> tuple[int, float]:
        """(balls, time steps at most) of ``dem3d.cantilever.cantilever_check`` for this
        case, from its formulas and nothing allocated: layers x rows balls; the relaxation
        stops after at most 100 periods of the beam and 3.5 more are timed, at 0.2 x the
        bonds' critical step (``dem3d.bonds.bond_critical_step``)."""
        r = self.thickness / (2.0 * self.layers)
        rows = int(round(self.length / (2.0 * r))) + 1
        rb = self.radius_multiplier * r
        area, inertia = math.pi * rb**2, 0.25 * math.pi * rb**4
        ei_w = self.youngs * self.thickness**3 / 12.0
        kn = ei_w / sum(area * ((2 * k + 1 - self.layers) * r) ** 2 + inertia for k in range(self.layers))
        ks = kn / self.shear_ratio
        m = self.density * 4.0 / 3.0 * math.pi * r**3
        dt = 0.2 * min(math.sqrt(m / (max(kn, ks) * area)),
                       math.sqrt(0.4 * m * r**2 / max(kn * inertia, 2.0 * ks * inertia)))
        d = 2.0 * r
        frequency = 1.875**2 * math.sqrt(ei_w * d / (self.layers * m / d * ((rows - 1) * d) ** 4)) / (2.0 * math.pi)
        cycle = frequency * dt
        return self.layers * rows, 103.5 / cycle if cycle > 0 else math.inf


def _calibrate(case: CantileverCase, opts: SimpleNamespace) -> tuple[dict, str]:
    from dem3d.cantilever import cantilever_check

    from ..progress import progress
    from ..runner import Stopwatch, finish, open_recording, open_run_folder

    clock = Stopwatch()
    folder = open_run_folder("cantilever", case, opts.out)
    rec = open_recording(None, study="cantilever", recording_id=folder.path.name, dim=3, folder=folder)
    with progress(opts.quiet) as bar:
        tasks = {"relax": bar.add_task("loaded tip relaxing (chunks, stops when still)", total=400, status=""),
                 "vibrate": bar.add_task("free vibration (samples)", total=1, status="")}
        r = cantilever_check(case.youngs, case.thickness, case.length, density=case.density, layers=case.layers,
                             radius_multiplier=case.radius_multiplier, shear_ratio=case.shear_ratio,
                             progress=lambda stage, done, total: bar.update(tasks[stage], completed=done,
                                                                            total=total),
                             on_frame=rec.log_frame if rec.enabled else None)
    rec.close()
    result = {"case": "cantilever", "particles": r.n_spheres,
              "bond": {"kn_N_per_m3": r.bonds.kn, "ks_N_per_m3": r.bonds.ks, "radius_multiplier": r.bonds.radius_multiplier,
                       "ball_radius_m": r.bonds.ball_radius, "EI_per_width_N_m2_per_m": r.bonds.ei_per_width},
              "tip_deflection_m": r.tip_deflection, "beam_tip_deflection_m": r.beam_deflection,
              "tip_deflection_over_beam": r.tip_deflection_over_beam, "frequency_Hz": r.frequency,
              "beam_frequency_Hz": r.beam_frequency, "frequency_over_beam": r.frequency_over_beam,
              "provenance": {"particles": r.n_spheres, "steps": r.steps, "length_m": r.length, "load_N": r.load},
              "wall_time_s": clock.total, "run_folder": str(folder.path)}
    finish(folder, result, particles=r.n_spheres, steps=r.steps, wall_time_s=clock.total)
    return result, f"run folder: {folder.path}"


def _text(r: dict) -> str:
    b = r["bond"]
    return (f"bonded strip of {r['particles']} balls: bond kn {b['kn_N_per_m3']:.4g} N/m^3 gives EI "
            f"{b['EI_per_width_N_m2_per_m']:.4g} N m^2/m; tip deflection {r['tip_deflection_over_beam']:.4f} x "
            f"F L^3/(3 EI), first frequency {r['frequency_Hz']:.1f} Hz = {r['frequency_over_beam']:.3f} x beam theory")


CALIBRATE = Command(
    verb="calibrate", help="bond stiffness of the bonded-ball sheet pile, checked as a cantilever (3D)",
    description="Parallel bonds (Potyondy & Cundall 2004) calibrated so a two-sheet strip of balls has "
                "EI = E t^3 / 12; a DEM cantilever checks the tip deflection and first frequency against "
                "Euler-Bernoulli. Defaults: Sizkow & El Shamy's wall at model scale (E 40 GPa, t 5 mm, L 13.5 cm; "
                "about 30 s).",
    default_case=CantileverCase, run=_calibrate, text=_text, seed_key=None,
    options=(Option("--E", "Young's modulus [Pa] (4e10)", key="youngs"),
             Option("--thickness", "wall thickness [m] (0.005)", key="thickness"),
             Option("--length", "cantilever length [m] (0.135)", key="length"), VTK))

STUDY = Study(name="cantilever", title="Bonded-ball sheet pile: bond stiffness for a target EI (Sizkow & El Shamy)",
              commands=(CALIBRATE,))
