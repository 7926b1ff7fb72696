"""Every numba kernel of the engine, in one file.

Why one file: numba's on-disk cache is keyed on the source file of the function being
compiled; a change to a jitted helper imported from *another* file does not invalidate the
caller's cache (numba #1833, #9483). Keeping the contact law, the
geometry helpers and the loops that call them together makes a stale cache impossible.

Layout of one time step (no shared accumulator in any parallel loop, so every result is
bitwise independent of the thread count and of the scheduler):

0. ``bond_forces``     (only with parallel bonds) prange over bonds: each bond updates its
                       own force and moment and writes the loads on its two spheres in
                       its own row; pass 2 gathers them per sphere in bond order.
1. ``pair_forces``     prange over spheres i: each pair listed under i (half list: every
                       pair once) evaluates the contact law once, updates its own
                       tangential history, sums the force on i, and stores the force on
                       the second sphere j in the pair's slot of j's (transposed) list.
2. ``gather_and_move`` prange over spheres i: adds the forces stored for i as a second
                       sphere (a sequential read), evaluates i's wall-panel
                       contacts (storing each force per wall pair for the panel loads), then
                       integrates i if it is a free sphere (leapfrog, PFC local damping).
   With ``Simulation.direct_sums``, pass 1 adds the force on j to j itself, slab by slab
   of cell layers (even slabs in parallel, then odd ones: the slabs of one phase never
   write the same sphere), and pass 2 has nothing to gather (``pair_forces``, ``direct``).
3. ``move_clumps``     prange over clumps: sums its members' forces and torques, integrates
                       the rigid body (quaternion), places the members.
4. ``panel_loads``     serial: sums the wall-pair forces per panel (force on the panel and
                       moment about the panel centre).

The material table is passed as ``None`` when off: numba compiles a separate specialisation
for a None argument and prunes the ``is None`` branches, so a run with one material
executes the single-material code unchanged (tests/dem3d/test_pinning.py checks it bit for
bit). Bonds and boundary segments are always passed, empty when off (a loop of no
entries, one length check a step): each None variant of ``advance`` cost 40-100 s of
compiling, and the empty loop adds nothing to any sum. External forces are a run-time
flag (one predictable branch per sphere). The material table and the direct sums stay
specialisations (measured 2026-11-29, ``benchmarks/dem3d_compile_time.py`` and
``dem3d_dynamics_speed.py``): as runtime flags one ``advance`` served all four kinds, but
the plain model stepped 6 % slower; with the flags made constants in each call of the
pair law (four inlined copies) the loss fell to 2-4 % and the first kind compiled in 108 s
of CPU against 44 s here (all four: 140 s here), so a user's first study would wait longer.

The leapfrog (central difference, as PFC) uses v(t - dt/2) in the velocity-dependent
forces at time t, then v(t + dt/2) = v(t - dt/2) + dt a(t), x(t + dt) = x(t) + dt v(t + dt/2).

No fastmath: with ``reassoc``/``contract`` a freshly compiled process and one loading
the same kernels from numba's cache gave different bits (LLVM fuses and reorders
differently depending on where a function gets inlined), which breaks run-to-run
reproducibility; strict IEEE code cost < 5 % here. (``nnan``/``ninf`` would also disable
the non-finite check.)
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import njit, prange

FASTMATH = False       # see the module docstring

# OpenMP before TBB (numba's own order is TBB, OpenMP, workqueue). Where libtbb is
# installed (a LIGGGHTS install brings it), a process that had run these kernels spent
# 2-4 min in tbb::finalize at exit on a busy 2-core machine (numba #5983, #10556: a
# finished run that does not end). OpenMP is thread-safe as well (a dask worker's
# threads), and no result depends on the scheduler (above). It is not fork-safe; nothing
# here forks without exec (dask's worker processes are spawned). A priority set in
# NUMBA_THREADING_LAYER_PRIORITY (other than numba's default order), or a layer named in
# NUMBA_THREADING_LAYER, wins.
_NUMBA_DEFAULT_PRIORITY = ["tbb", "omp", "workqueue"]


def prefer_openmp() -> None:
    """Put OpenMP first in numba's threading-layer priority until the layer is launched.

    numba re-reads its whole config from the environment whenever a NUMBA_* variable has
    changed since its last compile (a notebook that sets NUMBA_NUM_THREADS after import),
    which restores its default order; so this syncs that config first, then sets the
    order, and the engine calls it before every entry that may launch the threads. Once
    launched, the layer is fixed for the process and this does nothing."""
    try:
        numba.threading_layer()
        return
    except ValueError:          # not launched yet
        pass
    numba.config.reload_config()
    if list(numba.config.THREADING_LAYER_PRIORITY) == _NUMBA_DEFAULT_PRIORITY:
        numba.config.THREADING_LAYER_PRIORITY = ["omp", "tbb", "workqueue"]


prefer_openmp()

from . import params as _params
from .params import ContactParams

# switch values as plain module constants (numba freezes them into the compiled code)
LINEAR = 0
HERTZ_MINDLIN = 1
RATIO = 0
ABSOLUTE = 1
COULOMB_ELASTIC = 0
assert (LINEAR, HERTZ_MINDLIN, RATIO, ABSOLUTE, COULOMB_ELASTIC) == (
    _params.LINEAR, _params.HERTZ_MINDLIN, _params.RATIO, _params.ABSOLUTE, _params.COULOMB_ELASTIC)
SQRT_5_6 = math.sqrt(5.0 / 6.0)


# --------------------------------------------------------------------------------------
# contact law (the same for particle-particle and particle-panel contacts)
# --------------------------------------------------------------------------------------

@njit(cache=True, fastmath=FASTMATH, inline="always")
def contact_law(prm, mu, delta, nx, ny, nz, vrx, vry, vrz, m_eff, r_eff, ux, uy, uz, dt):
    """Force on body A of a contact between A and B.

    delta:        overlap [m] (> 0)
    n:            unit normal from A towards B
    vr:           velocity of A's contact point relative to B's [m/s]
    m_eff, r_eff: effective mass [kg] and radius [m] (for a wall: the sphere's)
    u:            tangential spring displacement of A relative to B from the last step [m]
    Returns (Fx, Fy, Fz, Fn, ux, uy, uz): force on A [N], the normal force Fn [N]
    (compression +) and the updated tangential displacement.
    Scalars only in and out, and inlined at numba IR level: a plain call cost ~20 % of
    the pair pass here, and passing arrays to a non-inlined function costs
    reference-count updates per call.

    Normal: Fn = Fe + c_n v_n with v_n = vr.n (closing > 0), Fe = kn delta (linear) or
    4/3 E* sqrt(R*) delta^1.5 (Hertz). The viscous part is not clipped (PFC dashpot mode 0,
    LIGGGHTS default), so a head-on collision follows the analytic damped oscillator.
    Tangential (incremental, Cundall & Strack 1979): the stored displacement is first
    rotated into the current tangent plane (projected, magnitude kept), then
    u_t += v_t dt, F_t = -k_t u_t - c_t v_t, and if |F_t| > mu Fe the force is scaled back
    to the cap and u_t set consistently (-(F_t + c_t v_t) / k_t), as LIGGGHTS
    tangential_model_history; the cap uses the elastic normal force Fe (PFC linear model)
    or, with prm.coulomb = COULOMB_TOTAL, |Fn| including the viscous part (LIGGGHTS).
    """
    vn = vrx * nx + vry * ny + vrz * nz
    vtx = vrx - vn * nx
    vty = vry - vn * ny
    vtz = vrz - vn * nz
    if prm.law == HERTZ_MINDLIN:
        sq = math.sqrt(r_eff * delta)
        kn_t = 2.0 * prm.e_star * sq          # tangent normal stiffness dFe/ddelta
        fe = (2.0 / 3.0) * kn_t * delta
        kt = 8.0 * prm.g_star * sq
        if prm.damping == RATIO:
            cn = 2.0 * SQRT_5_6 * prm.damp_n * math.sqrt(kn_t * m_eff)
            ct = 2.0 * SQRT_5_6 * prm.damp_s * math.sqrt(kt * m_eff)
        else:
            cn = prm.damp_n
            ct = prm.damp_s
    else:
        fe = prm.kn * delta
        kt = prm.ks
        if prm.damping == RATIO:
            cn = 2.0 * prm.damp_n * math.sqrt(prm.kn * m_eff)
            ct = 2.0 * prm.damp_s * math.sqrt(prm.ks * m_eff)
        else:
            cn = prm.damp_n
            ct = prm.damp_s
    fn = fe + cn * vn

    un = ux * nx + uy * ny + uz * nz
    if un != 0.0:
        ux -= un * nx
        uy -= un * ny
        uz -= un * nz
        p2 = ux * ux + uy * uy + uz * uz
        if p2 > 0.0:
            # restore the magnitude: |u|^2 = p2 + un^2, scale = sqrt(1 + e) with e = un^2/p2;
            # e is ~(rotation per step)^2 ~ 1e-10, where 1 + e/2 - e^2/8 is exact to 1e-16
            e = un * un / p2
            if e < 1e-4:
                s = 1.0 + e * (0.5 - 0.125 * e)
            else:
                s = math.sqrt(1.0 + e)
            ux *= s
            uy *= s
            uz *= s
    ux += vtx * dt
    uy += vty * dt
    uz += vtz * dt
    ftx = -kt * ux - ct * vtx
    fty = -kt * uy - ct * vty
    ftz = -kt * uz - ct * vtz
    cap = fe if prm.coulomb == COULOMB_ELASTIC else abs(fn)
    fmax = mu * cap if cap > 0.0 else 0.0
    ft2 = ftx * ftx + fty * fty + ftz * ftz
    if ft2 > fmax * fmax:
        scale = fmax / math.sqrt(ft2)
        ftx *= scale
        fty *= scale
        ftz *= scale
        if kt > 0.0:
            ux = -(ftx + ct * vtx) / kt
            uy = -(fty + ct * vty) / kt
            uz = -(ftz + ct * vtz) / kt
    return -fn * nx + ftx, -fn * ny + fty, -fn * nz + ftz, fn, ux, uy, uz


@njit(cache=True, fastmath=FASTMATH, inline="always")
def rolling_moment(prm, fn, delta, r_eff, wx, wy, wz, nx, ny, nz, mx, my, mz, dt):
    """Rolling-resistance moment on body A [N m] (ContactParams.mu_roll = mu_r), the
    elastic-plastic spring of Ai et al. (2011, model C without its dashpot; LIGGGHTS
    ``rolling_friction epsd2``): the stored moment m is first turned into the current
    tangent plane (magnitude kept), then m -= k_r w_r dt with w_r the rolling part of
    A's angular velocity relative to B, k_r = 2.25 k_n mu_r^2 R*^2 (k_n the normal
    tangent stiffness: kn, or 2 E* sqrt(R* delta) for Hertz), and |m| <= mu_r R* F_n.
    Below the cap a contact holds a moment without creeping and carries small-strain
    waves elastically; at the cap it rolls against a constant moment. B receives -m."""
    mn = mx * nx + my * ny + mz * nz
    if mn != 0.0:
        p2 = mx * mx + my * my + mz * mz
        mx -= mn * nx
        my -= mn * ny
        mz -= mn * nz
        q2 = mx * mx + my * my + mz * mz
        if q2 > 0.0:
            s = math.sqrt(p2 / q2)
            mx *= s
            my *= s
            mz *= s
    wn = wx * nx + wy * ny + wz * nz
    kn = prm.kn if prm.law != HERTZ_MINDLIN else 2.0 * prm.e_star * math.sqrt(r_eff * delta)
    kr = 2.25 * kn * prm.mu_roll * prm.mu_roll * r_eff * r_eff
    mx -= kr * (wx - wn * nx) * dt
    my -= kr * (wy - wn * ny) * dt
    mz -= kr * (wz - wn * nz) * dt
    cap = prm.mu_roll * r_eff * fn if fn > 0.0 else 0.0
    m2 = mx * mx + my * my + mz * mz
    if m2 > cap * cap:
        s = cap / math.sqrt(m2)
        mx *= s
        my *= s
        mz *= s
    return mx, my, mz


@njit(cache=True, fastmath=FASTMATH, inline="always")
def pair_params(mtab, a, b):
    """ContactParams of the material pair (a, b) from a material table (nm, nm, 12)
    (dem3d.params.material_table): the same record the single-material path passes, so
    a contact between two materials runs the identical law with the pair's numbers."""
    row = mtab[a, b]
    return ContactParams(int(row[0]), row[1], row[2], row[3], row[4], int(row[5]), row[6], row[7],
                         row[8], row[9], int(row[10]), row[11])


