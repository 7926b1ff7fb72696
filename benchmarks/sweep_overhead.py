"""What running a sweep on Dask costs against a plain loop (issue 27): the same points
of ``wallsim sweep nadukuru`` (2 seeds x the 4 modes, reduced size, no recording) run

1. one by one in this process (``Study.run``), numba on one thread as in a worker;
2. on a LocalCluster of 1 worker (``run_sweep``), the cluster started before the clock;
3. on a LocalCluster of 2 workers, likewise.

Printed (and written with --out): wall and CPU time of each, the cluster's start, the
per-point overhead of Dask ((1-worker sweep - serial loop) / points, and against the
mean point) and the 2-worker / 1-worker wall time ratio. The three give the same
numbers (checked). Each run starts from an empty folder, so each prepares the two
specimens (one per seed) and reuses them for the other modes.

    PYTHONPATH=. python benchmarks/sweep_overhead.py --particles 1000 --out docs/validation/sweep_overhead.json

A measurement, not a test. Wall times mean little on a shared machine: the load
average and the cores busy with other work are recorded before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import tempfile
import time
from pathlib import Path

os.environ["NUMBA_NUM_THREADS"] = "1"          # as in every worker; before numba is imported


def _cpu_self() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _worker_cpu(client) -> float:
    """CPU time [s] of the workers' processes so far."""
    def cpu():
        import resource as res
        r = res.getrusage(res.RUSAGE_SELF)
        return r.ru_utime + r.ru_stime
    return sum(client.run(cpu).values())


def _machine() -> dict:
    from studies.progress import busy_cores
    return {"load_average_1min": os.getloadavg()[0], "cores_busy_with_other_work": busy_cores(1.0),
            "cores": os.cpu_count()}


def serial(varied, sets, options, out: Path) -> dict:
    """The points one by one in this process, as ``run_point`` runs them but without Dask."""
    from studies import get
    from studies.sweep import build_points, point_outputs
    study = get("nadukuru")
    built = build_points(study, varied, sets=sets, options=options)
    t0, c0 = time.perf_counter(), _cpu_self()
    times, outputs = [], []
    for b in built:
        tp = time.perf_counter()
        result = study.run(b["case"], out=str(out), quiet=True, **options)
        times.append(time.perf_counter() - tp)
        outputs.append(point_outputs(study.command(), result))
    return {"wall_s": time.perf_counter() - t0, "cpu_s": _cpu_self() - c0, "point_wall_s": times,
            "outputs": outputs}


def on_dask(varied, sets, options, out: Path, workers: int) -> dict:
    """The same points as a sweep on a new LocalCluster of ``workers`` (its start timed apart)."""
    from studies.sweep import dask_client, run_sweep
    t0 = time.perf_counter()
    with dask_client(workers=workers) as client:
        start = time.perf_counter() - t0
        w0, c0, t1 = _worker_cpu(client), _cpu_self(), time.perf_counter()
        table = run_sweep("nadukuru", varied, sets=sets, out=out, client=client, options=options)
        wall = time.perf_counter() - t1
        cpu_workers, cpu_client = _worker_cpu(client) - w0, _cpu_self() - c0
    assert all(p["status"] == "done" for p in table["points"]), table["points"]
    return {"workers": workers, "cluster_start_s": start, "wall_s": wall, "cpu_workers_s": cpu_workers,
            "cpu_client_s": cpu_client, "point_wall_s": [p["wall_time_s"] for p in table["points"]],
            "points": table["points"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--particles", type=int, default=1000, help="spheres per point (1000)")
    ap.add_argument("--out", type=Path, help="write the figures here as JSON")
    args = ap.parse_args()
    from studies.runfolder import git_revision, package_versions
    from studies.sweep import parse_vary

    varied = parse_vary(["seed=1,2", "mode=T,RB,RT,mixed"])
    sets, options = [f"particles={args.particles}"], {"no_rrd": True}
    tmp = Path(tempfile.mkdtemp(prefix="sweep_overhead-"))
    before = _machine()
    s = serial(varied, sets, options, tmp / "serial")
    one = on_dask(varied, sets, options, tmp / "dask1", 1)
    two = on_dask(varied, sets, options, tmp / "dask2", 2)
    after = _machine()
    from studies.store import to_plain
    names = list(s["outputs"][0])
    for run in (one, two):                       # the same numbers, bit for bit (NaN as null in both)
        assert [[p[n] for n in names] for p in run["points"]] == to_plain([[o[n] for n in names] for o in s["outputs"]])
    n = len(s["point_wall_s"])
    per_point = (one["wall_s"] - s["wall_s"]) / n
    mean_point = s["wall_s"] / n
    out = {"git": git_revision(), "versions": package_versions(), "particles": args.particles, "points": n,
           "machine_before": before, "machine_after": after,
           "serial": {k: v for k, v in s.items() if k != "outputs"},
           "dask_1_worker": {k: v for k, v in one.items() if k != "points"},
           "dask_2_workers": {k: v for k, v in two.items() if k != "points"},
           "per_point_overhead_s": per_point, "mean_serial_point_s": mean_point,
           "per_point_overhead_fraction": per_point / mean_point,
           "in_worker_minus_serial_per_point_s": (sum(one["point_wall_s"]) - sum(s["point_wall_s"])) / n,
           "ratio_2_workers_over_1": two["wall_s"] / one["wall_s"],
           "same_numbers_in_all_three": True}
    text = json.dumps(out, indent=1)
    if args.out:
        args.out.write_text(text + "\n")
    print(text)
    print(f"\n{n} points of {args.particles} spheres: serial {s['wall_s']:.1f} s (CPU {s['cpu_s']:.1f} s); Dask 1 worker "
          f"{one['wall_s']:.1f} s + {one['cluster_start_s']:.1f} s cluster start; 2 workers {two['wall_s']:.1f} s "
          f"(ratio {out['ratio_2_workers_over_1']:.2f}); overhead {per_point:.2f} s per point = "
          f"{100 * out['per_point_overhead_fraction']:.1f} % of a {mean_point:.1f}-s point; load "
          f"{before['load_average_1min']:.1f} -> {after['load_average_1min']:.1f} on {before['cores']} cores")


if __name__ == "__main__":
    main()
