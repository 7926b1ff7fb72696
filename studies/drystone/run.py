"""One wall loaded by water to failure: the DEM run (``dem2d.blocks``), the limit-equilibrium
check (``analytic.drystone``), and the run folder (history CSV + PNG, mechanism figure,
DEM / limit equilibrium / measured table, result.json, recording)."""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from .case import DrystoneCase, assumptions, masonry, mode_word, percent_error, plan, solver, staircase_m

RIGID_NOTE = ("rigid-block kinematics: contacts have no stiffness, so displacements before failure are "
              "numerical, not physical; do not set them against the site sensors")


def _le_record(le, shift: float = 0.0) -> dict:
    return {"critical_height_m": le.critical_height_m + shift, "mode": le.mode,
            "mechanism_level_m": le.mechanism_level_m + shift, "sliding_height_m": le.sliding_height_m + shift,
            "toppling_height_m": le.toppling_height_m + shift, "theta_deg": le.theta_deg,
            "stands_to_crest": le.stands_to_crest}


def limit_equilibrium(case: DrystoneCase) -> dict:
    """``analytic.drystone.water_limit_equilibrium`` for the case's wall: the yield-design
    reconstruction (reference 5, mechanisms from the base), the bed-joint variant, and the
    yield design of the part above the fixed first course (the DEM's own boundary
    condition; heights shifted back to the toe level)."""
    from analytic.drystone import section_above_fixed_course, water_limit_equilibrium
    sec, phi, g, m = case.section(), case.phi_b_deg, case.unit_weight_kN_m3, staircase_m(case)
    upper, y = section_above_fixed_course(sec, case.block_height)
    return {"yield-design": _le_record(water_limit_equilibrium(sec, phi, g, staircase_m=m)),
            "bed-joints": _le_record(water_limit_equilibrium(sec, phi, g, method="bed-joints",
                                                             course_height_m=case.block_height)),
            "above-fixed-course": _le_record(water_limit_equilibrium(upper, phi, g, staircase_m=m), y)}


def run_dem(case: DrystoneCase, *, on_increment=None):
    """Build the wall and load it to failure (no files). ``on_increment(wall, h_w, crest)``
    after each increment. Returns (wall, LoadingResult, wall seconds, CPU seconds)."""
    from dem2d.blocks import BlockWall, load_to_failure

    t0, c0 = time.perf_counter(), time.process_time()
    wall = BlockWall.build(case.section(), masonry(case), solver(case))
    hook = None if on_increment is None else (lambda hw, crest: on_increment(wall, hw, crest))
    res = load_to_failure(wall, plan(case), progress=hook)
    return wall, res, time.perf_counter() - t0, time.process_time() - c0


def dem_summary(wall, res) -> dict:
    """The DEM's answer in the names of the validation JSON."""
    m = res.mechanism
    return {"critical_height_m": res.critical_height_m if res.failed else None,
            "last_stable_height_m": res.last_stable_height_m, "failed": res.failed,
            "mode": m.mode if m else None, "mechanism_level_m": m.level_m if m else None,
            "mechanism_course": m.course if m else None, "rotation_deg": m.rotation_deg if m else None,
            "pivot_m": list(m.pivot) if m and m.pivot is not None else None,
            "blocks": wall.block_count, "steps": res.steps, "simulated_s": res.simulated_s}


def wall_result(case: DrystoneCase, wall, res, seconds: float, cpu: float) -> dict:
    """Result of one wall: DEM, limit equilibrium, measured, paper's DEM, provenance."""
    w = case.wall_reference()
    s = case.section()
    dem = dem_summary(wall, res)
    le = limit_equilibrium(case)
    measured = {"height_m": w["measured_height_m"]["value"], "mode": mode_word(w["measured_mode"]["value"])}
    crit = dem["critical_height_m"]
    return {"case": "drystone", "wall": case.wall, "geometry": case.geometry,
            "section": {"height_m": s.height_m, "base_width_m": s.base_width_m, "crest_width_m": s.crest_width_m,
                        "batter_outer_deg": s.batter_outer_deg, "batter_inner_deg": s.batter_inner_deg,
                        "joint_slope_deg": s.joint_slope_deg},
            "assumptions": assumptions(case), "dem": dem, "limit_equilibrium": le, "measured": measured,
            "paper_dem": {"height_m": w["paper_dem_height_m"]["value"],
                          "mode": mode_word(w["paper_dem_mode"]["value"])},
            "error_percent": percent_error(crit if crit is not None else math.nan, measured["height_m"]),
            "mode_matches": dem["mode"] == measured["mode"],
            "contact": {"phi_b_deg": case.phi_b_deg, "friction": math.tan(math.radians(case.phi_b_deg)),
                        "collision_slop_m": wall.solver.collision_slop, "overlap_time_s": wall.solver.overlap_time,
                        "elasticity": 0.0, "pair_friction": "arbiter override (collision handler)"},
            "dt_s": case.dt, "iterations": case.iterations, "water_direction": case.water_direction,
            "increment_fraction": case.increment_fraction,
            "unit_weight_kN_m3": case.unit_weight_kN_m3, "particles": wall.block_count,
            "wall_time_s": seconds, "cpu_time_s": cpu, "note": RIGID_NOTE}


