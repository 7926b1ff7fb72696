"""The designer's own wall in DEM (3D, dem3d): ``wallsim compare wall WALL.toml`` runs
the wall that ``wallsim design WALL.toml`` checks, sets its load beside the theories and
reruns the design checks with the DEM's thrust; ``wallsim calibrate wall`` makes the phi
card that maps a friction angle to the backfill's micro parameters.

Modules: ``case`` (the file and the DEM's keys -> the shared granular pipeline's
records; what the DEM refuses), ``card`` (the phi card and its inverse), ``surcharge``
(the load on the top layer), ``compare`` (the run, the theories, the design rerun, the
run folder), ``calibrate`` (the card's triaxial tests), ``figures``. The study record is
``STUDY``.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from ..options import RECORDING, RESUME, VTK, output_folder
from ..study import Command, Option, Study

MODES = ("T", "RB", "RT", "mixed")


def _footprint(case):
    from ..runner import BASE_MEMORY, MEMORY_PER_SPHERE
    return "particles", case.particles, BASE_MEMORY + MEMORY_PER_SPHERE * case.particles


def _default_case():
    from .case import WallStudyCase
    return WallStudyCase()


def _compare(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from analytic.errors import InvalidParameter

    from ..progress import progress
    from ..runner import closing_line, recorded_options, run_root_and_options
    from .compare import compare_wall

    if case.design_file is None:
        raise InvalidParameter("design_file", "missing", "a WALL.toml as `wallsim design` reads (e.g. "
                               "docs/examples/cantilever.toml)")
    kept = {"rrd": opts.rrd if isinstance(opts.rrd, str) else None, "no_rrd": opts.no_rrd, "every": opts.every}
    root, kept = run_root_and_options(opts, kept)
    with progress(opts.quiet) as bar, recorded_options(kept):
        result, folder = compare_wall(case, root=root, rrd=kept["rrd"], spawn=opts.spawn, every=kept["every"],
                                      record=not kept["no_rrd"], progress=bar,
                                      resume=Path(opts.resume) if opts.resume else None)
    return result, closing_line(result, folder)


def _compare_text(result: dict):
    from .report import wall_text
    return wall_text(result)


def _default_card_case():
    from .calibrate import CardCase
    return CardCase()


def _calibrate(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..progress import progress
    from .calibrate import make_card

    with progress(opts.quiet) as bar:
        card, path, folder = make_card(case, root=Path(opts.out), progress=bar)
    return card | {"card": str(path), "run_folder": str(folder)}, f"phi card: {path}\nrun folder: {folder}"


def _card_text(card: dict) -> str:
    rows = [f"  friction {p['particle_friction']:<5g} rolling {p['rolling_friction']:<5g} peak phi "
            f"{p['phi_peak_deg']:5.1f} deg (end {p['phi_end_deg']:4.1f}), porosity {p['porosity']:.3f}"
            for p in card["points"]]
    return "phi card (triaxial peak phi along the path; " + card["path"] + "):\n" + "\n".join(rows)


COMPARE = Command(
    verb="compare", help="the designer's wall (WALL.toml of `wallsim design`) in DEM, and its checks rerun (3D)",
    description="Rains a backfill calibrated to the file's phi and unit weight behind a rigid wall of the "
                "design's retained height (wall friction by the file's convention, surcharge on the top layer), "
                "moves the wall away from the fill and reads the pressure per segment; sets thrust, K and the "
                "resultant's height beside Rankine, Coulomb and EN 1997-1 Annex C, then reruns the file's design "
                "checks with the DEM's thrust. Example: wallsim compare wall docs/examples/cantilever.toml "
                "--mode RB",
    default_case=_default_case, run=_compare, text=_compare_text, busy_note=True, footprint=_footprint,
    options=(
        Option("design_file", "the WALL.toml that `wallsim design` checks", key="design_file", metavar="WALL.toml"),
        Option("--mode", "T translation, RB rotation about the base, RT about the top, mixed about a point H/2 "
                         "above the top (T)", key="movement.mode", choices=MODES),
        Option("--particles", "spheres incl. clump members (15000; grains scale to fill the box)", key="particles"),
        Option("--format", "design format of the rerun checks (DA1)", key="design_format",
               choices=("DA1", "DA2", "DA3", "EQU", "fs")),
        RESUME,
        *RECORDING,
        VTK,
    ))

CALIBRATE = Command(
    verb="calibrate", help="the phi card of the wall backfill: triaxial peak phi along its micro parameters (3D)",
    description="Cubical triaxial tests of the wall study's backfill recipe at each point of the card's path "
                "(grain friction 0.1 to 0.65, then rolling resistance 0.05 to 0.3), collated into the phi card "
                "that `compare wall` inverts for a file's phi.",
    default_case=_default_card_case, run=_calibrate, text=_card_text, busy_note=True,
    options=(Option("--particles", "spheres per test (8200, the Nadukuru triaxial's)", key="particles"),))

def _default_check_case():
    from .validate import CheckCase
    return CheckCase()


def _validate(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..progress import log_stream, progress
    from .validate import validate_wall

    with progress(opts.quiet) as bar:
        rep = validate_wall(root=Path(opts.out), out_dir=Path(opts.docs), seed=case.seed, progress=bar,
                            log=lambda msg: print(msg, file=log_stream(), flush=True))
    return rep, f"report: {Path(opts.docs) / 'wall.md'}"


VALIDATE = Command(
    verb="validate", help="the phi card checked at 28, 34, 40 deg and the worked example run (about 20 min)",
    description="Triaxial tests at the phi card's micro parameters for 28, 34 and 40 deg (the card's size, another "
                "seed), each against the request within 1.5 deg, and `compare wall docs/examples/cantilever.toml` "
                "at the default size; writes docs/validation/wall.{md,json}.",
    default_case=_default_check_case, run=_validate, text=lambda rep: None, busy_note=True, seed_default=2,
    options=(Option("--docs", "where the report goes (docs/validation)", default="docs/validation", metavar="DIR",
                    parse=output_folder("docs")),))

STUDY = Study(name="wall", title="The designer's wall in DEM: a WALL.toml's backfill on a rigid wall, checks rerun",
              commands=(COMPARE, CALIBRATE, VALIDATE))
