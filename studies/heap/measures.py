"""What a heap run reads of its state: the heap's shape (``heap_shape``), porosity and
weight, the stress on the base bins (``base_stress``), the centre-over-peak ratio of
Fig. 1(c) and the centre's subsidence."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic.constants import G
from dem3d import measure

from .case import HeapCase, base_ids


# ----------------------------------------------------------------------------- measures
def on_base(case: HeapCase, x: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Spheres of the heap: above the catch floor's spill (z > -2 r) and over the base."""
    return (x[:, 2] > -2.0 * r) & (np.abs(x[:, 0]) <= 0.5 * case.base_length + r)


@dataclass(frozen=True)
class Shape:
    """The heap's shape: height H [m] (mean surface height over the central 0.4 m),
    slope [deg] (a line fitted to the surface of both flanks between 0.2 H and 0.8 H),
    the surface height of each 0.1 m column (x, top) and the grains on the base."""

    H: float
    slope_deg: float
    x: np.ndarray
    top: np.ndarray
    spheres: int


def heap_shape(case: HeapCase, sim) -> Shape:
    x, r = sim.spheres.x, sim.spheres.r
    keep = on_base(case, x, r)
    edges = np.arange(-0.5 * case.base_length, 0.5 * case.base_length + 1e-9, 0.1)
    col = np.clip(np.digitize(x[keep, 0], edges) - 1, 0, len(edges) - 2)
    top = np.zeros(len(edges) - 1)
    np.maximum.at(top, col, x[keep, 2] + r[keep])
    xc = 0.5 * (edges[1:] + edges[:-1])
    H = float(top[np.abs(xc) < 0.2].mean())
    flank = (top > 0.2 * H) & (top < 0.8 * H)
    slope = -np.polyfit(np.abs(xc[flank]), top[flank], 1)[0] if flank.sum() >= 2 else float("nan")
    return Shape(H, math.degrees(math.atan(slope)), xc, top, int(keep.sum()))


def heap_porosity(case: HeapCase, sim, H: float) -> float:
    """Porosity in the heap's core: |x| < L/8 (at least 0.3 m), 0.1 H < z < 0.5 H."""
    a = max(0.3, case.base_length / 8.0)
    return measure.porosity(sim, (-a, 0.0, 0.1 * H), (a, case.width, 0.5 * H))


def base_stress(sim, hist_f: np.ndarray | None = None) -> np.ndarray:
    """Normal stress [Pa] (compression +) on each base bin, left to right: the panel
    forces (averaged over ``hist_f`` (steps, panels, 3) when given) over the panel areas."""
    ids = base_ids(sim)
    force = sim.panel_force if hist_f is None else hist_f.mean(axis=0)
    fn = -np.einsum("pd,pd->p", force[ids], sim.walls.panels.normal[ids])
    return fn / sim.walls.areas()[ids]


def centre_over_peak(sigma: np.ndarray) -> tuple[float, float, float]:
    """(centre stress, peak stress, their ratio) of a base profile (left to right,
    symmetric bins): the profile is folded about the centre (mean of the bins at +-x,
    the heap being symmetric) to halve the noise; the centre stress is the folded bin
    next to the centre, the peak the largest folded bin. Ratio < 1: a dip (Fig. 1c)."""
    n = len(sigma) // 2
    folded = 0.5 * (sigma[:n][::-1] + sigma[n:])        # index 0 = next to the centre
    centre, peak = float(folded[0]), float(folded.max())
    return centre, peak, centre / peak if peak > 0 else float("nan")


def heap_weight(case: HeapCase, sim) -> float:
    """Weight [N] of the grains above the base (centres over it), a clump's mass shared
    equally by its spheres."""
    sph, clumps = sim.spheres, sim.clumps
    free = sph.clump < 0
    m = np.empty(sim.n_spheres)
    m[free] = 1.0 / sph.inv_m[free]
    c = sph.clump[~free]
    members = (clumps.members[c, 1] - clumps.members[c, 0]).astype(float)
    m[~free] = 1.0 / clumps.inv_m[c] / members
    over = (sph.x[:, 2] > -sph.r) & (np.abs(sph.x[:, 0]) <= 0.5 * case.base_length)
    return float(np.sum(m[over]) * G)


def centre_drop(sim) -> float:
    """Subsidence [m] of the base at the centre: depth of the inner edge of the left half."""
    corners = sim.walls.corners()[sim.walls.panel_ids("base_left")[-1]]
    return float(-corners[:, 2].min())


def heap_speed(case: HeapCase, sim) -> float:
    """Root-mean-square speed [m/s] of the grains on the base (the global unbalanced-force
    ratio would count the odd grain falling off the edge to the catch floor)."""
    keep = on_base(case, sim.spheres.x, sim.spheres.r) & (sim.spheres.x[:, 2] > 0.0)
    v = sim.spheres.v[keep]
    return float(np.sqrt(np.mean(np.sum(v * v, axis=1)))) if len(v) else 0.0
