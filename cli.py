"""wallsim command line: parse, dispatch, print. The work happens in the packages.

Bad input ends with one line on stderr naming the parameter and its valid range, and
exit code 2 -- never a traceback.
"""

from __future__ import annotations

import argparse
import json
import os
import sys

from analytic.errors import InvalidParameter

EXIT_BAD_INPUT = 2


class _Parser(argparse.ArgumentParser):
    """argparse that reports a usage error in one line (no usage dump)."""

    def error(self, message: str):  # noqa: D401 - argparse API
        sys.stderr.write(f"{self.prog}: error: {message}\n")
        sys.exit(EXIT_BAD_INPUT)


def _number(name: str, lo=None, hi=None, *, lo_open=True, hi_open=True, unit=""):
    """argparse type: a finite float in a range, with a one-line message naming both."""
    from analytic.inputs import require_number

    def parse(text: str) -> float:
        try:
            return require_number(name, text, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit)
        except InvalidParameter as err:
            raise argparse.ArgumentTypeError(str(err)) from None
    parse.__name__ = name
    return parse


def _add_theory(sub):
    p = sub.add_parser("theory", help="closed-form and arching earth pressure for one wall",
                       description="Every closed-form and arching method side by side. "
                                   "Defaults: Nadukuru & Michalowski's translation case.")
    p.add_argument("--phi", type=_number("phi", 0, 90, unit="deg"), default=34.0, help="friction angle [deg] (34)")
    p.add_argument("--delta", type=_number("delta", -90, 90, unit="deg"), default=24.7,
                   help="wall friction angle [deg], |delta| <= phi (24.7)")
    p.add_argument("--H", type=_number("H", 0, None, unit="m"), default=3.1, help="wall height [m] (3.1)")
    p.add_argument("--gamma", type=_number("gamma", 0, None, unit="kN/m^3"), default=16.7,
                   help="unit weight [kN/m^3] (16.7)")
    p.add_argument("--beta", type=_number("beta", -90, 90, unit="deg"), default=0.0,
                   help="backfill slope [deg], + rising away from the wall (0)")
    p.add_argument("--omega", type=_number("omega", -90, 90, unit="deg"), default=0.0,
                   help="back-face inclination from vertical [deg], + heel under the fill (0)")
    p.add_argument("--q", type=_number("q", 0, None, lo_open=False, unit="kPa"), default=0.0,
                   help="surcharge [kPa] (0)")
    p.add_argument("--kh", type=_number("kh", 0, 1, lo_open=False), default=0.0, help="horizontal seismic coefficient (0)")
    p.add_argument("--kv", type=_number("kv", -1, 1), default=0.0, help="vertical seismic coefficient, + upward (0)")
    p.add_argument("--width", type=_number("width", 0, None, unit="m"), default=None,
                   help="backfill width B for Janssen's slot [m] (default: H)")
    p.add_argument("--ps-exponent", choices=["iii", "i"], default="iii",
                   help="Paik-Salgado profile exponent form (see analytic/arching.py)")
    p.add_argument("--passive", action="store_true", help="passive instead of active")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", help="draw sigma_h(z) of every method")
    p.set_defaults(func=_cmd_theory)


