"""Case B: one of Colas's walls under a gravel backfill placed in stages until it fails
(``studies.drystone.backfill``), beside Coulomb's thrust with the slope and the rigid-block limit
equilibrium (``analytic.drystone.backfill_limit_equilibrium``), and its run folder
(stages CSV, thrust and thrust-height figures, mechanism figure, result.json)."""

from __future__ import annotations

import math
import pickle
import time
from pathlib import Path

import numpy as np
import pymunk

from .case import DrystoneCase, assumptions, masonry, mode_word, percent_error, reference, staircase_m
from .run import RIGID_NOTE

#: the fill as the reference gives it (3.1): unit weight [kN/m3], peak phi [deg]
GAMMA_S, PHI_FILL = 14.9, 37.7


def _calibrated_global(case: DrystoneCase) -> tuple[float, str]:
    """Interface angle delta for the theories [deg]: the global target (37.7) when the
    case's local value is the one docs/validation/gravel_calibration.json chose for it,
    the seed-mean global angle measured there at the case's local value, else 37.7 (the
    paper's)."""
    import json
    path = Path(__file__).resolve().parents[2] / "docs" / "validation" / "gravel_calibration.json"
    mu = case.backfill.interface_friction_deg
    try:
        cal = json.loads(path.read_text())["interface"]
        if abs(cal["interface_friction_deg"] - mu) < 1e-6 and cal["choice"]["reached"]:
            return 37.7, "the global target our calibration's local value gives (gravel_calibration.md)"
        hit = [r for r in cal["rows"] if abs(r["interface_friction_deg"] - mu) < 1e-6]
        if hit:
            return float(hit[0]["global_angle_deg"]), "measured global interface angle at the case's local value"
    except (OSError, KeyError, ValueError):
        pass
    return 37.7, "the paper's global interface angle (no calibration at the case's local value)"


def coulomb_rows(case: DrystoneCase, y_floor: float, heights: list[float], delta: float) -> list[dict]:
    """Coulomb's active thrust with the slope (horizontal part, vertical inner face):
    P_h = gamma_s (H_b - y_floor)^2 K_a cos(delta) / 2 at (H_b - y_floor) / 3 above the floor
    (K_a: ``analytic.drystone.coulomb_ka`` with phi 37.7, beta = the case's slope)."""
    from analytic.drystone import coulomb_ka
    ka = coulomb_ka(PHI_FILL, delta, case.backfill.slope_deg, case.section().batter_inner_deg)
    return [{"backfill_height_m": h, "thrust_N_m": 0.5 * GAMMA_S * 1e3 * (h - y_floor) ** 2 * ka
             * math.cos(math.radians(delta)), "thrust_height_m": y_floor + (h - y_floor) / 3, "ka": ka}
            for h in heights]


