"""The dem3d speed benchmark against LIGGGHTS on the same problem (benchmarks/liggghts).

Problem (benchmarks/liggghts/README.md): a settled packing of N spheres (diameters
0.05-0.07 m, density 2650) between walls at x = 0 and x = 3.5 m, on a floor at z = 0,
periodic in y over 0.5 m, gravity 9.81; Hookean contact kn = 8.3e6 N/m, kt = 3.32e6 N/m,
mu = 0.65 (walls too), absolute normal damping 487 N s/m, no tangential damping,
tangential history capped by mu |F_n| including the viscous part (as LIGGGHTS does; PFC and
dem3d's default cap on the elastic part only, which gave ~4 % less kinetic energy after
1000 steps); dt = 2e-5 s; zero initial velocities and no shear history.

Timing: wallsim excludes JIT compilation (a warm-up run compiles or loads the kernels
first) and set-up (building the first neighbour list), as LIGGGHTS' "Loop time" excludes
its set-up. Both engines run in the same process tree one after the other; on a shared
machine compare the ratio, not the absolute rates.
"""

from __future__ import annotations

import functools
import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

from analytic.errors import InvalidParameter

BENCH_DIR = Path(__file__).resolve().parent.parent / "benchmarks" / "liggghts"
LIGGGHTS = "liggghts"
BOX_X = 3.5
PERIOD_Y = 0.5
DT = 2e-5
SKIN = 0.01
DENSITY = 2650.0


class EngineRun(NamedTuple):
    """One timed run: wall seconds of the stepping loop, particle-steps per second, and the
    state after it for the physics cross-check (translational and rotational kinetic
    energy [J], sphere-sphere contacts counted per sphere, 2 x touching pairs, as
    LIGGGHTS' compute contact/atom summed over atoms); ``cpu_seconds``: CPU time of the
    stepping loop, every thread (wallsim), or of the whole LIGGGHTS process tree, every
    rank, its set-up included."""

    n: int
    steps: int
    seconds: float
    particle_steps_per_s: float
    kinetic_energy: float
    rotational_energy: float
    contacts: int
    cpu_seconds: float | None = None


def read_packing(n: int, copies_y: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Positions (N, 3) [m] and radii (N,) [m] of the settled packing of ``n`` spheres
    (``settled_<n>.data``: ``id type diameter density x y z``), replicated ``copies_y``
    times along the periodic y axis (the packing is periodic in y, so the copies join
    seamlessly; period = copies_y x 0.5 m)."""
    path = BENCH_DIR / f"settled_{n}.data"
    if not path.exists():
        raise InvalidParameter("n", n, "10000 or 30000 (a settled_<n>.data in benchmarks/liggghts)")
    rows = np.loadtxt(path, skiprows=11)
    rows = rows[np.argsort(rows[:, 0])]
    pos = rows[:, 4:7]
    radii = 0.5 * rows[:, 2]
    if copies_y > 1:
        pos = np.concatenate([pos + [0.0, k * PERIOD_Y, 0.0] for k in range(copies_y)])
        radii = np.tile(radii, copies_y)
    return pos, radii


def build_problem(n: int, copies_y: int = 1, direct_sums: bool = False):
    """The benchmark problem as a dem3d Simulation (``direct_sums``: Simulation's)."""
    from dem3d import Periodic, Simulation, Specimen, Wall, linear, plane

    pos, radii = read_packing(n, copies_y)
    spec = Specimen(pos, radii, -np.ones(len(radii), np.int64), DENSITY)
    params = linear(8.3e6, 3.32e6, 0.65, c_n=487.0, c_s=0.0, coulomb="total")   # LIGGGHTS' Coulomb cap
    walls = [Wall("x0", plane((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), mu=0.65)),
             Wall("x1", plane((BOX_X, 0.0, 0.0), (-1.0, 0.0, 0.0), mu=0.65)),
             Wall("floor", plane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), mu=0.65))]
    return Simulation(spec, params, dt=DT, walls=walls, periodic=Periodic(1, 0.0, PERIOD_Y * copies_y),
                      skin=SKIN, direct_sums=direct_sums)


