"""pymunk step speed on settled disk piles of about 10k, 30k and 50k grains.

Each pile is Khosravi et al.'s box (220 mm wide) filled to H = 0.3 m with grains scaled
so the count is close to the target (``--recipe layered``: the case's own fill, 20 mm
layers held below 20 mm, 40 sweeps a step; ``pour``: one damped layer, the first
version), settled, then timed over ``--steps`` steps with the settings of the Khosravi
run (dt 2e-4 s, spatial hash) at 10 and 40 iterations (``--iterations``), serial. CPU
time of this process is reported as well as wall time, because the machine may be
shared. Writes JSON to stdout (or --out).

    PYTHONPATH=. python benchmarks/dem2d_speed.py --sizes 10000,30000,50000 --out docs/validation/dem2d_speed.json
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from dataclasses import replace

from dem2d.grading import Grading
from dem2d.params import Solver
from dem2d.pluviation import Pluviation
from studies.khosravi.run import KhosraviRun
from studies.khosravi.case import KhosraviCase


def pile(n_target: int, seed: int = 1, recipe: str = "layered") -> KhosraviRun:
    """A settled pile of about ``n_target`` disks. ``layered``: the Khosravi case's own
    fill (``studies.khosravi.case.HELD_LAYERS`` and its solver); ``pour``: one damped layer (the
    first version of this benchmark; bodies then sit in memory in random order, which
    costs more per step)."""
    g = Grading(1.16e-3, 1.55)
    n_full = 0.22 * 0.3 * 0.82 / g.mean_area()
    scale = math.sqrt(n_full / n_target)
    case = KhosraviCase(particles_scale=scale, seed=seed)
    if recipe == "pour":
        plu = Pluviation(layer_thickness=0.3, drop_height=0.002, damping=0.05, final_ratio=0.02,
                         final_settle_time=0.6)
        case = replace(case, solver=Solver(dt=2e-4, iterations=10), pluviation=plu)
    run = KhosraviRun(case)
    for _ in run.fill():
        pass
    return run


def time_steps(run: KhosraviRun, iterations: int, steps: int) -> dict:
    sim = run.sim
    sim.set_solver(replace(sim.solver, iterations=iterations))
    sim.run(20)
    c0, t0 = time.process_time(), time.perf_counter()
    sim.run(steps)
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    n = len(sim.grains)
    return {"iterations": iterations, "grains": n, "steps": steps,
            "cpu_s_per_step": cpu / steps, "wall_s_per_step": wall / steps,
            "steps_per_s_cpu": steps / cpu, "body_steps_per_s_cpu": n * steps / cpu,
            "steps_per_s_wall": steps / wall, "body_steps_per_s_wall": n * steps / wall,
            "load_average_1min": os.getloadavg()[0]}  # > 1 here: another job shared the cores


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10000,30000,50000")
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--recipe", choices=("layered", "pour"), default="layered")
    ap.add_argument("--iterations", default="10,40", help="sweeps per step to time")
    ap.add_argument("--out")
    a = ap.parse_args(argv)
    rows = []
    for n in (int(x) for x in a.sizes.split(",")):
        t0 = time.perf_counter()
        c0 = time.process_time()
        run = pile(n, recipe=a.recipe)
        fill, fill_cpu = time.perf_counter() - t0, time.process_time() - c0
        for it in (int(x) for x in a.iterations.split(",")):
            r = time_steps(run, it, a.steps)
            r.update(fill_wall_s=fill, fill_cpu_s=fill_cpu, recipe=a.recipe)
            rows.append(r)
            print(json.dumps(r), file=sys.stderr, flush=True)
    import pymunk
    out = {"pymunk": pymunk.version, "dt": 2e-4, "broad_phase": "spatial hash (cell = d_max)",
           "note": "settled piles in Khosravi's box; serial; CPU time of this process on a 2-core VM; "
                   "load_average_1min per row says whether another job shared it",
           "rows": rows}
    text = json.dumps(out, indent=2)
    if a.out:
        with open(a.out, "w") as fh:
            fh.write(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)  # freeing a 50k-disk space is quadratic in pymunk (docs/dem2d.md): skip it
