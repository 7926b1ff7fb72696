"""``wallsim validate nadukuru``: every mode, both walls, at paper scale, written up.

Writes ``docs/validation/nadukuru.md``, ``nadukuru.json`` and figures: per wall one
settled specimen (cached) shared by the four modes, a half-speed repeat of translation
(rate check), and the triaxial calibration of the same mixture. Each figure is set
against Tables 1-2 with the validation targets (reference.json); a miss is reported with its figure,
never hidden.

Each DEM run (the triaxial test, each mode of each wall, the rate check) goes into a run
folder named by its resolved case, ``<root>/nadukuru/validate-<what>-<key>``
(``triaxial_run``, ``movement_run``): the same command run again after an interruption
reads the runs that finished, resumes the movement that was interrupted from its
checkpoint, and runs the others, to the same report. The key is of the settings, not the
code: after a change of the code, remove those folders to run them again.
"""

from __future__ import annotations

import dataclasses
import json
import math
import shutil
import time
from pathlib import Path

import numpy as np

import reproducibility

from analytic.constants import G

from ..granular.wall import MODE_TITLES, MODES, WallSetup
from ..measures import displacement_parallelism
from .case import REFERENCE, NadukuruCase, paper_values, rough_or_smooth
from .compare import theory_rows
from .scorecard import scorecard_rows
from ..scorecard import scorecard_json, scorecard_markdown
from ..granular.movement import run_modes
from ..granular.specimen import load_or_prepare
from ..config import with_current_names
from ..runfolder import package_versions, git_revision
from ..runner import finish, has_config, open_recording, open_run_folder, run_once
from ..store import atomic_write, content_key, load_npz, npz_bytes, read_report, to_plain

#: the validation targets (reference.json "targets"): K and h/H against Tables 1-2
TARGETS = json.loads((Path(__file__).with_name("reference.json")).read_text())["targets"]
TOL_K, TOL_H = TARGETS["K_abs_tol"], TARGETS["resultant_height_over_H_abs_tol"]


def _window(name: str) -> str:
    lo, hi = TARGETS[name]
    return f"{lo:g}-{hi:g}"


def validate_nadukuru(base: NadukuruCase, *, out_dir: Path = Path("docs/validation"), root: Path = Path("runs"),
                      walls=("rough", "smooth"), modes=MODES, rate_check: bool = True, triaxial: bool = True,
                      progress=None, log=print) -> dict:
    """Run ``modes`` for each wall kind in ``walls``, set them against the paper and write
    ``nadukuru.json``, ``nadukuru.md`` and (when every mode ran) the figures to
    ``out_dir``; specimens and calibration cards are cached under ``root``. Returns the report."""
    import viz.figures  # noqa: F401  (here, as before: a missing plotting stack fails before the runs)

    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    report = {"case": "nadukuru", "versions": package_versions(), "reproducibility": reproducibility.describe(),
              "git": git_revision(),
              "recipe": to_plain(base.specimen), "seed": base.seed, "walls": {}}
    phi, phi_src = _phi_for_theories(base, report, triaxial, root, progress, log)
    report["phi_for_theories"] = {"deg": phi, "source": phi_src}
    for wall_kind in walls:
        case = dataclasses.replace(base, wall=dataclasses.replace(base.wall, friction=rough_or_smooth(wall_kind)))
        entry, fields = _validate_wall(case, wall_kind, modes, phi, phi_src, rate_check, root, progress, log)
        report["walls"][wall_kind] = entry
        if set(modes) != set(MODES):    # a partial rerun: the figures need every mode, keep the old ones
            log(f"{wall_kind}: figures not redrawn (modes {','.join(modes)} only)")
            continue
        _draw_wall_figures(out_dir, wall_kind, entry)
        _copy_fields(out_dir, wall_kind, fields)
    report["wall_time_s"] = time.perf_counter() - t0
    return _write_report(report, out_dir)


def _phi_for_theories(base: NadukuruCase, report: dict, triaxial: bool, root: Path, progress, log) -> tuple:
    """(phi [deg], its source) for the theory rows: from a triaxial test run now
    (``triaxial``), else from a card of an earlier ``wallsim calibrate triaxial``, else
    the paper's. Adds the test's figures to ``report["triaxial"]`` when there are any."""
    if triaxial:
        card = triaxial_run(base, root, progress, log)
        report["triaxial"] = {k: card[k] for k in ("phi_peak_deg", "strain_at_peak", "phi_end_deg", "porosity",
                                                    "particles", "wall_time_s")}
        log(f"triaxial: phi peak {card['phi_peak_deg']:.1f} deg")
        return report["triaxial"]["phi_peak_deg"], "triaxial"
    from .compare import phi_card
    from ..triaxial.lab import card_path
    phi, phi_src = phi_card(root, base)
    card = card_path(root, base.specimen, base.seed)
    if card.exists():
        c = json.loads(card.read_text())
        report["triaxial"] = {k: c[k] for k in ("phi_peak_deg", "strain_at_peak", "phi_end_deg", "porosity",
                                                "particles", "wall_time_s")} | {"card": card.name}
    return phi, phi_src


