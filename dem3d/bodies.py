"""The bodies of a ``Simulation``: free spheres and rigid clumps built from a specimen
(contiguous runs of one clump label) with the masses, inertias and body frames the
kernels integrate; the checks that a periodic boundary and the panels agree with them;
and what a caller changes on them between steps (density, locks, spheres carried by a
wall). Nothing here steps."""

from __future__ import annotations

import math

import numpy as np

from analytic.errors import InvalidParameter

from . import kernels
from .clumps import clump_properties, matrix_to_quaternion, principal_frame
from .state import Clumps, Periodic, Spheres
from .walls import WallSet


def gather_ranges(starts: np.ndarray, ends: np.ndarray, order: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Concatenate the index ranges [starts[b], ends[b]) for b in ``order``: (new_to_old,
    where each body starts in the new order)."""
    length = (ends - starts)[order]
    new_start = np.zeros(len(order), np.int64)
    np.cumsum(length[:-1], out=new_start[1:])
    within = np.arange(int(length.sum()), dtype=np.int64) - np.repeat(new_start, length)
    return (np.repeat(starts[order], length) + within).astype(np.int64), new_start


def body_ranges(labels: np.ndarray) -> list[tuple[int, int]]:
    """[start, end) sphere ranges of bodies: each free sphere alone, each clump's run."""
    n = labels.shape[0]
    ranges = []
    i = 0
    seen = set()
    while i < n:
        lab = labels[i]
        if lab < 0:
            ranges.append((i, i + 1))
            i += 1
            continue
        if lab in seen:
            raise InvalidParameter("clump", int(lab), "contiguous spheres per clump label")
        seen.add(lab)
        j = i
        while j < n and labels[j] == lab:
            j += 1
        ranges.append((i, j))
        i = j
    return ranges


def check_periodic(periodic: Periodic, r_max: float, skin: float) -> None:
    if periodic.axis not in (0, 1, 2):
        raise InvalidParameter("periodic.axis", periodic.axis, "0, 1 or 2")
    need = 3.0 * (2.0 * r_max + skin)
    if not periodic.length >= need:
        raise InvalidParameter("periodic.length", periodic.length, f">= {need:.4g} m",
                               "three cells of 2 r_max + skin")


def check_panels_periodic(walls: WallSet, axis: int) -> None:
    """A panel may not end inside the periodic direction: coordinates along it are only
    defined modulo the period, so any in-plane extent with a component along the axis
    must be unbounded."""
    pan = walls.panels
    for p in range(walls.n_panels):
        for e, half in ((pan.e1[p], pan.half[p, 0]), (pan.e2[p], pan.half[p, 1])):
            if abs(e[axis]) > 1e-12 and np.isfinite(half):
                raise InvalidParameter(f"panel {p} half extent", float(half),
                                       "np.inf along the periodic axis (use unbounded_width / periodic_axis)")


def build_bodies(pos, radii, labels, vel, density) -> tuple[Spheres, Clumps]:
    n = pos.shape[0]
    bodies = body_ranges(labels)
    sph_mass = density * 4.0 / 3.0 * math.pi * radii ** 3
    inv_m = 1.0 / sph_mass
    inv_i = 1.0 / (0.4 * sph_mass * radii ** 2)
    clump_of = -np.ones(n, np.int64)
    body_id = np.arange(n, dtype=np.int64)
    x = pos.copy()
    v = vel.copy()
    offsets = np.zeros((n, 3))
    cl_x, cl_v, cl_q, cl_im, cl_ii = [], [], [], [], []
    clump_ranges = [(a, b) for a, b in bodies if labels[a] >= 0]
    for c, (a, b) in enumerate(clump_ranges):
        props = clump_properties(pos[a:b], radii[a:b], density)
        moments, axes = principal_frame(props.inertia)
        q = matrix_to_quaternion(axes)
        b_off = (pos[a:b] - props.centre) @ axes          # body-frame offsets
        offsets[a:b] = b_off
        # place members exactly where the kernel will (x = X + R b)
        for m in range(a, b):
            x[m] = props.centre + kernels.quat_rotate(q[0], q[1], q[2], q[3], *b_off[m - a])
        vc = vel[a:b].mean(axis=0)
        v[a:b] = vc
        cl_x.append(props.centre)
        cl_v.append(vc)
        cl_q.append(q)
        cl_im.append(1.0 / props.mass)
        cl_ii.append(1.0 / moments)
        clump_of[a:b] = c
        body_id[a:b] = a
        inv_m[a:b] = 1.0 / props.mass
        inv_i[a:b] = 0.0
    nc = len(clump_ranges)
    spheres = Spheres(x=np.ascontiguousarray(x), v=np.ascontiguousarray(v), w=np.zeros((n, 3)),
                      r=radii.copy(), inv_m=inv_m, inv_i=inv_i, clump=clump_of, body_id=body_id,
                      f=np.zeros((n, 3)), t=np.zeros((n, 3)), x_ref=x.copy(), mat=np.zeros(n, np.int32),
                      f_ext=np.zeros((n, 3)))
    clumps = Clumps(x=np.array(cl_x, float).reshape(nc, 3), v=np.array(cl_v, float).reshape(nc, 3),
                    am=np.zeros((nc, 3)), w=np.zeros((nc, 3)), q=np.array(cl_q, float).reshape(nc, 4),
                    inv_m=np.array(cl_im, float).reshape(nc), inv_i=np.array(cl_ii, float).reshape(nc, 3),
                    members=np.array(clump_ranges, np.int64).reshape(nc, 2), offset=offsets)
    return spheres, clumps


def set_density(sim, spheres, density: float) -> None:
    """Give free spheres (specimen indices) their own density [kg/m^3]: mass
    rho 4/3 pi r^3 and moment of inertia 2/5 m r^2 (e.g. the balls of a bonded
    structure heavier than the grains). Locked translations or rotations stay locked.
    The time-step checks still use the specimen's density: a denser ball is safer,
    a lighter one needs the caller's own margin."""
    density = float(density)
    if not (density > 0 and math.isfinite(density)):
        raise InvalidParameter("density", density, "> 0 kg/m^3")
    engine = np.empty(sim.n_spheres, np.int64)
    engine[sim.original_index] = np.arange(sim.n_spheres)
    rows = engine[np.asarray(spheres, np.int64).reshape(-1)]
    sph = sim.spheres
    if np.any(sph.clump[rows] >= 0):
        raise InvalidParameter("spheres", "clump members", "free spheres")
    m = density * 4.0 / 3.0 * math.pi * sph.r[rows] ** 3
    sph.inv_m[rows] = np.where(sph.inv_m[rows] > 0, 1.0 / m, 0.0)
    sph.inv_i[rows] = np.where(sph.inv_i[rows] > 0, 1.0 / (0.4 * m * sph.r[rows] ** 2), 0.0)


def lock(sim, spheres=None, *, translation: bool = False, rotation: bool = True) -> None:
    """Lock the translation and/or rotation of free spheres (indices, default all)
    and of the clumps they belong to."""
    sph = sim.spheres
    idx = np.arange(sim.n_spheres) if spheres is None else np.asarray(spheres, np.int64)
    for i in idx:
        c = sph.clump[i]
        if c < 0:
            if translation:
                sph.inv_m[i] = 0.0
                sph.v[i] = 0.0
            if rotation:
                sph.inv_i[i] = 0.0
                sph.w[i] = 0.0
        else:
            members = slice(sim.clumps.members[c, 0], sim.clumps.members[c, 1])
            if translation:
                sim.clumps.inv_m[c] = 0.0
                sim.clumps.v[c] = 0.0
                sph.inv_m[members] = 0.0
            if rotation:
                sim.clumps.inv_i[c] = 0.0
                sim.clumps.am[c] = 0.0
                sim.clumps.w[c] = 0.0
                sph.w[members] = 0.0


def attach_to_wall(sim, spheres, wall: str) -> None:
    """Carry free spheres (specimen indices) rigidly with a wall's translation (e.g. a
    layer of grains glued to a shaken base to make it rough): they are locked
    (translation and rotation) and move by the wall's pivot displacement each step
    with its half-step velocity (``kernels.move_attached``); wall rotation is not
    applied to them."""
    if wall not in sim.walls.names:
        raise InvalidParameter("wall", wall, ", ".join(sim.walls.names))
    idx = np.asarray(spheres, np.int64).reshape(-1)
    engine = np.empty(sim.n_spheres, np.int64)
    engine[sim.original_index] = np.arange(sim.n_spheres)
    rows = engine[idx]
    if np.any(sim.spheres.clump[rows] >= 0):
        raise InvalidParameter("spheres", "clump members", "free spheres")
    sim.lock(rows, translation=True, rotation=True)
    k = sim.walls.names.index(wall)
    old_s, old_w = sim.attached if sim.attached is not None else (np.zeros(0, np.int64),) * 2
    sim.attached = (np.concatenate([old_s, rows]).astype(np.int64),
                     np.concatenate([old_w, np.full(len(rows), k, np.int64)]))
