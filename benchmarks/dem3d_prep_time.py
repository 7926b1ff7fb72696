"""Wall and CPU time of the Nadukuru & Michalowski specimen preparation, stage by stage
(the goal: specimen preparation <= 15 min on this 2-core machine).

Runs ``studies.granular.specimen.prepare_specimen`` on the default recipe (rough wall, the
particle count and seed given) and writes, per stage, the steps, wall time, CPU time
(all threads: cpu / wall is the number of cores the stage kept busy) and the settle
trace (steps, unbalanced-force ratio, kinetic energy [J]), with the numba thread count
and threading layer and the machine's load average before and after, because the
machine is shared and a second job halves what one job gets.

    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/dem3d_prep_time.py --particles 30000 --seed 1 \\
        --out docs/validation/nadukuru_prep_time_1thread.json
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import time

import numba

from studies.granular import SpecimenRecipe
from studies.nadukuru.case import NadukuruCase
from studies.granular.specimen import prepare_specimen, specimen_key


def main() -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--particles", type=int, default=30_000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default=None, help="JSON file (default: stdout)")
    args = ap.parse_args()
    case = NadukuruCase(specimen=dataclasses.replace(SpecimenRecipe(), particles=args.particles),
                           seed=args.seed)
    load_before = os.getloadavg()
    wall0, cpu0 = time.perf_counter(), time.process_time()
    spec = prepare_specimen(case)
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    stages = {name: info for name, info in spec.stages.items() if isinstance(info, dict)}
    result = {
        "particles_requested": args.particles, "spheres": spec.n_spheres, "bodies": spec.n_bodies,
        "seed": args.seed, "specimen_key": specimen_key(case), "dt": spec.dt,
        "numba_threads": numba.get_num_threads(), "threading_layer": _threading_layer(),
        "cpu_count": os.cpu_count(), "machine": platform.processor() or platform.machine(),
        "load_average_1min_before_after": [round(load_before[0], 2), round(os.getloadavg()[0], 2)],
        "wall_s": round(wall, 1), "cpu_s": round(cpu, 1), "wall_min": round(wall / 60.0, 2),
        "porosity": spec.porosity, "K_at_rest": spec.K_at_rest, "settle_ratio_final": spec.settle_ratio,
        "stages": {name: {k: v for k, v in info.items() if k != "trace"} | {
            "final_ratio": info["trace"][-1][1] if info.get("trace") else None} for name, info in stages.items()},
        "traces": {name: info.get("trace", []) for name, info in stages.items()},
    }
    text = json.dumps(result, indent=1)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text + "\n")
    else:
        print(text)
    return result


def _threading_layer() -> str:
    try:
        return numba.threading_layer()
    except ValueError:          # no parallel region has run yet
        return "none"


if __name__ == "__main__":
    main()