#: the triaxial test of the validation: the paper's 8,200 spheres
TRIAXIAL_PARTICLES = 8200


def triaxial_run(base: NadukuruCase, root: Path, progress=None, log=print) -> dict:
    """The calibration card of the triaxial test of ``base``'s recipe and seed
    (``calibrate_triaxial``, which also writes it where ``compare`` finds it), as the run
    folder ``<root>/nadukuru/validate-triaxial-<key>`` keeps it in result.json: read when
    that holds a finished test, else run (a folder without result.json removed first)."""
    from ..elements.triaxial import TriaxialSetup
    from ..triaxial.lab import calibrate_triaxial
    setup = TriaxialSetup()
    what = {"specimen": base.specimen, "seed": base.seed, "triaxial": setup, "particles": TRIAXIAL_PARTICLES}
    folder = Path(root) / "nadukuru" / f"validate-triaxial-{content_key(what)}"

    def run(_: None) -> None:
        rf = open_run_folder("nadukuru", what, root, name=folder.name, seed=base.seed)
        card, path = calibrate_triaxial(base, setup, particles=TRIAXIAL_PARTICLES, root=root, progress=progress)
        finish(rf, dict(card) | {"card": str(path)}, main=False)

    return run_once(folder, run, log=log)


def movement_run(case: NadukuruCase, spec, what: str, root: Path, *, frame_every: int = 0, fields: str | None = None,
                 progress=None, log=print) -> tuple[dict, dict, Path]:
    """One wall movement of the validation (``run_modes`` on ``case`` from the settled
    ``spec``) in the run folder ``<root>/nadukuru/validate-<what>-<key>`` (key: the hash
    of the resolved case, so a changed setting never reads a stale run): read when it
    holds a finished run, resumed from its checkpoint when it holds an interrupted one,
    else run there. Returns (result.json, history.npz: the load history and the active
    figures exactly as ``run_modes`` gave them, the folder). ``fields``: the wall's word,
    to draw the force chains at the end (force_chains.png) and the displacements over the
    movement (displacements.png) in the folder, and to measure how parallel those
    displacements are (result.json ``displacement_field``)."""
    folder = Path(root) / "nadukuru" / f"validate-{what}-{content_key(case)}"

    def run(resume: Path | None) -> None:
        _move(case, spec, open_run_folder("nadukuru", case, root, name=folder.name, resume=resume), frame_every,
              fields, progress)

    return run_once(folder, run, resumable=has_config, log=log), load_npz(folder / "history.npz"), folder


#: the modes whose displacement field is drawn and measured: the paper draws RT's
#: (Fig. 3a) and describes T's and RB's ("all displacement vectors tend to be parallel")
FIELD_MODES = ("T", "RB", "RT")
#: the history arrays and active figures of a movement that its run folder keeps (history.npz)
_HISTORY = ("wall_disp_over_H", "K", "resultant_height_over_H", "segment_stress_active", "K_active",
            "resultant_height_over_H_active", "wall_disp_over_H_steady")


