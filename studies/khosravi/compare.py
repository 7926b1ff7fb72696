"""``wallsim compare khosravi`` and ``wallsim validate khosravi``: Khosravi et al.'s
PFC2D translation case run on dem2d and set beside Jaky, Rankine and the arching
theories.

Run folder (studies/runfolder.py): config.toml, manifest.json, result.json,
at_rest_panels.csv, readings_vs_displacement.csv, active_panels.csv, backfilling.csv,
fig10_at_rest.png, fig12_pressure_vs_displacement.png, fig13_profiles.png and, with
--rrd, recording.rrd. The settled specimen is kept in
``<root>/khosravi/_specimens/<key>.pkl`` (key = hash of everything that shapes the
specimen), so a second ``compare`` with the same seed and specimen settings skips the
pluviation; a run that fills the box goes on from the same stored bytes, so the two
continue alike.
"""

from __future__ import annotations

import json
import math
import pickle
import time
from pathlib import Path

import numpy as np

from analytic.classical import jaky_coefficient, rankine_coefficient
from studies.elements.biaxial import BiaxialCase
from studies.khosravi.run import KhosraviRun
from studies.measures import dem_profile, k_upper_half, normal_thrust, resultant_height_over_H, steady_displacement
from studies.khosravi.case import KhosraviCase
from studies.biaxial.calibrate import DEFAULT_CARDS, phi_for_friction, run_one
from studies.progress import progress
from studies.report import theory_row
from studies.runfolder import RunFolder, package_versions
from studies.runner import (Stopwatch, drop_checkpoint, finish, has_config, open_recording, open_run_folder,
                            run_once)
from studies.store import Store, content_key, to_plain

from .specimen import settled_box, specimen_key
from .theories import theories

#: Khosravi et al.'s published values the report compares with (shipped with the package)
REFERENCE = Path(__file__).resolve().parent / "reference.json"

def biaxial_phi(case: KhosraviCase, bar=None, card: Path | tuple[Path, ...] = DEFAULT_CARDS,
                root: str | Path | None = None) -> dict:
    """phi of the backfill material measured by the biaxial test: from the committed
    calibration card (or a test an earlier run saved under ``<root>/khosravi/_biaxial``)
    when one holds a 4 kPa test at this friction, grain size and the readings' solver
    (dt, sweeps: the strength the moving wall meets), else by running one (same friction,
    grading, particles_scale and solver) and saving
    it there for the next run (a full-size test takes ~15-25 min)."""
    bcase = BiaxialCase(d50=case.d50, cu=case.cu, particles_scale=case.particles_scale, gs=case.gs,
                        friction=case.friction, seed=case.seed, solver=case.reading_solver)
    store = Store(Path(root) / "khosravi" / "_biaxial") if root is not None else None
    saved = store.path(content_key(bcase), ".json") if store is not None else None
    cards = [card] if isinstance(card, (str, Path)) else list(card)
    t = phi_for_friction(case.friction, cards + ([saved] if saved else []),
                         particles_scale=case.particles_scale, solver=case.reading_solver)
    if t is not None:
        return {**t, "from": f"calibration card {Path(t.pop('card')).name}"}
    out, _, _ = run_one(bcase, bar, f"mu={case.friction:g}")
    out.pop("curve", None)
    if store is not None:
        store.save_json(content_key(bcase), {"source": "biaxial test run by wallsim compare khosravi", "tests": [out]})
    return {**out, "from": "biaxial test run for this comparison"}


#: the translation's snapshot in the run folder while the run goes on (``_translate``)
CHECKPOINT = "checkpoints/translation.pkl"


