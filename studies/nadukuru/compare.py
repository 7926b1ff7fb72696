"""``wallsim compare nadukuru``: specimen (cached), wall movement, theory, paper, outputs.

Writes the run folder (config.toml, manifest.json, result.json, history.csv,
segments.csv, fig3a_displacements.png, fig3b_force_chains.png, fig4_K.png,
fig5_segments.png, recording.rrd) and returns the result dict that ``--json`` prints.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic.constants import G

from ..measures import dem_profile
from ..report import theory_row
from ..runner import Stopwatch, drop_checkpoint, finish, open_recording, open_run_folder
from ..store import find_card_entry
from ..granular.movement import run_modes
from ..granular.specimen import load_or_prepare
from ..granular.wall import MODE_TITLES
from .case import NadukuruCase, paper_values


def phi_card(root: Path, case: NadukuruCase) -> tuple[float, str]:
    """phi for the theories: the triaxial calibration card of this recipe if one exists
    (``wallsim calibrate triaxial``), else the paper's 39 deg."""
    from ..triaxial.lab import card_path
    found = find_card_entry(card_path(root, case.specimen, case.seed), lambda card: "phi_peak_deg" in card)
    if found is not None:
        return float(found[0]["phi_peak_deg"]), f"triaxial, {found[1].name}"
    return 39.0, "paper's triaxial value; run `wallsim calibrate triaxial` for this recipe's own"


@dataclass(frozen=True)
class Comparison:
    """What the DEM is set beside: the fill's unit weight gamma [N/m^3], wall height H
    [m], phi [deg] and where it came from, the theory rows, the paper's figures, and the
    segment edges and centres as fractions of H (bottom to top)."""

    gamma: float
    H: float
    phi: float
    phi_source: str
    theories: list
    paper: dict
    edges: np.ndarray
    centres: np.ndarray

    @property
    def norm(self) -> float:
        """rho g (1 - n) H [Pa], the paper's normalisation of the segment stresses."""
        return self.gamma * self.H


def comparison(case: NadukuruCase, wall_kind: str, spec, root: Path) -> Comparison:
    gamma = case.specimen.density * (1.0 - spec.porosity) * G
    H = case.wall.height
    phi, phi_src = phi_card(Path(root), case)
    edges = np.linspace(0.0, 1.0, case.wall.segments + 1)
    return Comparison(gamma, H, phi, phi_src, theory_rows(case.movement.mode, phi, case.wall.friction, gamma, H,
                                                          phi_src),
                      paper_values(case.movement.mode, wall_kind), edges, 0.5 * (edges[1:] + edges[:-1]))


def compare_nadukuru(case: NadukuruCase, wall_kind: str, *, root: Path = Path("runs"), rrd: Path | None = None,
                     spawn: bool = False, every: int = 5, record: bool = True, progress=None,
                     resume: Path | None = None) -> tuple[dict, Path]:
    """Run (or, with ``resume`` = an interrupted run's folder, continue) the comparison."""
    from viz import paths as P
    from viz.recorder import wall_layout

    clock = Stopwatch()
    folder = open_run_folder("nadukuru", case, root, resume=resume)
    spec, cached = load_or_prepare(case, Path(root) / "nadukuru" / "specimens", progress)
    cmp = comparison(case, wall_kind, spec, root)
    # a resumed run records what it runs: the part after the resume, in its own file
    rrd_path = Path(rrd) if rrd is not None else folder.file("recording-resumed.rrd" if resume else "recording.rrd")
    recorder = open_recording(rrd_path if record else None, study="nadukuru", dim=3, spawn=spawn, folder=folder,
                              recording_id=f"{folder.path.name}-{case.movement.mode}",
                              layout=wall_layout(3, "backfill, wall segments and force chains",
                                                 (P.METRIC_PANEL_STRESS,)))
    recorder.log_case(_case_markdown(case, wall_kind, spec, cmp.phi, cmp.phi_source))
    _log_theory(recorder, cmp.phi, case, cmp.gamma, cmp.H)
    with clock("movement"):
        hist, frames = _move_and_record(case, spec, cmp, recorder, every, progress, folder)
        recorder.close()
    _write_tables(folder, case, hist, cmp)
    _write_figures(folder, case, wall_kind, spec, hist, frames, cmp, resumed=resume is not None)
    result = _result(case, wall_kind, spec, cached, hist, cmp, folder)
    result["wall_time_s"] = clock.total
    movement_s = clock.seconds["movement"]
    result["timings"] = {"movement_s": movement_s, "recording_s": recorder.seconds,
                         "recording_share_of_movement": recorder.seconds / movement_s,
                         "rrd_MB": rrd_path.stat().st_size / 1e6 if record and rrd_path.exists() else None}
    drop_checkpoint(folder.path, "checkpoints/movement.npz")                      # finished: nothing to resume
    finish(folder, result, particles=spec.n_spheres, dt=spec.dt, contact=result["provenance"]["contact"],
           wall_time_s=result["wall_time_s"])
    return result, folder.path