def _cmd_theory(args) -> int:
    from analytic import Soil, Wall
    from analytic.summary import theory_table
    from workflows.report import theory_json, theory_text

    soil = Soil(args.phi, args.gamma * 1e3)
    wall = Wall(args.H, args.delta, args.omega, args.beta, args.q * 1e3)
    rows = theory_table(soil, wall, kh=args.kh, kv=args.kv, passive=args.passive,
                        width=args.width, ps_exponent=args.ps_exponent)
    if args.json:
        print(json.dumps(theory_json(soil, wall, rows, args.passive), indent=2))
    else:
        _console().print(theory_text(soil, wall, rows, args.passive))
    if args.plot:
        from viz.figures import plot_theory_profiles
        plot_theory_profiles(rows, wall, args.plot)
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def _add_dsm(sub):
    p = sub.add_parser("dsm", help="differential slice method (Nadukuru & Michalowski 2012)",
                       description="Wall load distribution by the differential slice method, against "
                                   "the paper's Table 3 and Fang & Ishibashi's tests.")
    p.add_argument("--mode", choices=["T", "RB", "RT"], default="T",
                   help="T translation, RB rotation about the base, RT rotation about the top (T)")
    p.add_argument("--phi", type=_number("phi", 0, 90, unit="deg"), default=None,
                   help="friction angle [deg] (the mode's own: T 34, RB 33.4, RT 40.4)")
    p.add_argument("--delta", type=_number("delta", -90, 90, unit="deg"), default=24.7, help="wall friction [deg] (24.7)")
    p.add_argument("--H", type=_number("H", 0, None, unit="m"), default=3.1, help="wall height [m] (3.1)")
    p.add_argument("--gamma", type=_number("gamma", 0, None, unit="kN/m^3"), default=16.7,
                   help="unit weight [kN/m^3] (16.7)")
    p.add_argument("--theta-r", default=None, metavar="DEG|max|local",
                   help="slip surface: planar at DEG from vertical, 'max' (plane of maximum DSM load), "
                        "'local' (curved, 45 - phi*/2); default: the mode's own")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", help="draw the three modes like Fig. 8")
    p.set_defaults(func=_cmd_dsm)


def _cmd_dsm(args) -> int:
    from analytic.slices import MODES, mode_case, solve
    from workflows.report import dsm_json, dsm_text

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
    p.add_argument("--plot", metavar="FILE.png", help="draw the wall, pressures, forces and base pressure")
    p.set_defaults(func=_cmd_design)


def _read_toml(path: str, name: str) -> dict:
    import tomllib
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except OSError as err:
        raise InvalidParameter(name, path, "a readable TOML file", err.strerror or str(err)) from None
    except tomllib.TOMLDecodeError as err:
        raise InvalidParameter(name, path, "a valid TOML file", str(err)) from None


def _cmd_design(args) -> int:
    from analytic.design.config import case_from_dict
    from analytic.design.factors import Factors, load_factors
    from analytic.design.formats import verify
    from analytic.design.report import design_json, design_text
    from analytic.design.sizing import solve

    case = case_from_dict(_read_toml(args.wall_file, "WALL.toml"))
    factors = Factors.from_dict(_read_toml(args.factors, "--factors")) if args.factors else load_factors()
    fmts = ["DA1", "DA2", "DA3", "EQU", "fs", "seismic"] if args.format == "all" else [args.format]
    if args.format == "all" and case.seismic.kh == 0:
        fmts.remove("seismic")
    if args.solve:
        case = solve(case, factors, fmts, args.solve)
    results = {f: verify(case, factors, f) for f in fmts}
    if args.solve:
        check, combo, u = max((r.governing for r in results.values()), key=lambda g: g[2])
        print(f"solved {args.solve} = {_solved(case.wall, args.solve):.4f} m (B = {case.wall.B:.4f} m); "
              f"governing: {check} ({combo}), utilisation {u:.4f}", file=sys.stderr)
    out = {f: design_json(case, r, factors.fs if f == "fs" else None) for f, r in results.items()}
    if args.json:
        print(json.dumps(out[fmts[0]] if len(fmts) == 1 else out, indent=2))
    else:
        print("\n\n".join(design_text(case, r) for r in results.values()))
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
                                   "V and H per metre for a strip (L = inf), totals otherwise.")
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
    print(f"bearing ({b.method}): q_ult = {b.q_ult:.1f} kPa, R = {b.R:.1f} {unit}, B' = {b.B_eff:.3f} m")
    print("  " + ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k}: {v}" for k, v in b.factors.items()))
    return 0