def compare_khosravi(case: KhosraviCase, *, root: str | Path = "runs", rrd: bool | str | Path = False,
                     quiet: bool = False, frames: int = 40, specimen_cache: bool = True,
                     name: str | None = None, card: Path | tuple[Path, ...] = DEFAULT_CARDS,
                     resume: str | Path | None = None) -> tuple[dict, RunFolder]:
    """Pluviate (or reuse the settled specimen), read the wall at rest, translate it to
    Dis/H = case.wall_disp_over_H_max, compare with theory; write the run folder.

    Snapshots: every ``case.checkpoint_layers`` layers the fill goes on from its own
    snapshot, kept as ``<key>.partial.pkl`` beside the specimens (an interrupted fill
    resumes from it), and the settled specimen is kept as ``<key>.pkl`` (later runs with
    the same key skip the pluviation); every ``case.checkpoint_readings`` readings the
    translation goes on from its snapshot, kept in the run folder (``CHECKPOINT``).
    ``resume``: an interrupted run's folder (``case`` its config): the run goes on from
    its translation snapshot, or from the start of the translation's stage when it has
    none, and ends as the uninterrupted run, bit for bit; its recording (the part after
    the resume) goes to recording-resumed.rrd.
    ``rrd``: True for recording.rrd in the run folder, a path for elsewhere, False for none.
    Returns (result dict, run folder)."""
    clock, c_start = Stopwatch(), time.process_time()
    rf = open_run_folder("khosravi", case, root, name=name, resume=resume)
    specimens, key = Store(Path(root) / "khosravi" / "_specimens"), specimen_key(case)
    default_rrd = "recording-resumed.rrd" if resume is not None else "recording.rrd"
    recorder = _recording((rf.file(default_rrd) if rrd is True else Path(rrd)) if rrd else None, case, rf)
    with progress(quiet) as bar:
        run, reused = _started(case, rf.path / CHECKPOINT if resume is not None else None,
                               specimens if specimen_cache else None, key, bar, clock)
        rest = run.rest
        if not run.history:                 # the fill at rest is still there (not a resumed translation)
            corner_chains(run, rf.file("fig11_corner_chains.png"))

        def keep(blob: bytes) -> None:
            rf.save_checkpoint(CHECKPOINT, pickle.dumps({"run": blob, "specimen_reused": reused}))

        with clock("translation_s"):
            run = _translate(run, rest, recorder, bar, frames, clock, keep)
        # phi of the same material, looked up (or measured) after the long part so a
        # calibration running alongside can finish first
        with clock("biaxial_s"):
            phi_info = biaxial_phi(case, bar, card, root)
            # the peak: Khosravi et al.'s 20.7 deg is the plateau of a stiff-contact test, and
            # with converged impulses the critical state of free disks saturates at ~18.5 deg
            phi = float(phi_info["phi_peak_deg"])
            th = theories(phi, run.backfill.gamma, run.backfill.H)
    if recorder is not None:
        recorder.log_theory_profiles(list(th.values()), run.backfill.gamma, run.backfill.H)
        recorder.close()
    result = summarize(run, rest, phi, phi_info, th, reused, specimens.path(key, ".pkl"))
    # wall time on a shared machine depends on the other jobs: CPU time of this process too
    result["timings_s"] = {**clock.seconds, "total": clock.total, "cpu_total": time.process_time() - c_start}
    _write_outputs(rf, run, rest, result, th)
    drop_checkpoint(rf.path, CHECKPOINT)                     # finished: nothing to resume
    finish(rf, result, n_grains=run.backfill.n_grains, dt=case.solver.dt, iterations=case.solver.iterations,
           iterations_readings=case.reading_solver.iterations, friction=case.friction,
           wall_friction=case.material.wall_friction, specimen=result["specimen"], specimen_reused=reused,
           **result["timings_s"])
    return result, rf


def corner_chains(run: KhosraviRun, path: Path) -> Path:
    """Fig. 11(b) of the run's fill as it stands now (``figures.plot_corner_chains``)."""
    from .figures import plot_corner_chains
    frame = run.frame()
    wall_x = float(run.sim.walls["wall"].centres()[:, 0].mean())
    side = 1 if float(np.mean(frame.positions[:, 0])) > wall_x else -1
    return plot_corner_chains(frame, wall_x, side, run.backfill.H, path)


def _started(case: KhosraviCase, saved: Path | None, specimens: Store | None, key: str, bar,
             clock: Stopwatch) -> tuple[KhosraviRun, bool]:
    """The run read at rest, ready to translate: from the translation snapshot ``saved``
    when there is one (a resumed run), else the settled box (``settled_box``) read at
    rest. Returns (run, whether the specimen was a stored one)."""
    if saved is not None and saved.is_file():
        held = pickle.loads(saved.read_bytes())
        return KhosraviRun.restored(case, held["run"]), held["specimen_reused"]
    with clock("pluviation_s"):
        run, reused = settled_box(case, specimens, key, bar)
    with clock("at_rest_s"):
        run.at_rest()
    return run, reused


