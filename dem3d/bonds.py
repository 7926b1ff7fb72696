"""Parallel bonds (Potyondy & Cundall 2004, PFC "pbond") of a ``Simulation``: making
them between nearby spheres, the per-sphere index the kernels gather by, and the
critical time step of their stiffness."""

from __future__ import annotations

import math

import numpy as np

from analytic.errors import InvalidParameter

from .params import check_time_step
from .state import Bonds


def make_bonds(sim, gap: float, *, kn: float, ks: float, radius_multiplier: float = 1.0,
               sigma_c: float = math.inf, tau_c: float = math.inf, spheres=None,
               allow_unsafe_dt: bool = False) -> int:
    """Make a parallel bond (Potyondy & Cundall 2004) between every pair of the given
    spheres (specimen indices; default all) whose surfaces are less than ``gap`` [m]
    apart now (|x_j - x_i| < r_i + r_j + gap, minimum image across the periodic
    boundary, so bonds may cross it), and that are not bonded yet nor in one clump.

    kn, ks:            normal / shear stiffness per unit area [N/m^3]
    radius_multiplier: lambda, bond radius = lambda min(r_i, r_j)
    sigma_c, tau_c:    tensile / shear strength [Pa] (inf: unbreakable)
    The bonds start unloaded at the current positions. While a bond is intact its pair
    is left out of the neighbour list, so the bond replaces the contact law (it is not
    summed with it): the bond stiffness is then the whole stiffness of the joint, as the
    calibration (dem3d.cantilever) assumes, and the joint is as stiff in compression as
    in tension; a broken bond's pair returns to the contact law at once.
    The time step is checked against the bonds' stiffness (``dt_critical_bonds``).
    Returns the number of bonds made.
    """
    gap = float(gap)
    if not 0.0 <= gap <= sim.skin:
        raise InvalidParameter("gap", gap, f"[0, skin = {sim.skin:.4g}] m")
    for name, val in (("kn", kn), ("ks", ks), ("radius_multiplier", radius_multiplier)):
        if not (val > 0 and math.isfinite(val)):
            raise InvalidParameter(name, val, "> 0")
    if not (sigma_c > 0 and tau_c > 0):
        raise InvalidParameter("strength", (sigma_c, tau_c), "> 0 Pa (inf: unbreakable)")
    sim._rebuild()
    sim._need_rebuild = False
    n = sim.n_spheres
    chosen = np.ones(n, bool)
    if spheres is not None:
        chosen[:] = False
        engine = np.empty(n, np.int64)
        engine[sim.original_index] = np.arange(n)
        chosen[engine[np.asarray(spheres, np.int64)]] = True
    prs = sim.pairs
    total = int(prs.start[-1])
    i = np.repeat(np.arange(n, dtype=np.int64), np.diff(prs.start))
    j = prs.nbr[:total].copy()
    d = sim.spheres.x[j] - sim.spheres.x[i]
    if sim.periodic is not None:
        ax, length = sim.periodic.axis, sim.periodic.length
        d[:, ax] -= length * np.round(d[:, ax] / length)
    r = sim.spheres.r
    keep = chosen[i] & chosen[j] & (np.sqrt((d * d).sum(axis=1)) < r[i] + r[j] + gap)
    i, j = i[keep], j[keep]
    nb = len(i)
    rb = float(radius_multiplier) * np.minimum(r[i], r[j])
    new = Bonds(i=i, j=j, kn=np.full(nb, float(kn)), ks=np.full(nb, float(ks)), rb=rb,
                sigma_c=np.full(nb, float(sigma_c)), tau_c=np.full(nb, float(tau_c)),
                state=np.full(nb, 2, np.uint8), fn=np.zeros(nb), fs=np.zeros((nb, 3)), mt=np.zeros(nb),
                mb=np.zeros((nb, 3)), out=np.zeros((nb, 12)), start=np.zeros(n + 1, np.int64),
                entry=np.zeros(2 * nb, np.int64))
    if sim.bonds is not None:
        new = Bonds(*[np.concatenate([a, b]) if f not in ("start", "entry") else b
                      for f, a, b in zip(Bonds._fields, sim.bonds, new)])
    crit = bond_critical_step(new, r, sim.density)
    check_time_step(sim.dt, crit, allow_unsafe=allow_unsafe_dt)
    sim.dt_critical_bonds = crit
    sim.bonds = index_bonds(new, n)
    sim._need_rebuild = True          # bonded pairs leave the contact list
    return nb


def kernel_bonds(bnd: Bonds | None, n: int) -> Bonds:
    """What the kernels take for ``bnd``: the bonds, or for none an empty Bonds over n
    spheres (no bond, every sphere's index range empty), so one compiled kernel serves
    both (kernels module docstring)."""
    if bnd is not None:
        return bnd
    empty = np.zeros(0)
    return Bonds(i=np.zeros(0, np.int64), j=np.zeros(0, np.int64), kn=empty, ks=empty, rb=empty, sigma_c=empty,
                 tau_c=empty, state=np.zeros(0, np.uint8), fn=empty, fs=np.zeros((0, 3)), mt=empty,
                 mb=np.zeros((0, 3)), out=np.zeros((0, 12)), start=np.zeros(n + 1, np.int64),
                 entry=np.zeros(0, np.int64))


def index_bonds(bnd: Bonds, n: int) -> Bonds:
    """Bonds with the per-sphere index (start, entry) rebuilt: sphere s's entries list
    2 b + side in increasing bond index b, so the gather order is fixed."""
    nb = bnd.i.shape[0]
    sphere = np.concatenate([bnd.i, bnd.j]).astype(np.int64)
    entry = np.concatenate([2 * np.arange(nb), 2 * np.arange(nb) + 1]).astype(np.int64)
    order = np.lexsort((entry, sphere))
    start = np.zeros(n + 1, np.int64)
    np.cumsum(np.bincount(sphere, minlength=n), out=start[1:])
    return bnd._replace(i=np.ascontiguousarray(bnd.i, np.int64), j=np.ascontiguousarray(bnd.j, np.int64),
                        start=start, entry=np.ascontiguousarray(entry[order]))


def bond_critical_step(bnd: Bonds, r: np.ndarray, density: float) -> float:
    """Reference critical step of the bonds [s]: the smallest of sqrt(m / (k A)) (axial,
    shear) and sqrt(I_s / (k I_b)) (bending, twisting) over every bond, with m, I_s the
    lighter sphere's mass and moment of inertia (2/5 m r^2), k A = max(kn A, ks A),
    k I_b = max(kn I, ks J) (the PFC rule, as ``critical_time_step`` for contacts)."""
    if bnd.i.shape[0] == 0:
        return math.inf
    rs = np.minimum(r[bnd.i], r[bnd.j])
    m = density * 4.0 / 3.0 * math.pi * rs ** 3
    area = math.pi * bnd.rb ** 2
    inertia = 0.25 * math.pi * bnd.rb ** 4
    k_lin = np.maximum(bnd.kn, bnd.ks) * area
    k_rot = np.maximum(bnd.kn * inertia, bnd.ks * 2.0 * inertia)
    return float(min(np.sqrt(m / k_lin).min(), np.sqrt(0.4 * m * rs ** 2 / k_rot).min()))