def run_backfill(case: DrystoneCase, *, on_stage=None, on_reading=None, checkpoint=None,
                 resume: bytes | None = None) -> dict:
    """Fill until the wall fails or the next stage would pass ``max_height_m`` (no files).
    ``on_stage(bw, reading)`` after each stage. After every stage but the last the wall
    and its fill go on from their own snapshot (``BackfilledWall.snapshot``), handed to
    ``checkpoint(bytes)`` first; ``resume`` (such bytes) continues from one, to the bits
    of the run that was not interrupted. Returns the DEM part of the result and the
    objects the figures need."""
    from .backfill import BackfilledWall
    from dem2d.blocks import BlockSolver, LoadingPlan, classify_mechanism

    s, bf = case.section(), case.backfill
    t0, c0 = time.perf_counter(), time.process_time()
    if resume is None:
        loading = LoadingPlan(failure_energy_J_m=0.1, failure_readings=10, equilibrium_energy_J_m=1e-5)
        bw = BackfilledWall.build(s, masonry(case), bf.gravel(), bf.plan(),
                                  BlockSolver(dt=case.dt, iterations=bf.iterations), loading, seed=bf.seed)
        cpu_build = time.process_time() - c0
        stages, body_steps = [], 0
        x_ref, a_ref, out_ref = bw.wall.positions(), bw.wall.angles(), bw.wall.world_outlines()
    else:
        saved = pickle.loads(resume)
        bw = BackfilledWall.restored(saved["wall"])
        cpu_build, stages, body_steps = saved["cpu_build_s"], saved["stages"], saved["body_steps"]
        x_ref, a_ref, out_ref = saved["reference"]
    stop = bf.max_height_m if bf.max_height_m is not None else s.height_m + bf.formwork_m
    more = lambda: not bw.failed and bw.backfill_height_m + bf.layer_m <= stop + 1e-9  # noqa: E731
    while more():
        if stages and stages[-1]["settled"]:
            x_ref, a_ref, out_ref = bw.wall.positions(), bw.wall.angles(), bw.wall.world_outlines()
        s0 = bw.wall.steps
        r = bw.stage(on_reading)
        free = sum(1 for b in bw.bodies if b.body_type == pymunk.Body.DYNAMIC)
        body_steps += (bw.wall.steps - s0) * (free + int(bw.wall.dynamic.sum()))
        stages.append(dict(r))
        if on_stage is not None:
            on_stage(bw, r)
        if more():
            wall = bw.snapshot()
            if checkpoint is not None:
                checkpoint(pickle.dumps({"wall": wall, "stages": stages, "body_steps": body_steps,
                                         "reference": (x_ref, a_ref, out_ref), "cpu_build_s": cpu_build},
                                        protocol=pickle.HIGHEST_PROTOCOL))
            bw = BackfilledWall.restored(wall)
    mech = classify_mechanism(s, case.block_height, bw.wall.course, bw.wall.dynamic, x_ref, a_ref,
                              bw.wall.positions(), bw.wall.angles()) if bw.failed else None
    cpu = time.process_time() - c0
    phases = ("drop", "place", "settle", "read")
    return {"bw": bw, "stages": stages, "mechanism": mech, "reference_outlines": out_ref,
            "wall_time_s": time.perf_counter() - t0, "cpu_time_s": cpu,
            "speed": {"steps": bw.wall.steps, "steps_per_cpu_s": bw.wall.steps / max(cpu, 1e-9),
                      "body_steps_per_cpu_s": body_steps / max(cpu, 1e-9), "bodies_last": stages[-1]["grains"]
                      if stages else 0, "cpu_build_s": cpu_build,
                      # where the time goes: per phase of the stages (studies.drystone.backfill._PhaseClock)
                      "cpu_by_phase_s": {k: sum(r.get(f"cpu_{k}_s", 0.0) for r in stages) for k in phases},
                      "steps_by_phase": {k: sum(r.get(f"steps_{k}", 0) for r in stages) for k in phases}}}


def backfill_result(case: DrystoneCase, run: dict) -> dict:
    """The result of one case-B wall: DEM, Coulomb per stage, limit equilibrium, measured,
    the paper's DEM, local values (paper's and ours), provenance."""
    from analytic.drystone import backfill_limit_equilibrium
    bw, m, w = run["bw"], run["mechanism"], case.wall_reference()
    stages = [{k: v for k, v in r.items() if k not in PER_BLOCK} for r in run["stages"]]
    crit = stages[-1]["backfill_height_m"] if bw.failed else None
    delta, delta_note = _calibrated_global(case)
    le = backfill_limit_equilibrium(case.section(), case.phi_b_deg, case.unit_weight_kN_m3, GAMMA_S, PHI_FILL,
                                    delta, case.backfill.slope_deg, staircase_m=staircase_m(case),
                                    course_height_m=case.block_height)
    paper_local = reference()["backfill"]["paper_local"]
    measured = w["measured_height_m"]["value"]
    return {"case": "drystone", "load": "backfill", "wall": case.wall, "geometry": case.geometry,
            "critical_height_m": crit, "mode": m.mode if m else None,
            "mechanism_level_m": m.level_m if m else None, "measured_height_m": measured,
            "measured_mode": mode_word(w["measured_mode"]["value"]),
            "paper_dem_heights_m": w["paper_dem_heights_m"]["value"],
            "error_percent": percent_error(crit if crit is not None else math.nan, measured),
            "stages": stages, "coulomb": {"delta_deg": delta, "delta_source": delta_note, "phi_deg": PHI_FILL,
                                          "rows": coulomb_rows(case, bw.y_floor,
                                                               [r["backfill_height_m"] for r in stages], delta)},
            "limit_equilibrium": {"critical_height_m": le.critical_height_m, "mode": le.mode,
                                  "delta_deg": delta},
            "local_values": {"paper": {k: v["value"] for k, v in paper_local.items()},
                             "ours": {"grain_friction_deg": case.backfill.grain_friction_deg,
                                      "interface_friction_deg": case.backfill.interface_friction_deg,
                                      "placement_friction_deg": case.backfill.placement_friction_deg}},
            "block_forces": block_forces(run["stages"], bw.failed, bw.wall.course),
            "particles": {"blocks": bw.wall.block_count, "grains": len(bw.bodies), "held": len(bw.held)},
            "seed": case.backfill.seed, "dt_s": case.dt, "iterations": case.backfill.iterations,
            "speed": run["speed"], "wall_time_s": run["wall_time_s"], "cpu_time_s": run["cpu_time_s"],
            "assumptions": assumptions(case) + backfill_assumptions(case), "note": RIGID_NOTE}


