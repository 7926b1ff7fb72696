"""Speed of dem3d before/after the dynamics features (materials, bonds, external forces,
shaken walls, free-field boundaries), on the benchmark problem of studies/bench.py (30,000 settled spheres, one material, no bonds, 2 threads), plus a
bonded, two-material case of the same size.

Usage (from the repository root; ``--main`` is a checkout of the code to compare with,
e.g. ``git archive <commit> | tar -x -C /tmp/wallsim_main``):

    python benchmarks/dem3d_dynamics_speed.py --main /tmp/wallsim_main --steps 3000 --rounds 3

Each (code, case) runs in its own process (so each has its own numba cache and module
state), alternating main / this tree round after round on the same load; the warm-up
(compile or cache load, first neighbour list) is excluded as in studies/bench.py.
Prints one JSON line per run and a summary (median ns per particle-step).
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
import json, sys, time
import numba
import numpy as np
try:
    from studies import bench
except ImportError:                      # a checkout from before the study layer
    from workflows import bench
case, steps, threads = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
numba.set_num_threads(threads)
warm = bench.build_problem(10_000)
warm.step(3)
if case == "bonded":
    from dem3d import Periodic, Simulation, Specimen, Wall, linear, plane
    pos, radii = bench.read_packing(30_000)
    mat = (pos[:, 0] > 0.5 * bench.BOX_X).astype(np.int64)          # two materials, half each
    a = linear(8.3e6, 3.32e6, 0.65, c_n=487.0, c_s=0.0, coulomb="total")
    b = linear(1.66e7, 6.64e6, 0.4, c_n=487.0, c_s=0.0, coulomb="total")
    walls = [Wall("x0", plane((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), mu=0.65)),
             Wall("x1", plane((bench.BOX_X, 0.0, 0.0), (-1.0, 0.0, 0.0), mu=0.65)),
             Wall("floor", plane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), mu=0.65))]
    sim = Simulation(Specimen(pos, radii, -np.ones(len(radii), np.int64), bench.DENSITY), a, dt=bench.DT,
                     walls=walls, periodic=Periodic(1, 0.0, bench.PERIOD_Y), skin=bench.SKIN, materials=[a, b],
                     sphere_material=mat, wall_material={"floor": 1})
    wall_zone = np.nonzero(pos[:, 0] < 0.6)[0]                          # a bonded block (~1/6 of the spheres)
    area = np.pi * (0.5 * 0.03) ** 2                                   # bond of half a mean radius
    nb = sim.make_bonds(0.2 * bench.SKIN, kn=8.3e6 / area, ks=3.32e6 / area, radius_multiplier=0.5,
                        spheres=wall_zone)                            # kn A ~ the contact's kn
    sim.step(1)
else:
    sim = bench.build_problem(30_000)
    nb = 0
t = time.perf_counter()
sim.step(steps)
sec = time.perf_counter() - t
n = sim.n_spheres
print(json.dumps({"case": case, "n": n, "bonds": int(nb), "steps": steps, "seconds": sec,
                  "ns_per_particle_step": 1e9 * sec / (n * steps), "particle_steps_per_s": n * steps / sec}))
"""


def run(root: Path, case: str, steps: int, threads: int) -> dict:
    env = dict(os.environ, PYTHONPATH=str(root), NUMBA_CACHE_DIR=str(root / ".numba_cache"),
               NUMBA_NUM_THREADS=str(threads))
    out = subprocess.run([sys.executable, "-c", CHILD, case, str(steps), str(threads)], cwd=root, env=env,
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--main", type=Path, required=True, help="checkout of the code to compare with")
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    results: dict[str, list[float]] = {}
    for r in range(args.rounds):
        for label, root, case in (("main", args.main, "single"), ("branch", HERE, "single"),
                                  ("branch-bonded", HERE, "bonded")):
            res = run(root, case, args.steps, args.threads)
            res["code"] = label
            res["round"] = r
            print(json.dumps(res), flush=True)
            results.setdefault(label, []).append(res["ns_per_particle_step"])
    summary = {k: statistics.median(v) for k, v in results.items()}
    summary["branch_over_main"] = summary["branch"] / summary["main"]
    print(json.dumps({"median_ns_per_particle_step": summary}))


if __name__ == "__main__":
    main()
