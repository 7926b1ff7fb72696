"""``wallsim validate seismic``: the paper's frequencies (1, 3, 4, 5, 6 Hz prototype) one
after the other at one resolution, then docs/validation/seismic.{md,json} in the issue's
format: per frequency the wall's residual displacement, rotation and pivot, moments over
static, the passive K at 1.5 m below the dredge line, settlement at the wall and beyond
8 m, wall time; each of the paper's trends (reference section 7) stated as held, not held
or not run (a trend over frequencies needs all of them). Frequencies not run are listed
as not run, never filled in.

Each frequency runs in a run folder named by its resolved case,
``<root>/seismic/validate-<f>Hz-<key>`` (``frequency_run``): the same command run again
after an interruption reads the frequencies that finished, resumes the one that was
interrupted from its checkpoint, and runs the others, to the same report. The key is of
the settings, not the code: after a change of the code, remove those folders to run the
frequencies again.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import shutil
from pathlib import Path

import numpy as np

import reproducibility

from ..runfolder import git_revision, package_versions
from ..runner import finished_result, has_config, named_run, reusing_line, run_once
from ..store import content_key
from .case import PAPER_FREQUENCIES, SeismicCase

#: per-frequency keys of seismic.json (the issue's list)
KEYS = ("top_displacement_m", "rotation_deg", "pivot_height_over_wall_length", "residual_moment_over_static",
        "max_moment_over_static", "passive_K_max_at_1_5m", "settlement_at_wall_m", "settlement_at_8m_m",
        "wall_time_s")

#: how the paper's words are read (reference.json "targets", each with its note): the
#: residual pivot "near the base", the two faces' thrusts "equal and opposite", "almost no
#: settlement beyond 8 m", "significantly higher" / "far more", and a static failure
#: (trends then not assessed) [A]
_REFERENCE = json.loads(Path(__file__).with_name("reference.json").read_text())
_TARGETS = _REFERENCE["targets"]
PIVOT_NEAR_BASE = float(_TARGETS["pivot_near_base_over_wall_length"])
THRUST_BALANCE = float(_TARGETS["thrust_balance_rel_tol"])
FAR_SETTLEMENT = float(_TARGETS["far_settlement_over_wall_settlement"])
STATIC_FAILURE = float(_TARGETS["static_failure_top_over_wall_length"])
SIGNIFICANT = float(_TARGETS["significant_ratio"])


def validate_seismic(case: SeismicCase, *, frequencies=PAPER_FREQUENCIES, out_dir: Path = Path("docs/validation"),
                     root: Path = Path("runs"), rolling_resistances=(), progress=None, log=print) -> dict:
    """Run ``frequencies`` of ``case`` (each reused when finished, resumed when
    interrupted) and write the report. The paper's other frequencies go in too when their
    run folders under ``root`` hold finished runs of the same case (nothing else is run),
    so validating one frequency does not drop the others. ``rolling_resistances``: the
    same frequencies again at each of these mu_r (the assumed value moved across its
    plausible range), set beside the case's own in the report."""
    folders = {}
    for f in frequencies:
        log(f"seismic: {f:g} Hz")
        folders[float(f)] = frequency_run(dataclasses.replace(case, frequency=float(f)), root=root,
                                          record=f == 5.0, progress=progress, log=log)
    for f in PAPER_FREQUENCIES:
        folder = Path(root) / "seismic" / run_name(dataclasses.replace(case, frequency=float(f)))
        if float(f) not in folders and finished_result(folder) is not None:
            log(reusing_line(folder))
            folders[float(f)] = folder
    varied = {}
    for mu_r in rolling_resistances:
        for f in frequencies:
            log(f"seismic: {f:g} Hz at rolling resistance {mu_r:g}")
            c = dataclasses.replace(case, frequency=float(f), rolling_resistance=float(mu_r))
            varied.setdefault(float(mu_r), {})[float(f)] = frequency_run(c, root=root, progress=progress, log=log)
    return write_report(case, folders, out_dir, material=out_dir / "seismic_material.json",
                        rolling_resistance_runs=varied)


def run_name(case: SeismicCase) -> str:
    """The run folder of one frequency of the validation: the frequency and the hash of
    the whole resolved case, so a changed setting never reads a stale run."""
    return f"validate-{case.frequency:g}Hz-{content_key(case)}"


def frequency_run(case: SeismicCase, *, root: Path, record: bool = False, progress=None, log=print) -> Path:
    """The run folder of ``compare_seismic`` on ``case`` (what ``write_report`` reads):
    ``<root>/seismic/<run_name>``, read as it is when it holds a finished run
    (result.json), resumed from its checkpoint when it holds an interrupted one (its
    config.toml is ``case``), else run afresh there."""
    from .compare import compare_seismic
    folder = Path(root) / "seismic" / run_name(case)

    def run(resume: Path | None) -> None:
        with named_run(folder.name):
            compare_seismic(case, root=root, record=record, progress=progress, resume=resume)

    run_once(folder, run, resumable=has_config, log=log)
    return folder


def stood_before_shaking(series: dict, ramp_s: float, wall_length_m: float) -> tuple[bool, str]:
    """Whether the wall stood until the base acceleration reached a quarter of its
    amplitude (prototype t <= ramp_s / 4): its top moved by at most STATIC_FAILURE x the
    wall length [m] from the static reading; and the numbers."""
    t, top = series["time_s"], series["top_displacement_m"]
    early = t <= 0.25 * ramp_s
    growth = float(np.max(np.abs(top[early])) - abs(top[0])) if early.any() else 0.0
    stood = growth <= STATIC_FAILURE * wall_length_m
    return stood, (f"wall top moved {growth:.3f} m in the first {0.25 * ramp_s:g} s (base acceleration "
                   f"below a quarter of its amplitude; a standing wall moves < {STATIC_FAILURE * wall_length_m:.3f} m)")


