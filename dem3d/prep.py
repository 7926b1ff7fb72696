"""Specimen preparation: random non-overlapping generation and settling under gravity.

Pure functions over the engine (no I/O). Randomness comes only from the numpy
``Generator`` passed in, so a seed reproduces a specimen exactly.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from analytic.errors import InvalidParameter
from analytic.inputs import require_number

from .engine import Simulation
from .measure import kinetic_energy, unbalanced_force_ratio
from .state import Specimen


def random_specimen(rng: np.random.Generator, lo, hi, n_bodies: int, d_min: float, d_max: float, *,
                    clump_fraction: float = 0.0, clump_overlap: float = 1.0, density: float = 2650.0,
                    max_attempts_per_body: int = 2000) -> Specimen:
    """Place ``n_bodies`` non-overlapping bodies at random inside the box [lo, hi] [m]
    (random sequential addition), every sphere wholly inside the box.

    Diameters are uniform in [d_min, d_max] (Nadukuru & Michalowski 2012: 4.60-7.36 cm).
    A fraction ``clump_fraction`` of the bodies are two-sphere clumps of two equal spheres
    of the drawn diameter whose overlap is ``clump_overlap`` radii (centre distance
    (2 - clump_overlap) r; 1 = "overlap of one radius"), in a uniformly random direction.
    Raises InvalidParameter if the box is too full to place them (random sequential
    addition jams near a solid fraction of ~0.38 for spheres: generate loosely, then settle).
    """
    lo = np.asarray(lo, float).reshape(3)
    hi = np.asarray(hi, float).reshape(3)
    n_bodies = int(n_bodies)
    if n_bodies < 1:
        raise InvalidParameter("n_bodies", n_bodies, ">= 1")
    d_min = require_number("d_min", d_min, 0.0, None, unit="m")
    d_max = require_number("d_max", d_max, d_min, None, lo_open=False, unit="m")
    clump_fraction = require_number("clump_fraction", clump_fraction, 0.0, 1.0, lo_open=False, hi_open=False)
    clump_overlap = require_number("clump_overlap", clump_overlap, 0.0, 2.0, lo_open=False)
    if not np.all(hi - lo > d_max * (3.0 - clump_overlap)):
        raise InvalidParameter("hi - lo", tuple(hi - lo), f"> {d_max * (3.0 - clump_overlap):.4g} m per side")
    diam = rng.uniform(d_min, d_max, n_bodies)
    is_clump = np.zeros(n_bodies, bool)
    n_clumps = int(round(clump_fraction * n_bodies))
    is_clump[rng.permutation(n_bodies)[:n_clumps]] = True
    n_spheres = n_bodies + n_clumps
    pos = np.zeros((n_spheres, 3))
    rad = np.zeros(n_spheres)
    label = -np.ones(n_spheres, np.int64)
    cell = d_max          # two spheres can only overlap if their centres are < d_max apart
    nc = np.maximum(1, np.floor((hi - lo) / cell)).astype(np.int64)
    head = -np.ones(int(np.prod(nc)), np.int64)
    nxt = -np.ones(n_spheres, np.int64)
    placed_spheres = 0
    batch = 4096
    body = 0
    attempts = 0
    while body < n_bodies:
        u = rng.random((batch, 5))        # 3 position + 2 orientation numbers per attempt
        used, body, placed_spheres, attempts = _place(u, body, n_bodies, diam, is_clump, clump_overlap,
                                                      lo, hi, pos, rad, label, head, nxt, nc, cell,
                                                      placed_spheres, attempts, max_attempts_per_body)
        if used < batch and body < n_bodies:
            raise InvalidParameter("n_bodies", n_bodies, f"<= {body} for this box",
                                   f"no free spot found in {max_attempts_per_body} random tries")
    return Specimen(pos[:placed_spheres], rad[:placed_spheres], label[:placed_spheres], float(density))


@njit(cache=True)
def _place(u, body, n_bodies, diam, is_clump, overlap, lo, hi, pos, rad, label, head, nxt, nc, cell,
           placed, attempts, max_attempts):
    """Consume random rows of ``u`` to place bodies; returns (rows used, next body,
    spheres placed, attempts at the current body). Stops early (rows used < len(u)) when
    one body needs more than ``max_attempts`` tries."""
    for row in range(u.shape[0]):
        if body >= n_bodies:
            return row, body, placed, attempts
        if attempts >= max_attempts:
            return row, body, placed, attempts
        attempts += 1
        r = 0.5 * diam[body]
        two = is_clump[body]
        half = (1.0 - 0.5 * overlap) * r if two else 0.0     # centre to member centre
        # direction uniform on the sphere
        cz = 2.0 * u[row, 3] - 1.0
        phi = 2.0 * math.pi * u[row, 4]
        sz = math.sqrt(max(0.0, 1.0 - cz * cz))
        e0 = sz * math.cos(phi)
        e1 = sz * math.sin(phi)
        e2 = cz
        reach = r + half * np.array([abs(e0), abs(e1), abs(e2)])
        c = np.empty(3)
        ok = True
        for d in range(3):
            span = hi[d] - lo[d] - 2.0 * reach[d]
            if span <= 0.0:
                ok = False
            c[d] = lo[d] + reach[d] + u[row, d] * span
        if not ok:
            continue
        m = 2 if two else 1
        cand = np.empty((m, 3))
        for s in range(m):
            sign = 1.0 if s == 0 else -1.0
            cand[s, 0] = c[0] + sign * half * e0
            cand[s, 1] = c[1] + sign * half * e1
            cand[s, 2] = c[2] + sign * half * e2
        free = True
        for s in range(m):
            if not free:
                break
            idx = np.empty(3, np.int64)
            for d in range(3):
                idx[d] = min(max(int((cand[s, d] - lo[d]) / cell), 0), nc[d] - 1)
            for oz in range(max(idx[2] - 1, 0), min(idx[2] + 2, nc[2])):
                for oy in range(max(idx[1] - 1, 0), min(idx[1] + 2, nc[1])):
                    for ox in range(max(idx[0] - 1, 0), min(idx[0] + 2, nc[0])):
                        q = head[(oz * nc[1] + oy) * nc[0] + ox]
                        while q >= 0:
                            dx = cand[s, 0] - pos[q, 0]
                            dy = cand[s, 1] - pos[q, 1]
                            dz = cand[s, 2] - pos[q, 2]
                            lim = r + rad[q]
                            if dx * dx + dy * dy + dz * dz < lim * lim:
                                free = False
                                break
                            q = nxt[q]
                        if not free:
                            break
                    if not free:
                        break
                if not free:
                    break
        if not free:
            continue
        for s in range(m):
            pos[placed] = cand[s]
            rad[placed] = r
            label[placed] = body if two else -1
            lin = 0
            mult = 1
            for d in range(3):
                lin += min(max(int((cand[s, d] - lo[d]) / cell), 0), nc[d] - 1) * mult
                mult *= nc[d]
            nxt[placed] = head[lin]
            head[lin] = placed
            placed += 1
        body += 1
        attempts = 0
    return u.shape[0], body, placed, attempts


class SettleResult(NamedTuple):
    """steps taken, final unbalanced-force ratio, final kinetic energy [J], converged."""

    steps: int
    ratio: float
    kinetic_energy: float
    converged: bool


def settle(sim: Simulation, *, ratio: float = 1e-3, check_every: int = 200, max_steps: int = 200_000,
           min_steps: int = 0, trace: list | None = None, energy: float | None = None) -> SettleResult:
    """Step ``sim`` (particles falling and settling under gravity: raining when the
    specimen was generated above its final height) until PFC's unbalanced-force ratio
    (dem3d.measure.unbalanced_force_ratio) falls below ``ratio``, checked every
    ``check_every`` steps after ``min_steps``. Local damping, if wanted, is set on the
    contact parameters beforehand (``dem3d.params.with_local_damping``).

    ``energy`` [J], if given, is a second way to converge: the kinetic energy below it.
    The ratio is a mean over bodies, so a few grains that keep bouncing on the surface
    (rattlers; at high gravity they never come to rest) hold it up while the packing
    itself no longer moves; an energy bound says how much motion is left without that
    bias (e.g. a fraction of N m g d: each grain's energy of a drop of one diameter).

    ``trace``, if given, gets one (steps taken, ratio, kinetic energy [J]) per check: how
    a stage approached (or missed) its ratio, for reports on preparation time."""
    ratio = require_number("ratio", ratio, 0.0, None)
    taken = 0
    current = math.inf
    while taken < max_steps:
        k = min(check_every, max_steps - taken)
        sim.step(k)
        taken += k
        if taken < min_steps:
            continue
        current = unbalanced_force_ratio(sim)
        if trace is not None:
            trace.append((taken, current, kinetic_energy(sim)))
        if current < ratio:
            return SettleResult(taken, current, kinetic_energy(sim), True)
        if energy is not None and (ke := kinetic_energy(sim)) < energy:
            return SettleResult(taken, current, ke, True)
    return SettleResult(taken, current, kinetic_energy(sim), False)