@njit(cache=True, fastmath=FASTMATH)
def elastic_energy(prm, delta, r_eff):
    """Normal elastic energy of one contact [J]: kn delta^2 / 2 (linear) or
    8/15 E* sqrt(R*) delta^2.5 (Hertz)."""
    if prm.law == HERTZ_MINDLIN:
        return (8.0 / 15.0) * prm.e_star * math.sqrt(r_eff) * delta ** 2.5
    return 0.5 * prm.kn * delta * delta


@njit(cache=True, fastmath=FASTMATH)
def _min_image(d, length):
    if d > 0.5 * length:
        return d - length
    if d < -0.5 * length:
        return d + length
    return d


@njit(cache=True, fastmath=FASTMATH, inline="always")
def min_image(dx, dy, dz, pax, plen):
    """The separation (dx, dy, dz) with the minimum image along the periodic axis ``pax``
    (-1: none) of length ``plen``."""
    if pax == 0:
        dx = _min_image(dx, plen)
    elif pax == 1:
        dy = _min_image(dy, plen)
    elif pax == 2:
        dz = _min_image(dz, plen)
    return dx, dy, dz


@njit(cache=True, fastmath=FASTMATH, inline="always")
def separation(x, i, j, pax, plen):
    """x[j] - x[i] with the minimum image along the periodic axis ``pax`` (-1: none)."""
    return min_image(x[j, 0] - x[i, 0], x[j, 1] - x[i, 1], x[j, 2] - x[i, 2], pax, plen)


@njit(cache=True, fastmath=FASTMATH, inline="always")
def panel_closest_point(px, py, pz, pan, p):
    """Closest point of panel p to the point (px, py, pz), or ok = False when the point is
    behind the panel (on the side opposite its normal) or beyond a shared edge.

    Returns (ok, qx, qy, qz). Edges that are not shared are rounded (the closest point is
    clamped to the rectangle), so a sphere can touch a free panel edge.
    """
    dx = px - pan.centre[p, 0]
    dy = py - pan.centre[p, 1]
    dz = pz - pan.centre[p, 2]
    s = dx * pan.normal[p, 0] + dy * pan.normal[p, 1] + dz * pan.normal[p, 2]
    if s <= 0.0:
        return False, 0.0, 0.0, 0.0
    u = dx * pan.e1[p, 0] + dy * pan.e1[p, 1] + dz * pan.e1[p, 2]
    v = dx * pan.e2[p, 0] + dy * pan.e2[p, 1] + dz * pan.e2[p, 2]
    a = pan.half[p, 0]
    b = pan.half[p, 1]
    if u < -a:
        if pan.shared[p, 0]:
            return False, 0.0, 0.0, 0.0
        u = -a
    elif u >= a:
        if pan.shared[p, 1]:
            return False, 0.0, 0.0, 0.0
        u = a
    if v < -b:
        if pan.shared[p, 2]:
            return False, 0.0, 0.0, 0.0
        v = -b
    elif v >= b:
        if pan.shared[p, 3]:
            return False, 0.0, 0.0, 0.0
        v = b
    qx = pan.centre[p, 0] + u * pan.e1[p, 0] + v * pan.e2[p, 0]
    qy = pan.centre[p, 1] + u * pan.e1[p, 1] + v * pan.e2[p, 1]
    qz = pan.centre[p, 2] + u * pan.e1[p, 2] + v * pan.e2[p, 2]
    return True, qx, qy, qz


# --------------------------------------------------------------------------------------
# one time step
# --------------------------------------------------------------------------------------

