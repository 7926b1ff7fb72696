"""``wallsim compare wall WALL.toml``: the designer's wall in DEM beside the theories,
then the design checks of the same file rerun with the DEM's thrust.

Steps: the backfill rained and settled behind the wall (``studies.granular``, cached by
content), the surcharge put on its top layer (``surcharge``), the wall moved away from
the fill (the case's movement), the load read per segment. Beside it Rankine, Coulomb
and EN 1997-1 Annex C on the same back with the file's phi and surcharge and the DEM's
own unit weight. Then ``wallsim design``'s format on the file twice: classical, and with
the soil and surcharge thrust replaced by the DEM's (its K and resultant height applied
to the file's unit weight and surcharge: ``analytic.design.earth.with_measured``).

Writes the run folder: config.toml, wall.toml (the file as read), manifest.json,
result.json, history.csv, segments.csv, theory.csv, design.csv, fig_pressure.png,
fig_K.png, fig_displacements.png, fig_force_chains.png, recording.rrd.
"""

from __future__ import annotations

import dataclasses
import math
import shutil
from pathlib import Path

import numpy as np

from analytic.constants import G

from ..granular.movement import run_modes
from ..granular.specimen import load_or_prepare
from ..granular.wall import MODE_TITLES
from ..runner import Stopwatch, drop_checkpoint, finish, open_recording, open_run_folder
from .case import WallStudyCase
from .surcharge import load_or_surcharge

#: the theories set beside the DEM (``analytic.design.earth.METHODS``) and their labels
THEORIES = (("rankine-virtual-back", "Rankine"), ("coulomb", "Coulomb"), ("ec7-annex-c", "EN 1997-1 Annex C"))


def compare_wall(case: WallStudyCase, *, root: Path = Path("runs"), rrd: Path | None = None, spawn: bool = False,
                 every: int = 5, record: bool = True, progress=None,
                 resume: Path | None = None) -> tuple[dict, Path]:
    """Run (or, with ``resume`` = an interrupted run's folder, continue) the comparison."""
    from viz import paths as P
    from viz.recorder import wall_layout

    clock = Stopwatch()
    folder = open_run_folder("wall", case, root, resume=resume)
    if resume is None:
        shutil.copyfile(case.design_file, folder.file("wall.toml"))
    with clock("specimen"):
        spec, cached = load_or_prepare(case, Path(root) / "wall" / "specimens", progress)
        if case.surcharge > 0:
            spec, _ = load_or_surcharge(case, spec, case.surcharge * 1e3, Path(root) / "wall" / "specimens")
    rrd_path = Path(rrd) if rrd is not None else folder.file("recording-resumed.rrd" if resume else "recording.rrd")
    recorder = open_recording(rrd_path if record else None, study="wall", dim=3, spawn=spawn, folder=folder,
                              recording_id=f"{folder.path.name}-{case.movement.mode}",
                              layout=wall_layout(3, "backfill, wall segments and force chains",
                                                 (P.METRIC_PANEL_STRESS,)))
    gamma = case.specimen.density * (1.0 - spec.porosity) * G / 1e3        # kN/m3, the DEM's own
    recorder.log_case(_case_markdown(case, spec, gamma))
    with clock("movement"):
        hist, frames = _move_and_record(case, spec, recorder, every, progress, folder)
        recorder.close()
    dem = dem_load(case, spec, hist, gamma)
    passive = case.movement.direction == "passive"
    theories = passive_theory_rows(case, gamma) if passive else theory_rows(case, gamma)
    design = None if passive else design_rerun(case, dem)
    _write_tables(folder, case, hist, dem, theories, design)
    _write_figures(folder, case, hist, frames, dem, theories)
    result = _result(case, spec, cached, hist, dem, theories, design, folder, gamma)
    result["wall_time_s"] = clock.total
    result["timings"] = {k + "_s": v for k, v in clock.seconds.items()}
    drop_checkpoint(folder.path, "checkpoints/movement.npz")
    finish(folder, result, particles=spec.n_spheres, dt=spec.dt, contact=result["provenance"]["contact"],
           wall_time_s=result["wall_time_s"])
    return result, folder.path