def _move(case: NadukuruCase, spec, rf, frame_every: int, fields: str | None, progress) -> None:
    """Move the wall in run folder ``rf`` (checkpoints/movement.npz, resumed from when
    there), then write history.npz, the figures of ``fields`` and result.json (last)."""
    first = rf.path / "first_positions.npz"         # kept, so a resumed run draws the whole movement
    last = {}
    # --vtk: the frames of a compare run at its default cadence, written as VTK only
    from .compare import compare_frame_every
    rec = open_recording(None, study="nadukuru", dim=3, recording_id=rf.path.name, folder=rf)
    if rec.enabled:
        frame_every = min(f for f in (frame_every, compare_frame_every(case)) if f)

    def on_frame(frame, sample):
        if fields and not first.is_file():
            atomic_write(first, npz_bytes({"positions": frame.positions}))
        last["frame"] = frame
        rec.log_frame(frame, wall_disp_over_H=sample.wall_disp_over_H)

    tm = time.perf_counter()
    hist = run_modes(case, spec, frame_every=frame_every, progress=progress, on_frame=on_frame,
                     checkpoint_path=rf.file("checkpoints/movement.npz"), on_checkpoint=rf.checkpointed)
    seconds = time.perf_counter() - tm
    rec.close()
    atomic_write(rf.path / "history.npz", npz_bytes({k: np.asarray(hist[k]) for k in _HISTORY}
                                                    | {"segment_stress_first": np.asarray(hist["segment_stress"][0])}))
    field = None
    if fields and "frame" in last:
        start = load_npz(first)["positions"]
        _draw_fields(rf.path, fields, case.movement.mode, start, last["frame"])
        field = displacement_parallelism(start, last["frame"].positions)
    (rf.path / "checkpoints" / "movement.npz").unlink(missing_ok=True)        # finished: nothing to resume
    if (rf.path / "checkpoints").is_dir() and not any((rf.path / "checkpoints").iterdir()):
        (rf.path / "checkpoints").rmdir()
    result = {"mode": case.movement.mode, "speed_m_per_s": case.movement.speed, "K_active": hist["K_active"],
              "resultant_height_over_H_active": hist["resultant_height_over_H_active"],
              "wall_disp_over_H_steady": hist["wall_disp_over_H_steady"], "wall_time_s": seconds,
              "particles": spec.n_spheres, "seed": case.seed}
    if field is not None:
        result["displacement_field"] = field
    finish(rf, result, main=False, particles=spec.n_spheres, dt=spec.dt)


def _draw_fields(folder: Path, wall_kind: str, mode: str, start: np.ndarray, frame) -> None:
    """The force chains at the end of a movement and its Fig. 3(a) displacement field
    from ``start`` (positions of the first frame) to ``frame`` (the paper draws it for
    rotation about the top and describes it for translation and rotation about the
    base)."""
    from viz.figures import plot_displacement_field, plot_force_chains
    what = MODE_TITLES[mode]
    plot_force_chains(frame, folder / "force_chains.png",
                      title=f"{what.capitalize()}, {wall_kind} wall: force chains at the end")
    plot_displacement_field(start, frame.positions, folder / "displacements.png",
                            title=f"Fig. 3(a): {what}, {wall_kind} wall,\n"
                                  "displacements x15 at the end of the movement")


def _validate_wall(case: NadukuruCase, wall_kind: str, modes, phi: float, phi_src: str, rate_check: bool,
                   root: Path, progress, log) -> tuple[dict, dict]:
    """One wall kind: its settled specimen (cached under ``root``), each mode against the
    paper and, with ``rate_check``, translation at half speed. Returns (the report entry,
    each mode's row with the data of its Figs. 4 and 5 (``figure_data``); the run folders
    of the modes with displacement fields, FIELD_MODES, by mode)."""
    tp = time.perf_counter()
    spec, cached = load_or_prepare(case, root / "nadukuru" / "specimens", progress)
    entry = {"specimen": {"particles": spec.n_spheres, "bodies": spec.n_bodies, "porosity": spec.porosity,
                          "K_at_rest": spec.K_at_rest, "resultant_height_over_H_at_rest": spec.resultant_height_over_H_at_rest,
                          "thrust_at_rest_kN_per_0.5m": spec.thrust_at_rest_kN * 0.5 / spec.width,
                          "stress_ratio": spec.stress_ratio, "dt_s": spec.dt, "seed": case.seed,
                          "wall_time_s": None if cached else time.perf_counter() - tp, "cached": cached},
             "modes": {}}
    log(f"{wall_kind}: specimen n {spec.porosity:.3f}, K0 {spec.K_at_rest:.3f}")
    fields = {}
    gamma = case.specimen.density * (1 - spec.porosity) * G
    for mode in modes:
        row, hist, folder = _validate_mode(case, spec, mode, wall_kind, phi, phi_src, gamma, root, progress, log)
        row["figure_data"] = figure_data(hist, gamma * case.wall.height, case.movement.wall_disp_over_H)
        entry["modes"][mode] = row
        if mode in FIELD_MODES and (folder / "displacements.png").is_file():
            fields[mode] = folder
        paper = row["paper"]
        log(f"{wall_kind} {mode}: K {row['K']:.3f} (paper {paper['K']}), h/H {row['resultant_height_over_H']:.3f} "
            f"(paper {paper['resultant_height_over_H']}), {row['wall_time_s']:.0f} s")
    if rate_check and "T" in modes:
        entry["rate_check"] = _rate_check(case, spec, entry["modes"]["T"]["K"], wall_kind, root, progress, log)
        log(f"{wall_kind} T at half speed: K {entry['rate_check']['K']:.3f}")
    return entry, fields


