"""wallsim command line: parse, dispatch, print. The work happens in the packages.

Bad input ends with one line on stderr naming the parameter and its valid range, and
exit code 2 -- never a traceback.
"""

from __future__ import annotations

import argparse
import json
import os
import sys

import reproducibility

EXIT_BAD_INPUT = 2


class _Parser(argparse.ArgumentParser):
    """argparse that reports a usage error in one line (no usage dump)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)     # --particles must not pass for --particles-scale
        super().__init__(*args, **kwargs)

    def error(self, message: str):  # noqa: D401 - argparse API
        sys.stderr.write(f"{self.prog}: error: {message}\n")
        sys.exit(EXIT_BAD_INPUT)


def _number(name: str, lo=None, hi=None, *, lo_open=True, hi_open=True, unit=""):
    """argparse type: a finite float in a range, with a one-line message naming both."""
    from studies.options import number
    return _argparse_type(number(name, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit), name)


def _output_file(name: str, suffixes=(".png", ".pdf", ".svg")):
    from studies.options import output_file
    return _argparse_type(output_file(name, suffixes), name)


def _add_theory(sub):
    from analytic.inputs import MAX_HEIGHT_M, MAX_PRESSURE_KPA, MAX_UNIT_WEIGHT_KN_M3

    p = sub.add_parser("theory", help="closed-form and arching earth pressure for one wall",
                       description="Every closed-form and arching method side by side. "
                                   "Defaults: Nadukuru & Michalowski's translation case.")
    p.add_argument("--phi", type=_number("phi", 0, 90, lo_open=False, unit="deg"), default=34.0,
                   help="friction angle [deg], [0, 90); 0 with --c: undrained clay in total stress, c = c_u (34)")
    p.add_argument("--delta", type=_number("delta", -90, 90, unit="deg"), default=None,
                   help="wall friction angle [deg], |delta| <= phi (24.7; 0 when phi = 0)")
    p.add_argument("--H", type=_number("H", 0, MAX_HEIGHT_M, hi_open=False, unit="m"), default=3.1,
                   help=f"wall height [m], (0, {MAX_HEIGHT_M:g}] (3.1)")
    p.add_argument("--gamma", type=_number("gamma", 0, MAX_UNIT_WEIGHT_KN_M3, hi_open=False, unit="kN/m^3"),
                   default=16.7, help=f"unit weight [kN/m^3], (0, {MAX_UNIT_WEIGHT_KN_M3:g}] (16.7)")
    p.add_argument("--beta", type=_number("beta", -90, 90, unit="deg"), default=0.0,
                   help="backfill slope [deg], + rising away from the wall (0)")
    p.add_argument("--omega", type=_number("omega", -90, 90, unit="deg"), default=0.0,
                   help="back-face inclination from vertical [deg], + heel under the fill (0)")
    p.add_argument("--q", type=_number("q", 0, MAX_PRESSURE_KPA, lo_open=False, hi_open=False, unit="kPa"),
                   default=0.0, help=f"surcharge [kPa], [0, {MAX_PRESSURE_KPA:g}] (0)")
    p.add_argument("--kh", type=_number("kh", 0, 1, lo_open=False), default=0.0, help="horizontal seismic coefficient (0)")
    p.add_argument("--kv", type=_number("kv", -1, 1), default=0.0, help="vertical seismic coefficient, + upward (0)")
    p.add_argument("--width", type=_number("width", 0, 10 * MAX_HEIGHT_M, hi_open=False, unit="m"), default=None,
                   help="backfill width B for Janssen's slot [m] (default: H)")
    p.add_argument("--ps-exponent", choices=["iii", "i"], default="iii",
                   help="Paik-Salgado profile exponent form (see analytic/arching.py)")
    p.add_argument("--c", type=_number("c", 0, MAX_PRESSURE_KPA, lo_open=False, hi_open=False, unit="kPa"),
                   default=0.0, help="effective cohesion [kPa] (0): Rankine-Bell, Coulomb and EC7 with c")
    p.add_argument("--adhesion-ratio", type=_number("adhesion-ratio", 0, 1, lo_open=False, hi_open=False),
                   default=0.0, help="wall adhesion a/c for Coulomb with cohesion (0)")
    p.add_argument("--water-depth", type=_number("water-depth", 0, MAX_HEIGHT_M, lo_open=False, hi_open=False,
                                                 unit="m"), default=None,
                   help="water table behind the wall, depth below the wall top [m] (dry)")
    p.add_argument("--water-depth-front", type=_number("water-depth-front", 0, MAX_HEIGHT_M, lo_open=False,
                                                       hi_open=False, unit="m"),
                   default=None, help="water level in front of the wall, depth below the wall top [m] (none)")
    p.add_argument("--gamma-sat", type=_number("gamma-sat", 9.81, MAX_UNIT_WEIGHT_KN_M3, lo_open=False,
                                               hi_open=False, unit="kN/m^3"),
                   default=None, help="saturated unit weight below the water table [kN/m^3] (gamma)")
    p.add_argument("--layers", metavar="FILE.toml",
                   help="layered backfill: [[layer]] tables with thickness [m], phi [deg], gamma [kN/m^3], "
                        "c [kPa], gamma_sat [kN/m^3], top down, adding up to H (replaces --phi/--gamma/--c)")
    p.add_argument("--line-load", action="append", default=[], metavar="Q,X",
                   help="line load Q [kN/m] at X [m] behind the wall (repeatable)")
    p.add_argument("--strip-load", action="append", default=[], metavar="Q,X1,X2",
                   help="strip load Q [kPa] from X1 to X2 [m] behind the wall (repeatable)")
    p.add_argument("--crack-water", action="store_true",
                   help="the active tension crack of a cohesive fill full of water (gamma_w z down to it)")
    p.add_argument("--passive", action="store_true", help="passive instead of active")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", type=_output_file("plot"), help="draw sigma_h(z) of every method")
    p.set_defaults(func=_cmd_theory)


def _cmd_theory(args) -> int:
    from analytic import Soil, Wall
    from analytic.errors import InvalidParameter
    from analytic.summary import theory_table
    from studies.report import theory_json, theory_text

    from analytic.ground import theory_loads, theory_ground

    if args.phi == 0 and not args.c and not args.layers:
        raise InvalidParameter("c", args.c, "> 0 with --phi 0", "phi = 0 is the undrained case: give c_u as --c")
    delta = args.delta if args.delta is not None else (24.7 if args.phi > 0 else 0.0)
    soil = Soil(args.phi, args.gamma * 1e3, undrained=args.phi == 0)
    wall = Wall(args.H, delta, args.omega, args.beta, args.q * 1e3)
    layers = _read_toml("layers", args.layers) if args.layers else None
    ground = theory_ground(soil, wall.height, c_kPa=args.c, gamma_sat_kN=args.gamma_sat,
                           water_depth=args.water_depth, water_depth_front=args.water_depth_front,
                           layers_table=layers)
    if args.layers:
        top = ground.layers[0]       # the table's title and inputs show the top layer
        soil = Soil(top.phi_deg, top.unit_weight)
    loads = theory_loads(args.line_load, args.strip_load)
    rows = theory_table(soil, wall, kh=args.kh, kv=args.kv, passive=args.passive,
                        width=args.width, ps_exponent=args.ps_exponent, ground=ground,
                        adhesion_ratio=args.adhesion_ratio, crack_water=args.crack_water, **loads)
    if args.json:
        print(json.dumps(theory_json(soil, wall, rows, args.passive, ground=ground, **loads), indent=2))
    else:
        _console().print(theory_text(soil, wall, rows, args.passive, ground=ground, **loads))
    if args.plot:
        from viz.figures import plot_theory_profiles
        plot_theory_profiles(rows, wall, args.plot)
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def _read_toml(name: str, path: str) -> dict:
    """A TOML file as a dict, or InvalidParameter naming the option (one line, exit 2)."""
    import tomllib

    from analytic.errors import InvalidParameter
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except OSError as err:
        raise InvalidParameter(name, path, "a readable TOML file", err.strerror or type(err).__name__) from None
    except UnicodeDecodeError:
        raise InvalidParameter(name, path, "a readable TOML file", "not text") from None
    except tomllib.TOMLDecodeError as err:
        raise InvalidParameter(name, path, "a valid TOML file", str(err).splitlines()[0]) from None


def _add_dsm(sub):
    p = sub.add_parser("dsm", help="differential slice method (Nadukuru & Michalowski 2012)",
                       description="Wall load distribution by the differential slice method, against "
                                   "the paper's Table 3 and Fang & Ishibashi's tests.")
    p.add_argument("--mode", choices=["T", "RB", "RT"], default="T",
                   help="T translation, RB rotation about the base, RT rotation about the top (T)")
    p.add_argument("--phi", type=_number("phi", 0, 90, unit="deg"), default=None,
                   help="friction angle [deg] (the mode's own: T 34, RB 33.4, RT 40.4)")
    p.add_argument("--delta", type=_number("delta", 0, 90, lo_open=False, unit="deg"), default=24.7,
                   help="wall friction [deg], 0 <= delta (the slices' shear acts down the wall) (24.7)")
    p.add_argument("--H", type=_number("H", 0, None, unit="m"), default=3.1, help="wall height [m] (3.1)")
    p.add_argument("--gamma", type=_number("gamma", 0, None, unit="kN/m^3"), default=16.7,
                   help="unit weight [kN/m^3] (16.7)")
    p.add_argument("--theta-r", default=None, metavar="DEG|max|local",
                   help="slip surface: planar at DEG from vertical, 'max' (plane of maximum DSM load), "
                        "'local' (curved, 45 - phi*/2); default: the mode's own")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", type=_output_file("plot"), help="draw the three modes like Fig. 8")
    p.set_defaults(func=_cmd_dsm)


def _cmd_dsm(args) -> int:
    from analytic.errors import InvalidParameter
    from analytic.slices import MODES, mode_case, solve
    from studies.report import dsm_json, dsm_text

    from analytic.inputs import require_number

    theta = args.theta_r
    if theta not in (None, "max", "local"):
        if not _is_float(theta):
            raise InvalidParameter("theta-r", theta, "(0, 90) deg, 'max' or 'local'")
        theta = require_number("theta-r", theta, 0, 90, unit="deg")
    case = mode_case(args.mode, phi_deg=args.phi, delta_deg=args.delta, H=args.H, gamma=args.gamma * 1e3,
                     theta_r_deg=theta)
    result = solve(case)
    preset = MODES[args.mode]
    if args.json:
        out = dsm_json(args.mode, result, preset)
        out["phi_deg"] = case.phi_deg
        print(json.dumps(out, indent=2))
    else:
        _console().print(dsm_text(args.mode, result, preset, case))
    if args.plot:
        from viz.figures import plot_dsm_modes
        results = {m: (result if m == args.mode else solve(mode_case(m, delta_deg=args.delta, H=args.H,
                                                                        gamma=args.gamma * 1e3)))
                   for m in MODES}
        plot_dsm_modes(results, MODES, args.plot)
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def _add_design(sub):
    p = sub.add_parser("design", help="design checks of a retaining wall (EN 1997-1, EN 1998-5, factors of safety)",
                       description="Sliding, overturning, bearing and eccentricity of a cantilever, gravity or "
                                   "block wall described in WALL.toml; --solve sizes the toe, heel or base.")
    p.add_argument("wall_file", metavar="WALL.toml", help="wall, backfill, foundation, loads, method tables")
    p.add_argument("--format", choices=["DA1", "DA2", "DA3", "EQU", "fs", "seismic", "all"], default="DA1",
                   help="verification format (DA1)")
    p.add_argument("--solve", choices=["toe", "heel", "base"], default=None,
                   help="find the smallest toe, heel or base width passing every check of the format")
    p.add_argument("--factors", metavar="FACTORS.toml", default=None,
                   help="partial factors replacing the EN 1997-1 Annex A table (same layout)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", type=_output_file("plot"),
                   help="draw the wall, pressures, forces and base pressure")
    p.set_defaults(func=_cmd_design)



def _cmd_design(args) -> int:
    from analytic.design.config import case_from_dict
    from analytic.design.factors import Factors, load_factors
    from analytic.design.formats import verify
    from analytic.design.report import design_json, design_text
    from analytic.design.sizing import solve

    case = case_from_dict(_read_toml("WALL.toml", args.wall_file))
    factors = Factors.from_dict(_read_toml("--factors", args.factors)) if args.factors else load_factors()
    fmts = ["DA1", "DA2", "DA3", "EQU", "fs", "seismic"] if args.format == "all" else [args.format]
    skipped = {}
    if args.format == "all" and not case.seismic.given:
        fmts.remove("seismic")
        skipped["seismic"] = "no [seismic] table (alpha, S, r; EN 1998-5 7.3.2.2)"
    if args.solve:
        case = solve(case, factors, fmts, args.solve)
    results = {f: verify(case, factors, f) for f in fmts}
    if args.solve:
        check, combo, u = max((r.governing for r in results.values()), key=lambda g: g[2])
        print(f"solved {args.solve} = {_solved(case.wall, args.solve):.4f} m (B = {case.wall.B:.4f} m); "
              f"governing: {check} ({combo}), utilisation {u:.4f}", file=sys.stderr)
    out = {f: design_json(case, r, factors.fs if f == "fs" else None) for f, r in results.items()}
    ran = "formats run: " + ", ".join(fmts) + "".join(f"; {f} skipped: {why}" for f, why in skipped.items())
    if args.json:
        print(json.dumps(out[fmts[0]] if len(fmts) == 1 else out | {"skipped_formats": skipped}, indent=2))
    else:
        print("\n\n".join(design_text(case, r) for r in results.values()))
        if args.format == "all":
            print(ran)
    if args.plot:
        from viz.figures import plot_wall_design
        plot_wall_design(case, results[fmts[0]], args.plot)
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def _solved(wall, name: str) -> float:
    return wall.B if name == "base" else getattr(wall, name)


def _length_or_inf(text: str) -> float:
    if text.strip().lower() in ("inf", "strip"):
        return float("inf")
    return _number("L", 0, None, unit="m")(text)


def _add_bearing(sub):
    p = sub.add_parser("bearing", help="bearing resistance of a footing (EN 1997-1 Annex D or Vesic)",
                       description="Drained bearing resistance under an inclined, eccentric load. "
                                   "V and H per metre for a strip (L = inf), totals otherwise. "
                                   "Range of validity: the inclination factors stay in [0, 1] up to "
                                   "H_lim = (V + A' c' cot phi') (1 - Nq^(-1/m)) for c' > 0 (where i_c reaches "
                                   "0), H_lim = V for c' = 0 (where i_q does); at H >= H_lim the bearing fails, "
                                   "said with H_lim, never a negative resistance. No depth factors (Annex D "
                                   "has none); base inclination factors 1 (horizontal base).")
    p.add_argument("--phi", type=_number("phi", 0, 50, hi_open=False, unit="deg"), required=True,
                   help="friction angle [deg], (0, 50]")
    p.add_argument("--c", type=_number("c", 0, None, lo_open=False, unit="kPa"), default=0.0, help="c' [kPa] (0)")
    p.add_argument("--gamma", type=_number("gamma", 0, None, unit="kN/m3"), required=True,
                   help="unit weight below the base [kN/m3]")
    p.add_argument("--q", type=_number("q", 0, None, lo_open=False, unit="kPa"), default=0.0,
                   help="overburden at base level [kPa] (0)")
    p.add_argument("--B", type=_number("B", 0, None, unit="m"), required=True, help="width [m]")
    p.add_argument("--L", type=_length_or_inf, default=float("inf"), help="length [m] or inf (strip, default)")
    p.add_argument("--e", type=_number("e", None, None, unit="m"), default=0.0, help="eccentricity along B [m] (0)")
    p.add_argument("--V", type=_number("V", 0, None, unit="kN"), required=True, help="vertical load [kN or kN/m]")
    p.add_argument("--H", type=_number("H", 0, None, lo_open=False, unit="kN"), default=0.0,
                   help="horizontal load along B [kN or kN/m] (0)")
    p.add_argument("--method", choices=["ec7", "vesic"], default="ec7", help="factors (ec7)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=_cmd_bearing)


def _cmd_bearing(args) -> int:
    from analytic.design.bearing import bearing_resistance
    from analytic.design.report import bearing_json

    b = bearing_resistance(phi=args.phi, c=args.c, gamma=args.gamma, q=args.q, B=args.B, L=args.L, e=args.e,
                           V=args.V, H=args.H, method=args.method)
    out = bearing_json(b)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    unit = "kN/m" if b.L_eff == float("inf") else "kN"
    if b.fails:
        print(f"{b.fails}; q_ult = R = 0, B' = {b.B_eff:.3f} m")
    else:
        print(f"bearing ({b.method}): q_ult = {b.q_ult:.1f} kPa, R = {b.R:.1f} {unit}, B' = {b.B_eff:.3f} m "
              f"(valid up to H_lim = {b.H_limit:.4g} {unit})")
    print("  " + ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k}: {v}" for k, v in b.factors.items()))
    return 0


def _is_float(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


VERBS = {"compare": "run a DEM case and set it beside the theories",
         "calibrate": "calibrate DEM micro-parameters with virtual tests",
         "validate": "paper-scale validation runs written up in docs/validation/"}


def _verb_group(sub, verb: str):
    """The sub-subparsers of ``wallsim <verb>``, created on first use and shared by every
    study that has that command."""
    parser = sub.choices.get(verb)
    if parser is None:
        parser = sub.add_parser(verb, help=VERBS[verb], description=VERBS[verb])
        parser.add_subparsers(dest="study", required=True, parser_class=_Parser)
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))


def _argparse_type(parse, name: str):
    """A study option's parser as an argparse type (its one-line error kept)."""
    from analytic.errors import InvalidParameter

    def wrapped(text: str):
        try:
            return parse(text)
        except InvalidParameter as err:
            raise argparse.ArgumentTypeError(str(err)) from None
    wrapped.__name__ = name
    return wrapped