def _move_and_record(case: WallStudyCase, spec, recorder, every: int, progress, folder) -> tuple[dict, dict]:
    """Move the wall (``run_modes``, resumable from the folder's checkpoint), logging each
    load sample and every ``every`` x 500 steps the scene; the history and the first and
    last frames logged."""
    frames = {}
    n = case.wall.segments
    centres = (np.arange(n) + 0.5) / n

    def on_frame(frame, sample):
        frames.setdefault("first", frame)
        frames["last"] = frame
        recorder.log_frame(frame, wall_disp_over_H=sample.wall_disp_over_H,
                           profile=(1.0 - centres, sample.segment_stress / 1e3))

    def on_sample(sample):
        recorder.log_metrics(sample.step, sample.time,
                             {"K": sample.K, "resultant_height_over_H": sample.resultant_height_over_H,
                              "thrust_kN": sample.thrust_kN, "panel_stress_kPa": sample.segment_stress / 1e3},
                             sample.wall_disp_over_H)

    frame_every = max(1, every) * case.movement.record_every * 10
    hist = run_modes(case, spec, on_sample=on_sample, on_frame=on_frame, frame_every=frame_every,
                     progress=progress, checkpoint_path=folder.file("checkpoints/movement.npz"),
                     on_checkpoint=folder.checkpointed)
    if frames:
        f0, f1 = frames["first"], frames["last"]
        recorder.log_displacement(f0.positions, f1.positions, step=f1.step, time=f1.time,
                                  wall_disp_over_H=hist["wall_disp_over_H"][-1])
    return hist, frames


def dem_load(case: WallStudyCase, spec, hist: dict, gamma: float) -> dict:
    """The DEM's active load per metre of wall, averaged over the last 10 % of the
    movement: thrust and shear [kN/m], K = thrust / (0.5 gamma H^2 + q H) with the DEM's
    own gamma [kN/m3] (eq. 6 of Nadukuru & Michalowski when q = 0), resultant height,
    mobilised wall friction, segment stresses [kPa, compression +]."""
    H, q, w = case.wall.height, case.surcharge, spec.width
    eq6 = 0.5 * gamma * H * H
    K = hist["K_active"] * eq6 / (eq6 + q * H)     # K_active is eq. 6's; the same when q = 0
    thrust = hist["thrust_kN_active"] / w
    shear = hist["shear_kN_active"] / w
    return {"K": K, "thrust_kN_per_m": thrust, "shear_kN_per_m": shear,
            "resultant_height_over_H": hist["resultant_height_over_H_active"],
            "wall_friction_mobilised_deg": math.degrees(math.atan2(shear, thrust)),
            "segment_sigma_kPa": (hist["segment_stress_active"] / 1e3).tolist(),
            "K_at_rest": spec.K_at_rest, "resultant_height_over_H_at_rest": spec.resultant_height_over_H_at_rest,
            "porosity": spec.porosity, "wall_disp_over_H_steady": hist["wall_disp_over_H_steady"]}


