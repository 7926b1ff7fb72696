"""Checkpoints of a ``Simulation``: its whole state as plain numpy arrays (``to_arrays``)
and back (``from_arrays``), from which a run resumes bitwise identically."""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from analytic.errors import InvalidParameter

from .params import N_PARAM_FIELDS, ContactParams
from .state import Bonds, Clumps, Pairs, Periodic, Spheres, WallPairs
from .neighbours import empty_pairs, empty_wall_pairs
from .walls import Wall, WallSet

STATE_VERSION = 1


def to_arrays(sim) -> dict[str, np.ndarray]:
    """The full state as a dict of numpy arrays (copies): spheres, clumps, neighbour
    lists with contact history, panels and wall pivots, time, step, parameters.
    Save it with ``np.savez``; ``from_arrays`` resumes bitwise identically. Wall motions
    are functions and are not stored: pass the same ``walls`` again."""
    out: dict[str, np.ndarray] = {"version": np.array(STATE_VERSION)}
    used = {"pairs": int(sim.pairs.start[-1]), "wall_pairs": int(sim.wall_pairs.start[-1])}
    for prefix, rec in (("spheres", sim.spheres), ("clumps", sim.clumps), ("pairs", sim.pairs),
                        ("wall_pairs", sim.wall_pairs), ("panels", sim.walls.panels)):
        for name, arr in rec._asdict().items():
            if prefix in used and name not in ("start", "tstart", "slab_start", "slab_sphere"):
                arr = arr[:used[prefix]]          # drop the spare capacity
            out[f"{prefix}.{name}"] = np.array(arr, copy=True)
    for name, value in sim.params._asdict().items():
        out[f"params.{name}"] = np.array(value)
    if sim.mtab is not None:
        out["materials"] = sim.mtab.copy()
    if sim.bonds is not None:
        for name, arr in sim.bonds._asdict().items():
            out[f"bonds.{name}"] = np.array(arr, copy=True)
        out["dt_critical_bonds"] = np.array(sim.dt_critical_bonds)
    out["use_f_ext"] = np.array(sim.use_f_ext)
    if sim.attached is not None:
        out["attached.spheres"], out["attached.walls"] = (a.copy() for a in sim.attached)
    out["walls.pivot"] = sim.walls.pivot.copy()
    out["walls.ref_centre"], out["walls.ref_e1"], out["walls.ref_e2"] = (a.copy() for a in sim.walls._ref)
    out["panel_force"] = sim.panel_force.copy()
    out["panel_moment"] = sim.panel_moment.copy()
    out["original_index"] = sim.original_index.copy()
    scalars = {"time": sim.time, "step": sim.step_count, "dt": sim.dt, "skin": sim.skin,
               "density": sim.density, "dt_critical": sim.dt_critical, "n_rebuilds": sim.n_rebuilds,
               "need_rebuild": sim._need_rebuild, "spheres_per_thread": sim.spheres_per_thread,
               "sort_every": sim.sort_every, "direct_sums": sim.direct_sums}
    for name, value in scalars.items():
        out[name] = np.array(value)
    out["gravity"] = sim.gravity.copy()
    out["periodic"] = (np.array([-1.0, 0.0, 1.0]) if sim.periodic is None
                       else np.array([sim.periodic.axis, sim.periodic.lo, sim.periodic.length], float))
    return out


