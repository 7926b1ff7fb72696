"""``wallsim validate heap``: the heap at paper scale for seeds 1..N, one after the
other, and the report docs/validation/heap.{md,json} with heap_base_stress.png.

Each seed runs in a run folder named by its resolved case, ``<root>/heap/validate-seed<S>-<key>``
(``seed_run``): the same command run again after an interruption reads the seeds that
finished from their result.json and runs only the others, to the same report. The key
is of the settings, not the code: after a change of the code, remove those folders to
run the seeds again."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

import reproducibility

from ..runfolder import git_revision, package_versions
from ..runner import has_config, named_run, run_once
from ..store import content_key, read_report
from .compare import ASSUMPTIONS, compare_heap, slope_text
from .case import HeapCase

KEYS = ("centre_over_peak_before", "centre_over_peak_after", "slope_deg", "heap_height_m", "porosity",
        "base_load_over_heap_weight", "subsidence_over_H")


def validate_heap(case: HeapCase, *, seeds: tuple[int, ...] = (1, 2, 3), out_dir: Path = Path("docs/validation"),
                  root: Path = Path("runs"), progress=None, log=print) -> dict:
    """Run the heap for each of ``seeds`` (a seed that finished before is read: ``seed_run``)
    and write the report; returns its JSON record."""
    runs = []
    for k, seed in enumerate(seeds):
        log(f"heap: seed {seed} ({k + 1} of {len(seeds)})")
        res = seed_run(dataclasses.replace(case, seed=seed), root=root, record=k == 0, progress=progress, log=log)
        runs.append(res)
        log(f"heap: seed {seed}: centre/peak {res['centre_over_peak_before']:.3f} -> "
            f"{res['centre_over_peak_after']:.3f}, {slope_text(res['slope_deg'], short=True)}, {res['wall_time_s']:.0f} s")
    return write_report(case, runs, out_dir)


def run_name(case: HeapCase) -> str:
    """The run folder of one seed of the validation: its seed and the hash of the whole
    resolved case, so a changed setting never reads a stale run."""
    return f"validate-seed{case.seed}-{content_key(case)}"


def seed_run(case: HeapCase, *, root: Path, record: bool = False, progress=None, log=print) -> dict:
    """The result of ``compare_heap`` on ``case`` as its run folder's result.json holds it
    (the report reads the same numbers whether the run is new or not): read from
    ``<root>/heap/<run_name>`` when that holds a finished run, else run there; an
    interrupted run continues from its checkpoint, a folder without one is removed first
    and the seed run afresh."""
    folder = Path(root) / "heap" / run_name(case)

    def run(resume: Path | None) -> None:
        if resume is not None:
            compare_heap(case, root=root, record=record, progress=progress, resume=resume)
            return
        with named_run(folder.name):
            compare_heap(case, root=root, record=record, progress=progress)

    return run_once(folder, run, resumable=_resumable, log=log)


def _resumable(folder: Path) -> bool:
    """An interrupted heap run goes on from its checkpoint (config.toml and heap.npz)."""
    return has_config(folder) and (folder / "checkpoints" / "heap.npz").is_file()


def write_report(case: HeapCase, runs: list[dict], out_dir: Path) -> dict:
    """heap.json, heap_base_stress.png and heap.md (with heap_discussion.md, if there)
    from the runs' result dicts (``compare_heap``, or their result.json files)."""
    rep = report_json(case, runs)
    rep["scorecard"] = scorecard(rep)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "heap.json").write_text(json.dumps(rep, indent=2) + "\n")
    _figure(runs, out_dir / "heap_base_stress.png")
    (out_dir / "heap.md").write_text(report_markdown(rep, out_dir / "heap_discussion.md"))
    return rep


def rewrite(out_dir: Path) -> dict:
    """heap.json and heap.md in ``out_dir`` written again from the report there, nothing
    run: today's scorecard and text (heap_base_stress.png needs the runs and is kept)."""
    rep = read_report(out_dir, "heap.json")
    rep["scorecard"] = scorecard(rep)
    (out_dir / "heap.json").write_text(json.dumps(rep, indent=2) + "\n")
    (out_dir / "heap.md").write_text(report_markdown(rep, out_dir / "heap_discussion.md"))
    return rep


def _stats(values) -> dict:
    v = np.asarray(values, float)
    return {"mean": float(v.mean()), "sd": float(v.std(ddof=1)) if len(v) > 1 else 0.0,
            "per_seed": [float(x) for x in v]}


