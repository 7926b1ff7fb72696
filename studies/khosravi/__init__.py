"""Khosravi et al.: PFC2D-style disks behind a wall of 40 pressure cells translating
away from the fill (2D DEM on dem2d).

Modules: ``case`` (KhosraviCase, the box), ``run`` (KhosraviRun: fill, at rest,
translate), ``compare`` (run folder, figures, theories), ``report`` (the validation
report against ``reference.json``). The study record is ``STUDY``.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from ..options import RESUME, VTK, output_file, output_folder
from ..report import reduced_size_line
from ..runner import closing_line
from ..study import Command, Option, Study


def _footprint(case):
    from ..runner import BASE_MEMORY, MEMORY_PER_DISK
    return "particles_scale", case.particles_scale, BASE_MEMORY + MEMORY_PER_DISK * case.estimated_disks()


def _default_case():
    from .case import KhosraviCase
    return KhosraviCase()


def _validation_case():
    from .case import KhosraviCase
    from .compare import VALIDATION_DIS_OVER_H
    return KhosraviCase(wall_disp_over_H_max=VALIDATION_DIS_OVER_H)


def _compare(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..runner import recorded_options, run_root_and_options
    from .compare import compare_khosravi

    kept = {"rrd": opts.rrd, "no_cache": opts.no_cache}
    root, kept = run_root_and_options(opts, kept)
    with recorded_options(kept):
        result, rf = compare_khosravi(case, root=root, rrd=kept["rrd"], quiet=opts.quiet,
                                      specimen_cache=not kept["no_cache"], resume=opts.resume)
    return result, closing_line(result, rf.path)


def scale_note(case, result: dict) -> str | None:
    """One line for a run with coarser grains than the paper's: what it read against
    what the full-size validation read (coarse grains read a higher at-rest K)."""
    if case.particles_scale == 1.0:
        return None
    full = STUDY.reference()["wallsim_full_size"]
    d = result["dem"]
    return reduced_size_line(
        f"grains {case.particles_scale:g} x the paper's ({result['particles']} disks)",
        f"K0 {d['K_at_rest_upper_half_over_jaky']:.2f} x Jaky and active thrust {d['active_thrust_over_rankine']:.2f} "
        "x Rankine",
        f"({full['particles']} disks) {full['K_at_rest_upper_half_over_jaky']:.2f} and "
        f"{full['active_thrust_over_rankine']:.2f}", full["source"])


def _compare_text(res: dict):
    from rich.table import Table

    d = res["dem"]
    t = Table(title=f"Khosravi translation case: H = {res['H_m'] * 1e3:.0f} mm, {res['particles']} disks, "
                    f"seed {res['seed']}", title_justify="left")
    t.add_column("quantity")
    t.add_column("DEM", justify="right")
    t.add_column("compared with", justify="left")
    t.add_row("phi biaxial (peak) [deg]", f"{d['phi_biaxial']:.2f}", "paper 20.7")
    t.add_row("K at rest, upper half", f"{d['K_at_rest_upper_half']:.3f}",
              f"Jaky 1 - sin(phi_biaxial) = {d['jaky_K0']:.3f} (ratio {d['K_at_rest_upper_half_over_jaky']:.2f})")
    t.add_row("PS0 at rest / (Jaky at its depth)", f"{d['PS0_at_rest_over_jaky']:.2f}", "< 1: corner arching")
    t.add_row("active thrust / Rankine", f"{d['active_thrust_over_rankine']:.3f}", "paper: below 1")
    t.add_row("active below at rest everywhere", str(d["active_below_at_rest_everywhere"]), "")
    t.add_row("Dis/H steady (90 % of the drop)", f"{d['wall_disp_over_H_steady']:.5f}", "paper 0.0002-0.0005; <= 0.003")
    t.add_row("floor + walls vertical / weight", f"{d['weight_balance']:.4f}", "1")
    return t


def _validate(case, opts: SimpleNamespace) -> tuple[dict, None]:
    from .compare import REFERENCE, validate_khosravi
    if opts.report_only:
        from .report import rewrite
        return rewrite(Path(opts.docs), REFERENCE), None
    return validate_khosravi(out_dir=opts.docs, root=opts.out, quiet=opts.quiet, case=case, rrd=opts.rrd), None


def _validate_figures(report: dict) -> list[dict]:
    from .report import figures
    return figures(report)


def _validate_text(report: dict) -> str:
    return f"wrote {report['paths']['json']} and {report['paths']['md']}"


_H = Option("--H", "backfill height [m] (0.3; paper: 0.2, 0.25, 0.3)", key="H")
_SCALE = Option("--particles-scale", "multiply every grain diameter (1 = D50 1.16 mm, ~62k disks at H 0.3; "
                                     "2 = ~15k) (1)", key="particles_scale")

COMPARE = Command(
    verb="compare", help="Khosravi et al.'s box: pluviation, at rest, translation to Dis/H = 0.003",
    description="2D disks (pymunk) in a 220 x 400 mm box, rough wall of 40 pressure cells. "
                "An interrupted run goes on with --resume RUN_DIR, from its last snapshot (the fill every "
                "checkpoint_layers layers, the translation every checkpoint_readings readings), to the same bits. "
                "Example: wallsim compare khosravi --H 0.3 --particles-scale 2 --rrd",
    default_case=_default_case, run=_compare, text=_compare_text, scale_note=lambda case, result: scale_note(case, result),
    footprint=_footprint,
    options=(_H, _SCALE,
             Option("--rrd", "write a recording (disks, walls, force chains): recording.rrd in the run folder, "
                             "or FILE (off by default)", metavar="FILE", parse=output_file("rrd", (".rrd",)),
                    optional=True),
             Option("--no-cache", "do not reuse or keep the settled specimen", switch=True), VTK, RESUME))

VALIDATE = Command(
    verb="validate", help="full-size Khosravi case -> docs/validation/khosravi.{json,md} + figures",
    description="H = 0.3 m, D50 = 1.16 mm (~62k disks); the wall moves to Dis/H 0.01 and the active state is "
                "read at 0.003; about 55 min on a 2-core machine (pluviation at 40 sweeps ~13-17 min, at rest "
                "and translation to 0.01 at 80 sweeps ~38 min, a biaxial test for phi ~10 min when no card has "
                "one; docs/validation/khosravi.md).",
    default_case=_validation_case, run=_validate, text=_validate_text, figures=_validate_figures,
    footprint=_footprint,
    options=(Option("--docs", "where the report goes (docs/validation)", default="docs/validation", metavar="DIR",
                    parse=output_folder("docs")),
             Option("--rrd", "also keep recording.rrd in the run folder", switch=True),
             Option("--report-only", "write khosravi.{json,md} in --docs again from the report there: the scorecard "
                    "and text of today's code, nothing run", switch=True), VTK))

STUDY = Study(name="khosravi", title="Khosravi et al., PFC2D-style translating wall with 40 pressure cells",
              commands=(COMPARE, VALIDATE), reference_file=Path(__file__).with_name("reference.json"))
