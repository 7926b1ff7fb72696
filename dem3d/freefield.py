"""Absorbing free-field lateral boundaries (Lysmer & Kuhlemeyer 1969 dashpots tied to a
free-field column; the Itasca FLAC/PFC formulation, docs/reference/
seismic-sheetpile.md section 5.2), adapted to DEM.

Continuum formulation, per unit boundary area at depth z, outward normal n_out:
    t = sigma_ff(z) . n_out - rho C (v_main - v_ff(z)),
    C = rho C_p along the normal, rho C_s along the two tangents,
v_ff, sigma_ff the free-field velocity and stress at that depth (tension positive).

DEM adaptation (this module; an assumption, El Shamy's own scheme is not published):
* The main model's lateral boundary is a stack of rigid wall *segments*, one per slice
  [z_k, z_k+1) (``free_field_walls``), each a wall group of its own that translates (no
  rotation) with a velocity this module sets between steps (``driven``).
* Each segment of mass M and area A moves under the contact force of the main model's
  spheres on it (``Simulation.panel_force``) and the boundary force A t, with the dashpot
  taken implicitly (backward Euler, unconditionally stable for any M / (A rho C)):
      V+ = (M V- / dt + F_contacts + A sigma_ff . n_out + A C v_ff) / (M / dt + A C)
  per component in the segment's (normal, tangent, tangent) frame. V+ is the segment
  velocity over the next step (the leapfrog half step), so the pose is advanced by V+ dt.
* v_ff, sigma_ff per slice come from the caller, typically ``measure.slice_averages`` of
  a free-field column (a narrow DEM box of the same deposit on a base shaken like the
  main one) stepped alongside (``step_coupled``).
Limits: (1) the dashpots absorb normally incident P and S waves exactly only in the
continuum long-wave limit; a granular medium is dispersive near its grain-scale cutoff
and the segment mass M reflects a fraction |r|^2 = (w M)^2 / ((2 A rho C)^2 + (w M)^2)
at angular frequency w (keep M small: a few grain masses); surface and oblique waves are
absorbed only partly (Kontoe et al. 2009). (2) The segments move independently, so their
shared edges may open by the slices' relative displacement (small for wave amplitudes).
(3) The engine has one periodic axis, so a free-field column cannot be periodic in x and
y at once: give it rigid or laminar side walls and use its central slices. (4) The
segments are updated every step, inside the engine (``kernels.segments_velocity``); the
slice averages of the columns cost Python time (~1 ms a refresh), so they may be
refreshed every few steps (``every``).
"""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from analytic.errors import InvalidParameter

from .engine import Simulation
from .measure import slice_averages
from .state import Segments
from .walls import Motion, Panel, Steady, Wall


class _Held(Steady):
    """A velocity schedule whose value the coupling sets between steps (constant over a
    step): V(t) = value."""

    def __init__(self):
        self.value = np.zeros(3)

    def __call__(self, t: float):
        return (float(self.value[0]), float(self.value[1]), float(self.value[2]))


def driven(pivot=(0.0, 0.0, 0.0)) -> Motion:
    """A translation whose velocity is set from outside between steps
    (``motion.velocity.value = (vx, vy, vz)`` [m/s])."""
    return Motion(pivot=tuple(map(float, pivot)), velocity=_Held())


def free_field_walls(name: str, point, normal, z_edges, width: float, *, mu: float = 0.0,
                     unbounded_width: bool = False, up=(0.0, 0.0, 1.0)) -> list[Wall]:
    """One driven wall segment per slice [z_k, z_k+1) of a flat lateral boundary through
    ``point`` with ``normal`` into the model: walls named f"{name}{k}" (k from the
    bottom), each one panel of the given width (unbounded across if the width direction
    is periodic), edges shared with the neighbours."""
    n = np.asarray(normal, float)
    n = n / np.linalg.norm(n)
    e2 = np.asarray(up, float)
    e2 = e2 / np.linalg.norm(e2)
    if abs(float(n @ e2)) > 1e-12:
        raise InvalidParameter("normal.up", float(n @ e2), "0")
    e1 = np.cross(e2, n)
    z = np.asarray(z_edges, float)
    if len(z) < 2 or not np.all(np.diff(z) > 0):
        raise InvalidParameter("z_edges", len(z), ">= 2 increasing edges")
    base = np.asarray(point, float) - float(np.asarray(point, float) @ e2) * e2
    walls = []
    for k in range(len(z) - 1):
        h = 0.5 * (z[k + 1] - z[k])
        c = base + (z[k] + h) * e2
        a = np.inf if unbounded_width else 0.5 * float(width)
        shared = (False, False, k > 0, k < len(z) - 2)
        panel = Panel(tuple(c), tuple(e1), tuple(e2), (a, h), float(mu), shared, nominal_half=(0.5 * float(width), h))
        walls.append(Wall(f"{name}{k}", [panel], driven(tuple(c))))
    return walls