def _is_float(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


def _case_group(sub, name: str, help: str, description: str = ""):
    """The sub-subparsers of ``wallsim <name>`` (compare / calibrate / validate), created on
    first use and shared by every case that registers under it (other engines add theirs)."""
    parser = sub.choices.get(name)
    if parser is None:
        parser = sub.add_parser(name, help=help, description=description or help)
        parser.add_subparsers(dest="case", required=True, parser_class=_Parser)
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action
    raise RuntimeError(f"wallsim {name} has no sub-commands")


def _add_run_options(p, *, seed_default: int = 1):
    """Options every DEM command shares: seed, overrides, output, recording, progress."""
    p.add_argument("--seed", type=_count("seed"), default=seed_default, help=f"random seed ({seed_default})")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", default=[],
                   help="override any case field, e.g. --set clump_fraction=0 --set particle_friction=0.5")
    p.add_argument("--config", metavar="FILE.toml", help="case overrides from a TOML file (applied before --set)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--out", default="runs", metavar="DIR", help="root of the run folders (runs)")


def _add_compare_khosravi(sub):
    cases = _case_group(sub, "compare", "run a DEM case and set it beside the theories")
    k = cases.add_parser("khosravi", help="Khosravi et al.'s box: pluviation, at rest, translation to Dis/H = 0.003",
                         description="2D disks (pymunk) in a 220 x 400 mm box, rough wall of 40 pressure cells. "
                                     "Example: wallsim compare khosravi --H 0.3 --particles-scale 2 --rrd")
    k.add_argument("--H", type=_number("H", 0, 0.4, hi_open=False, unit="m"), default=0.3,
                   help="backfill height [m] (0.3; paper: 0.2, 0.25, 0.3)")
    k.add_argument("--particles-scale", type=_number("particles-scale", 0, None), default=1.0,
                   help="multiply every grain diameter (1 = D50 1.16 mm, ~62k disks at H 0.3; 2 = ~15k)")
    k.add_argument("--rrd", action="store_true", help="write recording.rrd (disks, walls, force chains)")
    k.add_argument("--no-cache", action="store_true", help="do not reuse or keep the settled specimen")
    _add_run_options(k)
    k.set_defaults(func=_cmd_compare_khosravi)


def _cmd_compare_khosravi(args) -> int:
    import dataclasses

    from dem2d.scenarios import KhosraviCase
    from workflows.config import apply_sets, apply_toml
    from workflows.khosravi import compare_khosravi

    case = KhosraviCase(H=args.H, particles_scale=args.particles_scale, seed=args.seed)
    if args.config:
        case = apply_toml(case, args.config)
    case = apply_sets(case, args.set)
    case = dataclasses.replace(case)  # re-validate after overrides
    result, rf = compare_khosravi(case, root=args.out, rrd=args.rrd, quiet=args.quiet,
                                  specimen_cache=not args.no_cache)
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        _print_khosravi(result)
    print(f"run folder: {rf.path}", file=sys.stderr)
    return 0


def _print_khosravi(res: dict) -> None:
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
    t.add_row("Dis/H steady (90 % of the drop)", f"{d['dis_over_H_steady']:.5f}", "paper 0.0002-0.0005; <= 0.003")
    t.add_row("floor + walls vertical / weight", f"{d['weight_balance']:.4f}", "1")
    _console().print(t)


def _add_calibrate(sub):
    tests = _case_group(sub, "calibrate", "calibrate DEM micro-parameters with virtual tests")
    b = tests.add_parser("biaxial", help="biaxial tests over frictions; the friction giving a target phi",
                         description="Khosravi et al. section 2: 70 x 200 mm specimen, servo lateral stress, "
                                     "axial compression. Example: wallsim calibrate biaxial --friction 0.3,0.5,0.7 "
                                     "--pressures 2,3,5 --particles-scale 2")
    b.add_argument("--friction", default="0.3,0.5,0.7", help="particle friction coefficients to test (0.3,0.5,0.7)")
    b.add_argument("--confining", type=_number("confining", 0, None, unit="kPa"), default=4.0,
                   help="confining stress for the friction sweep [kPa] (4)")
    b.add_argument("--pressures", default="", help="extra confining stresses [kPa] at the calibrated friction, e.g. 2,3,5")
    b.add_argument("--target-phi", type=_number("target-phi", 0, 90, unit="deg"), default=20.7,
                   help="friction angle to calibrate for [deg] (20.7)")
    b.add_argument("--particles-scale", type=_number("particles-scale", 0, None), default=1.0,
                   help="multiply every grain diameter (1 = D50 1.16 mm, ~12.7k disks)")
    b.add_argument("--card", metavar="FILE.json", help="also write the calibration card here")
    _add_run_options(b)
    b.set_defaults(func=_cmd_calibrate_biaxial)


