"""Sweeps and seed ensembles of any registered study on dask.distributed.

    from studies.sweep import parse_vary, run_sweep
    table = run_sweep("khosravi", parse_vary(["seed=1..3", "wall_speed=0.002,0.004"]),
                      sets=["H=0.1"], out="sweeps", workers=2)

``--vary KEY=V1,V2,...`` (or ``KEY=A..B``, whole numbers, both ends included) for each
varied key; the points are the Cartesian product. Each point's case is built as a normal
run builds it (defaults < ``--config`` < ``--set`` < the point's values) and run by the
study's main command, one dask task per point, into its own ordinary run folder
``<out>/<study>/<point name>`` (named by the point's values and a hash of its case, so a
rerun finds it and skips a point whose folder holds a result.json).

Specimens: a point waits for the points that differ from it by one non-seed key set back
to that key's first value (``lead_indices``). Whatever subset of the varied keys shapes
the study's specimen, the points sharing one specimen then start after one of them (the
one with every other key at its first value) has made and stored it: no two workers
prepare the same specimen at once, and the sweep layer needs no study's specimen key.

A point that raises is recorded with its one-line error; the others go on. A worker that
dies mid-point has its point run again on another worker (the scheduler's
``allowed-failures``, 3 by default); ``retries`` covers an exception from dask itself.
"""

from __future__ import annotations

import itertools
import math
import os
import re
import time
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass
from pathlib import Path

from analytic.errors import InvalidParameter

_RANGE = re.compile(r"^(-?\d+)\.\.(-?\d+)$")
_VARY_FORM = "KEY=V1,V2,... or KEY=A..B (whole numbers A <= B)"


@dataclass(frozen=True)
class Point:
    """One point of a sweep: ``values`` ((key, value as typed), ...) in ``--vary`` order and
    ``index``, the position of each value in its key's list."""

    values: tuple[tuple[str, str], ...]
    index: tuple[int, ...]

    @property
    def sets(self) -> list[str]:
        """The point's values as ``--set KEY=VALUE`` strings (applied after the shared ones)."""
        return [f"{k}={v}" for k, v in self.values]

    def label(self) -> str:
        return " ".join(self.sets)


#: the most points a sweep runs: each point is a run and a run folder, and 10,000 of the
#: shortest (a tilt test, ~1 s) already take hours on two cores
MAX_SWEEP_POINTS = 10_000


def parse_vary(items: list[str]) -> list[tuple[str, list[str]]]:
    """``["seed=1..3", "mode=T,RB"]`` -> ``[("seed", ["1", "2", "3"]), ("mode", ["T", "RB"])]``;
    ``InvalidParameter`` for text that is not ``KEY=V1,V2,...`` / ``KEY=A..B``, a key given
    twice or a value repeated in one list. Values are checked when the cases are built."""
    varied, seen = [], set()
    for item in items:
        key, eq, text = (s.strip() for s in item.partition("="))
        if not eq or not key or not text:
            raise InvalidParameter("--vary", item, _VARY_FORM)
        values = []
        for part in (p.strip() for p in text.split(",")):
            m = _RANGE.match(part)
            if m and int(m[1]) > int(m[2]):
                raise InvalidParameter("--vary", item, _VARY_FORM, f"{part} is an empty range")
            if not part or (".." in part and not m):
                raise InvalidParameter("--vary", item, _VARY_FORM)
            if m and int(m[2]) - int(m[1]) + 1 > MAX_SWEEP_POINTS:
                raise InvalidParameter("--vary", item, f"at most {MAX_SWEEP_POINTS:,} points",
                                       f"{part} alone is {int(m[2]) - int(m[1]) + 1:,}")
            values += [str(v) for v in range(int(m[1]), int(m[2]) + 1)] if m else [part]
        if key in seen:
            raise InvalidParameter("--vary", item, "each key once", f"{key} is varied twice")
        if len(set(values)) < len(values):
            raise InvalidParameter("--vary", item, "distinct values", "a value is repeated")
        seen.add(key)
        varied.append((key, values))
    if not varied:
        raise InvalidParameter("--vary", None, _VARY_FORM, "nothing to vary")
    total = math.prod(len(values) for _, values in varied)
    if total > MAX_SWEEP_POINTS:
        raise InvalidParameter("--vary", " ".join(items), f"at most {MAX_SWEEP_POINTS:,} points",
                               f"the product of the values is {total:,}")
    return varied