def _translate(run: KhosraviRun, rest, recorder, bar, frames: int, clock: Stopwatch,
               keep=lambda blob: None) -> KhosraviRun:
    """Move the wall to Dis/H = case.wall_disp_over_H_max (readings into ``run.history``),
    logging ``frames`` scenes; notes when the paper's active reading was reached. Every
    ``case.checkpoint_readings`` readings (the last aside) the run goes on from its own
    snapshot, handed to ``keep`` first (``settled_box`` says why). Returns the run at the
    end (a restored one when a snapshot was taken)."""
    case, bf = run.case, run.backfill
    t0 = time.perf_counter()
    n_total = int(math.ceil(case.wall_disp_over_H_max * bf.H / (case.wall_speed * case.window)))
    every = max(1, n_total // max(frames, 1))
    task = bar.add_task("translation", total=n_total, completed=len(run.history), status="")
    z, gH = run.panel_depths(), bf.gamma * bf.H
    if not run.history:
        _log(recorder, run, rest, z, 0.0, gH)
    while True:
        mark = None
        for r in run.translate():
            k = len(run.history)
            bar.update(task, completed=k, status=f"Dis/H {r.dis / bf.H:.5f}")
            if "translation_to_active_s" not in clock.seconds and r.dis / bf.H >= case.wall_disp_over_H_active:
                # the paper's movement ends here; a validation run goes on to judge steadiness
                clock.seconds["translation_to_active_s"] = time.perf_counter() - t0
            if recorder is not None and k % every == 0:
                _log(recorder, run, r, z, r.dis / bf.H, gH)
            if k % case.checkpoint_readings == 0 and r.dis / bf.H < case.wall_disp_over_H_max:
                mark = run.snapshot()
                break
        if mark is None:
            return run
        keep(mark)
        run = KhosraviRun.restored(case, mark)


def _recording(path: Path | None, case: KhosraviCase, folder: RunFolder):
    """The run's recorder (Rerun at ``path``, VTK with ``--vtk``), or None when it records nothing."""
    from viz.recorder import wall_layout
    recorder = open_recording(path, study="khosravi", dim=2, folder=folder,
                              recording_id=f"khosravi-{case.seed}", layout=wall_layout(2, "disks, pressure cells and force chains"))
    if not recorder.enabled:
        return None
    recorder.log_case(_case_text(case))
    return recorder


def _case_text(case: KhosraviCase) -> str:
    return ("# Khosravi et al. translation case (dem2d / pymunk)\n\n```\n"
            + json.dumps(to_plain(case), indent=1) + "\n```\n")


def _log(recorder, run, r, z, wall_disp_over_H, gH) -> None:
    if recorder is None:
        return
    frame = run.frame()
    frame = frame._replace(panel_force=np.concatenate(
        [np.column_stack([-r.sigma * run.case.panel_height, -r.tau * run.case.panel_height]),
         np.zeros((len(frame.panel_area) - len(r.sigma), 2))]))
    d, m, _ = run.readings_of(r)
    H = run.backfill.H
    F = normal_thrust(r.sigma, z, run.case.panel_height)
    recorder.log_frame(frame, wall_disp_over_H=wall_disp_over_H, profile=(d / H, m / gH),
                       metrics={"K": 2 * F / (gH * H), "thrust_kN": F / 1e3,
                                "resultant_height_over_H": resultant_height_over_H(r.sigma, z, run.case.panel_height, H)})


def active_record(run: KhosraviRun):
    """The wall reading the active figures come from: the first window centred at or past
    Dis/H = case.wall_disp_over_H_active (Khosravi et al. read the active state at 0.003), or the
    last one if the wall stopped before it."""
    target = run.case.wall_disp_over_H_active * run.backfill.H
    for r in run.history:
        if r.dis >= target * (1.0 - 1e-9):
            return r
    return run.history[-1]


def summarize(run: KhosraviRun, rest, phi: float, phi_info: dict, th: dict, reused: bool,
              cache: Path) -> dict:
    """Headline numbers: the ones the validation targets judge, each with what it is
    compared to."""
    c, bf = run.case, run.backfill
    H, g = bf.H, bf.gamma
    act = active_record(run)
    d, m_rest, _ = run.readings_of(rest)
    _, m_act, _ = run.readings_of(act)
    F_act = normal_thrust(act.sigma, run.panel_depths(), c.panel_height)
    return {
        "case": "khosravi", "particles": bf.n_grains, "seed": c.seed, "dt_s": c.solver.dt,
        "iterations": c.solver.iterations,              # sweeps a step during the fill
        "iterations_readings": c.reading_solver.iterations,  # at rest and translation
        "friction": c.friction, "wall_friction": c.material.wall_friction,
        "pymunk": package_versions().get("pymunk"),
        "H_m": H, "gamma_N_per_m3": g, "porosity": bf.porosity, "porosity_interior": bf.interior_porosity,
        "specimen_reused": reused, "specimen": str(cache),
        "wall_disp_over_H_active": float(act.dis / H),      # where the "active" figures are read
        "wall_disp_over_H_end": float(run.history[-1].dis / H),  # where the wall stopped (steadiness judged up to it)
        "phi_biaxial_source": phi_info.get("from"),
        "dem": {"phi_biaxial": phi, "phi_biaxial_peak": phi_info.get("phi_peak_deg"),
                "phi_biaxial_cs": phi_info.get("phi_cs_deg"),
                **_wall_figures(run, rest, act, phi), **_balance(rest, bf)},
        "readings": {"depth_over_H": (d / H).tolist(), "at_rest_over_gammaH": (m_rest / (g * H)).tolist(),
                     "active_over_gammaH": (m_act / (g * H)).tolist()},
        "theory": [theory_row(k, p, f"phi {phi:.2f} deg (biaxial), delta = phi") for k, p in th.items()],
        "theory_thrust_over_dem_active": {k: p.normal_force() / F_act for k, p in th.items() if k != "jaky"},
        "profile": {"at_rest": _profile(run, rest).as_dict(), "active": _profile(run, act).as_dict()},
    }


def _profile(run: KhosraviRun, reading):
    """A wall reading as the record the theories return (studies.measures.dem_profile)."""
    return dem_profile(run.panel_depths(), reading.sigma, reading.tau, run.case.panel_height, run.backfill.H,
                       run.backfill.gamma, source=f"dem2d, {run.backfill.n_grains} disks, 10 mm cells")


def _wall_figures(run: KhosraviRun, rest, act, phi: float) -> dict:
    """At-rest K against Jaky, active thrust against Rankine, steadiness, and the bottom
    corner (PS0) against the readings above it and Jaky at its depth."""
    c, bf = run.case, run.backfill
    z, ph, H, g = run.panel_depths(), c.panel_height, bf.H, bf.gamma
    K0_jaky = jaky_coefficient(math.radians(phi))
    K_up = k_upper_half(rest.sigma, z, ph, g, H)
    d, m_rest, ps0_rest = run.readings_of(rest)
    _, m_act, ps0_act = run.readings_of(act)
    F_rest, F_act = normal_thrust(rest.sigma, z, ph), normal_thrust(act.sigma, z, ph)
    F_rankine = 0.5 * rankine_coefficient(math.radians(phi), 0.0) * g * H**2
    dis = np.array([0.0] + [r.dis / H for r in run.history])
    F = np.array([F_rest] + [normal_thrust(r.sigma, z, ph) for r in run.history])
    z_ps0 = H - 0.5 * ph
    return {
        "K_at_rest_upper_half": K_up, "jaky_K0": K0_jaky, "K_at_rest_upper_half_over_jaky": K_up / K0_jaky,
        "K_at_rest_total": 2 * F_rest / (g * H**2), "K_active_total": 2 * F_act / (g * H**2),
        "active_thrust_N_per_m": F_act, "rankine_thrust_N_per_m": F_rankine,
        "active_thrust_over_rankine": F_act / F_rankine,
        "resultant_height_over_H_at_rest": resultant_height_over_H(rest.sigma, z, ph, H),
        "resultant_height_over_H_active": resultant_height_over_H(act.sigma, z, ph, H),
        "active_below_at_rest_everywhere": bool(np.all(m_act < m_rest)),
        "wall_disp_over_H_steady": steady_displacement(dis, F, 0.9),
        "wall_disp_over_H_steady_95": steady_displacement(dis, F, 0.95),
        "PS0_at_rest_over_gammaH": ps0_rest / (g * H),
        "PS0_at_rest_over_jaky": ps0_rest / (K0_jaky * g * z_ps0),
        "PS0_active_over_gammaH": ps0_act / (g * H),
        "lowest_reading_at_rest_over_gammaH": float(m_rest[0] / (g * H)) if len(m_rest) else None,
        # a milder measure of the corner: PS0 against the straight line through the
        # readings (the paper: "nearly linear ... except for the lower corner")
        "PS0_at_rest_over_linear_trend": _over_linear_trend(ps0_rest, d, m_rest, z_ps0),
    }


def _balance(rest, bf) -> dict:
    """The vertical reactions of floor and walls against the grains' weight."""
    return {"weight_balance": -(rest.floor_fy + rest.wall_fy + rest.far_fy) / bf.weight,
            "wall_friction_share_of_weight": -rest.wall_fy / bf.weight}


def _over_linear_trend(value: float, depth: np.ndarray, readings: np.ndarray, z: float) -> float | None:
    """value / the least-squares straight line through (depth, readings) at depth z."""
    if len(readings) < 2:
        return None
    return float(value / np.polyval(np.polyfit(depth, readings, 1), z))


def _write_outputs(rf, run, rest, result, th) -> None:
    """The run folder's tables and figures (Khosravi Figs. 9, 10, 12, 13)."""
    _write_tables(rf, run, rest)
    _write_figures(rf, run, rest, result, th)


def _readings_series(run: KhosraviRun, rest) -> tuple[np.ndarray, list, dict]:
    """Dis/H of every reading (at rest first), the CSV rows of the 4-panel readings and
    PS0, and each reading point's series of sigma / (gamma H) for Fig. 12."""
    c, H, gH = run.case, run.backfill.H, run.backfill.gamma * run.backfill.H
    rows, series = [], {}
    dis = np.array([0.0] + [r.dis / H for r in run.history])
    for k, r in enumerate([rest] + run.history):
        d, m, ps0 = run.readings_of(r)
        for j, (dz, mv) in enumerate(zip(d, m)):
            rows.append([dis[k], f"P{j + 1}", dz / H, mv / 1e3, mv / gH])
            series.setdefault(f"P{j + 1} (z/H = {dz / H:.2f})", []).append(mv / gH)
        rows.append([dis[k], "PS0", (H - 0.5 * c.panel_height) / H, ps0 / 1e3, ps0 / gH])
        series.setdefault("PS0 (bottom panel)", []).append(ps0 / gH)
    return dis, rows, series


def _write_tables(rf, run: KhosraviRun, rest) -> None:
    """Panels at rest and active, the readings against Dis/H, every panel of every
    window (a report can be re-read at any Dis/H)."""
    bf = run.backfill
    z, H = run.panel_depths(), bf.H
    gH = bf.gamma * H
    act = active_record(run)
    for name, r, extra in (("at_rest_panels.csv", rest, ["contacts_per_step"]), ("active_panels.csv", act, [])):
        rf.write_csv(name, ["panel", "depth_m", "depth_over_H", "sigma_h_kPa", "tau_kPa", "sigma_over_gammaH"] + extra,
                     [[i, z[i], z[i] / H, r.sigma[i] / 1e3, r.tau[i] / 1e3, r.sigma[i] / gH]
                      + ([r.contacts[i]] if extra else []) for i in range(len(z))])
    dis, rows, _ = _readings_series(run, rest)
    rf.write_csv("readings_vs_displacement.csv", ["wall_disp_over_H", "point", "depth_over_H", "sigma_h_kPa",
                                                   "sigma_over_gammaH"], rows)
    rf.write_csv("panels_vs_displacement.csv", ["wall_disp_over_H", "panel", "depth_m", "sigma_h_kPa", "tau_kPa"],
                 [[dis[k], i, z[i], r.sigma[i] / 1e3, r.tau[i] / 1e3]
                  for k, r in enumerate([rest] + run.history) for i in range(len(z))])


def _write_figures(rf, run: KhosraviRun, rest, result: dict, th: dict) -> None:
    """Khosravi et al.'s Figs. 9 (while filling, with backfilling.csv), 10 (at rest), 12
    (readings against Dis/H) and 13 (profiles against the theories)."""
    from .figures import plot_khosravi_at_rest, plot_khosravi_profiles, plot_khosravi_vs_displacement
    from .backfilling import write_backfilling

    c, bf, dem = run.case, run.backfill, result["dem"]
    z, H, g = run.panel_depths(), bf.H, bf.gamma
    gH = g * H
    act = active_record(run)
    d, m_rest, ps0 = run.readings_of(rest)
    _, m_act, _ = run.readings_of(act)
    dis, _, series = _readings_series(run, rest)
    inside = z > 0
    plot_khosravi_at_rest(d / H, m_rest / gH, rf.file("fig10_at_rest.png"), jaky_K=dem["jaky_K0"],
                          ps0=((H - 0.5 * c.panel_height) / H, ps0 / gH),
                          panels=(z[inside] / H, rest.sigma[inside] / gH),
                          title=f"At rest, H = {H * 1e3:.0f} mm, {bf.n_grains} disks\n"
                                f"K upper half {dem['K_at_rest_upper_half']:.3f}")
    plot_khosravi_vs_displacement(dis, {k: np.array(v) for k, v in series.items()},
                                  rf.file("fig12_pressure_vs_displacement.png"), steady=dem["wall_disp_over_H_steady"],
                                  title=f"H = {H * 1e3:.0f} mm, {bf.n_grains} disks, "
                                        f"wall speed {c.wall_speed * 1e3:g} mm/s")
    plot_khosravi_profiles(d / H, m_rest / gH, m_act / gH, [p for k, p in th.items() if k != "jaky"],
                           rf.file("fig13_profiles.png"), jaky_K=dem["jaky_K0"], gamma=g, H=H,
                           wall_disp_over_H=act.dis / H, title=f"phi_biaxial = {dem['phi_biaxial']:.1f} deg, delta = phi")
    write_backfilling(rf, bf.layer_readings, c.panel_height, gamma=g, H=H, n_grains=bf.n_grains)


#: the validation moves the wall on to here and reads the active state at 0.003: a run that
#: stops at 0.003 cannot show the pressure still falling after it (at full size 87 % of the
#: drop to 0.01 is there by 0.003 at 40 sweeps, over 90 % at 80; docs/validation/khosravi.md)
VALIDATION_DIS_OVER_H = 0.01


def validate_khosravi(*, out_dir: str | Path, root: str | Path = "runs", quiet: bool = False,
                      case: KhosraviCase | None = None, rrd: bool = False, log=None) -> dict:
    """Full-size run (H = 0.3 m, D50 = 1.16 mm) and its report: ``khosravi.json`` and
    ``khosravi.md`` with the figures in ``out_dir`` (docs/validation by default).

    Its two runs are read, not run again, when a finished run of the same case is there
    (the same command run again after an interruption): the translation in
    ``<root>/khosravi/validate-translation-<key>`` (``validation_run``), the free fill in
    ``<root>/khosravi/backfilling-<key>`` (``backfilling_run``); after a change of the code,
    remove those folders to run them again. ``log``: one line each (None: to stderr
    unless ``quiet``)."""
    from studies.khosravi.report import write_report

    if log is None:
        import sys
        log = (lambda msg: None) if quiet else (lambda msg: print(msg, file=sys.stderr, flush=True))
    case = case or KhosraviCase(wall_disp_over_H_max=VALIDATION_DIS_OVER_H)
    result, rf = validation_run(case, root=root, quiet=quiet, rrd=rrd, log=log)
    backfilling = None
    if case.pluviation.hold_depth > 0:  # Fig. 9 needs every cell read: a free fill of the same box
        backfilling = backfilling_run(case, root=root, quiet=quiet, log=log)
    return write_report(result, rf, Path(out_dir), REFERENCE, backfilling=backfilling)


def validation_run(case: KhosraviCase, *, root: str | Path = "runs", quiet: bool = False, rrd: bool = False,
                   log=lambda msg: None) -> tuple[dict, RunFolder]:
    """(result.json, run folder) of ``compare_khosravi`` on ``case`` in
    ``<root>/khosravi/validate-translation-<key>`` (key: the hash of the resolved case, so
    a changed setting never reads a stale run): read when that folder holds a finished
    run, resumed when it holds an interrupted one (from its translation snapshot, or
    with the pluviation going on from its stored one: ``settled_box``), else run there.
    The result is read back from result.json either way, so a report is the same from a
    new run, a resumed one or a finished one."""
    folder = Path(root) / "khosravi" / f"validate-translation-{content_key(case)}"

    def run(resume: Path | None) -> None:
        if resume is not None:
            compare_khosravi(case, root=root, quiet=quiet, rrd=rrd, resume=resume)
        else:
            compare_khosravi(case, root=root, quiet=quiet, rrd=rrd, name=folder.name)

    return run_once(folder, run, resumable=has_config, log=log), RunFolder.existing(folder, seed=case.seed)


def backfilling_run(case: KhosraviCase, *, root: str | Path = "runs", quiet: bool = False,
                    log=lambda msg: None) -> tuple[dict, RunFolder]:
    """(result.json, run folder) of the free fill of ``case``'s box (``run_backfilling``,
    in ``<root>/khosravi/<backfilling_name(case)>``, named by the free-fill case's content
    key): read when that folder holds a finished fill, else run afresh, whatever the
    folder held removed first."""
    from .backfilling import backfilling_name, run_backfilling
    folder = Path(root) / "khosravi" / backfilling_name(case)
    result = run_once(folder, lambda _: run_backfilling(case, root=root, quiet=quiet), log=log)
    return result, RunFolder.existing(folder, seed=case.seed)
