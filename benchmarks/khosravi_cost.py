"""Where the full-size Khosravi run spends its CPU.

``fill``: the case's pluviation (default case, seed 1; held layers at 40 sweeps and
layer_dt 4e-4 s, the last layer released and settled at the run's dt), one row per
layer: grains, held grains, steps, CPU seconds. ``steps SPECIMEN.pkl``: one settled
specimen (a stored ``_specimens/<key>.pkl``) stepped 100 times at 1, 10, 40 and 80
solver sweeps after 20 steps to warm the contact cache: the intercept is what no sweep
count removes (broad and narrow phase, integration), the slope what a sweep costs.
CPU seconds from time.process_time; one process, nothing else of ours running.

    PYTHONPATH=. python benchmarks/khosravi_cost.py fill --out fill.json
    PYTHONPATH=. python benchmarks/khosravi_cost.py steps runs/.../_specimens/KEY.pkl --out steps.json
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import time


def fill_profile() -> list[dict]:
    from studies.khosravi.case import KhosraviCase
    from studies.khosravi.run import KhosraviRun
    run = KhosraviRun(KhosraviCase(seed=1))
    sim = run.sim
    rows, c_layer, t_layer = [], time.process_time(), sim.time
    for s in run.fill():
        if s.done:
            rows.append({"layer": s.layer, "grains": s.n_grains, "held": int(sim.held().sum()),
                         "steps": round((sim.time - t_layer) / sim.dt), "dt_s": sim.dt,
                         "cpu_s": time.process_time() - c_layer, "settled": s.settled})
            print(json.dumps(rows[-1]), flush=True)
            c_layer, t_layer = time.process_time(), sim.time
    return rows


def step_cost(specimen: str) -> list[dict]:
    from dem2d.sim import restore
    blob = open(specimen, "rb").read()
    rows = []
    for sweeps in (1, 10, 40, 80):
        sim = restore(blob)
        sim.set_solver(dataclasses.replace(sim.solver, iterations=sweeps))
        sim.run(20)
        c0 = time.process_time()
        sim.run(100)
        rows.append({"iterations": sweeps, "grains": len(sim.grains),
                     "cpu_ms_per_step": 1e3 * (time.process_time() - c0) / 100})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=("fill", "steps"))
    ap.add_argument("specimen", nargs="?", help="steps: a stored specimen (.pkl)")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    rows = fill_profile() if a.what == "fill" else step_cost(a.specimen)
    with open(a.out, "w") as fh:
        json.dump(rows, fh, indent=1)
    os._exit(0)          # freeing a 61k-disk pymunk space takes minutes (docs/dem2d.md)


if __name__ == "__main__":
    main()
