"""The validation report of the Khosravi case: ``khosravi.json`` (numbers) and
``khosravi.md`` (what they mean, against the paper and the validation targets), with the
run's figures copied next to them."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from studies.report import check, checks_markdown, within
from studies.store import atomic_write, read_report, to_plain


def _trend(d: dict) -> str:
    """PS0 against the straight line through the readings (absent from older results)."""
    t = d.get("PS0_at_rest_over_linear_trend")
    return "" if t is None else f"; PS0 / straight line through the readings at its depth = {t:.2f}"


def _sweeps(res: dict) -> str:
    """'40' or '40 (fill), 80 (readings)' -- older results have no readings' sweeps."""
    fill, reading = res["iterations"], res.get("iterations_readings", res["iterations"])
    return f"{fill}" if fill == reading else f"{fill} (fill), {reading} (at rest and translation)"


def _dis_active(result: dict) -> str:
    """Dis/H of the record the active figures are read at (results before it was stored: n/a)."""
    x = result.get("wall_disp_over_H_active")
    return "n/a" if x is None else f"{x:.4g}"


def assess(result: dict, ref: dict) -> list[dict]:
    """Each validation target (reference.json "targets") with the measured figure and
    whether it holds."""
    d = result["dem"]
    tg = ref["targets"]
    rel = abs(d["K_at_rest_upper_half_over_jaky"] - 1.0)
    # steadiness is measured against the run's last value: only a run that goes well past
    # the target Dis/H can show the pressure still falling after it
    end = result.get("wall_disp_over_H_end", result.get("wall_disp_over_H_active"))
    judged = end is not None and end >= 2 * tg["wall_disp_over_H_steady_at_most"]
    return [
        check("at-rest K, upper half, within 15 % of 1 - sin(phi_biaxial)",
              f"K = {d['K_at_rest_upper_half']:.3f} vs {d['jaky_K0']:.3f} "
              f"({100 * (d['K_at_rest_upper_half_over_jaky'] - 1):+.1f} %)",
              rel <= tg["K_at_rest_upper_half_vs_jaky_rel_tol"]),
        check("at-rest reduction at the bottom corner visible in PS0",
              f"PS0 = {d['PS0_at_rest_over_gammaH']:.3f} gamma H; lowest 4-panel reading "
              f"{d['lowest_reading_at_rest_over_gammaH']:.3f} gamma H; PS0 / Jaky at its depth = "
              f"{d['PS0_at_rest_over_jaky']:.2f}" + _trend(d),
              d["PS0_at_rest_over_gammaH"] < d["lowest_reading_at_rest_over_gammaH"]),
        check("active profile below at-rest everywhere",
              "all reading points" if d["active_below_at_rest_everywhere"] else "not at every reading point",
              d["active_below_at_rest_everywhere"]),
        check(f"active total thrust below Rankine's (at Dis/H = {_dis_active(result)})",
              f"{d['active_thrust_over_rankine']:.3f} x Rankine",
              d["active_thrust_over_rankine"] < tg["active_thrust_over_rankine_below"]),
        check("steady state reached by Dis/H <= 0.003",
              f"Dis/H = {d['wall_disp_over_H_steady']:.5f} (90 % of the drop to the run's end), "
              f"{d['wall_disp_over_H_steady_95']:.5f} (95 %)"
              + ("" if judged else "; the run ends at the target, so this cannot show a later fall"),
              d["wall_disp_over_H_steady"] <= tg["wall_disp_over_H_steady_at_most"] if judged else None),
        check("vertical reactions = weight", f"{d['weight_balance']:.4f}",
              within(d["weight_balance"], 1.0, tg["weight_balance_abs_tol"])),
        _time_check(result, tg["case_wall_time_min_at_most"]),
    ]