#: the readings' per-block fields, kept in the result for one stage only (``block_forces``)
PER_BLOCK = ("block_fill_force_N_m", "block_outlines_m")


def block_forces(stages: list[dict], failed: bool, course=None) -> dict | None:
    """The fill's force on each block (Oetomo et al.'s Fig. 20) at the last stage the wall
    stood: the stage before the failing one (the failing stage's reading is taken while
    the wall moves), or the last stage of a wall that stood. ``fill_force_N_m`` per block
    [horizontal toward the outside, vertical downward] [N/m], ``outlines_m`` its corners,
    ``course`` its course (0 = base) when given."""
    standing = stages[:-1] if failed else stages
    if not standing or PER_BLOCK[0] not in standing[-1]:
        return None
    r = standing[-1]
    out = {"backfill_height_m": r["backfill_height_m"], "fill_force_N_m": r["block_fill_force_N_m"],
           "outlines_m": r["block_outlines_m"]}
    if course is not None:
        out["course"] = [int(k) for k in course]
    return out


#: an inner-face block "carries no force" below this fraction of the median inner-face block's
NO_FORCE_FRACTION = 0.01


def inner_face_forces(forces: dict, course) -> dict:
    """The fill's horizontal force on the loaded face (Oetomo et al. Fig. 20a: "some blocks
    do not withstand any forces from the backfill"): per course, the innermost block
    (largest x of its outline) whose centre lies below the fill surface. Returns their
    count, how many carry no force (below ``NO_FORCE_FRACTION`` of the median), and the
    least, median and largest force [N/m] (``forces``: ``block_forces``'s dict;
    ``course``: (n,) course of each block)."""
    course = np.asarray(course)
    outlines = [np.asarray(o, float) for o in forces["outlines_m"]]
    fx = np.asarray(forces["fill_force_N_m"], float)[:, 0]
    surface = forces["backfill_height_m"]
    face = []
    for k in np.unique(course):
        members = np.flatnonzero(course == k)
        inner = members[np.argmax([outlines[i][:, 0].max() for i in members])]
        if outlines[inner][:, 1].mean() < surface:
            face.append(inner)
    f = fx[face]
    median = float(np.median(f)) if len(f) else math.nan
    return {"backfill_height_m": surface, "blocks": len(face),
            "without_force": int(np.sum(f < NO_FORCE_FRACTION * median)) if len(f) else 0,
            "no_force_fraction": NO_FORCE_FRACTION, "no_force_below_N_m": NO_FORCE_FRACTION * median,
            "least_N_m": float(f.min()) if len(f) else math.nan, "median_N_m": median,
            "largest_N_m": float(f.max()) if len(f) else math.nan}


