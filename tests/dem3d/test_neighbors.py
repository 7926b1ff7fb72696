"""The cell list + Verlet list finds every contact: forces equal a brute-force O(n^2) sum."""

import math

import numpy as np

from dem3d import Periodic, Simulation, Specimen, Wall, box, linear
from dem3d import kernels


def brute_force(sim):
    """Force and torque on every sphere from all sphere pairs (minimum image along the
    periodic axis, clump mates excluded) and all panels, with the engine's contact law and
    zero tangential history (a freshly built simulation)."""
    sph = sim.spheres
    x, v, w, r = sph.x, sph.v, sph.w, sph.r
    n = x.shape[0]
    prm = sim.params
    f = np.zeros((n, 3))
    t = np.zeros((n, 3))
    ax, length = sim.periodic.axis, sim.periodic.length
    for i in range(n):
        d = x - x[i]
        d[:, ax] -= length * np.round(d[:, ax] / length)
        dist = np.linalg.norm(d, axis=1)
        for j in np.nonzero((dist < r + r[i]) & (np.arange(n) > i))[0]:
            if sph.clump[i] >= 0 and sph.clump[i] == sph.clump[j]:
                continue
            nrm = d[j] / dist[j]
            delta = r[i] + r[j] - dist[j]
            ai, aj = r[i] - delta / 2, r[j] - delta / 2
            vr = v[i] - v[j] + np.cross(ai * w[i] + aj * w[j], nrm)
            m_eff = 1.0 / (sph.inv_m[i] + sph.inv_m[j])
            fx, fy, fz, _, _, _, _ = kernels.contact_law(prm, prm.mu, delta, *nrm, *vr, m_eff,
                                                         r[i] * r[j] / (r[i] + r[j]), 0.0, 0.0, 0.0, sim.dt)
            force = np.array([fx, fy, fz])
            f[i] += force
            f[j] -= force
            t[i] += ai * np.cross(nrm, force)
            t[j] += aj * np.cross(nrm, force)
        pan = sim.panels
        for p in range(pan.centre.shape[0]):
            ok, qx, qy, qz = kernels.panel_closest_point(x[i, 0], x[i, 1], x[i, 2], pan, p)
            if not ok:
                continue
            d = np.array([qx, qy, qz]) - x[i]
            dist = np.linalg.norm(d)
            if dist >= r[i]:
                continue
            nrm = d / dist
            delta = r[i] - dist
            a = r[i] - delta / 2
            vr = v[i] + a * np.cross(w[i], nrm)
            fx, fy, fz, _, _, _, _ = kernels.contact_law(prm, pan.mu[p], delta, *nrm, *vr, 1.0 / sph.inv_m[i],
                                                         r[i], 0.0, 0.0, 0.0, sim.dt)
            force = np.array([fx, fy, fz])
            f[i] += force
            t[i] += a * np.cross(nrm, force)
    return f, t


def test_neighbour_list_forces_equal_brute_force():
    """400 free spheres and 40 two-sphere clumps at random (overlapping) positions in a box
    periodic along y, random velocities and spins: every sphere's force and torque from the
    engine equals the brute-force sum (to round-off of the summation order)."""
    rng = np.random.default_rng(3)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([0.4, 0.3, 0.4])
    n_free, n_clump = 400, 40
    r = rng.uniform(0.012, 0.02, n_free + n_clump)
    centres = lo + r[:, None] * 0.5 + rng.random((n_free + n_clump, 3)) * (hi - lo - r[:, None])
    pos, rad, lab = [], [], []
    for b in range(n_free + n_clump):
        if b < n_free:
            pos.append(centres[b]); rad.append(r[b]); lab.append(-1)
        else:
            e = rng.normal(size=3)
            e /= np.linalg.norm(e)
            for s in (-0.5, 0.5):
                pos.append(centres[b] + s * r[b] * e); rad.append(r[b]); lab.append(b)
    spec = Specimen(np.array(pos), np.array(rad), np.array(lab), 2650.0)
    sim = Simulation(spec, linear(1e5, 4e4, 0.5, zeta_n=0.2, zeta_s=0.1),
                     dt=1e-5, walls=[Wall("box", box(lo, hi, mu=0.3, top=True, periodic_axis=1))],
                     periodic=Periodic(1, 0.0, 0.3))
    free = sim.spheres.clump < 0
    sim.spheres.v[free] = rng.normal(0.0, 0.5, (free.sum(), 3))
    sim.spheres.w[free] = rng.normal(0.0, 20.0, (free.sum(), 3))
    f_ref, t_ref = brute_force(sim)
    f, t = sim.evaluate_forces()
    assert np.count_nonzero(sim.pairs.active) > 300            # a dense, overlapping packing
    scale_f = np.abs(f_ref).max()
    scale_t = np.abs(t_ref).max()
    np.testing.assert_allclose(f, f_ref, rtol=0, atol=1e-12 * scale_f)
    np.testing.assert_allclose(t, t_ref, rtol=0, atol=1e-12 * scale_t)