@njit(parallel=True, cache=True, fastmath=FASTMATH)
def pair_forces(sph, prs, prm, dt, pax, plen, mtab, rolling=None, direct=None):
    """Pass 1 (module docstring): evaluate every half-list pair once. The force and torque
    on the first sphere i are summed into sph.f / sph.t; those on the second sphere j are
    written to the pair's slot in the transposed order (``prs.pf``), which pass 2 adds.

    mtab: None (one material: ``prm`` for every pair; numba compiles this case without
    any lookup, so it is the single-material code unchanged) or a material table
    (nm, nm, 11): the pair's ContactParams are looked up by sph.mat[i], sph.mat[j]
    (``prm`` then only gives the model-wide law/damping mode, which the table shares).
    rolling: None (no rolling resistance: the plain code) or True (some contact has
    mu_roll > 0; the pair history is then 6 wide, the moment on the first sphere in
    columns 3-5): ``rolling_moment`` on both spheres of every touching pair with
    mu_roll > 0, from the normal force just computed, in the same visit of the pair (a
    second pass over the list cost ~70 % of this one); a pair that stops touching
    forgets its moment with its tangential history.
    direct: None (the rows above) or True: the force and torque on j are added straight
    to sph.f[j] / sph.t[j] as the pair is visited, and pass 2 gathers nothing (``prs.pf``
    then holds each pair's force on j and normal force by pair k, for the measurements).
    The spheres are visited by slab of cell layers (``prs.slab_start`` /
    ``prs.slab_sphere``; a pair's j lies in i's slab or the next one): the even slabs in
    parallel, then the odd ones, each slab in a fixed order, so every sum is taken in an
    order that does not depend on the thread count. The same forces to rounding, other
    bits; passes 1 and 2 ~0.8 of the rows' time on the seismic model
    (benchmarks/seismic_pair_pass.py, ``direct_j``)."""
    x = sph.x
    v = sph.v
    w = sph.w
    r = sph.r
    inv_m = sph.inv_m
    f = sph.f
    t = sph.t
    nbr = prs.nbr
    tpos = prs.tpos
    ut = prs.ut
    active = prs.active
    pf = prs.pf
    mat = sph.mat
    mu = prm.mu
    need_m = prm.damping == RATIO
    need_r = prm.law == HERTZ_MINDLIN
    n = x.shape[0]
    if direct is not None:
        for i in prange(n):
            for c in range(3):
                f[i, c] = 0.0
                t[i, c] = 0.0
    slab_start = prs.slab_start
    slab_sphere = prs.slab_sphere
    n_slabs = slab_start.shape[0] - 1
    for phase in range(1 if direct is None else 2):
        n_par = n if direct is None else (n_slabs + 1 - phase) // 2
        for s in prange(n_par):
            lo = s
            hi = s + 1
            if direct is not None:
                lo = slab_start[2 * s + phase]
                hi = slab_start[2 * s + phase + 1]
            for idx in range(lo, hi):
                i = idx if direct is None else slab_sphere[idx]
                _pair_row(i, x, v, w, r, inv_m, f, t, nbr, tpos, ut, active, pf, mat, prs.start, prm, mu,
                          mtab, rolling, direct, need_m, need_r, pax, plen, dt)


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _pair_row(i, x, v, w, r, inv_m, f, t, nbr, tpos, ut, active, pf, mat, start, prm, mu, mtab, rolling, direct,
              need_m, need_r, pax, plen, dt):
    """Every pair listed under sphere i (``pair_forces``): the law, the histories, the
    sums on i, the force on j (a row, or added to j with ``direct``)."""
    ri = r[i]
    xi = x[i, 0]
    yi = x[i, 1]
    zi = x[i, 2]
    vix = v[i, 0]      # hoisted: numba cannot prove the stores below do not alias them
    viy = v[i, 1]
    viz = v[i, 2]
    wix = w[i, 0]
    wiy = w[i, 1]
    wiz = w[i, 2]
    imi = inv_m[i]
    sfx = 0.0
    sfy = 0.0
    sfz = 0.0
    stx = 0.0
    sty = 0.0
    stz = 0.0
    rtx = 0.0          # the rolling moments, summed apart as the separate pass did
    rty = 0.0
    rtz = 0.0
    for k in range(start[i], start[i + 1]):
        j = nbr[k]
        dx, dy, dz = min_image(x[j, 0] - xi, x[j, 1] - yi, x[j, 2] - zi, pax, plen)
        rs = ri + r[j]
        d2 = dx * dx + dy * dy + dz * dz
        if d2 >= rs * rs:
            if active[k]:           # contact just opened: forget history and force
                active[k] = 0
                ut[k, 0] = 0.0
                ut[k, 1] = 0.0
                ut[k, 2] = 0.0
                if rolling is not None:
                    ut[k, 3] = 0.0
                    ut[k, 4] = 0.0
                    ut[k, 5] = 0.0
                kt_ = tpos[k] if direct is None else k
                for c in range(8):
                    pf[kt_, c] = 0.0
            continue
        d = math.sqrt(d2)
        inv_d = 1.0 / d
        nx = dx * inv_d
        ny = dy * inv_d
        nz = dz * inv_d
        delta = rs - d
        h = 0.5 * delta
        ai = ri - h          # lever arms to the centre of the overlap region
        aj = r[j] - h
        # contact-point velocity of i relative to j: v_i - v_j + (a_i w_i + a_j w_j) x n
        wx = ai * wix + aj * w[j, 0]
        wy = ai * wiy + aj * w[j, 1]
        wz = ai * wiz + aj * w[j, 2]
        vrx = vix - v[j, 0] + (wy * nz - wz * ny)
        vry = viy - v[j, 1] + (wz * nx - wx * nz)
        vrz = viz - v[j, 2] + (wx * ny - wy * nx)
        m_eff = 0.0
        if need_m:
            s = imi + inv_m[j]
            m_eff = 1.0 / s if s > 0.0 else 0.0
        r_eff = ri * r[j] / rs if need_r else 0.0
        if mtab is None:
            fx, fy, fz, fn, ux, uy, uz = contact_law(prm, mu, delta, nx, ny, nz, vrx, vry, vrz,
                                                     m_eff, r_eff, ut[k, 0], ut[k, 1], ut[k, 2], dt)
        else:
            pp = pair_params(mtab, mat[i], mat[j])
            fx, fy, fz, fn, ux, uy, uz = contact_law(pp, pp.mu, delta, nx, ny, nz, vrx, vry, vrz,
                                                     m_eff, r_eff, ut[k, 0], ut[k, 1], ut[k, 2], dt)
        ut[k, 0] = ux
        ut[k, 1] = uy
        ut[k, 2] = uz
        active[k] = 1
        # torque on i: (a_i n) x F; on j: (-a_j n) x (-F) = a_j (n x F)
        cx = ny * fz - nz * fy
        cy = nz * fx - nx * fz
        cz = nx * fy - ny * fx
        sfx += fx
        sfy += fy
        sfz += fz
        stx += ai * cx
        sty += ai * cy
        stz += ai * cz
        if direct is None:
            kt_ = tpos[k]
            pf[kt_, 0] = -fx
            pf[kt_, 1] = -fy
            pf[kt_, 2] = -fz
            pf[kt_, 3] = aj * cx
            pf[kt_, 4] = aj * cy
            pf[kt_, 5] = aj * cz
            pf[kt_, 6] = fn
        else:
            pf[k, 0] = -fx
            pf[k, 1] = -fy
            pf[k, 2] = -fz
            pf[k, 6] = fn
            f[j, 0] -= fx
            f[j, 1] -= fy
            f[j, 2] -= fz
            t[j, 0] += aj * cx
            t[j, 1] += aj * cy
            t[j, 2] += aj * cz
        if rolling is not None:
            pr = prm if mtab is None else pair_params(mtab, mat[i], mat[j])
            if pr.mu_roll > 0.0:
                mx, my, mz = rolling_moment(pr, fn, delta, ri * r[j] / rs, wix - w[j, 0], wiy - w[j, 1],
                                            wiz - w[j, 2], dx / d, dy / d, dz / d,
                                            ut[k, 3], ut[k, 4], ut[k, 5], dt)
                ut[k, 3] = mx
                ut[k, 4] = my
                ut[k, 5] = mz
                rtx += mx
                rty += my
                rtz += mz
                if direct is None:
                    pf[kt_, 3] -= mx
                    pf[kt_, 4] -= my
                    pf[kt_, 5] -= mz
                else:
                    t[j, 0] -= mx
                    t[j, 1] -= my
                    t[j, 2] -= mz
    if rolling is not None:
        stx += rtx
        sty += rty
        stz += rtz
    if direct is None:
        f[i, 0] = sfx
        f[i, 1] = sfy
        f[i, 2] = sfz
        t[i, 0] = stx
        t[i, 1] = sty
        t[i, 2] = stz
    else:
        f[i, 0] += sfx
        f[i, 1] += sfy
        f[i, 2] += sfz
        t[i, 0] += stx
        t[i, 1] += sty
        t[i, 2] += stz


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _panel_contact(sph, wps, pan, prm, mtab, dt, need_m, i, k, w_act, w_ut, w_out):
    """Sphere i against the panel of its wall candidate k, by the same contact law as a
    pair (the panel's mass and radius infinite; the pair's parameters with materials):
    (touching, force on the sphere (3) [N], its torque about the sphere centre (3)
    [N m]). Updates the candidate's tangential history and records its force and contact
    point in ``w_out``; a candidate that stopped touching forgets its history."""
    x = sph.x
    v = sph.v
    w = sph.w
    ri = sph.r[i]
    p = wps.panel[k]
    ok, qx, qy, qz = panel_closest_point(x[i, 0], x[i, 1], x[i, 2], pan, p)
    dx = 0.0
    dy = 0.0
    dz = 0.0
    d2 = 0.0
    if ok:
        dx = qx - x[i, 0]
        dy = qy - x[i, 1]
        dz = qz - x[i, 2]
        d2 = dx * dx + dy * dy + dz * dz
    if (not ok) or d2 >= ri * ri or d2 == 0.0:
        if w_act[k]:
            w_act[k] = 0
            w_ut[k, 0] = 0.0
            w_ut[k, 1] = 0.0
            w_ut[k, 2] = 0.0
            for c in range(6):
                w_out[k, c] = 0.0
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    d = math.sqrt(d2)
    nx = dx / d            # from the sphere towards the panel
    ny = dy / d
    nz = dz / d
    delta = ri - d
    a = ri - 0.5 * delta
    cx = x[i, 0] + a * nx  # contact point
    cy = x[i, 1] + a * ny
    cz = x[i, 2] + a * nz
    ox = cx - pan.centre[p, 0]
    oy = cy - pan.centre[p, 1]
    oz = cz - pan.centre[p, 2]
    pvx = pan.vel[p, 0] + pan.omega[p, 1] * oz - pan.omega[p, 2] * oy
    pvy = pan.vel[p, 1] + pan.omega[p, 2] * ox - pan.omega[p, 0] * oz
    pvz = pan.vel[p, 2] + pan.omega[p, 0] * oy - pan.omega[p, 1] * ox
    vrx = v[i, 0] + a * (w[i, 1] * nz - w[i, 2] * ny) - pvx
    vry = v[i, 1] + a * (w[i, 2] * nx - w[i, 0] * nz) - pvy
    vrz = v[i, 2] + a * (w[i, 0] * ny - w[i, 1] * nx) - pvz
    im = sph.inv_m[i]
    m_eff = 1.0 / im if (im > 0.0 and need_m) else 0.0
    if mtab is None:
        cfx, cfy, cfz, fn, ux, uy, uz = contact_law(prm, pan.mu[p], delta, nx, ny, nz, vrx, vry, vrz,
                                                    m_eff, ri, w_ut[k, 0], w_ut[k, 1],
                                                    w_ut[k, 2], dt)
    else:
        pp = pair_params(mtab, sph.mat[i], pan.mat[p])
        cfx, cfy, cfz, fn, ux, uy, uz = contact_law(pp, pp.mu, delta, nx, ny, nz, vrx, vry, vrz,
                                                    m_eff, ri, w_ut[k, 0], w_ut[k, 1],
                                                    w_ut[k, 2], dt)
    w_ut[k, 0] = ux
    w_ut[k, 1] = uy
    w_ut[k, 2] = uz
    w_out[k, 0] = cfx
    w_out[k, 1] = cfy
    w_out[k, 2] = cfz
    w_out[k, 3] = cx
    w_out[k, 4] = cy
    w_out[k, 5] = cz
    w_act[k] = 1
    return True, cfx, cfy, cfz, a * (ny * cfz - nz * cfy), a * (nz * cfx - nx * cfz), a * (nx * cfy - ny * cfx)


