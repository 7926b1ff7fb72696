"""Speed of ``Simulation(direct_sums=True)`` against the rows (the default), in one process.

Two copies of one model are stepped alternately in short blocks (A B B A, then B A A B,
``--rounds`` times), so that both see the same machine: on the shared 2-core machines
separate runs of 10-20 s moved by up to 40 % between neighbours, which hid a 15 % effect
(seismic_step_speed.py's pairs), while blocks of about a second interleaved this way do
not. Figures: CPU seconds (process time) per block, medians, and the median and
quartiles of the direct/rows ratio over the blocks taken side by side.

- ``seismic``: the default coarse seismic case's static state with its free-field columns
  (``dem3d.freefield.step_coupled``, one numba thread), 200 coupled steps a block;
  particle-steps count the main model and the columns.
- ``plain``: the LIGGGHTS benchmark problem (studies.bench, 30,000 spheres), on
  ``--threads`` numba threads (2), 100 steps a block; with two threads the CPU time is
  the process's (both threads).

The two copies start from the same state and part as their sums' rounding differs; a
block's cost does not depend on those last bits.

    NUMBA_NUM_THREADS=2 PYTHONPATH=. python benchmarks/direct_sums_speed.py --out docs/validation/direct_sums_speed.json
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent.parent


def seismic_models(cache: Path):
    """{mode: (advance(n_steps), particles)} of the coupled seismic model, rows and direct."""
    from dem3d.freefield import column_free_field, step_coupled
    from studies.seismic import specimen as M
    from studies.seismic.case import SeismicCase
    from studies.seismic.run import coupled, prepare

    case = SeismicCase(direct_sums=False)        # the rows' static state (the mode is set on each engine below)
    prepared = prepare(case, cache)
    models = {}
    for mode in ("rows", "direct"):
        main, columns, bnds, _ = coupled(case, prepared)
        for sim in (main, *columns):
            sim.direct_sums = mode == "direct"
        edges = [M.lateral_edges(case, case.front_height), M.lateral_edges(case, case.retained_height)]
        area = case.column_length * case.d_mean * case.width

        def free_field(columns=columns, edges=edges):
            return [column_free_field(c, e, area) for c, e in zip(columns, edges)]

        def advance(n, main=main, bnds=bnds, columns=columns, free_field=free_field):
            step_coupled(main, bnds, n, free_field=free_field, columns=columns, every=case.free_field_every)

        models[mode] = (advance, main.n_spheres + sum(c.n_spheres for c in columns))
    return models


def plain_models(n: int):
    from studies.bench import build_problem

    models = {}
    for mode in ("rows", "direct"):
        sim = build_problem(n, direct_sums=mode == "direct")
        models[mode] = (sim.step, sim.n_spheres)
    return models


def interleave(models: dict, steps: int, rounds: int) -> dict:
    for advance, _ in models.values():       # compile or load, build the lists
        advance(20)
    cpu = {mode: [] for mode in models}
    for k in range(rounds):
        order = ("rows", "direct", "direct", "rows") if k % 2 == 0 else ("direct", "rows", "rows", "direct")
        for mode in order:
            c = time.process_time()
            models[mode][0](steps)
            cpu[mode].append(time.process_time() - c)
    ratio = [d / r for d, r in zip(cpu["direct"], cpu["rows"])]
    q = statistics.quantiles(ratio, n=4)
    particles = models["rows"][1]
    return {"particles": particles, "steps_per_block": steps, "blocks_per_mode": len(ratio),
            "cpu_s_per_block": {m: statistics.median(v) for m, v in cpu.items()},
            "particle_steps_per_cpu_s": {m: particles * steps / statistics.median(v) for m, v in cpu.items()},
            "direct_over_rows_time": {"median": statistics.median(ratio), "quartiles": [q[0], q[2]],
                                      "min": min(ratio), "max": max(ratio)}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default="seismic,plain")
    ap.add_argument("--rounds", type=int, default=12)
    ap.add_argument("--threads", type=int, default=2, help="numba threads for the plain problem (2)")
    ap.add_argument("--cache", type=Path, default=HERE / "runs" / "seismic" / "cache")
    ap.add_argument("--out", type=Path)
    args = ap.parse_args()
    import numba

    out = {"load_average_1min_before": os.getloadavg()[0]}
    for name in args.models.split(","):
        threads = 1 if name == "seismic" else args.threads
        numba.set_num_threads(threads)
        models = seismic_models(args.cache) if name == "seismic" else plain_models(30_000)
        out[name] = interleave(models, 200 if name == "seismic" else 100, args.rounds) | {"threads": threads}
        print(name, json.dumps(out[name]), flush=True)
    out["load_average_1min_after"] = os.getloadavg()[0]
    if args.out:
        args.out.write_text(json.dumps(out, indent=1) + "\n")
    os._exit(0)


if __name__ == "__main__":
    main()
