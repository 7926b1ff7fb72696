"""Measurements on a Simulation or a Frame, apart from the engine. Pure functions.

Sign conventions follow dem3d.walls: ``panel_force`` is the force BY the particles ON a
panel, the panel normal points into the particles, so the compressive normal stress on a
panel is -F . n / A.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from analytic.errors import InvalidParameter
from analytic.frame import panel_normal_stress  # noqa: F401 - re-exported, the one definition

from .engine import Simulation


# ---------------------------------------------------------------- energies and balance

def kinetic_energy(sim: Simulation) -> float:
    """Translational + rotational kinetic energy [J] of all movable bodies, from the stored
    (half-step, t - dt/2) velocities: free spheres m v^2/2 + I w^2/2, clumps M V^2/2 + L.w/2."""
    sph = sim.spheres
    free = (sph.clump < 0)
    e = 0.0
    with np.errstate(divide="ignore"):
        m = np.where(sph.inv_m > 0, 1.0 / np.where(sph.inv_m > 0, sph.inv_m, 1.0), 0.0)
        inertia = np.where(sph.inv_i > 0, 1.0 / np.where(sph.inv_i > 0, sph.inv_i, 1.0), 0.0)
    e += 0.5 * float(np.sum(m[free] * np.sum(sph.v[free] ** 2, axis=1)))
    e += 0.5 * float(np.sum(inertia[free] * np.sum(sph.w[free] ** 2, axis=1)))
    clu = sim.clumps
    if clu.x.shape[0]:
        mc = np.where(clu.inv_m > 0, 1.0 / np.where(clu.inv_m > 0, clu.inv_m, 1.0), 0.0)
        e += 0.5 * float(np.sum(mc * np.sum(clu.v ** 2, axis=1)))
        e += 0.5 * float(np.sum(np.sum(clu.am * clu.w, axis=1)))
    return e


def unbalanced_force_ratio(sim: Simulation) -> float:
    """PFC's "ratio-average": mean over movable bodies of |contact force + weight| divided
    by the mean contact force magnitude over all contacts (pairs and walls), from the
    last force evaluation. 0 at static equilibrium; ~1 in free motion. Returns inf when
    nothing touches."""
    sph = sim.spheres
    g = sim.gravity
    free = (sph.clump < 0) & (sph.inv_m > 0)
    unbal = []
    if free.any():
        m = 1.0 / sph.inv_m[free]
        unbal.append(np.linalg.norm(sph.f[free] + m[:, None] * g, axis=1))
    clu = sim.clumps
    movable = np.nonzero(clu.inv_m > 0)[0]
    if movable.size:
        fc = np.zeros((clu.x.shape[0], 3))
        members = sph.clump >= 0
        np.add.at(fc, sph.clump[members], sph.f[members])
        unbal.append(np.linalg.norm(fc[movable] + (1.0 / clu.inv_m[movable])[:, None] * g, axis=1))
    if not unbal:
        return 0.0
    mean_unbal = float(np.mean(np.concatenate(unbal)))
    prs = sim.pairs
    total = int(prs.start[-1])
    act = prs.active[:total].astype(bool)
    pair_f = np.linalg.norm(prs.pf[sim.pair_rows()[act], 0:3], axis=1)
    wps = sim.wall_pairs
    wtotal = int(wps.start[-1])
    wall_f = np.linalg.norm(wps.out[:wtotal][wps.active[:wtotal].astype(bool), 0:3], axis=1)
    allf = np.concatenate([pair_f, wall_f])
    if allf.size == 0 or float(np.mean(allf)) == 0.0:
        return math.inf
    return mean_unbal / float(np.mean(allf))




# ---------------------------------------------------------------- porosity

def porosity(sim: Simulation, lo, hi, cells_per_radius: int = 8) -> float:
    """Porosity of the axis-aligned box [lo, hi] [m]: 1 - solid volume / box volume.

    The solid is the union of all spheres, so overlaps (clump members, contacts) count
    once. Midpoint quadrature on a grid of spacing r_min / ``cells_per_radius``; the
    relative error of the solid volume is ~ the spacing over the grain size (grid error on
    the sphere surfaces), about 1e-3 at the default for 0.025-0.035 m grains.
    Periodic images are included along the periodic axis.
    """
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    if not np.all(hi > lo):
        raise InvalidParameter("hi - lo", tuple(hi - lo), "> 0 in every direction")
    x = sim.spheres.x
    r = sim.spheres.r
    if sim.periodic is not None:
        ax, plo, length = sim.periodic
        xw = x.copy()
        xw[:, ax] = plo + np.mod(xw[:, ax] - plo, length)
        shifts = [np.eye(3)[ax] * s * length for s in (-1.0, 1.0)]
        x = np.concatenate([xw] + [xw + s for s in shifts])
        r = np.concatenate([r, r, r])
    rmax = float(r.max())
    keep = np.all((x > lo - rmax) & (x < hi + rmax), axis=1)
    x = np.ascontiguousarray(x[keep])
    r = np.ascontiguousarray(r[keep])
    h = float(sim.spheres.r.min()) / cells_per_radius
    counts = np.maximum(1, np.round((hi - lo) / h)).astype(np.int64)
    step = (hi - lo) / counts
    if x.shape[0] == 0:
        return 1.0
    cell = 2.0 * rmax
    glo = lo - rmax
    nc = np.maximum(1, np.ceil((hi - lo + 2 * rmax) / cell)).astype(np.int64)
    inside = _grid_union_count(x, r, lo, step, counts, glo, cell, nc)
    return 1.0 - inside / float(np.prod(counts))


@njit(cache=True)
def _grid_union_count(x, r, lo, step, counts, glo, cell, nc):
    """Number of grid midpoints inside at least one sphere (cell list of the spheres)."""
    ncell = nc[0] * nc[1] * nc[2]
    head = -np.ones(ncell, np.int64)
    nxt = -np.ones(x.shape[0], np.int64)
    for s in range(x.shape[0]):
        c = np.empty(3, np.int64)
        for d in range(3):
            c[d] = min(max(int((x[s, d] - glo[d]) / cell), 0), nc[d] - 1)
        lin = (c[2] * nc[1] + c[1]) * nc[0] + c[0]
        nxt[s] = head[lin]
        head[lin] = s
    total = 0
    for a in range(counts[0]):
        px = lo[0] + (a + 0.5) * step[0]
        ca = min(max(int((px - glo[0]) / cell), 0), nc[0] - 1)
        for b in range(counts[1]):
            py = lo[1] + (b + 0.5) * step[1]
            cb = min(max(int((py - glo[1]) / cell), 0), nc[1] - 1)
            for cidx in range(counts[2]):
                pz = lo[2] + (cidx + 0.5) * step[2]
                cc = min(max(int((pz - glo[2]) / cell), 0), nc[2] - 1)
                found = False
                for oz in range(max(cc - 1, 0), min(cc + 2, nc[2])):
                    for oy in range(max(cb - 1, 0), min(cb + 2, nc[1])):
                        for ox in range(max(ca - 1, 0), min(ca + 2, nc[0])):
                            s = head[(oz * nc[1] + oy) * nc[0] + ox]
                            while s >= 0:
                                dx = px - x[s, 0]
                                dy = py - x[s, 1]
                                dz = pz - x[s, 2]
                                if dx * dx + dy * dy + dz * dz <= r[s] * r[s]:
                                    found = True
                                    break
                                s = nxt[s]
                            if found:
                                break
                        if found:
                            break
                    if found:
                        break
                if found:
                    total += 1
    return total


# ---------------------------------------------------------------- walls







def stress_ratio(frame, lateral_ids, base_ids) -> float:
    """Mean compressive normal stress on the ``lateral`` panels over that on the ``base``
    panels (each = total normal force / total area): the at-rest ratio sigma_h/sigma_v
    of a box specimen when the lateral panels are side walls and the base is the floor."""
    def mean_stress(ids):
        ids = np.asarray(ids, np.int64)
        fn = -np.einsum("ij,ij->i", frame.panel_force[ids], frame.panel_normal[ids])
        return float(fn.sum() / frame.panel_area[ids].sum())
    return mean_stress(lateral_ids) / mean_stress(base_ids)


def force_chains(frame, threshold="mean") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The strong contacts of a frame: (a (k, 3), b (k, 3), force (k,)) for the contacts
    whose normal force exceeds ``threshold`` ("mean" = the mean normal force, or a number
    in N). Forces above the mean form the strong network that carries the load
    (Radjai et al. 1998)."""
    f = frame.contact_force
    if f.size == 0:
        return frame.contact_a[:0], frame.contact_b[:0], f[:0]
    limit = float(np.mean(f)) if isinstance(threshold, str) and threshold == "mean" else float(threshold)
    keep = f > limit
    return frame.contact_a[keep], frame.contact_b[keep], f[keep]