def frequency_record(folder: Path, case: SeismicCase | None = None) -> dict:
    """The issue's per-frequency record (prototype units) from one run folder
    (result.json, series.csv, settlement.csv), and the single-frequency trends (not
    assessed when the wall failed statically, ``stood_before_shaking``)."""
    res = json.loads((Path(folder) / "result.json").read_text())
    series = _csv(Path(folder) / "series.csv")
    settle = _csv(Path(folder) / "settlement.csv")
    p = res["prototype"]
    e = p["residual"]
    dist, s = settle["distance_m"], settle["settlement_m"]
    far = dist > 8.0
    rec = {"top_displacement_m": e["top_displacement_m"], "rotation_deg": e["rotation_deg"],
           "pivot_height_over_wall_length": e["pivot_height_over_wall_length"],
           "residual_moment_over_static": p["residual_moment_over_static"],
           "max_moment_over_static": p["max_moment_over_static"],
           "passive_K_max_at_1_5m": p["passive_K_max_at_1_5m"],
           "settlement_at_wall_m": float(s[0]) if len(s) else math.nan,
           "settlement_at_8m_m": float(np.mean(s[far])) if far.any() else math.nan,
           "wall_time_s": res["wall_time_s"]}
    back, front = series["thrust_back_kN_per_m"], series["thrust_front_kN_per_m"]
    rec["extra"] = {"passive_K_static_at_1_5m": p["passive_K_static_at_1_5m"],
                    "thrust_back_static_kN_per_m": float(back[0]), "thrust_back_max_kN_per_m": float(back.max()),
                    "thrust_front_static_kN_per_m": float(front[0]),
                    "thrust_front_max_kN_per_m": float(front.max()),
                    "thrust_front_residual_kN_per_m": float(front[-1]),
                    "mean_thrust_back_kN_per_m": float(back.mean()), "mean_thrust_front_kN_per_m": float(front.mean()),
                    "particles": res["particles"], "steps": res["steps"], "dt_s": res["dt_s"],
                    "steps_per_s": res["steps_per_s"], "porosity": res["porosity"], "run_folder": str(folder),
                    "rest": res.get("rest", {"rest_s": 0.0}),
                    "cpu_time_s": res.get("resources", {}).get("cpu_time_s")}
    case = case or SeismicCase()
    stood, why = stood_before_shaking(series, case.ramp_s, case.wall_length * case.scale_N)
    rec["extra"]["wall_stood_before_shaking"] = stood
    rec["trends"] = single_frequency_trends(rec)
    if not stood:
        rec["trends"] = {k: {"held": None, "numbers": f"not assessed: a static failure ({why}); read {t['numbers']}"}
                         for k, t in rec["trends"].items()}
    return rec


def _csv(path: Path) -> dict[str, np.ndarray]:
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in (rows[0] if rows else {})}


def single_frequency_trends(rec: dict) -> dict:
    """The paper's trends a single frequency can show: (held, the numbers)."""
    x = rec["extra"]
    pivot = rec["pivot_height_over_wall_length"]
    balance = abs(x["mean_thrust_back_kN_per_m"] - x["mean_thrust_front_kN_per_m"]) / x["mean_thrust_back_kN_per_m"]
    near, far = rec["settlement_at_wall_m"], rec["settlement_at_8m_m"]
    return {
        "rotation about a point near the base": {
            "held": bool(abs(pivot) <= PIVOT_NEAR_BASE),
            "numbers": f"residual pivot at {pivot:.2f} of the wall length above the toe "
                       f"(held if within {PIVOT_NEAR_BASE} of the toe), rotation {rec['rotation_deg']:.3f} deg"},
        "thrusts on the two faces equal and opposite": {
            "held": bool(balance <= THRUST_BALANCE),
            "numbers": f"mean over the record back {x['mean_thrust_back_kN_per_m']:.1f}, front "
                       f"{x['mean_thrust_front_kN_per_m']:.1f} kN/m (difference {100 * balance:.0f} %)"},
        "active thrust rising during shaking": {
            "held": bool(x["thrust_back_max_kN_per_m"] > x["thrust_back_static_kN_per_m"]),
            "numbers": f"back thrust static {x['thrust_back_static_kN_per_m']:.1f}, max "
                       f"{x['thrust_back_max_kN_per_m']:.1f} kN/m"},
        "maximum and residual moments significantly above static": {
            "held": bool(min(rec["max_moment_over_static"], rec["residual_moment_over_static"]) >= SIGNIFICANT),
            "numbers": f"max / static {rec['max_moment_over_static']:.2f}, residual / static "
                       f"{rec['residual_moment_over_static']:.2f} (held if both >= {SIGNIFICANT:g})"},
        "settlement concentrated near the wall, ~0 beyond 8 m": {
            # ~0 either way: a far ground that heaves is no more "~0" than one that settles
            "held": bool(near > 0 and abs(far) < FAR_SETTLEMENT * near),
            "numbers": f"at the wall {near * 1e3:.1f} mm, mean beyond 8 m {far * 1e3:.1f} mm (held if its size is "
                       f"below {FAR_SETTLEMENT:g} x the wall's)"},
        "front (passive) pressure rising with shaking": {
            "held": bool(rec["passive_K_max_at_1_5m"] > x["passive_K_static_at_1_5m"]),
            "numbers": f"K at 1.5 m below the dredge line static {x['passive_K_static_at_1_5m']:.2f}, max "
                       f"{rec['passive_K_max_at_1_5m']:.2f}"},
    }