def theory_rows(case: WallStudyCase, gamma: float) -> list[dict]:
    """Rankine, Coulomb and EN 1997-1 Annex C on the DEM's vertical back (height H,
    wall friction delta of the file; Rankine's thrust parallel to the surface), with the
    file's phi, slope and surcharge and the DEM's
    unit weight gamma [kN/m3]: thrust, K = thrust / (0.5 gamma H^2 + q H), resultant
    height / H, the horizontal stress at each segment centre [kPa]."""
    from analytic.design import Backfill
    from analytic.design.earth import design_thrust
    from analytic.design.walls import WallBack
    from analytic.errors import InvalidParameter

    fill = case.design.backfill
    H, q = case.wall.height, case.surcharge
    _, delta = case.back
    soil = Backfill(gamma, fill.phi, beta=fill.beta)
    back = WallBack(0.0, 0.0, H, virtual=True)
    n = case.wall.segments
    depth = H * (1.0 - (np.arange(n) + 0.5) / n)
    rows = []
    for method, label in THEORIES:
        try:
            t = design_thrust(soil, back, method, q=q, delta=delta)
        except InvalidParameter as err:          # e.g. a wall friction above phi for Coulomb
            rows.append({"name": label, "method": method, "thrust_kN_per_m": None, "K": None,
                         "resultant_height_over_H": None, "delta_deg": delta, "segment_sigma_kPa": None,
                         "notes": f"not applicable: {err}"})
            continue
        Ph = t.Ph
        height = math.fsum(p.Ph * p.y for p in t.parts) / Ph
        # linear soil part and uniform surcharge part (both theories' distributions)
        sigma = t.Kh * (gamma * depth + q * _surcharge_factor(t, q, H, gamma))
        rows.append({"name": label, "method": method, "thrust_kN_per_m": Ph, "K": Ph / (0.5 * gamma * H * H + q * H),
                     "resultant_height_over_H": height / H, "delta_deg": fill.beta if method.startswith("rankine") else delta,
                     "segment_sigma_kPa": sigma.tolist(), "notes": t.notes})
    return rows


#: the passive theories beside a movement into the fill (``analytic``'s profiles)
PASSIVE_THEORIES = (("rankine", "Rankine (passive)"), ("coulomb", "Coulomb (passive)"),
                    ("log-spiral", "log-spiral (Terzaghi)"))


def passive_theory_rows(case: WallStudyCase, gamma: float) -> list[dict]:
    """Rankine's and Coulomb's passive pressures and Terzaghi's log-spiral on the DEM's
    back (height H, delta of the file), the file's phi, slope and surcharge and the
    DEM's gamma [kN/m3]; the same fields as ``theory_rows``. The log-spiral needs a level
    fill: with a slope it is left out, and the row says so."""
    from analytic import Soil, Wall, coulomb, rankine
    from analytic.errors import InvalidParameter
    from analytic.logspiral import log_spiral

    fill = case.design.backfill
    H, q = case.wall.height, case.surcharge
    _, delta = case.back
    soil = Soil(fill.phi, gamma * 1e3)
    n = case.wall.segments
    depth = H * (1.0 - (np.arange(n) + 0.5) / n)
    rows = []
    for method, label in PASSIVE_THEORIES:
        wall = Wall(H, delta_deg=0.0 if method == "rankine" else delta, beta_deg=fill.beta, surcharge=q * 1e3)
        try:
            prof = {"rankine": lambda: rankine(soil, wall, passive=True),
                    "coulomb": lambda: coulomb(soil, wall, passive=True),
                    "log-spiral": lambda: log_spiral(soil, wall)}[method]()
        except InvalidParameter as err:
            rows.append({"name": label, "method": method, "thrust_kN_per_m": None, "K": None,
                         "resultant_height_over_H": None, "delta_deg": wall.delta_deg, "segment_sigma_kPa": None,
                         "notes": f"not applicable: {err}"})
            continue
        Ph = prof.thrust_h / 1e3
        rows.append({"name": label, "method": method, "thrust_kN_per_m": Ph, "K": Ph / (0.5 * gamma * H * H + q * H),
                     "resultant_height_over_H": prof.height / H, "delta_deg": wall.delta_deg,
                     "segment_sigma_kPa": (np.interp(depth, prof.z, prof.sigma_h) / 1e3).tolist(),
                     "notes": prof.notes or prof.source})
    return rows