#: points kept of each K curve in the report (enough to draw Fig. 4 at its size)
CURVE_POINTS = 200


def figure_data(hist: dict, gamma_H: float, wall_disp_over_H: float) -> dict:
    """What Figs. 4 and 5 draw of one movement, kept in the report so the figures can be
    drawn again without the runs (``rewrite``): the K curve at up to CURVE_POINTS evenly
    spaced readings (first and last kept), the active segment stresses over gamma H
    [-] from the top segment down, and the movement they are read at; the segment
    stresses of the first reading (the at-rest state, averaged over the movement's
    first ``record_every`` steps) likewise, with its Delta/H (a history written before
    they were kept has neither)."""
    x, k = np.asarray(hist["wall_disp_over_H"]), np.asarray(hist["K"])
    keep = np.unique(np.linspace(0, len(x) - 1, min(len(x), CURVE_POINTS)).round().astype(int))
    data = {"wall_disp_over_H": x[keep].tolist(), "K": k[keep].tolist(),
            "segment_stress_over_gamma_H": (np.asarray(hist["segment_stress_active"])[::-1] / gamma_H).tolist(),
            "segments_read_at_wall_disp_over_H": wall_disp_over_H}
    if "segment_stress_first" in hist:
        data["first_segment_stress_over_gamma_H"] = (np.asarray(hist["segment_stress_first"])[::-1] / gamma_H).tolist()
        data["first_reading_wall_disp_over_H"] = float(x[0])
    return data


def _validate_mode(case: NadukuruCase, spec, mode: str, wall_kind: str, phi: float, phi_src: str, gamma: float,
                   root: Path, progress, log) -> tuple[dict, dict, Path]:
    """One mode from the settled specimen (``movement_run``): its report row (active K and
    resultant height against the paper within TOL_K, TOL_H; the theories at ``phi`` [deg]
    and the unit weight ``gamma`` [N/m^3]; for FIELD_MODES how parallel the displacements
    are), the load history, and its run folder (for FIELD_MODES with the force chains and
    displacements)."""
    c = dataclasses.replace(case, movement=dataclasses.replace(case.movement, mode=mode))
    res, hist, folder = movement_run(c, spec, f"{wall_kind}-{mode}", root,
                                     frame_every=10**9 if mode != "RT" else 10**5,
                                     fields=wall_kind if mode in FIELD_MODES else None, progress=progress, log=log)
    paper = paper_values(mode, wall_kind)
    row = {"K": float(hist["K_active"]), "resultant_height_over_H": float(hist["resultant_height_over_H_active"]),
           "wall_disp_over_H_steady": float(hist["wall_disp_over_H_steady"]), "wall_time_s": res["wall_time_s"],
           "particles": spec.n_spheres, "seed": case.seed, "paper": paper,
           "theory": theory_rows(mode, phi, case.wall.friction, gamma, case.wall.height,
                                 phi_src)}
    if "displacement_field" in res:
        row["displacement_field"] = res["displacement_field"]
    if paper["K"] is not None:
        row["K_within_tol"] = abs(row["K"] - paper["K"]) <= TOL_K
        row["height_within_tol"] = abs(row["resultant_height_over_H"] - paper["resultant_height_over_H"]) <= TOL_H
    return row, hist, folder


def _rate_check(case: NadukuruCase, spec, K_translation: float, wall_kind: str, root: Path, progress, log) -> dict:
    """Translation again at half the wall speed (``movement_run``): the active K and its
    change from the full-speed K (the target is < 0.01, i.e. the movement is quasi-static)."""
    c = dataclasses.replace(case, movement=dataclasses.replace(case.movement, mode="T",
                                                               speed=0.5 * case.movement.speed))
    res, hist, _ = movement_run(c, spec, f"{wall_kind}-T-half-speed", root, progress=progress, log=log)
    K = float(hist["K_active"])
    return {"speed_m_per_s": c.movement.speed, "K": K, "dK": K - K_translation, "wall_time_s": res["wall_time_s"]}