def backfill_assumptions(case: DrystoneCase) -> list[str]:
    """The case-B values that are assumed or ours (not the paper's), one line each."""
    b = case.backfill
    hold = [f"grains held static {b.hold_depth_m:g} m below the surface and {b.hold_distance_m:g} m from the inner "
            "face (outside the failure wedge; ASSUMED harmless)"] if b.hold_depth_m is not None else []
    return [f"fill surface rising away from the wall at {b.slope_deg:g} deg (ASSUMED direction, reference 3.3)",
            f"container {b.container_m:g} m measured from the inner face at the heel (ASSUMED origin)",
            f"formwork column {b.formwork_m:g} m high on the line of the inner face (ASSUMED height), "
            + ("part of the innermost crest block, massless (S-OET 5.2: fixed to the inward wall face; "
               "ASSUMED massless)" if b.formwork == "crest" else
               "fixed in space (the site's, carried by the side formworks; not S-OET's)"),
            f"local frictions ours (grain {b.grain_friction_deg:g}, interface {b.interface_friction_deg:g}, "
            f"placement {b.placement_friction_deg:g} deg; paper's 45, 25, 15.6 for PFC2D clumps): "
            "docs/validation/gravel_calibration.md",
            "container floor and back wall at the interface friction (ASSUMED)"] + hold


def write_outputs_b(folder, case: DrystoneCase, result: dict, run: dict) -> None:
    """stages.csv, thrust.png (DEM and Coulomb against H_b, with the thrust height),
    block_forces.png (Fig. 20), mechanism.png."""
    from viz.figures import plot_series

    from .figures import plot_block_forces, plot_drystone_mechanism

    st, co = result["stages"], result["coulomb"]["rows"]
    keys = ["backfill_height_m", "thrust_N_m", "thrust_vertical_N_m", "thrust_height_m", "formwork_thrust_N_m",
            "container_vertical_N_m",
            "wall_vertical_N_m", "fill_weight_N_m", "grains", "held", "crest_displacement_m", "settled", "time_s",
            "steps"] + [f"{q}_{k}{u}" for k in ("drop", "place", "settle", "read")
                        for q, u in (("cpu", "_s"), ("steps", ""))]
    folder.write_csv("stages.csv", keys + ["coulomb_thrust_N_m", "coulomb_thrust_height_m"],
                     [[r[k] for k in keys] + [c["thrust_N_m"], c["thrust_height_m"]] for r, c in zip(st, co)])
    h = [r["backfill_height_m"] for r in st]
    d = result["coulomb"]["delta_deg"]
    plot_series(h, {"DEM thrust [kN/m]": [r["thrust_N_m"] / 1e3 for r in st],
                    f"Coulomb, beta {case.backfill.slope_deg:g}, delta {d:.1f} [kN/m]":
                        [c["thrust_N_m"] / 1e3 for c in co],
                    "DEM thrust height above the toe [m]": [r["thrust_height_m"] for r in st],
                    "Coulomb thrust height [m]": [c["thrust_height_m"] for c in co]},
                folder.file("thrust.png"), xlabel="backfill height at the inner face H_b [m]", ylabel="kN/m ; m",
                title=f"{case.wall}: fill thrust against backfill height")
    if result.get("block_forces"):
        bf = result["block_forces"]
        plot_block_forces(bf["outlines_m"], bf["fill_force_N_m"], folder.file("block_forces.png"),
                          title=f"{case.wall}: the fill's force on each block at H_b = {bf['backfill_height_m']:.2f} m "
                                f"(the last stage the wall stood)", notes=result["assumptions"])
    m = run["mechanism"]
    bw = run["bw"]
    title = (f"{case.wall} at failure, H_b = {result['critical_height_m']:.2f} m: {m.mode} at {m.level_m:.2f} m"
             if m else f"{case.wall}: stood to H_b = {st[-1]['backfill_height_m']:.2f} m" if st else case.wall)
    plot_drystone_mechanism(run["reference_outlines"], bw.wall.world_outlines(), bw.wall.velocities(),
                            folder.file("mechanism.png"), water_height=None,
                            backfill_height=st[-1]["backfill_height_m"] if st else None, title=title,
                            level_m=m.level_m if m else None, pivot=m.pivot if m and m.mode == "toppling" else None,
                            notes=result["assumptions"])