def across_frequencies(freqs: dict) -> dict:
    """Trends over frequencies: held / not held when all the paper's frequencies ran,
    else not run."""
    done = {f: r for f, r in freqs.items() if r is not None}
    if set(done) != set(PAPER_FREQUENCIES):
        missing = ", ".join(f"{f:g}" for f in PAPER_FREQUENCIES if f not in done)
        note = f"not run (needs every frequency; missing {missing} Hz)"
        return {k: {"held": None, "numbers": note} for k in
                ("largest wall displacement at 4 or 5 Hz", "passive pressure rising far more at 4-6 Hz than 1, 3 Hz",
                 "largest settlement at 5 Hz")}
    top = {f: abs(r["top_displacement_m"]) for f, r in done.items()}
    k = {f: r["passive_K_max_at_1_5m"] for f, r in done.items()}
    s = {f: r["settlement_at_wall_m"] for f, r in done.items()}
    f_top = max(top, key=top.get)
    f_s = max(s, key=s.get)
    return {"largest wall displacement at 4 or 5 Hz": {"held": f_top in (4.0, 5.0), "numbers": f"largest at {f_top:g} Hz"},
            "passive pressure rising far more at 4-6 Hz than 1, 3 Hz": {
                "held": min(k[4.0], k[5.0], k[6.0]) >= SIGNIFICANT * max(k[1.0], k[3.0]),
                "numbers": ", ".join(f"{f:g} Hz K {v:.2f}" for f, v in sorted(k.items()))
                + f" (smallest at 4-6 Hz / largest at 1, 3 Hz "
                  f"{min(k[4.0], k[5.0], k[6.0]) / max(k[1.0], k[3.0]):.2f}; held if >= {SIGNIFICANT:g})"},
            "largest settlement at 5 Hz": {"held": f_s == 5.0, "numbers": f"largest at {f_s:g} Hz"}}


#: what the report's figures show and what to compare them with (the paper's words)
FIGURE_CAPTIONS = {
    "fig3_pressures.png": ("Fig. 3", "Static, maximum and residual pressure on both faces at every frequency. "
                           "The paper: the front (excavated side) pressure rises substantially during shaking, "
                           "most at 4-6 Hz, whose maximum and residual are alike; much less at 1 and 3 Hz."),
    "fig4_K_rotation.png": ("Fig. 4", "K on the front face 1.5 m below the dredge line against the wall's "
                            "rotation, 3-6 Hz as in the paper. The paper: at 4, 5 and 6 Hz the wall rotates "
                            "enough to mobilise the full passive strength there; at 1 and 3 Hz it does not."),
    "fig5_thrusts.png": ("Fig. 5", "Total thrust on both faces against time. The paper: the active thrust "
                         "rises during shaking, and the two thrusts stay equal and opposite."),
    "fig8_settlement.png": ("Fig. 8", "Settlement of the retained ground against distance from the wall, every "
                            "frequency. The paper: most settlement next to the wall, almost none beyond 8 m, "
                            "the largest at 5 Hz."),
}
#: each run's own sheets: Figs. 2, 3, 5, 6 and 8 of one frequency; Fig. 4; Fig. 7
RUN_FIGURES = {"seismic.png": ("Figs. 2, 3, 5, 6, 8", "One frequency: the deformed shape (the paper: mostly a "
                               "rigid rotation about a point near the toe), face pressures with Mononobe-Okabe, "
                               "thrusts, bending moments (the paper: maximum and residual well above static), "
                               "displacements and settlement."),
               "K_vs_rotation.png": ("Fig. 4", "One frequency: K 1.5 m below the dredge line against rotation."),
               "shear_strain.png": ("Fig. 7", "Maximum shear strain since the base started to move at 1.5, 2, "
                                    "3.5 and 9 s. The paper (5 Hz): a Coulomb-like planar failure wedge forms "
                                    "behind the wall.")}


def report_figures(folders: dict, out_dir: Path) -> list[dict]:
    """The paper's figures from the run folders (Hz -> folder) into ``out_dir``/seismic/:
    Figs. 3, 4, 5 and 8 with every frequency side by side, and each run's own sheets;
    returns one record per file (file, the paper's figure, caption)."""
    from .figures import (plot_K_rotation_by_frequency, plot_pressures_by_frequency, plot_settlement_by_frequency,
                          plot_thrusts_by_frequency)
    target = Path(out_dir) / "seismic"
    if target.exists():
        shutil.rmtree(target)                       # no figure of an earlier report stays beside these
    target.mkdir(parents=True)
    folders = {float(f): Path(d) for f, d in sorted(folders.items())}
    series = {f: _csv(d / "series.csv") for f, d in folders.items()}
    made = [plot_pressures_by_frequency({f: _csv(d / "pressure_profiles.csv") for f, d in folders.items()},
                                        target / "fig3_pressures.png"),
            plot_thrusts_by_frequency(series, target / "fig5_thrusts.png"),
            plot_settlement_by_frequency({f: _csv(d / "settlement.csv") for f, d in folders.items()},
                                         target / "fig8_settlement.png")]
    fig4 = {f: s for f, s in series.items() if f >= 3.0}
    if fig4:
        mo = _REFERENCE["mononobe_okabe"]
        lines = {"Coulomb K_P, delta 0": mo["delta_0"]["K_P"],
                 "Coulomb K_P, delta 2 phi / 3 (the scorecard's full passive)": mo["delta_2phi_over_3"]["K_P"]}
        made.append(plot_K_rotation_by_frequency(fig4, target / "fig4_K_rotation.png", K_p=lines))
    out = [{"file": f"seismic/{p.name}", "paper": FIGURE_CAPTIONS[p.name][0], "caption": FIGURE_CAPTIONS[p.name][1]}
           for p in made]
    for f, d in folders.items():
        for name, (paper, caption) in RUN_FIGURES.items():
            if (d / name).is_file():
                dest = target / f"{f:g}Hz_{name}"
                shutil.copyfile(d / name, dest)
                out.append({"file": f"seismic/{dest.name}", "paper": paper, "caption": f"{f:g} Hz. {caption}"})
    return out