def parse_options(cmd, items: list[str]) -> dict:
    """``["no-rrd", "every=10"]`` -> ``{"no_rrd": True, "every": 10}``: run options of
    ``cmd`` (its flags that set no case key) as the flag parses them; a switch takes no
    value. ``InvalidParameter`` naming --option for an unknown name or a bad value."""
    by_name = {o.flag.lstrip("-"): o for o in cmd.options if o.key is None}
    options = {}
    for item in items:
        name, eq, text = (s.strip() for s in item.partition("="))
        opt = by_name.get(name.replace("_", "-"))
        if opt is None or opt.dest in ("resume",):
            raise InvalidParameter("--option", item, " | ".join(n for n in by_name if n != "resume"),
                                   f"not a run option of {cmd.verb}")
        if opt.switch or (opt.optional and not eq):
            if eq:
                raise InvalidParameter("--option", item, f"{name} alone (a switch)")
            options[opt.dest] = True
            continue
        if not eq or not text:
            raise InvalidParameter("--option", item, f"{name}=VALUE")
        if opt.choices and text not in opt.choices:
            raise InvalidParameter("--option", item, " | ".join(opt.choices))
        options[opt.dest] = opt.parse(text) if opt.parse else text
    return options


def expand(varied: list[tuple[str, list[str]]]) -> list[Point]:
    """The Cartesian product of the varied values, the last key varying fastest."""
    keys = [k for k, _ in varied]
    ranges = [range(len(vals)) for _, vals in varied]
    return [Point(tuple(zip(keys, (varied[i][1][j] for i, j in enumerate(idx)))), idx)
            for idx in itertools.product(*ranges)]


def is_seed(key: str, seed_key: str | None) -> bool:
    """Whether a varied key is the command's seed (dotted or bare)."""
    return seed_key is not None and key.split(".")[-1] == seed_key.split(".")[-1]


def lead_indices(points: list[Point], seed_at: int | None) -> list[list[int]]:
    """For each point, the points it waits for: itself with one non-seed key set back to
    that key's first value (module docstring, "Specimens")."""
    where = {p.index: i for i, p in enumerate(points)}
    leads = []
    for p in points:
        back = [p.index[:k] + (0,) + p.index[k + 1:] for k, j in enumerate(p.index) if j > 0 and k != seed_at]
        leads.append([where[b] for b in back])
    return leads


#: run options that say where and how quietly a point runs, not what it computes: left
#: out of the point's name
_PLACE_OPTIONS = ("out", "quiet", "docs")

#: an option value that ``run_point`` replaces by the point's own folder (``validate
#: --seeds`` writes each seed's report there)
POINT_FOLDER = "<point folder>"


def point_name(point: Point, case, options: dict | None = None, prefix: str = "") -> str:
    """The point's run-folder name: ``prefix``, its values, then a hash of the whole case
    and of the run options that shape what it computes (a rerun with other shared
    settings makes new folders instead of skipping)."""
    from .store import content_key
    words = "_".join(f"{k.split('.')[-1]}{v}" for k, v in point.values)
    shaping = {k: v for k, v in (options or {}).items() if k not in _PLACE_OPTIONS}
    key = content_key({"case": case, "options": shaping}, 8) if shaping else content_key(case, 8)
    return re.sub(r"[^A-Za-z0-9._=-]", "-", prefix + words)[:120] + "-" + key


def is_main(study, verb: str | None) -> bool:
    """Whether ``verb`` is the study's main (first) command."""
    return verb is None or verb == study.commands[0].verb