@njit(parallel=True, cache=True, fastmath=FASTMATH)
def gather_and_move(sph, prs, wps, pan, prm, dt, gx, gy, gz, ref_limit2, speed_limit2, integrate,
                    mtab, has_fext, bnd, direct=None):
    """Pass 2 (see module docstring): total contact force and torque per sphere (starting
    from pass 1's partial sums in sph.f / sph.t), bond forces (``bnd``: Bonds, empty for
    none, ``bonds.kernel_bonds``; from ``bond_forces``, gathered per sphere in increasing
    bond order), wall contacts,
    the external force sph.f_ext (if ``has_fext``), and the leapfrog update of free
    spheres (if ``integrate``). Must follow ``pair_forces``. ``mtab`` as in pair_forces
    (panel material sph.mat / pan.mat; the pair's friction replaces the panel's mu).
    sph.f / sph.t hold the total (contact + bond + external) force and torque afterwards.
    direct: as in pair_forces (None: add the rows of the pairs where i is the second
    sphere; True: pass 1 has added them already).

    Returns (n_moved, n_bad, n_fast): spheres farther than sqrt(ref_limit2) from their
    position at the last list build, spheres with a non-finite state, spheres faster than
    sqrt(speed_limit2).
    """
    x = sph.x
    v = sph.v
    w = sph.w
    f = sph.f
    t = sph.t
    pf = prs.pf
    # numba 0.68 dropped writes made as ``record.field[k] = ...`` inside a prange body
    # (observed here); every written array is bound to a local name first
    w_act = wps.active
    w_ut = wps.ut
    w_out = wps.out
    inv_m = sph.inv_m
    x_ref = sph.x_ref
    alpha = prm.local_damping
    need_m = prm.damping == RATIO
    has_bonds = bnd.i.shape[0] > 0
    n_moved = 0
    n_bad = 0
    n_fast = 0
    for i in prange(x.shape[0]):
        fx = f[i, 0]     # pairs listed under i, summed by pass 1
        fy = f[i, 1]
        fz = f[i, 2]
        tx = t[i, 0]
        ty = t[i, 1]
        tz = t[i, 2]
        if direct is None:
            for kk in range(prs.tstart[i], prs.tstart[i + 1]):
                # pairs where i is the second sphere: sequential, zero rows for open pairs
                fx += pf[kk, 0]
                fy += pf[kk, 1]
                fz += pf[kk, 2]
                tx += pf[kk, 3]
                ty += pf[kk, 4]
                tz += pf[kk, 5]
        if has_bonds:
            for kk in range(bnd.start[i], bnd.start[i + 1]):
                e = bnd.entry[kk]
                b = e >> 1
                o = 6 * (e & 1)
                fx += bnd.out[b, o]
                fy += bnd.out[b, o + 1]
                fz += bnd.out[b, o + 2]
                tx += bnd.out[b, o + 3]
                ty += bnd.out[b, o + 4]
                tz += bnd.out[b, o + 5]
        # wall panels: the same law, wall mass and radius infinite
        for k in range(wps.start[i], wps.start[i + 1]):
            touching, cfx, cfy, cfz, ctx, cty, ctz = _panel_contact(sph, wps, pan, prm, mtab, dt, need_m, i, k,
                                                                    w_act, w_ut, w_out)
            if touching:
                fx += cfx
                fy += cfy
                fz += cfz
                tx += ctx
                ty += cty
                tz += ctz
        if has_fext:
            fx += sph.f_ext[i, 0]
            fy += sph.f_ext[i, 1]
            fz += sph.f_ext[i, 2]
        f[i, 0] = fx
        f[i, 1] = fy
        f[i, 2] = fz
        t[i, 0] = tx
        t[i, 1] = ty
        t[i, 2] = tz
        if (not integrate) or sph.clump[i] >= 0:
            continue
        im = inv_m[i]
        if im > 0.0:
            _leapfrog(v, x, i, fx, fy, fz, im, gx, gy, gz, alpha, dt)
        ii = sph.inv_i[i]
        if ii > 0.0:
            bx = tx * ii
            by = ty * ii
            bz = tz * ii
            if alpha > 0.0:
                bx -= alpha * abs(bx) * _sign(w[i, 0])
                by -= alpha * abs(by) * _sign(w[i, 1])
                bz -= alpha * abs(bz) * _sign(w[i, 2])
            w[i, 0] += dt * bx
            w[i, 1] += dt * by
            w[i, 2] += dt * bz
        n_moved_i, n_bad_i, n_fast_i = _check(x, v, w, x_ref, i, ref_limit2, speed_limit2)
        n_moved += n_moved_i
        n_bad += n_bad_i
        n_fast += n_fast_i
    return n_moved, n_bad, n_fast


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _keep_in_plane(ax, ay, az, nx, ny, nz, spin):
    """The vector a carried into the plane normal to the new unit normal n, as a rigid
    rotation would: rotated by the angle ``spin`` about n (the pair's mean spin about the
    bond axis times dt), then its component along n removed and the magnitude restored
    (PFC/P&C 2004 update of the shear force and bending moment)."""
    a2 = ax * ax + ay * ay + az * az
    if a2 == 0.0:
        return ax, ay, az
    if spin != 0.0:
        cx = ny * az - nz * ay
        cy = nz * ax - nx * az
        cz = nx * ay - ny * ax
        ax += spin * cx
        ay += spin * cy
        az += spin * cz
    an = ax * nx + ay * ny + az * nz
    ax -= an * nx
    ay -= an * ny
    az -= an * nz
    p2 = ax * ax + ay * ay + az * az
    if p2 > 0.0 and p2 != a2:
        s = math.sqrt(a2 / p2)
        ax *= s
        ay *= s
        az *= s
    return ax, ay, az


@njit(parallel=True, cache=True, fastmath=FASTMATH)
def bond_forces(sph, bnd, dt, pax, plen):
    """Parallel-bond forces and moments (Potyondy & Cundall 2004, eqs. 8-12), one bond per
    iteration, each writing only its own row (bnd.out), so the result does not depend on
    the thread count; pass 2 gathers them per sphere.

    Bond of radius R = bnd.rb, area A = pi R^2, I = pi R^4 / 4, J = pi R^4 / 2, at the
    contact point (distances a_i = r_i - h, a_j = r_j - h from the centres along
    n = unit(x_j - x_i), h = (r_i + r_j - d) / 2; a gap gives h < 0). Over the last step
    (leapfrog: the displacement increment is exactly v(t - dt/2) dt):
        dF_n = kn A  v_n dt            (compression +, v_n closing)
        dF_s = -ks A v_s dt            (on i; v_s the tangential relative velocity of the
                                        contact point of i with respect to j)
        dM_t = -ks J (w_i - w_j).n dt  (twist on i, about n)
        dM_b = -kn I (w_i - w_j)_s dt  (bending on i)
    The stored shear force and bending moment are first carried with the pair's rigid
    rotation (``_keep_in_plane``). Force on i: -F_n n + F_s; torque on i:
    a_i n x F + M_t n + M_b; on j the opposites, torque a_j n x F - M_t n - M_b.
    Breakage (eq. 12): tensile stress -F_n / A + |M_b| R / I >= sigma_c, or shear stress
    |F_s| / A + |M_t| R / J >= tau_c: the bond is removed (state 0, no force from then on).
    A bond in state 2 (just made) takes no increment at its first evaluation.
    Returns the number of bonds broken in this call.
    """
    x = sph.x
    v = sph.v
    w = sph.w
    r = sph.r
    st = bnd.state
    fn_ = bnd.fn
    fs_ = bnd.fs
    mt_ = bnd.mt
    mb_ = bnd.mb
    out = bnd.out
    broken = 0
    for b in prange(bnd.i.shape[0]):
        s = st[b]
        if s == 0:
            continue
        i = bnd.i[b]
        j = bnd.j[b]
        dx, dy, dz = separation(x, i, j, pax, plen)
        d = math.sqrt(dx * dx + dy * dy + dz * dz)
        nx = dx / d
        ny = dy / d
        nz = dz / d
        h = 0.5 * (r[i] + r[j] - d)
        ai = r[i] - h
        aj = r[j] - h
        rb = bnd.rb[b]
        area = math.pi * rb * rb
        inertia = 0.25 * math.pi * rb ** 4
        polar = 2.0 * inertia
        kn = bnd.kn[b]
        ks = bnd.ks[b]
        fn = fn_[b]
        fsx = fs_[b, 0]
        fsy = fs_[b, 1]
        fsz = fs_[b, 2]
        mt = mt_[b]
        mbx = mb_[b, 0]
        mby = mb_[b, 1]
        mbz = mb_[b, 2]
        if s == 1:
            wrx = w[i, 0] - w[j, 0]
            wry = w[i, 1] - w[j, 1]
            wrz = w[i, 2] - w[j, 2]
            spin = 0.5 * ((w[i, 0] + w[j, 0]) * nx + (w[i, 1] + w[j, 1]) * ny + (w[i, 2] + w[j, 2]) * nz) * dt
            fsx, fsy, fsz = _keep_in_plane(fsx, fsy, fsz, nx, ny, nz, spin)
            mbx, mby, mbz = _keep_in_plane(mbx, mby, mbz, nx, ny, nz, spin)
            ox = ai * w[i, 0] + aj * w[j, 0]
            oy = ai * w[i, 1] + aj * w[j, 1]
            oz = ai * w[i, 2] + aj * w[j, 2]
            vrx = v[i, 0] - v[j, 0] + (oy * nz - oz * ny)
            vry = v[i, 1] - v[j, 1] + (oz * nx - ox * nz)
            vrz = v[i, 2] - v[j, 2] + (ox * ny - oy * nx)
            vn = vrx * nx + vry * ny + vrz * nz
            fn += kn * area * vn * dt
            c = -ks * area * dt
            fsx += c * (vrx - vn * nx)
            fsy += c * (vry - vn * ny)
            fsz += c * (vrz - vn * nz)
            wn = wrx * nx + wry * ny + wrz * nz
            mt -= ks * polar * wn * dt
            c = -kn * inertia * dt
            mbx += c * (wrx - wn * nx)
            mby += c * (wry - wn * ny)
            mbz += c * (wrz - wn * nz)
        else:
            st[b] = 1
        sigma = -fn / area + math.sqrt(mbx * mbx + mby * mby + mbz * mbz) * rb / inertia
        tau = math.sqrt(fsx * fsx + fsy * fsy + fsz * fsz) / area + abs(mt) * rb / polar
        if sigma >= bnd.sigma_c[b] or tau >= bnd.tau_c[b]:
            st[b] = 0
            broken += 1
            fn = 0.0
            fsx = fsy = fsz = 0.0
            mt = 0.0
            mbx = mby = mbz = 0.0
        fn_[b] = fn
        fs_[b, 0] = fsx
        fs_[b, 1] = fsy
        fs_[b, 2] = fsz
        mt_[b] = mt
        mb_[b, 0] = mbx
        mb_[b, 1] = mby
        mb_[b, 2] = mbz
        fx = -fn * nx + fsx
        fy = -fn * ny + fsy
        fz = -fn * nz + fsz
        cx = ny * fz - nz * fy
        cy = nz * fx - nx * fz
        cz = nx * fy - ny * fx
        out[b, 0] = fx
        out[b, 1] = fy
        out[b, 2] = fz
        out[b, 3] = ai * cx + mt * nx + mbx
        out[b, 4] = ai * cy + mt * ny + mby
        out[b, 5] = ai * cz + mt * nz + mbz
        out[b, 6] = -fx
        out[b, 7] = -fy
        out[b, 8] = -fz
        out[b, 9] = aj * cx - mt * nx - mbx
        out[b, 10] = aj * cy - mt * ny - mby
        out[b, 11] = aj * cz - mt * nz - mbz
    return broken


