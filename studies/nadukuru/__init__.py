"""Nadukuru & Michalowski (2012): a 3.1 m wall, rained spheres and clumps, four modes
of wall movement (3D DEM on dem3d).

Modules: ``case`` (wall, movement, the case and the paper's values), ``specimen`` (the
rained backfill and its cache), ``run`` (the wall movement and its load history),
``load`` (the wall load of a frame, K by eq. 6), ``compare`` (one mode beside the
theories: run folder, figures, recording), ``figures``, ``validate`` (every mode and
wall at paper scale -> docs/validation/nadukuru.md). The study record is ``STUDY``.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from analytic.errors import InvalidParameter

from ..options import RECORDING, RESUME, VTK, output_folder
from ..report import reduced_size_line
from ..runner import closing_line
from ..study import Command, Option, Study

MODES = ("T", "RB", "RT", "mixed")


def _footprint(case):
    from ..runner import BASE_MEMORY, MEMORY_PER_SPHERE
    return "particles", case.specimen.particles, BASE_MEMORY + MEMORY_PER_SPHERE * case.specimen.particles


def _default_case():
    from .case import NadukuruCase
    return NadukuruCase()


def _wall_friction(word: str) -> float:
    from .case import rough_or_smooth
    return rough_or_smooth(word)


def wall_kind(case) -> str:
    """'smooth' for a frictionless wall, else 'rough': what the run really has."""
    return "smooth" if case.wall.friction == 0 else "rough"


def _compare(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..progress import progress
    from ..runner import recorded_options, run_root_and_options
    from .compare import compare_nadukuru

    kept = {"rrd": opts.rrd if isinstance(opts.rrd, str) else None, "no_rrd": opts.no_rrd, "every": opts.every}
    root, kept = run_root_and_options(opts, kept)
    with progress(opts.quiet) as bar, recorded_options(kept):
        result, folder = compare_nadukuru(case, wall_kind(case), root=root, rrd=kept["rrd"], spawn=opts.spawn,
                                          every=kept["every"], record=not kept["no_rrd"], progress=bar,
                                          resume=Path(opts.resume) if opts.resume else None)
    return result, closing_line(result, folder)


def scale_note(case, result: dict) -> str | None:
    """One line for a run with fewer particles than the paper's: what it gave against
    what wallsim gave at paper scale for the same mode and wall."""
    ref = STUDY.reference()
    if case.specimen.particles >= ref["specimen"]["particles"]:
        return None
    wall = wall_kind(case)
    full = ref["wallsim_paper_scale"][wall]
    mode = case.movement.mode
    d = result["dem"]
    return reduced_size_line(
        f"{result['particles']} spheres (paper ~{ref['specimen']['particles']:,})",
        f"K {d['K']:.3f}, h/H {d['resultant_height_over_H']:.3f}",
        f"({full['particles']} spheres) {mode} {wall}: K {full[mode]['K']:.3f}, "
        f"h/H {full[mode]['resultant_height_over_H']:.3f}", ref["wallsim_paper_scale"]["source"])


def _compare_text(result: dict):
    from ..report import nadukuru_text
    return nadukuru_text(result)


def _word_list(name: str, allowed: tuple[str, ...]):
    def parse(text: str) -> list[str]:
        words = [w.strip() for w in text.split(",") if w.strip()]
        for w in words:
            if w not in allowed:
                raise InvalidParameter(name, w, " | ".join(allowed))
        return words
    parse.__name__ = name
    return parse


def _validate(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..progress import log_stream, progress
    from .validate import rewrite, validate_nadukuru

    if opts.report_only:
        return rewrite(Path(opts.docs)), f"report: {Path(opts.docs) / 'nadukuru.md'}"
    with progress(opts.quiet) as bar:
        rep = validate_nadukuru(case, out_dir=Path(opts.docs), root=Path(opts.out), walls=opts.walls,
                                modes=opts.modes, triaxial=not opts.no_triaxial,
                                rate_check=not opts.no_rate_check, progress=bar,
                                log=lambda msg: print(msg, file=log_stream(), flush=True))
    return rep, f"report: {Path(opts.docs) / 'nadukuru.md'}"


def _validate_figures(report: dict) -> list[dict]:
    from .validate import figures
    return figures(report)


_PARTICLES_HELP = "spheres incl. clump members (30000 = paper scale; fewer scale the grains up)"

COMPARE = Command(
    verb="compare", help="Nadukuru & Michalowski's 3.1 m wall: four modes of movement (3D)",
    description="Spheres and two-sphere clumps rained behind a 3.1 m wall of 6 segments; the wall translates "
                "or rotates to Delta/H = 0.008. DEM K and resultant height beside the paper, Fang & Ishibashi, "
                "Coulomb, Rankine and the DSM. Example: wallsim compare nadukuru --mode RT --wall rough "
                "--particles 6000",
    default_case=_default_case, run=_compare, text=_compare_text, busy_note=True, scale_note=scale_note,
    footprint=_footprint,
    options=(
        Option("--mode", "T translation, RB rotation about the base, RT about the top, mixed about a point H/2 "
                         "above the top (T)", key="movement.mode", choices=MODES),
        Option("--wall", "wall friction 0.35 (rough) or 0 (smooth) (rough)", key="wall.friction",
               choices=("rough", "smooth"), to_case=_wall_friction),
        Option("--particles", _PARTICLES_HELP + " (30000)", key="specimen.particles"),
        RESUME,
        *RECORDING,
        VTK,
    ))

VALIDATE = Command(
    verb="validate", help="all four modes, rough and smooth walls, at paper scale (hours)",
    description="Triaxial calibration, one settled specimen per wall, the four modes and a half-speed "
                "translation; writes docs/validation/nadukuru.{md,json} and figures.",
    default_case=_default_case, run=_validate, text=lambda rep: None, busy_note=True, figures=_validate_figures,
    footprint=_footprint,
    options=(
        Option("--particles", "spheres (30000)", key="specimen.particles"),
        Option("--walls", "comma list of rough, smooth (rough,smooth)", parse=_word_list("walls", ("rough", "smooth")),
               default=["rough", "smooth"]),
        Option("--modes", "comma list of T, RB, RT, mixed (all)", parse=_word_list("modes", MODES),
               default=list(MODES)),
        Option("--no-triaxial", "skip the triaxial calibration (an existing card for the recipe is used)",
               switch=True),
        Option("--no-rate-check", "skip the half-speed repeat of translation", switch=True),
        Option("--docs", "where the report goes (docs/validation)", default="docs/validation", metavar="DIR",
               parse=output_folder("docs")),
        Option("--report-only", "write nadukuru.{json,md} in --docs again from the report there: the scorecard "
               "and text of today's code, Figs. 4 and 5 from the data the report keeps; nothing run", switch=True),
        VTK,
    ))

STUDY = Study(name="nadukuru", title="Nadukuru & Michalowski (2012), 3D DEM, four modes of wall movement",
              commands=(COMPARE, VALIDATE), reference_file=Path(__file__).with_name("reference.json"))
