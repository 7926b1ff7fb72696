"""Sizkow & El Shamy: a cantilever sheet pile of bonded balls retaining 9 m of dry sand
over 6 m (prototype), a 50 g centrifuge model in 3D DEM with free-field lateral
boundaries, its base shaken by 0.1 g sinusoids of 1-6 Hz (prototype).

Modules (the study layout, docs/architecture.md): ``case`` (the record in model units,
resolution presets, centrifuge scaling), ``specimen`` (the model built: deposit, wall,
excavation, boundaries, base motion), ``run`` (static state, cached; the shaking),
``measures`` (wall, faces, moments, settlement, Mononobe-Okabe), ``compare`` (one
frequency: run folder, tables, figures, recording), ``calibrate`` (the material checks:
Vs / f0 of the free-field columns, phi from a triaxial at the case's contact
parameters), ``validate`` (the paper's frequencies -> docs/validation/seismic.{md,json}),
``figures``, ``scorecard``. Data and every assumption: docs/reference/seismic-sheetpile.md,
reference.json.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from ..options import RESUME, VTK, number_list, output_file, output_folder
from ..runner import closing_line
from ..study import Command, Option, Study


def _default_case():
    from .case import SeismicCase
    return SeismicCase()


def _compare(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..progress import progress
    from ..runner import recorded_options, run_root_and_options
    from .compare import compare_seismic

    kept = {"rrd": opts.rrd}
    root, kept = run_root_and_options(opts, kept)
    with progress(opts.quiet) as bar, recorded_options(kept):
        task = bar.add_task("shaking", total=1, status="")
        result, folder = compare_seismic(
            case, root=root, record=bool(kept["rrd"]), rrd=kept["rrd"] if isinstance(kept["rrd"], str) else None,
            progress=lambda done, total: bar.update(task, completed=done, total=total, status=""),
            log=lambda msg: bar.update(task, status=msg), resume=Path(opts.resume) if opts.resume else None)
    return result, closing_line(result, folder)


def scale_note(case) -> str | None:
    """The line every coarser-than-paper run carries (the resolution is stated in every output)."""
    if case.scale == 1.0:
        return None
    return (f"grain scale {case.scale:g}: grains {case.grains[0] * 1e3:.1f}-{case.grains[1] * 1e3:.1f} mm and a "
            f"{2 * case.wall_ball * 1e3:.0f} mm wall of the paper's EI and mass (paper: 1.5-2.5 mm grains, 5 mm "
            "wall); how results move with resolution is not measured yet")


def _rest_line(rest: dict) -> str:
    """The rest before shaking: how far the wall moved once the shaking model took over."""
    top, back = rest["top_displacement_m"], rest["thrust_back_kN_per_m"]
    return (f"rest {rest['rest_s']:g} s before the base moved: wall top {top[0] * 1e3:.1f} -> {top[1] * 1e3:.1f} mm "
            f"({rest['top_change_over_last_fifth_m'] * 1e3:+.1f} mm over its last fifth), thrust back "
            f"{back[0]:.1f} -> {back[1]:.1f} kN/m")


def _text(r: dict) -> str:
    p = r["prototype"]
    s, e = p["static"], p["residual"]
    return (f"{r['frequency_Hz']:g} Hz (prototype), grain scale {r['grain_scale']:g}: {r['particles']} spheres "
            f"(+{sum(r['column_particles'])} in the free-field columns), porosity {r['porosity']:.3f}, "
            f"dt {r['dt_s']:.3g} s, {r['steps']} steps at {r['steps_per_s']:.0f} steps/s\n"
            f"{_rest_line(r['rest'])}\n"
            f"static: wall top {s['top_displacement_m'] * 1e3:.1f} mm toward the excavation, thrust back "
            f"{s['thrust_back_kN_per_m']:.1f} / front {s['thrust_front_kN_per_m']:.1f} kN/m, moment "
            f"{s['max_moment_kN_m_per_m']:.1f} kN m/m\n"
            f"residual: wall top {e['top_displacement_m'] * 1e3:.1f} mm, rotation {e['rotation_deg']:.3f} deg "
            f"(pivot at {e['pivot_height_over_wall_length']:.2f} of the wall above its toe), thrust back "
            f"{e['thrust_back_kN_per_m']:.1f} / front {e['thrust_front_kN_per_m']:.1f} kN/m; moment max / static "
            f"{p['max_moment_over_static']:.2f}, residual / static {p['residual_moment_over_static']:.2f}")


COMPARE = Command(
    verb="compare", help="Sizkow & El Shamy's sheet pile at 50 g, one shaking frequency (3D, long; five frequencies in docs/validation/seismic.md)",
    description="A cantilever sheet pile of bonded balls retaining 9 m of dry sand over 6 m (prototype), "
                "a 50 g model with free-field lateral boundaries, the base shaken by a 0.1 g sinusoid "
                "(3 s ramp, 4 s hold, 1 s decay). Results in prototype units with Mononobe-Okabe. "
                "The grains carry a rolling resistance (mu_r 0.25, an assumption calibrated so the deposit's "
                "triaxial gives phi ~31 deg as the paper's sand; friction alone gives ~18 and the wall fails). "
                "The coarse resolution (~16k spheres) takes about 20 min of one core a frequency, the 1 s rest before "
                "shaking included (the static state 3-6 min more, cached for other frequencies); medium ~1.5 h, "
                "paper ~23 h (estimated). "
                "Example: wallsim compare seismic --freq 5 --resolution coarse",
    default_case=_default_case, run=_compare, text=_text, busy_note=True,
    scale_note=lambda case, result: scale_note(case),
    options=(
        Option("--freq", "base-motion frequency, prototype [Hz] (5)", key="frequency"),
        Option("--resolution", "coarse (grains x 3), medium (x 2) or paper (1.5-2.5 mm grains) (coarse)",
               key="resolution", choices=("coarse", "medium", "paper")),
        Option("--rrd", "write a recording (recording.rrd in the run folder, or FILE)", metavar="FILE",
               parse=output_file("rrd", (".rrd",)), optional=True),
        VTK,
        RESUME,
    ))

def _validate(case, opts: SimpleNamespace) -> tuple[dict, str]:
    import sys

    from ..progress import progress
    from .validate import validate_seismic

    with progress(opts.quiet) as bar:
        task = bar.add_task("shaking", total=1, status="")
        rep = validate_seismic(case, frequencies=tuple(opts.freqs), out_dir=Path(opts.docs), root=Path(opts.out),
                               rolling_resistances=tuple(opts.rolling_resistances or ()),
                               progress=lambda done, total: bar.update(task, completed=done, total=total),
                               log=lambda msg: print(msg, file=sys.stderr, flush=True))
    return rep, f"report: {Path(opts.docs) / 'seismic.md'}"


VALIDATE = Command(
    verb="validate", help="the paper's frequencies one after the other -> docs/validation/seismic.md (long)",
    description="Runs 1, 3, 4, 5 and 6 Hz (prototype) at one resolution and writes "
                "docs/validation/seismic.{md,json}: per frequency the wall's residual displacement, rotation "
                "and pivot, moments over static, passive K at 1.5 m below the dredge line, settlement; each "
                "of the paper's trends held / not held / not run. About 20 min of one core per frequency at "
                "the coarse resolution. The paper's other frequencies already run (same case, under --out) "
                "stay in the report. Example: wallsim validate seismic --freqs 5,4",
    default_case=_default_case, run=_validate, text=lambda rep: None, busy_note=True,
    options=(Option("--freqs", "frequencies, prototype [Hz] (1,3,4,5,6)", default=[1.0, 3.0, 4.0, 5.0, 6.0],
                    parse=number_list("freqs", lo=0.0, hi=20.0, unit="Hz")),
             Option("--resolution", "coarse, medium or paper (coarse)", key="resolution",
                    choices=("coarse", "medium", "paper")),
             Option("--rolling-resistances", "the frequencies again at each of these rolling resistances mu_r "
                    "(the assumed contact value), beside the case's own in the report (none)", default=(),
                    parse=number_list("rolling_resistances", lo=0.0, hi=1.0), metavar="MU_R,..."),
             Option("--docs", "where the report goes (docs/validation)", default="docs/validation", metavar="DIR",
                    parse=output_folder("docs")), VTK))

STUDY = Study(name="seismic", title="Sizkow & El Shamy, a sheet pile shaken at 50 g (3D DEM, free-field boundaries)",
              commands=(COMPARE, VALIDATE), reference_file=Path(__file__).with_name("reference.json"))