def _time_check(result: dict, goal_min: float) -> dict:
    """The time goal: pluviation + at-rest reading + translation to the active
    reading, wall time of one run that filled its own box (a reused specimen cannot say)."""
    t = result.get("timings_s", {})
    item = f"full-size case (pluviation + translation to Dis/H 0.003) within {goal_min:g} min"
    parts = [t.get(k) for k in ("pluviation_s", "at_rest_s", "translation_to_active_s")]
    if result.get("specimen_reused"):
        return check(item, "n/a: the specimen was reused, so this run did not fill", None)
    if any(p is None for p in parts):  # results written before the time to the active reading was kept
        return check(item, "n/a: this result does not record the time of each stage", None)
    minutes = sum(parts) / 60
    return check(item, f"{minutes:.1f} min (pluviation {parts[0] / 60:.1f}, at rest {parts[1] / 60:.1f}, "
                       f"translation {parts[2] / 60:.1f})", minutes <= goal_min)


_FIGURES = ("fig09_backfilling.png", "fig10_at_rest.png", "fig11_corner_chains.png", "fig12_pressure_vs_displacement.png",
            "fig13_profiles.png")
#: what to compare in a figure that does not say it in its own title
FIGURE_CAPTIONS = {"fig11_corner_chains": "Fig. 11(b), the strong force network at rest in the lower corner: the "
                                          "paper sees local arching there (chains turning off the wall toward the "
                                          "base), which lowers the at-rest pressure of the lowest cells (Fig. 10)"}
_MANIFEST_KEYS = ("versions", "git", "host", "cpu_count", "wall_time_s")


def _manifest(folder: Path) -> dict:
    p = folder / "manifest.json"
    return json.loads(p.read_text()) if p.exists() else {}


def write_report(result: dict, rf, out_dir: Path, reference: Path, backfilling: tuple | None = None) -> dict:
    """Write khosravi.json / khosravi.md and copy the figures into ``out_dir``.
    ``backfilling``: (result, run folder) of the free fill (backfilling.py) whose Fig. 9
    and backfilling.csv replace the held-layer run's."""
    out_dir.mkdir(parents=True, exist_ok=True)
    figdir = out_dir / "khosravi"
    figdir.mkdir(exist_ok=True)
    source = {name: rf.path for name in _FIGURES + ("backfilling.csv",)}
    if backfilling is not None:
        source["fig09_backfilling.png"] = source["backfilling.csv"] = backfilling[1].path
    figs = {}
    for name, folder in source.items():
        if (folder / name).exists():
            shutil.copy(folder / name, figdir / name)
            if name in _FIGURES:
                figs[name] = f"khosravi/{name}"
    ref = json.loads(reference.read_text())
    checks = assess(result, ref)
    manifest = _manifest(rf.path)
    report = {"result": result, "checks": checks, "figures": figs, "run_folder": str(rf.path),
              "manifest": {k: manifest.get(k) for k in _MANIFEST_KEYS},
              "reference": str(reference.name)}
    if backfilling is not None:
        bf_manifest = _manifest(backfilling[1].path)
        report["backfilling"] = {**backfilling[0], "run_folder": str(backfilling[1].path),
                                 "manifest": {k: bf_manifest.get(k) for k in _MANIFEST_KEYS}}
    old = out_dir / "khosravi.json"
    if old.is_file() and "other_heights" in (kept := json.loads(old.read_text())):
        report["other_heights"] = kept["other_heights"]        # runs of the paper's other walls stay
    return _write(report, out_dir, ref)


def _write(report: dict, out_dir: Path, ref: dict) -> dict:
    """khosravi.json and khosravi.md from ``report``, its scorecard computed first."""
    report["scorecard"] = scorecard(report, ref)
    pj = out_dir / "khosravi.json"
    atomic_write(pj, (json.dumps(to_plain(report), indent=2) + "\n").encode())
    pm = out_dir / "khosravi.md"
    text = _markdown(report["result"], report["checks"], report["figures"], report["manifest"], ref,
                     report.get("backfilling"), report["scorecard"]) + _other_heights_lines(report)
    discussion = out_dir / "khosravi_discussion.md"          # hand-written, kept across runs
    if discussion.is_file():
        text = text.rstrip("\n") + "\n\n" + discussion.read_text()
    atomic_write(pm, text.encode())
    report["paths"] = {"json": str(pj), "md": str(pm)}
    return report