def report_json(case: HeapCase, runs: list[dict]) -> dict:
    rep = {k: _stats([r[k] for r in runs]) for k in KEYS}
    # every seed rains exactly case.particles spheres (random_specimen places all or refuses)
    rep |= {"particles": case.particles, "bodies": case.bodies,
            "heap_spheres": [r["heap_spheres"] for r in runs], "seeds": [r["seed"] for r in runs],
            "wall_time_s": _stats([r["wall_time_s"] for r in runs]),
            "cpu_time_s": _stats([r["cpu_time_s"] for r in runs]),
            "stages": [r["stages"] for r in runs], "dt_s": runs[0]["provenance"]["dt_s"],
            "base_stress_over_rho_g_1mn_H": [r["base_stress_over_rho_g_1mn_H"] for r in runs],
            "case": dataclasses.asdict(case) | {"seed": None}, "assumptions": ASSUMPTIONS,
            "run_folders": [r["run_folder"] for r in runs],
            "git": _started_at(runs), "versions": package_versions(), "reproducibility": reproducibility.describe(),
            "source": "Nadukuru & Michalowski (2012), Fig. 1 and its description (section on arching)"}
    return rep


def _started_at(runs: list[dict]) -> str:
    """The git revision the runs started from (their manifests), not the one at the end."""
    revs = []
    for r in runs:
        man = Path(r["run_folder"]) / "manifest.json"
        revs.append(json.loads(man.read_text())["git"] if man.is_file() else git_revision())
    return ", ".join(dict.fromkeys(revs))


def _figure(runs: list[dict], path: Path) -> None:
    from viz.figures import plot_series

    x = np.array(runs[0]["base_stress_over_rho_g_1mn_H"]["x_m"])
    ys = {}
    for r in runs:
        prof = r["base_stress_over_rho_g_1mn_H"]
        ys[f"seed {r['seed']} before"] = (x, np.array(prof["before"]))
        ys[f"seed {r['seed']} after"] = (x, np.array(prof["after"]))
    plot_series(x, ys, path, xlabel="x [m] (base centre at 0)", ylabel="sigma_v / (rho g (1 - n) H)",
                title="Heap base stress before / after subsidence (paper Fig. 1c)")


def _row(name: str, s: dict, fmt: str = ".3f") -> str:
    seeds = ", ".join(f"{v:{fmt}}" for v in s["per_seed"])
    return f"| {name} | {s['mean']:{fmt}} +- {s['sd']:{fmt}} | {seeds} |"


def scorecard(rep: dict) -> dict:
    """The report's scorecard (``studies.heap.scorecard``) from its own record."""
    from ..scorecard import scorecard_json
    from .scorecard import scorecard_rows
    ref = json.loads(Path(__file__).with_name("reference.json").read_text())
    return scorecard_json(scorecard_rows(rep, ref))


def report_markdown(rep: dict, discussion: Path | None = None) -> str:
    """The report; ``discussion`` (hand-written markdown, if the file exists) is appended."""
    from ..scorecard import scorecard_markdown
    lines = [
        "# Validation: Nadukuru & Michalowski (2012) Fig. 1, a heap over a subsiding base",
        "",
        f"Generated by `wallsim validate heap` (git {rep['git']}); {rep['particles']} spheres "
        f"({rep['bodies']} bodies), seeds {rep['seeds']}, dt {rep['dt_s']:.3g} s.",
        "",
        *(scorecard_markdown(rep["scorecard"], "Scorecard: every statement of the paper")
          if "scorecard" in rep else []),
        "Paper: after the base halves turn about their outer edges to a centre subsidence "
        "Delta/H = 0.0067 the base stress has \"a distinct local minimum at the center (a dip)\" "
        "(Fig. 1c); before the deflection the paper shows the profile but states no dip. "
        "Fig. 1 gives no numbers, so the check is qualitative: centre / peak < 1 after.",
        "",
        "| quantity | mean +- sd | per seed |",
        "|---|---|---|",
        _row("centre / peak base stress, before subsidence", rep["centre_over_peak_before"]),
        _row("centre / peak base stress, after subsidence", rep["centre_over_peak_after"]),
        _row("heap slope [deg]", rep["slope_deg"], ".1f"),
        _row("heap height H [m]", rep["heap_height_m"]),
        _row("porosity of the heap's core", rep["porosity"]),
        _row("Delta/H reached", rep["subsidence_over_H"], ".4f"),
        _row("base load / heap weight (before)", rep["base_load_over_heap_weight"]),
        _row("wall time [s]", rep["wall_time_s"], ".0f"),
        _row("CPU time [s] (all threads)", rep["cpu_time_s"], ".0f"),
        "",
        "Centre stress: the mean of the two bins next to the centre after folding the profile about "
        "it (mean of the bins at +-x); peak: the largest folded bin. Base profiles of every seed: "
        "[heap_base_stress.png](heap_base_stress.png).",
        "",
        "Assumptions (the paper omits \"the remaining details\"):",
        "",
        *[f"* {a}" for a in rep["assumptions"]],
        "",
    ]
    if discussion is not None and discussion.is_file():
        lines += [discussion.read_text()]
    return "\n".join(lines)