def _summary(sim, n: int, steps: int, seconds: float, cpu_seconds: float | None = None) -> EngineRun:
    from dem3d.measure import kinetic_energy

    sph = sim.spheres
    m = 1.0 / sph.inv_m
    ke = 0.5 * float(np.sum(m * np.sum(sph.v ** 2, axis=1)))
    total = kinetic_energy(sim)
    pairs = int(np.count_nonzero(sim.pairs.active[:sim.pairs.start[-1]]))
    return EngineRun(n, steps, seconds, n * steps / seconds, ke, total - ke, 2 * pairs, cpu_seconds)


def time_wallsim(n: int, steps: int, threads: int, copies_y: int = 1, direct_sums: bool = False) -> EngineRun:
    """Time ``steps`` steps of the benchmark in dem3d on ``threads`` numba threads."""
    import numba

    if threads > numba.config.NUMBA_NUM_THREADS:
        raise InvalidParameter("threads", threads, f"<= {numba.config.NUMBA_NUM_THREADS} (NUMBA_NUM_THREADS)")
    numba.set_num_threads(threads)
    warm = build_problem(10_000, direct_sums=direct_sums)      # compiles (or loads from the cache) every kernel
    warm.step(3)
    sim = build_problem(n, copies_y, direct_sums)
    start, cpu = time.perf_counter(), time.process_time()
    sim.step(steps)
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    return _summary(sim, n * copies_y, steps, seconds, cpu)


_LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms")


def _launcher(ranks: int) -> list[str]:
    """The MPI launch prefix for ``ranks`` > 1 LIGGGHTS processes (none for one)."""
    if ranks == 1:
        return []
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        raise InvalidParameter("liggghts_ranks", ranks, "1 (no mpirun installed)")
    root = ["--allow-run-as-root"] if hasattr(os, "geteuid") and os.geteuid() == 0 else []
    return [mpirun, "-np", str(ranks), *root]


def run_liggghts(n: int, steps: int, executable: str = LIGGGHTS, ranks: int = 1) -> EngineRun:
    """Run LIGGGHTS on the same problem exactly as benchmarks/liggghts/README.md says, on
    ``ranks`` MPI processes, and parse its ``Loop time`` and final thermo line (step atoms
    ke rke contacts cpu)."""
    exe = shutil.which(executable)
    if exe is None:
        raise InvalidParameter("liggghts", executable, "an installed LIGGGHTS (apt-get install liggghts)",
                               "or pass --no-liggghts")
    launch = _launcher(ranks)
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("bench.in", "model.in", f"settled_{n}.data"):
            shutil.copy(BENCH_DIR / name, tmp)
        cmd = [*launch, exe, "-in", "bench.in", "-var", "MODEL", "model.in", "-var", "DATA", f"settled_{n}.data",
               "-var", "DT", f"{DT:g}", "-var", "NRUN", str(steps), "-var", "SKIN", f"{SKIN:g}",
               "-log", "none", "-echo", "none"]
        before = _children_cpu()
        out = subprocess.run(cmd, cwd=tmp, capture_output=True, text=True, check=True).stdout
        cpu = _children_cpu() - before
    loop = _LOOP.search(out)
    if loop is None:
        raise RuntimeError("LIGGGHTS printed no 'Loop time' line: " + out[-300:].replace("\n", " | "))
    seconds = float(loop.group(1))
    thermo = [line.split() for line in out.splitlines()
              if line.split()[:1] == [str(steps)] and len(line.split()) == 6]
    step, atoms, ke, rke, contacts, _ = thermo[-1]
    return EngineRun(int(atoms), steps, seconds, int(atoms) * steps / seconds, float(ke), float(rke),
                     int(float(contacts)), cpu)


