"""The bonded-ball sheet pile's calibration (Sizkow & El Shamy, model scale): the
parallel-bond stiffness that gives a two-sheet strip of balls the flexural rigidity
E t^3 / 12, checked by a DEM cantilever against Euler-Bernoulli (tip deflection and
first frequency). Engine: ``dem3d.cantilever``; data:
../shared/reference/seismic-sheetpile.md (EI = 416.7 N m^2/m at model scale: E 40 GPa,
t 5 mm; the bond parameters are not published, so they are calibrated here)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace

from analytic.inputs import require_number

from ..options import number
from ..study import Command, Option, Study


@dataclass(frozen=True)
class CantileverCase:
    """youngs:            target Young's modulus E of the wall [Pa] (40 GPa, concrete-like)
    thickness:         wall thickness t at model scale [m] (5 mm = 0.25 m / N, N = 50)
    length:            cantilever length, clamped row to loaded row [m] (13.5 cm)
    density:           ball density [kg/m^3] (4000)
    layers:            sheets of balls across the thickness (2)
    radius_multiplier: bond radius / ball radius (1)
    shear_ratio:       bond kn / ks (1)
    """

    youngs: float = 40e9
    thickness: float = 5e-3
    length: float = 0.135
    density: float = 4000.0
    layers: int = 2
    radius_multiplier: float = 1.0
    shear_ratio: float = 1.0

    def __post_init__(self):
        for name in ("youngs", "thickness", "density", "radius_multiplier", "shear_ratio"):
            require_number(name, getattr(self, name), 0, None)
        require_number("length", self.length, 5 * self.thickness, None, lo_open=False, unit="m")
        require_number("layers", self.layers, 1, 8, lo_open=False, hi_open=False)


def _calibrate(case: CantileverCase, opts: SimpleNamespace) -> tuple[dict, str]:
    from dem3d.cantilever import cantilever_check

    from ..runner import Stopwatch, finish, open_run_folder

    clock = Stopwatch()
    folder = open_run_folder("cantilever", case, opts.out)
    r = cantilever_check(case.youngs, case.thickness, case.length, density=case.density, layers=case.layers,
                         radius_multiplier=case.radius_multiplier, shear_ratio=case.shear_ratio)
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
    options=(Option("--E", "Young's modulus [Pa] (4e10)", key="youngs",
                    parse=number("E", 0, None, unit="Pa")),
             Option("--thickness", "wall thickness [m] (0.005)", key="thickness", parse=number("thickness", 0, None)),
             Option("--length", "cantilever length [m] (0.135)", key="length", parse=number("length", 0, None))))

STUDY = Study(name="cantilever", title="Bonded-ball sheet pile: bond stiffness for a target EI (Sizkow & El Shamy)",
              commands=(CALIBRATE,))
