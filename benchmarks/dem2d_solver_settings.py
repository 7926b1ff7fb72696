"""Solver-settings study for dem2d (the "before/after" figures of docs/dem2d.md).

Measured on one reduced-size settled specimen (Khosravi's box, grains 4x coarser,
the tests' fixture) restored from a snapshot for every variant, so only the setting
changes, never the packing:

1. step cost [ms CPU] against iterations, bounding-box tree vs spatial hash;
2. at-rest K of the upper half and the share of the weight carried by wall friction
   against dt (iterations 10) and against iterations (dt 2e-4);
3. the naive set-up of the first probe (shape friction 0.5 everywhere = pair
   friction 0.25, collision_slop 0.1 m, dt 1e-4, all grains poured at once) against
   the chosen one (pair friction 0.5, slop 2 % of r_min, dt 2e-4, layered pluviation):
   at-rest profile and wall time.

    PYTHONPATH=. python benchmarks/dem2d_solver_settings.py --out docs/validation/solver_settings
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from dem2d.measure import readings
from dem2d.params import Solver
from dem2d.pluviation import Pluviation
from studies.khosravi.run import KhosraviRun
from studies.measures import k_upper_half
from studies.khosravi.case import KhosraviCase
from dem2d.sim import restore

REDUCED = KhosraviCase(particles_scale=4.0, friction=0.5, seed=7, solver=Solver(dt=2e-4, iterations=10),
                       pluviation=Pluviation(layer_thickness=0.03))


def settled(case: KhosraviCase) -> tuple[bytes, float]:
    t0 = time.perf_counter()
    run = KhosraviRun(case)
    for _ in run.fill():
        pass
    run.sim.run(int(0.05 / case.solver.dt))
    return run.sim.snapshot(), time.perf_counter() - t0


def at_rest(blob: bytes, case: KhosraviCase, solver: Solver, settle: float = 0.1) -> dict:
    sim = restore(blob)
    sim.set_solver(solver)
    run = KhosraviRun(replace(case, solver=solver, window=0.04), sim=sim)
    sim.run(int(round(settle / solver.dt)))
    r = run.reading()
    z = run.panel_depths()
    bf = run.backfill
    d, m, ps0 = run.readings_of(r)
    return {"K_upper": k_upper_half(r.sigma, z, case.panel_height, bf.gamma, bf.H),
            "wall_friction_share": -r.wall_fy / bf.weight,
            "balance": -(r.floor_fy + r.wall_fy + r.far_fy) / bf.weight,
            "z_over_H": (d / bf.H).tolist(), "sigma_over_gammaH": (m / (bf.gamma * bf.H)).tolist()}


def step_cost(blob: bytes, iterations: int, spatial_hash: bool, steps: int = 150) -> float:
    sim = restore(blob)
    solver = replace(sim.solver, iterations=iterations, spatial_hash=spatial_hash)
    if not spatial_hash:
        # restore() honours solver.spatial_hash only at build time: rebuild with the tree
        import pickle
        payload = pickle.loads(blob)
        payload["sim"]["solver"] = solver
        sim = restore(pickle.dumps(payload))
    sim.set_solver(solver)
    sim.run(20)
    c0 = time.process_time()
    sim.run(steps)
    return (time.process_time() - c0) / steps * 1e3


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/validation/solver_settings")
    ap.add_argument("--skip-naive", action="store_true")
    a = ap.parse_args(argv)
    from viz.figures import plot_series

    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    blob, fill_s = settled(REDUCED)
    res = {"specimen": {"particles_scale": 4.0, "fill_wall_s": fill_s}, "step_cost_ms": {}, "dt": {}, "iterations": {}}
    its = [5, 10, 20, 40]
    for h in (False, True):
        res["step_cost_ms"]["hash" if h else "tree"] = [step_cost(blob, it, h) for it in its]
        print(res["step_cost_ms"], file=sys.stderr, flush=True)
    base = REDUCED.solver
    dts = [4e-4, 2e-4, 1e-4, 5e-5]
    for dt in dts:
        res["dt"][str(dt)] = at_rest(blob, REDUCED, replace(base, dt=dt))
        print(dt, res["dt"][str(dt)]["K_upper"], file=sys.stderr, flush=True)
    for it in (5, 10, 20, 40):
        res["iterations"][str(it)] = at_rest(blob, REDUCED, replace(base, iterations=it))
        print(it, res["iterations"][str(it)]["K_upper"], file=sys.stderr, flush=True)
    plot_series(its, {"bounding-box tree": res["step_cost_ms"]["tree"],
                      "spatial hash (cell = d_max)": res["step_cost_ms"]["hash"]},
                out / "step_cost_vs_iterations.png", xlabel="solver iterations",
                ylabel="CPU per step [ms]", title=f"Settled pile, reduced size (scale 4), dt 2e-4 s")
    plot_series(dts, {"K upper half": [res["dt"][str(d)]["K_upper"] for d in dts],
                      "wall friction / weight": [res["dt"][str(d)]["wall_friction_share"] for d in dts]},
                out / "at_rest_vs_dt.png", xlabel="dt [s]", ylabel="[-]", logx=True,
                title="Same settled packing, iterations 10")
    plot_series([5, 10, 20, 40], {"K upper half": [res["iterations"][str(i)]["K_upper"] for i in (5, 10, 20, 40)],
                                  "wall friction / weight": [res["iterations"][str(i)]["wall_friction_share"]
                                                             for i in (5, 10, 20, 40)]},
                out / "at_rest_vs_iterations.png", xlabel="solver iterations", ylabel="[-]",
                title="Same settled packing, dt 2e-4 s")
    if not a.skip_naive:
        naive = replace(REDUCED, friction=0.25, solver=Solver(dt=1e-4, iterations=10, slop_fraction=0.1 / (REDUCED.grading.d_min / 2),
                                                              spatial_hash=False),
                        pluviation=Pluviation(layer_thickness=0.3, drop_height=0.01))
        nblob, nfill = settled(naive)
        res["naive"] = {**at_rest(nblob, naive, naive.solver), "fill_wall_s": nfill}
        res["chosen"] = {**at_rest(blob, REDUCED, base), "fill_wall_s": fill_s}
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 6))
        for key, lab in (("naive", "before: pair mu 0.25, slop 0.1 m, dt 1e-4, one pour, BB-tree"),
                         ("chosen", "after: pair mu 0.5, slop 0.02 r_min, dt 2e-4, 30 mm layers, hash")):
            ax.plot(res[key]["sigma_over_gammaH"], res[key]["z_over_H"], "o-",
                    label=f"{lab}\nK upper {res[key]['K_upper']:.2f}, fill {res[key]['fill_wall_s']:.0f} s")
        ax.set_ylim(1.02, 0)
        ax.set_xlim(left=0)
        ax.set_xlabel("sigma_h / (gamma H)")
        ax.set_ylabel("z / H")
        ax.legend(fontsize=6)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(out / "before_after_at_rest.png", dpi=130)
        plt.close(fig)
    (out / "solver_settings.json").write_text(json.dumps(res, indent=2) + "\n")
    print(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