def _draw_wall_figures(out_dir: Path, wall_kind: str, entry: dict) -> None:
    """Figs. 4 and 5 of the paper for one wall (K vs Delta/H, segment stresses) from its
    report entry's ``figure_data``; nothing is drawn when a mode lacks it (a report
    written before it was kept: its committed figures stay)."""
    from .figures import plot_load_history, plot_segment_stress

    modes = entry["modes"]
    if not all("figure_data" in r for r in modes.values()):
        return
    data = {m: r["figure_data"] for m, r in modes.items()}
    curves = {m: (d["wall_disp_over_H"], d["K"]) for m, d in data.items()}
    paper_K = {m: paper_values(m, wall_kind)["K"] for m in modes if paper_values(m, wall_kind)["K"]}
    spec = entry["specimen"]
    plot_load_history(curves, out_dir / f"nadukuru_fig4_{wall_kind}.png", paper=paper_K, at_rest=spec["K_at_rest"],
                      title=f"K vs wall movement, {wall_kind} wall ({spec['particles']} spheres)")
    segs = {m: d["segment_stress_over_gamma_H"] for m, d in data.items()}
    edges = np.linspace(0, 1, len(next(iter(segs.values()))) + 1)
    at = next(iter(data.values()))["segments_read_at_wall_disp_over_H"]
    plot_segment_stress(segs, edges, out_dir / f"nadukuru_fig5_{wall_kind}.png",
                        title=f"Segment stress at Delta/H = {at:g}, {wall_kind} wall")


def _copy_fields(out_dir: Path, wall_kind: str, fields: dict) -> None:
    """The Fig. 3(a) displacement field of each mode in ``fields`` (mode -> run folder)
    and the force chains of RT, from the run folders into ``out_dir``."""
    for mode, folder in fields.items():
        shutil.copyfile(folder / "displacements.png", out_dir / f"nadukuru_fig3a_{mode}_{wall_kind}.png")
        if mode == "RT":
            shutil.copyfile(folder / "force_chains.png", out_dir / f"nadukuru_chains_RT_{wall_kind}.png")


def _write_report(report: dict, out_dir: Path) -> dict:
    """Merge with the previous ``nadukuru.json`` (``_keep_other_walls``), write it and
    ``nadukuru.md`` (``_write``). Returns the merged report."""
    return _write(_keep_other_walls(report, out_dir / "nadukuru.json"), out_dir)


def rewrite(out_dir: Path) -> dict:
    """``nadukuru.json`` and ``nadukuru.md`` in ``out_dir`` written again from the report
    there, nothing run: today's scorecard and text, and Figs. 4 and 5 of each wall whose
    report keeps their data (``figure_data``)."""
    report = with_current_names(read_report(out_dir, "nadukuru.json"))
    for wall_kind, entry in report["walls"].items():
        _draw_wall_figures(out_dir, wall_kind, entry)
    return _write(report, out_dir)


def _write(report: dict, out_dir: Path) -> dict:
    """The scorecard of ``report``, then ``nadukuru.json`` and ``nadukuru.md`` (with the
    hand-written discussion, if any) in ``out_dir``."""
    report["scorecard"] = scorecard(report, out_dir)
    atomic_write(out_dir / "nadukuru.json", (json.dumps(to_plain(report), indent=1) + "\n").encode())
    notes = out_dir / "nadukuru_discussion.md"
    atomic_write(out_dir / "nadukuru.md", markdown(report, notes.read_text() if notes.exists() else None,
                                                   out_dir).encode())
    return report


#: supporting files of the report that statements of the scorecard read (``kind`` spread)
SUPPORTING = ("nadukuru_rt_checks.json", "nadukuru_fields_reduced.json", "nadukuru_profiles_reduced.json")


def _reduced_runs(reports: dict, pick) -> tuple[dict, list, str]:
    """From reduced-size validation reports (seed -> the path of its nadukuru.json):
    ``pick(entry)`` of each wall entry per seed, the particle counts and the gits."""
    runs, particles, gits = {}, set(), set()
    for seed, path in sorted(reports.items()):
        rep = with_current_names(json.loads(Path(path).read_text()))
        gits.add(rep["git"])
        runs[str(seed)] = {w: pick(e) for w, e in rep["walls"].items()}
        particles |= {e["specimen"]["particles"] for e in rep["walls"].values()}
    return runs, sorted(particles), ", ".join(sorted(gits))