def compare_frame_every(case: NadukuruCase, every: int = 5) -> int:
    """Steps between the frames a compare run records: ``every`` x 10 load samples."""
    return max(1, every) * case.movement.record_every * 10


def _move_and_record(case: NadukuruCase, spec, cmp: Comparison, recorder, every: int, progress,
                     folder) -> tuple[dict, dict]:
    """Move the wall (``run_modes``, resumable from the folder's checkpoint), logging every
    load sample and every ``every`` x 500 steps the scene; returns the history and the
    first and last frames logged ({} when none was)."""
    frames = {}

    def on_frame(frame, sample):
        frames.setdefault("first", frame)
        frames["last"] = frame
        recorder.log_frame(frame, wall_disp_over_H=sample.wall_disp_over_H,
                           profile=(1.0 - cmp.centres, sample.segment_stress / cmp.norm))

    def on_sample(sample):
        recorder.log_metrics(sample.step, sample.time,
                             {"K": sample.K, "resultant_height_over_H": sample.resultant_height_over_H, "thrust_kN": sample.thrust_kN,
                              "panel_stress_kPa": sample.segment_stress / 1e3}, sample.wall_disp_over_H)

    frame_every = compare_frame_every(case, every)
    hist = run_modes(case, spec, on_sample=on_sample, on_frame=on_frame, frame_every=frame_every,
                     progress=progress, checkpoint_path=folder.file("checkpoints/movement.npz"),
                     on_checkpoint=folder.checkpointed)
    if frames:          # displacement field over the whole movement (Fig. 3a)
        f0, f1 = frames["first"], frames["last"]
        recorder.log_displacement(f0.positions, f1.positions, step=f1.step, time=f1.time,
                                  wall_disp_over_H=hist["wall_disp_over_H"][-1])
    return hist, frames


def _write_tables(folder, case: NadukuruCase, hist: dict, cmp: Comparison) -> None:
    """history.csv (K, resultant height and segment stresses against Delta/H) and
    segments.csv (the active stresses of the segments)."""
    seg_cols = [f"segment{k + 1}_sigma_kPa" for k in range(case.wall.segments)]
    folder.write_csv("history.csv", ["wall_disp_over_H", "time_s", "step", "K", "resultant_height_over_H"] + seg_cols,
                     [[d, t, s, k, c, *(seg / 1e3)] for d, t, s, k, c, seg in
                      zip(hist["wall_disp_over_H"], hist["time"], hist["step"], hist["K"], hist["resultant_height_over_H"],
                          hist["segment_stress"])])
    active = hist["segment_stress_active"]
    folder.write_csv("segments.csv", ["segment", "centre_height_over_H", "sigma_active_kPa",
                                      "sigma_over_rho_g_1mn_H"],
                     [[k + 1, cmp.centres[k], active[k] / 1e3, active[k] / cmp.norm]
                      for k in range(case.wall.segments)])


def _write_figures(folder, case: NadukuruCase, wall_kind: str, spec, hist: dict, frames: dict,
                   cmp: Comparison, resumed: bool = False) -> None:
    """The paper's figures for this run: Fig. 4 (K), Fig. 5 (segments), Fig. 3 (field,
    chains; after a resume the field covers the movement since the resume, and says so)."""
    from viz.figures import plot_displacement_field, plot_force_chains

    from .figures import plot_load_history, plot_segment_stress

    mode = MODE_TITLES[case.movement.mode]
    label = f"{case.movement.mode} ({wall_kind})"
    plot_load_history({label: (hist["wall_disp_over_H"], hist["K"])}, folder.file("fig4_K.png"),
                      paper={label: cmp.paper["K"]} if cmp.paper["K"] else None, at_rest=spec.K_at_rest,
                      title=f"Nadukuru & Michalowski Fig. 4: {mode}, {wall_kind} wall")
    plot_segment_stress({f"{label} DEM": hist["segment_stress_active"][::-1] / cmp.norm}, cmp.edges,
                        folder.file("fig5_segments.png"),
                        theory={t["name"]: (np.array([0.0, 1.0]), np.array([0.0, t["K"]]))
                                for t in cmp.theories if t["K"] is not None and t["name"] in ("coulomb", "rankine")},
                        title=f"Fig. 5(a): stress on each segment at Delta/H = {case.movement.wall_disp_over_H:g}")
    if frames:
        end = hist["wall_disp_over_H"][-1]
        plot_displacement_field(frames["first"].positions, frames["last"].positions,
                                folder.file("fig3a_displacements.png"),
                                title=f"Fig. 3(a): displacements x15 at Delta/H = {end:.4f}"
                                      + (" since the resume" if resumed else "") + f"\n{mode}, {wall_kind} wall")
        plot_force_chains(frames["last"], folder.file("fig3b_force_chains.png"),
                          title=f"Force chains at Delta/H = {end:.4f} ({mode}, {wall_kind} wall)")


