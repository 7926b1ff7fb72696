"""Grain-shape probe for the case-B gravel (issue 24): peak and critical-state angles of
the biaxial test at 35 kPa (``studies.elements.gravel_biaxial``, the calibration's test at a reduced
specimen) for each grain shape of ``dem2d.gravel`` (capsule, three-circle clump, rounded
hexagon; all in the AR 2.5 envelope, widths 10-16 mm), at the local frictions given, on
the seeds given; with steps per CPU second (the one-hour budget of a case-B wall).
Target (Colas, S-OET 4.1): peak 37.7 deg, critical state about 32 deg.

    PYTHONPATH=. python benchmarks/gravel_shape_probe.py --shapes capsule,clump3,hexagon \
        --frictions 45,72.8 --seeds 1,2 --width 0.5 --height 1.0 --out FILE
    PYTHONPATH=. python benchmarks/gravel_shape_probe.py --table docs/validation/gravel_shape_probe.json

(the committed file gathers several runs under "runs", each with its command; ``--table``
prints the markdown table of gravel_calibration_discussion.md from it).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
import pymunk

from dem2d.gravel import Gravel
from studies.elements.gravel_biaxial import GravelBiaxialCase
from dem2d.params import Solver
from studies.gravel.calibrate import GravelCalibration, biaxial_test
from studies.runfolder import git_revision


def table(path: str) -> str:
    """Markdown table: per specimen, strain, sweeps, shape and friction, the seed means (and
    per-seed values) of peak and critical state, inner porosity, steps and body-steps per CPU-s."""
    runs = json.load(open(path))["runs"]
    groups: dict = {}
    for r in runs:
        for t in r["rows"]:
            key = (tuple(r["specimen_m"]), r["max_strain"], r["iterations"], t["shape"], t["friction_deg"])
            groups.setdefault(key, []).append(t)
    order = {"capsule": 0, "clump3": 1, "hexagon": 2}
    lines = ["| specimen [m] (grains) | max strain | sweeps | shape | local friction | peak: mean (per seed) "
             "| critical state: mean (per seed) | porosity (inner) | steps/CPU-s | body-steps/CPU-s |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for key in sorted(groups, key=lambda k: (k[0], k[1], k[2], order[k[3]], k[4])):
        ts = groups[key]
        pk, cs = [t["phi_peak_deg"] for t in ts], [t["phi_cs_deg"] for t in ts]
        sps, n = float(np.mean([t["steps"] / t["cpu_time_s"] for t in ts])), ts[0]["n_grains"]
        lines.append(f"| {key[0][0]:g} x {key[0][1]:g} ({n}) | {key[1]:g} | {key[2]} | {key[3]} | {key[4]:g} | "
                     f"**{np.mean(pk):.1f}** ({', '.join(f'{x:.1f}' for x in pk)}) | "
                     f"**{np.mean(cs):.1f}** ({', '.join(f'{x:.1f}' for x in cs)}) | "
                     f"{np.mean([t['inner_porosity'] for t in ts]):.3f} | {sps:.0f} | {sps * n / 1e6:.2f} M |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--shapes", default="capsule,clump3,hexagon")
    ap.add_argument("--frictions", default="45,72.8")
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--width", type=float, default=0.5)
    ap.add_argument("--height", type=float, default=1.0)
    ap.add_argument("--max-strain", type=float, default=0.20)
    ap.add_argument("--iterations", type=int, default=40)
    ap.add_argument("--out")
    ap.add_argument("--table", metavar="JSON", help="print the markdown table of a probe file and stop")
    a = ap.parse_args()
    if a.table:
        print(table(a.table))
        return
    rows = []
    t0 = time.process_time()
    for shape in a.shapes.split(","):
        plan = GravelCalibration(gravel=Gravel(placement_friction_deg=45.0, shape=shape),
                                 biaxial=GravelBiaxialCase(width=a.width, height=a.height,
                                                           max_strain=a.max_strain,
                                                           solver=Solver(dt=5e-4, iterations=a.iterations,
                                                                         slop_fraction=0.02)))
        for mu in (float(x) for x in a.frictions.split(",")):
            for seed in (int(x) for x in a.seeds.split(",")):
                r = biaxial_test(plan, mu, seed)
                row = {"shape": shape, **{k: v for k, v in r.items() if k != "curve"},
                       "steps_per_cpu_s": r["steps"] / r["cpu_time_s"]}
                rows.append(row)
                print(json.dumps({k: (round(v, 4) if isinstance(v, float) else v) for k, v in row.items()}),
                      flush=True)
    out = {"script": "benchmarks/gravel_shape_probe.py", "git": git_revision(), "pymunk": pymunk.version,
           "specimen_m": [a.width, a.height], "max_strain": a.max_strain, "confining_Pa": 35e3, "dt_s": 5e-4,
           "iterations": a.iterations,
           "placement_friction_deg": 45.0, "rows": rows, "cpu_time_s": time.process_time() - t0}
    if a.out:
        with open(a.out, "w") as f:
            json.dump(out, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
