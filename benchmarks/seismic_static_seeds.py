"""Where the seismic model's preparation ends, seed by seed, in three arms: the default
contact sums by rows ("rows"), the direct sums ("direct", ``SeismicCase.direct_sums``),
and the rows with the first sphere of the first simulation (the rain) moved 1e-12 m
along +x ("nudged") or -x ("nudged_minus") before its first step: a perturbation and
nothing else, the control for the direct sums, whose forces equal the rows' to rounding;
"nudged_install": sphere 0 of the model with the wall installed (the third Simulation
built: rain, the porosity reader, then this one) moved 1e-12 m along +x, so the rain is
the default's bit for bit; "nudged_stiffen": sphere 0 of the rain moved 1e-12 m along +x
when the rain has come to rest, as its stiffening begins (its first ``set_params``).

Each run prepares the coarse default case from scratch (``studies.seismic.run.prepare``,
no cache: ~185 s of CPU on one thread), restores it as the shaking does
(``coupled``), evaluates the forces once and reads the wall (``measures.wall_reading``):
the back and front thrusts at the end of the static stage, prototype kN/m (model N/m x
N / 1000, N = ``case.scale_N``). One JSON line per run.

    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/seismic_static_seeds.py run 7 nudged >> runs.jsonl
    python benchmarks/seismic_static_seeds.py summary runs.jsonl [more.jsonl ...] --out seeds.json

    PYTHONPATH=. python benchmarks/seismic_static_seeds.py lateral 1-12 >> lateral.jsonl

``lateral`` reads the static states that the rows and direct runs left in the cache
(runs/seismic/cache; ``run`` does not write it, ``prepare`` with a cache does) and prints,
per seed and order of sums, sigma_xx / sigma_zz of vertical slices behind the wall (edges
``LATERAL_EDGES`` from its back face, model m) and in front (two halves), Love-Weber
(``dem3d.measure.slice_averages``), and sigma_xx behind [Pa, model].

``summary`` groups the lines by arm: each arm's values by seed, mean, standard deviation,
median, and for every pair of arms the Mann-Whitney U test (two-sided) and, over the seeds
both ran, how many seeds stand higher in the second arm; the run lines and any ``lateral``
lines follow as they are.
"""

from __future__ import annotations

import json
import sys
import time
from itertools import combinations

NUDGE_M = 1e-12
LATERAL_EDGES = (0.0, 0.03, 0.06, 0.1, 0.2, 0.3, 0.38)
ARMS = ("rows", "direct", "nudged", "nudged_minus", "nudged_install", "nudged_stiffen")


def nudge_simulation(dx: float, which: int = 0) -> None:
    """Move sphere 0 of the ``which``-th Simulation built in this process (0: the first)
    by ``dx`` [m] along x, once it is built."""
    import dem3d.engine as engine
    original = engine.Simulation.__init__
    done = []

    def init(self, *args, **kwargs):
        original(self, *args, **kwargs)
        done.append(True)
        if len(done) == which + 1:
            self.spheres.x[0, 0] += dx
            print(f"nudged sphere 0 of Simulation {which} ({self.n_spheres} spheres)", file=sys.stderr)
    engine.Simulation.__init__ = init


def nudge_at_stiffening(dx: float) -> None:
    """Move sphere 0 of the first Simulation built by ``dx`` [m] along x at its first
    ``set_params`` (the rain's stiffening, ``specimen.rain_deposit``)."""
    import dem3d.engine as engine
    original = engine.Simulation.set_params
    done = []

    def set_params(self, *args, **kwargs):
        if not done:
            done.append(True)
            self.spheres.x[0, 0] += dx
            print(f"nudged sphere 0 at t = {self.time:.5f} s ({self.n_spheres} spheres)", file=sys.stderr)
        return original(self, *args, **kwargs)
    engine.Simulation.set_params = set_params


