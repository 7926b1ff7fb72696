"""``wallsim validate <study> --seeds 1..3``: a command run once per seed on the sweep
machinery (``studies/sweep.py``, Dask: ``--workers``, ``--scheduler``), and each of its
figures as mean +- sd over the seeds against the paper's tolerance.

    from studies.seeds import run_seeds
    report = run_seeds("nadukuru", [1, 2, 3], options={"walls": ["rough"], "docs": "docs/validation"},
                       flags={"specimen.particles": 30000})

Any command that declares ``figures`` (``Command.figures``: its result -> ``figure``
records) and draws random numbers takes ``--seeds``; nothing here names a study. Each
seed is one sweep point, an ordinary run of the command whose own report goes to the
point's folder ``<out>/<study>/<verb>-seed<N>-<hash>/`` (its ``--docs``, with run.log,
run_options.json and ``<verb>.json``); a rerun skips the seeds that finished. The seeds
report, ``<docs>/<study>_seeds.md`` and ``.json``, gives per figure: each seed's value,
mean and sample sd (n - 1), min and max, whether the mean and how many seeds lie inside
the target window, and whether the reference value (the paper's) lies within the seed
spread, mean +- sd and min..max. A figure's target is the same for every seed.
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import reproducibility

from analytic.errors import InvalidParameter

_SEEDS_FORM = "whole numbers >= 1: A..B (both ends included) or a list 1,2,5"


def figure(name: str, value: float | None, *, reference: float | None = None, reference_name: str = "paper",
           lo: float | None = None, hi: float | None = None, target: str = "") -> dict:
    """One figure a command judges: ``value``, the ``reference`` value it is set against
    (named by ``reference_name``: "paper", "Jaky", ...) and the target window [lo, hi]
    (either end None: open), described in words by ``target``."""
    return {"name": name, "value": None if value is None else float(value), "reference": reference,
            "reference_name": reference_name, "lo": lo, "hi": hi, "target": target}


def within(value: float | None, lo: float | None, hi: float | None) -> bool | None:
    """lo <= value <= hi (an end that is None is open); None when there is no value or
    no window."""
    if value is None or (lo is None and hi is None) or math.isnan(value):
        return None
    return (lo is None or value >= lo) and (hi is None or value <= hi)


def parse_seeds(text: str) -> list[int]:
    """``"1..3"`` -> [1, 2, 3]; ``"1,2,5"`` -> [1, 2, 5] (ranges and lists mix, as
    ``--vary``); ``InvalidParameter`` naming --seeds otherwise."""
    from .sweep import parse_vary
    try:
        (_, values), = parse_vary([f"seed={text}"])
    except InvalidParameter as err:
        raise InvalidParameter("--seeds", text, _SEEDS_FORM, err.why) from None
    seeds = [int(v) if v.isdigit() else 0 for v in values]
    if min(seeds) < 1:
        raise InvalidParameter("--seeds", text, _SEEDS_FORM)
    return seeds


def run_seeds(study_name: str, seeds: list[int], *, verb: str = "validate", config: str | None = None,
              flags: dict | None = None, sets: list[str] | None = None, options: dict | None = None,
              out: str | Path = "runs", workers: int | None = None, scheduler: str | None = None,
              client=None, quiet: bool = True) -> dict:
    """Run ``verb`` of the study once per seed on Dask and write the seeds report to the
    ``docs`` run option's folder (the module docstring); returns the report. ``flags``:
    case key -> value as typed flags set them; ``options``: the command's run options
    (``docs`` is where the seeds report goes; each seed's own report goes to its point
    folder)."""
    from . import get
    from .sweep import POINT_FOLDER, build_points, run_sweep
    from .store import content_key
    t0 = time.perf_counter()
    study = get(study_name)
    cmd = study.command(verb)
    if cmd.figures is None or cmd.seed_key is None:
        raise InvalidParameter("--seeds", ",".join(map(str, seeds)), "a command with figures and a seed",
                               f"{verb} {study_name} has none")
    options = dict(options or {})
    docs = Path(options.pop("docs", None) or "docs/validation")
    if any(o.dest == "docs" for o in cmd.options):
        options["docs"] = POINT_FOLDER
    varied = [(cmd.seed_key, [str(s) for s in seeds])]
    names = [b["name"] for b in build_points(study, varied, config=config, sets=sets, verb=verb, flags=flags,
                                             options=options)]
    tables = Path(out) / study_name / f"{verb}-seeds-{content_key(names, 8)}"
    table = run_sweep(study_name, varied, config=config, sets=sets, out=out, workers=workers, scheduler=scheduler,
                      client=client, quiet=quiet, verb=verb, flags=flags, options=options, tables=tables)
    report = seeds_report(study, cmd, table, seeds, settings={"config": config, "sets": sets, "flags": flags,
                                                             "options": options},
                          tables=tables, wall_time_s=time.perf_counter() - t0,
                          cluster=scheduler or f"LocalCluster of {workers or 'the cores'} workers")
    return write_seeds_report(report, docs)


def seeds_report(study, cmd, table: dict, seeds: list[int], *, settings: dict, tables: Path,
                 wall_time_s: float, cluster: str) -> dict:
    """The report's record: the seeds, their points, and per figure the statistics of the
    sweep's one group (mean, sd, min, max over the finished seeds) with the target and
    the verdicts (``figure_summary``)."""
    from .runfolder import git_revision, package_versions
    from .sweep import result_file
    points = [{"seed": p[cmd.seed_key], **{k: p[k] for k in ("status", "error", "run_folder", "wall_time_s")}}
              for p in table["points"]]
    done = [p for p in points if p["status"] in ("done", "skipped")]
    first = json.loads((Path(done[0]["run_folder"]) / result_file(study, cmd.verb)).read_text()) if done else None
    targets = {f["name"]: f for f in cmd.figures(first)} if first is not None else {}
    group = table["groups"][0] if table["groups"] else {}
    rows = [r for r in table["points"] if r["status"] in ("done", "skipped")]
    figures = [figure_summary(t, {p["seed"]: r[name] for p, r in zip(done, rows)}, group)
               for name, t in targets.items()]
    return {"study": study.name, "title": study.title, "verb": cmd.verb, "seeds": seeds,
            "finished_seeds": [p["seed"] for p in done], "points": points, "figures": figures,
            "settings": settings, "cluster": cluster, "sweep_tables": str(tables),
            "command": "wallsim " + " ".join(sys.argv[1:]) if Path(sys.argv[0]).name in ("cli.py", "wallsim") else None,
            "git": git_revision(), "versions": package_versions(), "reproducibility": reproducibility.describe(),
            "wall_time_s": wall_time_s,
            "points_wall_time_s": math.fsum(p["wall_time_s"] or 0.0 for p in done)}


def figure_summary(target: dict, values: dict, group: dict) -> dict:
    """One figure over the seeds: its target (``figure`` record without the value), the
    value of each seed, the sweep group's n, mean, sd, min, max, and the verdicts: mean
    within the target, how many seeds within it, the reference within mean +- sd and
    within min..max (None where there is no reference or too few seeds)."""
    name = target["name"]
    s = {k: group.get(f"{name}_{k}") for k in ("mean", "sd", "min", "max")}
    finite = [v for v in values.values() if v is not None and not math.isnan(v)]
    ref, lo, hi = target["reference"], target["lo"], target["hi"]
    judged = [within(v, lo, hi) for v in finite]
    spread = (s["mean"] - s["sd"], s["mean"] + s["sd"]) if s["sd"] is not None else (None, None)
    return {**{k: v for k, v in target.items() if k != "value"}, "values": values, "n": len(finite), **s,
            "mean_within_target": within(s["mean"], lo, hi),
            "seeds_within_target": None if lo is None and hi is None else sum(bool(j) for j in judged),
            "reference_within_mean_sd": None if ref is None or spread[0] is None else within(ref, *spread),
            "reference_within_min_max": None if ref is None or len(finite) < 2 else within(ref, s["min"], s["max"])}


def write_seeds_report(report: dict, docs: Path) -> dict:
    """``<docs>/<study>_seeds.json`` and ``.md``; returns the report with their paths."""
    from .store import atomic_write, to_plain
    stem = docs / f"{report['study']}_seeds"
    report["paths"] = {"json": str(stem.with_suffix(".json")), "md": str(stem.with_suffix(".md"))}
    atomic_write(stem.with_suffix(".json"), (json.dumps(to_plain(report), indent=1) + "\n").encode())
    atomic_write(stem.with_suffix(".md"), seeds_markdown(report).encode())
    return report


def _num(x, fmt: str = ".4g") -> str:
    return "-" if x is None else format(x, fmt)


def _yes(ok: bool | None) -> str:
    return "n/a" if ok is None else ("yes" if ok else "**no**")


def _window(f: dict) -> str:
    lo, hi = f["lo"], f["hi"]
    return "-" if lo is None and hi is None else f"[{_num(lo)}, {_num(hi)}]"


def spread_line(f: dict) -> str | None:
    """Whether the reference value lies within the seed spread, in words (None for a
    figure without a reference)."""
    if f["reference"] is None or f["mean"] is None:
        return None
    ref = f"{f['reference_name']} {_num(f['reference'])}"
    if f["sd"] is None:
        return f"{f['name']}: one seed only ({_num(f['mean'])}); no spread to set {ref} against"
    sd, mm = f["reference_within_mean_sd"], f["reference_within_min_max"]
    where = ("within mean +- sd and within min..max" if sd and mm else
             "outside mean +- sd but within min..max" if mm else
             "within mean +- sd but outside min..max" if sd else
             f"outside the seed spread ({'above' if f['reference'] > f['max'] else 'below'} every seed)")
    return (f"{f['name']}: {ref} lies {where} (mean +- sd {_num(f['mean'])} +- {_num(f['sd'], '.2g')}, "
            f"min..max {_num(f['min'])}..{_num(f['max'])}, {f['n']} seeds)")


def seeds_markdown(r: dict) -> str:
    """The seeds report for people: provenance, the figure table, one line per figure
    with a reference on whether it lies within the seed spread, and the seeds' folders."""
    seeds = ", ".join(map(str, r["seeds"]))
    command = r["command"] or f"wallsim {r['verb']} {r['study']} --seeds ..."
    L = [f"# {r['title']}: {r['verb']} over seeds {seeds}", "",
         f"Generated by `{command}` (git {r['git']}, "
         f"wallsim {r['versions'].get('wallsim')}); each seed one run of `wallsim {r['verb']} {r['study']}` on Dask "
         f"({r['cluster']}); {len(r['finished_seeds'])} of {len(r['seeds'])} seeds finished; wall time "
         f"{r['wall_time_s'] / 60:.1f} min, the seeds' own wall times add up to {r['points_wall_time_s'] / 60:.1f} min.",
         "", "Mean +- sd over the finished seeds (sample sd, n - 1). A target window [lo, hi] includes its ends; "
         "\"seeds within\" counts the seeds inside it. The reference (the paper's value where it has one) is set "
         "against the seed spread: mean +- sd, and min..max.", "",
         "| figure | target | reference | per seed | mean +- sd | min..max | mean within target | seeds within "
         "| reference within mean +- sd | within min..max |", "|---|---|---|---|---|---|---|---|---|---|"]
    for f in r["figures"]:
        per_seed = ", ".join(_num(v) for v in f["values"].values())
        within_n = "n/a" if f["seeds_within_target"] is None else f"{f['seeds_within_target']}/{f['n']}"
        L.append(f"| {f['name']} | {f['target'] or _window(f)} | {_num(f['reference'])} | {per_seed} | "
                 f"{_num(f['mean'])} +- {_num(f['sd'], '.2g')} | {_num(f['min'])}..{_num(f['max'])} | "
                 f"{_yes(f['mean_within_target'])} | {within_n} | {_yes(f['reference_within_mean_sd'])} | "
                 f"{_yes(f['reference_within_min_max'])} |")
    lines = [x for x in map(spread_line, r["figures"]) if x]
    if lines:
        L += ["", "## Reference within the seed spread", "", *[f"- {x}." for x in lines]]
    L += ["", "## Seeds", "", "| seed | status | wall time | run folder (its own report) |", "|---|---|---|---|"]
    L += [f"| {p['seed']} | {p['status']}{': ' + p['error'] if p['error'] else ''} | "
          f"{_num(p['wall_time_s'] and p['wall_time_s'] / 60, '.1f')} min | {p['run_folder'] or '-'} |"
          for p in r["points"]]
    L += ["", f"Sweep tables (sweep.csv, sweep_groups.csv, sweep.json): `{r['sweep_tables']}`.", ""]
    return "\n".join(L)


def seeds_text(r: dict) -> str:
    """One line per figure for the terminal: mean +- sd, min..max, the target and the
    verdicts."""
    out = []
    for f in r["figures"]:
        if f["mean"] is None:
            out.append(f"{f['name']}: no finished seed")
            continue
        ref = "" if f["reference"] is None else (
            f"; {f['reference_name']} {_num(f['reference'])} within mean +- sd: {_yes(f['reference_within_mean_sd'])}, "
            f"min..max: {_yes(f['reference_within_min_max'])}")
        judged = "" if f["seeds_within_target"] is None else (
            f", mean within target {_yes(f['mean_within_target'])}, {f['seeds_within_target']}/{f['n']} seeds within")
        out.append(f"{f['name']}: {_num(f['mean'])} +- {_num(f['sd'], '.2g')} ({_num(f['min'])}..{_num(f['max'])}, "
                   f"{f['n']} seeds); target {f['target'] or _window(f)}{judged}{ref}".replace("**", ""))
    return "\n".join(out)
