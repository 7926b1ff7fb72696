"""``wallsim validate drystone --case A``: the five walls at the default settings, the
solver-convergence repeat (dt / 2, twice the iterations), the band of critical
heights over the missing data (both geometries, gamma_m 18-22 kN/m3, alpha 0-8.5 deg for
the limestone walls) and the independence runs (each wall on the other rows of the
back-fit and on the disk-count section, beside the limit equilibrium of the same section)
-> docs/validation/drystone.{md,json} and drystone/ figures.

Each DEM run (a wall, its convergence repeat, a band corner) goes into a run folder named
by its resolved case, ``<root>/drystone/validate-<what>-<key>`` (``dem_run``): the same
command run again after an interruption reads the runs that finished from their
result.json and runs only the others, to the same report. The key is of the settings,
not the code: after a change of the code, remove those folders to run the walls again."""

from __future__ import annotations

import itertools
import json
import math
import shutil
import time
from dataclasses import replace
from pathlib import Path

import reproducibility

from ..runfolder import git_revision, package_versions
from ..store import atomic_write, content_key, to_plain
from .case import ACCURACY_LIMIT_PERCENT, CONVERGENCE_LIMIT_PERCENT, DrystoneCase, GEOMETRIES, reference, solver
from .run import RIGID_NOTE, increment_logger, limit_equilibrium, run_dem, wall_result


def band_corners(case: DrystoneCase) -> list[DrystoneCase]:
    """The corners of the missing-data box: geometry x gamma_m (18, 22) x alpha (0, 8.5)
    for the limestone walls (alpha is found for V5S)."""
    ref = reference()
    g_lo, g_hi = ref["unit_weight_range_kN_m3"]["value"]
    a_lo, a_hi = ref["joint_slope_range_deg"]["value"]
    alphas = (None,) if ref["walls"][case.wall]["joint_slope_deg"]["tag"] == "F" else (a_lo, a_hi)
    return [replace(case, geometry=g, unit_weight_kN_m3=gm, joint_slope_deg=a)
            for g, gm, a in itertools.product(GEOMETRIES, (g_lo, g_hi), alphas)]


def _le_height(case: DrystoneCase) -> tuple[float, bool]:
    """Yield-design critical height [m] (above the crest: the balance extended past it, the
    wall stands with water at its crest) and whether it stands."""
    le = limit_equilibrium(case)["yield-design"]
    return le["critical_height_m"], bool(le["stands_to_crest"])


def dem_run(case: DrystoneCase, what: str, root: Path, *, figures: bool = False, log=None) -> dict:
    """One DEM run (``run_dem``) of the validation as its run folder's result.json holds
    it (``wall_result`` and ``run_folder``; the report reads the same numbers whether the
    run is new or not). The folder, ``<root>/drystone/validate-<what>-<key>`` (key: the
    hash of the resolved case, so a changed setting never reads a stale run), is read
    when it holds a finished run, else the run goes there, a folder without result.json
    (an interrupted run) removed first. ``figures``: the wall's history and mechanism
    figures too, history.png and mechanism.png in the folder."""
    from ..runner import finish, open_recording, open_run_folder, run_once
    folder = run_folder(case, what, root)

    def run(_: None) -> None:
        rf = open_run_folder("drystone", case, root, name=folder.name, seed=None)
        rec = open_recording(None, study="drystone", recording_id=f"drystone-{case.wall}", dim=2, folder=rf)
        wall, res, seconds, cpu = run_dem(case, on_increment=increment_logger(rec))
        rec.close()
        r = wall_result(case, wall, res, seconds, cpu) | {"run_folder": str(rf.path)}
        if figures:
            _wall_figures(case, r, res, rf.path)
        finish(rf, r, main=False, particles=wall.block_count, steps=res.steps, dt_s=case.dt, iterations=case.iterations,
               contact=r["contact"], wall_time_s=seconds, cpu_time_s=cpu, assumptions=r["assumptions"])

    return run_once(folder, run, log=log or (lambda line: None))


def run_folder(case: DrystoneCase, what: str, root: Path) -> Path:
    """Where ``dem_run`` keeps the run ``what`` (wall, convergence, band) of ``case``."""
    return Path(root) / "drystone" / f"validate-{what}-{content_key(case)}"


