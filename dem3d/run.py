"""The run driver: advance a Simulation and yield immutable ``Frame`` snapshots.

The output cadence (``every``) is the caller's choice and independent of dt; the caller
decides what to log (``viz/`` reads Frames duck-typed). Nothing here writes or prints.
"""

from __future__ import annotations

from typing import Iterator

import numpy as np

from analytic.frame import Frame

from .engine import Simulation


def contacts(sim: Simulation) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Touching sphere pairs of the last force evaluation: (i (m,), j (m,), separation
    x_j - x_i with the minimum image (m, 3) [m], normal force (m,) [N])."""
    i, j, d, k = _touching(sim)
    return i, j, d, sim.pairs.pf[sim.pair_rows()[k], 6].copy()


def _touching(sim: Simulation):
    """(i, j, separation, pair index k) of every touching pair (engine order)."""
    prs = sim.pairs
    total = int(prs.start[-1])
    k = np.nonzero(prs.active[:total])[0]
    i = np.searchsorted(prs.start, k, side="right") - 1
    j = prs.nbr[k]
    x = sim.spheres.x
    return i, j, _minimum_image(sim, x[j] - x[i]), k


def _shear(force: np.ndarray, d: np.ndarray) -> np.ndarray:
    """(m,) magnitude of the part of each contact force (m,3) across the line of centres d (m,3)."""
    n = d / np.maximum(np.linalg.norm(d, axis=1), 1e-300)[:, None]
    along = np.einsum("md,md->m", force, n)
    return np.linalg.norm(force - along[:, None] * n, axis=1)


def _bonds(sim: Simulation) -> dict:
    """The Frame fields of the intact bonds: centres of both spheres (the second
    periodic-unwrapped) [m], normal force (compression +) and shear magnitude [N]."""
    b = sim.bonds
    if b is None:
        return {}
    intact = b.state > 0
    i, j = b.i[intact], b.j[intact]
    x = sim.spheres.x
    d = _minimum_image(sim, x[j] - x[i])
    return {"bond_a": x[i].copy(), "bond_b": x[i] + d, "bond_force": b.fn[intact].copy(),
            "bond_shear": np.linalg.norm(b.fs[intact], axis=1)}


def _minimum_image(sim: Simulation, d: np.ndarray) -> np.ndarray:
    """Separations d (m,3) wrapped to the shortest across the periodic axis, if any."""
    if sim.periodic is not None:
        ax = sim.periodic.axis
        length = sim.periodic.length
        d[:, ax] -= length * np.round(d[:, ax] / length)
    return d


def frame(sim: Simulation) -> Frame:
    """The current state as a Frame (all arrays copied). Sphere arrays are in the
    specimen's order whatever order the engine keeps internally (it re-sorts by cell for
    memory locality), so sphere k of every frame is the same grain."""
    i, j, d, k = _touching(sim)
    pf = sim.pairs.pf[sim.pair_rows()[k]]
    x = sim.spheres.x
    corners = sim.walls.corners()
    orig = sim.original_index

    def specimen_order(a):
        out = np.empty_like(a)
        out[orig] = a
        return out

    return Frame(step=int(sim.step_count), time=float(sim.time), positions=specimen_order(x),
                 radii=specimen_order(sim.spheres.r), velocities=specimen_order(sim.spheres.v),
                 body_id=specimen_order(orig[sim.spheres.body_id]), contact_a=x[i].copy(), contact_b=x[i] + d,
                 contact_force=pf[:, 6].copy(), panel_corners=corners, panel_normal=sim.walls.panels.normal.copy(),
                 panel_force=sim.panel_force.copy(), panel_moment=sim.panel_moment.copy(),
                 panel_area=sim.walls.areas(), particle_force=specimen_order(sim.spheres.f),
                 material=specimen_order(sim.spheres.mat), contact_shear=_shear(pf[:, 0:3], d), **_bonds(sim))


def run(sim: Simulation, n_steps: int, every: int) -> Iterator[Frame]:
    """Advance ``sim`` by ``n_steps`` steps, yielding a Frame before the first step and
    after every ``every`` steps (and after the last step if it is not a multiple)."""
    if every < 1:
        from analytic.errors import InvalidParameter
        raise InvalidParameter("every", every, ">= 1 step")
    yield frame(sim)
    done = 0
    while done < n_steps:
        k = min(every, n_steps - done)
        sim.step(k)
        done += k
        yield frame(sim)
