"""Dry-stone retaining walls (Oetomo et al.'s PFC2D study): case A, Villemus's five walls
loaded by water, and case B, Colas's three walls under a gravel backfill: rigid blocks on
pymunk (``dem2d.blocks``, ``studies.drystone.backfill``) to failure, beside the rigid-block limit
equilibrium (``analytic.drystone``) and the site measurements.

Modules: ``case`` (the case record, the geometry estimates, what is assumed; case B's
``BackfillSettings``), ``run`` (one case-A wall: DEM, limit equilibrium, run folder),
``run_b`` (one case-B wall: the fill to failure, Coulomb with the slope, run folder),
``validate`` (case A: five walls, the solver-convergence check and the bands ->
docs/validation/drystone.{md,json}). Data: ``reference.json`` (from
docs/reference/drystone-walls.md). The study record is ``STUDY``.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from ..options import RECORDING, RESUME, VTK, output_folder
from ..study import Command, Option, Study
from .case import DIRECTIONS, GEOMETRIES, WALLS, WALLS_B


def _default_case():
    from .case import DrystoneCase
    return DrystoneCase()


def _compare(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..progress import progress
    from ..runner import closing_line
    from .run import compare_wall

    if case.case_b:
        return _compare_b(case, opts)
    if opts.resume:
        from analytic.errors import InvalidParameter
        raise InvalidParameter("--resume", opts.resume, "a case-B run folder (--wall C2S, C3S or C4L)",
                               "a case-A run takes minutes and starts again instead")

    with progress(opts.quiet) as bar:
        task = bar.add_task(f"{case.wall}: water raised (% of h)", total=100)

        def tick(hw, crest):
            bar.update(task, completed=100 * hw / case.section().height_m, status=f"crest {crest * 1e3:.2f} mm")
        result, folder = compare_wall(case, root=Path(opts.out), rrd=opts.rrd if isinstance(opts.rrd, str) else None,
                                      record=not opts.no_rrd, spawn=opts.spawn, progress=tick)
    return result, closing_line(result, folder)


_PHASES = ("drop", "place", "settle", "read")


def _compare_b(case, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..progress import progress
    from ..runner import closing_line
    from .run_b import compare_backfill

    from ..runner import recorded_options, run_root_and_options

    top = case.section().height_m + case.backfill.formwork_m
    kept = {"rrd": opts.rrd if isinstance(opts.rrd, str) else None, "no_rrd": opts.no_rrd}
    root, kept = run_root_and_options(opts, kept)
    with progress(opts.quiet) as bar, recorded_options(kept):
        task = bar.add_task(f"{case.wall}: backfill height (% of h + formwork)", total=100)

        def tick(hb, crest, r):
            bar.update(task, completed=100 * hb / top,
                       status=f"H_b {hb:.2f} m, crest {crest * 1e3:.2f} mm, {r['grains']} grains ({r['held']} held), "
                              f"{r['steps']} steps, stage CPU {sum(r.get(f'cpu_{k}_s', 0.0) for k in _PHASES):.0f} s")
        result, folder = compare_backfill(case, root=root, rrd=kept["rrd"], record=not kept["no_rrd"],
                                          spawn=opts.spawn, progress=tick,
                                          resume=Path(opts.resume) if opts.resume else None)
    return result, closing_line(result, folder)


def _compare_b_text(r: dict) -> str:
    crit = "stands" if r["critical_height_m"] is None else f"{r['critical_height_m']:.2f} m"
    st = r["stages"][-1] if r["stages"] else {}
    lo, ou = r["local_values"]["paper"], r["local_values"]["ours"]
    return "\n".join([
        f"{r['wall']} (case B, {r['particles']['blocks']} blocks, {r['particles']['grains']} grains): DEM {crit}, "
        f"{r['mode']}; measured {r['measured_height_m']:.2f} m {r['measured_mode']}; paper's DEM "
        f"{', '.join(f'{h:.2f}' for h in r['paper_dem_heights_m'])} m",
        f"  last stage H_b {st.get('backfill_height_m', float('nan')):.2f} m: thrust "
        f"{st.get('thrust_N_m', float('nan')) / 1e3:.2f} kN/m at {st.get('thrust_height_m', float('nan')):.2f} m "
        f"(Coulomb {r['coulomb']['rows'][-1]['thrust_N_m'] / 1e3:.2f} kN/m)" if st else "  no stage",
        f"  limit equilibrium {r['limit_equilibrium']['critical_height_m']:.2f} m {r['limit_equilibrium']['mode']}",
        f"  local frictions ours grain {ou['grain_friction_deg']:g} / interface {ou['interface_friction_deg']:g} deg; "
        f"paper's {lo['grain_friction_deg']:g} / {lo['interface_friction_deg']:g} deg",
        f"  wall {r['wall_time_s']:.1f} s, CPU {r['cpu_time_s']:.1f} s, "
        f"{r['speed']['steps_per_cpu_s']:.0f} steps/CPU-s, "
        f"{r['speed']['body_steps_per_cpu_s']:.3g} body-steps/CPU-s; CPU by phase: build "
        f"{r['speed'].get('cpu_build_s', float('nan')):.0f} s, "
        + ", ".join(f"{k} {v:.0f} s ({r['speed']['steps_by_phase'][k]} steps)"
                    for k, v in r['speed'].get('cpu_by_phase_s', {}).items()),
        "  assumed: " + "; ".join(r["assumptions"])])


def _compare_text(r: dict) -> str:
    if r.get("load") == "backfill":
        return _compare_b_text(r)
    d, le, m = r["dem"], r["limit_equilibrium"]["yield-design"], r["measured"]
    crit = "stands to the crest" if d["critical_height_m"] is None else f"{d['critical_height_m']:.3f} m"
    lines = [f"{r['wall']} ({r['geometry']} geometry, b {r['section']['base_width_m']:.3g} m, "
             f"{d['blocks']} blocks): DEM {crit}, {d['mode']} at {d['mechanism_level_m']} m",
             f"  limit equilibrium {le['critical_height_m']:.3f} m {le['mode']}; measured {m['height_m']:.2f} m "
             f"{m['mode']}; paper's DEM {r['paper_dem']['height_m']:.2f} m {r['paper_dem']['mode']}",
             f"  wall {r['wall_time_s']:.1f} s, CPU {r['cpu_time_s']:.1f} s; {r['note']}",
             "  assumed: " + "; ".join(r["assumptions"])]
    return "\n".join(lines)


def _validate(case, opts: SimpleNamespace) -> tuple[dict, str]:
    import sys

    from analytic.errors import InvalidParameter

    from ..options import writable_folder
    from .validate import validate_drystone
    from .validate_b import validate_case_b
    own = WALLS_B if opts.case == "B" else WALLS
    walls = opts.walls or list(own)
    if any(w not in own for w in walls):
        raise InvalidParameter("walls", ",".join(walls), f"walls of case {opts.case}: " + ", ".join(own))
    writable_folder("docs", opts.docs)
    writable_folder("docs", str(Path(opts.docs) / "drystone"))
    log = None if opts.quiet else (lambda msg: print(msg, file=sys.stderr, flush=True))
    if opts.case == "B":
        rep = validate_case_b(case, out_dir=Path(opts.docs), root=Path(opts.out), walls=walls, seeds=opts.backfill_seeds,
                              run_missing=not opts.finished_only, log=log)
    else:
        rep = validate_drystone(case, out_dir=Path(opts.docs), walls=walls, band=opts.band,
                                convergence=not opts.no_convergence, other_sections=not opts.no_independence, log=log,
                                root=Path(opts.out))
    return rep, f"report: {Path(opts.docs) / 'drystone.md'}"


def _walls(text: str) -> list[str]:
    from analytic.errors import InvalidParameter
    words = [w.strip() for w in text.split(",")]
    if any(not w for w in words):
        raise InvalidParameter("walls", text, "a comma list of walls of " + ", ".join(WALLS + WALLS_B), "an empty item")
    for w in words:
        if w not in WALLS + WALLS_B:
            raise InvalidParameter("walls", w, " | ".join(WALLS + WALLS_B))
    if len(set(words)) < len(words):
        raise InvalidParameter("walls", text, "a comma list of distinct walls of " + ", ".join(WALLS + WALLS_B),
                               "a wall is named twice")
    return words


def _seeds(text: str) -> tuple[int, ...]:
    from analytic.errors import InvalidParameter
    try:
        seeds = tuple(int(w) for w in text.split(","))          # an empty item is refused, not dropped
    except ValueError:
        seeds = ()
    from analytic.schema import MAX_SEED
    if not seeds or min(seeds) < 0 or max(seeds) > MAX_SEED or len(set(seeds)) < len(seeds):
        raise InvalidParameter("backfill-seeds", text, f"a comma list of distinct integers in [0, {MAX_SEED}]")
    return seeds


_CASE_OPTIONS = (
    Option("--geometry", "back-fit (reference 2.3) or disk-count (reference 6) (back-fit)", key="geometry",
           choices=GEOMETRIES),
    Option("--unit-weight", "masonry unit weight gamma_m [kN/m3] (20, assumed)", key="unit_weight_kN_m3"),
    Option("--joint-slope", "joint counter-slope alpha [deg] (the wall's: V5S 8.53, others 0 assumed)",
           key="joint_slope_deg"),
    Option("--water-direction", "normal to the current face, or fixed at its initial normal (the paper's) (normal)",
           key="water_direction", choices=DIRECTIONS),
    Option("--dt", "time step [s] (5e-4)", key="dt"),
)

COMPARE = Command(
    verb="compare",
    help="a dry-stone wall to failure: Villemus's under water (case A) or Colas's under gravel (case B)",
    description="Case A: courses of 0.30 x 0.125 m rigid blocks with staggered joints, first course fixed, water "
                "raised by 1 % of h per increment until the wall fails. Case B: 0.33 x 0.12 m blocks, first course "
                "free, gravel (rounded hexagons) placed in 10 cm stages with the slope re-cut to 32 deg until the wall fails "
                "(an hour or more of CPU at full size; an interrupted case-B run goes on with --resume RUN_DIR from its "
                "last stage, to the same bits). DEM beside the limit equilibrium and the site value. "
                "Example: wallsim compare drystone --wall V3L --geometry disk-count",
    default_case=_default_case, run=_compare, text=_compare_text, seed_key=None,
    options=(Option("--wall", "V1L | V2L | V3L | V4L | V5S (case A, water) | C2S | C3S | C4L (case B, "
                    "backfill) (V1L)", key="wall", choices=WALLS + WALLS_B),
             *_CASE_OPTIONS, *RECORDING[:3], VTK, RESUME))

VALIDATE = Command(
    verb="validate", help="case A: the five walls, convergence and bands (minutes); case B: three walls x two "
                          "seeds under gravel (about 4 h of one core)",
    description="Case A: every wall at the default settings, again with dt / 2 and twice the iterations, and the "
                "band of critical heights over both geometries, gamma_m 18-22 kN/m3 and alpha 0-8.5 deg, and each "
                "wall on the other back-fit rows and the disk-count section (whether the DEM follows its section). Case B: "
                "C2S, C3S and C4L filled to failure on seeds 1 and 2 (35-40 min of one core each; a finished run "
                "folder of the same resolved case under --out is read instead of run again). Writes "
                "docs/validation/drystone.{md,json} (the other case kept) and figures. "
                "Example: wallsim validate drystone --case B --walls C3S --seeds 1",
    default_case=_default_case, run=_validate, text=lambda rep: None, seed_key=None,
    options=(Option("--case", "A: water (Villemus's walls); B: gravel backfill (Colas's walls) (A)",
                    choices=("A", "B"), default="A"),
             Option("--walls", "comma list of the case's walls: V1L,V2L,V3L,V4L,V5S or C2S,C3S,C4L (all)",
                    parse=_walls, default=None),
             Option("--backfill-seeds", "case B: comma list of backfill seeds, the realisations (1,2)", parse=_seeds,
                    default=(1, 2)),
             Option("--finished-only", "case B: report the finished runs under --out; a wall and seed without one "
                    "keeps its entry of the present report, else is reported as not run (nothing is run)",
                    switch=True),
             Option("--band", "case A: dem: DEM runs over the band corners; le: limit equilibrium only (dem)",
                    choices=("dem", "le"), default="dem"),
             Option("--no-convergence", "case A: skip the dt / 2, 2 x iterations repeat", switch=True),
             Option("--no-independence", "case A: skip the runs on the other back-fit rows and the disk-count "
                    "sections", switch=True),
             *_CASE_OPTIONS[5:],
             Option("--docs", "where the report goes (docs/validation)", default="docs/validation", metavar="DIR",
                    parse=output_folder("docs")), VTK))

STUDY = Study(name="drystone",
              title="Dry-stone retaining walls to failure (Oetomo et al.): Villemus's under water, Colas's under gravel",
              commands=(COMPARE, VALIDATE), reference_file=Path(__file__).with_name("reference.json"))