# --------------------------------------------------------------------------------------
# slice averages (free-field columns), bonded-structure forces, strain, settlement
# --------------------------------------------------------------------------------------

def contact_branches(sim: Simulation) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every force acting at a contact point on a sphere, from the last evaluation:
    (sphere (m,) engine index, branch (m, 3) from the sphere's centre to the contact
    point [m], force on the sphere (m, 3) [N]); sphere pairs give two rows (one per
    sphere), panel contacts and intact parallel bonds likewise (bonds at their contact
    point, with their force; their moments are not contact forces and are left out)."""
    rows_s, rows_b, rows_f = [], [], []
    sph = sim.spheres
    prs = sim.pairs
    total = int(prs.start[-1])
    k = np.nonzero(prs.active[:total])[0]
    if len(k):
        i = np.searchsorted(prs.start, k, side="right") - 1
        j = prs.nbr[k]
        d = _min_image(sim, sph.x[j] - sph.x[i])
        dist = np.sqrt((d * d).sum(axis=1))
        n = d / dist[:, None]
        h = 0.5 * (sph.r[i] + sph.r[j] - dist)
        f_j = prs.pf[sim.pair_rows()[k], 0:3]
        rows_s += [i, j]
        rows_b += [(sph.r[i] - h)[:, None] * n, -(sph.r[j] - h)[:, None] * n]
        rows_f += [-f_j, f_j]
    wps = sim.wall_pairs
    wk = np.nonzero(wps.active[:int(wps.start[-1])])[0]
    if len(wk):
        i = np.searchsorted(wps.start, wk, side="right") - 1
        rows_s.append(i)
        rows_b.append(wps.out[wk, 3:6] - sph.x[i])
        rows_f.append(wps.out[wk, 0:3].copy())
    bnd = sim.bonds
    if bnd is not None and np.any(bnd.state == 1):
        b = np.nonzero(bnd.state == 1)[0]
        i, j = bnd.i[b], bnd.j[b]
        d = _min_image(sim, sph.x[j] - sph.x[i])
        dist = np.sqrt((d * d).sum(axis=1))
        n = d / dist[:, None]
        h = 0.5 * (sph.r[i] + sph.r[j] - dist)
        rows_s += [i, j]
        rows_b += [(sph.r[i] - h)[:, None] * n, -(sph.r[j] - h)[:, None] * n]
        rows_f += [bnd.out[b, 0:3].copy(), bnd.out[b, 6:9].copy()]
    if not rows_s:
        return np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros((0, 3))
    return np.concatenate(rows_s), np.concatenate(rows_b), np.concatenate(rows_f)


def _min_image(sim: Simulation, d: np.ndarray) -> np.ndarray:
    if sim.periodic is not None:
        ax, length = sim.periodic.axis, sim.periodic.length
        d = d.copy()
        d[:, ax] -= length * np.round(d[:, ax] / length)
    return d


@njit(cache=True)
def _branch(x, r, i, j, pax, plen):
    """Branches from the centres of i and j to their contact point (the middle of the
    overlap), as ``contact_branches`` computes them."""
    d0 = x[j, 0] - x[i, 0]
    d1 = x[j, 1] - x[i, 1]
    d2 = x[j, 2] - x[i, 2]
    if pax == 0:
        d0 -= plen * np.round(d0 / plen)
    elif pax == 1:
        d1 -= plen * np.round(d1 / plen)
    elif pax == 2:
        d2 -= plen * np.round(d2 / plen)
    dist = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    n0 = d0 / dist
    n1 = d1 / dist
    n2 = d2 / dist
    h = 0.5 * (r[i] + r[j] - dist)
    a = r[i] - h
    b = -(r[j] - h)
    return a * n0, a * n1, a * n2, b * n0, b * n1, b * n2


@njit(cache=True)
def _add_outer(stress, s, l0, l1, l2, f0, f1, f2):
    if s < 0 or s >= stress.shape[0]:
        return
    ls = (l0, l1, l2)
    fs = (f0, f1, f2)
    for a in range(3):
        for b in range(3):
            stress[s, a, b] += ls[a] * fs[b]


@njit(cache=True)
def _love_weber_sums(stress, slice_of, x, r, start, nbr, active, row, pf, wstart, wactive, wout,
                     bi, bj, bstate, bout, pax, plen):
    """stress[s] += l (x) f over every contact force on a sphere of slice s (rows in
    ``contact_branches``'s order: the first spheres of the pairs, their second spheres,
    the panel contacts, the bonds' first and second spheres), summed in that order."""
    n = start.shape[0] - 1
    for side in range(2):
        for i in range(n):
            for k in range(start[i], start[i + 1]):
                if not active[k]:
                    continue
                j = nbr[k]
                ai0, ai1, ai2, aj0, aj1, aj2 = _branch(x, r, i, j, pax, plen)
                f0 = pf[row[k], 0]
                f1 = pf[row[k], 1]
                f2 = pf[row[k], 2]
                if side == 0:
                    _add_outer(stress, slice_of[i], ai0, ai1, ai2, -f0, -f1, -f2)
                else:
                    _add_outer(stress, slice_of[j], aj0, aj1, aj2, f0, f1, f2)
    for i in range(wstart.shape[0] - 1):
        for k in range(wstart[i], wstart[i + 1]):
            if wactive[k]:
                _add_outer(stress, slice_of[i], wout[k, 3] - x[i, 0], wout[k, 4] - x[i, 1], wout[k, 5] - x[i, 2],
                           wout[k, 0], wout[k, 1], wout[k, 2])
    for side in range(2):
        for b in range(bi.shape[0]):
            if bstate[b] != 1:
                continue
            ai0, ai1, ai2, aj0, aj1, aj2 = _branch(x, r, bi[b], bj[b], pax, plen)
            if side == 0:
                _add_outer(stress, slice_of[bi[b]], ai0, ai1, ai2, bout[b, 0], bout[b, 1], bout[b, 2])
            else:
                _add_outer(stress, slice_of[bj[b]], aj0, aj1, aj2, bout[b, 6], bout[b, 7], bout[b, 8])


class SliceAverages(NamedTuple):
    """Averages over slices between ``edges`` along one axis.

    centre:   (ns,) slice mid-coordinates [m]
    velocity: (ns, 3) mass-weighted mean sphere velocity [m/s] (leapfrog half step)
    stress:   (ns, 3, 3) Love-Weber mean stress sigma_ab = <l_a f_b>, tension positive [Pa]
    mass:     (ns,) sphere mass in the slice [kg] (by centre)
    """

    centre: np.ndarray
    velocity: np.ndarray
    stress: np.ndarray
    mass: np.ndarray


def slice_averages(sim: Simulation, edges, area: float, axis: int = 2) -> SliceAverages:
    """Mean velocity and stress of the spheres whose centres lie in each slice
    [edges[k], edges[k+1]) along ``axis``, the slice volume being ``area`` [m^2] x its
    thickness. Stress (Love 1927; Weber 1966; Christoffersen et al. 1981), static part:
        sigma_ab = (1 / V) sum_{p in V} sum_{c of p} l_a f_b,
    l the branch from p's centre to the contact point, f the force on p there (contacts,
    panels, bonds), tension positive; in equilibrium a column's sigma_zz at depth is minus
    the weight above per area. Not symmetrised: grains that rotate freely balance their
    moments and make it symmetric in equilibrium; with rotations locked (or bond
    moments, not included here) it need not be, and the traction on a plane of normal n
    is then t_b = n_a sigma_ab (what dem3d.freefield uses)."""
    edges = np.asarray(edges, float)
    sph = sim.spheres
    ns = len(edges) - 1
    s = np.searchsorted(edges, sph.x[:, axis], side="right") - 1
    inside = (s >= 0) & (s < ns)
    m = 1.0 / np.where(sph.inv_m > 0, sph.inv_m, np.inf)
    m = np.where(sph.inv_m > 0, m, sim.sphere_masses())          # locked spheres: their own ball
    mass = np.bincount(s[inside], weights=m[inside], minlength=ns)
    vel = np.stack([np.bincount(s[inside], weights=(m * sph.v[:, d])[inside], minlength=ns) for d in range(3)],
                   axis=1) / np.where(mass > 0, mass, 1.0)[:, None]
    stress = np.zeros((ns, 3, 3))
    prs, wps, bnd = sim.pairs, sim.wall_pairs, sim.bonds
    pax, plen = (sim.periodic.axis, sim.periodic.length) if sim.periodic is not None else (-1, 0.0)
    no_bonds = (np.zeros(0, np.int64), np.zeros((0, 12)))
    _love_weber_sums(stress, s, sph.x, sph.r, prs.start, prs.nbr, prs.active, sim.pair_rows(), prs.pf,
                     wps.start, wps.active, wps.out, *((bnd.i, bnd.j, bnd.state, bnd.out) if bnd is not None
                                                      else (no_bonds[0], no_bonds[0], no_bonds[0], no_bonds[1])),
                     pax, plen)
    volume = float(area) * np.diff(edges)
    stress /= volume[:, None, None]
    return SliceAverages(0.5 * (edges[1:] + edges[:-1]), vel, stress, mass)


class SectionForces(NamedTuple):
    """Internal forces of a bonded structure at cuts normal to one axis.

    cut:     (nc,) cut coordinates [m]
    point:   (nc, 3) reference point of each cut (mean contact point of the cut bonds) [m]
    force:   (nc, 3) force exerted by the part below the cut ON the part above [N]
    moment:  (nc, 3) moment of it about ``point`` [N m]
    n_bonds: (nc,) intact bonds crossing the cut
    """

    cut: np.ndarray
    point: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    n_bonds: np.ndarray


def section_forces(sim: Simulation, cuts, *, axis: int = 2, spheres=None) -> SectionForces:
    """Axial force, shear force and bending moment along a bonded structure (e.g. a sheet
    pile along z) from its bond forces and moments (last evaluation): at each cut
    coordinate c, the bonds with one sphere below c and the other above (along ``axis``)
    act on the upper part with force F = sum F_up and moment about the cut's point P
    M = sum ((x_up - P) x F_up + T_up), T_up the bond's torque on the upper sphere about
    its centre (bond moment plus the lever of its force). In static equilibrium these are
    minus the resultant and moment of the external loads on the part above (the beam's
    section forces). Contacts are not included (they are loads on the structure).
    ``spheres``: specimen indices of the structure (default: every bonded sphere).
    Axial force = force[:, axis]; shear and moment components as the caller's axes."""
    cuts = np.asarray(cuts, float).reshape(-1)
    nc = len(cuts)
    point = np.zeros((nc, 3))
    force = np.zeros((nc, 3))
    moment = np.zeros((nc, 3))
    count = np.zeros(nc, np.int64)
    bnd = sim.bonds
    if bnd is None:
        return SectionForces(cuts, point, force, moment, count)
    x = sim.spheres.x
    keep = bnd.state == 1
    if spheres is not None:
        mine = np.zeros(sim.n_spheres, bool)
        engine = np.empty(sim.n_spheres, np.int64)
        engine[sim.original_index] = np.arange(sim.n_spheres)
        mine[engine[np.asarray(spheres, np.int64)]] = True
        keep &= mine[bnd.i] & mine[bnd.j]
    b = np.nonzero(keep)[0]
    i, j = bnd.i[b], bnd.j[b]
    d = _min_image(sim, x[j] - x[i])
    dist = np.sqrt((d * d).sum(axis=1))
    n = d / dist[:, None]
    h = 0.5 * (sim.spheres.r[i] + sim.spheres.r[j] - dist)
    contact = x[i] + (sim.spheres.r[i] - h)[:, None] * n
    xi_ax = x[i, axis]
    xj_ax = xi_ax + d[:, axis]
    for k, c in enumerate(cuts):
        i_up = (xi_ax >= c) & (xj_ax < c)
        j_up = (xj_ax >= c) & (xi_ax < c)
        sel = i_up | j_up
        count[k] = int(sel.sum())
        if not count[k]:
            continue
        ref = contact[sel][0]
        rel = _min_image(sim, contact[sel] - ref)
        p = ref + rel.mean(axis=0)
        point[k] = p
        f_up = np.where(i_up[sel, None], bnd.out[b[sel], 0:3], bnd.out[b[sel], 6:9])
        t_up = np.where(i_up[sel, None], bnd.out[b[sel], 3:6], bnd.out[b[sel], 9:12])
        x_up = np.where(i_up[sel, None], x[i[sel]], x[i[sel]] + d[sel])
        arm = _min_image(sim, x_up - p)
        force[k] = f_up.sum(axis=0)
        moment[k] = (np.cross(arm, f_up) + t_up).sum(axis=0)
    return SectionForces(cuts, point, force, moment, count)


class StrainField(NamedTuple):
    """Best-fit local deformation between two frames, per cell.

    centre:   (nc, 3) cell centres [m]
    count:    (nc,) spheres (by reference position) in the cell
    grad:     (nc, 3, 3) displacement gradient du_a / dX_b [-] (nan where count < min_count)
    strain:   (nc, 3, 3) small-strain tensor, the symmetric part of grad [-]
    """

    centre: np.ndarray
    count: np.ndarray
    grad: np.ndarray
    strain: np.ndarray


def strain_field(x_ref, x_cur, edges, *, min_count: int = 4, period: tuple | None = None) -> StrainField:
    """Local displacement gradient in grid cells (``edges``: three arrays of cell edges
    along x, y, z [m]) from sphere positions in a reference and a current frame (same
    sphere order, e.g. two Frames' ``positions``): in each cell the least-squares affine
    fit u = u0 + G (X - X_c) over the spheres whose reference centre lies in it (Cundall
    et al. 1982 / Bagi 2006's best-fit method), G = du/dX. ``period`` = (axis, length)
    unwraps displacements across a periodic boundary."""
    x0 = np.asarray(x_ref, float)
    x1 = np.asarray(x_cur, float)
    u = x1 - x0
    if period is not None:
        ax, length = period
        u[:, ax] -= length * np.round(u[:, ax] / length)
    edges = [np.asarray(e, float) for e in edges]
    shape = tuple(len(e) - 1 for e in edges)
    idx = [np.searchsorted(e, x0[:, d], side="right") - 1 for d, e in enumerate(edges)]
    inside = np.all([(k >= 0) & (k < s) for k, s in zip(idx, shape)], axis=0)
    lin = np.ravel_multi_index([k[inside] for k in idx], shape)
    pts = np.nonzero(inside)[0]
    nc = int(np.prod(shape))
    grad = np.full((nc, 3, 3), np.nan)
    count = np.bincount(lin, minlength=nc)
    order = np.argsort(lin, kind="stable")
    start = np.concatenate([[0], np.cumsum(count)])
    for c in np.nonzero(count >= min_count)[0]:
        members = pts[order[start[c]:start[c + 1]]]
        X = x0[members] - x0[members].mean(axis=0)
        A = np.hstack([np.ones((len(members), 1)), X])
        coef, _, rank, _ = np.linalg.lstsq(A, u[members], rcond=None)
        if rank == 4:
            grad[c] = coef[1:].T
    centres = np.stack(np.meshgrid(*[0.5 * (e[1:] + e[:-1]) for e in edges], indexing="ij"), axis=-1).reshape(-1, 3)
    strain = 0.5 * (grad + np.transpose(grad, (0, 2, 1)))
    return StrainField(centres, count, grad, strain)


def max_shear_strain(strain: np.ndarray, plane: tuple | None = None) -> np.ndarray:
    """Maximum engineering shear strain [-]: eps_max - eps_min of the principal strains
    (3D), or in the plane of axes (a, b): sqrt((e_aa - e_bb)^2 + (2 e_ab)^2) (Mohr's
    circle diameter; for simple shear gamma it is gamma). nan for nan cells."""
    eps = np.asarray(strain, float)
    if plane is not None:
        a, b = plane
        return np.sqrt((eps[..., a, a] - eps[..., b, b]) ** 2 + (2.0 * eps[..., a, b]) ** 2)
    out = np.full(eps.shape[:-2], np.nan)
    ok = np.all(np.isfinite(eps), axis=(-2, -1))
    w = np.linalg.eigvalsh(eps[ok])
    out[ok] = w[..., -1] - w[..., 0]
    return out


def settlement_profile(x_ref, x_cur, radii, edges, *, axis: int = 0, up: int = 2,
                       depth: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Ground-surface settlement along ``axis`` [m], positive downwards: in each bin
    [edges[k], edges[k+1]) the surface grains are those whose reference top (z + r) lies
    within ``depth`` (default 2 mean diameters) of the bin's highest top; the settlement
    is minus their mean vertical displacement. Returns (bin centres, settlement); nan
    for empty bins. Tracking grains (not the surface height) keeps a grain rolling off
    the crest from showing as settlement."""
    x0 = np.asarray(x_ref, float)
    x1 = np.asarray(x_cur, float)
    r = np.asarray(radii, float)
    edges = np.asarray(edges, float)
    depth = 4.0 * float(r.mean()) if depth is None else float(depth)
    nb = len(edges) - 1
    k = np.searchsorted(edges, x0[:, axis], side="right") - 1
    top = x0[:, up] + r
    out = np.full(nb, np.nan)
    for b in range(nb):
        sel = k == b
        if not np.any(sel):
            continue
        surface = sel & (top >= top[sel].max() - depth)
        out[b] = -float(np.mean(x1[surface, up] - x0[surface, up]))
    return 0.5 * (edges[1:] + edges[:-1]), out