def _add_option(p, opt) -> None:
    """A study option; a case key's flag defaults to "not given" so that only what the
    user typed overrides the config file (studies/study.py, precedence)."""
    kw = {"help": opt.help, "dest": opt.dest}
    if not opt.flag.startswith("-"):          # a positional case key, e.g. WALL.toml
        p.add_argument(opt.dest, help=opt.help, metavar=opt.metavar, nargs="?",
                       type=_argparse_type(opt.parse, opt.dest) if opt.parse else None, default=argparse.SUPPRESS)
        return
    if opt.switch:
        kw["action"] = "store_true"
    else:
        if opt.parse is not None:
            kw["type"] = _argparse_type(opt.parse, opt.dest)
        if opt.choices:
            kw["choices"] = list(opt.choices)
        if opt.metavar:
            kw["metavar"] = opt.metavar
        if opt.optional:
            kw |= {"nargs": "?", "const": True}
    kw["default"] = argparse.SUPPRESS if opt.key is not None else opt.default
    p.add_argument(opt.flag, **kw)


#: flags that were renamed so every study spells them alike: old -> new
RENAMED_FLAGS = {"--out-dir": "--docs"}


class _Renamed(argparse.Action):
    """An old flag: stop with one line that gives its new name."""

    def __call__(self, parser, namespace, values, option_string=None):
        parser.error(f"{option_string} is now {RENAMED_FLAGS[option_string]}")