def _cmd_calibrate_biaxial(args) -> int:
    import dataclasses

    from dem2d.biaxial import BiaxialCase
    from workflows.biaxial import CalibrationPlan, calibrate, parse_list
    from workflows.config import apply_sets, apply_toml

    base = BiaxialCase(particles_scale=args.particles_scale, seed=args.seed, confining=args.confining * 1e3)
    plan = CalibrationPlan(frictions=parse_list("friction", args.friction),
                           pressures=parse_list("pressures", args.pressures, 1e3) if args.pressures else (),
                           target_phi=args.target_phi, case=base)
    if args.config:
        plan = apply_toml(plan, args.config)
    plan = apply_sets(plan, args.set)
    plan = dataclasses.replace(plan, case=dataclasses.replace(plan.case))
    result, rf = calibrate(plan, root=args.out, quiet=args.quiet, card=args.card)
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        from rich.table import Table
        t = Table(title=f"Biaxial calibration (target phi {plan.target_phi:g} deg)", title_justify="left")
        for col in ("friction", "sigma_3 kPa", "phi peak", "eps peak", "phi cs", "eps to cs", "band deg",
                    "n", "grains"):
            t.add_column(col, justify="right")
        for r in result["tests"]:
            t.add_row(f"{r['friction']:.3f}", f"{r['confining'] / 1e3:g}", f"{r['phi_peak_deg']:.2f}",
                      f"{r['eps_peak']:.4f}", f"{r['phi_cs_deg']:.2f}", f"{r['eps_cs']:.4f}",
                      f"{r['band_angle_deg']:.0f}", f"{1 - r['solid_fraction_0']:.3f}", str(r["n_grains"]))
        _console().print(t)
        _console().print(f"calibrated friction for phi = {plan.target_phi:g} deg: {result['calibrated_friction']:.4f}")
    print(f"run folder: {rf.path}", file=sys.stderr)
    return 0


def _add_validate_khosravi(sub):
    cases = _case_group(sub, "validate", "full-size validation runs and their reports")
    k = cases.add_parser("khosravi", help="full-size Khosravi case -> docs/validation/khosravi.{json,md} + figures",
                         description="H = 0.3 m, D50 = 1.16 mm (~62k disks); the wall moves to Dis/H 0.01 and the active state is read at 0.003; about 55 min on a 2-core machine (pluviation at 40 sweeps ~13-17 min, at rest and translation to 0.01 at 80 sweeps ~38 min, a biaxial test for phi ~10 min when no card has one; docs/validation/khosravi.md).")
    k.add_argument("--out-dir", default="docs/validation", help="where the report goes (docs/validation)")
    k.add_argument("--rrd", action="store_true", help="also keep recording.rrd in the run folder")
    _add_run_options(k)
    k.set_defaults(func=_cmd_validate_khosravi)