def result_file(study, verb: str | None) -> str:
    """The file that marks a point as finished: the main command's result.json (written
    last by ``runner.finish``), or ``<verb>.json``, the result of another command
    (validate) that ``run_point`` writes last."""
    return "result.json" if is_main(study, verb) else f"{verb}.json"


def point_outputs(cmd, result: dict) -> dict[str, float]:
    """A point's outputs: the command's figures (name -> value) when it declares them,
    else ``result_outputs``."""
    if cmd.figures is not None:
        return {f["name"]: f["value"] for f in cmd.figures(result)}
    return result_outputs(result)


def one_line(err: BaseException) -> str:
    """An exception as one line: an ``InvalidParameter`` as it is, else its type and first line."""
    text = str(err).strip().splitlines()[0] if str(err).strip() else ""
    return text if isinstance(err, InvalidParameter) else f"{type(err).__name__}: {text}".rstrip(": ")


def numeric_leaves(obj, prefix: str = "") -> dict[str, float]:
    """Every finite-or-NaN number (not bool) in nested dicts, by dotted name."""
    out = {}
    for k, v in obj.items():
        name = f"{prefix}{k}"
        if isinstance(v, dict):
            out |= numeric_leaves(v, name + ".")
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            out[name] = float(v)
    return out


def result_outputs(result: dict) -> dict[str, float]:
    """The numbers a sweep tabulates from a result: the leaves of ``result["dem"]`` when the
    study has one (the DEM's headline figures), else the top-level numbers."""
    if isinstance(result.get("dem"), dict):
        return numeric_leaves(result["dem"])
    return numeric_leaves({k: v for k, v in result.items() if not isinstance(v, dict)})


def finished_point(out: str | Path, name: str, study: str, verb: str | None = None) -> dict | None:
    """The row of a point whose run folder under ``out`` holds a finished run
    (``result_file``), else None."""
    import json
    from . import get
    s = get(study)
    for folder in sorted(Path(out).glob(f"*/{name}")):
        p = folder / result_file(s, verb)
        if p.is_file():
            result = json.loads(p.read_text())
            manifest = folder / "manifest.json"
            wall = json.loads(manifest.read_text()).get("wall_time_s") if manifest.is_file() else None
            return {"status": "skipped", "error": None, "outputs": point_outputs(s.command(verb), result),
                    "wall_time_s": wall if wall is not None else result.get("wall_time_s"),
                    "run_folder": str(folder)}
    return None


def run_point(study: str, verb: str | None, case, name: str, out: str, options: dict | None = None,
              *after) -> dict:
    """One point, in a worker: run the study's command on ``case`` with the run
    ``options`` into ``<out>/<study folder>/<name>``; a raised error becomes the row's
    one-line ``error``. The point's progress and start/end lines go to ``run.log`` in its
    folder (appended: a point run again after a worker died says so), its run options to
    run_options.json; a command other than the main one has its result written last as
    ``<verb>.json``. ``after``: the rows of the points this one waited for (unused; they
    order the tasks)."""
    from . import get
    from .progress import logging_to
    from .runner import named_run, recorded_options
    t0 = time.perf_counter()
    s = get(study)
    folder = Path(out) / study / name
    folder.mkdir(parents=True, exist_ok=True)
    opts = {k: (str(folder) if v == POINT_FOLDER else v) for k, v in (options or {}).items()}
    with open(folder / "run.log", "a", encoding="utf-8") as log, logging_to(log, interval=10.0):
        _log_line(log, f"point {name}: {study} {s.command(verb).verb}, started on {_where()}")
        try:
            recorded = vars(s.command(verb).run_options(out=str(out), quiet=True, **opts))
            with named_run(name), recorded_options(recorded):
                result = s.run(case, verb, out=str(out), quiet=True, **opts)
            _point_files(s, verb, folder, recorded, result)
        except Exception as err:          # recorded for this point; the sweep goes on
            _log_line(log, f"point failed after {time.perf_counter() - t0:.1f} s: {one_line(err)}")
            return {"status": "failed", "error": one_line(err), "outputs": {},
                    "wall_time_s": time.perf_counter() - t0, "run_folder": None}
        _log_line(log, f"point finished in {time.perf_counter() - t0:.1f} s")
    folders = sorted(Path(out).glob(f"*/{name}"))
    return {"status": "done", "error": None, "outputs": point_outputs(s.command(verb), result),
            "wall_time_s": time.perf_counter() - t0, "run_folder": str(folders[0]) if folders else None}