def fields_check(reports: dict, command: str) -> dict:
    """The supporting file ``nadukuru_fields_reduced.json`` from reduced-size validation
    reports (seed -> the path of its nadukuru.json): each seed's displacement-field
    measure per wall and mode (``displacement_parallelism``), which the scorecard's
    Fig. 3 row reads while the paper-scale report has none."""
    runs, particles, git = _reduced_runs(reports, lambda e: {m: r["displacement_field"] for m, r in e["modes"].items()
                                                             if "displacement_field" in r})
    return {"what": "Fig. 3's text at reduced size: how parallel the displacements of T, RB and RT are "
                    "(studies.measures.displacement_parallelism), per seed, wall and mode",
            "command": command, "particles": particles, "git": git, "runs": runs}


#: the profile data of a mode that ``profiles_check`` keeps
_PROFILE_KEYS = ("first_segment_stress_over_gamma_H", "first_reading_wall_disp_over_H", "segment_stress_over_gamma_H",
                 "segments_read_at_wall_disp_over_H")


def profiles_check(reports: dict, command: str) -> dict:
    """The supporting file ``nadukuru_profiles_reduced.json`` from reduced-size
    validation reports (as ``fields_check``): per seed, wall and mode the segment
    stresses of the first reading (at rest) and of the active state, which the
    scorecard's linearity row reads while the paper-scale report has none."""
    runs, particles, git = _reduced_runs(reports, lambda e: {"modes": {
        m: {"figure_data": {k: r["figure_data"][k] for k in _PROFILE_KEYS}} for m, r in e["modes"].items()}})
    return {"what": "the wall's stress profiles at reduced size: the segment stresses / gamma H (top down) of "
                    "the first reading (at rest) and of the active state, per seed, wall and mode",
            "command": command, "particles": particles, "git": git, "runs": runs}


def scorecard(report: dict, out_dir: Path) -> dict:
    """The scorecard of ``report`` (``studies.nadukuru.scorecard``), with the supporting
    files found in ``out_dir``."""
    supporting = {name: json.loads((out_dir / name).read_text()) for name in SUPPORTING
                  if (out_dir / name).is_file()}
    return scorecard_json(scorecard_rows(report, REFERENCE, supporting))


def _keep_other_walls(report: dict, previous: Path) -> dict:
    """A validation may run one wall, or some modes, per invocation (a wall takes an hour
    at paper scale): walls, modes and rate checks in an earlier report that this run did
    not redo are kept, each with the git revision that produced it."""
    for entry in report["walls"].values():
        entry["git"] = report["git"]
        for row in entry["modes"].values():
            row["git"] = report["git"]
        if "rate_check" in entry:
            entry["rate_check"]["git"] = report["git"]
    if not previous.exists():
        return report
    old = with_current_names(json.loads(previous.read_text()))
    kept_any = False
    for wall, old_entry in old.get("walls", {}).items():
        old_git = old_entry.get("git", old.get("git"))
        if wall not in report["walls"]:
            old_entry.setdefault("git", old_git)
            report["walls"][wall] = old_entry
            kept_any = True
            continue
        entry = report["walls"][wall]
        kept = {m: row | {"git": row.get("git", old_git)} for m, row in old_entry.get("modes", {}).items()
                if m not in entry["modes"]}
        kept_any = kept_any or bool(kept)
        merged = entry["modes"] | kept
        entry["modes"] = {m: merged[m] for m in MODES if m in merged}      # in the table's order
        if "rate_check" not in entry and "rate_check" in old_entry:
            entry["rate_check"] = old_entry["rate_check"] | {"git": old_entry["rate_check"].get("git", old_git)}
            kept_any = True
    if "triaxial" not in report and "triaxial" in old:
        report["triaxial"] = old["triaxial"]
    if kept_any:        # the time of the runs kept is part of the report's cost
        report["wall_time_s"] += old.get("wall_time_s", 0.0)
    return report


def markdown(rep: dict, discussion: str | None = None, figures_dir: Path | None = None) -> str:
    """The report; ``discussion`` (hand-written, docs/validation/nadukuru_discussion.md)
    is appended so the reasons for a miss sit next to the generated numbers. Optional
    figures are linked when they exist in ``figures_dir``."""
    rep = with_current_names(rep)       # a report written before the glossary reads too
    L = _markdown_head(rep)
    if "scorecard" in rep:
        L[4:4] = scorecard_markdown(rep["scorecard"], "Scorecard: every statement of the paper")
    for wall, e in rep["walls"].items():
        L += _markdown_wall(wall, e, rep["git"], figures_dir)
    if discussion:
        L += ["## Discussion", "", discussion.strip(), ""]
    return "\n".join(L) + "\n"


