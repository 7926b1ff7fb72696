"""The neighbour lists of a ``Simulation``: a cell list with cells of 2 r_max + skin and a
half stencil; a half Verlet list (pairs within r_i + r_j + skin) scanned into
fixed-capacity rows whose overflow is checked outside the kernel (grow the rows and scan
again), then compacted to CSR with the contact histories carried over; wall candidates
within r + skin. Two buffers of each are kept and swapped at every rebuild, grown by a
quarter when the pairs outgrow them. The lists are rebuilt when any sphere has moved
more than skin/2, or any panel point more than skin/2, since the last build: then no
pair can have closed a gap of skin unseen. ``sort_by_cell`` reorders the bodies for
memory locality."""

from __future__ import annotations

import math

import numpy as np

from . import kernels
from .bodies import gather_ranges
from .bonds import index_bonds, kernel_bonds
from .state import Clumps, Pairs, Spheres, WallPairs


def empty_pairs(n: int, cap: int, width: int = 3) -> Pairs:
    return Pairs(start=np.zeros(n + 1, np.int64), nbr=np.zeros(cap, np.int64),
                 tstart=np.zeros(n + 1, np.int64), tpair=np.zeros(cap, np.int64),
                 tpos=np.zeros(cap, np.int64), ut=np.zeros((cap, width)), active=np.zeros(cap, np.uint8),
                 pf=np.zeros((cap, 8)), slab_start=np.zeros(1, np.int64), slab_sphere=np.zeros(0, np.int64))


def slabs(cell_start: np.ndarray, order: np.ndarray, nc: np.ndarray, pax: int) -> tuple[np.ndarray, np.ndarray]:
    """(slab_start, slab_sphere) of ``state.Pairs`` from this build's ``cell_sort``: the
    spheres in cell order (z slowest), so a slab is a run of whole cell layers along z.
    The half stencil lists a pair under the sphere whose layer is the same or the one
    below, so a pair's second sphere lies in its first sphere's slab or the next;
    periodic along z with an odd number of layers, the last layer joins the one below
    it, so that the last slab's pairs reaching across to slab 0 are made in the phase
    that does not visit slab 0 (pair_forces ``direct``)."""
    n_layers = int(nc[2])
    start = cell_start[::int(nc[0] * nc[1])].astype(np.int64)      # n_layers + 1 bounds
    if pax == 2 and n_layers % 2 == 1 and n_layers > 1:
        start = np.delete(start, n_layers - 1)
    return start, order.astype(np.int64)


def empty_wall_pairs(n: int, cap: int) -> WallPairs:
    return WallPairs(start=np.zeros(n + 1, np.int64), panel=np.zeros(cap, np.int64),
                     ut=np.zeros((cap, 3)), active=np.zeros(cap, np.uint8), out=np.zeros((cap, 6)))


def periodic_args(sim) -> tuple[int, float]:
    if sim.periodic is None:
        return -1, 1.0
    return int(sim.periodic.axis), float(sim.periodic.length)


