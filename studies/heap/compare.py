"""``wallsim compare heap``: rain, slump, subside; the base stress before and after.

Writes the run folder (config.toml, manifest.json, result.json, base_stress.csv,
subsidence.csv, surface.csv, fig1a_heap.png, fig1b_force_chains.png,
fig1c_base_stress.png, centre_over_peak.png, recording.rrd) and returns the result dict
that ``--json`` prints. While it runs, checkpoints/heap.npz holds the run so far
(``--resume`` continues it bit for bit); it is gone once the result is written.
"""

from __future__ import annotations

import resource
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ..runner import Stopwatch, drop_checkpoint, finish, open_recording, open_run_folder
from ..store import load_npz, npz_bytes
from analytic.constants import G

from .case import HeapCase, bin_centres
from .measures import centre_over_peak
from .run import HeapRun, run_heap

#: the run's checkpoint in the run folder (dropped once the run has its result)
CHECKPOINT = "checkpoints/heap.npz"


def cpu_seconds() -> float:
    """User + system CPU time of this process, all threads [s]."""
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def slope_text(slope_deg, short: bool = False) -> str:
    """The flank slope, or why there is none: too few grains to rise into flanks."""
    if slope_deg is None or slope_deg != slope_deg:
        return "slope n/a" if short else ("slope n/a (no flanks between 0.2 H and 0.8 H to fit: too few "
                                          "spheres for a heap; Fig. 1 needs ~12,000)")
    return f"slope {slope_deg:.1f} deg"


def compare_heap(case: HeapCase, *, root: Path = Path("runs"), rrd: Path | None = None, spawn: bool = False,
                 record: bool = True, progress=None, resume: Path | None = None,
                 checkpoint_every_s: float | None = None) -> tuple[dict, Path]:
    """One heap run: its run folder, recording, figures and the result dict.

    The run is checkpointed to <run folder>/checkpoints/heap.npz (every
    ``checkpoint_every_s`` of wall time, default ``model.CHECKPOINT_EVERY_S``, and every
    10 % of each stage); with ``resume`` (an interrupted run's folder, ``case`` its
    config) the run continues from its checkpoint (from the start when it has none) and
    ends as the uninterrupted run would, bit for bit; its recording (the part after the
    resume) goes to recording-resumed.rrd unless ``rrd`` names a file. Wall and CPU time
    count both parts (up to the checkpoint)."""
    clock, cpu0 = Stopwatch(), cpu_seconds()
    folder = open_run_folder("heap", case, root, resume=resume)
    saved = folder.path / CHECKPOINT
    state = load_npz(saved) if resume is not None and saved.is_file() else None
    default_rrd = "recording-resumed.rrd" if resume is not None else "recording.rrd"
    rrd_path = Path(rrd) if rrd is not None else folder.file(default_rrd)
    recorder = open_recording(rrd_path if record else None, study="heap", dim=3, spawn=spawn, folder=folder,
                              recording_id=f"{folder.path.name}-heap")
    recorder.log_case(_case_markdown(case))

    def on_frame(frame, disp):
        recorder.log_frame(frame, wall_disp_over_H=disp)

    def save(arrays: dict) -> None:
        folder.save_checkpoint(CHECKPOINT, npz_bytes(arrays))

    try:
        with clock("run"):
            run = run_heap(case, on_frame=on_frame, progress=progress, checkpoint=save, resume=state,
                           checkpoint_every_s=checkpoint_every_s)
        norm = case.density * G * (1.0 - run.porosity) * run.shape.H
        for d, s, t, c, p in zip(run.history.disp_over_H, run.history.step, run.history.time, run.history.centre,
                                 run.history.peak):
            recorder.log_metrics(s, t, {"centre_over_peak": c / p, "centre_stress_over_rho_g_1mn_H": c / norm}, d)
    finally:
        recorder.close()
    _write_tables(folder, case, run, norm)
    _write_figures(folder, case, run, norm)
    result = _result(case, run, norm, folder)
    result["wall_time_s"] = clock.total + run.before_resume_s[0]
    result["cpu_time_s"] = cpu_seconds() - cpu0 + run.before_resume_s[1]
    drop_checkpoint(folder.path, CHECKPOINT)                      # finished: nothing to resume
    finish(folder, result, particles=run.spheres, dt=run.dt, contact=result["provenance"]["contact"],
           wall_time_s=result["wall_time_s"], cpu_time_s=result["cpu_time_s"])
    return result, folder.path



def _write_tables(folder, case: HeapCase, run: HeapRun, norm: float) -> None:
    x = bin_centres(case)
    folder.write_csv("base_stress.csv", ["bin", "x_m", "sigma_before_kPa", "sigma_after_kPa",
                                         "sigma_before_over_rho_g_1mn_H", "sigma_after_over_rho_g_1mn_H"],
                     [[k + 1, x[k], run.sigma_before[k] / 1e3, run.sigma_after[k] / 1e3,
                       run.sigma_before[k] / norm, run.sigma_after[k] / norm] for k in range(case.bins)])
    h = run.history
    folder.write_csv("subsidence.csv", ["subsidence_over_H", "time_s", "step", "centre_kPa", "peak_kPa",
                                        "centre_over_peak"],
                     [[d, t, s, c / 1e3, p / 1e3, c / p] for d, t, s, c, p in
                      zip(h.disp_over_H, h.time, h.step, h.centre, h.peak)])
    folder.write_csv("surface.csv", ["x_m", "surface_height_m"], list(zip(run.shape.x, run.shape.top)))


