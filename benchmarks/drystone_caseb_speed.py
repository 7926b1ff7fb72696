"""Speed of the dry-stone case-B fill at full size (issue 24): stages of C2S (h 2.5 m,
b 0.60 m, reference 3.3 back-fit) with the full gravel (10-16 mm), our calibrated local
frictions (interface 75 deg: the value of the first calibration run; 84.6 now), 40 sweeps,
the hold (0.5 m below the surface, 1.5 m from the inner face),
until a CPU budget is spent. Per stage: grains, free grains, steps, CPU seconds, steps
and body-steps (steps x free grains) per CPU second, thrust, its height, and the
vertical reactions over the weight (about 0.54 with the hold: held grains carry their
own weight). Then the estimate of one wall from the measured body-steps rate.

    PYTHONPATH=. python benchmarks/drystone_caseb_speed.py --cpu 600 --out docs/validation/drystone_caseb_speed.json
"""

from __future__ import annotations

import argparse
import json
import time

import pymunk

from analytic.drystone import WallSection
from studies.drystone.backfill import BackfilledWall, FillPlan
from dem2d.blocks import BlockSolver, Masonry
from dem2d.gravel import Gravel
from studies.runfolder import git_revision


def run(cpu_budget: float, iterations: int, hold: float | None) -> list[dict]:
    sec = WallSection(2.5, 0.60, 8.53, 0.0, 8.53)
    g = Gravel(friction_deg=72.8, interface_friction_deg=75.0, placement_friction_deg=45.0)
    t0 = time.process_time()
    bw = BackfilledWall.build(sec, Masonry(friction_deg=25, block_length_m=0.33, block_height_m=0.12,
                                           first_course_fixed=False), g, FillPlan(hold_depth_m=hold),
                              solver=BlockSolver(dt=5e-4, iterations=iterations), seed=1)
    rows = []
    while time.process_time() - t0 < cpu_budget and not bw.failed:
        s0, c0 = bw.wall.steps, time.process_time()
        r = bw.stage()
        dc, ds = time.process_time() - c0, bw.wall.steps - s0
        free = sum(1 for b in bw.bodies if b.body_type == pymunk.Body.DYNAMIC)
        rows.append({"H": r["backfill_height_m"], "grains": r["grains"], "free": free, "steps": ds,
                     "cpu": round(dc, 1), "steps_s": round(ds / dc, 1), "body_steps_s": round(ds * free / dc),
                     "thrust": round(r["thrust_N_m"]), "y": round(r["thrust_height_m"], 3), "settled": r["settled"],
                     "crest": r["crest_displacement_m"],
                     "rw": round((r["container_vertical_N_m"] + r["wall_vertical_N_m"]) / r["fill_weight_N_m"], 4)})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def estimate(rows: list[dict], stages: int = 28) -> dict:
    """CPU for ``stages`` stages: free grains grow by the measured mean per stage, each
    stage takes the measured mean steps, at the measured mean body-steps rate."""
    rate = sum(r["body_steps_s"] for r in rows[1:]) / max(len(rows) - 1, 1)
    grow = (rows[-1]["free"] - rows[0]["free"]) / max(len(rows) - 1, 1)
    steps = sum(r["steps"] for r in rows[1:]) / max(len(rows) - 1, 1)
    cpu = sum(steps * (rows[0]["free"] + grow * k) / rate for k in range(stages)) + rows[0]["cpu"]
    return {"stages": stages, "body_steps_per_cpu_s": rate, "free_grains_per_stage": grow,
            "steps_per_stage": steps, "cpu_s": cpu, "free_grains_last": rows[0]["free"] + grow * (stages - 1)}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cpu", type=float, default=600.0)
    ap.add_argument("--iterations", type=int, default=40)
    ap.add_argument("--hold", type=float, default=0.5)
    ap.add_argument("--out")
    a = ap.parse_args()
    rows = run(a.cpu, a.iterations, a.hold if a.hold > 0 else None)
    out = {"script": "benchmarks/drystone_caseb_speed.py", "git": git_revision(), "iterations": a.iterations,
           "dt_s": 5e-4, "hold_depth_m": a.hold, "rows": rows, "estimate_28_stages": estimate(rows)}
    if a.out:
        with open(a.out, "w") as f:
            json.dump(out, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