def write_report(case: SeismicCase, folders: dict, out_dir: Path, *, material: Path | None = None,
                 note: str = "", rolling_resistance_runs: dict | None = None) -> dict:
    """seismic.json and seismic.md from run folders by frequency (prototype Hz -> folder);
    frequencies of the paper without a folder are written as not run. At the default
    resolution the report is rewritten (an earlier ``other_resolutions`` block kept); at
    another, the runs go into ``other_resolutions[<name>]`` of the existing report and are
    set beside the default resolution's frequency by frequency (``resolution_changes``).
    ``note`` (else ``seismic_discussion.md`` beside the report, written by hand) goes in
    after the material checks. ``rolling_resistance_runs`` (mu_r -> frequency -> folder,
    default resolution only) replace those values' entries of the report's
    ``rolling_resistance`` block; the others are kept while their runs rested as this
    report's did (``rolling_resistance_block``)."""
    path = out_dir / "seismic.json"
    old = json.loads(path.read_text()) if path.is_file() else None
    default = SeismicCase().resolution
    main = old is None or case.resolution == default or old.get("resolution") != default
    earlier = old if main else (old.get("other_resolutions", {}).get(case.resolution) if old else None)
    kept = {f: r for f, r in kept_records(earlier, case).items() if f not in folders}
    freqs = {f: (frequency_record(folders[f], case) if f in folders else kept.get(f)) for f in PAPER_FREQUENCIES}
    block = {"resolution": case.resolution, "grain_scale": case.scale, "contact_sums": contact_sums(case),
             "frequencies": {f"{f:g}": (_stored(r) if r is not None else "not run") for f, r in freqs.items()},
             "git": _started_at(folders, earlier if kept else None)}
    if main:
        rep = block | {"trends_across_frequencies": None, "versions": package_versions(),         # reread fills it
                       "applied": applied_input(case, [f for f, r in freqs.items() if r is not None]),
                       "reproducibility": reproducibility.describe(),
                       "source": "Sizkow & El Shamy (conference paper), trends of section 7 of "
                                 "docs/reference/seismic-sheetpile.md"}
        if old is not None and case.resolution == default and "other_resolutions" in old:
            rep["other_resolutions"], superseded = _same_protocol(old["other_resolutions"], case)
            if superseded:
                rep["superseded"] = superseded
        if (sums := other_sums_block(old, case)) is not None:
            rep["other_sums"] = sums
        if folders and not kept:
            rep["figures"] = report_figures(folders, out_dir)
        elif kept and "figures" in old:
            rep["figures"] = old["figures"]     # drawn from every frequency's folder; some are not here
        mu_r = rolling_resistance_block(case, (old or {}).get("rolling_resistance", {}).get("runs", {}),
                                        rolling_resistance_runs or {})
        if mu_r:
            rep["rolling_resistance"] = {"report_value": case.rolling_resistance, "runs": mu_r}
    else:
        rep = old
        rep.setdefault("other_resolutions", {})[case.resolution] = block
    reread(rep)
    rep["resolution_changes"] = resolution_changes(rep)
    if material is not None and Path(material).is_file():
        rep["material"] = json.loads(Path(material).read_text())
    rep["scorecard"] = scorecard(rep)
    out_dir.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(rep, indent=1) + "\n")
    discussion = out_dir / "seismic_discussion.md"
    if not note and discussion.is_file():
        note = discussion.read_text().strip()          # the hand-written part survives a rerun
    (out_dir / "seismic.md").write_text(report_markdown(rep, note))
    return rep


def applied_input(case: SeismicCase, frequencies) -> dict:
    """What ``case`` sets and applies, from its definition (nothing is run): the grain
    density, and per prototype frequency in ``frequencies`` the base acceleration that
    ``specimen.base_motion`` builds for it (``dem3d.sine_ramp``, baseline-corrected), read
    back in prototype units (peak [g], length [s], the baseline correction's constant [g]),
    beside the envelope times the case sets. The scorecard reads the paper's inputs
    (Table 1's unit weight, the base motion of section 3) against these."""
    from analytic.constants import G
    from .specimen import base_motion
    motion = {}
    for f in frequencies:
        c = dataclasses.replace(case, frequency=float(f))
        _, table = base_motion(c, 0.0)
        a = table.accel[:, 0] / (c.scale_N * G)                  # prototype g
        motion[f"{f:g}"] = {"frequency_Hz": c.frequency, "model_frequency_Hz": c.model_frequency,
                            "peak_g": float(np.max(np.abs(a))), "baseline_g": float(a[0]),
                            "length_s": float(c.to_prototype_time(table.times[-1] - table.times[0])),
                            "ramp_s": c.ramp_s, "hold_s": c.hold_s, "decay_s": c.decay_s, "envelope": "linear ramps"}
    return {"source": "the case definition (studies/seismic/case.py) and the base acceleration it applies "
                      "(studies/seismic/specimen.py base_motion), prototype units; computed, not measured in a run",
            "grain_density_kg_per_m3": case.grain_density, "g_m_per_s2": G, "motion": motion}