def _point_files(study, verb: str | None, folder: Path, options: dict, result: dict) -> None:
    """run_options.json where the study opened no run folder that wrote it, then, for a
    command other than the main one, its result as ``<verb>.json`` (last: it marks the
    point finished)."""
    import json
    from .store import atomic_write, to_plain
    if not (folder / "run_options.json").is_file():
        atomic_write(folder / "run_options.json", (json.dumps(to_plain(options), indent=2) + "\n").encode())
    if not is_main(study, verb):
        atomic_write(folder / result_file(study, verb), (json.dumps(to_plain(result), indent=2) + "\n").encode())


def _log_line(log, text: str) -> None:
    log.write(f"[{time.strftime('%Y-%m-%d %H:%M:%S')}] {text}\n")
    log.flush()


def _where() -> str:
    """Host and process of this worker."""
    import socket
    return f"{socket.gethostname()} (pid {os.getpid()})"


def build_points(study, varied, *, config: str | None = None, sets: list[str] | None = None,
                 verb: str | None = None, flags: dict | None = None, options: dict | None = None) -> list[dict]:
    """Every point with its case, before anything runs: ``{"point", "inputs", "case",
    "name", "error"}``. Each case is resolved as the command line resolves one: defaults
    < ``config`` < ``flags`` (case key -> value, the typed flags) < ``sets`` < the point's
    values. An unknown varied key or run option stops the sweep (``InvalidParameter``); a
    value that the case refuses is that point's ``error`` (case None), the others go on.
    A command other than the main one prefixes its points' names with its verb."""
    from .config import case_value
    from .store import to_plain
    cmd = study.command(verb)
    default = cmd.resolve(config=config, flags=flags, sets=sets)    # a bad --set/--config stops everything
    cmd.run_options(**(options or {}))                                # an unknown run option too
    for key, _ in varied:
        try:
            case_value(default, key)
        except InvalidParameter as err:
            raise InvalidParameter("--vary", key, err.valid, err.why) from None
    prefix = "" if is_main(study, verb) else f"{cmd.verb}-"
    rows = []
    for p in expand(varied):
        try:
            case = cmd.resolve(config=config, flags=flags, sets=[*(sets or []), *p.sets])
            inputs = {k: to_plain(case_value(case, k)) for k, _ in p.values}
            rows.append({"point": p, "inputs": inputs, "case": case, "name": point_name(p, case, options, prefix),
                         "error": None})
        except InvalidParameter as err:
            rows.append({"point": p, "inputs": dict(p.values), "case": None, "name": None, "error": str(err)})
    return rows


@contextmanager
def dask_client(workers: int | None = None, scheduler: str | None = None):
    """A dask.distributed client: of the cluster at ``scheduler`` (``tcp://host:8786``), or
    of a new LocalCluster on this machine, ``workers`` processes (default: the cores) of
    one thread each, numba on one thread in each (NUMBA_NUM_THREADS=1). The local
    cluster starts with SIGINT held (``_sigint_held``): Ctrl-C reaches this process
    only, which closes the cluster."""
    import logging
    from dask.distributed import Client, LocalCluster
    if scheduler:
        try:
            client = Client(scheduler)
        except OSError as err:  # nobody answers there: one line, not dask's traceback
            from analytic.errors import InvalidParameter
            raise InvalidParameter("scheduler", scheduler, f"a running Dask scheduler ({err})") from None
        with client:
            yield client
        return
    n = workers or os.cpu_count() or 1
    with _sigint_held():
        # ":0": the scheduler's HTTP server on a free port (None still tries 8787 and warns
        # when another Dask cluster on the machine holds it). Logs at CRITICAL only: a point's
        # failure is reported in sweep.json; what Dask logs at ERROR is its own (a worker's
        # heartbeat to the scheduler that Ctrl-C is closing, on a loaded machine: 31 lines
        # after the one the interrupt promises)
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                               silence_logs=logging.CRITICAL, env={"NUMBA_NUM_THREADS": "1"})
    with cluster, Client(cluster) as client:
        try:
            yield client
        except KeyboardInterrupt:
            _stop_workers(cluster)
            raise


