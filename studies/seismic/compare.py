"""``wallsim compare seismic``: one frequency, static stage (cached) then shaking; the
result in prototype units (reference section 1: lengths and times x N, stresses x 1,
force per width x N, moment per width x N^2), tables, figures and the recording."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..runner import Stopwatch, drop_checkpoint, finish, open_run_folder
from ..store import load_npz, npz_bytes
from .case import SeismicCase
from .measures import (STRAIN_CELL_GRAINS, STRAIN_MIN_GRAINS, STRAIN_TIMES, mononobe_okabe_overlay, period_mean,
                       rotation_fit, row_moments, settlement, shear_strain_map, unit_weight)
from .run import Prepared, Shaken, checkpoint_samples, prepare, shake

#: the shaking's checkpoint in the run folder (dropped once the run has its result)
CHECKPOINT = "checkpoints/shake.npz"


def wall_summary(case: SeismicCase, x0: np.ndarray, reading, base: float = 0.0) -> dict:
    """Displacement relative to the base (toward the excavation), rotation, pivot,
    thrusts and the largest moment of one reading against the wall rows ``x0`` before
    excavation, the base displaced by ``base`` along x [m] (prototype units)."""
    n = case.scale_N
    u = -(reading.x - x0 - base)
    rot, pivot, top = rotation_fit(reading.z, u, case)
    return {"top_displacement_m": float(u[-1] * n), "fit_top_displacement_m": top * n, "rotation_deg": rot,
            "pivot_height_over_wall_length": pivot, "thrust_front_kN_per_m": reading.thrust_front * n / 1e3,
            "thrust_back_kN_per_m": reading.thrust_back * n / 1e3,
            "max_moment_kN_m_per_m": float(np.max(np.abs(reading.moment))) * n * n / 1e3}


def passive_K(case: SeismicCase, reading, porosity: float, depth_proto: float = 1.5) -> float:
    """sigma_h / (gamma z) on the front face at ``depth_proto`` [m] below the dredge line
    (the paper's Fig. 4 point): the row nearest that depth."""
    z = case.front_height - depth_proto / case.scale_N
    k = int(np.argmin(np.abs(reading.z - z)))
    sigma_v = unit_weight(case, porosity) * case.scale_N * (case.front_height - reading.z[k])
    return float(reading.sigma_front[k] / sigma_v) if sigma_v > 0 else math.nan


def dynamic_summary(case: SeismicCase, x0, shaken: Shaken, porosity: float) -> dict:
    """Static (start of shaking), maximum and residual (end) figures of the paper's Figs. 2-6."""
    static, final = shaken.readings[0], shaken.readings[-1]
    m_static = float(np.max(np.abs(static.moment)))
    m_max = max(float(np.max(np.abs(r.moment))) for r in shaken.readings)
    return {"static": wall_summary(case, x0, static), "residual": wall_summary(case, x0, final, shaken.base[-1]),
            "max_moment_over_static": m_max / m_static if m_static > 0 else math.nan,
            "residual_moment_over_static": float(np.max(np.abs(final.moment))) / m_static if m_static > 0 else math.nan,
            "passive_K_static_at_1_5m": passive_K(case, static, porosity),
            "passive_K_max_at_1_5m": max(passive_K(case, r, porosity) for r in shaken.readings)}


def rest_summary(case: SeismicCase, x0, shaken: Shaken) -> dict:
    """How the wall moved while the shaking model rested before the base moved
    (prototype): its top and thrusts as the static stage left them and at the end of the
    rest, and the top's movement over the rest's last fifth (how far from standing)."""
    n, r = case.scale_N, shaken.rest.readings
    top = np.array([-(x.x[-1] - x0[-1]) * n for x in r])
    last = top[-max(2, len(top) // 5):]
    return {"rest_s": case.rest_s, "readings": len(r),
            "top_displacement_m": [float(top[0]), float(top[-1])],
            "top_change_over_last_fifth_m": float(last[-1] - last[0]),
            "thrust_back_kN_per_m": [r[0].thrust_back * n / 1e3, r[-1].thrust_back * n / 1e3],
            "thrust_front_kN_per_m": [r[0].thrust_front * n / 1e3, r[-1].thrust_front * n / 1e3]}


def series_table(case: SeismicCase, x0, shaken: Shaken, porosity: float) -> dict[str, np.ndarray]:
    """Time series in prototype units: time, base displacement, wall top displacement
    relative to the base (toward the excavation), thrusts, largest moment, the wall's
    rotation (``rotation_fit``) and the passive K 1.5 m below the dredge line (each
    reading, and its mean over one period of the base motion: the paper's Fig. 4)."""
    n = case.scale_N
    u = [-(r.x - x0 - b) for r, b in zip(shaken.readings, shaken.base)]
    t = shaken.time * n
    K = np.array([passive_K(case, r, porosity) for r in shaken.readings])
    return {"time_s": t, "base_displacement_m": shaken.base * n,
            "top_displacement_m": np.array([ur[-1] * n for ur in u]),
            "thrust_front_kN_per_m": np.array([r.thrust_front * n / 1e3 for r in shaken.readings]),
            "thrust_back_kN_per_m": np.array([r.thrust_back * n / 1e3 for r in shaken.readings]),
            "max_moment_kN_m_per_m": np.array([np.max(np.abs(r.moment)) * n * n / 1e3 for r in shaken.readings]),
            "rotation_deg": np.array([rotation_fit(r.z, ur, case)[0] for r, ur in zip(shaken.readings, u)]),
            "passive_K_at_1_5m": K,
            "passive_K_period_mean_at_1_5m": period_mean(t, K, 1.0 / case.frequency if case.frequency > 0 else 0.0)}


def profiles_table(case: SeismicCase, shaken: Shaken) -> dict[str, np.ndarray]:
    """Face pressures [kPa] static / max / residual against prototype height [m]."""
    n = case.scale_N
    r0, r1 = shaken.readings[0], shaken.readings[-1]
    front = np.array([r.sigma_front for r in shaken.readings])
    back = np.array([r.sigma_back for r in shaken.readings])
    return {"height_m": r0.z * n, "front_static_kPa": r0.sigma_front / 1e3, "front_max_kPa": front.max(0) / 1e3,
            "front_residual_kPa": r1.sigma_front / 1e3, "back_static_kPa": r0.sigma_back / 1e3,
            "back_max_kPa": back.max(0) / 1e3, "back_residual_kPa": r1.sigma_back / 1e3}


def settlement_table(case: SeismicCase, prepared: Prepared, shaken: Shaken):
    """Settlement [m] of the retained ground against distance from the wall [m], prototype."""
    soil = np.setdiff1d(np.arange(len(prepared.model.radii)), prepared.model.wall)
    x0 = shaken.rest.start
    x1 = _positions(shaken.final)
    dist, s = settlement(x0, x1, prepared.model.radii, case, soil)
    return {"distance_m": dist * case.scale_N, "settlement_m": s * case.scale_N}


def _positions(arrays: dict) -> np.ndarray:
    out = np.empty_like(arrays["spheres.x"])
    out[arrays["original_index"]] = arrays["spheres.x"]
    return out


def strain_maps(case: SeismicCase, prepared: Prepared, shaken: Shaken, cell_grains: float = STRAIN_CELL_GRAINS):
    """[(Snapshot, ShearStrainMap)]: the soil's maximum shear strain since the start of
    shaking at each snapshot (the paper's Fig. 7), model units."""
    soil = np.setdiff1d(np.arange(len(prepared.model.radii)), prepared.model.wall)
    x0 = shaken.rest.start
    return [(snap, shear_strain_map(case, x0, snap.positions, soil, cell_grains)) for snap in shaken.snapshots]


def strain_summary(case: SeismicCase, prepared: Prepared, shaken: Shaken, maps, asked=STRAIN_TIMES) -> dict:
    """What result.json says of the strain field: times taken and skipped, the cell
    [A], the largest and 95th-percentile strain per time, and how the last time's 95th
    percentile moves with the cell size (1.5, 2, 3 mean diameters)."""
    taken = [s.asked_s for s, _ in maps]
    out = {"asked_s": list(asked), "times_s": [s.time_s for s, _ in maps],
           "skipped_s": [t for t in asked if t not in taken],
           "cell_grains": STRAIN_CELL_GRAINS, "cell_m": STRAIN_CELL_GRAINS * case.d_mean * case.scale_N,
           "min_grains_per_cell": STRAIN_MIN_GRAINS,
           "largest": [_nanstat(np.nanmax, m.max_shear_strain) for _, m in maps],
           "p95": [_nanstat(_p95, m.max_shear_strain) for _, m in maps],
           "assumptions": "cell size and minimum grains per cell [A] (the paper's sampling spheres are not sized); "
                          "strain since the start of shaking, averaged across the periodic slab"}
    if maps:
        last = shaken._replace(snapshots=shaken.snapshots[-1:])
        out["p95_last_by_cell_grains"] = {
            f"{c:g}": _nanstat(_p95, strain_maps(case, prepared, last, c)[0][1].max_shear_strain)
            for c in (1.5, STRAIN_CELL_GRAINS, 3.0)}
    return out


def _nanstat(f, g) -> float:
    return float(f(g)) if np.isfinite(g).any() else math.nan


def _p95(g) -> float:
    return np.nanpercentile(g, 95)


def strain_table(case: SeismicCase, maps) -> dict[str, np.ndarray]:
    """The strain maps as one long table, prototype units: time [s], cell centre x from
    the wall's front face and height above the base [m], grains in the cell, maximum
    shear strain [-] (nan: too few grains)."""
    n = case.scale_N
    cols = {"time_s": [], "x_m": [], "height_m": [], "grains": [], "max_shear_strain": []}
    for snap, m in maps:
        xc, zc = 0.5 * (m.x_edges[1:] + m.x_edges[:-1]), 0.5 * (m.z_edges[1:] + m.z_edges[:-1])
        X, Z = np.meshgrid(xc, zc, indexing="ij")
        for key, v in (("time_s", np.full(X.size, snap.time_s)), ("x_m", X.ravel() * n),
                       ("height_m", Z.ravel() * n), ("grains", m.grains.ravel()),
                       ("max_shear_strain", m.max_shear_strain.ravel())):
            cols[key].append(v)
    return {k: np.concatenate(v) if v else np.array([]) for k, v in cols.items()}


def compare_seismic(case: SeismicCase, *, root: Path, fraction: float = 1.0, log=lambda s: None,
                    record: bool = False, rrd=None, progress=None,
                    strain_times: tuple = STRAIN_TIMES, resume: Path | None = None,
                    checkpoint_every_s: float | None = None) -> tuple[dict, Path]:
    """One frequency: prepare (cached under root/seismic/cache) and shake; writes the run
    folder (and recording.rrd with ``record``); the shear-strain field at ``strain_times``
    (prototype [s]; the paper's Fig. 7 times by default).

    The shaking is checkpointed to <run folder>/checkpoints/shake.npz (every
    ``checkpoint_every_s`` of wall time, default ``run.CHECKPOINT_EVERY_S``, and every
    10 % of the motion); with ``resume`` (an interrupted run's folder, ``case`` its
    config) the run continues from its checkpoint (from the start of shaking when it
    has none) and ends as the uninterrupted run would, bit for bit; its recording (the
    part after the resume) goes to recording-resumed.rrd unless ``rrd`` names a file."""
    clock = Stopwatch()
    folder = open_run_folder("seismic", case, root, resume=resume)
    default_rrd = "recording-resumed.rrd" if resume is not None else "recording.rrd"
    path = (Path(rrd) if isinstance(rrd, (str, Path)) else folder.path / default_rrd) if record else None
    saved = folder.path / CHECKPOINT
    state = load_npz(saved) if resume is not None and saved.is_file() else None
    if state is not None:
        log(f"resuming the shaking after {checkpoint_samples(state)} readings")

    def save(arrays: dict) -> None:
        folder.save_checkpoint(CHECKPOINT, npz_bytes(arrays))

    with clock("prepare"):
        prepared = prepare(case, Path(root) / "seismic" / "cache", log=log)
    x0 = np.array(prepared.info["x_wall_before_excavation"])
    rows = prepared.model.wall_row
    x0_rows = np.bincount(rows, weights=x0[:, 0]) / np.bincount(rows)
    porosity = float(prepared.info["porosity"])
    rec = _Recording(case, path, folder, x0_rows, prepared.model, porosity, progress)
    if state is not None:
        rec.count = checkpoint_samples(state)          # frames every 10th reading, as in one run
    try:
        with clock("shake"):
            shaken = shake(case, prepared, fraction=fraction, on_sample=rec.on_sample, snapshot_times=strain_times,
                           checkpoint=save, resume=state, checkpoint_every_s=checkpoint_every_s)
        with clock("strain"):
            maps = strain_maps(case, prepared, shaken)
        rec.finish(maps)
    finally:
        rec.close()
    result = _result(case, prepared, shaken, x0_rows, porosity, fraction)
    result["max_shear_strain"] = strain_summary(case, prepared, shaken, maps, strain_times)
    if result["max_shear_strain"]["skipped_s"]:
        log(f"shear strain: {result['max_shear_strain']['skipped_s']} s (prototype) not reached by this run, skipped")
    series = series_table(case, x0_rows, shaken, porosity)
    _write_tables(folder, case, prepared, shaken, series, maps)
    _figures(folder, case, shaken, series, porosity, settlement_table(case, prepared, shaken), maps,
             result["max_shear_strain"]["skipped_s"])
    result |= {"wall_time_s": clock.total, "stage_seconds": clock.seconds, "run_folder": str(folder.path)}
    drop_checkpoint(folder.path, CHECKPOINT)                     # finished: nothing to resume
    finish(folder, result, particles=result["particles"], seed=case.seed, dt_s=result["dt_s"],
           steps=shaken.steps, wall_time_s=clock.total)
    return result, folder.path



def _layout():
    """How the recording opens: grains, the sheet pile coloured by its moment and the
    shear-strain cells; thrust on both faces, passive K 1.5 m below the dredge line,
    wall top and rotation, the largest moment."""
    from viz import paths as P
    from viz.recorder import Layout, Series
    m = P.METRICS
    return Layout(3, "grains, sheet pile (moment), max shear strain", (
        Series("thrust on both faces kN/m", m, ("$origin/thrust_back_kN_per_m", "$origin/thrust_front_kN_per_m")),
        Series("passive K 1.5 m below dredge line", m, ("$origin/passive_K_at_1_5m",)),
        Series("wall top m, rotation deg", m, ("$origin/top_displacement_m", "$origin/rotation_deg")),
        Series("largest moment kN m/m", m, ("$origin/max_moment_kN_m_per_m",))))


class _Recording:
    """The run's recording (prototype seconds on the sim_time timeline) and progress bar:
    every sample the thrusts, wall top, rotation, passive K, largest moment and the sheet
    pile's balls (kept, then logged at the end with one moment scale: the run's largest);
    the grains every 10th sample; the shear-strain cells at their snapshot times."""

    def __init__(self, case: SeismicCase, path, folder, x0_rows, model, porosity: float, progress):
        from ..runner import open_recording
        self.rec = open_recording(path, study="seismic", recording_id=folder.path.name, dim=3,
                                  layout=_layout(), folder=folder)
        self.case, self.x0_rows, self.model, self.porosity, self.progress = case, x0_rows, model, porosity, progress
        self.count = 0
        self.wall: list = []          # (step, time, wall ball positions, moment per ball [kN m/m])

    def on_sample(self, sim, reading, t_model, base, done, total):
        from dem3d import frame as take_frame
        if self.rec.enabled:
            self._log(sim, reading, t_model * self.case.scale_N, base, take_frame)
        self.count += 1
        if self.progress is not None:
            self.progress(done, total)

    def _log(self, sim, reading, t, base, take_frame):
        n, case = self.case.scale_N, self.case
        u = -(reading.x - self.x0_rows - base)
        metrics = {"thrust_back_kN_per_m": reading.thrust_back * n / 1e3,
                   "thrust_front_kN_per_m": reading.thrust_front * n / 1e3,
                   "top_displacement_m": float(u[-1] * n), "rotation_deg": rotation_fit(reading.z, u, case)[0],
                   "passive_K_at_1_5m": passive_K(case, reading, self.porosity),
                   "max_moment_kN_m_per_m": float(np.max(np.abs(reading.moment))) * n * n / 1e3}
        if self.count % 10 == 0:
            self.rec.log_frame(take_frame(sim)._replace(time=t), metrics=metrics)
        else:
            self.rec.log_metrics(sim.step_count, t, metrics)
        engine = np.empty(sim.n_spheres, np.int64)
        engine[sim.original_index] = np.arange(sim.n_spheres)
        moment = row_moments(reading)[self.model.wall_row] * n * n / 1e3
        self.wall.append((int(sim.step_count), t, sim.spheres.x[engine[self.model.wall]].copy(), moment))

    def finish(self, maps) -> None:
        """The sheet pile (moment colours) and the strain cells, and the case text."""
        if not self.rec.enabled:
            return
        from viz import paths as P
        case = self.case
        m_max = max((float(np.max(np.abs(m))) for *_, m in self.wall), default=0.0)
        for step, t, x, m in self.wall:
            self.rec.log_scalar_points(P.SHEET_PILE, step, t, x, 0.55 * case.wall_ball, m, m_max, diverging=True)
        g_all = np.concatenate([g.max_shear_strain.ravel() for _, g in maps]) if maps else np.array([])
        g_max = float(np.nanpercentile(g_all, 99)) if np.isfinite(g_all).any() else 1.0
        for snap, g in maps:
            xc, zc = 0.5 * (g.x_edges[1:] + g.x_edges[:-1]), 0.5 * (g.z_edges[1:] + g.z_edges[:-1])
            X, Z = np.meshgrid(xc, zc, indexing="ij")
            centres = np.column_stack([X.ravel(), np.full(X.size, -0.75 * case.width), Z.ravel()])
            half = np.tile([0.5 * np.diff(g.x_edges)[0], 0.02 * case.width, 0.5 * np.diff(g.z_edges)[0]], (X.size, 1))
            self.rec.log_scalar_boxes(P.SHEAR_STRAIN, snap.step, snap.time_s, centres, half,
                                      g.max_shear_strain.ravel(), g_max)
        self.rec.log_case(
            f"# Sizkow & El Shamy, {case.frequency:g} Hz, 0.1 g (prototype)\n\nresolution {case.resolution}, "
            f"grain scale {case.scale:g}; scene in model metres, time in prototype seconds.\n\n"
            f"* world/sheet_pile: bending moment of each ball's row, blue -{m_max:.3g} ... white 0 ... red "
            f"+{m_max:.3g} kN m/m (prototype; + the retained face in tension)\n"
            f"* world/shear_strain (beside the slab, y < 0): maximum shear strain since the start of shaking, "
            f"viridis 0 ... {g_max:.3g} (99th percentile), cells of {STRAIN_CELL_GRAINS:g} mean diameters [A], "
            f"at {', '.join(f'{s.time_s:g}' for s, _ in maps) or 'no'} s")

    def close(self) -> None:
        self.rec.close()


def _result(case, prepared, shaken, x0_rows, porosity, fraction) -> dict:
    from .case import prototype_factors
    info = prepared.info
    n_main = int(prepared.main["spheres.x"].shape[0])
    n_cols = [int(c["spheres.x"].shape[0]) for c in prepared.columns]
    mo = mononobe_okabe_overlay(case, porosity)
    return {"case": "seismic", "frequency_Hz": case.frequency, "resolution": case.resolution,
            "grain_scale": case.scale, "particles": n_main, "column_particles": n_cols,
            "wall_balls": int(len(prepared.model.wall)), "porosity": porosity, "dt_s": float(info["dt_s"]),
            "steps": shaken.steps, "fraction_of_motion": fraction, "shake_seconds": shaken.seconds,
            "steps_per_s": shaken.steps / shaken.seconds if shaken.seconds > 0 else math.nan,
            "prepare": {k: v for k, v in info.items() if k != "x_wall_before_excavation"},
            "prototype": dynamic_summary(case, x0_rows, shaken, porosity),
            "rest": rest_summary(case, x0_rows, shaken),
            "mononobe_okabe": {k: {"thrust_kN_per_m": p.thrust / 1e3, "K": p.K} for k, p in mo.items()},
            "units": "prototype (model x " + ", ".join(f"{k} {v:g}" for k, v in
                                                      prototype_factors(case.scale_N).items()) + ")"}


def _write_tables(folder, case, prepared, shaken, series, maps) -> None:
    for name, table in (("series.csv", series), ("pressure_profiles.csv", profiles_table(case, shaken)),
                        ("settlement.csv", settlement_table(case, prepared, shaken)),
                        ("strain_field.csv", strain_table(case, maps))):
        cols = list(table)
        folder.write_csv(name, cols, zip(*(np.asarray(table[c]) for c in cols)))


def _figures(folder, case, shaken, series, porosity, settled, maps, skipped) -> None:
    from .figures import plot_seismic, plot_seismic_K_rotation, plot_seismic_strain
    title = f"{case.frequency:g} Hz, 0.1 g (prototype), grain scale {case.scale:g}"
    mo = mononobe_okabe_overlay(case, porosity)
    plot_seismic(case.scale_N, shaken.readings, series, profiles_table(case, shaken), mo,
                 folder.path / "seismic.png", settlement=settled, title=title)
    plot_seismic_K_rotation(series["rotation_deg"], series["passive_K_at_1_5m"],
                            series["passive_K_period_mean_at_1_5m"], folder.path / "K_vs_rotation.png",
                            K_p={"Coulomb K_P (phi 31 deg, delta 0)": mo["passive_static"].K,
                                 "Mononobe-Okabe K_PE (kh 0.1)": mo["passive_MO"].K},
                            title=f"K 1.5 m below the dredge line vs wall rotation (Fig. 4)\n{title}")
    n = case.scale_N
    note = (f"cells of {STRAIN_CELL_GRAINS:g} mean diameters, >= {STRAIN_MIN_GRAINS} grains [A]; "
            "strain since the start of shaking, averaged across the periodic slab")
    if skipped:
        note += f"; {', '.join(f'{t:g}' for t in skipped)} s not reached by this run (skipped)"
    if maps:
        t = 2.0 * case.wall_ball
        plot_seismic_strain(maps[0][1].x_edges * n, maps[0][1].z_edges * n,
                            [(s.time_s, m.max_shear_strain) for s, m in maps], folder.path / "shear_strain.png",
                            wall=(0.0, t * n, case.toe * n, (case.toe + case.wall_length) * n),
                            ground=(case.front_height * n, case.retained_height * n),
                            title=f"maximum shear strain since the start of shaking (Fig. 7), {title}", note=note)