def _result(case: NadukuruCase, wall_kind: str, spec, cached: bool, hist: dict, cmp: Comparison, folder) -> dict:
    """The headline numbers (what ``--json`` prints), with what produced them."""
    rec = case.specimen
    return {
        "case": "nadukuru", "mode": case.movement.mode, "wall": wall_kind,
        "particles": spec.n_spheres, "bodies": spec.n_bodies, "seed": case.seed,
        "specimen_cached": cached,
        "dem": {"K": hist["K_active"], "resultant_height_over_H": hist["resultant_height_over_H_active"],
                "K_at_rest": spec.K_at_rest, "resultant_height_over_H_at_rest": spec.resultant_height_over_H_at_rest,
                "porosity": spec.porosity, "thrust_at_rest_kN_per_0.5m": spec.thrust_at_rest_kN * 0.5 / spec.width,
                "wall_disp_over_H_steady": hist["wall_disp_over_H_steady"],
                "segment_stress_over_rho_g_1mn_H": (hist["segment_stress_active"] / cmp.norm).tolist()},
        "profile": {"active": _active_profile(case, spec, hist, cmp).as_dict()},
        "paper": cmp.paper, "theory": cmp.theories, "phi_deg": cmp.phi, "phi_source": cmp.phi_source,
        "provenance": {"particles": spec.n_spheres, "seed": case.seed, "dt_s": spec.dt,
                       "grain_scale": spec.grain_scale, "width_m": spec.width,
                       "contact": {"kn_N_per_m": rec.kn, "ks_N_per_m": rec.ks, "mu": rec.particle_friction,
                                   "damping_ratio": rec.damping_ratio, "wall_mu": case.wall.friction},
                       "specimen_steps": spec.steps, "movement_steps": int(hist["step"][-1] - hist["step"][0])},
        "run_folder": str(folder.path),
    }


def _active_profile(case: NadukuruCase, spec, hist: dict, cmp: Comparison):
    """The active segment stresses as the record the theories return, the resultant at
    the height from the panel forces and moments (studies.measures.dem_profile)."""
    n = case.wall.segments
    sigma = hist["segment_stress_active"]
    return dem_profile(cmp.H * (1.0 - cmp.centres), sigma, np.zeros(n), cmp.H / n, cmp.H, cmp.gamma,
                       height=hist["resultant_height_over_H_active"] * cmp.H,
                       source=f"dem3d, {spec.n_spheres} spheres, {n} segments")


def _case_markdown(case: NadukuruCase, wall_kind: str, spec, phi: float, phi_src: str) -> str:
    return (f"# Nadukuru & Michalowski (2012): {MODE_TITLES[case.movement.mode]}, {wall_kind} wall\n\n"
            f"* {spec.n_spheres} spheres ({spec.n_bodies} bodies, {case.specimen.clump_fraction:.0%} clumps), "
            f"grain scale {spec.grain_scale:.2f}, porosity {spec.porosity:.3f}\n"
            f"* at rest: K {spec.K_at_rest:.3f}, resultant at {spec.resultant_height_over_H_at_rest:.3f} H\n"
            f"* wall H {case.wall.height} m, width {spec.width:.3f} m, {case.wall.segments} segments, "
            f"friction {case.wall.friction}\n* theory phi {phi:.1f} deg ({phi_src})\n")


def _log_theory(recorder, phi, case, gamma, H):
    from analytic import Soil, Wall, coulomb, jaky, rankine
    delta = math.degrees(math.atan(case.wall.friction))
    soil = Soil(phi, gamma)
    recorder.log_theory_profiles([coulomb(soil, Wall(H, delta)), rankine(soil, Wall(H)), jaky(soil, Wall(H))],
                                 gamma, H)


def theory_rows(mode: str, phi_deg: float, wall_friction: float, gamma: float, H: float,
                phi_source: str) -> list[dict]:
    """The theories beside the DEM, as the *normal* load coefficient on the wall
    (comparable with eq. 6, which uses the normal force): Coulomb Ka cos(delta),
    Rankine Ka, Jaky K0, and the DSM of the mode (Kh, resultant_height_over_H)."""
    from analytic import Soil, Wall, coulomb, jaky, rankine
    from analytic.slices import mode_case, solve

    delta = math.degrees(math.atan(wall_friction))
    soil, w = Soil(phi_deg, gamma), Wall(H, delta)
    note = f"phi {phi_deg:.1f}, delta {delta:.1f} deg"
    rows = [theory_row(name, prof, note) for name, prof in
            (("coulomb", coulomb(soil, w)), ("rankine", rankine(soil, Wall(H))), ("jaky (at rest)", jaky(soil, Wall(H))))]
    if mode in ("T", "RB", "RT"):
        res = solve(mode_case(mode, phi_deg=phi_deg, delta_deg=delta, H=H, gamma=gamma))
        rows.append(theory_row("dsm", res.profile, f"k_l, phi* shapes of eqs. 13/18/19 at phi {phi_deg:.1f}, "
                               f"delta {delta:.1f}" + ("; curved surface: wallsim reconstruction" if mode == "RT" else ""),
                               height_over_H=res.resultant_height_over_H))
    else:
        rows.append(theory_row("dsm", None, "no DSM preset for the mixed mode"))
    return rows