def _cmd_validate_khosravi(args) -> int:
    import dataclasses

    from dem2d.scenarios import KhosraviCase
    from workflows.config import apply_sets, apply_toml
    from workflows.khosravi import VALIDATION_DIS_OVER_H, validate_khosravi

    case = KhosraviCase(seed=args.seed, dis_over_H_max=VALIDATION_DIS_OVER_H)
    if args.config:
        case = apply_toml(case, args.config)
    case = dataclasses.replace(apply_sets(case, args.set))
    report = validate_khosravi(out_dir=args.out_dir, root=args.out, quiet=args.quiet, case=case, rrd=args.rrd)
    if args.json:
        print(json.dumps(report, indent=2))
    else:
        _console().print(f"wrote {report['paths']['json']} and {report['paths']['md']}")
    return 0


def _add_recording_options(p):
    p.add_argument("--rrd", metavar="FILE", help="recording path (default: recording.rrd in the run folder)")
    p.add_argument("--no-rrd", action="store_true", help="write no recording")
    p.add_argument("--spawn", action="store_true", help="also open the Rerun viewer")
    p.add_argument("--every", type=_count("every"), default=5,
                   help="log the scene (particles, chains) every N x 500 steps (5)")


def _add_compare_nadukuru(sub):
    cases = _case_group(sub, "compare", "run a DEM case and set it beside the theories")
    p = cases.add_parser("nadukuru", help="Nadukuru & Michalowski's 3.1 m wall: four modes of movement (3D)",
                         description="Spheres and two-sphere clumps rained behind a 3.1 m wall of 6 segments; "
                                     "the wall translates or rotates to Delta/H = 0.008. DEM K and resultant "
                                     "height beside the paper, Fang & Ishibashi, Coulomb, Rankine and the DSM. "
                                     "Example: wallsim compare nadukuru --mode RT --wall rough --particles 6000")
    p.add_argument("--mode", choices=["T", "RB", "RT", "mixed"], default="T",
                   help="T translation, RB rotation about the base, RT about the top, "
                        "mixed about a point H/2 above the top (T)")
    p.add_argument("--wall", choices=["rough", "smooth"], default="rough",
                   help="wall friction 0.35 (rough) or 0 (smooth) (rough)")
    p.add_argument("--particles", type=_count("particles"), default=30_000,
                   help="spheres incl. clump members (30000 = paper scale; fewer scale the grains up)")
    p.add_argument("--resume", metavar="RUN_DIR",
                   help="continue an interrupted run from its folder (uses that folder's config.toml)")
    _add_recording_options(p)
    _add_run_options(p)
    p.set_defaults(func=_cmd_compare_nadukuru)


def _nadukuru_case(args):
    import dataclasses

    from workflows.config import apply_sets, apply_toml
    from workflows.nadukuru import Movement, NadukuruCase, SpecimenRecipe, WallSetup, rough_or_smooth

    case = NadukuruCase(specimen=SpecimenRecipe(particles=args.particles),
                        wall=WallSetup(friction=rough_or_smooth(args.wall)),
                        movement=Movement(mode=getattr(args, "mode", "T")), seed=args.seed)
    if args.config:
        case = apply_toml(case, args.config)
    return dataclasses.replace(apply_sets(case, args.set))


def _note_if_busy() -> None:
    from workflows.progress import busy_machine_note

    note = busy_machine_note()
    if note:
        sys.stderr.write(note + "\n")


def _cmd_compare_nadukuru(args) -> int:
    from pathlib import Path

    from workflows.nadukuru_run import compare_nadukuru
    from workflows.progress import progress
    from workflows.report import nadukuru_text

    _note_if_busy()

    if args.resume:
        args.config = str(Path(args.resume) / "config.toml")
        if not Path(args.config).exists():
            raise InvalidParameter("--resume", args.resume, "a run folder with a config.toml")
    case = _nadukuru_case(args)
    wall_kind = "smooth" if case.wall.friction == 0 else "rough"     # what the run really has
    with progress(args.quiet) as bar:
        result, folder = compare_nadukuru(case, wall_kind, root=Path(args.out), rrd=args.rrd,
                                          spawn=args.spawn, every=args.every, record=not args.no_rrd,
                                          progress=bar, resume=Path(args.resume) if args.resume else None)
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        _console().print(nadukuru_text(result))
    print(f"run folder: {folder}", file=sys.stderr)
    return 0


