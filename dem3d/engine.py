"""``Simulation``: the engine object that owns the arrays and advances them.

Pure computation: no files, no printing, no logging. A workflow builds a Simulation from a
``Specimen``, a ``ContactParams``, walls and a time step, then calls ``step`` (or iterates
``dem3d.run.run``) and reads ``panel_force`` / ``panel_moment`` or ``Frame`` snapshots.
``to_arrays`` / ``Simulation.from_arrays`` give a checkpoint of plain numpy arrays from
which a run resumes bitwise identically.

The Simulation holds the state and steps it (``kernels.advance``); its parts live beside
it: ``bodies`` (spheres and clumps from a specimen), ``neighbours`` (the cell and Verlet
lists and their rebuilds), ``bonds`` (parallel bonds), ``checkpoint`` (the state as
arrays and back).
"""

from __future__ import annotations

import math
from typing import Sequence

import numba
import numpy as np

from analytic.constants import G
from analytic.errors import InvalidParameter

from . import bodies, bonds, checkpoint, kernels, neighbours
from .errors import BlowUp
from .params import N_PARAM_FIELDS, ContactParams, check_time_step, critical_time_step, material_table, pair_params
from .state import NO_SEGMENTS, Bonds, Pairs, PanelLoads, Periodic, Segments, Specimen, WallMotion, WallPairs
from .walls import Wall, WallSet


STATE_VERSION = 1