def _other_heights_lines(report: dict) -> str:
    """The paper's other walls (``other_heights``), one row each, after the main report."""
    others = report.get("other_heights")
    if not others:
        return ""
    lines = ["", "## The paper's other wall heights", "",
             "Full size, the same recipe and seed; each from its own `wallsim validate khosravi --set H=...` run "
             "(`other_heights` in khosravi.json; Fig. 13 of each in `khosravi/fig13_profiles_H<H>.png`).", "",
             "| H [m] | disks | porosity | at-rest K upper half / Jaky | active thrust / Rankine | 90 % of the drop by "
             "Dis/H | theory / DEM thrust | CPU [min] | git |", "|---|---|---|---|---|---|---|---|---|"]
    for H, o in sorted(others.items(), key=lambda kv: float(kv[0])):
        d = o["dem"]
        ratios = ", ".join(f"{k} {v:.2f}" for k, v in o.get("theory_thrust_over_dem_active", {}).items())
        cpu = o.get("timings_s", {}).get("cpu_total")
        lines.append(f"| {H} | {o['particles']} | {o['porosity']:.3f} | {d['K_at_rest_upper_half_over_jaky']:.3f} | "
                     f"{d['active_thrust_over_rankine']:.3f} | {d['wall_disp_over_H_steady']:.4f} | {ratios} | "
                     + (f"{cpu / 60:.1f}" if cpu is not None else "-") + f" | {o.get('git')} |")
    return "\n".join(lines) + "\n"


#: the biaxial card whose test at the report's friction gave its phi (committed)
BIAXIAL_CARD = Path(__file__).parents[1] / "biaxial" / "cards" / "biaxial_full_it80.json"


def scorecard(report: dict, ref: dict) -> dict:
    """The report's scorecard (``studies.khosravi.scorecard``)."""
    from ..scorecard import scorecard_json
    from .scorecard import scorecard_rows
    card = json.loads(BIAXIAL_CARD.read_text()) if BIAXIAL_CARD.is_file() else None
    return scorecard_json(scorecard_rows(report, ref, card))


def rewrite(out_dir: Path, reference: Path) -> dict:
    """khosravi.json and khosravi.md written again from the report ``out_dir`` holds: the
    scorecard and the text of today's code on the same runs (nothing is run)."""
    return _write(read_report(out_dir, "khosravi.json"), out_dir, json.loads(Path(reference).read_text()))


def add_other_height(out_dir: Path, other: Path, reference: Path) -> dict:
    """Put the result of a validation at another wall height (``other``: its
    khosravi.json, written to a scratch --docs, or the run folder's result.json) into
    ``out_dir``/khosravi.json under ``other_heights[H]`` and rewrite the report."""
    report = json.loads((out_dir / "khosravi.json").read_text())
    data = json.loads(Path(other).read_text())
    res = data.get("result", data)
    keep = ("particles", "seed", "H_m", "porosity", "dem", "theory_thrust_over_dem_active", "timings_s", "friction")
    H = f"{round(res['H_m'], 2):g}"
    manifest = Path(other).with_name("manifest.json")
    git = json.loads(manifest.read_text()).get("git") if manifest.is_file() else data.get("manifest", {}).get("git")
    report.setdefault("other_heights", {})[H] = {k: res[k] for k in keep if k in res} | {"source": str(other),
                                                                                           "git": git}
    for stem in ("fig13_profiles", "fig11_corner_chains"):      # the paper's Figs. 13 and 11(b) at this height
        fig = Path(other).with_name(f"{stem}.png")
        if fig.is_file():
            name = f"{stem}_H{H}.png"
            shutil.copy(fig, out_dir / "khosravi" / name)
            report["figures"][name] = f"khosravi/{name}"
    return _write(report, out_dir, json.loads(Path(reference).read_text()))


