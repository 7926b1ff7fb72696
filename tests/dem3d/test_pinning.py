"""Bit-for-bit pins of existing single-material runs (issue 22, hard constraint 1; issue 37).

Each case runs a few hundred steps of an existing code path and hashes the raw bytes of
its final state arrays (positions, velocities, spins, forces, torques, contact histories,
panel loads, clump poses). Any change to the arithmetic of the single-material path,
even in the last bit or the sign of a zero, changes a hash.

Recorded in the portable mode (reproducibility.py): they hold on any x86-64 CPU
(tests/dem3d/test_lesser_cpu.py checks them with numba on the baseline target and glibc's
SSE2 libm) and on Python 3.11 as on 3.12. Re-record (``python tests/dem3d/test_pinning.py``
in the portable mode: ``eval "$(wallsim env --exports)"``) only once a change's cause is
known. Last re-recorded when the clump check stopped reading stale positions (9f6519e)
and the portable mode came in.
"""

import hashlib

import numpy as np
import pytest

from dem3d import (Periodic, Simulation, Wall, box, hertz_mindlin, linear, prep, rotation, segmented_wall,
                   translation)
from tests.conftest import portable_only

KEYS = ("spheres.x", "spheres.v", "spheres.w", "spheres.f", "spheres.t", "clumps.x", "clumps.v", "clumps.q",
        "clumps.am", "pairs.nbr", "pairs.ut", "pairs.active", "pairs.pf", "wall_pairs.ut", "wall_pairs.out",
        "panels.centre", "panels.normal", "panel_force", "panel_moment", "time", "step")


def settled_packing():
    """Linear law with viscous and local damping: spheres rain into a closed box."""
    rng = np.random.default_rng(11)
    lo, hi = np.zeros(3), np.array([0.3, 0.3, 0.6])
    spec = prep.random_specimen(rng, lo, hi, 150, 0.04, 0.06)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5, zeta_n=0.2, zeta_s=0.1, local_damping=0.3), dt=4e-5,
                     walls=[Wall("box", box(lo, hi, mu=0.3))], gravity=(0.0, 0.0, -40.0))
    sim.step(4000)
    return sim


def wall_translation():
    """Hertz-Mindlin, periodic slab, a segmented wall translating away from the fill."""
    rng = np.random.default_rng(12)
    lo, hi = np.zeros(3), np.array([0.4, 0.2, 0.4])
    spec = prep.random_specimen(rng, lo, hi, 120, 0.03, 0.045)
    spec = spec._replace(velocities=rng.normal(0.0, 2.0, (len(spec.radii), 3)))
    walls = [Wall("box", box(lo, (0.4, 0.2, 1.0), mu=0.2, periodic_axis=1, omit=("x-",))),
             Wall("wall", segmented_wall((0.0, 0.1, 0.0), (1, 0, 0), (0, 0, 1), 0.2, 0.4, 4, mu=0.4,
                                         unbounded_width=True), translation((-0.05, 0.0, 0.0)))]
    sim = Simulation(spec, hertz_mindlin(7e7, 0.25, 0.5, zeta_n=0.1, zeta_s=0.1), dt=2e-5, walls=walls,
                     periodic=Periodic(1, 0.0, 0.2), sort_every=3, gravity=(0.0, 0.0, -300.0))
    sim.step(1200)
    return sim


def clumps_rotating_wall():
    """Clumps and spheres, periodic, a wall rotating about its base, LIGGGHTS Coulomb cap."""
    rng = np.random.default_rng(13)
    lo, hi = np.zeros(3), np.array([0.4, 0.2, 0.4])
    spec = prep.random_specimen(rng, lo, hi, 100, 0.03, 0.045, clump_fraction=0.5)
    spec = spec._replace(velocities=rng.normal(0.0, 2.0, (len(spec.radii), 3)))
    walls = [Wall("box", box(lo, (0.4, 0.2, 1.0), mu=0.2, periodic_axis=1)),
             Wall("wall", segmented_wall((0.0, 0.1, 0.0), (1, 0, 0), (0, 0, 1), 0.2, 0.4, 4, mu=0.4,
                                         unbounded_width=True), rotation((0.0, 0.1, 0.0), (0, 1, 0), -0.5))]
    sim = Simulation(spec, linear(1e5, 4e4, 0.5, c_n=2.0, c_s=1.0, coulomb="total"), dt=3e-5, walls=walls,
                     periodic=Periodic(1, 0.0, 0.2), sort_every=4, gravity=(0.0, 0.0, -300.0))
    sim.step(1200)
    return sim


CASES = {"settled_packing": settled_packing, "wall_translation": wall_translation,
         "clumps_rotating_wall": clumps_rotating_wall}

PINNED = {
    "settled_packing": "a633275b5f10754cbe5a56e405addae212585822c8cdd7232615dea5844aa8d7",
    "wall_translation": "d55280bb9d6b5760cca73a229719ebadc8c4a98557ab5d9c28f59fd72b010d21",
    "clumps_rotating_wall": "21851d924b72470ba23eccf46ad7983093b79cccb1fb91aaf1a90499fdcf2b19",
}


def state_hash(sim) -> str:
    arrays = sim.to_arrays()
    h = hashlib.sha256()
    for k in KEYS:
        a = np.ascontiguousarray(arrays[k])
        h.update(k.encode())
        h.update(str(a.dtype).encode() + str(a.shape).encode())
        h.update(a.tobytes())
    return h.hexdigest()


@portable_only
@pytest.mark.parametrize("name", list(CASES))
def test_single_material_runs_are_bitwise_those_of_main(name):
    sim = CASES[name]()
    assert sim.n_rebuilds > 0 and np.count_nonzero(sim.pairs.active) > 10
    assert state_hash(sim) == PINNED[name]


if __name__ == "__main__":      # re-record (prints the dict to paste above)
    import reproducibility
    assert reproducibility.describe()["mode"] == "portable", 'record pins in the portable mode: eval "$(wallsim env --exports)"'
    print({name: state_hash(build()) for name, build in CASES.items()})