def grid(sim, x: np.ndarray, r_max: float):
    """Cell grid covering x: (lo (3,), inv_h (3,), nc (3,)) with cells >= 2 r_max + skin."""
    h = 2.0 * r_max + sim.skin
    lo = x.min(axis=0)
    extent = x.max(axis=0) - lo
    nc = np.maximum(1, np.floor(extent / h)).astype(np.int64)
    while int(np.prod(nc)) > 8 * x.shape[0] + 64:      # sparse outliers: coarser grid
        nc = np.maximum(1, nc // 2)
    if sim.periodic is not None:
        ax = sim.periodic.axis
        lo[ax] = sim.periodic.lo
        extent[ax] = sim.periodic.length
        nc[ax] = int(math.floor(sim.periodic.length / h))
    with np.errstate(divide="ignore"):
        inv_h = np.where(extent > 0, nc / np.where(extent > 0, extent, 1.0), 0.0)
    return lo, inv_h, nc


def locality_order(sim, pos, radii, starts, ends) -> np.ndarray:
    # body centre = mean of its spheres (the sum of a body's rows in sphere order, as
    # ndarray.mean takes it, so the order does not depend on how it is computed)
    centres = np.add.reduceat(pos, starts, axis=0) / (ends - starts)[:, None]
    lo, inv_h, nc = grid(sim, centres, float(radii.max()))
    return kernels.body_cell_order(centres, lo, inv_h, nc)


def wrap(sim) -> None:
    """Map positions into the periodic cell (whole clumps move together)."""
    pax = sim.periodic.axis
    lo = sim.periodic.lo
    length = sim.periodic.length
    sph = sim.spheres
    clu = sim.clumps
    free = sph.clump < 0
    if free.all():
        kernels.wrap_periodic(sph.x, pax, lo, length)
        return
    xs = sph.x[free, pax]
    sph.x[free, pax] = lo + np.mod(xs - lo, length)
    if clu.x.shape[0]:
        old = clu.x[:, pax].copy()
        clu.x[:, pax] = lo + np.mod(old - lo, length)
        shift = clu.x[:, pax] - old
        member = sph.clump >= 0
        sph.x[member, pax] += shift[sph.clump[member]]


def sort_by_cell(sim) -> np.ndarray:
    """Reorder the bodies by cell (as at construction) so that neighbours sit close in
    memory; worth it after large rearrangements such as raining. Sphere indices change:
    returns ``new_to_old`` (sphere k now was sphere new_to_old[k]), and
    ``original_index`` keeps mapping to the specimen order. Contact histories are
    carried over; the result differs from an unsorted run only by the order of
    floating-point sums."""
    sph = sim.spheres
    n = sim.n_spheres
    # a body starts at every free sphere and at the first member of every clump
    first = np.ones(n, bool)
    first[1:] = (sph.clump[1:] < 0) | (sph.clump[1:] != sph.clump[:-1])
    starts = np.flatnonzero(first).astype(np.int64)
    ends = np.append(starts[1:], n).astype(np.int64)
    order = locality_order(sim, sph.x, sph.r, starts, ends)
    new_to_old, new_start = gather_ranges(starts, ends, order)
    if np.array_equal(new_to_old, np.arange(n)):
        rebuild(sim)
        return new_to_old
    head_clump = sph.clump[starts[order]]
    is_clump = head_clump >= 0
    clump_order = head_clump[is_clump].astype(np.int64)
    new_clump = -np.ones(len(sim.clumps.x), np.int64)
    new_clump[clump_order] = np.arange(len(clump_order))
    fields = {f: np.ascontiguousarray(getattr(sph, f)[new_to_old]) for f in Spheres._fields}
    member = fields["clump"] >= 0
    fields["clump"][member] = new_clump[fields["clump"][member]]
    length = (ends - starts)[order]
    members = np.stack([new_start[is_clump], new_start[is_clump] + length[is_clump]], axis=1).astype(np.int64)
    fields["body_id"] = np.repeat(new_start, length).astype(np.int64)   # free sphere: itself
    sim.spheres = Spheres(**fields)
    clu = sim.clumps
    sim.clumps = Clumps(**{f: np.ascontiguousarray(getattr(clu, f)[clump_order]) for f in Clumps._fields
                            if f not in ("members", "offset")},
                         members=members, offset=np.ascontiguousarray(clu.offset[new_to_old]))
    sim.original_index = sim.original_index[new_to_old]
    if sim.bonds is not None:
        old_to_new = np.empty(n, np.int64)
        old_to_new[new_to_old] = np.arange(n)
        bnd = sim.bonds._replace(i=old_to_new[sim.bonds.i], j=old_to_new[sim.bonds.j])
        sim.bonds = index_bonds(bnd, n)
    if sim.attached is not None:
        old_to_new = np.empty(n, np.int64)
        old_to_new[new_to_old] = np.arange(n)
        sim.attached = (old_to_new[sim.attached[0]], sim.attached[1])
    rebuild(sim, new_to_old=new_to_old)
    return new_to_old


def rebuild(sim, first: bool = False, new_to_old: np.ndarray | None = None) -> None:
    sph = sim.spheres
    n = sim.n_spheres
    if sim.periodic is not None:
        wrap(sim)
    pax, plen = periodic_args(sim)
    plo = sim.periodic.lo if sim.periodic is not None else 0.0
    lo, inv_h, nc = grid(sim, sph.x, float(sph.r.max()))
    cell, cell_start, order = kernels.cell_sort(sph.x, lo, inv_h, nc, pax, plo, plen)
    old = sim.pairs
    new = sim._pair_bufs[1 - sim._cur]
    counts = np.empty(n, np.int64)
    xr = np.empty((n, 4))
    xr[:, :3] = sph.x[order]
    xr[:, 3] = sph.r[order]
    clump_sorted = sph.clump[order]
    while True:      # fixed-capacity rows; on overflow (checked here) grow and scan again
        kernels.scan_pairs(sph.x, sph.r, sph.clump, cell, cell_start, order, xr, clump_sorted, nc, pax,
                           plen, sim.skin, kernels._FORWARD, sim._rows, counts, kernel_bonds(sim.bonds, n))
        widest = int(counts.max()) if n else 0
        if widest <= sim._rows.shape[1]:
            break
        sim._rows = np.empty((n, widest + 8), np.int64)
    total = int(counts.sum())
    if new.nbr.shape[0] < total:          # grow the spare CSR buffer
        new = empty_pairs(n, int(1.25 * total) + 64, old.ut.shape[1])
    kernels.compact_rows(sim._rows, counts, new.start, new.nbr)
    identity = np.arange(n, dtype=np.int64) if new_to_old is None else new_to_old
    kernels.carry_pair_history(new.start, new.nbr, new.ut, new.active, old.start, old.nbr, old.ut,
                               old.active, identity)
    kernels.touching_first(sph.x, sph.r, pax, plen, new.start, new.nbr, new.ut, new.active,
                           np.empty(total, np.int64), np.empty((total, new.ut.shape[1])),
                           np.empty(total, np.uint8))
    kernels.transpose_pairs(new.start, new.nbr, n, new.tstart, new.tpair, new.tpos)
    # pass 2 sums every transposed row: rows of open pairs must be zero; rows of
    # carried contacts are rewritten by the next pass 1 before pass 2 reads them
    new.pf[:total] = 0.0
    slab_start, slab_sphere = slabs(cell_start, order, nc, pax)
    new = new._replace(slab_start=slab_start, slab_sphere=slab_sphere)
    sim._pair_bufs[1 - sim._cur] = new
    sim._cur = 1 - sim._cur

    pan = sim.walls.panels
    wold = sim.wall_pairs
    wnew = sim._wall_bufs[1 - sim._wcur]
    wstart = np.zeros(n + 1, np.int64)
    if pan.centre.shape[0]:
        kernels.scan_wall_pairs(sph.x, sph.r, pan, sim.skin, wstart, wnew.panel, False)
    np.cumsum(wstart, out=wstart)
    wtotal = int(wstart[-1])
    if wnew.panel.shape[0] < wtotal:
        wnew = empty_wall_pairs(n, int(1.25 * wtotal) + 64)
    wnew.start[:] = wstart
    if wtotal:
        kernels.scan_wall_pairs(sph.x, sph.r, pan, sim.skin, wnew.start, wnew.panel, True)
        kernels.carry_wall_history(wnew.start, wnew.panel, wnew.ut, wnew.active, wnew.out, wold.start,
                                   wold.panel, wold.ut, wold.active, wold.out, identity)
    sim._wall_bufs[1 - sim._wcur] = wnew
    sim._wcur = 1 - sim._wcur
    sph.x_ref[:] = sph.x
    sim.walls.mark_reference()
    if not first:
        sim.n_rebuilds += 1


def fit_history(sim) -> None:
    """Pair history 6 wide (tangential displacement, rolling moment) with rolling
    resistance, else 3 wide: the plain contact pass keeps its memory traffic."""
    width = 6 if sim.rolling else 3
    for b, prs in enumerate(sim._pair_bufs):
        if prs.ut.shape[1] != width:
            ut = np.zeros((prs.ut.shape[0], width))
            keep = min(width, prs.ut.shape[1])
            ut[:, :keep] = prs.ut[:, :keep]
            sim._pair_bufs[b] = prs._replace(ut=ut)