def _children_cpu() -> float:
    """User + system CPU seconds of the finished child processes so far."""
    import resource
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def bench_dem3d(n: int = 30_000, steps: int = 5_000, threads: int = 2, liggghts: bool = True,
                ranks: int | None = None, pairs: int = 3, *, direct_sums: bool = False, engines=None) -> dict:
    """Both engines on the same problem, core for core (LIGGGHTS on ``ranks`` MPI
    processes, default as many as dem3d's ``threads``), as ``pairs`` interleaved pairs
    (wallsim, LIGGGHTS, wallsim, LIGGGHTS, ...): a shared machine's speed drifts between
    runs by tens of per cent, so only figures taken side by side compare. The dict has
    the medians the CLI's --json prints (wallsim_particle_steps_per_s,
    liggghts_particle_steps_per_s, ratio: the median of the pairs' ratios) with their
    min-max, every pair, CPU seconds, and the physics cross-check of the last pair.
    ``direct_sums``: dem3d's Simulation option. ``engines``: (wallsim runner, LIGGGHTS
    runner) to time, for tests."""
    ranks = threads if ranks is None else ranks
    time_ours, time_theirs = engines or (functools.partial(time_wallsim, direct_sums=direct_sums), run_liggghts)
    runs = []
    for _ in range(pairs):
        ours = time_ours(n, steps, threads)
        theirs = time_theirs(n, steps, ranks=ranks) if liggghts else None
        runs.append((ours, theirs))
    ours, theirs = runs[-1]

    def spread(values) -> dict:
        v = [x for x in values if x is not None]
        return {"median": float(np.median(v)), "min": float(min(v)), "max": float(max(v))} if v else None

    ps_ours = spread(o.particle_steps_per_s for o, _ in runs)
    ps_theirs = spread(t.particle_steps_per_s for _, t in runs) if liggghts else None
    ratios = spread(o.particle_steps_per_s / t.particle_steps_per_s for o, t in runs) if liggghts else None
    return {
        "n": n, "steps": steps, "threads": threads, "liggghts_ranks": ranks if liggghts else None, "pairs": pairs,
        "direct_sums": direct_sums,
        "wallsim_particle_steps_per_s": ps_ours["median"],
        "liggghts_particle_steps_per_s": ps_theirs["median"] if ps_theirs else None,
        "ratio": ratios["median"] if ratios else None,
        "spread": {"wallsim_particle_steps_per_s": ps_ours, "liggghts_particle_steps_per_s": ps_theirs,
                   "ratio": ratios,
                   "wallsim_cpu_seconds": spread(o.cpu_seconds for o, _ in runs),
                   "liggghts_cpu_seconds": spread(t.cpu_seconds for _, t in runs) if liggghts else None},
        "runs": [{"wallsim_particle_steps_per_s": o.particle_steps_per_s, "wallsim_seconds": o.seconds,
                  "wallsim_cpu_seconds": o.cpu_seconds,
                  "liggghts_particle_steps_per_s": t.particle_steps_per_s if t else None,
                  "liggghts_seconds": t.seconds if t else None, "liggghts_cpu_seconds": t.cpu_seconds if t else None}
                 for o, t in runs],
        "wallsim_seconds": ours.seconds,
        "liggghts_seconds": theirs.seconds if theirs else None,
        "check": {
            "wallsim": {"kinetic_energy_J": ours.kinetic_energy, "rotational_energy_J": ours.rotational_energy,
                        "contacts": ours.contacts},
            "liggghts": ({"kinetic_energy_J": theirs.kinetic_energy, "rotational_energy_J": theirs.rotational_energy,
                          "contacts": theirs.contacts} if theirs else None),
        },
    }


def scaling(steps: int = 500, threads: int = 2) -> list[dict]:
    """Time per step versus N: the 10k and 30k packings and the 10k packing tiled 10 times
    along the periodic axis (100k spheres, period 5 m)."""
    rows = []
    for n, copies in ((10_000, 1), (30_000, 1), (10_000, 10)):
        run = time_wallsim(n, steps, threads, copies_y=copies)
        rows.append({"n": run.n, "steps": steps, "threads": threads,
                     "ms_per_step": 1e3 * run.seconds / steps,
                     "ns_per_particle_step": 1e9 * run.seconds / (steps * run.n),
                     "particle_steps_per_s": run.particle_steps_per_s})
    return rows