def _add_calibrate_triaxial(sub):
    tests = _case_group(sub, "calibrate", "calibrate DEM micro-parameters with virtual tests")
    p = tests.add_parser("triaxial", help="numerical triaxial test on the Nadukuru backfill mixture (3D)",
                         description="Cubical triaxial test (six servo platens, sigma_2 = sigma_3) on the "
                                     "sphere/clump mixture; peak and critical-state phi, written to a "
                                     "calibration card that `compare nadukuru` uses for its theories.")
    p.add_argument("--particles", type=_count("particles"), default=8200, help="spheres (8200, the paper's)")
    p.add_argument("--confining", type=_number("confining", 0, None, unit="kPa"), default=200.0,
                   help="confining stress [kPa] (200)")
    _add_run_options(p)
    p.set_defaults(func=_cmd_calibrate_triaxial, mode="T", wall="rough")


def _cmd_calibrate_triaxial(args) -> int:
    from pathlib import Path

    from workflows.progress import progress
    from workflows.triaxial import TriaxialSetup, calibrate_triaxial

    _note_if_busy()

    case = _nadukuru_case(args)
    with progress(args.quiet) as bar:
        card, path = calibrate_triaxial(case, TriaxialSetup(confining=args.confining * 1e3),
                                        particles=args.particles, root=Path(args.out), progress=bar)
    if args.json:
        print(json.dumps(card, indent=2))
    else:
        print(f"triaxial: peak phi {card['phi_peak_deg']:.1f} deg at axial strain {card['strain_at_peak']:.3f}, "
              f"end (critical-state estimate) {card['phi_end_deg']:.1f} deg; porosity {card['porosity']:.3f}; "
              f"{card['particles']} spheres, seed {card['seed']}, {card['wall_time_s']:.0f} s "
              f"(paper: 39 deg)")
    print(f"calibration card: {path}", file=sys.stderr)
    return 0


def _add_validate_nadukuru(sub):
    cases = _case_group(sub, "validate", "paper-scale validation runs written up in docs/validation/")
    p = cases.add_parser("nadukuru", help="all four modes, rough and smooth walls, at paper scale (hours)",
                         description="Triaxial calibration, one settled specimen per wall, the four modes and a "
                                     "half-speed translation; writes docs/validation/nadukuru.{md,json} and figures.")
    p.add_argument("--particles", type=_count("particles"), default=30_000, help="spheres (30000)")
    p.add_argument("--walls", default="rough,smooth", help="comma list of rough, smooth (rough,smooth)")
    p.add_argument("--modes", default="T,RB,RT,mixed", help="comma list of T, RB, RT, mixed (all)")
    p.add_argument("--no-triaxial", action="store_true",
                   help="skip the triaxial calibration (an existing card for the recipe is used)")
    p.add_argument("--no-rate-check", action="store_true", help="skip the half-speed repeat of translation")
    p.add_argument("--docs", default="docs/validation", metavar="DIR", help="where the report goes")
    _add_run_options(p)
    p.set_defaults(func=_cmd_validate_nadukuru, mode="T", wall="rough")


def _cmd_validate_nadukuru(args) -> int:
    from pathlib import Path

    from workflows.nadukuru import MODES
    from workflows.nadukuru_validate import validate_nadukuru
    from workflows.progress import progress

    _note_if_busy()

    walls = [w.strip() for w in args.walls.split(",") if w.strip()]
    modes = [m.strip() for m in args.modes.split(",") if m.strip()]
    for w in walls:
        if w not in ("rough", "smooth"):
            raise InvalidParameter("walls", w, "rough | smooth")
    for m in modes:
        if m not in MODES:
            raise InvalidParameter("modes", m, " | ".join(MODES))
    case = _nadukuru_case(args)
    with progress(args.quiet) as bar:
        rep = validate_nadukuru(case, out_dir=Path(args.docs), root=Path(args.out), walls=walls, modes=modes,
                                triaxial=not args.no_triaxial, rate_check=not args.no_rate_check, progress=bar,
                                log=lambda msg: print(msg, file=sys.stderr, flush=True))
    if args.json:
        print(json.dumps(rep, indent=2, default=str))
    print(f"report: {Path(args.docs) / 'nadukuru.md'}", file=sys.stderr)
    return 0


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
    d.add_argument("--no-liggghts", action="store_true", help="time dem3d only")
    d.add_argument("--scaling", action="store_true",
                   help="also time 10k, 30k and 100k spheres (the 10k packing tiled) for --steps/10 steps")
    d.add_argument("--json", action="store_true", help="machine-readable output")
    d.set_defaults(func=_cmd_bench_dem3d)


