"""A uniform surcharge on the settled backfill, carried by its top layer of grains.

The plan of the fill (L x w) is cut into square-ish cells about 1.5 of the largest
grain across; the grain that reaches highest in each cell takes the cell's share of
q L w as a constant downward force (dem3d external force, kept through checkpoints).
The fill then settles under it and the at-rest load is measured again. A plate would
spread the load by its stiffness; loaded grains spread it by their contacts, as a
surcharge of fill would.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

import dem3d
from analytic.constants import G

from ..granular.load import wall_load
from ..granular.recipe import frictional_law
from ..granular.specimen import Specimen, box_walls, specimen_key
from ..store import Store, content_key


def top_layer_forces(x: np.ndarray, r: np.ndarray, length: float, width: float, q: float) -> np.ndarray:
    """(n, 3) forces [N]: q [Pa] times the plan area L x w [m^2], shared equally among
    the cells of the plan, each cell's share on its highest-reaching sphere (cells with
    no sphere centre pass their share to the others)."""
    cell = 1.5 * 2.0 * float(r.max())
    nx, ny = max(1, int(round(length / cell))), max(1, int(round(width / cell)))
    ix = np.clip((x[:, 0] / length * nx).astype(int), 0, nx - 1)
    iy = np.clip((np.mod(x[:, 1], width) / width * ny).astype(int), 0, ny - 1)
    top = x[:, 2] + r
    highest = {}
    for k in np.argsort(top, kind="stable"):        # later (higher) overwrite lower
        highest[(ix[k], iy[k])] = k
    f = np.zeros((len(r), 3))
    share = q * length * width / len(highest)
    for k in highest.values():
        f[k, 2] = -share
    return f


def surcharge_key(case, q: float) -> str:
    return content_key({"specimen": specimen_key(case), "surcharge_Pa": q, "procedure": 1})


def load_or_surcharge(case, spec: Specimen, q: float, cache_dir: Path) -> tuple[Specimen, bool]:
    """The settled specimen under a surcharge ``q`` [Pa] (from ``cache_dir`` when made
    before): the top layer loaded (``top_layer_forces``), settled with the recipe's
    friction and local damping, then 2000 steps without local damping, and the at-rest
    thrust and resultant measured again (``Specimen.thrust_at_rest_kN`` includes the
    surcharge's share; ``K_at_rest`` is the thrust over 0.5 gamma H^2 + q H)."""
    store, key = Store(cache_dir), surcharge_key(case, q)
    found = store.load_arrays(key)
    if found is not None:
        state, info = found
        return dataclasses.replace(spec, state=state, **{k: v for k, v in info.items() if k in _REMEASURED}), True
    rec = case.specimen
    wall = dataclasses.replace(case.wall, width=spec.width)
    sim = dem3d.Simulation.from_arrays(spec.state, walls=box_walls(wall, rec))
    sph = sim.spheres
    f = top_layer_forces(sph.x, sph.r, wall.backfill_length, wall.width, q)
    sim.set_external_force(f, specimen_order=False)
    sim.set_params(frictional_law(rec, rec.local_damping))
    res = dem3d.settle(sim, ratio=rec.settle_ratio, check_every=500, max_steps=int(2.0 / sim.dt))
    sim.set_params(frictional_law(rec, 0.0))
    sim.step(2000)
    load = wall_load(dem3d.frame(sim), sim.walls.panel_ids("wall"), wall.height)
    H, w = wall.height, wall.width
    gamma = rec.density * (1.0 - spec.porosity) * G
    info = {"K_at_rest": load.normal / ((0.5 * gamma * H * H + q * H) * w),
            "resultant_height_over_H_at_rest": load.height / H, "thrust_at_rest_kN": load.normal / 1e3,
            "steps": spec.steps + res.steps + 2000, "sim_time": sim.time}
    out = dataclasses.replace(spec, state=sim.to_arrays(), **info)
    store.save_arrays(key, out.state, info)
    return out, False


_REMEASURED = ("K_at_rest", "resultant_height_over_H_at_rest", "thrust_at_rest_kN", "steps", "sim_time")
