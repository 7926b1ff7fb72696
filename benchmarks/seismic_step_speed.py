"""Speed of the shaken seismic model (Sizkow & El Shamy), this tree against another
checkout: the default coarse case's static state (13,401 spheres, bonded sheet pile,
Hertz-Mindlin with rolling resistance, two free-field columns of 1,021 and 1,569 spheres)
stepped with its free-field boundaries exactly as ``studies.seismic.run.shake`` steps it
(``dem3d.freefield.step_coupled``, a refresh every ``free_field_every`` steps), one
numba thread.

Usage (from the repository root; ``--main`` is a checkout of the code to compare with,
e.g. ``git worktree add /tmp/wallsim_main <commit>``; the static state comes from the
cache that ``wallsim compare seismic`` or ``validate seismic`` leaves in runs/seismic/cache):

    python benchmarks/seismic_step_speed.py --main /tmp/wallsim_main --steps 2000 --pairs 3

Each (code) runs in its own process (its own numba cache and module state), the two
interleaved pair after pair (main, this tree, main, this tree, ...) on the same load;
the warm-up (compile or cache load, 50 coupled steps, then a rebuild of every neighbour
list, whose kernels the 50 steps may not reach: a freshly compiled tree's first run took
14.8 s against 8.5 s without it) is excluded. The rebuild reorders the pairs, so the
checksums differ from those of the JSON records made before it. The figure is
particle-steps (main model and columns) per CPU-second of the stepping (process time:
what a shared machine's wall clock inflates is left out). Each run also prints a
checksum of the final positions and velocities: equal checksums say the two codes
computed the same bits (``--tree-direct-sums``: this tree's runs add the pair forces on
the second sphere in the contact pass, ``Simulation.direct_sums``; other bits, so the
checksums differ in their last digits). Prints one JSON line per run and a summary (medians, min-max,
the ratio of each pair); ``--out FILE`` writes all of it as JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent.parent

CHILD = r"""
import json, os, sys, time
import numpy as np
from pathlib import Path
from studies.seismic.case import SeismicCase
from studies.seismic.run import prepare, coupled
try:
    from studies.seismic import specimen as M
except ImportError:                     # a checkout from before the study layout
    from studies.seismic import model as M
from dem3d.freefield import step_coupled, column_free_field
steps, cache, direct = int(sys.argv[1]), Path(sys.argv[2]), sys.argv[3] == "direct"
import dataclasses
# both sides from the static state the rows prepare (a tree from before direct_sums has no such field)
rows = {"direct_sums": False} if "direct_sums" in {f.name for f in dataclasses.fields(SeismicCase)} else {}
case = SeismicCase(**rows)
p = prepare(case, cache)
main, columns, bnds, _ = coupled(case, p)
if direct:
    for sim in (main, *columns):
        sim.direct_sums = True
edges = [M.lateral_edges(case, case.front_height), M.lateral_edges(case, case.retained_height)]
area = case.column_length * case.d_mean * case.width
free_field = lambda: [column_free_field(c, e, area) for c, e in zip(columns, edges)]
step_coupled(main, bnds, 50, free_field=free_field, columns=columns, every=case.free_field_every)
for sim in (main, *columns):        # the list-building kernels compile here, not in the timed steps
    sim._rebuild()
n = main.n_spheres + sum(c.n_spheres for c in columns)
cpu = time.process_time()
wall = time.perf_counter()
step_coupled(main, bnds, steps, free_field=free_field, columns=columns, every=case.free_field_every)
cpu = time.process_time() - cpu
wall = time.perf_counter() - wall
print(json.dumps({"particles": n, "main_spheres": main.n_spheres, "steps": steps, "cpu_seconds": cpu,
                  "wall_seconds": wall, "particle_steps_per_cpu_s": n * steps / cpu,
                  "checksum": [float(np.abs(main.spheres.x).sum()), float(np.abs(main.spheres.v).sum())],
                  "load_average_1min": os.getloadavg()[0]}))
"""


def run(root: Path, steps: int, cache: Path, direct: bool = False) -> dict:
    env = dict(os.environ, PYTHONPATH=str(root), NUMBA_CACHE_DIR=str(root / ".numba_cache"), NUMBA_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", CHILD, str(steps), str(cache), "direct" if direct else "rows"],
                         cwd=root, env=env,
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def spread(values: list[float]) -> dict:
    return {"median": statistics.median(values), "min": min(values), "max": max(values)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--main", type=Path, required=True, help="checkout of the code to compare with")
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--cache", type=Path, default=HERE / "runs" / "seismic" / "cache",
                    help="the seismic static-state cache (runs/seismic/cache)")
    ap.add_argument("--out", type=Path, help="write every run and the summary to this JSON file")
    ap.add_argument("--tree-direct-sums", action="store_true",
                    help="this tree's runs with Simulation.direct_sums (other bits: the checksums then differ)")
    args = ap.parse_args()
    runs = []
    for k in range(args.pairs):
        for label, root in (("main", args.main), ("tree", HERE)):
            direct = label == "tree" and args.tree_direct_sums
            res = run(root, args.steps, args.cache.resolve(), direct) | {"code": label, "pair": k, "direct_sums": direct}
            print(json.dumps(res), flush=True)
            runs.append(res)
    rate = {c: [r["particle_steps_per_cpu_s"] for r in runs if r["code"] == c] for c in ("main", "tree")}
    summary = {"particle_steps_per_cpu_s": {c: spread(v) for c, v in rate.items()},
               "tree_over_main": spread([t / m for m, t in zip(rate["main"], rate["tree"])]),
               "same_bits": len({tuple(r["checksum"]) for r in runs}) == 1}
    print(json.dumps(summary))
    if args.out:
        args.out.write_text(json.dumps({"steps": args.steps, "pairs": args.pairs,
                                        "tree_direct_sums": args.tree_direct_sums, "runs": runs,
                                        "summary": summary}, indent=1) + "\n")


if __name__ == "__main__":
    main()