def run(seed: int, arm: str) -> dict:
    from studies.seismic.case import SeismicCase
    from studies.seismic.measures import wall_reading
    from studies.seismic.run import coupled, prepare

    if arm == "nudged_stiffen":
        nudge_at_stiffening(NUDGE_M)
    elif arm.startswith("nudged"):
        nudge_simulation(-NUDGE_M if arm == "nudged_minus" else NUDGE_M, 2 if arm == "nudged_install" else 0)
    case = SeismicCase(seed=seed, direct_sums=arm == "direct")
    cpu = time.process_time()
    prepared = prepare(case, None)
    main, _, _, _ = coupled(case, prepared)
    main.evaluate_forces()
    reading = wall_reading(main, case, prepared.model)
    to_prototype = case.scale_N / 1000.0        # model N/m -> prototype kN/m (as compare.py)
    return {"seed": seed, "arm": arm, "back_kN_m": reading.thrust_back * to_prototype,
            "front_kN_m": reading.thrust_front * to_prototype,
            "porosity": prepared.info["porosity"], "installed_steps": prepared.info["installed_steps"],
            "cpu_s": time.process_time() - cpu}


def lateral(seed: int, direct: bool) -> dict:
    from pathlib import Path

    import numpy as np

    from dem3d.measure import slice_averages
    from studies.seismic.case import SeismicCase
    from studies.seismic.run import coupled, prepare

    case = SeismicCase(seed=seed, direct_sums=direct)
    prepared = prepare(case, Path("runs/seismic/cache"))
    main, _, _, _ = coupled(case, prepared)
    main.evaluate_forces()
    behind = slice_averages(main, 2 * case.wall_ball + np.array(LATERAL_EDGES),
                            case.retained_height * case.width, axis=0).stress
    front = slice_averages(main, np.array([-case.front, -case.front / 2, 0.0]),
                           case.front_height * case.width, axis=0).stress
    return {"seed": seed, "direct": direct, "K_behind": (behind[:, 0, 0] / behind[:, 2, 2]).tolist(),
            "K_front": (front[:, 0, 0] / front[:, 2, 2]).tolist(), "sxx_behind_Pa": (-behind[:, 0, 0]).tolist()}


def summary(records: list[dict]) -> dict:
    import numpy as np
    from scipy.stats import mannwhitneyu

    lines = [r for r in records if "arm" in r]
    slices = [r for r in records if "K_behind" in r]

    by_arm = {a: {int(r["seed"]): float(r["back_kN_m"]) for r in lines if r["arm"] == a} for a in ARMS}
    by_arm = {a: dict(sorted(v.items())) for a, v in by_arm.items() if v}
    arms = {}
    for a, values in by_arm.items():
        v = np.array(list(values.values()))
        arms[a] = {"back_kN_m_by_seed": values, "n": len(v), "mean": float(v.mean()),
                   "sd": float(v.std(ddof=1)) if len(v) > 1 else None, "median": float(np.median(v))}
    tests = []
    for a, b in combinations(by_arm, 2):
        u = mannwhitneyu(list(by_arm[a].values()), list(by_arm[b].values()), alternative="two-sided")
        common = sorted(set(by_arm[a]) & set(by_arm[b]))
        tests.append({"arms": [a, b], "mann_whitney_p": float(u.pvalue),
                      "seeds_both": len(common),
                      "seeds_second_higher": sum(by_arm[b][s] > by_arm[a][s] for s in common)})
    return {"quantity": "back-face thrust at the end of the static stage, prototype kN/m",
            "arms": arms, "tests": tests, "runs": lines,
            "lateral": {"edges_behind_m": list(LATERAL_EDGES), "states": slices} if slices else None}


def main(argv: list[str]) -> None:
    if len(argv) >= 3 and argv[0] == "run" and argv[2] in ARMS:
        print(json.dumps(run(int(argv[1]), argv[2])), flush=True)
        return
    if len(argv) == 2 and argv[0] == "lateral":
        first, last = (int(v) for v in argv[1].split("-"))
        for direct in (False, True):
            for seed in range(first, last + 1):
                print(json.dumps(lateral(seed, direct)), flush=True)
        return
    if len(argv) >= 2 and argv[0] == "summary":
        out = argv[argv.index("--out") + 1] if "--out" in argv else None
        files = [f for f in argv[1:] if f != "--out" and f != out]
        lines = [json.loads(s) for f in files for s in open(f) if s.strip()]
        result = summary(lines)
        text = json.dumps(result, indent=1)
        if out:
            with open(out, "w") as fh:
                fh.write(text + "\n")
        print(text)
        return
    sys.exit("usage: seismic_static_seeds.py run SEED rows|direct|nudged|nudged_minus|nudged_install|nudged_stiffen | lateral FIRST-LAST | summary FILE... [--out FILE]")


if __name__ == "__main__":
    main(sys.argv[1:])