def _stop_workers(cluster, timeout: float = 0.5) -> None:
    """Close the local cluster's workers at once, a point still running or not (a
    paper-scale point runs for an hour; Dask's own close waits 4 s per worker for it
    first). Closing through the nannies keeps them from starting new workers."""
    import asyncio
    from distributed.utils import sync

    async def close_all():
        await asyncio.gather(*(n.close(timeout=timeout, reason="wallsim sweep interrupted")
                               for n in list(cluster.workers.values())), return_exceptions=True)
    sync(cluster.loop, close_all)


@contextmanager
def _sigint_held():
    """SIGINT blocked in this thread while the block runs (the local cluster starts).
    Threads started meanwhile (the cluster's event loop) and the worker processes they
    spawn, now or on a restart, inherit the blocked signal, so a Ctrl-C at the terminal,
    which signals the whole process group, reaches this process only: the workers do not
    die each with a traceback; this process stops the sweep and closes the cluster. A
    Ctrl-C while the block runs is delivered when it ends.

    multiprocessing's resource tracker is started first: starting it unblocks SIGINT in
    the thread that starts it, which would be the cluster's event loop."""
    import signal
    import threading
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "pthread_sigmask"):
        yield
        return
    from multiprocessing import resource_tracker
    resource_tracker.ensure_running()
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def submit_points(client, study: str, verb: str | None, built: list[dict], out: str, seed_at: int | None,
                  retries: int = 2, options: dict | None = None) -> dict:
    """One task per point to run (not finished before, case built), each after its leads
    (``lead_indices``) that run too. Returns {row index: future}."""
    leads = lead_indices([b["point"] for b in built], seed_at)
    futures = {}
    for i, b in enumerate(built):
        if b["case"] is None or "status" in b:
            continue
        after = [futures[j] for j in leads[i] if j in futures]
        futures[i] = client.submit(run_point, study, verb, b["case"], b["name"], str(out), options or {}, *after,
                                   key=f"point-{b['name']}", retries=retries, pure=False)
    return futures


def run_sweep(study_name: str, varied, *, config: str | None = None, sets: list[str] | None = None,
              out: str | Path = "sweeps", workers: int | None = None, scheduler: str | None = None,
              client=None, quiet: bool = True, verb: str | None = None, outputs: list[str] | None = None,
              flags: dict | None = None, options: dict | None = None, tables: str | Path | None = None) -> dict:
    """Run every point of ``varied`` (``parse_vary``) of the study's main command (or
    ``verb``) on dask; write ``sweep.json``, ``sweep.csv``, ``sweep_groups.csv`` and
    ``sweep.png`` in ``tables`` (default ``out``) and return ``{"points": [...],
    "groups": [...]}`` (module docstring). ``flags``: case key -> value, as typed flags
    set them; ``options``: the command's run options for every point (``POINT_FOLDER``
    for the point's own folder). ``client``: an open dask client to use instead of
    making one."""
    from . import get
    from .progress import progress
    study = get(study_name)
    seed_key = study.command(verb).seed_key
    built = build_points(study, varied, config=config, sets=sets, verb=verb, flags=flags, options=options)
    for b in built:
        done = finished_point(out, b["name"], study_name, verb) if b["case"] is not None else None
        b.update(done or {})
    seed_at = next((k for k, (key, _) in enumerate(varied) if is_seed(key, seed_key)), None)
    settings = {"sets": sets, "config": config} | ({"flags": flags} if flags else {}) \
        | ({"verb": verb, "options": options} if options or not is_main(study, verb) else {})
    with (nullcontext(client) if client is not None else dask_client(workers, scheduler)) as c, \
            progress(quiet) as bar:
        futures = submit_points(c, study_name, verb, built, str(Path(out).resolve()), seed_at, options=options)
        task = bar.add_task(f"sweep {study_name}", total=len(built),
                            completed=len(built) - len(futures), status="")
        where = tables if tables is not None else out
        try:
            _collect(futures, built, bar, task)
        except BaseException:     # Ctrl-C: the finished points are in their run folders; the
            _finished_meanwhile(built, out, study_name, verb)      # table says which, at once
            write_tables(study_name, varied, built, where, seed_key, outputs, figure=False, **settings)
            raise                 # (the figure takes seconds)
        table = write_tables(study_name, varied, built, where, seed_key, outputs, **settings)
    return table