def _time_text(rep: dict) -> str:
    """The wall time of the runs the report reads, each as its own run recorded it (a
    report assembled from finished runs took seconds itself, so its own time says
    nothing of what the figures cost)."""
    walls = rep["walls"].values()
    modes = sum(r.get("wall_time_s") or 0.0 for w in walls for r in w["modes"].values())
    rate = sum((w.get("rate_check") or {}).get("wall_time_s") or 0.0 for w in walls)
    prep = [w["specimen"].get("wall_time_s") for w in walls]
    tri = (rep.get("triaxial") or {}).get("wall_time_s")
    parts = [f"wall movements {modes / 60:.1f} min", f"half-speed checks {rate / 60:.1f} min"]
    if tri:
        parts.append(f"triaxial test {tri / 60:.1f} min")
    parts.append("specimen preparation " + (f"{sum(prep) / 60:.1f} min" if all(prep) else "not timed here (cached)"))
    return "wall time of the runs read, each as its run recorded it: " + ", ".join(parts) + "."


def _markdown_head(rep: dict) -> list[str]:
    """Title, provenance, tolerances, phi for the theories (with the reach of Rankine's
    wedge [m]) and the triaxial calibration, as Markdown lines."""
    L = ["# Validation: Nadukuru & Michalowski (2012), 3D DEM wall modes", "",
         f"Generated by `wallsim validate nadukuru` (git {rep['git']}, wallsim {rep['versions'].get('wallsim')}, "
         f"numba {rep['versions'].get('numba')}); {_time_text(rep)}",
         "", f"Tolerances (the validation targets): K within +-{TOL_K}, resultant height within +-{TOL_H} H of the "
         "paper's Tables 1-2.", ""]
    ph = rep.get("phi_for_theories")
    if ph:
        wall = WallSetup()
        wedge = wall.height * math.tan(math.radians(45.0 - 0.5 * ph["deg"]))
        L += [f"phi for the theories: {ph['deg']:.1f} deg ({ph['source']}). Rankine's wedge from the wall base "
              f"reaches {wedge:.2f} m behind the wall at the surface, inside the {wall.backfill_length:g} m "
              "backfill.", ""]
    if "triaxial" in rep:
        t = rep["triaxial"]
        L += ["## Triaxial calibration", "",
              f"Peak phi **{t['phi_peak_deg']:.1f} deg** at axial strain {t['strain_at_peak']:.3f}; end of test "
              f"{t['phi_end_deg']:.1f} deg; porosity {t['porosity']:.3f}; {t['particles']} spheres; "
              f"{t['wall_time_s']:.0f} s. Paper: 39 deg (target window {_window('triaxial_phi_deg_window')}).", ""]
    return L


def _markdown_wall(wall: str, e: dict, git: str, figures_dir: Path | None) -> list[str]:
    """One wall's section: specimen, the mode table against the paper, the RB < T < RT
    order of resultant heights, the rate check, the theories and the figure links.
    ``git`` is the report's revision, shown where a row or the wall has none of its own."""
    s = e["specimen"]
    L = [f"## {wall.capitalize()} wall", "",
         f"Specimen: {s['particles']} spheres ({s['bodies']} bodies), seed {s['seed']}, dt {s['dt_s']:.2e} s, "
         f"porosity **{s['porosity']:.3f}** (paper ~0.35), at-rest K **{s['K_at_rest']:.3f}** (paper 0.385; "
         f"target window {_window('K_at_rest_window')}), resultant at {s['resultant_height_over_H_at_rest']:.3f} H "
         f"(paper 0.323), at-rest load {s['thrust_at_rest_kN_per_0.5m']:.1f} kN per 0.5 m (paper ~15.4)"
         + (f", prepared in {s['wall_time_s'] / 60:.1f} min." if s.get("wall_time_s") else " (cached)."), "",
         "| mode | DEM K | paper K | DEM h/H | paper h/H | within tol. | steady by Delta/H | wall time | git |",
         "|---|---|---|---|---|---|---|---|---|"]
    L += [_mode_table_row(m, r, e.get("git", git)) for m, r in e["modes"].items()]
    order = [e["modes"][m]["resultant_height_over_H"] for m in ("RB", "T", "RT") if m in e["modes"]]
    if len(order) == 3:
        L += ["", f"Resultant heights RB < T < RT: **{'yes' if order[0] < order[1] < order[2] else 'NO'}** "
                  f"({order[0]:.3f}, {order[1]:.3f}, {order[2]:.3f})."]
    if "rate_check" in e:
        rc = e["rate_check"]
        L += [f"Half wall speed ({rc['speed_m_per_s']} m/s): K {rc['K']:.3f}, change {rc['dK']:+.3f} "
              f"(target: < {TARGETS['rate_check_dK_below']:g}); git {rc.get('git', e.get('git', git))}."]
    L.append("")
    th = {m: {t["name"]: t for t in r.get("theory", [])} for m, r in e["modes"].items()}
    for m, rows in th.items():
        got = [f"{name} {t['K']:.3f} / {t['resultant_height_over_H']:.3f}" for name, t in rows.items()
               if t.get("K") is not None and t.get("resultant_height_over_H") is not None]
        if got:
            L.append(f"- {m}, theory K / h/H: " + "; ".join(got))
    L += ["", f"![K vs movement](nadukuru_fig4_{wall}.png) ![segments](nadukuru_fig5_{wall}.png)", ""]
    if "RT" in e["modes"]:
        L += [f"![force chains, RT](nadukuru_chains_RT_{wall}.png)", ""]
    drawn = [m for m in FIELD_MODES if m in e["modes"] and figures_dir is not None
             and (figures_dir / f"nadukuru_fig3a_{m}_{wall}.png").exists()]
    if drawn:
        L += [" ".join(f"![displacements, {m}](nadukuru_fig3a_{m}_{wall}.png)" for m in drawn), ""]
    measured = {m: e["modes"][m]["displacement_field"] for m in FIELD_MODES
                if "displacement_field" in e["modes"].get(m, {})}
    if measured:
        L += ["Displacement field at the end of the movement (grains moving at least a quarter of the 99th "
              "percentile; R = 1: all parallel; spread: the circular standard deviation of their directions): "
              + "; ".join(f"{m} R {d['resultant_length']:.3f} (spread {d['spread_deg']:.0f} deg), mean "
                          f"{d['inclination_deg']:.0f} deg below the horizontal, {d['moving_grains']} grains"
                          for m, d in measured.items()) + ".", ""]
    return L