def rolling_resistance_block(case: SeismicCase, kept: dict, runs: dict) -> dict:
    """The runs of the case at other rolling resistances: {mu_r: {frequency: record}}
    (``frequency_record``), the new ``runs`` (mu_r -> frequency -> folder) over the
    ``kept`` ones; kept runs that did not rest as ``case`` does are dropped (their static
    readings do not compare)."""
    out = {k: v for k, v in kept.items() if _rest_s({"frequencies": v}) == case.rest_s}
    for mu_r, by_freq in runs.items():
        c = dataclasses.replace(case, rolling_resistance=mu_r)
        recs = {f"{f:g}": frequency_record(folder, dataclasses.replace(c, frequency=f)) for f, folder in by_freq.items()}
        out[f"{mu_r:g}"] = {**out.get(f"{mu_r:g}", {}), **{f: _stored(r) for f, r in recs.items()}}
    return dict(sorted(out.items(), key=lambda kv: float(kv[0])))


def _stored(rec: dict) -> dict:
    """One frequency's record as the report keeps it: the KEYS, its trends and extra."""
    return {k: rec[k] for k in KEYS} | {"trends": rec["trends"], "extra": rec["extra"]}


def _rest_s(block: dict) -> float:
    """The rest before shaking (prototype s) of a resolution's runs (0 before it existed)."""
    return max((r["extra"].get("rest", {"rest_s": 0.0})["rest_s"] for r in block["frequencies"].values()
                if r != "not run"), default=0.0)


def _same_protocol(others: dict, case: SeismicCase) -> tuple[dict, dict]:
    """(kept, superseded): the other resolutions' blocks whose runs rested as ``case``'s
    do before shaking, and the others with why they cannot stand beside this report."""
    kept, gone = {}, {}
    for name, block in others.items():
        if _rest_s(block) == case.rest_s:
            kept[name] = block
        else:
            gone[name] = {"git": block["git"], "frequencies": [f for f, r in block["frequencies"].items()
                                                               if r != "not run"],
                          "why": f"run with a rest of {_rest_s(block):g} s before shaking (this report: "
                                 f"{case.rest_s:g} s): its static readings were taken on a wall still moving, "
                                 "so its ratios to static do not compare; run it again to set it beside"}
    return kept, gone


def scorecard(rep: dict) -> dict:
    """The report's scorecard (``studies.seismic.scorecard``) from its own record."""
    from ..scorecard import scorecard_json
    from .scorecard import scorecard_rows
    ref = json.loads((Path(__file__).with_name("reference.json")).read_text())
    return scorecard_json(scorecard_rows(rep, ref, rep.get("material")))


#: the static state and the peaks behind the ratios, compared as well
COMPARED_EXTRA = ("passive_K_static_at_1_5m", "thrust_back_static_kN_per_m", "thrust_back_max_kN_per_m",
                  "thrust_front_static_kN_per_m", "thrust_front_max_kN_per_m")


def block_changes(base: dict, other: dict, base_name: str, other_name: str) -> dict:
    """Per frequency run in both blocks: each KEYS value (wall time left out: it is a
    cost) and each COMPARED_EXTRA value in ``base`` and in ``other`` (named so in the
    rows) and the change [%], the particles, and whether each trend has the same verdict."""
    rows = {}
    for f, r in other["frequencies"].items():
        b_rec = base["frequencies"].get(f)
        if r == "not run" or b_rec in (None, "not run"):
            continue
        pairs = {k: (b_rec[k], r[k]) for k in KEYS if k != "wall_time_s"} | \
            {k: (b_rec["extra"][k], r["extra"][k]) for k in COMPARED_EXTRA}
        rows[f] = {k: {base_name: b, other_name: o, "change_percent": 100 * (o - b) / abs(b) if b else None}
                   for k, (b, o) in pairs.items()}
        rows[f]["particles"] = {base_name: b_rec["extra"]["particles"], other_name: r["extra"]["particles"]}
        rows[f]["trends_same"] = {t: _held(b_rec["trends"][t]) == _held(r["trends"][t]) for t in b_rec["trends"]}
    return rows


def resolution_changes(rep: dict) -> dict:
    """Per other resolution: ``block_changes`` of the report against it."""
    return {name: block_changes(rep, other, rep["resolution"], name)
            for name, other in rep.get("other_resolutions", {}).items()}


def other_sums_block(old: dict | None, case: SeismicCase) -> dict | None:
    """The runs of an earlier report at ``case``'s resolution and rest whose contact
    forces were summed in the other order (``direct_sums``), kept beside the new runs to
    show what the order of sums moves: the earlier report's own frequencies when it
    summed otherwise, else the block it kept, else None."""
    if old is None or old.get("resolution") != case.resolution:
        return None
    if block_sums(old) != contact_sums(case) and _rest_s(old) == case.rest_s:
        return {"contact_sums": block_sums(old), "git": old["git"], "frequencies": old["frequencies"]}
    kept = old.get("other_sums")
    return kept if kept and kept["contact_sums"] != contact_sums(case) else None