@njit(cache=True, fastmath=FASTMATH, inline="always")
def bonded(bnd, i, j):
    """True if spheres i and j share an intact bond (scans i's few bonds)."""
    for kk in range(bnd.start[i], bnd.start[i + 1]):
        b = bnd.entry[kk] >> 1
        if bnd.state[b] != 0 and (bnd.i[b] == j or bnd.j[b] == j):
            return True
    return False


@njit(cache=True, fastmath=FASTMATH)
def _sign(a):
    if a > 0.0:
        return 1.0
    if a < 0.0:
        return -1.0
    return 0.0


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _leapfrog(v, x, i, fx, fy, fz, im, gx, gy, gz, alpha, dt):
    """Translate body ``i`` one step: a = F / m + g with PFC's local damping (each
    component reduced by alpha |a| against the velocity's sign), then v += dt a (the
    half-step velocity) and x += dt v. The one update of free spheres and clumps."""
    ax = fx * im + gx
    ay = fy * im + gy
    az = fz * im + gz
    if alpha > 0.0:
        ax -= alpha * abs(ax) * _sign(v[i, 0])
        ay -= alpha * abs(ay) * _sign(v[i, 1])
        az -= alpha * abs(az) * _sign(v[i, 2])
    v[i, 0] += dt * ax
    v[i, 1] += dt * ay
    v[i, 2] += dt * az
    x[i, 0] += dt * v[i, 0]
    x[i, 1] += dt * v[i, 1]
    x[i, 2] += dt * v[i, 2]


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _check(x, v, w, x_ref, i, ref_limit2, speed_limit2):
    """(moved, bad, fast) flags of sphere i after its update.

    Takes the arrays the caller wrote through, never the record (``sph.x``): inside a
    prange body LLVM may serve a read through the record's pointer from before the write
    through the local name, and which one it does depends on the CPU it compiles for
    (a rebuild was missed on one target and taken on another)."""
    ddx = x[i, 0] - x_ref[i, 0]
    ddy = x[i, 1] - x_ref[i, 1]
    ddz = x[i, 2] - x_ref[i, 2]
    moved = 1 if ddx * ddx + ddy * ddy + ddz * ddz > ref_limit2 else 0
    s = x[i, 0] + x[i, 1] + x[i, 2] + v[i, 0] + v[i, 1] + v[i, 2] + w[i, 0] + w[i, 1] + w[i, 2]
    bad = 0 if math.isfinite(s) else 1
    fast = 1 if v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2] > speed_limit2 else 0
    return moved, bad, fast


# ---- quaternions (w, x, y, z), body -> world -----------------------------------------

@njit(cache=True, fastmath=FASTMATH)
def quat_rotate(q0, q1, q2, q3, vx, vy, vz):
    """R(q) v for a unit quaternion q = (q0; q1, q2, q3)."""
    # t = 2 q_vec x v ; v' = v + q0 t + q_vec x t
    tx = 2.0 * (q2 * vz - q3 * vy)
    ty = 2.0 * (q3 * vx - q1 * vz)
    tz = 2.0 * (q1 * vy - q2 * vx)
    return (vx + q0 * tx + (q2 * tz - q3 * ty),
            vy + q0 * ty + (q3 * tx - q1 * tz),
            vz + q0 * tz + (q1 * ty - q2 * tx))


@njit(cache=True, fastmath=FASTMATH)
def _world_omega(q0, q1, q2, q3, i0, i1, i2, lx, ly, lz):
    """omega = R I^-1 R^T L for principal inverse moments (i0, i1, i2)."""
    bx, by, bz = quat_rotate(q0, -q1, -q2, -q3, lx, ly, lz)
    return quat_rotate(q0, q1, q2, q3, bx * i0, by * i1, bz * i2)


@njit(cache=True, fastmath=FASTMATH)
def _quat_advance(q0, q1, q2, q3, wx, wy, wz, h):
    """exp(omega h / 2) * q, renormalised: rotation by the angle |omega| h about omega."""
    om = math.sqrt(wx * wx + wy * wy + wz * wz)
    if om == 0.0:
        return q0, q1, q2, q3
    half = 0.5 * om * h
    s = math.sin(half) / om
    c = math.cos(half)
    p0, p1, p2, p3 = c, s * wx, s * wy, s * wz
    r0 = p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3
    r1 = p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2
    r2 = p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1
    r3 = p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0
    nrm = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2 + r3 * r3)
    return r0 / nrm, r1 / nrm, r2 / nrm, r3 / nrm


@njit(parallel=True, cache=True, fastmath=FASTMATH)
def move_clumps(sph, clu, prm, dt, gx, gy, gz, ref_limit2, speed_limit2):
    """Pass 3: rigid-body leapfrog of each clump from its members' forces and torques.

    Translation as a free sphere. Rotation: angular momentum L (world) is kicked,
    L(t + dt/2) = L(t - dt/2) + dt T(t); the orientation at the half step is predicted with
    omega(t) = R I^-1 R^T L(t), L(t) ~ L(t - dt/2) + dt/2 T, and q(t + dt) = exp(omega(t + dt/2)
    dt / 2) q(t) with omega(t + dt/2) evaluated at the predicted half-step orientation
    (second order; after Omelyan 1998 / the scheme YADE uses for aspherical bodies).
    Members are then placed rigidly: x_m = X + R b_m, v_m = V + omega x (x_m - X).
    """
    alpha = prm.local_damping
    # bind every written array to a local name (see gather_and_move)
    cx_ = clu.x
    cv_ = clu.v
    cam = clu.am
    cw_ = clu.w
    cq_ = clu.q
    sx = sph.x
    sv = sph.v
    sw = sph.w
    sf = sph.f
    st = sph.t
    x_ref = sph.x_ref
    n_moved = 0
    n_bad = 0
    n_fast = 0
    for c in prange(clu.x.shape[0]):
        s0 = clu.members[c, 0]
        s1 = clu.members[c, 1]
        fx = 0.0
        fy = 0.0
        fz = 0.0
        tx = 0.0
        ty = 0.0
        tz = 0.0
        for m in range(s0, s1):
            rx = sx[m, 0] - cx_[c, 0]
            ry = sx[m, 1] - cx_[c, 1]
            rz = sx[m, 2] - cx_[c, 2]
            fx += sf[m, 0]
            fy += sf[m, 1]
            fz += sf[m, 2]
            tx += st[m, 0] + (ry * sf[m, 2] - rz * sf[m, 1])
            ty += st[m, 1] + (rz * sf[m, 0] - rx * sf[m, 2])
            tz += st[m, 2] + (rx * sf[m, 1] - ry * sf[m, 0])
        im = clu.inv_m[c]
        if im > 0.0:
            _leapfrog(cv_, cx_, c, fx, fy, fz, im, gx, gy, gz, alpha, dt)
        q0 = cq_[c, 0]
        q1 = cq_[c, 1]
        q2 = cq_[c, 2]
        q3 = cq_[c, 3]
        i0 = clu.inv_i[c, 0]
        i1 = clu.inv_i[c, 1]
        i2 = clu.inv_i[c, 2]
        if i0 > 0.0 or i1 > 0.0 or i2 > 0.0:
            if alpha > 0.0:
                tx -= alpha * abs(tx) * _sign(cw_[c, 0])
                ty -= alpha * abs(ty) * _sign(cw_[c, 1])
                tz -= alpha * abs(tz) * _sign(cw_[c, 2])
            lx = cam[c, 0] + 0.5 * dt * tx
            ly = cam[c, 1] + 0.5 * dt * ty
            lz = cam[c, 2] + 0.5 * dt * tz
            wx, wy, wz = _world_omega(q0, q1, q2, q3, i0, i1, i2, lx, ly, lz)
            h0, h1, h2, h3 = _quat_advance(q0, q1, q2, q3, wx, wy, wz, 0.5 * dt)
            cam[c, 0] += dt * tx
            cam[c, 1] += dt * ty
            cam[c, 2] += dt * tz
            wx, wy, wz = _world_omega(h0, h1, h2, h3, i0, i1, i2, cam[c, 0], cam[c, 1], cam[c, 2])
            q0, q1, q2, q3 = _quat_advance(q0, q1, q2, q3, wx, wy, wz, dt)
            cq_[c, 0] = q0
            cq_[c, 1] = q1
            cq_[c, 2] = q2
            cq_[c, 3] = q3
            cw_[c, 0] = wx
            cw_[c, 1] = wy
            cw_[c, 2] = wz
        wx = cw_[c, 0]
        wy = cw_[c, 1]
        wz = cw_[c, 2]
        for m in range(s0, s1):
            bx, by, bz = quat_rotate(q0, q1, q2, q3, clu.offset[m, 0], clu.offset[m, 1], clu.offset[m, 2])
            sx[m, 0] = cx_[c, 0] + bx
            sx[m, 1] = cx_[c, 1] + by
            sx[m, 2] = cx_[c, 2] + bz
            sv[m, 0] = cv_[c, 0] + (wy * bz - wz * by)
            sv[m, 1] = cv_[c, 1] + (wz * bx - wx * bz)
            sv[m, 2] = cv_[c, 2] + (wx * by - wy * bx)
            sw[m, 0] = wx
            sw[m, 1] = wy
            sw[m, 2] = wz
            a, b, cc = _check(sx, sv, sw, x_ref, m, ref_limit2, speed_limit2)
            n_moved += a
            n_bad += b
            n_fast += cc
    return n_moved, n_bad, n_fast