def _add_study_command(sub, study, cmd) -> None:
    """``wallsim <verb> <study>`` with the command's options and the ones every run shares."""
    from studies.options import output_folder

    p = _verb_group(sub, cmd.verb).add_parser(study.name, help=cmd.help, description=cmd.description)
    for opt in cmd.options:
        _add_option(p, opt)
    for old, new in RENAMED_FLAGS.items():
        if any(o.flag == new for o in cmd.options):
            p.add_argument(old, action=_Renamed, nargs="?", help=argparse.SUPPRESS)
    if cmd.seed_key is not None:
        p.add_argument("--seed", default=argparse.SUPPRESS, metavar="SEED",
                       help=f"random seed ({cmd.seed_default})")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", default=[],
                   help="override any case field (after --config and the flags); `wallsim keys "
                        f"{study.name}` lists them")
    p.add_argument("--config", metavar="FILE.toml", help="case settings from a TOML file (before the flags)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--out", default="runs", metavar="DIR", type=_argparse_type(output_folder("out"), "out"),
                   help="root of the run folders (runs)")
    if cmd.figures is not None and cmd.seed_key is not None:
        _add_seeds_options(p)
    p.set_defaults(func=lambda args: _cmd_study(cmd, args))


def _add_seeds_options(p) -> None:
    """--seeds (and where its runs go) for a command that declares figures."""
    from studies.seeds import parse_seeds
    p.add_argument("--seeds", type=_argparse_type(parse_seeds, "seeds"), default=None, metavar="A..B|S1,S2",
                   help="run once per seed on Dask (one run folder each under --out) and report each figure's "
                        "mean +- sd over the seeds against the paper's tolerance (<docs>/<study>_seeds.md)")
    p.add_argument("--workers", type=_count("workers"), default=None,
                   help="with --seeds: worker processes of the local cluster (the cores)")
    from studies.options import scheduler_address
    p.add_argument("--scheduler", metavar="ADDRESS", type=_argparse_type(scheduler_address("scheduler"), "scheduler"),
                   help="with --seeds: an existing Dask cluster, e.g. tcp://host:8786")


