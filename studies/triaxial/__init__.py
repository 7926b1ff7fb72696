"""The numerical triaxial test of Nadukuru & Michalowski's backfill mixture (3D, dem3d):
peak and critical-state phi, written to a calibration card that ``compare nadukuru``
uses for its theories. The test itself is in ``lab``; the study record is ``STUDY``."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from analytic.inputs import MAX_PRESSURE_KPA

from ..options import VTK, kpa_to_pa, number
from ..study import Command, Option, Study


def _footprint(case):
    from ..runner import BASE_MEMORY, MEMORY_PER_SPHERE
    return "particles", case.specimen.particles, BASE_MEMORY + MEMORY_PER_SPHERE * case.specimen.particles


def _default_case():
    from .lab import TriaxialCase
    return TriaxialCase()


def _calibrate(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..progress import progress
    from ..runner import finish, open_recording, open_run_folder
    from .lab import calibrate_triaxial

    folder = open_run_folder("triaxial", case, opts.out)      # the card is shared; the run has its folder
    rec = open_recording(None, study="triaxial", recording_id=folder.path.name, dim=3, folder=folder)
    with progress(opts.quiet) as bar:
        card, path = calibrate_triaxial(case, case.setup, particles=case.specimen.particles, root=Path(opts.out),
                                        progress=bar, on_frame=rec.log_frame if rec.enabled else None)
    rec.close()
    result = dict(card) | {"card": str(path), "run_folder": str(folder.path)}
    finish(folder, result, particles=card.get("particles"), seed=case.seed)
    return result, f"calibration card: {path}\nrun folder: {folder.path}"


def _text(card: dict) -> str:
    return (f"triaxial: peak phi {card['phi_peak_deg']:.1f} deg at axial strain {card['strain_at_peak']:.3f}, "
            f"end (critical-state estimate) {card['phi_end_deg']:.1f} deg; porosity {card['porosity']:.3f}; "
            f"{card['particles']} spheres, seed {card['seed']}, {card['wall_time_s']:.0f} s (paper: 39 deg)")


CALIBRATE = Command(
    verb="calibrate", help="numerical triaxial test on the Nadukuru backfill mixture (3D)",
    description="Cubical triaxial test (six servo platens, sigma_2 = sigma_3) on the sphere/clump mixture; "
                "peak and critical-state phi, written to a calibration card that `compare nadukuru` uses for "
                "its theories.",
    default_case=_default_case, run=_calibrate, text=_text, busy_note=True, footprint=_footprint,
    options=(Option("--particles", "spheres (8200, the paper's)", key="specimen.particles"),
             Option("--confining", "confining stress [kPa] (200)", key="setup.confining",
                    parse=number("confining", 0, MAX_PRESSURE_KPA, hi_open=False, unit="kPa"), to_case=kpa_to_pa),
             VTK))

STUDY = Study(name="triaxial", title="Triaxial test of the Nadukuru backfill (phi for the theories)",
              commands=(CALIBRATE,))
