"""CPU and wall time of the seismic study's static state (``studies.seismic.run.prepare``:
deposit rained and settled, wall installed, front excavated, both free-field columns),
stage by stage, with the porosity reached and the steps each settling took.

    NUMBA_NUM_THREADS=2 PYTHONPATH=. python benchmarks/seismic_prep_time.py --grain-scale 3 \\
        --out docs/validation/seismic_prep_time.json
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numba

from studies.seismic.case import SeismicCase
from studies.seismic.run import prepare


def main() -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grain-scale", type=float, default=3.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default=None, help="JSON file (default: stdout)")
    args = ap.parse_args()
    case = SeismicCase(grain_scale=args.grain_scale, seed=args.seed)
    marks = []
    wall0, cpu0 = time.perf_counter(), time.process_time()

    def log(msg: str) -> None:
        marks.append({"stage_done": msg, "wall_s": round(time.perf_counter() - wall0, 1),
                      "cpu_s": round(time.process_time() - cpu0, 1)})
        print(marks[-1], flush=True)

    load_before = os.getloadavg()
    prep = prepare(case, None, log=log)
    result = {"grain_scale": case.scale, "seed": args.seed, "numba_threads": numba.get_num_threads(),
              "load_average_1min_before_after": [round(load_before[0], 2), round(os.getloadavg()[0], 2)],
              "wall_s": round(time.perf_counter() - wall0, 1), "cpu_s": round(time.process_time() - cpu0, 1),
              "main_spheres": int(prep.main["spheres.x"].shape[0]),
              "column_spheres": [int(c["spheres.x"].shape[0]) for c in prep.columns],
              "marks": marks, "info": {k: v for k, v in prep.info.items() if k != "x_wall_before_excavation"}}
    text = json.dumps(result, indent=1)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text + "\n")
    print(text)
    return result


if __name__ == "__main__":
    main()
