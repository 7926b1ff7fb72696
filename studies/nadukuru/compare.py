"""``wallsim compare nadukuru``: specimen (cached), wall movement, theory, paper, outputs.

Writes the run folder (config.toml, manifest.json, result.json, history.csv,
segments.csv, fig3a_displacements.png, fig3b_force_chains.png, fig4_K.png,
fig5_segments.png, recording.rrd) and returns the result dict that ``--json`` prints.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from pathlib import Path

import numpy as np

from .model import (G, MODE_TITLES, NadukuruCase, load_or_prepare, paper_values, run_modes, theory_rows,
                       wall_load)
from ..runfolder import RunFolder


def phi_card(root: Path, case: NadukuruCase) -> tuple[float, str]:
    """phi for the theories: the triaxial calibration card of this recipe if one exists
    (``wallsim calibrate triaxial``), else the paper's 39 deg."""
    from ..triaxial.lab import card_path
    p = card_path(root, case.specimen, case.seed)
    if p.exists():
        card = json.loads(p.read_text())
        return float(card["phi_peak_deg"]), f"triaxial, {p.name}"
    return 39.0, "paper's triaxial value; run `wallsim calibrate triaxial` for this recipe's own"


def compare_nadukuru(case: NadukuruCase, wall_kind: str, *, root: Path = Path("runs"), rrd: Path | None = None,
                     spawn: bool = False, every: int = 5, record: bool = True, progress=None,
                     resume: Path | None = None) -> tuple[dict, Path]:
    """Run (or, with ``resume`` = an interrupted run's folder, continue) the comparison."""
    from viz.figures import plot_load_history, plot_segment_stress
    from viz.recorder import Recorder

    t_start = time.perf_counter()
    if resume is not None:
        folder = RunFolder.existing(resume)
    else:
        folder = RunFolder("nadukuru", case.seed, root=root)
        folder.write_config(case)
    spec, cached = load_or_prepare(case, Path(root) / "nadukuru" / "specimens", progress)
    H, w = case.wall.height, spec.width
    rec = case.specimen
    gamma = rec.density * (1.0 - spec.porosity) * G
    rrd_path = Path(rrd) if rrd is not None else folder.file("recording.rrd")
    from viz.recorder import nadukuru_blueprint
    recorder = Recorder(rrd_path if record else None, app_id="wallsim nadukuru",
                        recording_id=f"{folder.path.name}-{case.movement.mode}", dim=3, every=1,
                        spawn=spawn, enabled=record or spawn, blueprint=nadukuru_blueprint())
    phi, phi_src = phi_card(Path(root), case)
    theories = theory_rows(case.movement.mode, phi, case.wall.friction, gamma, H, phi_src)
    paper = paper_values(case.movement.mode, wall_kind)
    recorder.log_case(_case_markdown(case, wall_kind, spec, phi, phi_src))
    _log_theory(recorder, phi, case, gamma, H)
    edges = np.linspace(0.0, 1.0, case.wall.segments + 1)
    centres = 0.5 * (edges[1:] + edges[:-1])
    norm = gamma * H                                   # rho g (1 - n) H

    last = {}

    def on_frame(frame, sample):
        last.setdefault("first", frame)
        last["frame"] = frame
        recorder.log_frame(frame, wall_disp_over_H=sample.disp_over_H,
                           profile=(1.0 - centres, sample.segment_stress / norm))

    def on_sample(sample):
        recorder.log_metrics(sample.step, sample.time,
                             {"K": sample.K, "centroid": sample.centroid, "thrust_kN": sample.normal_kN,
                              "panel_stress_kPa": sample.segment_stress / 1e3}, sample.disp_over_H)

    frame_every = max(1, every) * case.movement.record_every * 10
    t_move = time.perf_counter()
    hist = run_modes(case, spec, on_sample=on_sample, on_frame=on_frame, frame_every=frame_every,
                     progress=progress, checkpoint_path=folder.file("checkpoints/movement.npz"))
    if "frame" in last:          # displacement field over the whole movement (Fig. 3a)
        f0, f1 = last["first"], last["frame"]
        recorder.log_displacement(f0.positions, f1.positions, step=f1.step, time=f1.time,
                                  disp_over_H=hist["disp_over_H"][-1])
    recorder.close()
    movement_s = time.perf_counter() - t_move
    # tables and figures
    seg_cols = [f"segment{k + 1}_sigma_kPa" for k in range(case.wall.segments)]
    folder.write_csv("history.csv", ["disp_over_H", "time_s", "step", "K", "resultant_height_over_H"] + seg_cols,
                     [[d, t, s, k, c, *(seg / 1e3)] for d, t, s, k, c, seg in
                      zip(hist["disp_over_H"], hist["time"], hist["step"], hist["K"], hist["centroid"],
                          hist["segment_stress"])])
    folder.write_csv("segments.csv", ["segment", "centre_height_over_H", "sigma_active_kPa",
                                      "sigma_over_rho_g_1mn_H"],
                     [[k + 1, centres[k], hist["segment_stress_active"][k] / 1e3,
                       hist["segment_stress_active"][k] / norm] for k in range(case.wall.segments)])
    label = f"{case.movement.mode} ({wall_kind})"
    plot_load_history({label: (hist["disp_over_H"], hist["K"])}, folder.file("fig4_K.png"),
                      paper={label: paper["K"]} if paper["K"] else None, at_rest=spec.K_at_rest,
                      title=f"Nadukuru & Michalowski Fig. 4: {MODE_TITLES[case.movement.mode]}, {wall_kind} wall")
    plot_segment_stress({f"{label} DEM": hist["segment_stress_active"][::-1] / norm}, edges,
                        folder.file("fig5_segments.png"),
                        theory={t["name"]: (np.array([0.0, 1.0]), np.array([0.0, t["K"]]))
                                for t in theories if t["K"] is not None and t["name"] in ("coulomb", "rankine")},
                        title="Fig. 5(a): stress on each segment at Delta/H = "
                              f"{case.movement.disp_over_H:g}")
    if "frame" in last:
        from viz.figures import plot_displacement_field, plot_force_chains
        plot_displacement_field(last["first"].positions, last["frame"].positions, folder.file("fig3a_displacements.png"),
                                title=f"Fig. 3(a): displacements x15 at Delta/H = {hist['disp_over_H'][-1]:.4f}\n"
                                      f"{MODE_TITLES[case.movement.mode]}, {wall_kind} wall")
        plot_force_chains(last["frame"], folder.file("fig3b_force_chains.png"),
                          title=f"Force chains at Delta/H = {hist['disp_over_H'][-1]:.4f} "
                                f"({MODE_TITLES[case.movement.mode]}, {wall_kind} wall)")
    wall_time = time.perf_counter() - t_start
    result = {
        "case": "nadukuru",
        "mode": case.movement.mode,
        "wall": wall_kind,
        "particles": spec.n_spheres,
        "bodies": spec.n_bodies,
        "seed": case.seed,
        "wall_time_s": wall_time,
        "specimen_cached": cached,
        "timings": {"movement_s": movement_s, "recording_s": recorder.seconds,
                    "recording_share_of_movement": recorder.seconds / movement_s,
                    "rrd_MB": rrd_path.stat().st_size / 1e6 if record and rrd_path.exists() else None},
        "dem": {"K": hist["K_active"], "resultant_height_over_H": hist["centroid_active"],
                "K_at_rest": spec.K_at_rest, "resultant_height_over_H_at_rest": spec.centroid_at_rest,
                "porosity": spec.porosity, "at_rest_wall_load_kN": spec.wall_load_kN * 0.5 / spec.width,
                "disp_over_H_steady": hist["disp_over_H_steady"],
                "segment_stress_over_rho_g_1mn_H": (hist["segment_stress_active"] / norm).tolist()},
        "paper": paper,
        "theory": theories,
        "phi_deg": phi,
        "phi_source": phi_src,
        "provenance": {"particles": spec.n_spheres, "seed": case.seed, "dt_s": spec.dt,
                       "grain_scale": spec.grain_scale, "width_m": spec.width,
                       "contact": {"kn_N_per_m": rec.kn, "ks_N_per_m": rec.ks, "mu": rec.particle_friction,
                                   "damping_ratio": rec.damping_ratio, "wall_mu": case.wall.friction},
                       "specimen_steps": spec.steps, "movement_steps": int(hist["step"][-1] - hist["step"][0])},
        "run_folder": str(folder.path),
    }
    folder.write_json("result.json", result)
    folder.file("checkpoints/movement.npz").unlink(missing_ok=True)      # finished: nothing to resume
    folder.write_manifest(particles=spec.n_spheres, dt=spec.dt, contact=result["provenance"]["contact"],
                          wall_time_s=wall_time)
    return result, folder.path


def _case_markdown(case: NadukuruCase, wall_kind: str, spec, phi: float, phi_src: str) -> str:
    return (f"# Nadukuru & Michalowski (2012): {MODE_TITLES[case.movement.mode]}, {wall_kind} wall\n\n"
            f"* {spec.n_spheres} spheres ({spec.n_bodies} bodies, {case.specimen.clump_fraction:.0%} clumps), "
            f"grain scale {spec.grain_scale:.2f}, porosity {spec.porosity:.3f}\n"
            f"* at rest: K {spec.K_at_rest:.3f}, resultant at {spec.centroid_at_rest:.3f} H\n"
            f"* wall H {case.wall.height} m, width {spec.width:.3f} m, {case.wall.segments} segments, "
            f"friction {case.wall.friction}\n* theory phi {phi:.1f} deg ({phi_src})\n")


def _log_theory(recorder, phi, case, gamma, H):
    from analytic import Soil, Wall, coulomb, jaky, rankine
    delta = math.degrees(math.atan(case.wall.friction))
    soil = Soil(phi, gamma)
    recorder.log_theory_profiles([coulomb(soil, Wall(H, delta)), rankine(soil, Wall(H)), jaky(soil, Wall(H))],
                                 gamma, H)