class Simulation:
    """A soft-sphere / clump DEM system with wall panels.

    Parameters
    ----------
    specimen:       the particles (positions, radii, clump labels, density)
    params:         the contact law (``dem3d.params.linear`` or ``hertz_mindlin``)
    dt:             time step [s]; refused above ``DT_SAFETY`` x the critical step unless
                    ``allow_unsafe_dt``
    walls:          ``Wall`` groups of panels with their motions
    gravity:        (3,) [m/s^2]
    periodic:       ``Periodic`` or None
    skin:           Verlet skin [m] (default 0.4 r_min)
    sort_by_cell:   reorder bodies by cell once at construction for memory locality;
                    ``original_index[k]`` is then the specimen index of sphere k
    spheres_per_thread: ``step`` uses at most one numba thread per this many spheres
                    (small systems run faster on one thread); results do not depend on
                    the thread count
    sort_every:     re-sort bodies by cell (``sort_by_cell``) at every this many
                    neighbour-list builds, 0 = never; Frames stay in specimen order
    materials:      None (``params`` for every contact, the single-material path) or a
                    sequence of ContactParams, one per material (a contact between two
                    grains of it); pairs mix by ``dem3d.params.mix`` unless given in
                    ``material_pairs`` {(a, b): ContactParams}. ``params`` must share their
                    law, damping mode and Coulomb cap and gives the local damping.
    sphere_material: (n,) material id per sphere, specimen order (default 0)
    wall_material:  {wall name: material id} (default 0); with materials, a panel contact
                    uses the pair's parameters, its friction included (the panel's own mu
                    is then not used)
    direct_sums:    add each pair's force on its second sphere to that sphere during the
                    contact pass, in an order fixed by slabs of cell layers (kernels
                    ``pair_forces``, ``direct``), instead of through per-pair rows that
                    the second pass gathers: the same forces to rounding, other bits; a
                    whole step 1.04 times faster on the seismic model and no faster on the
                    plain benchmark, measured in separate runs (docs/validation/
                    seismic_step_speed_direct_sums.json, dem3d_bench_quiet.json); still
                    independent of the thread count. Off by default.
    """

    def __init__(self, specimen: Specimen, params: ContactParams, *, dt: float,
                 walls: Sequence[Wall] = (), gravity=(0.0, 0.0, -G),
                 periodic: Periodic | None = None, skin: float | None = None,
                 allow_unsafe_dt: bool = False, sort_by_cell: bool = True,
                 spheres_per_thread: int = 4000, sort_every: int = 50, materials=None,
                 sphere_material=None, wall_material=None, material_pairs=None, direct_sums: bool = False):
        kernels.prefer_openmp()
        pos = np.ascontiguousarray(specimen.positions, float).reshape(-1, 3)
        n = pos.shape[0]
        radii = np.ascontiguousarray(specimen.radii, float).reshape(-1)
        labels = np.asarray(specimen.clump if specimen.clump is not None else -np.ones(n), np.int64).reshape(-1)
        if radii.shape[0] != n or labels.shape[0] != n:
            raise InvalidParameter("specimen", f"{n} positions, {radii.shape[0]} radii, {labels.shape[0]} labels",
                                   "equal lengths")
        if n == 0:
            raise InvalidParameter("specimen", 0, ">= 1 sphere")
        if not np.all(radii > 0) or not np.all(np.isfinite(pos)):
            raise InvalidParameter("radii", float(radii.min()), "> 0 m with finite positions")
        density = float(specimen.density)
        if not density > 0:
            raise InvalidParameter("density", density, "> 0 kg/m^3")
        vel = (np.zeros((n, 3)) if specimen.velocities is None
               else np.ascontiguousarray(specimen.velocities, float).reshape(n, 3))
        self.params = params
        self.density = density
        self.spheres_per_thread = int(spheres_per_thread)
        self.sort_every = int(sort_every)
        self.direct_sums = bool(direct_sums)
        self.gravity = np.asarray(gravity, float).reshape(3)
        self.periodic = periodic
        r_min = float(radii.min())
        self.skin = 0.4 * r_min if skin is None else float(skin)
        if not self.skin > 0:
            raise InvalidParameter("skin", self.skin, "> 0 m")
        self.mtab = None
        if materials is not None:
            self.mtab = material_table(materials, material_pairs)
            for name in ("law", "damping", "coulomb"):
                if getattr(params, name) != getattr(materials[0], name):
                    raise InvalidParameter(f"params.{name}", getattr(params, name),
                                           f"the materials' {getattr(materials[0], name)}")
        self.dt_critical = self._critical_step(params, r_min, density)
        self.dt = check_time_step(dt, self.dt_critical, allow_unsafe=allow_unsafe_dt)
        self.bonds: Bonds | None = None
        self.dt_critical_bonds = math.inf
        self.use_f_ext = False
        self.attached: tuple[np.ndarray, np.ndarray] | None = None
        ranges = bodies.body_ranges(labels)
        if periodic is not None:
            bodies.check_periodic(periodic, float(radii.max()), self.skin)
        starts = np.array([a for a, _ in ranges], np.int64)
        ends = np.array([b for _, b in ranges], np.int64)
        order = np.arange(len(ranges))
        if sort_by_cell:
            order = self._locality_order(pos, radii, starts, ends)
        new_to_old, _ = bodies.gather_ranges(starts, ends, order)
        self.original_index = new_to_old
        pos, radii, labels, vel = pos[new_to_old], radii[new_to_old], labels[new_to_old], vel[new_to_old]
        self.spheres, self.clumps = bodies.build_bodies(pos, radii, labels, vel, density)
        self.walls = WallSet(walls)
        if sphere_material is not None or wall_material is not None:
            if self.mtab is None:
                raise InvalidParameter("materials", None, "a sequence of ContactParams when material ids are given")
            nm = self.mtab.shape[0]
            if sphere_material is not None:
                ids = np.asarray(sphere_material, np.int64).reshape(-1)
                if ids.shape[0] != n or ids.min() < 0 or ids.max() >= nm:
                    raise InvalidParameter("sphere_material", f"{ids.shape[0]} ids", f"{n} ids in [0, {nm})")
                self.spheres.mat[:] = ids[new_to_old]
            for name, mid in (wall_material or {}).items():
                if name not in self.walls.names or not 0 <= int(mid) < nm:
                    raise InvalidParameter("wall_material", (name, mid), f"a wall name and an id in [0, {nm})")
                self.walls.panels.mat[self.walls.panel_ids(name)] = int(mid)
        if periodic is not None:
            bodies.check_panels_periodic(self.walls, periodic.axis)
        self.walls.set_velocities(0.0)
        p = self.walls.n_panels
        self.panel_force = np.zeros((p, 3))
        self.panel_moment = np.zeros((p, 3))
        self.time = 0.0
        self.step_count = 0
        self.n_rebuilds = 0
        self._pair_bufs = [neighbours.empty_pairs(n, 0), neighbours.empty_pairs(n, 0)]
        self._fit_history()
        self._wall_bufs = [neighbours.empty_wall_pairs(n, 0), neighbours.empty_wall_pairs(n, 0)]
        self._cur = 0
        self._wcur = 0
        self._rows = np.empty((n, 16), np.int64)
        self._rebuild(first=True)
        self._need_rebuild = False

    def _critical_step(self, params: ContactParams, r_min: float, density: float) -> float:
        """Reference critical step of the contact law(s): ``critical_time_step`` of
        ``params``, or the smallest over the material table's pairs."""
        m_min = density * 4.0 / 3.0 * math.pi * r_min ** 3
        if self.mtab is None:
            return critical_time_step(params, m_min, r_min, density)
        nm = self.mtab.shape[0]
        return min(critical_time_step(pair_params(self.mtab, a, b), m_min, r_min, density)
                   for a in range(nm) for b in range(nm))

    # ---------------------------------------------------------------- properties
    @property
    def n_spheres(self) -> int:
        return self.spheres.x.shape[0]

    @property
    def pairs(self) -> Pairs:
        return self._pair_bufs[self._cur]

    @property
    def wall_pairs(self) -> WallPairs:
        return self._wall_bufs[self._wcur]

    @property
    def panels(self):
        return self.walls.panels

    @property
    def r_min(self) -> float:
        return float(self.spheres.r.min())

    def sphere_masses(self) -> np.ndarray:
        """(n,) mass of each sphere's own ball (rho 4/3 pi r^3) [kg], overlap not removed."""
        return self.density * 4.0 / 3.0 * math.pi * self.spheres.r ** 3

    def body_masses(self) -> np.ndarray:
        """(n_bodies,) masses [kg] of free spheres and clumps (clumps after the free spheres)."""
        free = self.spheres.clump < 0
        m_free = 1.0 / self.spheres.inv_m[free]
        return np.concatenate([m_free, 1.0 / self.clumps.inv_m])

    # ---------------------------------------------------------------- control
    def set_params(self, params: ContactParams, *, allow_unsafe_dt: bool = False) -> None:
        """Swap the contact law between stages (e.g. local damping on for settling). The
        time step is re-checked against the new stiffness (one-line InvalidParameter)."""
        crit = self._critical_step(params, self.r_min, self.density)
        check_time_step(self.dt, crit, allow_unsafe=allow_unsafe_dt)
        self.params = params
        self.dt_critical = crit
        self._fit_history()

    @property
    def rolling(self) -> bool:
        """Whether some particle contact has rolling resistance (ContactParams.mu_roll)."""
        if self.mtab is not None:
            return bool(np.any(self.mtab[..., N_PARAM_FIELDS - 1] > 0.0))
        return self.params.mu_roll > 0.0

    def _fit_history(self) -> None:
        neighbours.fit_history(self)

    def set_density(self, spheres, density: float) -> None:
        """Give free spheres (specimen indices) their own density [kg/m^3] (``bodies.set_density``)."""
        bodies.set_density(self, spheres, density)

    def lock(self, spheres=None, *, translation: bool = False, rotation: bool = True) -> None:
        """Lock the translation and/or rotation of free spheres (indices, default all) and of
        their clumps (``bodies.lock``)."""
        bodies.lock(self, spheres, translation=translation, rotation=rotation)

    # ---------------------------------------------------------------- external forces
    @property
    def f_ext(self) -> np.ndarray:
        """(n, 3) external force per sphere [N] in ENGINE order (``original_index[k]`` is
        the specimen index of row k), added to each sphere's contact force while
        ``use_f_ext`` is on; write into it between steps (``set_external_force`` takes
        specimen order). Kept in step with the spheres when the engine re-sorts them."""
        return self.spheres.f_ext

    def set_external_force(self, force, *, specimen_order: bool = True) -> None:
        """Set the external force on every sphere [N] ((n, 3), or (3,) for all alike) and
        switch external forces on. A free sphere then moves with a = (F_contact + F_ext) / m
        + g; a clump member's F_ext acts on its clump at the member's centre."""
        f = np.asarray(force, float)
        n = self.n_spheres
        f = np.broadcast_to(f, (n, 3)) if f.shape == (3,) else f.reshape(n, 3)
        if not np.all(np.isfinite(f)):
            raise InvalidParameter("force", "non-finite", "finite values [N]")
        self.spheres.f_ext[:] = f[self.original_index] if specimen_order else f
        self.use_f_ext = True

    def clear_external_force(self) -> None:
        """Zero the external forces and switch them off (the single-material fast path)."""
        self.spheres.f_ext[:] = 0.0
        self.use_f_ext = False

    # ---------------------------------------------------------------- parallel bonds
    def make_bonds(self, gap: float, *, kn: float, ks: float, radius_multiplier: float = 1.0,
                   sigma_c: float = math.inf, tau_c: float = math.inf, spheres=None,
                   allow_unsafe_dt: bool = False) -> int:
        """Parallel bonds between spheres closer than ``gap`` [m] (``bonds.make_bonds``: the
        law, the strengths, the time-step check); returns the number made."""
        return bonds.make_bonds(self, gap, kn=kn, ks=ks, radius_multiplier=radius_multiplier, sigma_c=sigma_c,
                                tau_c=tau_c, spheres=spheres, allow_unsafe_dt=allow_unsafe_dt)

    def attach_to_wall(self, spheres, wall: str) -> None:
        """Carry free spheres (specimen indices) rigidly with a wall's translation
        (``bodies.attach_to_wall``)."""
        bodies.attach_to_wall(self, spheres, wall)

    def bond_pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """(i, j) specimen indices of every bond (broken ones included; see bonds.state)."""
        if self.bonds is None:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        return self.original_index[self.bonds.i], self.original_index[self.bonds.j]

    def step(self, n_steps: int = 1, *, record_panels: bool = False, segments: Segments | None = None):
        """Advance ``n_steps`` time steps.

        ``segments``: boundary segments whose velocity the engine sets after every step
        (``state.Segments``, made by ``dem3d.freefield``); their walls' motions must read
        their velocity from ``segments.velocity`` (the engine updates it in place).

        With ``record_panels`` returns (force, moment), each (n_steps, p, 3): the load on
        every panel at every step (force BY the particles ON the panel [N]; moment about
        the panel centre [N m]); otherwise None (``panel_force``/``panel_moment`` always
        hold the last step's loads). Raises ``BlowUp`` (one line) on a non-finite state or
        a sphere faster than half the smallest radius per step.
        """
        kernels.prefer_openmp()
        threads = numba.get_num_threads()
        numba.set_num_threads(max(1, min(threads, self.n_spheres // max(1, self.spheres_per_thread))))
        try:
            return self._step(int(n_steps), record_panels, segments)
        finally:
            numba.set_num_threads(threads)

    def _step(self, n_steps: int, record_panels: bool, segments: Segments | None = None):
        p = self.walls.n_panels
        rows = n_steps if record_panels else 0
        hist_f = np.zeros((rows, p, 3))
        hist_m = np.zeros((rows, p, 3))
        gx, gy, gz = (float(c) for c in self.gravity)
        pax, plen = self._periodic_args()
        speed_limit2 = (0.5 * self.r_min / self.dt) ** 2
        moving = self.walls.moving
        chunk = n_steps if not moving.any() else min(n_steps, 2000)
        done = 0
        self._need_rebuild |= self._lacks_slabs()
        while done < n_steps:
            if self._need_rebuild:
                if self.sort_every > 0 and (self.n_rebuilds + 1) % self.sort_every == 0:
                    self.sort_by_cell()      # locality decays as bodies move (includes the rebuild)
                else:
                    self._rebuild()
            todo = min(chunk, n_steps - done)
            om_mid, v_mid, om_end, v_end = self.walls.schedule(self.time, self.dt, todo if moving.any() else 0)
            if not moving.any():
                om_mid = om_end = np.zeros((1, len(moving)))
                v_mid = v_end = np.zeros((1, len(moving), 3))
            ref = self.walls._ref
            motion = WallMotion(self.walls.wall_of_panel, moving, self.walls.pivot, self.walls.axis, ref[0], ref[1],
                                ref[2], om_mid, v_mid, om_end, v_end)
            loads = PanelLoads(self.panel_force, self.panel_moment, hist_f[done:] if rows else hist_f,
                               hist_m[done:] if rows else hist_m)
            ran, time, status, count = kernels.advance(
                self.spheres, self.clumps, self.pairs, self.wall_pairs, self.walls.panels, self.params,
                self.dt, gx, gy, gz, pax, plen, self.skin, speed_limit2, motion, loads, todo, self.time,
                self.mtab, self.use_f_ext, bonds.kernel_bonds(self.bonds, self.n_spheres),
                self.attached if self.attached is not None else _NO_ATTACHED, self.rolling,
                NO_SEGMENTS if segments is None else segments, True if self.direct_sums else None)
            done += ran
            self.time = time
            self.step_count += ran
            self._need_rebuild = status == kernels.STATUS_REBUILD
            if status == kernels.STATUS_NONFINITE:
                raise BlowUp(self.step_count, self.time, f"{count} spheres have a non-finite position or velocity")
            if status == kernels.STATUS_TOO_FAST:
                vmax = float(np.sqrt((self.spheres.v ** 2).sum(axis=1)).max())
                raise BlowUp(self.step_count, self.time,
                             f"a sphere moves at {vmax:.4g} m/s, more than half the smallest radius "
                             f"per step ({0.5 * self.r_min / self.dt:.4g} m/s)")
        return (hist_f, hist_m) if record_panels else None

    def evaluate_forces(self) -> tuple[np.ndarray, np.ndarray]:
        """Contact force and torque on every sphere at the current state, without moving
        anything: (f (n, 3) [N], t (n, 3) [N m]). Tangential histories do advance by one
        increment, exactly as the force evaluation of a step would."""
        kernels.prefer_openmp()
        if self._need_rebuild or self._lacks_slabs():
            self._rebuild()
        pax, plen = self._periodic_args()
        if self.bonds is not None:
            kernels.bond_forces(self.spheres, self.bonds, self.dt, pax, plen)
        direct = True if self.direct_sums else None
        kernels.pair_forces(self.spheres, self.pairs, self.params, self.dt, pax, plen, self.mtab,
                            True if self.rolling else None, direct)
        kernels.gather_and_move(self.spheres, self.pairs, self.wall_pairs, self.walls.panels, self.params,
                                self.dt, 0.0, 0.0, 0.0, 0.0, 0.0, False, self.mtab, self.use_f_ext,
                                bonds.kernel_bonds(self.bonds, self.n_spheres), direct)
        if self.walls.n_panels:
            kernels.panel_loads(self.wall_pairs, self.walls.panels, self.panel_force, self.panel_moment)
        return self.spheres.f.copy(), self.spheres.t.copy()

    def contact_energy(self) -> float:
        """Elastic normal energy stored in every contact at the current positions [J]."""
        pax, plen = self._periodic_args()
        if self._need_rebuild:
            self._rebuild()
        return float(kernels.contact_energy(self.spheres, self.pairs, self.wall_pairs, self.walls.panels,
                                            self.params, pax, plen, self.mtab))

    # ---------------------------------------------------------------- neighbour lists
    def _periodic_args(self) -> tuple[int, float]:
        return neighbours.periodic_args(self)


    def _locality_order(self, pos, radii, starts, ends) -> np.ndarray:
        return neighbours.locality_order(self, pos, radii, starts, ends)


    def sort_by_cell(self) -> np.ndarray:
        """Reorder the bodies by cell so that neighbours sit close in memory (see
        ``neighbours.sort_by_cell``); returns ``new_to_old``."""
        return neighbours.sort_by_cell(self)

    def _rebuild(self, first: bool = False, new_to_old: np.ndarray | None = None) -> None:
        neighbours.rebuild(self, first, new_to_old)

    @property
    def direct_sums(self) -> bool:
        """The constructor's ``direct_sums``; switched on a running simulation, the rows of
        ``pairs.pf`` are moved to the other layout, so measurements read the right rows and
        pass 2 never adds a row of a pair not in contact (all-zero in both layouts)."""
        return self._direct_sums

    @direct_sums.setter
    def direct_sums(self, on: bool) -> None:
        on = bool(on)
        if getattr(self, "_direct_sums", on) != on:
            prs = self.pairs
            total = int(prs.start[-1])
            tpos = prs.tpos[:total]
            rows = prs.pf[:total].copy()
            if on:
                prs.pf[:total] = rows[tpos]          # by transposed position -> by pair
            else:
                prs.pf[tpos] = rows                  # by pair -> by transposed position
        self._direct_sums = on

    def pair_rows(self) -> np.ndarray:
        """For each listed pair k (0 .. pairs.start[-1] - 1) the row of ``pairs.pf`` that
        holds its force on the second sphere and its normal force: its transposed position,
        or k itself with ``direct_sums`` (state.Pairs)."""
        total = int(self.pairs.start[-1])
        return np.arange(total, dtype=np.int64) if self.direct_sums else self.pairs.tpos[:total]

    def _lacks_slabs(self) -> bool:
        """direct_sums on lists restored from a checkpoint saved before the slabs existed."""
        return self.direct_sums and self.n_spheres > 0 and self.pairs.slab_start.shape[0] == 1

    # ---------------------------------------------------------------- checkpoint
    def to_arrays(self) -> dict[str, np.ndarray]:
        """The full state as a dict of numpy arrays (copies): spheres, clumps, neighbour
        lists with contact history, panels and wall pivots, time, step, parameters.
        Save it with ``np.savez``; ``from_arrays`` resumes bitwise identically. Wall motions
        are functions and are not stored: pass the same ``walls`` again."""
        return checkpoint.to_arrays(self)

    @classmethod
    def from_arrays(cls, arrays, walls: Sequence[Wall] = ()) -> "Simulation":
        """Rebuild a Simulation from ``to_arrays`` output (or a loaded .npz). ``walls`` must
        be the same wall groups (same panel count and order) to re-attach their motions;
        the stored panel poses replace the geometry given in ``walls``; their friction must
        match the stored one (to change a wall's friction, edit ``arrays["panels.mu"]``)."""
        return checkpoint.from_arrays(cls, arrays, walls)


# --------------------------------------------------------------------------------------
# construction helpers
# --------------------------------------------------------------------------------------


_NO_ATTACHED = (np.zeros(0, np.int64), np.zeros(0, np.int64))


