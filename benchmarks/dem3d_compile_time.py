"""CPU time numba spends compiling dem3d's time step cold, this tree against another
checkout: what a user's first run of a study waits for, and what a test suite on a
fresh machine pays once per kind of model.

Usage (from the repository root; ``--main`` is a checkout of the code to compare with,
e.g. ``git worktree add /tmp/wallsim_main <commit>``):

    python benchmarks/dem3d_compile_time.py --main /tmp/wallsim_main --rounds 2

Each run is a fresh process with an empty numba cache (a new temporary NUMBA_CACHE_DIR)
that builds the 10,000-sphere benchmark problem of studies/bench.py in the four kinds
the studies use, one after the other, and steps each twice: one material with the
pair rows (the Nadukuru, heap and wall studies), one material with the direct sums, two
materials with the rows, two materials with the direct sums (the seismic case). It
records the process CPU time [s] after each kind (compiling dominates: the steps are
few), so the first figure is one study's cold start and the increments say what each
further kind of model adds. Runs alternate main / this tree, round after round.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent.parent

CHILD = r"""
import json, time
import numpy as np
from studies import bench
from dem3d import Periodic, Simulation, Specimen, Wall, linear, plane

def model(two_materials, direct):
    if not two_materials:
        return bench.build_problem(10_000, direct_sums=direct)
    pos, radii = bench.read_packing(10_000)
    a = linear(8.3e6, 3.32e6, 0.65, c_n=487.0, c_s=0.0, coulomb="total")
    b = linear(1.66e7, 6.64e6, 0.4, c_n=487.0, c_s=0.0, coulomb="total")
    walls = [Wall("x0", plane((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), mu=0.65)),
             Wall("x1", plane((bench.BOX_X, 0.0, 0.0), (-1.0, 0.0, 0.0), mu=0.65)),
             Wall("floor", plane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), mu=0.65))]
    return Simulation(Specimen(pos, radii, -np.ones(len(radii), np.int64), bench.DENSITY), a, dt=bench.DT,
                      walls=walls, periodic=Periodic(1, 0.0, bench.PERIOD_Y), skin=bench.SKIN, materials=[a, b],
                      sphere_material=(pos[:, 0] > 0.5 * bench.BOX_X).astype(np.int64),
                      wall_material={"floor": 1}, direct_sums=direct)

out = {"start": time.process_time()}
for name, two, direct in (("one material, rows", False, False), ("one material, direct sums", False, True),
                          ("two materials, rows", True, False), ("two materials, direct sums", True, True)):
    sim = model(two, direct)
    sim.step(2)
    out[name] = time.process_time()
print(json.dumps(out))
"""


def run(root: Path) -> dict:
    with tempfile.TemporaryDirectory(prefix="numba_cold_") as cache:
        env = dict(os.environ, PYTHONPATH=str(root), NUMBA_CACHE_DIR=cache, NUMBA_NUM_THREADS="2")
        out = subprocess.run([sys.executable, "-c", CHILD], cwd=root, env=env, capture_output=True, text=True,
                             check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--main", type=Path, required=True, help="checkout of the code to compare with")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--out", type=Path, help="write every run and the summary to this JSON file")
    args = ap.parse_args()
    runs = []
    for k in range(args.rounds):
        for code, root in (("main", args.main.resolve()), ("tree", HERE)):
            r = run(root) | {"code": code, "round": k}
            print(json.dumps(r), flush=True)
            runs.append(r)
    kinds = [key for key in runs[0] if key not in ("start", "code", "round")]
    summary = {code: {kind: statistics.median(r[kind] for r in runs if r["code"] == code) for kind in kinds}
               for code in ("main", "tree")}
    print(json.dumps({"median_cpu_s_after_each_kind": summary}))
    if args.out is not None:
        args.out.write_text(json.dumps({"runs": runs, "summary": summary}, indent=2) + "\n")


if __name__ == "__main__":
    main()