def _mode_table_row(m: str, r: dict, git: str) -> str:
    """One row of the mode table; ``git`` is shown when the row has no revision of its own."""
    p = r["paper"]
    ok = ("no paper value" if p.get("K") is None else
          "yes" if r.get("K_within_tol") and r.get("height_within_tol") else
          "K " + ("ok" if r.get("K_within_tol") else "MISS") + ", h " + ("ok" if r.get("height_within_tol") else "MISS"))
    return (f"| {m} | {r['K']:.3f} | {p['K']} | {r['resultant_height_over_H']:.3f} | "
            f"{p['resultant_height_over_H']} | {ok} | {r['wall_disp_over_H_steady']:.4f} | {r['wall_time_s'] / 60:.1f} min | "
            f"{r.get('git', git)} |")


def figures(report: dict) -> list[dict]:
    """The report's figures against the paper and the validation targets, for ``validate
    --seeds`` (studies/seeds.py): the triaxial peak phi, and per wall the at-rest K, each
    mode's K and resultant height (paper +- TOL_K, TOL_H; no window where the paper has
    no value) and the half-speed change of K."""
    from ..seeds import figure
    spec = json.loads((Path(__file__).with_name("reference.json")).read_text())["specimen"]
    out = []
    if "triaxial" in report:
        lo, hi = TARGETS["triaxial_phi_deg_window"]
        out.append(figure("triaxial.phi_peak_deg", report["triaxial"]["phi_peak_deg"], reference=spec["triaxial_phi_deg"],
                          lo=lo, hi=hi, target=f"{_window('triaxial_phi_deg_window')} deg"))
    for wall, e in report["walls"].items():
        lo, hi = TARGETS["K_at_rest_window"]
        out.append(figure(f"{wall}.K_at_rest", e["specimen"]["K_at_rest"], reference=spec["at_rest_K"], lo=lo, hi=hi,
                          target=_window("K_at_rest_window")))
        for mode, row in e["modes"].items():
            for key, tol in (("K", TOL_K), ("resultant_height_over_H", TOL_H)):
                ref = row["paper"][key]
                out.append(figure(f"{wall}.{mode}.{key}", row[key], reference=ref,
                                  lo=None if ref is None else ref - tol, hi=None if ref is None else ref + tol,
                                  target="no paper value" if ref is None else f"paper {ref} +- {tol}"))
        if "rate_check" in e:
            below = TARGETS["rate_check_dK_below"]
            out.append(figure(f"{wall}.rate_check.dK", e["rate_check"]["dK"], reference=None, lo=-below, hi=below,
                              target=f"abs(dK) < {below:g}"))
    return out