def _finished_meanwhile(built: list[dict], out, study: str, verb: str | None) -> None:
    """Points marked interrupted whose run finished before this process heard of it:
    done, as their folders say."""
    for b in built:
        if b.get("status") == "interrupted":
            row = finished_point(out, b["name"], study, verb)
            if row is not None:
                b.update(row | {"status": "done"})


def _collect(futures: dict, built: list[dict], bar, task) -> None:
    """Fill each built row with its task's row as the tasks finish."""
    from dask.distributed import as_completed
    index = {f.key: i for i, f in futures.items()}
    try:
        for fut in as_completed(list(futures.values())):
            try:
                row = fut.result()
            except Exception as err:        # the task itself failed (a worker died too often)
                row = {"status": "failed", "error": one_line(err), "outputs": {}, "wall_time_s": None,
                       "run_folder": None}
            built[index[fut.key]].update(row)
            failed = sum(b.get("status") == "failed" or b["case"] is None for b in built)
            bar.advance(task)
            bar.update(task, status=f"{failed} failed" if failed else "")
    except BaseException:
        for i, fut in futures.items():
            fut.cancel()
            built[i].setdefault("status", "interrupted")    # running or queued when the sweep stopped
        raise


def stats(values: list[float]) -> dict:
    """n, mean, sample standard deviation (n - 1 in the denominator; None for one value),
    min and max of ``values`` (None for no values)."""
    n = len(values)
    if n == 0:
        return {"n": 0, "mean": None, "sd": None, "min": None, "max": None}
    mean = math.fsum(values) / n
    sd = math.sqrt(math.fsum((v - mean) ** 2 for v in values) / (n - 1)) if n > 1 else None
    return {"n": n, "mean": mean, "sd": sd, "min": min(values), "max": max(values)}


def point_rows(built: list[dict], outputs: list[str]) -> list[dict]:
    """One row per point: its inputs, status (done, skipped, failed, interrupted: queued
    or running when the sweep stopped), one-line error, the chosen outputs, wall time [s] and run folder."""
    rows = []
    for b in built:
        status = "failed" if b["case"] is None else b.get("status", "not run")
        row = {"point": b["name"] or b["point"].label(), **b["inputs"], "status": status,
               "error": b.get("error")}
        row |= {o: b.get("outputs", {}).get(o) for o in outputs}
        row |= {"wall_time_s": b.get("wall_time_s"), "run_folder": b.get("run_folder")}
        rows.append(row)
    return rows


def group_rows(rows: list[dict], group_keys: list[str], outputs: list[str]) -> list[dict]:
    """Per group of points that differ only in seed: the group's inputs, how many points it
    has and how many finished, and ``<output>_mean``, ``_sd``, ``_min``, ``_max`` over the
    finished points (NaN and missing values left out)."""
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault(tuple(r[k] for k in group_keys), []).append(r)
    out = []
    for values, members in groups.items():
        ok = [r for r in members if r["status"] in ("done", "skipped")]
        g = {**dict(zip(group_keys, values)), "points": len(members), "finished": len(ok)}
        for o in outputs:
            s = stats([r[o] for r in ok if r[o] is not None and not math.isnan(r[o])])
            g |= {f"{o}_{k}": s[k] for k in ("mean", "sd", "min", "max")}
        out.append(g)
    return out


