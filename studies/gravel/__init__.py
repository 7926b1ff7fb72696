"""The case-B gravel: its local grain and fill-block frictions recalibrated for
rigid capsules against the global targets S-OET calibrated PFC's values to (biaxial peak
37.7 deg at 35 kPa; interface 37.7 deg). ``calibrate`` (the two series, the report);
modules ``calibrate`` (plan and tests) and ``report`` (files). The study record is
``STUDY``."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from ..options import VTK, output_folder
from ..study import Command, Option, Study


def _default_plan():
    from .calibrate import GravelCalibration
    return GravelCalibration()


def _calibrate(plan, opts: SimpleNamespace) -> tuple[dict, str]:
    import sys
    import time

    from ..options import writable_folder
    from ..progress import progress
    from ..runfolder import git_revision
    from ..runner import finish, open_run_folder
    from .calibrate import run_calibration
    from .report import write_docs, write_figures, write_tables

    if opts.docs:
        writable_folder("docs", opts.docs)
    folder = open_run_folder("gravel", plan, opts.out)
    t0, c0 = time.perf_counter(), time.process_time()
    with progress(opts.quiet) as bar:
        result = run_calibration(plan, bar, folder)
    result |= {"command": "wallsim calibrate gravel " + " ".join(sys.argv[3:]), "git": git_revision(),
               "wall_time_s": time.perf_counter() - t0, "cpu_time_s": time.process_time() - c0,
               "run_folder": str(folder.path)}
    write_tables(folder, result)
    result["figures"] = write_figures(folder, result)
    if opts.docs:
        write_docs(Path(opts.docs), result, folder)
    finish(folder, result, seeds=list(plan.seeds), dt_s=plan.biaxial.solver.dt,
           iterations=plan.biaxial.solver.iterations, wall_time_s=result["wall_time_s"],
           cpu_time_s=result["cpu_time_s"])
    return result, f"run folder: {folder.path}"


def _text(result: dict) -> str:
    from .report import _f
    lines = []
    if "biaxial" in result:
        b = result["biaxial"]
        lines += [f"biaxial, local {r['friction_deg']:g} deg: peak {r['phi_peak_deg']:.1f}, critical "
                  f"{r['phi_cs_deg']:.1f} deg, porosity {r['porosity']:.3f} (inner {r['inner_porosity']:.3f})"
                  for r in b["rows"]]
        lines.append(f"grain friction nearest to peak {result['targets']['phi_peak_deg']:g} and critical state "
                     f"{result['targets']['phi_cs_deg']:g} deg: {_f(b['grain_friction_deg'])} deg (there "
                     f"{_f(b['phi_peak_at_chosen_deg'])} / {_f(b['phi_cs_at_chosen_deg'])}; peak alone: "
                     f"{_f(b['peak_only']['value_deg'])}; paper's local: 45)")
    if "interface" in result:
        i = result["interface"]
        lines += [f"interface, local {r['interface_friction_deg']:g} deg: global {r['global_angle_deg']:.2f} "
                  f"(sd {r['global_angle_sd_deg']:.2f}) deg" for r in i["rows"]]
        lines.append(f"interface friction for global {result['targets']['interface_angle_deg']:g} deg: "
                     f"{_f(i['interface_friction_deg'])} deg (paper's local: 25)")
    return "\n".join(lines)


CALIBRATE = Command(
    verb="calibrate", help="the gravel's local frictions from the biaxial and interface targets (minutes)",
    description="Biaxial tests of the gravel (rounded hexagons) at 35 kPa over local grain frictions (peak 37.7 and "
                "critical state 32 deg), then "
                "the interface shear test over local fill-block frictions (global 37.7 deg). "
                "Example: wallsim calibrate gravel --frictions 45,60,75 --docs docs/validation",
    default_case=_default_plan, run=_calibrate, text=_text, seed_key=None,
    options=(Option("--tests", "both | biaxial | interface (both)", key="tests",
                    choices=("both", "biaxial", "interface")),
             Option("--frictions", "local grain frictions of the biaxial series [deg] (35,40,45,50,55)",
                    key="frictions_deg"),
             Option("--interface-frictions", "local fill-block frictions [deg] (37.7,45,60,75,89)",
                    key="interface_frictions_deg"),
             Option("--grain-friction", "grain friction of the interface series [deg] (from the biaxial series)",
                    key="grain_friction_deg"),
             Option("--docs", "also write gravel_calibration.{md,json} here (none)", metavar="DIR",
                    parse=output_folder("docs")), VTK))

STUDY = Study(name="gravel", title="Case-B gravel: local frictions from the biaxial and interface targets",
              commands=(CALIBRATE,))