def _surcharge_factor(thrust, q: float, H: float, gamma: float) -> float:
    """The surcharge part's coefficient over the soil part's (1 for a level fill: both
    are K; Annex C's K_q differs from K_gamma)."""
    if q <= 0:
        return 0.0
    parts = {p.kind: p for p in thrust.parts}
    soil, sur = parts["soil"].Ph / (0.5 * gamma * H * H), parts["surcharge"].Ph / (q * H)
    return sur / soil


def design_rerun(case: WallStudyCase, dem: dict) -> dict:
    """The file's design checks in the case's format, classical and with the DEM's thrust
    (its K and resultant height on the file's unit weight and surcharge, its mobilised
    wall friction): utilisation of each check side by side, and the overturning moment
    of the thrust about the toe both ways."""
    from analytic.design import MeasuredThrust, load_factors, verify
    from analytic.design.actions import thrust_for

    design = case.design
    factors = load_factors()
    unit = {k: 1.0 for k in factors.format("DA1")[0].materials}
    classical_thrust = thrust_for(design, unit)
    back = classical_thrust.back
    H, q, gamma = back.height, case.surcharge, design.backfill.gamma
    Ph = dem["K"] * (0.5 * gamma * H * H + q * H)
    Pv = Ph * dem["shear_kN_per_m"] / dem["thrust_kN_per_m"] if dem["thrust_kN_per_m"] > 0 else 0.0
    measured = MeasuredThrust(Ph, Pv, dem["resultant_height_over_H"] * H,
                              source=f"wallsim DEM, {case.movement.mode} to Delta/H {case.movement.wall_disp_over_H:g}")
    informed = dataclasses.replace(design, measured_thrust=measured)
    fmt = case.design_format
    classical, dem_result = verify(design, factors, fmt), verify(informed, factors, fmt)
    checks = {}
    for name, (combo, c) in classical.worst.items():
        d_combo, d = dem_result.worst[name]
        checks[name] = {"classical": {"E_d": c.E_d, "R_d": c.R_d, "utilisation": c.utilisation, "combination": combo},
                        "dem": {"E_d": d.E_d, "R_d": d.R_d, "utilisation": d.utilisation, "combination": d_combo}}
    m_classical = _thrust_moment(classical_thrust)
    m_dem = _thrust_moment(thrust_for(informed, unit))
    return {"format": fmt, "checks": checks,
            "classical_governing": _governing(classical), "dem_governing": _governing(dem_result),
            "thrust": {"classical": _thrust_json(classical_thrust), "dem": measured_json(measured, gamma, q, H)},
            "thrust_overturning_moment_kNm_per_m": {"classical": m_classical, "dem": m_dem,
                                                     "change": m_dem / m_classical - 1.0 if m_classical else None},
            "convention": "the DEM's K and resultant height applied to the file's unit weight and surcharge, "
                          "characteristic; each combination scales it by its factor on the classical thrust "
                          "(design over characteristic, so the margin on phi stays), soil and surcharge shares as "
                          "the classical ones, moved together to the DEM's height"}


def _thrust_moment(thrust) -> float:
    """Overturning moment about the toe of the thrust's horizontal soil and surcharge parts
    [kNm/m], characteristic (Ph times the height above the base underside)."""
    return math.fsum(p.Ph * p.y for p in thrust.parts if p.kind in ("soil", "surcharge"))


def _thrust_json(t) -> dict:
    Ph = math.fsum(p.Ph for p in t.parts if p.kind in ("soil", "surcharge"))
    Pv = math.fsum(p.Pv for p in t.parts if p.kind in ("soil", "surcharge"))
    y = math.fsum(p.Ph * p.y for p in t.parts if p.kind in ("soil", "surcharge")) / Ph if Ph else float("nan")
    return {"Ph_kN_per_m": Ph, "Pv_kN_per_m": Pv, "height_m": y - t.back.y0, "back_height_m": t.back.height}


def measured_json(m, gamma: float, q: float, H: float) -> dict:
    return {"Ph_kN_per_m": m.Ph, "Pv_kN_per_m": m.Pv, "height_m": m.height, "back_height_m": H,
            "unit_weight_kN_m3": gamma, "surcharge_kPa": q, "source": m.source}