def _wall_figures(case: DrystoneCase, r: dict, res, folder: Path) -> None:
    """history.png (water height vs crest displacement) and mechanism.png (the blocks at
    failure) of one wall's run, in ``folder``."""
    from .figures import plot_drystone_history, plot_drystone_mechanism

    le = r["limit_equilibrium"]["yield-design"]
    plot_drystone_history(res.water_height_m, res.crest_displacement_m, folder / "history.png",
                          title=f"{case.wall}: water height vs crest displacement\n(rigid-block kinematics: pre-failure displacements are numerical)",
                          measured_m=r["measured"]["height_m"], le_m=le["critical_height_m"],
                          critical_m=r["dem"]["critical_height_m"], notes=r["assumptions"])
    m = res.mechanism
    plot_drystone_mechanism(res.reference_outlines, res.outlines, res.velocities, folder / "mechanism.png",
                            water_height=res.water_height_m[-1],
                            title=f"{case.wall} at failure: {m.mode} at {m.level_m:.3f} m" if m else case.wall,
                            level_m=m.level_m if m else None, pivot=m.pivot if m and m.mode == "toppling" else None,
                            notes=r["assumptions"])


def band(case: DrystoneCase, dem: bool, log=None, root: Path = Path("runs")) -> dict:
    """Critical heights over the band corners: the limit equilibrium at every corner, and
    (``dem``) the DEM at the corners where it is lowest, highest, and highest with the
    default (back-fit) geometry (``dem_run``, under ``root``)."""
    corners = band_corners(case)
    found = [_le_height(c) for c in corners]
    les = [h for h, _ in found]
    rows = [{"geometry": c.geometry, "unit_weight_kN_m3": c.unit_weight_kN_m3,
             "joint_slope_deg": c.section().joint_slope_deg, "limit_equilibrium_height_m": h,
             "limit_equilibrium_stands_to_crest": st} for c, (h, st) in zip(corners, found)]
    h_wall = case.section().height_m
    out = {"corners": rows, "limit_equilibrium_band_m": [min(les), None if max(les) >= h_wall else max(les)],
           "source": "limit equilibrium (None: stands with water at the crest)"}
    if not dem:
        out["band_m"] = out["limit_equilibrium_band_m"]
        return out
    back = [i for i, c in enumerate(corners) if c.geometry == "back-fit"]
    picks = sorted({les.index(min(les)), max(back, key=lambda i: les[i]), les.index(max(les))})
    for i in picks:
        r = dem_run(corners[i], "band", root, log=log)
        d, fx = r["dem"], limit_equilibrium(corners[i])["above-fixed-course"]
        pivot = d["pivot_m"]
        rows[i] |= {"dem_height_m": d["critical_height_m"],
                    "dem_mode": d["mode"], "dem_mechanism_level_m": d["mechanism_level_m"],
                    "dem_pivot_m": pivot,
                    # > 0: the toppling pivot lies inside the outer face (the limit equilibrium's is on it)
                    "dem_pivot_inside_outer_face_m": pivot[0] - corners[i].section().x_outer(pivot[1])
                    if d["mode"] == "toppling" and pivot is not None else None,
                    "dem_stands_to_crest": not d["failed"],
                    "limit_equilibrium_above_fixed_course": fx,
                    "dem_minus_fixed_course_le_m": (d["critical_height_m"] - fx["critical_height_m"])
                    if d["failed"] else None,
                    "increment_m": corners[i].section().height_m * corners[i].increment_fraction,
                    "wall_time_s": r["wall_time_s"], "cpu_time_s": r["cpu_time_s"]}
        if log:
            log(f"  band corner {rows[i]['geometry']}, gamma {rows[i]['unit_weight_kN_m3']:g}, alpha "
                f"{rows[i]['joint_slope_deg']:g}: DEM {rows[i]['dem_height_m']} ({rows[i]['dem_mode']})")
    dem_vals = [rows[i]["dem_height_m"] for i in picks]
    lo = min(v for v in dem_vals if v is not None) if any(v is not None for v in dem_vals) else None
    hi = None if any(v is None for v in dem_vals) else max(dem_vals)
    out |= {"band_m": [lo, hi], "source": "DEM at the corners of lowest, highest and highest back-fit limit equilibrium",
            "hi_stands_to_crest": hi is None,
            "band_note": "band_m = [lowest, highest] DEM critical height over the corners run; an upper value "
                         "null means at least one corner stood with water at its crest (no failure up to h)"}
    return out


def convergence(case: DrystoneCase, base: dict, root: Path = Path("runs"), log=None) -> dict:
    """The same wall with dt / 2 and twice the iterations (``dem_run``, under ``root``)."""
    fine = replace(case, dt=case.dt / 2, iterations=case.iterations * 2)
    r = dem_run(fine, "convergence", root, log=log)
    h0, h1 = base["dem"]["critical_height_m"], r["dem"]["critical_height_m"]
    change = 100 * abs(h1 - h0) / h0 if h0 and h1 else math.nan
    mode1 = r["dem"]["mode"]
    return {"dt_s": fine.dt, "iterations": fine.iterations, "critical_height_m": h1, "mode": mode1,
            "change_percent": change, "mode_same": mode1 == base["dem"]["mode"],
            "holds": bool(change < CONVERGENCE_LIMIT_PERCENT and mode1 == base["dem"]["mode"]),
            "wall_time_s": r["wall_time_s"], "cpu_time_s": r["cpu_time_s"]}


