"""Nadukuru & Michalowski (2012), Fig. 1: arching in a prismatic heap whose base
subsides at the centre (3D DEM on dem3d).

Modules: ``case`` (the case, its assumptions, the box and base), ``run`` (rain, slump,
subsidence, checkpoints), ``measures`` (shape, base stress, centre over peak),
``compare`` (one run: run folder, figures, recording), ``validate`` (3 seeds ->
docs/validation/heap.md).
The study record is ``STUDY``.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from ..options import RECORDING, RESUME, VTK, output_folder
from ..study import Command, Option, Study


def _footprint(case):
    from ..runner import BASE_MEMORY, MEMORY_PER_SPHERE
    return "particles", case.particles, BASE_MEMORY + MEMORY_PER_SPHERE * case.particles


def _default_case():
    from .case import HeapCase
    return HeapCase()


def _compare(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..progress import progress
    from ..runner import recorded_options, run_root_and_options
    from .compare import compare_heap

    kept = {"rrd": opts.rrd if isinstance(opts.rrd, str) else None, "no_rrd": opts.no_rrd}
    root, kept = run_root_and_options(opts, kept)
    with progress(opts.quiet) as bar, recorded_options(kept):
        result, folder = compare_heap(case, root=root, rrd=kept["rrd"], spawn=opts.spawn, record=not kept["no_rrd"],
                                      progress=bar, resume=Path(opts.resume) if opts.resume else None)
    return result, f"run folder: {folder}"


def _compare_text(res: dict) -> str:
    from .compare import slope_text

    return (f"heap: {res['particles']} spheres ({res['heap_spheres']} on the base), seed {res['seed']}\n"
            f"  H {res['heap_height_m']:.3f} m, {slope_text(res['slope_deg'])}, porosity {res['porosity']:.3f}\n"
            f"  centre / peak base stress: before {res['centre_over_peak_before']:.3f}, after "
            f"{res['centre_over_peak_after']:.3f} (Delta/H {res['subsidence_over_H']:.4f})\n"
            f"  base load / heap weight {res['base_load_over_heap_weight']:.3f}; wall {res['wall_time_s']:.0f} s, "
            f"CPU {res['cpu_time_s']:.0f} s")


def _validate(case, opts: SimpleNamespace) -> tuple[dict, str]:
    import sys

    from ..progress import progress
    from .validate import rewrite, validate_heap

    if opts.report_only:
        return rewrite(Path(opts.docs)), f"report: {Path(opts.docs) / 'heap.md'}"
    with progress(opts.quiet) as bar:
        rep = validate_heap(case, seeds=opts.seeds, out_dir=Path(opts.docs), root=Path(opts.out), progress=bar,
                            log=lambda msg: print(msg, file=sys.stderr, flush=True))
    return rep, f"report: {Path(opts.docs) / 'heap.md'}"


def _seeds(text: str) -> tuple[int, ...]:
    from ..seeds import parse_seeds
    return tuple(parse_seeds(text))


_PARTICLES = Option("--particles", "spheres incl. clump members (12000)", key="particles")

COMPARE = Command(
    verb="compare", help="Nadukuru & Michalowski's Fig. 1: a heap whose base subsides at the centre (3D)",
    description="Spheres and two-sphere clumps rained into a 4.8 m x 0.6 m box (periodic along 0.6 m); the end "
                "walls go and the fill slumps to a prismatic heap; the base halves turn about their outer edges "
                "to a centre subsidence Delta/H = 0.0067. Base stress before and after, force chains. "
                "An interrupted run continues with --resume RUN_DIR (checkpoints every 5 min and every 10 % of "
                "each stage), ending as the uninterrupted run would, bit for bit. "
                "Example: wallsim compare heap --particles 6000 --seed 2",
    default_case=_default_case, run=_compare, text=_compare_text, busy_note=True, footprint=_footprint,
    options=(_PARTICLES, *RECORDING[:3], VTK, RESUME))

VALIDATE = Command(
    verb="validate", help="three seeds at paper scale -> docs/validation/heap.md (about 30-45 min)",
    description="Runs the heap for each seed of --seeds one after the other and writes docs/validation/heap.{md,json} "
                "and heap_base_stress.png: centre / peak base stress before and after subsidence (mean +- sd).",
    default_case=_default_case, run=_validate, text=lambda rep: None, busy_note=True, seed_key=None,
    footprint=_footprint,
    options=(_PARTICLES,
             Option("--seeds", "the seeds, A..B or a list S1,S2 (1..3)", parse=_seeds, default=(1, 2, 3),
                    metavar="A..B|S1,S2"),
             Option("--docs", "where the report goes (docs/validation)", default="docs/validation", metavar="DIR",
                    parse=output_folder("docs")),
             Option("--report-only", "write heap.{json,md} in --docs again from the report there: the scorecard "
                    "and text of today's code, nothing run", switch=True), VTK))

STUDY = Study(name="heap", title="Nadukuru & Michalowski (2012) Fig. 1, heap over a subsiding base (3D DEM)",
              commands=(COMPARE, VALIDATE), reference_file=Path(__file__).with_name("reference.json"))