def typed_flags(cmd, args) -> dict:
    """Case key -> value of the case flags the user typed (the others are absent from ``args``)."""
    return {o.key: (o.to_case(getattr(args, o.dest)) if o.to_case else getattr(args, o.dest))
            for o in cmd.options if o.key is not None and hasattr(args, o.dest)}


def case_from_args(cmd, args):
    """The case a study command runs: only the flags the user typed count (the others
    are absent from ``args``), then ``cmd.resolve`` applies the precedence rule."""
    flags = typed_flags(cmd, args)
    names = {o.key: o.flag for o in cmd.options if o.key is not None}
    if hasattr(args, "seed"):
        flags[cmd.seed_key] = args.seed
        names[cmd.seed_key] = "--seed"
    return cmd.resolve(config=args.config, flags=flags, sets=args.set, resume=getattr(args, "resume", None),
                       study=args.study, flag_names=names)


def _setting_sources(cmd, args) -> dict[str, str]:
    from studies.config import setting_sources
    typed = {o.key: o.flag for o in cmd.options if o.key is not None and hasattr(args, o.dest)}
    if hasattr(args, "seed"):
        typed[cmd.seed_key] = "--seed"
    return setting_sources(args.config, typed, args.set, typed)


def _cmd_study(cmd, args) -> int:
    from analytic.errors import InvalidParameter
    from studies.runner import finished_result

    if getattr(args, "seeds", None) is not None and not any(o.flag == "--seeds" for o in cmd.options):
        return _cmd_seeds(cmd, args)
    if getattr(args, "workers", None) is not None or getattr(args, "scheduler", None) is not None:
        raise InvalidParameter("--workers/--scheduler", args.workers or args.scheduler, "only with --seeds")
    case = case_from_args(cmd, args)
    resume = getattr(args, "resume", None)
    if resume is not None and finished_result(resume) is not None:
        print(f"{resume} holds a finished run (result.json): nothing to resume", file=sys.stderr)
        return 0
    opts = cmd.run_options(**{o.dest: getattr(args, o.dest) for o in cmd.options if o.key is None},
                           out=args.out, quiet=args.quiet)
    _check_run_options(opts)
    cmd.check_fits(case)
    if cmd.busy_note and not getattr(opts, "report_only", False):     # a rewrite runs no DEM
        _note_if_busy()
    with cmd.envelope(case, _setting_sources(cmd, args), opts):
        result, where = cmd.run(case, opts)
    if args.json:
        from studies.store import to_plain
        print(json.dumps(to_plain(result), indent=2, default=str))     # NaN -> null: JSON has no NaN
    else:
        shown = cmd.text(result)
        if shown is not None:
            _console().print(shown)
    if where:
        print(where, file=sys.stderr)
    return 0