def _backfilling_lines(bf: dict | None, main: dict) -> list[str]:
    """Where Fig. 9 comes from: the free fill's own run, or the held-layer run's cells."""
    if bf is None:
        return ["Fig. 9 is the held-layer fill's: cells beside grains held static are not read."]
    rev = (bf.get("manifest") or {}).get("git", "unknown")
    held = f"{bf.get('replaces_hold_depth_m', float('nan')) * 100:.3g} cm"
    t = bf.get("timings_s", {})
    return [f"Fig. 9 and `khosravi/backfilling.csv` come from a free fill of the same box (nothing held, "
            f"{bf['particles']} disks, porosity {bf['porosity']:.3f} against the held fill's {main['porosity']:.3f}, "
            f"seed {bf['seed']}, {bf['layers']} layers, "
            f"{bf['unread_cells_below_surface']} cells below the surface not read; pluviation "
            f"{t.get('pluviation_s', float('nan')) / 60:.1f} min, CPU {t.get('cpu_total', float('nan')) / 60:.1f} min; "
            f"git {rev}): the run above holds grains deeper than {held} below the surface static while the "
            f"next layers fall (fewer moving grains), so beside them the wall reads only the free strip along it. "
            f"A free fill settles denser, so Fig. 9 is of a slightly different deposit from the other figures. "
            f"Each layer is read over 0.2 reading windows as the next layer starts to fall, with the fill's "
            f"solver ({bf.get('sweeps', '?')} sweeps, dt {bf.get('layer_dt_s') or bf.get('run_dt_s', float('nan')):g} s; "
            f"the last reading after the switch to the run's {bf.get('run_dt_s', float('nan')):g} s), not the "
            f"{main.get('iterations_readings', '?')} sweeps of the at-rest reading: compare the profiles' shape "
            f"with Fig. 10, not their level (the intermediate ones read lower)."]


def _markdown(res: dict, checks: list[dict], figs: dict, manifest: dict, ref: dict,
              backfilling: dict | None = None, card: dict | None = None) -> str:
    from ..scorecard import scorecard_markdown
    d = res["dem"]
    t = res.get("timings_s", {})
    lines = [
        "# Khosravi et al. translation case on dem2d (pymunk)",
        "",
        "Generated by `wallsim validate khosravi` (studies/khosravi/report.py); numbers in `khosravi.json`.",
        "",
        *(scorecard_markdown(card, "Scorecard: every statement of the paper") if card else []),
        f"* particles: {res['particles']}, seed {res['seed']}, dt = {res['dt_s']:g} s, sweeps a step {_sweeps(res)}, "
        f"particle friction mu = {res['friction']:.4f} (wall = {res['wall_friction']:.4f}), pymunk {res['pymunk']}",
        f"* backfill: H = {res['H_m'] * 1e3:.1f} mm, gamma = {res['gamma_N_per_m3'] / 1e3:.2f} kN/m3, "
        f"porosity {res['porosity']:.3f} (interior {res['porosity_interior']:.3f}; paper 0.21)",
        f"* phi from the biaxial test on the same material: {d['phi_biaxial']:.2f} deg, used for Jaky and the "
        f"active theories" + (f" ({d['phi_biaxial_cs']:.2f} deg at critical state)" if d.get("phi_biaxial_cs") is not None else "")
        + f" ({res.get('phi_biaxial_source')})",
        f"* wall time: pluviation {t.get('pluviation_s', float('nan')) / 60:.1f} min"
        + (" (specimen reused from its checkpoint)" if res.get("specimen_reused") else "")
        + f", at rest {t.get('at_rest_s', float('nan')) / 60:.1f} min, translation "
          f"{t.get('translation_s', float('nan')) / 60:.1f} min, biaxial {t.get('biaxial_s', float('nan')) / 60:.1f} min, "
          f"total {t.get('total', float('nan')) / 60:.1f} min on {manifest.get('cpu_count', '?')} cores"
        + (f" (CPU time of the run {t['cpu_total'] / 60:.1f} min)" if "cpu_total" in t else ""),
        "",
        *checks_markdown(checks),
    ]
    lines += [
        "",
        "## Against the paper",
        "",
        f"* Paper (section 4): {ref['results']['at_rest']}.",
        f"* Paper: {ref['results']['active']}.",
        f"* Paper: {ref['results']['thrust']}. Here: theory thrust / DEM active thrust = "
        + ", ".join(f"{k} {v:.2f}" for k, v in res["theory_thrust_over_dem_active"].items()) + ".",
        f"* Paper: the pressure drops sharply to Dis/H = 0.0002-0.0005, then is steady. Here: 90 % of the drop "
        f"by Dis/H = {d['wall_disp_over_H_steady']:.5f}.",
        "",
        "Reading points (4 panels each; z = depth of their centre below the fill surface) as sigma_h / (gamma H):",
        "",
        f"| z/H | at rest | active (Dis/H = {_dis_active(res)}) |",
        "|---|---|---|",
    ]
    r = res["readings"]
    for zh, a, b in zip(r["depth_over_H"], r["at_rest_over_gammaH"], r["active_over_gammaH"]):
        lines.append(f"| {zh:.3f} | {a:.4f} | {b:.4f} |")
    lines += ["", "## Figures", "", *_backfilling_lines(backfilling, res), ""]
    for name, rel in figs.items():
        caption = next((c for stem, c in FIGURE_CAPTIONS.items() if name.startswith(stem)), None)
        lines += ([f"{caption} ({rel}):", ""] if caption else []) + [f"![{name}]({rel})"]
    lines += ["", "What an impulse solver means for these numbers: see docs/dem2d.md.", ""]
    return "\n".join(lines)