def _count(name: str):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = 0
        if value < 1:
            raise argparse.ArgumentTypeError(str(InvalidParameter(name, text, ">= 1")))
        return value
    parse.__name__ = name
    return parse


def _cmd_bench_dem3d(args) -> int:
    from workflows.bench import bench_dem3d, scaling

    result = bench_dem3d(args.n, args.steps, args.threads, liggghts=not args.no_liggghts)
    rows = scaling(max(1, args.steps // 10), args.threads) if args.scaling else None
    if args.json:
        if rows is not None:
            result["scaling"] = rows
        print(json.dumps(result, indent=2))
        return 0
    ours, theirs = result["wallsim_particle_steps_per_s"], result["liggghts_particle_steps_per_s"]
    print(f"dem3d benchmark: {result['n']} spheres x {result['steps']} steps, dem3d on {result['threads']} thread(s)")
    print(f"  wallsim  {ours:10.3e} particle-steps/s  ({result['wallsim_seconds']:.2f} s)")
    if theirs is not None:
        print(f"  LIGGGHTS {theirs:10.3e} particle-steps/s  ({result['liggghts_seconds']:.2f} s, 1 process)")
        print(f"  ratio    {result['ratio']:.2f}")
        w, lg = result["check"]["wallsim"], result["check"]["liggghts"]
        print(f"  check: kinetic energy {w['kinetic_energy_J']:.4g} vs {lg['kinetic_energy_J']:.4g} J, "
              f"rotational {w['rotational_energy_J']:.4g} vs {lg['rotational_energy_J']:.4g} J, "
              f"contacts {w['contacts']} vs {lg['contacts']}")
    for row in rows or []:
        print(f"  N = {row['n']:6d}: {row['ms_per_step']:7.3f} ms/step, {row['ns_per_particle_step']:6.1f} ns per "
              f"particle-step ({row['steps']} steps)")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="wallsim", description="Earth pressure on retaining walls: theory and DEM.")
    parser.add_argument("--version", action="version", version=f"wallsim {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    _add_theory(sub)
    _add_dsm(sub)
    _add_design(sub)
    _add_bearing(sub)
    _add_compare_nadukuru(sub)
    _add_compare_khosravi(sub)
    _add_calibrate_triaxial(sub)
    _add_calibrate(sub)
    _add_validate_nadukuru(sub)
    _add_validate_khosravi(sub)
    _add_bench(sub)
    return parser


def _version() -> str:
    try:
        from importlib.metadata import version
        return version("wallsim")
    except Exception:
        return "unknown"


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except InvalidParameter as err:
        sys.stderr.write(f"wallsim: error: {err}\n")
        return EXIT_BAD_INPUT


def entry() -> None:
    """The ``wallsim`` console script: ``main``, then leave without Python's teardown.

    Freeing a large pymunk space is quadratic: pymunk removes every shape, and each
    removal scans chipmunk's whole cached-contact table (never shrunk), so the full-size
    Khosravi fill (63,548 disks) took ~4 min of CPU to exit after its report was written
    (40k disks in contact: 60 s). Every file and recording is written and closed by
    then (viz.recorder flushes and disconnects), so nothing is lost by skipping it."""
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    entry()