def _check_run_options(opts) -> None:
    """Run options that contradict each other or name a folder that cannot be written:
    refused before any work and any folder."""
    from analytic.errors import InvalidParameter
    from studies.options import writable_root

    if isinstance(getattr(opts, "rrd", None), str) and getattr(opts, "no_rrd", False):
        raise InvalidParameter("--rrd", opts.rrd, "a recording path without --no-rrd", "the two contradict")
    writable_root("out", opts.out)
    if getattr(opts, "resume", None):        # before the busy-machine note: a refusal is one line
        from studies.runner import refuse_new_recording
        refuse_new_recording(opts.resume, bool(getattr(opts, "vtk", False)))


def _cmd_seeds(cmd, args) -> int:
    """``--seeds``: the command once per seed on Dask, the seeds report (studies/seeds.py)."""
    from analytic.errors import InvalidParameter
    from studies.store import to_plain
    from studies.seeds import run_seeds, seeds_text

    if hasattr(args, "seed"):
        raise InvalidParameter("--seed", args.seed, "none when --seeds is given", "--seeds names every seed")
    import time
    options = {o.dest: getattr(args, o.dest) for o in cmd.options if o.key is None}
    started = time.time()
    try:
        report = run_seeds(args.study, args.seeds, verb=cmd.verb, config=args.config, flags=typed_flags(cmd, args),
                           sets=args.set,
                           options=options, out=args.out, workers=args.workers, scheduler=args.scheduler,
                           quiet=args.quiet)
    except KeyboardInterrupt:
        print(f"wallsim: interrupted; {_finished_since(args.out, args.study, started, 'seeds')}", file=sys.stderr)
        return EXIT_INTERRUPTED
    print(json.dumps(to_plain(report), indent=2) if args.json else seeds_text(report))
    failed = [p for p in report["points"] if p["status"] == "failed"]
    for p in failed:
        print(f"wallsim: seed {p['seed']} failed: {p['error']}", file=sys.stderr)
    print(f"seeds report: {report['paths']['md']}", file=sys.stderr)
    return 1 if failed else 0


