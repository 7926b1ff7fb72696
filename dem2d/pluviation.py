"""Layered pluviation: drop the backfill in layers from a set height, let each settle.

Khosravi et al. (§3.1, Fig. 5) fill the box "layer by layer ... where the soil particles
dropped under the gravity force"; air pluviation gives a uniform density when the drop
height and the layer thickness are constant. Here each layer is a loose cloud of grains
(areal solid fraction ``cloud_fraction``, zero velocity) whose bottom starts
``drop_height`` above the current surface; it falls, lands and is left to settle until
the unbalance (sum |m a| / sum m g, ``measure.weight_normalised_unbalance``) and the
kinetic energy per grain are small, then the next layer is released. A layer holds the number of grains that fills ``layer_thickness`` at
the expected deposit fraction ``target_fraction`` (the last layer is cut to reach H).

The layer loop is a generator: it yields after every check (``check_every`` steps)
so the caller can draw frames, show progress or stop.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Iterator, NamedTuple

import numpy as np

from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param

from .build import add_disks
from analytic.constants import G

from .grading import Grading
from .measure import kinetic_energy, weight_normalised_unbalance
from .params import Material
from .sim import Sim


@dataclass(frozen=True)
class Pluviation:
    """Layered pluviation settings (module docstring)."""

    # layers = H / layer_thickness, each settling >= min_layer_time and <= max_layer_time: at 0.5 mm
    # (about the finest grain) a 0.3 m fill is 600 layers, up to 6e5 steps at 0.4 s a layer and
    # layer_dt 4e-4 s, ~2 days at the paper's grain size; thinner layers only add layers
    layer_thickness: float = param(0.02, unit="m", lo=5e-4, meaning="deposit per layer (the last is cut to reach H)")
    drop_height: float = param(0.005, unit="m", lo=0,
                               meaning="gap between the surface and the bottom of the falling cloud")
    cloud_fraction: float = param(0.5, lo=0, hi=0.5, lo_open=True,
                                  meaning="areal solid fraction of the released cloud (at most ~0.5)")
    target_fraction: float = param(0.82, lo=0, hi=0.907, lo_open=True, hi_open=True,
                                   meaning="expected solid fraction of the deposit, sizes each layer")
    # viscous, so it also caps the fall speed at g tau, tau = -1 / ln(damping); reset to 1 when
    # the filling ends
    damping: float = param(1.0, lo=0, hi=1, lo_open=True,
                           meaning="pymunk space.damping while filling: fraction of velocity left after 1 s "
                                   "(1 = none)")
    settle_ratio: float = param(0.05, lo=0, lo_open=True,
                                meaning="a layer is settled when the weight-normalised unbalance of its grains "
                                        "is below this (and settle_ke holds)")
    settle_ke: float = param(1e-3, lo=0, lo_open=True,
                             meaning="a layer is settled only when its kinetic energy per grain is also below this "
                                     "times m g d50")
    final_ratio: float = param(0.01, lo=0, lo_open=True,
                               meaning="the settle_ratio criterion for the whole deposit after the last layer")
    # each layer is stepped for at least min_layer_time and at most max_layer_time; the last
    # layer for at most final_settle_time: 10 s is 2.5e4 steps at layer_dt 4e-4 s, and ~15
    # layers of the paper's fill at that cap ~4e5 steps, ~1 day at the paper's grain size
    min_layer_time: float = param(0.03, unit="s", lo=0, hi=10,
                                  meaning="never release the next layer earlier than this")
    max_layer_time: float = param(0.4, unit="s", lo=0, hi=10,
                                  meaning="release the next layer after this even if not settled")
    # 10 s is 5e4 steps at 2e-4 s, ~8 h at 61k disks and 40 sweeps (~0.6 s a step)
    final_settle_time: float = param(1.0, unit="s", lo=0, hi=10, meaning="at most this long for the last layer")
    # a layer steps at least check_every steps: 10,000 are 2-4 s of fill, 1-2 h at 61k disks
    check_every: int = param(50, lo=1, hi=10_000, meaning="steps between settling checks")
    # grains within hold_margin of a wall or the floor are never held, so the pressure cells
    # keep their contacts; all are released, with their contact impulses, before the last
    # layer settles
    hold_depth: float = param(0.0, unit="m", lo=0,
                              meaning="grains deeper than this below the surface are held static while the next "
                                      "layers fall (0 = the whole deposit moves throughout)")
    hold_margin: float = param(2.0, lo=0,
                               meaning="the strip along the walls and floor that is never held, in largest grain "
                                       "diameters")
    # below 1e-5 s a fill needs > 40x the steps of the case's 4e-4 s (as Solver.dt)
    layer_dt: float | None = param(None, unit="s", lo=1e-5, hi=0.01, hi_open=True,
                                   meaning="time step while the layers fall and settle (none = the solver's); the "
                                           "last layer always settles at the solver's dt")
    # instead of the one-step ratio below final_ratio, which the impulse solver's
    # step-to-step jitter keeps at 0.02-0.04 on a deposit that no longer moves; a released
    # deposit rocks for a while, and one window can catch it level
    final_balance: float | None = param(None, lo=0, hi=1, lo_open=True, hi_open=True,
                                        meaning="when set, the deposit is settled when the walls' and floor's vertical "
                                                "reactions equal its weight within this fraction (none = final_ratio)")
    # each window is check_every steps: 1000 windows of 50 steps at 2e-4 s are 10 s, the cap of
    # final_settle_time
    final_windows: int = param(3, lo=1, hi=1000,
                               meaning="consecutive check windows that must meet final_balance")

    def __post_init__(self):
        check_fields(self)


class LayerStatus(NamedTuple):
    """Progress of the pluviation: layer (1-based), of n_layers, grains so far, surface
    height [m], weight-normalised unbalance [-], KE per grain / (m g d50) [-], settled flag,
    and done: the last status of this layer (settled, or its time limit reached);
    balance: vertical reactions / weight over the last check window (last layer with
    ``final_balance`` only, else nan)."""

    layer: int
    n_layers: int
    n_grains: int
    surface: float
    ratio: float
    ke: float
    settled: bool
    done: bool = False
    balance: float = float("nan")


def cloud(n: int, grading: Grading, rng: np.random.Generator, x0: float, x1: float,
          y0: float, fraction: float) -> tuple[np.ndarray, np.ndarray]:
    """``n`` non-overlapping disks (centres (n,2), radii (n,)) filling the strip x0..x1
    upwards from y0 in rows, at an areal solid fraction close to ``fraction``.

    Grains are drawn from the grading in random order and laid along each row with a
    clear gap g between neighbours; a row is as tall as its largest grain plus g. The gap
    is chosen so that mean area / ((E[d] + g)(d_max + g)) = fraction (rows are about
    d_max + g tall), then each grain gets a random vertical jitter inside its row and
    each row a random start, so the cloud has no lattice."""
    d = grading.sample(n, rng)
    a, b = grading.d_min, grading.d_max
    mean_d = a * b / (b - a) * math.log(b / a) if b > a else a
    A = grading.mean_area()
    # solve A / ((mean_d + g)(b + g)) = fraction for g >= 0
    s = mean_d + b
    disc = s * s - 4 * (mean_d * b - A / fraction)
    g = max((-s + math.sqrt(max(disc, 0.0))) / 2.0, 0.02 * b)
    centres = np.empty((n, 2))
    width = x1 - x0
    if width < b + g:
        raise InvalidParameter("box width", width, f"> {b + g:g} m", "narrower than one grain")
    k, y = 0, y0
    while k < n:
        x = x0 + rng.uniform(0.0, g)
        row = []
        while k + len(row) < n:
            di = d[k + len(row)]
            if x + di > x1:
                break
            row.append(x + di / 2)
            x += di + g
        m = len(row)
        dr = d[k:k + m]
        h = dr.max() + g
        centres[k:k + m, 0] = row
        centres[k:k + m, 1] = y + dr / 2 + rng.uniform(0.0, 1.0, m) * (h - g - dr)
        k += m
        y += h
    return centres, d / 2


def surface_height(position: np.ndarray, radius: np.ndarray, settled: np.ndarray,
                   x0: float, x1: float, bins: int = 10) -> float:
    """Height of the deposit's surface [m]: the mean over ``bins`` vertical strips of the
    highest grain top among settled grains."""
    if not np.any(settled):
        return 0.0
    p, r = position[settled], radius[settled]
    top = p[:, 1] + r
    k = np.clip(((p[:, 0] - x0) / (x1 - x0) * bins).astype(int), 0, bins - 1)
    tops = np.full(bins, np.nan)
    for b in range(bins):
        m = k == b
        if np.any(m):
            tops[b] = top[m].max()
    return float(np.nanmean(tops))


def _overburden_factor(sim: Sim, surface: float) -> np.ndarray | None:
    """Per held contact, (surface now - contact height) / (surface when it was held -
    contact height): a geostatic estimate of how much its load grew while it was held
    (>= 1). Used to scale the saved impulses when the deposit is released."""
    c = sim.held_contacts()
    if len(c["a"]) == 0:
        return None
    y = sim.state().position[:, 1]
    yc = 0.5 * (y[c["a"]] + y[c["b"]])
    return np.clip((surface - yc) / np.maximum(c["tag"] - yc, 1e-12), 1.0, None)


def pluviate(sim: Sim, grading: Grading, material: Material, *, x0: float, x1: float,
             floor: float, height: float, settings: Pluviation,
             g: float = G) -> Iterator[LayerStatus]:
    """Fill the strip x0..x1 above ``floor`` [m] to ``height`` [m] of deposit, layer by
    layer (module docstring). Grains go into ``sim`` (disks, ``material``); the random
    draws come from ``sim.rng``. Yields a ``LayerStatus`` after every settling check;
    the ratio and kinetic energy are those of the newest layer, and after the last
    layer those of the whole deposit."""
    p = settings
    width = x1 - x0
    n_layers = max(1, math.ceil(height / p.layer_thickness - 1e-9))
    margin = 0.0005 * width
    deposited_area = float(np.sum(np.pi * sim.grains.circle_radius**2))  # > 0 when resumed
    d50 = grading.d50
    sim.space.damping = p.damping
    # the run's own solver; a checkpoint taken mid-fill carries it in meta, since its
    # sim.solver is then the layer_dt one
    solver = sim.meta.setdefault("fill_solver", sim.solver)
    if p.layer_dt is not None:
        sim.set_solver(dataclasses.replace(solver, dt=p.layer_dt))
    keep_free = p.hold_margin * grading.d_max
    try:
        for layer in range(1, n_layers + 1):
            if len(sim.grains):
                st = sim.state()
                surf = surface_height(st.position, sim.grains.circle_radius,
                                      np.ones(len(sim.grains), bool), x0, x1)
            else:
                surf = floor
            # grains to add: fill up to the goal at the fraction the deposit has so far
            # (the target fraction until there is a deposit to measure)
            frac = p.target_fraction
            if surf - floor > 4 * p.layer_thickness / 2:
                frac = min(max(deposited_area / (width * (surf - floor)), 0.5), 0.9)
            goal = min(layer * p.layer_thickness, height)
            if layer <= sim.meta.get("fill_layers_done", 0):
                continue  # continued from a snapshot taken after this layer: it is there
            area_needed = (goal - max(surf - floor, 0.0)) * width * frac
            n = max(int(round(area_needed / grading.mean_area())), 0)
            last = layer == n_layers
            if last:
                if sim.held().any():  # the surface it is filled to; a fresh space in creation order
                    sim.release_all(_overburden_factor(sim, floor + goal), rebuild=True)
                sim.set_solver(solver)
            elif p.hold_depth > 0 and len(sim.grains):
                x, y = st.position[:, 0], st.position[:, 1]
                deep = ((y < surf - p.hold_depth) & (x - x0 > keep_free) & (x1 - x > keep_free)
                        & (y - floor > keep_free))
                sim.hold(np.flatnonzero(deep), tag=surf)
            first = len(sim.grains)
            if n:
                centres, radii = cloud(n, grading, sim.rng, x0 + margin, x1 - margin,
                                       max(surf, floor) + p.drop_height, p.cloud_fraction)
                add_disks(sim.space, sim.grains, centres, radii, material, sim.rng)
                deposited_area += float(np.sum(np.pi * radii**2))
            mass = sim.masses()
            sel = slice(0, None) if last else slice(first, None)
            m_sel = mass[sel]
            scale = float(np.sum(m_sel)) * g * d50
            t_start = sim.time
            limit = p.final_settle_time if last else p.max_layer_time
            by_balance = last and p.final_balance is not None
            level_windows = 0
            while True:
                if by_balance:
                    sim.probe.start()
                sim.run(p.check_every - 1)
                st_a = sim.state()
                sim.run(1)
                st = sim.state()
                balance = float("nan")
                if by_balance:
                    sim.probe.stop()
                    balance = -float(np.sum(sim.probe.force()[:, 1])) / (float(np.sum(m_sel)) * g)
                ratio = weight_normalised_unbalance(st_a.velocity[sel], st.velocity[sel], sim.dt, m_sel, g)
                ke = kinetic_energy(st.velocity[sel], m_sel) / scale
                elapsed = sim.time - t_start
                if by_balance:
                    level_windows = level_windows + 1 if abs(balance - 1.0) < p.final_balance else 0
                    at_rest = level_windows >= p.final_windows
                else:
                    at_rest = ratio < (p.final_ratio if last else p.settle_ratio)
                settled = elapsed >= p.min_layer_time and at_rest and ke < p.settle_ke
                surf = surface_height(st.position, sim.grains.circle_radius,
                                      np.linalg.norm(st.velocity, axis=1) < 0.05, x0, x1)
                done = settled or elapsed >= limit
                if done:
                    sim.meta["fill_layers_done"] = layer   # a snapshot taken now goes on at the next
                yield LayerStatus(layer, n_layers, len(sim.grains), surf, ratio, ke, settled, done, balance)
                if done:
                    break
    finally:
        sim.space.damping = 1.0
        if sim.solver.dt != solver.dt:
            sim.set_solver(solver)
        sim.meta.pop("fill_solver", None)
        if sim.meta.get("fill_layers_done", 0) >= n_layers:
            sim.meta.pop("fill_layers_done")