#: masonry unit weights [kN/m3] of the back-fit rows run besides the default's 20: the
#: plausible range of reference 2.3, each with its base width fitted again
BACK_FIT_ROWS = (18.0, 22.0)


def refit_base_width(case: DrystoneCase) -> float:
    """The base width [m] at which the yield-design limit equilibrium of ``case``'s section
    fails at the measured water height (reference 2.3's back-fit, done again at the case's
    unit weight; the crest follows from the outer batter)."""
    from scipy.optimize import brentq

    target = float(reference()["walls"][case.wall]["measured_height_m"]["value"])

    def excess(b: float) -> float:
        return _le_height(replace(case, base_width_m=b))[0] - target
    sec = case.section()
    batter = math.tan(math.radians(sec.batter_outer_deg)) + math.tan(math.radians(sec.batter_inner_deg))
    # a crest of at least a centimetre on a base longer than one block (the case's limits)
    narrowest = max(sec.height_m * batter + 0.01, 1.001 * case.block_length)
    return float(brentq(excess, narrowest, 4.0, xtol=1e-4))


def independence(case: DrystoneCase, base: dict, root: Path = Path("runs"), log=None) -> list[dict]:
    """Whether the DEM follows the section it is given, not the site: the wall on the
    other rows of the back-fit (unit weights ``BACK_FIT_ROWS``, base widths fitted again so
    the limit equilibrium fails at the measured height) and on the disk-count section, each
    DEM beside the limit equilibrium of the same section (``dem_run``, under ``root``);
    ``base`` is the default run (back-fit, 20 kN/m3), the first row."""
    cases = [(replace(case, unit_weight_kN_m3=g, base_width_m=refit_base_width(replace(case, unit_weight_kN_m3=g))),
              "back-fit, refitted") for g in BACK_FIT_ROWS]
    cases.append((replace(case, geometry="disk-count"), "disk-count"))
    rows = [_independence_row(case, "back-fit (the report's)", base)]
    for c, label in cases:
        rows.append(_independence_row(c, label, dem_run(c, "independence", root, log=log)))
        if log:
            log(f"  {label} {c.unit_weight_kN_m3:g} kN/m3, b {rows[-1]['base_width_m']:.3f} m: DEM "
                f"{rows[-1]['dem_height_m']} m, LE {rows[-1]['le_height_m']:.3f} m")
    return rows


def _independence_row(case: DrystoneCase, label: str, r: dict) -> dict:
    d, le = r["dem"], r["limit_equilibrium"]
    above = le["above-fixed-course"]
    return {"section": label, "unit_weight_kN_m3": case.unit_weight_kN_m3, "height_m": r["section"]["height_m"],
            "base_width_m": r["section"]["base_width_m"],
            "crest_width_m": r["section"]["crest_width_m"], "le_height_m": le["yield-design"]["critical_height_m"],
            "le_stands_to_crest": bool(le["yield-design"]["stands_to_crest"]), "le_mode": le["yield-design"]["mode"],
            "le_above_fixed_course_m": above["critical_height_m"], "dem_height_m": d["critical_height_m"],
            "dem_mode": d["mode"], "dem_minus_own_le_m": (d["critical_height_m"] - above["critical_height_m"])
            if d["critical_height_m"] is not None else None,
            "increment_m": r["section"]["height_m"] * r["increment_fraction"],
            "measured_height_m": r["measured"]["height_m"], "error_percent": r["error_percent"],
            "cpu_time_s": r["cpu_time_s"]}


def validate_wall(case: DrystoneCase, fig_dir: Path, *, dem_band: bool, check: bool, log=None,
                  root: Path = Path("runs"), other_sections: bool = True) -> dict:
    """One wall: the default run (with its figures), the convergence repeat, the band, the
    runs on other sections (``independence``); each DEM run in its own run folder under
    ``root`` (``dem_run``)."""
    r = dem_run(case, "wall", root, figures=True, log=log)
    if log:
        log(f"{case.wall}: DEM {r['dem']['critical_height_m']} m {r['dem']['mode']} "
            f"({r['wall_time_s']:.1f} s wall, {r['cpu_time_s']:.1f} s CPU)")
    for name in ("history", "mechanism"):
        shutil.copyfile(run_folder(case, "wall", root) / f"{name}.png", fig_dir / f"{case.wall}_{name}.png")
    r["convergence"] = convergence(case, r, root, log) if check else None
    if log and check:
        log(f"  convergence: {r['convergence']['critical_height_m']} m {r['convergence']['mode']} "
            f"({r['convergence']['change_percent']:.2f} %)")
    r["band"] = band(case, dem_band, log, root)
    r["independence"] = (independence(case, r, root, log) if other_sections and case.geometry == "back-fit"
                         else None)
    return r


