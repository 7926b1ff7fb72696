"""The run driver: advance a Simulation and yield immutable ``Frame`` snapshots.

The output cadence (``every``) is the caller's choice and independent of dt; the caller
decides what to log (``viz/`` reads Frames duck-typed). Nothing here writes or prints.
"""

from __future__ import annotations

from typing import Iterator, NamedTuple

import numpy as np

from .engine import Simulation


class Frame(NamedTuple):
    """A snapshot (copies, SI units) after ``step`` steps.

    step:           steps taken since the simulation was built
    time:           simulated time [s]
    positions:      (n, 3) sphere centres [m] (periodic coordinates may lie up to a skin
                    outside the periodic cell between neighbour-list builds)
    radii:          (n,) [m]
    velocities:     (n, 3) centre velocities [m/s] at time - dt/2 (leapfrog half step)
    body_id:        (n,) body of each sphere: the sphere's own index for a free sphere, the
                    index of the clump's first sphere for a clump member (sphere arrays are
                    in the specimen's order)
    contact_a:      (m, 3) centre of the first sphere of each touching sphere pair [m]
    contact_b:      (m, 3) centre of the second, periodic-unwrapped (b - a is the short
                    separation vector) [m]
    contact_force:  (m,) normal contact force [N], compression positive (the viscous part
                    may make it slightly negative while a contact opens)
    panel_corners:  (p, 4, 3) panel corners [m] (nominal extent for unbounded panels)
    panel_normal:   (p, 3) unit normals pointing from the wall into the particles
    panel_force:    (p, 3) force exerted BY the particles ON each panel [N]; pressing
                    particles give panel_force . panel_normal < 0
    panel_moment:   (p, 3) moment of that force about the panel's centre (the mean of its
                    corners) [N m]
    panel_area:     (p,) [m^2] (nominal for unbounded panels)

    Contact and panel forces are those of the last force evaluation, i.e. at time - dt.
    """

    step: int
    time: float
    positions: np.ndarray
    radii: np.ndarray
    velocities: np.ndarray
    body_id: np.ndarray
    contact_a: np.ndarray
    contact_b: np.ndarray
    contact_force: np.ndarray
    panel_corners: np.ndarray
    panel_normal: np.ndarray
    panel_force: np.ndarray
    panel_moment: np.ndarray
    panel_area: np.ndarray


def contacts(sim: Simulation) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Touching sphere pairs of the last force evaluation: (i (m,), j (m,), separation
    x_j - x_i with the minimum image (m, 3) [m], normal force (m,) [N])."""
    prs = sim.pairs
    total = int(prs.start[-1])
    k = np.nonzero(prs.active[:total])[0]
    i = np.searchsorted(prs.start, k, side="right") - 1
    j = prs.nbr[k]
    x = sim.spheres.x
    d = x[j] - x[i]
    if sim.periodic is not None:
        ax = sim.periodic.axis
        length = sim.periodic.length
        d[:, ax] -= length * np.round(d[:, ax] / length)
    return i, j, d, prs.pf[prs.tpos[k], 6].copy()


def frame(sim: Simulation) -> Frame:
    """The current state as a Frame (all arrays copied). Sphere arrays are in the
    specimen's order whatever order the engine keeps internally (it re-sorts by cell for
    memory locality), so sphere k of every frame is the same grain."""
    i, _, d, fn = contacts(sim)
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
                 contact_force=fn, panel_corners=corners, panel_normal=sim.walls.panels.normal.copy(),
                 panel_force=sim.panel_force.copy(), panel_moment=sim.panel_moment.copy(),
                 panel_area=sim.walls.areas())


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