def comparison_rows(result: dict) -> list[list]:
    """DEM / limit equilibrium (two variants) / paper's DEM / measured, one row each."""
    d, le = result["dem"], result["limit_equilibrium"]
    return [["DEM (this run)", d["critical_height_m"], d["mode"], d["mechanism_level_m"]],
            ["limit equilibrium (yield design, ref. 5)", le["yield-design"]["critical_height_m"],
             le["yield-design"]["mode"], le["yield-design"]["mechanism_level_m"]],
            ["limit equilibrium (bed joints)", le["bed-joints"]["critical_height_m"], le["bed-joints"]["mode"],
             le["bed-joints"]["mechanism_level_m"]],
            ["limit equilibrium above the fixed first course (yield design)",
             le["above-fixed-course"]["critical_height_m"], le["above-fixed-course"]["mode"],
             le["above-fixed-course"]["mechanism_level_m"]],
            ["paper's DEM (S-OET Table 3)", result["paper_dem"]["height_m"], result["paper_dem"]["mode"], None],
            ["measured (Villemus, S-OET Table 3)", result["measured"]["height_m"], result["measured"]["mode"], None]]


def _recorder_hook(rec, wall):
    """What the recording logs after each increment: blocks by displacement, water, joint forces."""
    x0 = wall.positions()
    xs = wall.section.base_width_m

    def hook(w, hw, crest):
        pts, fs = w.contact_forces()
        disp = np.hypot(*(w.positions() - x0).T)
        water = np.zeros((w.block_count, 2))
        loads = w.water_loads()
        if loads is not None:
            water[loads[0]] = loads[1]
        rec.log_block_wall(w.steps, w.time, w.world_outlines(), disp, water_height=hw, water_x=(xs, xs + 0.5),
                           contact_points=pts, contact_forces=fs, block_forces={"water_force": water},
                           metrics={"crest_displacement_mm": crest * 1e3, "water_height_m": hw})
    return hook


def increment_logger(rec, progress=None):
    """What runs after each water increment: the recording's frame (when it records:
    Rerun or VTK) and the progress line."""
    hook = []

    def on_increment(wall, hw, crest):
        if rec.enabled:
            if not hook:
                hook.append(_recorder_hook(rec, wall))
            hook[0](wall, hw, crest)
        if progress is not None:
            progress(hw, crest)
    return on_increment


def write_outputs(folder, case: DrystoneCase, result: dict, res) -> None:
    """History CSV + PNG, mechanism PNG, comparison CSV (the run folder's files)."""
    from .figures import plot_drystone_history, plot_drystone_mechanism

    notes = result["assumptions"]
    folder.write_csv("history.csv", ["water_height_m", "crest_displacement_m", "settled", "time_s"],
                     zip(res.water_height_m, res.crest_displacement_m, [int(s) for s in res.settled], res.time_s))
    le = result["limit_equilibrium"]["yield-design"]["critical_height_m"]
    title = (f"{case.wall} ({case.geometry} geometry): water height vs crest displacement\n"
             "rigid-block kinematics: displacements before failure are numerical, not physical")
    plot_drystone_history(res.water_height_m, res.crest_displacement_m, folder.file("history.png"), title=title,
                          measured_m=result["measured"]["height_m"], le_m=le,
                          critical_m=result["dem"]["critical_height_m"], notes=notes)
    m = res.mechanism
    mtitle = (f"{case.wall} at failure, h_w = {res.critical_height_m:.3f} m: {m.mode} at {m.level_m:.3f} m"
              if m else f"{case.wall}: no failure up to the crest")
    plot_drystone_mechanism(res.reference_outlines, res.outlines, res.velocities, folder.file("mechanism.png"),
                            water_height=res.water_height_m[-1], title=mtitle, level_m=m.level_m if m else None,
                            pivot=m.pivot if m and m.mode == "toppling" else None, notes=notes)
    # the assumptions ride along as rows of their own, so the table never travels without them
    folder.write_csv("comparison.csv", ["source", "critical_height_m", "mode", "mechanism_level_m"],
                     comparison_rows(result) + [[f"assumption: {a}", "", "", ""] for a in notes])


def compare_wall(case: DrystoneCase, *, root: Path, rrd: str | None = None, record: bool = True,
                 spawn: bool = False, progress=None) -> tuple[dict, Path]:
    """``wallsim compare drystone``: one wall to failure, its run folder written."""
    from viz import paths as P
    from viz.recorder import Layout, Series

    from ..runner import finish, open_recording, open_run_folder

    folder = open_run_folder("drystone", case, root, seed=None)
    path = Path(rrd) if rrd else (folder.file("recording.rrd") if record else None)
    rec = open_recording(path, study="drystone", recording_id=f"drystone-{case.wall}", dim=2,
                         layout=Layout(2, "blocks (colour: displacement), water, joint forces", (
                             Series("crest displacement mm", f"{P.METRICS}/crest_displacement_mm"),
                             Series("water height m", f"{P.METRICS}/water_height_m"))), spawn=spawn, folder=folder)
    rec.log_case("\n".join([f"# {case.wall}, {case.geometry} geometry", "", RIGID_NOTE, "", "Assumed:",
                            *[f"- {a}" for a in assumptions(case)]]))

    wall, res, seconds, cpu = run_dem(case, on_increment=increment_logger(rec, progress))
    rec.close()
    result = wall_result(case, wall, res, seconds, cpu) | {"run_folder": str(folder.path)}
    write_outputs(folder, case, result, res)
    finish(folder, result, particles=wall.block_count, steps=res.steps, dt_s=case.dt, iterations=case.iterations,
           contact=result["contact"], wall_time_s=seconds, cpu_time_s=cpu, assumptions=result["assumptions"])
    return result, folder.path