def heap_only(frame, half_length: float, y_band: tuple[float, float]) -> SimpleNamespace:
    """The grains and contacts of a frame above the base (the spill on the catch floor
    left out) within a slab ``y_band`` [m] of the periodic width (a thin slab shows the
    chains; the whole 0.6 m projected is a thicket), with the base panels."""
    pos = np.asarray(frame.positions)

    def inside(p):
        return (p[:, 2] > -0.05) & (np.abs(p[:, 0]) < half_length + 0.1) & (p[:, 1] >= y_band[0]) & (p[:, 1] < y_band[1])

    ca = np.asarray(frame.contact_a)
    kc = inside(ca)
    corners = np.asarray(frame.panel_corners)
    base = np.abs(corners[:, :, 2]).max(axis=1) < 0.5
    return SimpleNamespace(positions=pos[inside(pos)], contact_force=np.asarray(frame.contact_force)[kc],
                           contact_a=ca[kc], contact_b=np.asarray(frame.contact_b)[kc], panel_corners=corners[base])


def _write_figures(folder, case: HeapCase, run: HeapRun, norm: float) -> None:
    """Fig. 1(a) the heap (chains before), 1(b) chains after, 1(c) base stress, and the
    centre / peak ratio along the subsidence."""
    from viz.figures import plot_force_chains, plot_series

    half, x = 0.5 * case.base_length, bin_centres(case)
    band = (0.5 * case.width - 1.5 * case.d_max, 0.5 * case.width + 1.5 * case.d_max)    # ~3 grains thick
    plot_force_chains(heap_only(run.frames["before"], half, band), folder.file("fig1a_heap.png"),
                      title=f"Fig. 1(a): the heap before subsidence (H {run.shape.H:.2f} m, "
                            f"{slope_text(run.shape.slope_deg, short=True)}), force chains in a slab "
                            f"{band[1] - band[0]:.2f} m thick")
    plot_force_chains(heap_only(run.frames["after"], half, band), folder.file("fig1b_force_chains.png"),
                      title=f"Fig. 1(b): force chains after subsidence, Delta/H = {run.disp_over_H:.4f}, "
                            f"slab {band[1] - band[0]:.2f} m thick")
    plot_series(x, {"before subsidence": run.sigma_before / norm,
                    f"after, Delta/H = {run.disp_over_H:.4f}": run.sigma_after / norm},
                folder.file("fig1c_base_stress.png"), xlabel="x [m] (base centre at 0)",
                ylabel="sigma_v / (rho g (1 - n) H)",
                title=f"Fig. 1(c): base stress, {run.spheres} spheres, seed {case.seed}")
    h = run.history
    plot_series(np.array(h.disp_over_H), {"centre / peak": np.array(h.centre) / np.array(h.peak)},
                folder.file("centre_over_peak.png"), xlabel="Delta / H at the centre",
                ylabel="centre stress / peak stress", title="The dip forming as the base subsides")


def _result(case: HeapCase, run: HeapRun, norm: float, folder) -> dict:
    c0, p0, r0 = centre_over_peak(run.sigma_before)
    c1, p1, r1 = centre_over_peak(run.sigma_after)
    return {
        "case": "heap", "particles": run.spheres, "bodies": run.bodies, "seed": case.seed,   # as rained
        "heap_spheres": run.shape.spheres, "heap_height_m": run.shape.H, "slope_deg": run.shape.slope_deg,
        "porosity": run.porosity, "subsidence_over_H": run.disp_over_H,
        "centre_over_peak_before": r0, "centre_over_peak_after": r1,
        "centre_stress_over_rho_g_1mn_H": {"before": c0 / norm, "after": c1 / norm},
        "peak_stress_over_rho_g_1mn_H": {"before": p0 / norm, "after": p1 / norm},
        "base_stress_over_rho_g_1mn_H": {"x_m": bin_centres(case).tolist(),
                                         "before": (run.sigma_before / norm).tolist(),
                                         "after": (run.sigma_after / norm).tolist()},
        "rho_g_1mn_H_kPa": norm / 1e3,
        "base_load_over_heap_weight": run.base_force_before_N / run.weight_N,
        "stages": run.stages,
        "provenance": {"particles": run.spheres, "seed": case.seed, "dt_s": run.dt,
                       "contact": {"kn_N_per_m": case.kn, "ks_N_per_m": case.ks, "mu": case.particle_friction,
                                   "damping_ratio": case.damping_ratio, "local_damping": case.local_damping,
                                   "base_mu": case.base_friction},
                       "assumptions": ASSUMPTIONS},
        "run_folder": str(folder.path),
    }


#: what the paper leaves out and this study assumes (studies/heap/case.py docstring)
ASSUMPTIONS = ["grain sizes 2.3-3.7 cm read as radii (diameters 4.6-7.36 cm, the wall study's)",
               "particles = spheres incl. clump members (12,000; 15,000 if the paper counted bodies)",
               "periodic along the 0.6 m width (an infinitely long prism)",
               "contact law of the wall study: kn 8.3 MN/m, ks 3.32 MN/m, density 2650 kg/m^3",
               "viscous normal damping 0.2; PFC local damping 0.7 except while the fill falls and flows",
               "the flow lasts slump_time (2.5 s) before the heap is arrested",
               "base friction 0.65; subsidence speed 0.02 m/s at the centre"]


def _case_markdown(case: HeapCase) -> str:
    return (f"# Nadukuru & Michalowski (2012) Fig. 1: heap over a subsiding base\n\n"
            f"* {case.particles} spheres ({case.bodies} bodies, {case.clump_fraction:.0%} clumps), "
            f"diameters {case.d_min * 100:.2f}-{case.d_max * 100:.2f} cm, friction {case.particle_friction}\n"
            f"* base {case.base_length} m x {case.width} m (periodic), {case.bins} bins, "
            f"centre subsidence Delta/H = {case.subsidence_over_H}\n"
            + "".join(f"* assumption: {a}\n" for a in ASSUMPTIONS))