def figures(report: dict) -> list[dict]:
    """The validation targets as figures, for ``validate --seeds`` (studies/seeds.py):
    each the number ``assess`` judges, with the same window (reference.json "targets").
    Yes/no targets are 1 or 0 (their mean is the share of seeds where they hold); the
    steadiness is judged only when the run went to twice the target Dis/H, as in
    ``assess``."""
    from studies.seeds import figure
    result = report["result"]
    d, tg = result["dem"], json.loads(Path(__file__).with_name("reference.json").read_text())["targets"]
    rel = tg["K_at_rest_upper_half_vs_jaky_rel_tol"]
    end = result.get("wall_disp_over_H_end", result.get("wall_disp_over_H_active"))
    steady = tg["wall_disp_over_H_steady_at_most"]
    judged = end is not None and end >= 2 * steady
    return [
        figure("K_at_rest_upper_half_over_jaky", d["K_at_rest_upper_half_over_jaky"], reference=1.0,
               reference_name="Jaky", lo=1 - rel, hi=1 + rel, target=f"Jaky 1 - sin(phi_biaxial) +- {rel:.0%}"),
        figure("PS0_at_rest_over_lowest_reading", _ratio(d["PS0_at_rest_over_gammaH"],
                                                         d["lowest_reading_at_rest_over_gammaH"]), hi=1.0, target="< 1: PS0 below the lowest 4-panel reading (corner reduction)"),
        figure("active_below_at_rest_everywhere", float(bool(d["active_below_at_rest_everywhere"])), lo=1.0, hi=1.0,
               target="1 (yes) at every reading point"),
        figure("active_thrust_over_rankine", d["active_thrust_over_rankine"],
               hi=tg["active_thrust_over_rankine_below"], target="< 1 (paper: every theory overestimates)"),
        figure("wall_disp_over_H_steady", d["wall_disp_over_H_steady"], hi=steady if judged else None,
               target=f"<= {steady:g}" if judged else "not judged: the run ends before twice the target Dis/H"),
        figure("weight_balance", d["weight_balance"], reference=1.0, reference_name="weight",
               lo=1 - tg["weight_balance_abs_tol"], hi=1 + tg["weight_balance_abs_tol"],
               target=f"1 +- {tg['weight_balance_abs_tol']:g}"),
    ]


def _ratio(a: float | None, b: float | None) -> float | None:
    """a / b, None when either is missing (NaN is stored as null)."""
    return None if a is None or b is None else a / b