def from_arrays(cls, arrays, walls: Sequence[Wall] = ()):
    """Rebuild a Simulation from ``to_arrays`` output (or a loaded .npz). ``walls`` must
    be the same wall groups (same panel count and order) to re-attach their motions;
    the stored panel poses replace the geometry given in ``walls``; their friction must
    match the stored one (to change a wall's friction, edit ``arrays["panels.mu"]``)."""
    # copies: the caller's arrays (e.g. a cached specimen shared by several runs) must
    # not be advanced by this simulation
    a = {k: np.array(arrays[k], copy=True) for k in arrays}
    if int(a["version"]) != STATE_VERSION:
        raise InvalidParameter("version", int(a["version"]), f"{STATE_VERSION}")
    sim = cls.__new__(cls)
    a.setdefault("params.mu_roll", np.array(0.0))                    # states saved before rolling resistance
    sim.params = ContactParams(**{f: a[f"params.{f}"].item() for f in ContactParams._fields})
    n_sph = a["spheres.x"].shape[0]
    a.setdefault("spheres.mat", np.zeros(n_sph, np.int32))          # states saved before materials
    a.setdefault("spheres.f_ext", np.zeros((n_sph, 3)))
    a.setdefault("panels.mat", np.zeros(a["panels.centre"].shape[0], np.int32))
    sim.spheres = Spheres(**{f: np.ascontiguousarray(a[f"spheres.{f}"]) for f in Spheres._fields})
    sim.mtab = a["materials"].copy() if "materials" in a else None
    if sim.mtab is not None and sim.mtab.shape[-1] < N_PARAM_FIELDS:   # saved before rolling resistance
        sim.mtab = np.concatenate([sim.mtab, np.zeros(sim.mtab.shape[:2] + (1,))], axis=-1)
    sim.bonds = (Bonds(**{f: np.ascontiguousarray(a[f"bonds.{f}"]) for f in Bonds._fields})
                  if "bonds.i" in a else None)
    sim.dt_critical_bonds = float(a["dt_critical_bonds"]) if "dt_critical_bonds" in a else math.inf
    sim.use_f_ext = bool(a["use_f_ext"]) if "use_f_ext" in a else False
    sim.attached = ((a["attached.spheres"].astype(np.int64), a["attached.walls"].astype(np.int64))
                     if "attached.spheres" in a else None)
    sim.clumps = Clumps(**{f: np.ascontiguousarray(a[f"clumps.{f}"]) for f in Clumps._fields})
    n = sim.spheres.x.shape[0]
    a.setdefault("pairs.slab_start", np.zeros(1, np.int64))          # states saved before the slabs
    a.setdefault("pairs.slab_sphere", np.zeros(0, np.int64))
    sim._pair_bufs = [Pairs(**{f: np.ascontiguousarray(a[f"pairs.{f}"]) for f in Pairs._fields}),
                       empty_pairs(n, 0)]
    sim._fit_history()
    sim._wall_bufs = [WallPairs(**{f: np.ascontiguousarray(a[f"wall_pairs.{f}"]) for f in WallPairs._fields}),
                       empty_wall_pairs(n, 0)]
    sim._cur = 0
    sim._wcur = 0
    sim._rows = np.empty((n, 16), np.int64)
    sim.walls = WallSet(walls)
    if sim.walls.n_panels != a["panels.centre"].shape[0]:
        raise InvalidParameter("walls", f"{sim.walls.n_panels} panels",
                               f"the {a['panels.centre'].shape[0]} panels of the checkpoint")
    if not np.array_equal(sim.walls.panels.mu, a["panels.mu"]):
        # the stored friction would silently win over the one the caller asked for
        raise InvalidParameter("walls", f"panel friction {sim.walls.panels.mu.tolist()}",
                               f"the checkpoint's {a['panels.mu'].tolist()} (edit arrays['panels.mu'] to change it)")
    for f in sim.walls.panels._fields:
        getattr(sim.walls.panels, f)[...] = a[f"panels.{f}"]
    sim.walls.pivot[...] = a["walls.pivot"]
    sim.walls._ref = (a["walls.ref_centre"].copy(), a["walls.ref_e1"].copy(), a["walls.ref_e2"].copy())
    sim.panel_force = a["panel_force"].copy()
    sim.panel_moment = a["panel_moment"].copy()
    sim.original_index = a["original_index"].copy()
    sim.time = float(a["time"])
    sim.step_count = int(a["step"])
    sim.dt = float(a["dt"])
    sim.skin = float(a["skin"])
    sim.density = float(a["density"])
    sim.dt_critical = float(a["dt_critical"])
    sim.n_rebuilds = int(a["n_rebuilds"])
    sim._need_rebuild = bool(a["need_rebuild"])
    sim.spheres_per_thread = int(a["spheres_per_thread"])
    sim.sort_every = int(a["sort_every"])
    sim.direct_sums = bool(a["direct_sums"]) if "direct_sums" in a else False
    sim.gravity = a["gravity"].astype(float).copy()
    per = a["periodic"]
    sim.periodic = None if per[0] < 0 else Periodic(int(per[0]), float(per[1]), float(per[2]))
    return sim