def chosen_outputs(built: list[dict], outputs: list[str] | None) -> list[str]:
    """The outputs to tabulate: ``outputs`` if given, else every output any finished point
    has, in the order they first appear."""
    if outputs:
        return list(outputs)
    names = {}
    for b in built:
        names |= dict.fromkeys(b.get("outputs", {}))
    return list(names)


def figure_outputs(groups: list[dict], names: list[str], most: int = 6) -> list[str]:
    """What the figure shows when no output was chosen: up to ``most`` outputs, the
    glossary's headline figures first (K..., resultant_height_over_H...), those whose
    mean changes between groups before those that do not."""
    def rank(name):
        means = {g[f"{name}_mean"] for g in groups if g[f"{name}_mean"] is not None}
        headline = name.split(".")[-1].startswith(("K", "resultant_height_over_H"))
        return (len(means) < 2 and len(groups) > 1, not headline, names.index(name))
    return sorted((n for n in names if any(g[f"{n}_mean"] is not None for g in groups)), key=rank)[:most]


def write_tables(study: str, varied, built: list[dict], out, seed_key: str | None,
                 outputs: list[str] | None = None, figure: bool = True, **settings) -> dict:
    """sweep.json (the study, the varied values, the shared settings, points and groups),
    sweep.csv (points), sweep_groups.csv (groups) and, with ``figure``, sweep.png in
    ``out``; returns ``{"points", "groups"}`` as in sweep.json."""
    import json
    from .store import atomic_write, to_plain
    names = chosen_outputs(built, outputs)
    rows = point_rows(built, names)
    group_keys = [k for k, _ in varied if not is_seed(k, seed_key)]
    groups = group_rows(rows, group_keys, names)
    out = Path(out)
    table = {"study": study, "varied": dict(varied), **settings, "outputs": names, "points": rows, "groups": groups}
    atomic_write(out / "sweep.json", (json.dumps(to_plain(table), indent=2) + "\n").encode())
    atomic_write(out / "sweep.csv", _csv(rows))
    atomic_write(out / "sweep_groups.csv", _csv(groups))
    finished = [g for g in groups if g["finished"]]
    shown = list(outputs)[:6] if outputs else figure_outputs(finished, names)
    if shown and figure:
        from viz.figures import plot_sweep
        plot_sweep(finished, group_keys, shown, out / "sweep.png", title=f"{study} sweep")
    return {"points": to_plain(rows), "groups": to_plain(groups)}


def _csv(rows: list[dict]) -> bytes:
    """Rows as CSV, floats in full (shortest exact) precision, None as empty."""
    import csv
    import io
    buf = io.StringIO(newline="")
    if rows:
        w = csv.DictWriter(buf, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows({k: ("" if v is None else repr(v) if isinstance(v, float) else v) for k, v in r.items()}
                     for r in rows)
    return buf.getvalue().encode()


def sweep_text(table: dict, most: int = 4) -> str:
    """The groups for people: their inputs, finished/points and mean +- sd of the first
    ``most`` outputs of the figure's choice."""
    groups = table["groups"]
    if not groups:
        return "no points"
    fixed = {"points", "finished"}
    keys = [k for k in groups[0] if k not in fixed and not k.endswith(("_mean", "_sd", "_min", "_max"))]
    names = figure_outputs(groups, [k[:-5] for k in groups[0] if k.endswith("_mean")], most)
    lines = []
    for g in groups:
        head = " ".join(f"{k}={g[k]}" for k in keys) or "all points"
        cells = [f"{n} {g[n + '_mean']:.4g}" + (f" +- {g[n + '_sd']:.2g}" if g[n + "_sd"] is not None else "")
                 for n in names if g[n + "_mean"] is not None]
        lines.append(f"{head}: {g['finished']}/{g['points']} finished" + ("; " + ", ".join(cells) if cells else ""))
    return "\n".join(lines)