def entry(r: dict) -> dict:
    """The per-wall record of drystone.json (the report's keys first, then the rest)."""
    d, le = r["dem"], r["limit_equilibrium"]["yield-design"]
    conv = r["convergence"]
    return {"critical_height_m": d["critical_height_m"], "mode": d["mode"], "mechanism_level_m": d["mechanism_level_m"],
            "measured_height_m": r["measured"]["height_m"], "measured_mode": r["measured"]["mode"],
            "limit_equilibrium_height_m": le["critical_height_m"], "limit_equilibrium_mode": le["mode"],
            "band_m": r["band"]["band_m"], "wall_time_s": r["wall_time_s"],
            "cpu_time_s": r["cpu_time_s"], "error_percent": r["error_percent"],
            # None: no failure up to the crest (result.json holds NaN as null)
            "within_10_percent": bool(abs(r["error_percent"]) <= ACCURACY_LIMIT_PERCENT)
            if r["error_percent"] is not None and math.isfinite(r["error_percent"]) else False,
            "mode_matches": r["mode_matches"], "paper_dem": r["paper_dem"],
            "limit_equilibrium_bed_joints": r["limit_equilibrium"]["bed-joints"],
            "limit_equilibrium_above_fixed_course": r["limit_equilibrium"]["above-fixed-course"],
            "dem_minus_fixed_course_le_m": (d["critical_height_m"] - r["limit_equilibrium"]["above-fixed-course"]
                                            ["critical_height_m"]) if d["critical_height_m"] is not None else None,
            "increment_m": r["section"]["height_m"] * r["increment_fraction"], "section": r["section"],
            "geometry": r["geometry"], "assumptions": r["assumptions"], "blocks": d["blocks"], "steps": d["steps"],
            "convergence": conv, "band": r["band"], "independence": r["independence"]}


def validate_drystone(case: DrystoneCase, *, out_dir: Path, walls: list[str], band: str = "dem",
                      convergence: bool = True, other_sections: bool = True, log=None,
                      root: Path = Path("runs")) -> dict:
    """Every wall in ``walls``; writes drystone.json, drystone.md and drystone/*.png. The
    DEM runs go into run folders under ``root`` (``dem_run``): those that finished before
    are read, not run again."""
    from .report import write_report

    t0, c0 = time.perf_counter(), time.process_time()
    git = git_revision()        # before the run writes its figures (which would read as "+dirty")
    fig_dir = out_dir / "drystone"
    fig_dir.mkdir(parents=True, exist_ok=True)
    results = {}
    for w in walls:
        results[w] = validate_wall(replace(case, wall=w), fig_dir, dem_band=band == "dem", check=convergence,
                                   log=log, root=Path(root), other_sections=other_sections)
    rep = {"case": "A", "study": "drystone", "walls": {w: entry(r) for w, r in results.items()},
           "settings": {"geometry": case.geometry, "dt_s": case.dt, "iterations": case.iterations,
                        "water_direction": case.water_direction, "increment_fraction": case.increment_fraction,
                        "block_length_m": case.block_length, "block_height_m": case.block_height, "collision_slop_m": solver(case).collision_slop,
                        "unit_weight_kN_m3": case.unit_weight_kN_m3},
           "note": RIGID_NOTE, "git": git, "versions": package_versions(),
           "reproducibility": reproducibility.describe(),
           "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
           "wall_time_s": time.perf_counter() - t0, "cpu_time_s": time.process_time() - c0}
    old = out_dir / "drystone.json"
    if old.is_file() and "case_b" in (kept := json.loads(old.read_text())):
        rep["case_b"] = kept["case_b"]          # validate --case B wrote it; this run is case A only
    from .report import back_fit_band
    for e in rep["walls"].values():
        e["band_back_fit_m"] = back_fit_band(e)
    write_report(rep, out_dir)          # adds rep["timing"]
    atomic_write(out_dir / "drystone.json", (json.dumps(to_plain(rep), indent=2) + "\n").encode())
    return rep