def sum_order_lines(rep: dict) -> list[str]:
    """What the order of sums moved: each frequency run both ways, beside each other."""
    other = rep.get("other_sums")
    rows = block_changes(rep, other, block_sums(rep), other["contact_sums"]) if other else {}
    if not rows:
        return []
    a, b = block_sums(rep), other["contact_sums"]
    lines = ["", f"## How the results move with the order of sums: {a} vs {b} (git {other['git']})", "",
             "The same case and seed, each contact force the same to rounding, summed on each grain in another "
             "order: another realization of the deposit. Whether a change is larger than the seed scatter is "
             "not read from one seed; the discussion sets it against several.", ""]
    for f, row in rows.items():
        lines += ["", f"{f} Hz:", "", f"| quantity | {a} | {b} | change |", "|---|---|---|---|"]
        for k in [k for k in KEYS if k != "wall_time_s"] + list(COMPARED_EXTRA):
            c = row[k]
            ch = "" if c["change_percent"] is None else f"{c['change_percent']:+.0f} %"
            lines.append(f"| {k} | {c[a]:.4g} | {c[b]:.4g} | {ch} |")
        diff = [t for t, ok in row["trends_same"].items() if not ok]
        lines += ["", f"Trends with the same verdict both ways: {len(row['trends_same']) - len(diff)} of "
                      f"{len(row['trends_same'])}" + (f"; different: {', '.join(diff)}" if diff else "") + "."]
    return lines


#: what the paper leaves out and the model assumes (reference.json tags each value)
ASSUMPTIONS = ("Assumed, not from the paper (reference.json, tag A): the contact law (Hertz-Mindlin, quartz "
               "G 29 GPa, nu 0.15), friction 0.5, contact damping 5 %, the wall-soil friction (= the grains'), "
               "the bonds' stiffness split, and the rolling resistance mu_r 0.25 of the grains, calibrated once "
               "(not per frequency) so that the deposit's triaxial gives the paper's phi ~31 deg: friction alone "
               "gives ~18-19 deg and the wall then fails statically.")


#: the paper's free-field column: 9 m of soil ringing at 5.8 Hz, Vs 210 m/s
PAPER_COLUMN = {"height_m": 9.0, "f0_Hz": 5.8, "Vs_m_per_s": 210.0}


def _paper_column(height_m: float) -> str:
    """The paper's column beside ours: its f0 where the heights agree, else the f0 its Vs
    gives a column of our height (f0 = Vs / 4 H): frequencies of columns of different
    heights are not comparable, the soil's Vs is."""
    p = PAPER_COLUMN
    if abs(height_m - p["height_m"]) < 1e-9:
        return f"paper, {p['height_m']:g} m column: {p['f0_Hz']:g} Hz, {p['Vs_m_per_s']:g} m/s"
    return (f"paper: Vs {p['Vs_m_per_s']:g} m/s, so a {height_m:g} m column at {p['Vs_m_per_s'] / (4 * height_m):.2f} "
            f"Hz; its {p['height_m']:g} m column rang at {p['f0_Hz']:g} Hz")


def material_lines(mat: dict) -> list[str]:
    """The material checks (benchmarks/seismic_material.py) as report lines."""
    out = ["## Material (measured, docs/validation/seismic_material.json)", ""]
    for name in ("retained", "front"):
        c = mat.get(f"column_{name}")
        if c:
            out.append(f"- free-field column {name} ({c['height_m_prototype']:g} m): f0 {c['f0_Hz_prototype']:.2f} Hz, "
                       f"Vs = 4 H f0 = {c['Vs_from_f0_m_per_s']:.0f} m/s ({_paper_column(c['height_m_prototype'])})")
    for t in mat.get("triaxial", []):
        out.append(f"- triaxial {t['confining_kPa']:g} kPa, friction {t['friction']:g}, mu_r "
                   f"{t.get('rolling_resistance', 0):g}: peak phi {t['phi_peak_deg']:.1f} deg, end "
                   f"{t['phi_end_deg']:.1f}, inner porosity {t.get('inner_porosity', float('nan')):.3f} "
                   f"(paper ~31 deg at 0.40)")
    return out


def reread(rep: dict) -> None:
    """Every stored record of ``rep`` (each resolution's, each rolling resistance's) judged
    again by today's reading of the paper's words from its stored numbers
    (``single_frequency_trends``; ``across_frequencies`` per resolution), so a report
    written without its runs never keeps the verdict of an older reading. A record of a
    wall that failed statically keeps its 'not assessed'."""
    blocks = [rep, *rep.get("other_resolutions", {}).values()]
    records = [r for b in blocks for r in b["frequencies"].values()]
    records += [r for by_f in rep.get("rolling_resistance", {}).get("runs", {}).values() for r in by_f.values()]
    for r in records:
        if r != "not run" and r["extra"].get("wall_stood_before_shaking", True):
            r["trends"] = single_frequency_trends(r)
    for b in blocks:
        b["trends_across_frequencies"] = across_frequencies(
            {float(f): (None if r == "not run" else r) for f, r in b["frequencies"].items()})


def kept_records(block: dict | None, case: SeismicCase) -> dict:
    """The finished frequencies of an earlier report ``block`` (one resolution's) that ran
    ``case`` itself: their run folder is this case's ``run_name`` at that frequency (the
    content key of every case field), so a report written where those folders are absent
    keeps them instead of calling them not run. Prototype Hz -> stored record."""
    out = {}
    for f, rec in ((block or {}).get("frequencies") or {}).items():
        if rec != "not run" and \
                Path(rec["extra"]["run_folder"]).name == run_name(dataclasses.replace(case, frequency=float(f))):
            out[float(f)] = rec
    return out