@njit(cache=True, fastmath=FASTMATH)
def panel_loads(wps, pan, force, moment):
    """Pass 4 (serial): force exerted BY the spheres ON each panel [N] and its moment about
    the panel centre [N m], from the per-wall-pair forces of the last evaluation.
    force, moment: (p, 3) outputs, overwritten."""
    force[:] = 0.0
    moment[:] = 0.0
    for k in range(wps.start[wps.start.shape[0] - 1]):
        if not wps.active[k]:
            continue
        p = wps.panel[k]
        fx = -wps.out[k, 0]
        fy = -wps.out[k, 1]
        fz = -wps.out[k, 2]
        ox = wps.out[k, 3] - pan.centre[p, 0]
        oy = wps.out[k, 4] - pan.centre[p, 1]
        oz = wps.out[k, 5] - pan.centre[p, 2]
        force[p, 0] += fx
        force[p, 1] += fy
        force[p, 2] += fz
        moment[p, 0] += oy * fz - oz * fy
        moment[p, 1] += oz * fx - ox * fz
        moment[p, 2] += ox * fy - oy * fx


# --------------------------------------------------------------------------------------
# neighbour search: cell list, half Verlet list, wall candidates
# --------------------------------------------------------------------------------------

@njit(cache=True)
def wrap_periodic(x, pax, lo, length):
    """Map coordinate ``pax`` of every row of x into [lo, lo + length)."""
    for i in range(x.shape[0]):
        s = x[i, pax] - lo
        if s < 0.0 or s >= length:
            s -= length * math.floor(s / length)
            if s >= length:   # floor rounding at the upper edge
                s -= length
            x[i, pax] = lo + s


@njit(cache=True)
def cell_sort(x, lo, inv_h, nc, pax, plo, plen):
    """Counting sort of spheres into cells. Returns (cell (n,), cell_start (ncell+1,), order (n,)).

    The periodic coordinate is wrapped into [plo, plo + plen) for binning only."""
    n = x.shape[0]
    ncell = nc[0] * nc[1] * nc[2]
    cell = np.empty(n, np.int64)
    for i in range(n):
        lin = 0
        mult = 1
        for d in range(3):
            xd = x[i, d]
            if d == pax:
                s = xd - plo
                s -= plen * math.floor(s / plen)
                xd = plo + s
            c = int(math.floor((xd - lo[d]) * inv_h[d]))
            if c < 0:
                c = 0
            elif c >= nc[d]:
                c = nc[d] - 1
            lin += c * mult
            mult *= nc[d]
        cell[i] = lin
    cell_start = np.zeros(ncell + 1, np.int64)
    for i in range(n):
        cell_start[cell[i] + 1] += 1
    for c in range(ncell):
        cell_start[c + 1] += cell_start[c]
    fill = cell_start[:-1].copy()
    order = np.empty(n, np.int64)
    for i in range(n):
        order[fill[cell[i]]] = i
        fill[cell[i]] += 1
    return cell, cell_start, order


