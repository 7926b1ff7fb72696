"""``wallsim compare seismic``: one frequency, static stage (cached) then shaking; the
result in prototype units (reference section 1: lengths and times x N, stresses x 1,
force per width x N, moment per width x N^2), tables, figures and the recording."""

from __future__ import annotations

import math
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ..runner import Stopwatch, finish, open_run_folder
from .case import SeismicCase
from .measures import mononobe_okabe_overlay, rotation_fit, settlement, unit_weight
from .run import Prepared, Shaken, prepare, shake


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


def series_table(case: SeismicCase, x0, shaken: Shaken) -> dict[str, np.ndarray]:
    """Time series in prototype units: time, base displacement, wall top displacement
    relative to the base (toward the excavation), thrusts, largest moment."""
    n = case.scale_N
    return {"time_s": shaken.time * n, "base_displacement_m": shaken.base * n,
            "top_displacement_m": np.array([-(r.x[-1] - x0[-1] - b) * n for r, b in zip(shaken.readings, shaken.base)]),
            "thrust_front_kN_per_m": np.array([r.thrust_front * n / 1e3 for r in shaken.readings]),
            "thrust_back_kN_per_m": np.array([r.thrust_back * n / 1e3 for r in shaken.readings]),
            "max_moment_kN_m_per_m": np.array([np.max(np.abs(r.moment)) * n * n / 1e3 for r in shaken.readings])}


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
    x0 = _positions(prepared.main)
    x1 = _positions(shaken.final)
    dist, s = settlement(x0, x1, prepared.model.radii, case, soil)
    return {"distance_m": dist * case.scale_N, "settlement_m": s * case.scale_N}


def _positions(arrays: dict) -> np.ndarray:
    out = np.empty_like(arrays["spheres.x"])
    out[arrays["original_index"]] = arrays["spheres.x"]
    return out


def compare_seismic(case: SeismicCase, *, root: Path, fraction: float = 1.0, log=lambda s: None,
                    record: bool = False, rrd=None, progress=None) -> tuple[dict, Path]:
    """One frequency: prepare (cached under root/seismic/cache) and shake; writes the run
    folder (and recording.rrd with ``record``)."""
    clock = Stopwatch()
    folder = open_run_folder("seismic", case, root)
    path = (Path(rrd) if isinstance(rrd, str) else folder.path / "recording.rrd") if record else None
    with clock("prepare"):
        prepared = prepare(case, Path(root) / "seismic" / "cache", log=log)
    x0 = np.array(prepared.info["x_wall_before_excavation"])
    rows = prepared.model.wall_row
    x0_rows = np.bincount(rows, weights=x0[:, 0]) / np.bincount(rows)
    with clock("shake"), _recording(case, path, folder, x0_rows, progress) as on_sample:
        shaken = shake(case, prepared, fraction=fraction, on_sample=on_sample)
    porosity = float(prepared.info["porosity"])
    result = _result(case, prepared, shaken, x0_rows, porosity, fraction)
    series = series_table(case, x0_rows, shaken)
    _write_tables(folder, case, prepared, shaken, series)
    _figures(folder, case, shaken, series, porosity, settlement_table(case, prepared, shaken))
    result |= {"wall_time_s": clock.total, "stage_seconds": clock.seconds, "run_folder": str(folder.path)}
    finish(folder, result, particles=result["particles"], seed=case.seed, dt_s=result["dt_s"],
           steps=shaken.steps, wall_time_s=clock.total)
    return result, folder.path


@contextmanager
def _recording(case: SeismicCase, path, folder, x0_rows, progress):
    """A sample callback: the recording (prototype seconds on the sim_time timeline:
    thrusts, wall top displacement, largest moment every sample; the grains and wall
    every 10th) and the progress bar."""
    from dem3d import frame as take_frame

    from ..runner import open_recording
    rec = open_recording(path, study="seismic", recording_id=folder.path.name, dim=3)
    n = case.scale_N
    count = [0]

    def on_sample(sim, reading, t_model, base, done, total):
        t = t_model * n
        metrics = {"thrust_back_kN_per_m": reading.thrust_back * n / 1e3,
                   "thrust_front_kN_per_m": reading.thrust_front * n / 1e3,
                   "wall_top_displacement_m": float(-(reading.x[-1] - x0_rows[-1] - base) * n),
                   "max_moment_kN_m_per_m": float(np.max(np.abs(reading.moment))) * n * n / 1e3}
        if count[0] % 10 == 0:
            rec.log_frame(take_frame(sim)._replace(time=t), metrics=metrics)
        else:
            rec.log_metrics(sim.step_count, t, metrics)
        count[0] += 1
        if progress is not None:
            progress(done, total)
    try:
        yield on_sample
    finally:
        rec.close()


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
            "mononobe_okabe": {k: {"thrust_kN_per_m": p.thrust / 1e3, "K": p.K} for k, p in mo.items()},
            "units": "prototype (model x " + ", ".join(f"{k} {v:g}" for k, v in
                                                      prototype_factors(case.scale_N).items()) + ")"}


def _write_tables(folder, case, prepared, shaken, series) -> None:
    for name, table in (("series.csv", series), ("pressure_profiles.csv", profiles_table(case, shaken)),
                        ("settlement.csv", settlement_table(case, prepared, shaken))):
        cols = list(table)
        folder.write_csv(name, cols, zip(*(np.asarray(table[c]) for c in cols)))


def _figures(folder, case, shaken, series, porosity, settled) -> None:
    from viz.figures import plot_seismic
    plot_seismic(case.scale_N, shaken.readings, series, profiles_table(case, shaken),
                 mononobe_okabe_overlay(case, porosity), folder.path / "seismic.png", settlement=settled,
                 title=f"{case.frequency:g} Hz, 0.1 g (prototype), grain scale {case.scale:g}")
