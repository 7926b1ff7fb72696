"""``wallsim validate drystone --case B``: Colas's three walls under gravel, each on two
backfill realisations (seeds 1 and 2, as the paper's two), to failure at full size ->
case B of docs/validation/drystone.{json,md} and drystone/ figures.

A wall and seed whose finished run folder (result.json) under ``--out`` was made from
the same resolved case (config.toml equal field for field) is read, not run again: a
wall costs 35-65 min of one core, and a validation interrupted after three walls keeps
them."""

from __future__ import annotations

import json
import math
import shutil
import sys
import time
import tomllib
from dataclasses import replace
from pathlib import Path

import reproducibility

from ..runfolder import claimed, config_toml, git_revision, package_versions

from ..store import atomic_write, to_plain
from .case import ACCURACY_LIMIT_PERCENT, WALLS_B, DrystoneCase
from .run import RIGID_NOTE

SEEDS = (1, 2)


def _config(case: DrystoneCase) -> dict:
    """The case as its run folder's config.toml reads back."""
    return tomllib.loads(config_toml(case))


def finished_run(case: DrystoneCase, root: Path, *, holding: str = "result.json") -> Path | None:
    """The newest run folder under ``root``/drystone holding a finished run of exactly
    ``case`` (same resolved settings, seed included), else None; ``holding``: the file
    that marks the run wanted (``run_b.CHECKPOINT``: an interrupted one)."""
    want = _config(case)
    for folder in sorted((root / "drystone").glob("*"), reverse=True):
        cfg, res = folder / "config.toml", folder / holding
        if cfg.is_file() and res.is_file() and (holding == "result.json" or not (folder / "result.json").is_file()):
            try:
                if tomllib.loads(cfg.read_text()) == want:
                    return folder
            except tomllib.TOMLDecodeError:
                continue
    return None


def run_wall(case: DrystoneCase, root: Path, log=None, run_missing: bool = True) -> tuple[dict, dict, Path] | None:
    """(result, manifest, folder) of one wall and seed: read from its finished run folder
    or run now (``run_b.compare_backfill``, with its recording); None when it has no finished
    run and ``run_missing`` is False."""
    from .run_b import CHECKPOINT, compare_backfill
    folder = finished_run(case, root)
    tag = f"{case.wall} seed {case.backfill.seed}"
    if folder is None and not run_missing:
        if log:
            log(f"{tag}: no finished run under {root}")
        return None
    interrupted = finished_run(case, root, holding=CHECKPOINT) if folder is None else None
    if interrupted is not None:
        if log:
            log(f"{tag}: resuming the interrupted run in {interrupted}")
        with claimed(interrupted):
            _, folder = compare_backfill(case, root=root, record=True, resume=interrupted)
    elif folder is None:
        if log:
            log(f"{tag}: running (35-65 min of one core at full size)")
        _, folder = compare_backfill(case, root=root, record=True)
    elif log:
        log(f"{tag}: finished run found in {folder}")
    return (json.loads((folder / "result.json").read_text()), json.loads((folder / "manifest.json").read_text()),
            folder)