def _backfill_frame(rec, bw, reading: dict | None = None, *, at_failure: bool = False) -> None:
    """One recording frame: blocks by displacement since the wall was built, grains,
    force chains, the block velocities ``at_failure``; the stage's fill height, thrust
    (from its ``reading``) and crest movement."""
    from dem2d.gravel import grain_outlines

    w, x0 = bw.wall, bw.x_start
    held = {id(b) for b in bw.held}
    segs, forces = bw.force_chains()
    metrics = {"backfill_height_m": bw.backfill_height_m, "crest_displacement_mm": 1e3 * w.crest_displacement(x0)}
    if reading is not None:
        metrics["thrust_kN"] = reading["thrust_N_m"] / 1e3
    rec.log_backfilled_wall(w.steps, w.time, w.world_outlines(), np.hypot(*(w.positions() - x0).T),
                            grain_outlines=grain_outlines(bw.positions(), bw.angles(), bw.widths, bw.gravel)
                            if bw.bodies else np.zeros((0, 1, 2)),
                            grain_held=np.array([id(b) in held for b in bw.bodies], bool),
                            chain_segments=segs, chain_forces=forces,
                            block_centres=w.positions() if at_failure else None,
                            block_velocities=w.velocities() if at_failure else None, metrics=metrics)


#: the fill's snapshot in the run folder while the run goes on (``run_backfill``)
CHECKPOINT = "checkpoints/backfill.pkl"


def compare_backfill(case: DrystoneCase, *, root: Path, rrd: str | None = None, record: bool = True,
                     spawn: bool = False, progress=None, resume: Path | None = None) -> tuple[dict, Path]:
    """``wallsim compare drystone --wall C2S|C3S|C4L``: one wall filled to failure, its run
    folder written (and the recording: a frame per stage, the last with block velocities).
    After every stage the fill's snapshot is kept in the run folder (``CHECKPOINT``);
    ``resume`` (an interrupted run's folder, ``case`` its config) goes on from it, or
    from the start when there is none, and ends as the uninterrupted run, bit for bit;
    its recording (the stages after the resume) goes to recording-resumed.rrd."""
    from viz import paths as P
    from viz.recorder import Layout, Series

    from ..runner import drop_checkpoint, finish, open_recording, open_run_folder

    folder = open_run_folder("drystone", case, root, seed=case.backfill.seed, resume=resume)
    saved = folder.path / CHECKPOINT
    state = saved.read_bytes() if resume is not None and saved.is_file() else None
    default_rrd = "recording-resumed.rrd" if resume is not None else "recording.rrd"
    path = Path(rrd) if rrd else (folder.file(default_rrd) if record else None)
    rec = open_recording(path, study="drystone", recording_id=f"drystone-{case.wall}-seed{case.backfill.seed}", dim=2,
                         layout=Layout(2, "blocks (colour: displacement), grains, force chains", (
                             Series("backfill height m", f"{P.METRICS}/backfill_height_m"),
                             Series("fill thrust kN/m", P.METRIC_THRUST),
                             Series("crest displacement mm", f"{P.METRICS}/crest_displacement_mm"))), spawn=spawn, folder=folder)
    rec.log_case("\n".join([f"# {case.wall} under gravel backfill, seed {case.backfill.seed}", "", RIGID_NOTE, "",
                            "Assumed:", *[f"- {a}" for a in assumptions(case) + backfill_assumptions(case)]]))

    def on_stage(bw, r):
        if rec.enabled:
            _backfill_frame(rec, bw, r)
        if progress is not None:
            progress(r["backfill_height_m"], r["crest_displacement_m"], r)

    try:
        run = run_backfill(case, on_stage=on_stage, checkpoint=lambda blob: folder.save_checkpoint(CHECKPOINT, blob),
                           resume=state)
        if rec.enabled and run["stages"]:
            _backfill_frame(rec, run["bw"], run["stages"][-1], at_failure=True)
    finally:
        rec.close()
    result = backfill_result(case, run) | {"run_folder": str(folder.path)}
    if path is not None:
        result["recording"] = str(path)
    write_outputs_b(folder, case, result, run)
    drop_checkpoint(folder.path, CHECKPOINT)                 # finished: nothing to resume
    finish(folder, result, particles=result["particles"], seed=case.backfill.seed, steps=run["speed"]["steps"],
           dt_s=case.dt, iterations=case.backfill.iterations, local_values=result["local_values"],
           wall_time_s=run["wall_time_s"], cpu_time_s=run["cpu_time_s"], assumptions=result["assumptions"])
    return result, folder.path