def _governing(result) -> dict:
    name, combo, u = result.governing
    return {"check": name, "combination": combo, "utilisation": u, "passes": u <= 1.0}


def _write_tables(folder, case: WallStudyCase, hist: dict, dem: dict, theories: list, design: dict | None) -> None:
    theories = [r for r in theories if r["K"] is not None]        # a theory that does not apply has no row
    n = case.wall.segments
    seg_cols = [f"segment{k + 1}_sigma_kPa" for k in range(n)]
    folder.write_csv("history.csv", ["wall_disp_over_H", "time_s", "step", "K_eq6", "resultant_height_over_H",
                                     "thrust_kN", "shear_kN"] + seg_cols,
                     [[d, t, s, k, c, th, sh, *(seg / 1e3)] for d, t, s, k, c, th, sh, seg in
                      zip(hist["wall_disp_over_H"], hist["time"], hist["step"], hist["K"],
                          hist["resultant_height_over_H"], hist["thrust_kN"], hist["shear_kN"],
                          hist["segment_stress"])])
    H = case.wall.height
    folder.write_csv("segments.csv", ["segment", "centre_depth_m", "sigma_dem_kPa"] +
                     [f"sigma_{r['method']}_kPa" for r in theories],
                     [[k + 1, H * (1 - (k + 0.5) / n), dem["segment_sigma_kPa"][k]] +
                      [r["segment_sigma_kPa"][k] for r in theories] for k in range(n)])
    folder.write_csv("theory.csv", ["source", "thrust_kN_per_m", "K", "resultant_height_over_H"],
                     [["dem", dem["thrust_kN_per_m"], dem["K"], dem["resultant_height_over_H"]]] +
                     [[r["method"], r["thrust_kN_per_m"], r["K"], r["resultant_height_over_H"]] for r in theories])
    if design is None:
        return                     # a passive movement: no design check takes its load
    folder.write_csv("design.csv", ["check", "E_d_classical", "R_d_classical", "utilisation_classical",
                                    "E_d_dem", "R_d_dem", "utilisation_dem"],
                     [[name, c["classical"]["E_d"], c["classical"]["R_d"], c["classical"]["utilisation"],
                       c["dem"]["E_d"], c["dem"]["R_d"], c["dem"]["utilisation"]]
                      for name, c in design["checks"].items()])


def _write_figures(folder, case: WallStudyCase, hist: dict, frames: dict, dem: dict, theories: list) -> None:
    from viz.figures import plot_displacement_field, plot_force_chains

    from .figures import plot_K_history, plot_pressure

    mode = MODE_TITLES[case.movement.mode] + (", passive" if case.movement.direction == "passive" else "")
    theories = [r for r in theories if r["K"] is not None]
    plot_pressure(case.wall.height, dem["segment_sigma_kPa"], theories, folder.file("fig_pressure.png"),
                  title=f"Pressure on the wall at Delta/H = {case.movement.wall_disp_over_H:g} ({mode})")
    to_total = dem["K"] / hist["K_active"] if hist["K_active"] else 1.0      # eq. 6's K -> the total thrust's
    plot_K_history(hist["wall_disp_over_H"], hist["K"] * to_total, theories, dem["K_at_rest"],
                   folder.file("fig_K.png"), title=f"K against wall movement ({mode})")
    if frames:
        end = hist["wall_disp_over_H"][-1]
        plot_displacement_field(frames["first"].positions, frames["last"].positions,
                                folder.file("fig_displacements.png"),
                                title=f"displacements x15 at Delta/H = {end:.4f} ({mode})")
        plot_force_chains(frames["last"], folder.file("fig_force_chains.png"),
                          title=f"force chains at Delta/H = {end:.4f} ({mode})")