def entry(result: dict, manifest: dict, folder: Path, course=None) -> dict:
    """One wall and seed in drystone.json's case B (the issue's keys first); ``course``:
    each block's course, for a run whose block forces predate the course in its result."""
    from .run_b import inner_face_forces
    forces = result.get("block_forces")
    err = result["error_percent"]
    ok = err is not None and math.isfinite(err)
    return {"critical_height_m": result["critical_height_m"], "mode": result["mode"],
            "measured_height_m": result["measured_height_m"], "measured_mode": result["measured_mode"],
            "wall_time_s": result["wall_time_s"], "cpu_time_s": result["cpu_time_s"],
            "error_percent": err if ok else None,
            "within_10_percent": bool(ok and abs(err) <= ACCURACY_LIMIT_PERCENT),
            "mode_matches": result["mode"] in result["measured_mode"].split("/"),     # "sliding/toppling": either
            "mechanism_level_m": result["mechanism_level_m"],
            "paper_dem_heights_m": result["paper_dem_heights_m"],
            "limit_equilibrium": result["limit_equilibrium"],
            "coulomb_delta_deg": result["coulomb"]["delta_deg"],
            "particles": result["particles"], "stages": len(result["stages"]), "steps": result["speed"]["steps"],
            "steps_per_cpu_s": result["speed"]["steps_per_cpu_s"],
            "body_steps_per_cpu_s": result["speed"]["body_steps_per_cpu_s"],
            "cpu_by_phase_s": {"build": result["speed"]["cpu_build_s"], **result["speed"]["cpu_by_phase_s"]},
            "seed": result["seed"], "dt_s": result["dt_s"], "iterations": result["iterations"],
            "git": manifest.get("git"), "versions": manifest.get("versions"),
            "load_average_1min": manifest.get("load_average_1min"), "run_folder": str(folder),
            "recording": result.get("recording"),
            # the stage of the block-force field (Fig. 20), where the run has it
            "block_forces_height_m": (forces or {}).get("backfill_height_m"),
            "block_forces_inner_face": (inner_face_forces(forces, forces.get("course", course))
                                        if forces and (course is not None or "course" in forces) else None)}


def motion_at_failure(case: DrystoneCase, recording: Path) -> dict | None:
    """How the blocks above the first course moved in the failing stage, from the run's
    recording: one rigid motion fitted to their outline centres between the last settled
    stage (the last frame before the failing stage's step) and the failure frame
    (``dem2d.blocks.rigid_motion_fit``). A second reading of the mode, beside
    ``classify_mechanism``'s (which uses the top two courses only). None without a
    recording holding both frames."""
    import numpy as np

    from dem2d.blocks import BlockWall, rigid_motion_fit
    from viz import paths as P
    from viz import readback

    from .case import masonry
    if not recording.is_file():
        return None
    steps, frames = readback.read_column(recording, "/" + P.BLOCKS, "LineStrips2D:strips")
    before = [k for k, t in enumerate(steps) if t < steps[-1]] if len(steps) else []
    if not before:
        return None
    wall = BlockWall.build(case.section(), masonry(case))
    centres = [np.array([np.asarray(s, float)[:-1].mean(axis=0) for s in frames[k]]) for k in (before[-1], -1)]
    if any(len(c) != len(wall.course) for c in centres):
        return None
    upper = wall.course >= 1
    fit = rigid_motion_fit(centres[0][upper], centres[1][upper])
    moved = np.hypot(*(centres[1] - centres[0]).T)
    top = wall.course == wall.course.max()
    worst = np.flatnonzero(upper)[fit.worst]
    return {"rotation_deg": fit.rotation_deg, "pivot_m": fit.pivot, "rms_residual_mm": 1e3 * fit.rms_residual_m,
            "max_residual_mm": 1e3 * fit.max_residual_m, "max_residual_course": int(wall.course[worst]),
            "crest_movement_mm": float(1e3 * moved[top].mean()), "blocks": int(upper.sum()),
            "steps": [int(steps[before[-1]]), int(steps[-1])]}


def _figures(folder: Path, fig_dir: Path, wall: str, seed: int) -> None:
    """The run's thrust, block-force (Fig. 20) and mechanism figures, copied beside the report."""
    for name in ("thrust", "block_forces", "mechanism"):
        src = folder / f"{name}.png"
        if src.is_file():
            shutil.copyfile(src, fig_dir / f"{wall}_seed{seed}_{name}.png")


def tagged_assumptions(by_wall: dict[str, list[str]]) -> list[str]:
    """Every run's assumptions once: those all walls share as they are, the others
    (sections differ per wall) led by the walls they belong to, e.g. "C3S: base width ..."."""
    shared = [a for a in next(iter(by_wall.values()), []) if all(a in v for v in by_wall.values())]
    own: dict[str, list[str]] = {}
    for w, items in by_wall.items():
        for a in items:
            if a not in shared:
                own.setdefault(a, []).append(w)
    return shared + [f"{', '.join(ws)}: {a}" for a, ws in own.items()]