@njit(cache=True)
def _cell_coords(c, nc):
    cx = c % nc[0]
    cy = (c // nc[0]) % nc[1]
    cz = c // (nc[0] * nc[1])
    return cx, cy, cz


# the 13 neighbour-cell offsets (dx, dy, dz) after (0, 0, 0) in lexicographic (dz, dy, dx)
# order: with the own cell they form a half stencil that meets every pair of cells once
_FORWARD = np.array([(dx, dy, dz) for dz in (-1, 0, 1) for dy in (-1, 0, 1) for dx in (-1, 0, 1)
                     if (dz, dy, dx) > (0, 0, 0)], dtype=np.int64)


@njit(parallel=True, cache=True)
def scan_pairs(x, r, clump, cell, cell_start, order, xr, clump_sorted, nc, pax, plen, skin, forward,
               rows, counts, bnd):
    """Half Verlet list into fixed-capacity rows: pairs with |x_j - x_i| < r_i + r_j + skin,
    two spheres of one clump excluded. Sphere i lists j from its own cell with j > i and
    all j from the 13 forward neighbour cells, so every pair appears once (needs >= 3
    cells along a periodic axis). xr (n, 4) = (x, y, z, r) and clump_sorted (n,) are the
    spheres in cell order (order[k] is the sphere at position k), so candidates are read
    contiguously. rows: (n, cap) output; counts: (n,) output, which may exceed cap: then
    the rows overflowed and the caller must grow cap and scan again. Cells are visited in
    a fixed order, so row contents are deterministic. ``bnd`` (Bonds, empty for none): pairs
    with an intact bond are left out (the bond replaces the contact law until it breaks)."""
    n = x.shape[0]
    cap = rows.shape[1]
    has_bonds = bnd.i.shape[0] > 0
    for i in prange(n):
        cx, cy, cz = _cell_coords(cell[i], nc)
        xi = x[i, 0]
        yi = x[i, 1]
        zi = x[i, 2]
        ri = r[i]
        ci = clump[i]
        cnt = 0
        for o in range(14):
            if o == 0:
                xx, y, z = cx, cy, cz
            else:
                xx = cx + forward[o - 1, 0]
                y = cy + forward[o - 1, 1]
                z = cz + forward[o - 1, 2]
                if z < 0 or z >= nc[2]:
                    if pax != 2:
                        continue
                    z = (z + nc[2]) % nc[2]
                if y < 0 or y >= nc[1]:
                    if pax != 1:
                        continue
                    y = (y + nc[1]) % nc[1]
                if xx < 0 or xx >= nc[0]:
                    if pax != 0:
                        continue
                    xx = (xx + nc[0]) % nc[0]
            c = (z * nc[1] + y) * nc[0] + xx
            for kk in range(cell_start[c], cell_start[c + 1]):
                if ci >= 0 and ci == clump_sorted[kk]:
                    continue
                dx, dy, dz = min_image(xr[kk, 0] - xi, xr[kk, 1] - yi, xr[kk, 2] - zi, pax, plen)
                cut = ri + xr[kk, 3] + skin
                if dx * dx + dy * dy + dz * dz < cut * cut:
                    j = order[kk]
                    if o == 0 and j <= i:
                        continue
                    if has_bonds and bonded(bnd, i, j):
                        continue
                    if cnt < cap:
                        rows[i, cnt] = j
                    cnt += 1
        counts[i] = cnt


@njit(cache=True)
def compact_rows(rows, counts, start, nbr):
    """CSR from fixed-capacity rows: start = prefix sum of counts, nbr = the rows' entries."""
    start[0] = 0
    for i in range(counts.shape[0]):
        start[i + 1] = start[i] + counts[i]
    for i in range(counts.shape[0]):
        s = start[i]
        for m in range(counts[i]):
            nbr[s + m] = rows[i, m]


@njit(parallel=True, cache=True)
def carry_pair_history(start, nbr, ut, active, old_start, old_nbr, old_ut, old_active, new_to_old):
    """Copy each surviving pair's tangential history from the previous list.

    A pair (i, j) is looked up in the old row of i, then in the old row of j: which of
    the two spheres lists the pair depends on their cells, which change between builds.
    Found the other way round, the history (a displacement of the first sphere relative
    to the second) changes sign, as does a rolling-resistance moment (columns 3-5 of a
    6-wide history, on the first sphere). ``new_to_old`` maps sphere indices if they
    were permuted; columns the old history lacks start at zero."""
    width = ut.shape[1]
    carried = min(width, old_ut.shape[1])
    for i in prange(start.shape[0] - 1):
        oi = new_to_old[i]
        for k in range(start[i], start[i + 1]):
            oj = new_to_old[nbr[k]]
            for d in range(width):
                ut[k, d] = 0.0
            active[k] = 0
            found = False
            for m in range(old_start[oi], old_start[oi + 1]):
                if old_nbr[m] == oj:
                    active[k] = old_active[m]
                    for d in range(carried):
                        ut[k, d] = old_ut[m, d]
                    found = True
                    break
            if not found:
                for m in range(old_start[oj], old_start[oj + 1]):
                    if old_nbr[m] == oi:
                        active[k] = old_active[m]
                        for d in range(carried):
                            ut[k, d] = -old_ut[m, d]
                        break


@njit(parallel=True, cache=True)
def touching_first(x, r, pax, plen, start, nbr, ut, active, nbr_tmp, ut_tmp, active_tmp):
    """Within each row, move the pairs that overlap now to the front (stable). The contact
    test in pass 1 then branches the same way for runs of pairs, which made the pass ~9 %
    faster here (branch prediction). *_tmp: scratch of the same length as nbr."""
    for i in prange(start.shape[0] - 1):
        pos = start[i]
        for first in (True, False):
            for k in range(start[i], start[i + 1]):
                dx, dy, dz = separation(x, i, nbr[k], pax, plen)
                rs = r[i] + r[nbr[k]]
                if (dx * dx + dy * dy + dz * dz < rs * rs) == first:
                    nbr_tmp[pos] = nbr[k]
                    active_tmp[pos] = active[k]
                    for d in range(ut.shape[1]):
                        ut_tmp[pos, d] = ut[k, d]
                    pos += 1
        for k in range(start[i], start[i + 1]):
            nbr[k] = nbr_tmp[k]
            active[k] = active_tmp[k]
            for d in range(ut.shape[1]):
                ut[k, d] = ut_tmp[k, d]


@njit(cache=True)
def transpose_pairs(start, nbr, n, tstart, tpair, tpos):
    """tstart/tpair: for each j, the pair indices k with nbr[k] == j, in increasing k;
    tpos: the inverse map (transposed position of each pair)."""
    total = start[n]
    tstart[:] = 0
    for k in range(total):
        tstart[nbr[k] + 1] += 1
    for j in range(n):
        tstart[j + 1] += tstart[j]
    fill = tstart[:-1].copy()
    for k in range(total):
        j = nbr[k]
        tpair[fill[j]] = k
        tpos[k] = fill[j]
        fill[j] += 1


@njit(cache=True, fastmath=FASTMATH, inline="always")
def panel_reach2(px, py, pz, pan, p, skin):
    """Squared distance from a point to the closed rectangle of panel p, ignoring the
    shared-edge rule (a sphere near a shared edge is a candidate for both panels, since it
    may cross the edge before the next list build); inf if the point lies more than
    ``skin`` behind the panel plane."""
    dx = px - pan.centre[p, 0]
    dy = py - pan.centre[p, 1]
    dz = pz - pan.centre[p, 2]
    s = dx * pan.normal[p, 0] + dy * pan.normal[p, 1] + dz * pan.normal[p, 2]
    if s <= -skin:
        return np.inf
    u = dx * pan.e1[p, 0] + dy * pan.e1[p, 1] + dz * pan.e1[p, 2]
    v = dx * pan.e2[p, 0] + dy * pan.e2[p, 1] + dz * pan.e2[p, 2]
    a = pan.half[p, 0]
    b = pan.half[p, 1]
    du = 0.0
    if u < -a:
        du = -a - u
    elif u > a:
        du = u - a
    dv = 0.0
    if v < -b:
        dv = -b - v
    elif v > b:
        dv = v - b
    return s * s + du * du + dv * dv


@njit(parallel=True, cache=True)
def scan_wall_pairs(x, r, pan, skin, start, panel, fill):
    """Sphere-panel candidates: the sphere centre within r + skin of the panel rectangle.
    Counting / filling as ``scan_pairs``."""
    n = x.shape[0]
    npan = pan.centre.shape[0]
    for i in prange(n):
        cnt = 0
        pos = start[i] if fill else 0
        for p in range(npan):
            cut = r[i] + skin
            if panel_reach2(x[i, 0], x[i, 1], x[i, 2], pan, p, skin) < cut * cut:
                if fill:
                    panel[pos] = p
                    pos += 1
                else:
                    cnt += 1
        if not fill:
            start[i + 1] = cnt


@njit(parallel=True, cache=True)
def carry_wall_history(start, panel, ut, active, out, old_start, old_panel, old_ut, old_active,
                       old_out, new_to_old):
    """Copy each surviving sphere-panel candidate's history from the previous list."""
    for i in prange(start.shape[0] - 1):
        oi = new_to_old[i]
        for k in range(start[i], start[i + 1]):
            for d in range(3):
                ut[k, d] = 0.0
            for d in range(6):
                out[k, d] = 0.0
            active[k] = 0
            for m in range(old_start[oi], old_start[oi + 1]):
                if old_panel[m] == panel[k]:
                    active[k] = old_active[m]
                    for d in range(3):
                        ut[k, d] = old_ut[m, d]
                    for d in range(6):
                        out[k, d] = old_out[m, d]
                    break


@njit(cache=True)
def body_cell_order(x_body, lo, inv_h, nc):
    """Order of bodies by the linear cell index of their position (stable), for locality."""
    n = x_body.shape[0]
    key = np.empty(n, np.int64)
    for i in range(n):
        idx = 0
        mult = 1
        for d in range(3):
            c = int(math.floor((x_body[i, d] - lo[d]) * inv_h[d]))
            c = min(max(c, 0), nc[d] - 1)
            idx += c * mult
            mult *= nc[d]
        key[i] = idx
    return np.argsort(key, kind="mergesort")


# --------------------------------------------------------------------------------------
# diagnostics (serial: float sums in a fixed order, so they are reproducible)
# --------------------------------------------------------------------------------------

@njit(cache=True)
def contact_energy(sph, prs, wps, pan, prm, pax, plen, mtab):
    """Elastic normal energy stored in all contacts (pairs and walls) at the current
    positions [J]. Tangential springs are not included (zero when mu = 0)."""
    e = 0.0
    x = sph.x
    r = sph.r
    for i in range(x.shape[0]):
        for k in range(prs.start[i], prs.start[i + 1]):
            j = prs.nbr[k]
            dx, dy, dz = separation(x, i, j, pax, plen)
            d = math.sqrt(dx * dx + dy * dy + dz * dz)
            delta = r[i] + r[j] - d
            if delta > 0.0:
                pp = prm if mtab is None else pair_params(mtab, sph.mat[i], sph.mat[j])
                e += elastic_energy(pp, delta, r[i] * r[j] / (r[i] + r[j]))
        for k in range(wps.start[i], wps.start[i + 1]):
            ok, qx, qy, qz = panel_closest_point(x[i, 0], x[i, 1], x[i, 2], pan, wps.panel[k])
            if ok:
                d = math.sqrt((qx - x[i, 0]) ** 2 + (qy - x[i, 1]) ** 2 + (qz - x[i, 2]) ** 2)
                if d < r[i]:
                    pp = prm if mtab is None else pair_params(mtab, sph.mat[i], pan.mat[wps.panel[k]])
                    e += elastic_energy(pp, r[i] - d, r[i])
    return e


# --------------------------------------------------------------------------------------
# the time loop (compiled, so a step costs no Python dispatch)
# --------------------------------------------------------------------------------------

STATUS_DONE = 0
STATUS_REBUILD = 1
STATUS_NONFINITE = 2
STATUS_TOO_FAST = 3


@njit(cache=True, fastmath=FASTMATH)
def _rotate_about(ax, ay, az, angle, vx, vy, vz):
    """Rodrigues rotation of v by ``angle`` about the unit axis a."""
    c = math.cos(angle)
    s = math.sin(angle)
    dot = ax * vx + ay * vy + az * vz
    cx = ay * vz - az * vy
    cy = az * vx - ax * vz
    cz = ax * vy - ay * vx
    k = (1.0 - c) * dot
    return vx * c + cx * s + ax * k, vy * c + cy * s + ay * k, vz * c + cz * s + az * k


@njit(cache=True, fastmath=FASTMATH)
def move_walls(pan, wall_of_panel, moving, pivot, axis, om_mid, v_mid, om_end, v_end, dt):
    """Advance every moving wall by one step: rotate its panels about the pivot by
    omega(t + dt/2) dt, translate panels and pivot by V(t + dt/2) dt, then set the panel
    velocities from omega(t + dt), V(t + dt) (dem3d.walls module docstring)."""
    for p in range(pan.centre.shape[0]):
        k = wall_of_panel[p]
        if not moving[k]:
            continue
        angle = om_mid[k] * dt
        ax = axis[k, 0]
        ay = axis[k, 1]
        az = axis[k, 2]
        if angle != 0.0:
            rx, ry, rz = _rotate_about(ax, ay, az, angle, pan.centre[p, 0] - pivot[k, 0],
                                       pan.centre[p, 1] - pivot[k, 1], pan.centre[p, 2] - pivot[k, 2])
            pan.centre[p, 0] = pivot[k, 0] + rx
            pan.centre[p, 1] = pivot[k, 1] + ry
            pan.centre[p, 2] = pivot[k, 2] + rz
            for arr in (pan.e1, pan.e2, pan.normal):
                rx, ry, rz = _rotate_about(ax, ay, az, angle, arr[p, 0], arr[p, 1], arr[p, 2])
                arr[p, 0] = rx
                arr[p, 1] = ry
                arr[p, 2] = rz
        for d in range(3):
            pan.centre[p, d] += v_mid[k, d] * dt
    for k in range(pivot.shape[0]):
        if moving[k]:
            for d in range(3):
                pivot[k, d] += v_mid[k, d] * dt
    for p in range(pan.centre.shape[0]):
        k = wall_of_panel[p]
        if not moving[k]:
            continue
        ox = axis[k, 0] * om_end[k]
        oy = axis[k, 1] * om_end[k]
        oz = axis[k, 2] * om_end[k]
        rx = pan.centre[p, 0] - pivot[k, 0]
        ry = pan.centre[p, 1] - pivot[k, 1]
        rz = pan.centre[p, 2] - pivot[k, 2]
        pan.omega[p, 0] = ox
        pan.omega[p, 1] = oy
        pan.omega[p, 2] = oz
        pan.vel[p, 0] = v_end[k, 0] + (oy * rz - oz * ry)
        pan.vel[p, 1] = v_end[k, 1] + (oz * rx - ox * rz)
        pan.vel[p, 2] = v_end[k, 2] + (ox * ry - oy * rx)


@njit(cache=True, fastmath=FASTMATH)
def move_attached(sph, att_sphere, att_wall, v_mid, dt, ref_limit2):
    """Spheres attached to a wall (immovable spheres carried by it, e.g. the rough layer
    of a shaken base) translate with the wall's pivot over the step: x += V(t + dt/2) dt,
    and carry v = V(t + dt/2) (the half-step velocity the contacts read, as a sphere's
    leapfrog velocity). Wall rotation is not applied to them. Returns how many moved
    farther than sqrt(ref_limit2) since the last list build."""
    x = sph.x
    v = sph.v
    moved = 0
    for k in range(att_sphere.shape[0]):
        i = att_sphere[k]
        w = att_wall[k]
        dd = 0.0
        for d in range(3):
            v[i, d] = v_mid[w, d]
            x[i, d] += v_mid[w, d] * dt
            e = x[i, d] - sph.x_ref[i, d]
            dd += e * e
        if dd > ref_limit2:
            moved += 1
    return moved


@njit(cache=True, fastmath=FASTMATH)
def wall_displacement(pan, ref_centre, ref_e1, ref_e2):
    """Bound on the displacement of any panel point since the reference pose [m]
    (|dq| <= |dc| + a |de1| + b |de2|)."""
    worst = 0.0
    for p in range(pan.centre.shape[0]):
        dc = 0.0
        du = 0.0
        dv = 0.0
        for d in range(3):
            dc += (pan.centre[p, d] - ref_centre[p, d]) ** 2
            du += (pan.e1[p, d] - ref_e1[p, d]) ** 2
            dv += (pan.e2[p, d] - ref_e2[p, d]) ** 2
        disp = math.sqrt(dc)
        if du > 0.0:
            disp += pan.half[p, 0] * math.sqrt(du)
        if dv > 0.0:
            disp += pan.half[p, 1] * math.sqrt(dv)
        if disp > worst:
            worst = disp
    return worst


@njit(cache=True, fastmath=FASTMATH)
def segments_velocity(seg, panel_force, dt):
    """One step of the free-field segment balance (``state.Segments``; ``dem3d.freefield``
    module docstring), per local component, the dashpot implicit:
        V+ = (M V- / dt + F_contacts + A t_ff + A rho C v_ff) / (M / dt + A rho C),
    F_contacts the last step's force of the spheres on the segment's panels. Updates
    ``seg.velocity`` in place (world frame)."""
    vel = seg.velocity
    q = seg.frame
    for s in range(vel.shape[0]):
        p0 = seg.panel[seg.panel_start[s]]
        fx = panel_force[p0, 0]
        fy = panel_force[p0, 1]
        fz = panel_force[p0, 2]
        for k in range(seg.panel_start[s] + 1, seg.panel_start[s + 1]):
            fx += panel_force[seg.panel[k], 0]
            fy += panel_force[seg.panel[k], 1]
            fz += panel_force[seg.panel[k], 2]
        m_dt = seg.mass[s] / dt
        l0 = 0.0
        l1 = 0.0
        l2 = 0.0
        for i in range(3):
            qv = q[s, i, 0] * vel[s, 0] + q[s, i, 1] * vel[s, 1] + q[s, i, 2] * vel[s, 2]
            qf = q[s, i, 0] * fx + q[s, i, 1] * fy + q[s, i, 2] * fz
            num = m_dt * qv + qf + seg.traction[s, i] + seg.dashpot[s, i]
            v_local = num / (m_dt + seg.area[s] * seg.impedance[s, i])
            if i == 0:
                l0 = v_local
            elif i == 1:
                l1 = v_local
            else:
                l2 = v_local
        for j in range(3):
            vel[s, j] = q[s, 0, j] * l0 + q[s, 1, j] * l1 + q[s, 2, j] * l2


@njit(cache=True)
def advance(sph, clu, prs, wps, pan, prm, dt, gx, gy, gz, pax, plen, skin, speed_limit2,
            walls, loads, n_steps, time, mtab, has_fext, bnd, att, rolling, seg, direct=None):
    """Run up to ``n_steps`` steps (module docstring, passes 1-4, then the walls move).

    walls: ``state.WallMotion`` (the motion samples of each step: only rows of moving
    walls are read); loads: ``state.PanelLoads`` (the last step's panel loads and, with
    rows, every step's).
    mtab, has_fext, bnd: material table or None, external forces on/off, Bonds (empty for
    none, ``bonds.kernel_bonds``: a runtime check, not a specialisation, so runs with and
    without bonds share one compiled advance); bonds are evaluated first in each step.
    att: (spheres, walls) int64 arrays of spheres carried by moving walls, empty for none
    (``move_attached``, after the spheres move, before the walls do; one check per step,
    so it is not a separate specialisation).
    rolling: some contact has rolling resistance (``pair_forces`` then sums the moments).
    seg: ``state.Segments`` (empty for none, ``state.NO_SEGMENTS``; a runtime check, as
    for bonds): boundary segments whose velocity each step sets for the next (``segments_velocity``, after the walls move; written into the next step's
    rows of ``walls``).
    direct: None or True, as in pair_forces and gather_and_move.
    Returns (steps_done, time, status, count): stops early with STATUS_REBUILD after a step
    that moved a sphere or a panel more than skin/2 since the last list build, or broke a
    bond (the pair must enter the neighbour list), or with STATUS_NONFINITE /
    STATUS_TOO_FAST (count = offending spheres).
    """
    wall_of_panel, moving, pivot, axis, ref_centre, ref_e1, ref_e2, om_mid, v_mid, om_end, v_end = walls
    panel_force, panel_moment, hist_force, hist_moment = loads
    ref_limit2 = (0.5 * skin) ** 2
    has_clumps = clu.x.shape[0] > 0
    n_pan = pan.centre.shape[0]
    record = hist_force.shape[0] > 0
    any_moving = False
    for k in range(moving.shape[0]):
        if moving[k]:
            any_moving = True
    # the flags handed on are runtime bools (a literal True is typed Literal[bool]), as the
    # engine's evaluate_forces passes them from Python: both then call the same compiled
    # pair_forces and gather_and_move, each compiled once (~25-30 s apiece)
    integrate = n_steps >= 0
    for s in range(n_steps):
        broken = 0
        if bnd.i.shape[0] > 0:
            broken = bond_forces(sph, bnd, dt, pax, plen)
        if rolling:
            pair_forces(sph, prs, prm, dt, pax, plen, mtab, rolling, direct)
        else:
            pair_forces(sph, prs, prm, dt, pax, plen, mtab, None, direct)
        moved, bad, fast = gather_and_move(sph, prs, wps, pan, prm, dt, gx, gy, gz,
                                           ref_limit2, speed_limit2, integrate, mtab, has_fext, bnd, direct)
        if has_clumps:
            m2, b2, f2 = move_clumps(sph, clu, prm, dt, gx, gy, gz, ref_limit2, speed_limit2)
            moved += m2
            bad += b2
            fast += f2
        if any_moving and att[0].shape[0] > 0:
            moved += move_attached(sph, att[0], att[1], v_mid[s], dt, ref_limit2)
        if n_pan > 0:
            panel_loads(wps, pan, panel_force, panel_moment)
            if record:
                hist_force[s] = panel_force
                hist_moment[s] = panel_moment
            if any_moving:
                move_walls(pan, wall_of_panel, moving, pivot, axis, om_mid[s], v_mid[s], om_end[s], v_end[s], dt)
            if seg.wall.shape[0] > 0:
                segments_velocity(seg, panel_force, dt)
                if s + 1 < n_steps:
                    for g in range(seg.wall.shape[0]):
                        for c in range(3):
                            v_mid[s + 1, seg.wall[g], c] = seg.velocity[g, c]
                            v_end[s + 1, seg.wall[g], c] = seg.velocity[g, c]
        time += dt
        if bad > 0:
            return s + 1, time, STATUS_NONFINITE, bad
        if fast > 0:
            return s + 1, time, STATUS_TOO_FAST, fast
        if moved > 0 or broken > 0:
            return s + 1, time, STATUS_REBUILD, moved
        if any_moving and wall_displacement(pan, ref_centre, ref_e1, ref_e2) > 0.5 * skin:
            return s + 1, time, STATUS_REBUILD, 0
    return n_steps, time, STATUS_DONE, 0