class FreeFieldBoundary:
    """The coupling of one lateral boundary (module docstring).

    sim:           the main model, built with the walls of ``free_field_walls``
    walls:         the names of the boundary's segments, bottom to top (slice k)
    rho:           bulk density of the deposit [kg/m^3]
    cp, cs:        P and S wave speeds [m/s] (rho cp, rho cs the dashpot impedances)
    segment_mass:  M of each segment [kg]
    """

    def __init__(self, sim: Simulation, walls: Sequence[str], *, rho: float, cp: float, cs: float,
                 segment_mass: float):
        if not (rho > 0 and cp > 0 and cs > 0 and segment_mass > 0):
            raise InvalidParameter("free field", (rho, cp, cs, segment_mass), "rho, cp, cs, M > 0")
        self.sim = sim
        self.ids = [sim.walls.names.index(w) for w in walls]
        self.motions = [sim.walls.walls[k].motion for k in self.ids]
        for w, m in zip(walls, self.motions):
            if not isinstance(m.velocity, _Held):
                raise InvalidParameter("walls", w, "segments made by free_field_walls (driven motions)")
        self.panels = [np.nonzero(sim.walls.wall_of_panel == k)[0] for k in self.ids]
        pan = sim.walls.panels
        p0 = [p[0] for p in self.panels]
        self.frame = np.stack([pan.normal[p0], pan.e1[p0], pan.e2[p0]], axis=1)   # (ns, 3, 3) rows n, e1, e2
        self.area = sim.walls.areas()[p0] * np.array([len(p) for p in self.panels])
        self.impedance = rho * np.array([cp, cs, cs])
        self.mass = float(segment_mass)
        self.velocity = np.zeros((len(self.ids), 3))      # world frame, the current half step

    @property
    def n_slices(self) -> int:
        return len(self.ids)

    def free_field_terms(self, v_ff: np.ndarray, sigma_ff: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(A t_ff, A rho C v_ff), each (ns, 3) in the segments' local frames [N]: the
        free-field part of the segment balance (module docstring) from the free-field
        state (v_ff (ns, 3) [m/s], sigma_ff (ns, 3, 3) [Pa], tension positive,
        sigma_ab = <l_a f_b> as ``measure.slice_averages``, so the traction on the plane
        of normal n is t_b = n_a sigma_ab) at each segment's slice."""
        v_ff = np.asarray(v_ff, float).reshape(self.n_slices, 3)
        sigma_ff = np.asarray(sigma_ff, float).reshape(self.n_slices, 3, 3)
        n_out = -self.frame[:, 0]
        t_ff = np.einsum("sa,sab->sb", n_out, sigma_ff)            # t_b = n_a sigma_ab (Love-Weber's l_a f_b)
        area = self.area[:, None]
        return (area * np.einsum("sij,sj->si", self.frame, t_ff),
                area * self.impedance * np.einsum("sij,sj->si", self.frame, v_ff))


def column_free_field(column: Simulation, edges, area: float) -> tuple[np.ndarray, np.ndarray]:
    """(v_ff (ns, 3) [m/s], sigma_ff (ns, 3, 3) [Pa]) of a free-field column in slices
    [edges[k], edges[k+1]) along z with cross-section ``area`` [m^2] (mass-weighted mean
    velocity and Love-Weber stress, ``measure.slice_averages``): what ``step_coupled``'s
    ``free_field`` returns for one boundary."""
    av = slice_averages(column, edges, area)
    return av.velocity, av.stress


def step_coupled(sim: Simulation, boundaries: Sequence[FreeFieldBoundary], n_steps: int, *,
                 free_field: Callable[[], Sequence[tuple[np.ndarray, np.ndarray]]] | None = None,
                 columns: Sequence[Simulation] = (), every: int = 1) -> None:
    """Advance the main model ``n_steps`` steps with its free-field boundaries (the
    engine sets the segments' velocity after every step, ``state.Segments``), stepping
    the free-field ``columns`` alongside. ``free_field()`` returns (v_ff, sigma_ff) per
    boundary (e.g. from ``measure.slice_averages`` of the columns); it is called every
    ``every`` steps (None: at rest, stress free), and between two calls the main model
    and each column run in one engine call each."""
    every = max(1, int(every))
    seg = segments(boundaries)
    rows = np.cumsum([0] + [b.n_slices for b in boundaries])
    for b, lo in zip(boundaries, rows):
        for k, m in enumerate(b.motions):
            m.velocity.value = seg.velocity[lo + k]          # a view: the engine updates it
    s, n_steps = 0, int(n_steps)
    while s < n_steps:
        # the columns do not feel the main model: each runs to the next refresh at once
        block = n_steps - s if free_field is None else min(every - s % every, n_steps - s)
        if free_field is not None and s % every == 0:
            _set_free_field(seg, boundaries, rows, free_field())
        for c in columns:
            c.step(block)
        sim.step(block, segments=seg)
        s += block
    for b, lo in zip(boundaries, rows):
        b.velocity = seg.velocity[lo:lo + b.n_slices].copy()
        for k, m in enumerate(b.motions):
            m.velocity.value = b.velocity[k]


def segments(boundaries: Sequence[FreeFieldBoundary]) -> Segments:
    """The engine's record of the boundaries' segments (``state.Segments``), one after
    the other, each boundary's segments as it holds them now (free-field load zero)."""
    panels = [p for b in boundaries for p in b.panels]
    ns = len(panels)
    return Segments(
        wall=np.array([k for b in boundaries for k in b.ids], np.int64),
        panel_start=np.cumsum([0] + [len(p) for p in panels]).astype(np.int64),
        panel=np.concatenate(panels).astype(np.int64),
        frame=np.ascontiguousarray(np.concatenate([b.frame for b in boundaries]), float),
        mass=np.concatenate([np.full(b.n_slices, float(b.mass)) for b in boundaries]),
        area=np.ascontiguousarray(np.concatenate([b.area for b in boundaries]), float),
        impedance=np.concatenate([np.tile(b.impedance, (b.n_slices, 1)) for b in boundaries]),
        traction=np.zeros((ns, 3)), dashpot=np.zeros((ns, 3)),
        velocity=np.ascontiguousarray(np.concatenate([b.velocity for b in boundaries]), float))


def _set_free_field(seg: Segments, boundaries, rows, states) -> None:
    for b, lo, (v, sig) in zip(boundaries, rows, states):
        traction, dashpot = b.free_field_terms(v, sig)
        seg.traction[lo:lo + b.n_slices] = traction
        seg.dashpot[lo:lo + b.n_slices] = dashpot