def validate_case_b(case: DrystoneCase, *, out_dir: Path, root: Path, walls: list[str] = list(WALLS_B),
                    seeds: tuple[int, ...] = SEEDS, run_missing: bool = True, log=None) -> dict:
    """Every wall in ``walls`` on every seed; writes case B into drystone.json (case A
    kept as it is) and drystone.md, and the figures into drystone/. ``run_missing``
    False: only the finished runs; a wall and seed without one keeps its entry of the
    present drystone.json (made where its run folder was), else it is written as "not run"."""
    from dem2d.blocks import BlockWall

    from .case import assumptions, masonry
    from .report import write_report
    from .run_b import backfill_assumptions
    t0, c0 = time.perf_counter(), time.process_time()
    git = git_revision()
    fig_dir = out_dir / "drystone"
    fig_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "drystone.json"
    rep = json.loads(path.read_text()) if path.is_file() else {"study": "drystone"}
    kept = rep.get("case_b", {}).get("walls", {})
    rows: dict[str, dict[str, dict]] = {}
    local_values, assumptions_by_wall = rep.get("case_b", {}).get("local_values"), {}
    for w in walls:
        for seed in seeds:
            c = replace(case, wall=w, backfill=replace(case.backfill, seed=seed))
            found = run_wall(c, root, log, run_missing)
            if found is None:
                old = kept.get(w, {}).get(str(seed))
                rows.setdefault(w, {})[str(seed)] = old if isinstance(old, dict) else "not run"
                if isinstance(old, dict):
                    assumptions_by_wall.setdefault(w, assumptions(c) + backfill_assumptions(c))
                if log:
                    log(f"  kept from {path} (run at git {old.get('git')})" if isinstance(old, dict)
                        else "  reported as not run")
                continue
            result, manifest, folder = found
            course = BlockWall.build(c.section(), masonry(c)).course
            rows.setdefault(w, {})[str(seed)] = entry(result, manifest, folder, course)
            rows[w][str(seed)]["motion_at_failure"] = motion_at_failure(c, folder / "recording.rrd")
            local_values = result["local_values"]
            assumptions_by_wall.setdefault(w, result["assumptions"])
            _figures(folder, fig_dir, w, seed)
            if log:
                e = rows[w][str(seed)]
                log(f"  {w} seed {seed}: DEM {e['critical_height_m']} m {e['mode']} (measured "
                    f"{e['measured_height_m']} m {e['measured_mode']}), {e['cpu_time_s']:.0f} s CPU")
    b = case.backfill
    rep["case_b"] = {
        "walls": rows, "seeds": list(seeds),
        "settings": {"geometry": case.geometry, "dt_s": case.dt, "iterations": b.iterations,
                     "grain_shape": b.grain_shape, "width_m": [b.width_min_m, b.width_max_m], "layer_m": b.layer_m,
                     "slope_deg": b.slope_deg, "container_m": b.container_m, "formwork_m": b.formwork_m,
                     "formwork": b.formwork, "hold_depth_m": b.hold_depth_m, "hold_distance_m": b.hold_distance_m,
                     "max_stage_s": b.max_stage_s},
        "local_values": local_values, "assumptions": tagged_assumptions(assumptions_by_wall), "note": RIGID_NOTE,
        "command": " ".join(sys.argv), "runs_root": str(root),
        "command_git": git, "versions": package_versions(), "reproducibility": reproducibility.describe(),
        "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "command_wall_time_s": time.perf_counter() - t0, "command_cpu_time_s": time.process_time() - c0}
    write_report(rep, out_dir)
    atomic_write(path, (json.dumps(to_plain(rep), indent=2) + "\n").encode())
    return rep