def _finished_since(out: str, study: str, started: float, what: str) -> str:
    """What an interrupted sweep left, from the files that exist: the finished runs
    (result.json written since ``started``) and sweep.csv, or that nothing was written."""
    from pathlib import Path
    root = Path(out) / study
    done = [p for p in root.glob("*/result.json") if p.stat().st_mtime >= started] if root.is_dir() else []
    table = Path(out) / "sweep.csv"
    if not done and not (table.is_file() and table.stat().st_mtime >= started):
        return "nothing was written"
    said = f"{len(done)} finished {what} in their run folders under {root}"
    if table.is_file() and table.stat().st_mtime >= started:
        said += f", and {table}"
    return said + "; the same command runs the rest"


def _note_if_busy() -> None:
    from studies.progress import busy_machine_note

    note = busy_machine_note()
    if note:
        sys.stderr.write(note + "\n")


def _add_sweep(sub) -> None:
    from studies import NAMES
    from studies.options import output_folder, scheduler_address

    p = sub.add_parser("sweep", help="a study over the product of varied settings and seeds, on Dask",
                       description="Every point of --vary (Cartesian product) run by the study's main command, "
                                   "one Dask task and one run folder each under --out; sweep.csv, "
                                   "sweep_groups.csv (mean, sd, min, max over seeds), sweep.json, sweep.png. "
                                   "A rerun skips the points that finished.")
    p.add_argument("study", choices=list(NAMES))
    p.add_argument("--vary", action="append", required=True, metavar="KEY=V1,V2|KEY=A..B",
                   help="a case key and its values (repeatable), e.g. --vary seed=1..3 --vary mode=T,RB")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", default=[],
                   help="a case field for every point (after --config, before --vary)")
    p.add_argument("--config", metavar="FILE.toml", help="case settings for every point from a TOML file")
    p.add_argument("--option", action="append", metavar="NAME[=VALUE]", default=[],
                   help="a run option of the study's command for every point, as its flag without the dashes "
                        "(repeatable), e.g. --option no-rrd, --option every=10")
    p.add_argument("--outputs", metavar="NAME,NAME", type=lambda t: [w.strip() for w in t.split(",") if w.strip()],
                   help="outputs to tabulate and draw (default: every number of the result's 'dem' record)")
    p.add_argument("--workers", type=_count("workers"), default=None,
                   help="worker processes of the local cluster (the cores)")
    p.add_argument("--scheduler", metavar="ADDRESS", type=_argparse_type(scheduler_address("scheduler"), "scheduler"),
                   help="an existing Dask cluster, e.g. tcp://host:8786")
    p.add_argument("--out", default="sweeps", metavar="DIR", type=_argparse_type(output_folder("out"), "out"),
                   help="run folders (DIR/<study>/<point>) and the sweep tables (sweeps)")
    p.add_argument("--json", action="store_true", help="print {points, groups} as JSON on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_sweep)


def _cmd_sweep(args) -> int:
    from studies import get
    from studies.sweep import parse_options, parse_vary, run_sweep, sweep_text

    import time
    varied, options = parse_vary(args.vary), parse_options(get(args.study).command(), args.option)
    started = time.time()
    try:
        table = run_sweep(args.study, varied, config=args.config, sets=args.set, out=args.out, workers=args.workers,
                          scheduler=args.scheduler, quiet=args.quiet, outputs=args.outputs, options=options or None)
    except KeyboardInterrupt:
        print(f"wallsim: interrupted; {_finished_since(args.out, args.study, started, 'points')}", file=sys.stderr)
        return EXIT_INTERRUPTED
    from studies.store import to_plain
    print(json.dumps(to_plain(table), indent=2) if args.json else sweep_text(table))     # NaN -> null
    failed = [p for p in table["points"] if p["status"] == "failed"]
    for p in failed:
        print(f"wallsim: point {p['point']} failed: {p['error']}", file=sys.stderr)
    print(f"sweep table: {os.path.join(args.out, 'sweep.csv')}", file=sys.stderr)
    return 1 if failed else 0


def _add_keys(sub) -> None:
    from studies import NAMES

    p = sub.add_parser("keys", help="the settable keys of a study's case (for --set and --config)",
                       description="Every key of the case with its default and meaning, as --set KEY=VALUE "
                                   "and a --config TOML file take them (tables for dotted keys).")
    p.add_argument("study", choices=list(NAMES))
    p.add_argument("--verb", default=None, help="the command whose case to list (the study's first)")
    p.add_argument("--json", action="store_true", help="key, default, unit, valid, meaning of every key as JSON")
    p.set_defaults(func=_cmd_keys)


def _cmd_keys(args) -> int:
    from studies import get
    from studies.config import describe_keys

    cmd = get(args.study).command(args.verb)
    rows = describe_keys(cmd.default_case())
    if args.json:
        from studies.store import to_plain
        print(json.dumps([to_plain(r) for r in rows], indent=2))
        return 0
    for r in rows:      # two lines a key: nothing is cut, whatever the terminal's width
        default = ", ".join(map(str, r.default)) if isinstance(r.default, tuple) else str(r.default)
        unit = "" if r.unit in ("-", "") else f" [{r.unit}]"
        print(f"{r.key}{unit} = {default}    valid: {r.valid}")
        print(f"    {r.meaning}")
    return 0


def _add_studies(sub) -> None:
    from studies import all_studies

    for study in all_studies():
        for cmd in study.commands:
            _add_study_command(sub, study, cmd)


def _console():
    from rich.console import Console
    return Console()


def _add_bench(sub):
    p = sub.add_parser("bench", help="speed benchmarks", description="Speed benchmarks against reference codes.")
    targets = p.add_subparsers(dest="target", required=True, parser_class=_Parser)
    d = targets.add_parser("dem3d", help="dem3d vs LIGGGHTS on the settled-packing problem",
                           description="Time dem3d and LIGGGHTS on benchmarks/liggghts (same contact law, "
                                       "walls, periodic y, dt 2e-5) and print particle-steps/s and their ratio.")
    d.add_argument("--n", type=int, choices=[10_000, 30_000], default=30_000, help="spheres (30000)")
    d.add_argument("--steps", type=_count("steps"), default=5_000, help="time steps (5000)")
    d.add_argument("--threads", type=int, choices=[1, 2], default=2, help="numba threads for dem3d (2)")
    d.add_argument("--liggghts-ranks", type=int, choices=[1, 2], default=None,
                   help="MPI processes for LIGGGHTS (default: as many as --threads, core for core)")
    d.add_argument("--no-liggghts", action="store_true", help="time dem3d only")
    d.add_argument("--direct-sums", action="store_true",
                   help="dem3d adds each pair's force on its second sphere in the contact pass "
                        "(Simulation direct_sums; other bits, off by default)")
    d.add_argument("--pairs", type=_count("pairs"), default=3,
                   help="interleaved pairs, dem3d then LIGGGHTS each (3): medians and min-max")
    d.add_argument("--scaling", action="store_true",
                   help="also time 10k, 30k and 100k spheres (the 10k packing tiled) for --steps/10 steps")
    d.add_argument("--json", action="store_true", help="machine-readable output")
    d.set_defaults(func=_cmd_bench_dem3d)


def _count_value(name: str):
    from studies.options import count
    return count(name)


def _count(name: str):
    return _argparse_type(_count_value(name), name)


def _cmd_bench_dem3d(args) -> int:
    from studies.bench import bench_dem3d, scaling

    result = bench_dem3d(args.n, args.steps, args.threads, liggghts=not args.no_liggghts, ranks=args.liggghts_ranks,
                         pairs=args.pairs, direct_sums=args.direct_sums)
    rows = scaling(max(1, args.steps // 10), args.threads) if args.scaling else None
    if args.json:
        if rows is not None:
            result["scaling"] = rows
        print(json.dumps(result, indent=2))
        return 0
    spread = result["spread"]
    print(f"dem3d benchmark: {result['n']} spheres x {result['steps']} steps, dem3d on {result['threads']} thread(s)"
          f"{' with direct sums' if result['direct_sums'] else ''}, {result['pairs']} interleaved run(s) each; "
          f"median (min-max)")

    def line(name: str, key: str, cpu: str, extra: str = "") -> None:
        s, c = spread[key], spread[cpu]
        print(f"  {name:8s} {s['median']:10.3e} particle-steps/s ({s['min']:.3e}-{s['max']:.3e}); "
              f"CPU {c['median']:.2f} s ({c['min']:.2f}-{c['max']:.2f}){extra}")

    line("wallsim", "wallsim_particle_steps_per_s", "wallsim_cpu_seconds", " in the stepping loop")
    if result["liggghts_particle_steps_per_s"] is not None:
        ranks = result["liggghts_ranks"]
        line("LIGGGHTS", "liggghts_particle_steps_per_s", "liggghts_cpu_seconds",
             f" for the process, set-up included ({ranks} MPI process{'es' if ranks > 1 else ''})")
        r = spread["ratio"]
        print(f"  ratio    {r['median']:.2f} ({r['min']:.2f}-{r['max']:.2f}), pair by pair")
        w, lg = result["check"]["wallsim"], result["check"]["liggghts"]
        print(f"  check: kinetic energy {w['kinetic_energy_J']:.4g} vs {lg['kinetic_energy_J']:.4g} J, "
              f"rotational {w['rotational_energy_J']:.4g} vs {lg['rotational_energy_J']:.4g} J, "
              f"contacts {w['contacts']} vs {lg['contacts']}")
    for row in rows or []:
        print(f"  N = {row['n']:6d}: {row['ms_per_step']:7.3f} ms/step, {row['ns_per_particle_step']:6.1f} ns per "
              f"particle-step ({row['steps']} steps)")
    return 0


def _add_env(sub):
    p = sub.add_parser("env", help="the reproducibility mode: same bits where, and how to get it in Python",
                       description="Which mode this command runs in (portable unless "
                                   "WALLSIM_REPRODUCIBILITY=native) and what each library was found doing. "
                                   "--exports prints the settings that put your own Python (a notebook) in "
                                   "the portable mode: eval \"$(wallsim env --exports)\" before starting it.")
    p.add_argument("--exports", action="store_true", help="print the portable settings as shell export lines")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=_cmd_env)


def _cmd_env(args) -> int:
    if args.exports:
        print(reproducibility.shell_exports())
        return 0
    mode = reproducibility.describe()
    if args.json:
        print(json.dumps(mode, indent=2))
        return 0
    blas = mode["openblas"]
    simd = mode["numpy_simd"]
    print(f"mode: {mode['mode']}: the same bits {mode['same_bits']}")
    print(f"  libm variant: {mode['libm']}; numpy SIMD: {simd if isinstance(simd, str) else ', '.join(simd)}; "
          f"OpenBLAS core: {blas['OPENBLAS_CORETYPE'] or 'by CPU'}, threads: {blas['OPENBLAS_NUM_THREADS'] or 'all'}")
    print(f"  CPU: {mode['cpu']}")
    print('  your own Python in the portable mode: eval "$(wallsim env --exports)", then start it')
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="wallsim", description="Earth pressure on retaining walls: theory and DEM.")
    parser.add_argument("--version", action="version", version=f"wallsim {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    _add_theory(sub)
    _add_dsm(sub)
    _add_design(sub)
    _add_bearing(sub)
    _add_studies(sub)
    _add_sweep(sub)
    _add_keys(sub)
    _add_bench(sub)
    _add_env(sub)
    return parser


def _version() -> str:
    try:
        from importlib.metadata import version
        return version("wallsim")
    except Exception:
        return "unknown"


EXIT_INTERRUPTED = 130        # 128 + SIGINT, as a shell reports it
EXIT_BROKEN_PIPE = 141        # 128 + SIGPIPE


def main(argv: list[str] | None = None) -> int:
    from analytic.errors import InvalidParameter

    interrupts = _watch_interrupts()
    try:
        parser = build_parser()
        if not (sys.argv[1:] if argv is None else argv):
            parser.print_help(sys.stderr)       # no command: what there is to run, not only an error
            return EXIT_BAD_INPUT
        args = parser.parse_args(argv)
        return args.func(args)
    except InvalidParameter as err:
        sys.stderr.write(f"wallsim: error: {err}\n")
        return EXIT_BAD_INPUT
    except KeyboardInterrupt as err:
        return _interrupted(argv, getattr(err, "folder", None))
    except BrokenPipeError:
        return _reader_went_away()
    except Exception:
        if interrupts:            # Ctrl-C landed in a C callback (numba's first compile) and
            return _interrupted(argv)   # surfaced as another error: still an interrupt
        raise


def _watch_interrupts() -> list:
    """Record every Ctrl-C (still raising KeyboardInterrupt). A KeyboardInterrupt that a
    C callback swallows (numba's first compile: "Exception ignored on calling ctypes
    callback", and the run went on) is raised again once Python code runs: the run
    stops with one line either way. Nothing changes when the process ignores Ctrl-C or
    main runs outside the main thread."""
    import signal
    import threading

    seen: list = []
    if threading.current_thread() is not threading.main_thread() or \
            signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        return seen

    def on_sigint(signum, frame):
        seen.append(signum)
        raise KeyboardInterrupt

    def again(signum, frame):
        raise KeyboardInterrupt

    def unraisable(u):
        if issubclass(u.exc_type, KeyboardInterrupt):
            # swallowed in a C callback: raise it again 50 ms on, from a timer, so it lands
            # in Python code (swallowed again, it comes back again)
            signal.signal(signal.SIGALRM, again)
            signal.setitimer(signal.ITIMER_REAL, 0.05)
        else:
            default_hook(u)

    signal.signal(signal.SIGINT, on_sigint)
    default_hook = sys.unraisablehook
    sys.unraisablehook = unraisable
    return seen


def _interrupted(argv, folder=None) -> int:
    from studies.runner import interrupted_line
    words = list(sys.argv[1:] if argv is None else argv)
    sys.stderr.write(f"wallsim: {interrupted_line(_resume_command(argv), folder, reruns=words[:1] == ['validate'])}\n")
    return EXIT_INTERRUPTED


def _reader_went_away() -> int:
    """stdout's reader closed early (``wallsim ... --json | head``): no traceback; point
    stdout at /dev/null so the final flush cannot fail again, exit as a shell would."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    return EXIT_BROKEN_PIPE


def _resume_command(argv: list[str] | None) -> str | None:
    """'wallsim compare nadukuru' when the interrupted command takes --resume, else None."""
    words = list(sys.argv[1:] if argv is None else argv)[:2]
    if len(words) == 2 and words[0] in VERBS:
        from studies import NAMES, get
        commands = [c for c in get(words[1]).commands if c.verb == words[0]] if words[1] in NAMES else []
        if commands and any(o.flag == "--resume" for o in commands[0].options):
            return "wallsim " + " ".join(words)
    return None


def entry() -> None:
    """The ``wallsim`` console script: ``main``, then leave without Python's teardown.

    Freeing a large pymunk space is quadratic: pymunk removes every shape, and each
    removal scans chipmunk's whole cached-contact table (never shrunk), so the full-size
    Khosravi fill (63,548 disks) took ~4 min of CPU to exit after its report was written
    (40k disks in contact: 60 s). Every file and recording is written and closed by
    then (viz.recorder flushes and disconnects), so nothing is lost by skipping it.

    First of all, the process re-starts itself in the portable mode unless
    WALLSIM_REPRODUCIBILITY=native (reproducibility.py): the settings act only in a
    process that starts with them."""
    try:
        reproducibility.enter_requested_mode()
    except ValueError as err:
        sys.stderr.write(f"wallsim: error: {err}\n")
        os._exit(EXIT_BAD_INPUT)
    code = main()
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        code = _reader_went_away()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    entry()
