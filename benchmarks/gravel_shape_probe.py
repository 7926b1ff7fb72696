"""Grain-shape probe for the case-B gravel (issue 24): peak and critical-state angles of
the biaxial test at 35 kPa (``dem2d.gravel_biaxial``, the calibration's test at a reduced
specimen) for each grain shape of ``dem2d.gravel`` (capsule, three-circle clump, rounded
hexagon; all in the AR 2.5 envelope, widths 10-16 mm), at the local frictions given, on
the seeds given; with steps per CPU second (the one-hour budget of a case-B wall).
Target (Colas, S-OET 4.1): peak 37.7 deg, critical state about 32 deg.

    PYTHONPATH=. python benchmarks/gravel_shape_probe.py --shapes capsule,clump3,hexagon \
        --frictions 45,72.8 --seeds 1,2 --width 0.5 --height 1.0 --out docs/validation/gravel_shape_probe.json
"""

from __future__ import annotations

import argparse
import json
import time

import pymunk

from dem2d.gravel import Gravel
from dem2d.gravel_biaxial import GravelBiaxialCase
from studies.gravel.calibrate import GravelCalibration, biaxial_test
from studies.runfolder import git_revision


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--shapes", default="capsule,clump3,hexagon")
    ap.add_argument("--frictions", default="45,72.8")
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--width", type=float, default=0.5)
    ap.add_argument("--height", type=float, default=1.0)
    ap.add_argument("--max-strain", type=float, default=0.20)
    ap.add_argument("--out")
    a = ap.parse_args()
    rows = []
    t0 = time.process_time()
    for shape in a.shapes.split(","):
        plan = GravelCalibration(gravel=Gravel(placement_friction_deg=45.0, shape=shape),
                                 biaxial=GravelBiaxialCase(width=a.width, height=a.height,
                                                           max_strain=a.max_strain))
        for mu in (float(x) for x in a.frictions.split(",")):
            for seed in (int(x) for x in a.seeds.split(",")):
                r = biaxial_test(plan, mu, seed)
                row = {"shape": shape, **{k: v for k, v in r.items() if k != "curve"},
                       "steps_per_cpu_s": r["steps"] / r["cpu_time_s"]}
                rows.append(row)
                print(json.dumps({k: (round(v, 4) if isinstance(v, float) else v) for k, v in row.items()}),
                      flush=True)
    out = {"script": "benchmarks/gravel_shape_probe.py", "git": git_revision(), "pymunk": pymunk.version,
           "specimen_m": [a.width, a.height], "max_strain": a.max_strain, "confining_Pa": 35e3, "dt_s": 5e-4, "iterations": 40,
           "placement_friction_deg": 45.0, "rows": rows, "cpu_time_s": time.process_time() - t0}
    if a.out:
        with open(a.out, "w") as f:
            json.dump(out, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
