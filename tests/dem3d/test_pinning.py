"""Bit-for-bit pinning of existing single-material runs (issue 22, hard constraint 1).

The hashes below were recorded with the engine at main 9d8b6f6, before materials, bonds,
external forces, acceleration-driven walls and free-field boundaries were added. Each
case runs a few hundred steps of an existing code path and hashes the raw bytes of its
final state arrays (positions, velocities, spins, forces, torques, contact histories,
panel loads, clump poses). Any change to the arithmetic of the single-material path,
even in the last bit or the sign of a zero, changes a hash.

The hashes hold for this machine's numba/LLVM/libm (x86-64, numba 0.68, no fastmath);
on another platform re-record them at main's code with ``python tests/dem3d/test_pinning.py``.
"""

import hashlib

import numpy as np
import pytest

from dem3d import (Periodic, Simulation, Wall, box, hertz_mindlin, linear, prep, rotation, segmented_wall,
                   translation)

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
    "settled_packing": "b57660e85287848e96a286c9710300d345ea962c7202fa6354aabf1b9be94075",
    "wall_translation": "59d25a1fca18b8b9b9d50f188728e9f4cb4f10f4c56551b4711cbb8ffc0baae2",
    "clumps_rotating_wall": "7ee74c37a5078496de156451fe1da9fdd735b5d1db477f75a327dcc9d4d9380a",
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


@pytest.mark.parametrize("name", list(CASES))
def test_single_material_runs_are_bitwise_those_of_main(name):
    sim = CASES[name]()
    assert sim.n_rebuilds > 0 and np.count_nonzero(sim.pairs.active) > 10
    assert state_hash(sim) == PINNED[name]


if __name__ == "__main__":      # re-record (prints the dict to paste above)
    print({name: state_hash(build()) for name, build in CASES.items()})