def _started_at(folders: dict, earlier: dict | None = None) -> str:
    """The git revisions the runs started at (their manifests), after those of the
    ``earlier`` block whose records are kept."""
    revs = [r.strip() for r in earlier["git"].split(",")] if earlier else []
    for _, folder in sorted(folders.items()):
        man = Path(folder) / "manifest.json"
        revs.append(json.loads(man.read_text()).get("git", "?") if man.is_file() else git_revision())
    return ", ".join(dict.fromkeys(revs)) or git_revision()


def _seconds(s) -> str:
    return "not recorded" if s is None else f"{s:.0f}"


def _held(t) -> str:
    if t["held"] is None:
        return "not assessed" if t["numbers"].startswith("not assessed") else "not run"
    return "held" if t["held"] else "NOT held"


def report_markdown(rep: dict, note: str = "") -> str:
    from ..scorecard import scorecard_markdown
    lines = ["# Validation: Sizkow & El Shamy, a sheet pile shaken at 50 g (3D DEM)", "",
             f"Generated by `studies.seismic.validate.write_report` (git {rep['git']}); resolution "
             f"{rep['resolution']} (grain scale {rep['grain_scale']:g}: grains and wall balls "
             f"{rep['grain_scale']:g} x the paper's, the wall's EI and mass per area the paper's); "
             f"{SUMS_TEXT[block_sums(rep)]}. Prototype units. The paper gives one table (Table 1, the soil's properties), the base motion in "
             "numbers (section 3), and otherwise trends and figures: its results are checked as trends.", ""]
    if "scorecard" in rep:
        lines += scorecard_markdown(rep["scorecard"], "Scorecard: every statement of the paper")
    moved = any(rep.get("resolution_changes", {}).values())
    lines += [ASSUMPTIONS + (" How they move with resolution: the last section." if moved else
                             " How they move with resolution is not measured yet."), ""]
    if "material" in rep:
        lines += material_lines(rep["material"]) + [""]
    lines += rest_lines(rep)
    if note:
        lines += [note, ""]
    lines += ["| Hz | top displacement [m] | rotation [deg] | pivot / L | M max / static | M residual / static | "
              "passive K max at 1.5 m | settlement at wall [m] | beyond 8 m [m] | wall time [s] | CPU [s] |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    for f, r in rep["frequencies"].items():
        if r == "not run":
            lines.append(f"| {f} | not run | | | | | | | | | |")
            continue
        lines.append(f"| {f} | {r['top_displacement_m']:.4f} | {r['rotation_deg']:.3f} | "
                     f"{r['pivot_height_over_wall_length']:.2f} | {r['max_moment_over_static']:.2f} | "
                     f"{r['residual_moment_over_static']:.2f} | {r['passive_K_max_at_1_5m']:.2f} | "
                     f"{r['settlement_at_wall_m']:.4f} | {r['settlement_at_8m_m']:.4f} | {r['wall_time_s']:.0f} | "
                     f"{_seconds(r['extra'].get('cpu_time_s'))} |")
    lines += ["", "## Trends", "", "| trend | frequency | result | numbers |", "|---|---|---|---|"]
    for f, r in rep["frequencies"].items():
        if r == "not run":
            continue
        for name, t in r["trends"].items():
            lines.append(f"| {name} | {f} Hz | {_held(t)} | {t['numbers']} |")
    for name, t in rep["trends_across_frequencies"].items():
        lines.append(f"| {name} | all | {_held(t)} | {t['numbers']} |")
    lines += resolution_lines(rep)
    lines += sum_order_lines(rep)
    lines += rolling_resistance_lines(rep)
    for name, why in rep.get("superseded", {}).items():
        lines += ["", f"The {name} resolution (git {why['git']}, {', '.join(why['frequencies'])} Hz) is left out: "
                      f"{why['why']}."]
    lines += figure_lines(rep.get("figures", []))
    return "\n".join(lines) + "\n"


def rest_lines(rep: dict) -> list[str]:
    """The static state: how the wall moved while the shaken model rested before the base
    moved (the same static state and rest for every frequency)."""
    rests = {f: r["extra"].get("rest", {}) for f, r in rep["frequencies"].items() if r != "not run"}
    if not rests or not any(v.get("rest_s") for v in rests.values()):
        return []
    f, r = next(iter(rests.items()))
    same = all(v == r for v in rests.values())
    top, back = r["top_displacement_m"], r["thrust_back_kN_per_m"]
    return ["## The static state", "",
            f"The static stage settles under local damping 0.7; the shaken model has none, and it rests "
            f"{r['rest_s']:g} s (prototype) with the base still before the base moves. In the rest the wall top "
            f"moved {top[0] * 1e3:.1f} -> {top[1] * 1e3:.1f} mm toward the excavation "
            f"({r['top_change_over_last_fifth_m'] * 1e3:+.1f} mm over its last fifth) and the back thrust "
            f"{back[0]:.1f} -> {back[1]:.1f} kN/m" + (" (the same at every frequency)." if same else
                                                     f" ({f} Hz; the other frequencies differ: see the JSON).")
            + " Every 'static' figure below is the one at the end of the rest.", ""]


def figure_lines(figures: list[dict]) -> list[str]:
    """The figures of the report, each with the paper's figure and what to compare."""
    if not figures:
        return []
    lines = ["", "## Figures", ""]
    for fig in figures:
        lines += [f"**{fig['paper']}** ({fig['file']}): {fig['caption']}", "", f"![{fig['paper']}]({fig['file']})", ""]
    return lines


def rolling_resistance_lines(rep: dict) -> list[str]:
    """How the results move with the assumed rolling resistance: per frequency run at
    other mu_r, each KEYS value and the static state beside the report's own run."""
    block = rep.get("rolling_resistance")
    if not block:
        return []
    own = f"{block['report_value']:g}"
    lines = ["", f"## How the results move with the rolling resistance (assumed; this report: mu_r {own})", "",
             "mu_r is the one contact value fitted to the paper (the deposit's triaxial phi ~31 deg at 0.25: 29.9 "
             "and 32.3 deg at 0.2 and 0.3); each run below is the report's case with only mu_r changed, with the "
             "same rest before shaking and its own static state."]
    freqs = sorted({f for runs in block["runs"].values() for f in runs}, key=float)
    for f in freqs:
        cols = {mu: runs[f] for mu, runs in block["runs"].items() if f in runs}
        if rep["frequencies"].get(f, "not run") != "not run":
            cols[own] = rep["frequencies"][f]
        cols = dict(sorted(cols.items(), key=lambda kv: float(kv[0])))
        lines += ["", f"{f} Hz:", "", "| quantity | " + " | ".join(f"mu_r {mu}" for mu in cols) + " |",
                  "|---|" + "---|" * len(cols)]
        for k in [k for k in KEYS if k != "wall_time_s"]:
            lines.append(f"| {k} | " + " | ".join(f"{r[k]:.4g}" for r in cols.values()) + " |")
        for k in COMPARED_EXTRA:
            lines.append(f"| {k} | " + " | ".join(f"{r['extra'][k]:.4g}" for r in cols.values()) + " |")
        lines.append("| CPU [s] | " + " | ".join(_seconds(r["extra"].get("cpu_time_s")) for r in cols.values()) + " |")
        lines.append("| single-frequency trends held | " + " | ".join(
            f"{sum(t['held'] is True for t in r['trends'].values())} of {len(r['trends'])}" for r in cols.values())
            + " |")
    return lines


def contact_sums(case: SeismicCase) -> str:
    """How the runs summed contact forces (``SeismicCase.direct_sums``): 'direct' or 'rows'."""
    return "direct" if case.direct_sums else "rows"


#: the report's words for each ``contact_sums``
SUMS_TEXT = {"direct": "each contact force added to both its grains at once (direct_sums true)",
             "rows": "each contact force stored as a row and gathered per grain after (direct_sums false)"}


def block_sums(block: dict) -> str:
    """A report block's ``contact_sums``; a block written before the field: 'rows'."""
    return block.get("contact_sums", "rows")


def resolution_lines(rep: dict) -> list[str]:
    """How the results move between the report's resolution and the others run."""
    lines = []
    for name, rows in rep.get("resolution_changes", {}).items():
        other = rep["other_resolutions"][name]
        lines += ["", f"## How the results move with resolution: {rep['resolution']} (grain scale "
                      f"{rep['grain_scale']:g}) vs {name} (grain scale {other['grain_scale']:g}, git {other['git']})", ""]
        if block_sums(rep) != block_sums(other):
            lines += [f"The two also sum contact forces in another order ({rep['resolution']}: {block_sums(rep)}, "
                      f"{name}: {block_sums(other)}; the same forces, each grain's total within rounding): another "
                      "realization of the same case, so each change below holds the seed scatter as well as the "
                      "resolution's effect.", ""]
        across = other.get("trends_across_frequencies", {})
        if across:
            lines += [f"Trends across frequencies at {name}:", ""]
            lines += [f"- {t}: " + (v["numbers"] if v["held"] is None else f"**{_held(v)}** ({v['numbers']})")
                      for t, v in across.items()]
        if not rows:
            lines.append(f"No frequency was run at both resolutions ({name}: "
                         f"{', '.join(f for f, r in other['frequencies'].items() if r != 'not run') or 'none'}).")
            continue
        for f, row in rows.items():
            r = other["frequencies"][f]
            cpu = r["extra"].get("cpu_time_s")
            cost = f"{name} CPU {cpu:.0f} s" if cpu is not None else f"{name} wall time {r['wall_time_s']:.0f} s"
            lines += ["", f"{f} Hz: {row['particles'][rep['resolution']]} vs {row['particles'][name]} particles "
                      f"(spheres in the model, the free-field columns apart); {cost}.", "",
                      f"| quantity | {rep['resolution']} | {name} | change |", "|---|---|---|---|"]
            for k in [k for k in KEYS if k != "wall_time_s"] + list(COMPARED_EXTRA):
                c = row[k]
                ch = "" if c["change_percent"] is None else f"{c['change_percent']:+.0f} %"
                lines.append(f"| {k} | {c[rep['resolution']]:.4g} | {c[name]:.4g} | {ch} |")
            same = [t for t, ok in row["trends_same"].items() if ok]
            diff = [t for t, ok in row["trends_same"].items() if not ok]
            lines += ["", f"Single-frequency trends with the same verdict at both: {len(same)} of "
                          f"{len(row['trends_same'])}" + (f"; different: {', '.join(diff)} ({name}: "
                          + ", ".join(_held(r['trends'][t]) for t in diff) + ")" if diff else "") + "."]
    return lines