def _result(case: WallStudyCase, spec, cached: bool, hist: dict, dem: dict, theories: list, design: dict | None,
            folder, gamma: float) -> dict:
    rec, fill = case.specimen, case.design.backfill
    back, delta = case.back
    return {
        "case": "wall", "design_file": str(case.design_file), "wall_type": case.design.wall.kind,
        "mode": case.movement.mode, "direction": case.movement.direction,
        "wall_disp_over_H": case.movement.wall_disp_over_H,
        "particles": spec.n_spheres, "bodies": spec.n_bodies, "seed": case.seed, "specimen_cached": cached,
        "wall": {"height_m": case.wall.height, "back": "virtual (through the heel)" if back.virtual else "real",
                 "delta_deg": delta, "friction": case.wall.friction, "backfill_length_m": case.wall.backfill_length,
                 "segments": case.wall.segments, "surcharge_kPa": case.surcharge},
        "backfill": {"phi_requested_deg": fill.phi, "phi_card": case.phi_match.as_dict(),
                     "unit_weight_requested_kN_m3": fill.gamma, "unit_weight_dem_kN_m3": gamma,
                     "porosity": spec.porosity, "grain_density_kg_m3": rec.density},
        "dem": dem, "theory": theories, "design": design,
        "assumptions": assumptions(case),
        "provenance": {"particles": spec.n_spheres, "seed": case.seed, "dt_s": spec.dt,
                       "grain_scale": spec.grain_scale, "width_m": spec.width,
                       "contact": {"kn_N_per_m": rec.kn, "ks_N_per_m": rec.ks, "mu": rec.particle_friction,
                                   "mu_roll": rec.rolling_friction, "damping_ratio": rec.damping_ratio,
                                   "wall_mu": case.wall.friction, "floor_mu": rec.floor_friction},
                       "specimen_steps": spec.steps, "movement_steps": int(hist["step"][-1] - hist["step"][0])},
        "run_folder": str(folder.path),
    }


def assumptions(case: WallStudyCase) -> list[str]:
    """What the DEM assumes that the file does not say (every output carries it)."""
    rec, design = case.specimen, case.design
    unused = [f"the file's {name} is not in the DEM (it enters the design checks only)"
              for name, given in (("[seismic] table", design.seismic.given), ("water in front", design.water.front > 0))
              if given]
    return unused + [
        f"backfill: Nadukuru & Michalowski's sphere/clump recipe (kn {rec.kn:g} N/m, ks {rec.ks:g} N/m), grain "
        f"friction {rec.particle_friction:g} and rolling resistance {rec.rolling_friction:g} from the phi card "
        "(triaxial peak phi), grains scaled to fill the box with the particle count",
        f"grain density {rec.density:g} kg/m3 for the file's unit weight at porosity {rec.target_porosity:g}; the "
        "DEM's own unit weight (achieved porosity) is reported and used for its K",
        f"floor friction {rec.floor_friction:g} (fitted in the Nadukuru study), periodic slab along the wall, "
        f"backfill {case.wall.backfill_length:g} m long",
        "the wall is rigid and moves as the case's movement says; the design's wall does not deflect in the DEM",
        "surcharge: a constant load on the highest grain of each ~1.5 grain-wide cell of the surface"
        if case.surcharge > 0 else "no surcharge",
    ]


def _case_markdown(case: WallStudyCase, spec, gamma: float) -> str:
    fill = case.design.backfill
    return (f"# {case.design.wall.kind} wall of {case.design_file}: {MODE_TITLES[case.movement.mode]}\n\n"
            f"* back height {case.wall.height:g} m, wall friction {case.wall.friction:g}, surcharge "
            f"{case.surcharge:g} kPa\n* phi {fill.phi:g} deg -> grain friction {case.specimen.particle_friction:g}, "
            f"rolling {case.specimen.rolling_friction:g}\n* {spec.n_spheres} spheres, porosity {spec.porosity:.3f}, "
            f"unit weight {gamma:.2f} kN/m3 (file {fill.gamma:g})\n")
