"""``Simulation``: the engine object that owns the arrays and advances them.

Pure computation: no files, no printing, no logging. A workflow builds a Simulation from a
``Specimen``, a ``ContactParams``, walls and a time step, then calls ``step`` (or iterates
``dem3d.run.run``) and reads ``panel_force`` / ``panel_moment`` or ``Frame`` snapshots.
``to_arrays`` / ``Simulation.from_arrays`` give a checkpoint of plain numpy arrays from
which a run resumes bitwise identically.

Neighbour search: cell list with cell size 2 r_max + skin and a half stencil; a half
Verlet list (pairs within r_i + r_j + skin) scanned into fixed-capacity rows whose overflow
is checked outside the kernel (grow and scan again), then compacted to CSR; wall
candidates within r + skin. The lists are rebuilt when any sphere has moved more than
skin/2, or any panel point more than skin/2, since the last build: then no pair can have
closed a gap of skin unseen.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Sequence

import numba
import numpy as np

from analytic.constants import G
from analytic.errors import InvalidParameter

from . import kernels
from .clumps import clump_properties, matrix_to_quaternion, principal_frame
from .errors import BlowUp
from .params import N_PARAM_FIELDS, ContactParams, check_time_step, critical_time_step, material_table, pair_params
from .state import Bonds, Clumps, Pairs, Spheres, Specimen, WallPairs
from .walls import Wall, WallSet


class Periodic(NamedTuple):
    """Periodic boundary along one axis (0, 1, 2 = x, y, z): coordinates in [lo, lo + length)."""

    axis: int
    lo: float
    length: float


_STATE_VERSION = 1


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
    """

    def __init__(self, specimen: Specimen, params: ContactParams, *, dt: float,
                 walls: Sequence[Wall] = (), gravity=(0.0, 0.0, -G),
                 periodic: Periodic | None = None, skin: float | None = None,
                 allow_unsafe_dt: bool = False, sort_by_cell: bool = True,
                 spheres_per_thread: int = 4000, sort_every: int = 50, materials=None,
                 sphere_material=None, wall_material=None, material_pairs=None):
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
        bodies = _body_ranges(labels)
        if periodic is not None:
            _check_periodic(periodic, float(radii.max()), self.skin)
        starts = np.array([a for a, _ in bodies], np.int64)
        ends = np.array([b for _, b in bodies], np.int64)
        order = np.arange(len(bodies))
        if sort_by_cell:
            order = self._locality_order(pos, radii, starts, ends)
        new_to_old, _ = _gather_ranges(starts, ends, order)
        self.original_index = new_to_old
        pos, radii, labels, vel = pos[new_to_old], radii[new_to_old], labels[new_to_old], vel[new_to_old]
        self.spheres, self.clumps = _build_bodies(pos, radii, labels, vel, density)
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
            _check_panels_periodic(self.walls, periodic.axis)
        self.walls.set_velocities(0.0)
        p = self.walls.n_panels
        self.panel_force = np.zeros((p, 3))
        self.panel_moment = np.zeros((p, 3))
        self.time = 0.0
        self.step_count = 0
        self.n_rebuilds = 0
        self._pair_bufs = [_empty_pairs(n, 0), _empty_pairs(n, 0)]
        self._fit_history()
        self._wall_bufs = [_empty_wall_pairs(n, 0), _empty_wall_pairs(n, 0)]
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
        """Pair history 6 wide (tangential displacement, rolling moment) with rolling
        resistance, else 3 wide: the plain contact pass keeps its memory traffic."""
        width = 6 if self.rolling else 3
        for b, prs in enumerate(self._pair_bufs):
            if prs.ut.shape[1] != width:
                ut = np.zeros((prs.ut.shape[0], width))
                keep = min(width, prs.ut.shape[1])
                ut[:, :keep] = prs.ut[:, :keep]
                self._pair_bufs[b] = prs._replace(ut=ut)

    def set_density(self, spheres, density: float) -> None:
        """Give free spheres (specimen indices) their own density [kg/m^3]: mass
        rho 4/3 pi r^3 and moment of inertia 2/5 m r^2 (e.g. the balls of a bonded
        structure heavier than the grains). Locked translations or rotations stay locked.
        The time-step checks still use the specimen's density: a denser ball is safer,
        a lighter one needs the caller's own margin."""
        density = float(density)
        if not (density > 0 and math.isfinite(density)):
            raise InvalidParameter("density", density, "> 0 kg/m^3")
        engine = np.empty(self.n_spheres, np.int64)
        engine[self.original_index] = np.arange(self.n_spheres)
        rows = engine[np.asarray(spheres, np.int64).reshape(-1)]
        sph = self.spheres
        if np.any(sph.clump[rows] >= 0):
            raise InvalidParameter("spheres", "clump members", "free spheres")
        m = density * 4.0 / 3.0 * math.pi * sph.r[rows] ** 3
        sph.inv_m[rows] = np.where(sph.inv_m[rows] > 0, 1.0 / m, 0.0)
        sph.inv_i[rows] = np.where(sph.inv_i[rows] > 0, 1.0 / (0.4 * m * sph.r[rows] ** 2), 0.0)

    def lock(self, spheres=None, *, translation: bool = False, rotation: bool = True) -> None:
        """Lock the translation and/or rotation of free spheres (indices, default all)
        and of the clumps they belong to."""
        sph = self.spheres
        idx = np.arange(self.n_spheres) if spheres is None else np.asarray(spheres, np.int64)
        for i in idx:
            c = sph.clump[i]
            if c < 0:
                if translation:
                    sph.inv_m[i] = 0.0
                    sph.v[i] = 0.0
                if rotation:
                    sph.inv_i[i] = 0.0
                    sph.w[i] = 0.0
            else:
                members = slice(self.clumps.members[c, 0], self.clumps.members[c, 1])
                if translation:
                    self.clumps.inv_m[c] = 0.0
                    self.clumps.v[c] = 0.0
                    sph.inv_m[members] = 0.0
                if rotation:
                    self.clumps.inv_i[c] = 0.0
                    self.clumps.am[c] = 0.0
                    self.clumps.w[c] = 0.0
                    sph.w[members] = 0.0

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
        if not 0.0 <= gap <= self.skin:
            raise InvalidParameter("gap", gap, f"[0, skin = {self.skin:.4g}] m")
        for name, val in (("kn", kn), ("ks", ks), ("radius_multiplier", radius_multiplier)):
            if not (val > 0 and math.isfinite(val)):
                raise InvalidParameter(name, val, "> 0")
        if not (sigma_c > 0 and tau_c > 0):
            raise InvalidParameter("strength", (sigma_c, tau_c), "> 0 Pa (inf: unbreakable)")
        self._rebuild()
        self._need_rebuild = False
        n = self.n_spheres
        chosen = np.ones(n, bool)
        if spheres is not None:
            chosen[:] = False
            engine = np.empty(n, np.int64)
            engine[self.original_index] = np.arange(n)
            chosen[engine[np.asarray(spheres, np.int64)]] = True
        prs = self.pairs
        total = int(prs.start[-1])
        i = np.repeat(np.arange(n, dtype=np.int64), np.diff(prs.start))
        j = prs.nbr[:total].copy()
        d = self.spheres.x[j] - self.spheres.x[i]
        if self.periodic is not None:
            ax, length = self.periodic.axis, self.periodic.length
            d[:, ax] -= length * np.round(d[:, ax] / length)
        r = self.spheres.r
        keep = chosen[i] & chosen[j] & (np.sqrt((d * d).sum(axis=1)) < r[i] + r[j] + gap)
        i, j = i[keep], j[keep]
        nb = len(i)
        rb = float(radius_multiplier) * np.minimum(r[i], r[j])
        new = Bonds(i=i, j=j, kn=np.full(nb, float(kn)), ks=np.full(nb, float(ks)), rb=rb,
                    sigma_c=np.full(nb, float(sigma_c)), tau_c=np.full(nb, float(tau_c)),
                    state=np.full(nb, 2, np.uint8), fn=np.zeros(nb), fs=np.zeros((nb, 3)), mt=np.zeros(nb),
                    mb=np.zeros((nb, 3)), out=np.zeros((nb, 12)), start=np.zeros(n + 1, np.int64),
                    entry=np.zeros(2 * nb, np.int64))
        if self.bonds is not None:
            new = Bonds(*[np.concatenate([a, b]) if f not in ("start", "entry") else b
                          for f, a, b in zip(Bonds._fields, self.bonds, new)])
        crit = _bond_critical_step(new, r, self.density)
        check_time_step(self.dt, crit, allow_unsafe=allow_unsafe_dt)
        self.dt_critical_bonds = crit
        self.bonds = _index_bonds(new, n)
        self._need_rebuild = True          # bonded pairs leave the contact list
        return nb

    def attach_to_wall(self, spheres, wall: str) -> None:
        """Carry free spheres (specimen indices) rigidly with a wall's translation (e.g. a
        layer of grains glued to a shaken base to make it rough): they are locked
        (translation and rotation) and move by the wall's pivot displacement each step
        with its half-step velocity (``kernels.move_attached``); wall rotation is not
        applied to them."""
        if wall not in self.walls.names:
            raise InvalidParameter("wall", wall, ", ".join(self.walls.names))
        idx = np.asarray(spheres, np.int64).reshape(-1)
        engine = np.empty(self.n_spheres, np.int64)
        engine[self.original_index] = np.arange(self.n_spheres)
        rows = engine[idx]
        if np.any(self.spheres.clump[rows] >= 0):
            raise InvalidParameter("spheres", "clump members", "free spheres")
        self.lock(rows, translation=True, rotation=True)
        k = self.walls.names.index(wall)
        old_s, old_w = self.attached if self.attached is not None else (np.zeros(0, np.int64),) * 2
        self.attached = (np.concatenate([old_s, rows]).astype(np.int64),
                         np.concatenate([old_w, np.full(len(rows), k, np.int64)]))

    def bond_pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """(i, j) specimen indices of every bond (broken ones included; see bonds.state)."""
        if self.bonds is None:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        return self.original_index[self.bonds.i], self.original_index[self.bonds.j]

    def step(self, n_steps: int = 1, *, record_panels: bool = False):
        """Advance ``n_steps`` time steps.

        With ``record_panels`` returns (force, moment), each (n_steps, p, 3): the load on
        every panel at every step (force BY the particles ON the panel [N]; moment about
        the panel centre [N m]); otherwise None (``panel_force``/``panel_moment`` always
        hold the last step's loads). Raises ``BlowUp`` (one line) on a non-finite state or
        a sphere faster than half the smallest radius per step.
        """
        threads = numba.get_num_threads()
        numba.set_num_threads(max(1, min(threads, self.n_spheres // max(1, self.spheres_per_thread))))
        try:
            return self._step(int(n_steps), record_panels)
        finally:
            numba.set_num_threads(threads)

    def _step(self, n_steps: int, record_panels: bool):
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
            ran, time, status, count = kernels.advance(
                self.spheres, self.clumps, self.pairs, self.wall_pairs, self.walls.panels, self.params,
                self.dt, gx, gy, gz, pax, plen, self.skin, speed_limit2,
                self.walls.wall_of_panel, moving, self.walls.pivot, self.walls.axis, ref[0], ref[1], ref[2],
                om_mid, v_mid, om_end, v_end, self.panel_force, self.panel_moment,
                hist_f[done:] if rows else hist_f, hist_m[done:] if rows else hist_m, todo, self.time,
                self.mtab, self.use_f_ext, self.bonds,
                self.attached if self.attached is not None else _NO_ATTACHED, self.rolling)
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
        if self._need_rebuild:
            self._rebuild()
        pax, plen = self._periodic_args()
        if self.bonds is not None:
            kernels.bond_forces(self.spheres, self.bonds, self.dt, pax, plen)
        kernels.pair_forces(self.spheres, self.pairs, self.params, self.dt, pax, plen, self.mtab)
        if self.rolling:
            kernels.rolling_torques(self.spheres, self.pairs, self.params, self.dt, pax, plen, self.mtab)
        kernels.gather_and_move(self.spheres, self.pairs, self.wall_pairs, self.walls.panels, self.params,
                                self.dt, 0.0, 0.0, 0.0, 0.0, 0.0, False, self.mtab, self.use_f_ext, self.bonds)
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
        if self.periodic is None:
            return -1, 1.0
        return int(self.periodic.axis), float(self.periodic.length)

    def _grid(self, x: np.ndarray, r_max: float):
        """Cell grid covering x: (lo (3,), inv_h (3,), nc (3,)) with cells >= 2 r_max + skin."""
        h = 2.0 * r_max + self.skin
        lo = x.min(axis=0)
        extent = x.max(axis=0) - lo
        nc = np.maximum(1, np.floor(extent / h)).astype(np.int64)
        while int(np.prod(nc)) > 8 * x.shape[0] + 64:      # sparse outliers: coarser grid
            nc = np.maximum(1, nc // 2)
        if self.periodic is not None:
            ax = self.periodic.axis
            lo[ax] = self.periodic.lo
            extent[ax] = self.periodic.length
            nc[ax] = int(math.floor(self.periodic.length / h))
        with np.errstate(divide="ignore"):
            inv_h = np.where(extent > 0, nc / np.where(extent > 0, extent, 1.0), 0.0)
        return lo, inv_h, nc

    def _locality_order(self, pos, radii, starts, ends) -> np.ndarray:
        # body centre = mean of its spheres (the sum of a body's rows in sphere order, as
        # ndarray.mean takes it, so the order does not depend on how it is computed)
        centres = np.add.reduceat(pos, starts, axis=0) / (ends - starts)[:, None]
        lo, inv_h, nc = self._grid(centres, float(radii.max()))
        return kernels.body_cell_order(centres, lo, inv_h, nc)

    def _wrap(self) -> None:
        """Map positions into the periodic cell (whole clumps move together)."""
        pax = self.periodic.axis
        lo = self.periodic.lo
        length = self.periodic.length
        sph = self.spheres
        clu = self.clumps
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

    def sort_by_cell(self) -> np.ndarray:
        """Reorder the bodies by cell (as at construction) so that neighbours sit close in
        memory; worth it after large rearrangements such as raining. Sphere indices change:
        returns ``new_to_old`` (sphere k now was sphere new_to_old[k]), and
        ``original_index`` keeps mapping to the specimen order. Contact histories are
        carried over; the result differs from an unsorted run only by the order of
        floating-point sums."""
        sph = self.spheres
        n = self.n_spheres
        # a body starts at every free sphere and at the first member of every clump
        first = np.ones(n, bool)
        first[1:] = (sph.clump[1:] < 0) | (sph.clump[1:] != sph.clump[:-1])
        starts = np.flatnonzero(first).astype(np.int64)
        ends = np.append(starts[1:], n).astype(np.int64)
        order = self._locality_order(sph.x, sph.r, starts, ends)
        new_to_old, new_start = _gather_ranges(starts, ends, order)
        if np.array_equal(new_to_old, np.arange(n)):
            self._rebuild()
            return new_to_old
        head_clump = sph.clump[starts[order]]
        is_clump = head_clump >= 0
        clump_order = head_clump[is_clump].astype(np.int64)
        new_clump = -np.ones(len(self.clumps.x), np.int64)
        new_clump[clump_order] = np.arange(len(clump_order))
        fields = {f: np.ascontiguousarray(getattr(sph, f)[new_to_old]) for f in Spheres._fields}
        member = fields["clump"] >= 0
        fields["clump"][member] = new_clump[fields["clump"][member]]
        length = (ends - starts)[order]
        members = np.stack([new_start[is_clump], new_start[is_clump] + length[is_clump]], axis=1).astype(np.int64)
        fields["body_id"] = np.repeat(new_start, length).astype(np.int64)   # free sphere: itself
        self.spheres = Spheres(**fields)
        clu = self.clumps
        self.clumps = Clumps(**{f: np.ascontiguousarray(getattr(clu, f)[clump_order]) for f in Clumps._fields
                                if f not in ("members", "offset")},
                             members=members, offset=np.ascontiguousarray(clu.offset[new_to_old]))
        self.original_index = self.original_index[new_to_old]
        if self.bonds is not None:
            old_to_new = np.empty(n, np.int64)
            old_to_new[new_to_old] = np.arange(n)
            bnd = self.bonds._replace(i=old_to_new[self.bonds.i], j=old_to_new[self.bonds.j])
            self.bonds = _index_bonds(bnd, n)
        if self.attached is not None:
            old_to_new = np.empty(n, np.int64)
            old_to_new[new_to_old] = np.arange(n)
            self.attached = (old_to_new[self.attached[0]], self.attached[1])
        self._rebuild(new_to_old=new_to_old)
        return new_to_old

    def _rebuild(self, first: bool = False, new_to_old: np.ndarray | None = None) -> None:
        sph = self.spheres
        n = self.n_spheres
        if self.periodic is not None:
            self._wrap()
        pax, plen = self._periodic_args()
        plo = self.periodic.lo if self.periodic is not None else 0.0
        lo, inv_h, nc = self._grid(sph.x, float(sph.r.max()))
        cell, cell_start, order = kernels.cell_sort(sph.x, lo, inv_h, nc, pax, plo, plen)
        old = self.pairs
        new = self._pair_bufs[1 - self._cur]
        counts = np.empty(n, np.int64)
        xr = np.empty((n, 4))
        xr[:, :3] = sph.x[order]
        xr[:, 3] = sph.r[order]
        clump_sorted = sph.clump[order]
        while True:      # fixed-capacity rows; on overflow (checked here) grow and scan again
            kernels.scan_pairs(sph.x, sph.r, sph.clump, cell, cell_start, order, xr, clump_sorted, nc, pax,
                               plen, self.skin, kernels._FORWARD, self._rows, counts, self.bonds)
            widest = int(counts.max()) if n else 0
            if widest <= self._rows.shape[1]:
                break
            self._rows = np.empty((n, widest + 8), np.int64)
        total = int(counts.sum())
        if new.nbr.shape[0] < total:          # grow the spare CSR buffer
            new = _empty_pairs(n, int(1.25 * total) + 64, old.ut.shape[1])
        kernels.compact_rows(self._rows, counts, new.start, new.nbr)
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
        self._pair_bufs[1 - self._cur] = new
        self._cur = 1 - self._cur

        pan = self.walls.panels
        wold = self.wall_pairs
        wnew = self._wall_bufs[1 - self._wcur]
        wstart = np.zeros(n + 1, np.int64)
        if pan.centre.shape[0]:
            kernels.scan_wall_pairs(sph.x, sph.r, pan, self.skin, wstart, wnew.panel, False)
        np.cumsum(wstart, out=wstart)
        wtotal = int(wstart[-1])
        if wnew.panel.shape[0] < wtotal:
            wnew = _empty_wall_pairs(n, int(1.25 * wtotal) + 64)
        wnew.start[:] = wstart
        if wtotal:
            kernels.scan_wall_pairs(sph.x, sph.r, pan, self.skin, wnew.start, wnew.panel, True)
            kernels.carry_wall_history(wnew.start, wnew.panel, wnew.ut, wnew.active, wnew.out, wold.start,
                                       wold.panel, wold.ut, wold.active, wold.out, identity)
        self._wall_bufs[1 - self._wcur] = wnew
        self._wcur = 1 - self._wcur
        sph.x_ref[:] = sph.x
        self.walls.mark_reference()
        if not first:
            self.n_rebuilds += 1

    # ---------------------------------------------------------------- checkpoint
    def to_arrays(self) -> dict[str, np.ndarray]:
        """The full state as a dict of numpy arrays (copies): spheres, clumps, neighbour
        lists with contact history, panels and wall pivots, time, step, parameters.
        Save it with ``np.savez``; ``from_arrays`` resumes bitwise identically. Wall motions
        are functions and are not stored: pass the same ``walls`` again."""
        out: dict[str, np.ndarray] = {"version": np.array(_STATE_VERSION)}
        used = {"pairs": int(self.pairs.start[-1]), "wall_pairs": int(self.wall_pairs.start[-1])}
        for prefix, rec in (("spheres", self.spheres), ("clumps", self.clumps), ("pairs", self.pairs),
                            ("wall_pairs", self.wall_pairs), ("panels", self.walls.panels)):
            for name, arr in rec._asdict().items():
                if prefix in used and name not in ("start", "tstart"):
                    arr = arr[:used[prefix]]          # drop the spare capacity
                out[f"{prefix}.{name}"] = np.array(arr, copy=True)
        for name, value in self.params._asdict().items():
            out[f"params.{name}"] = np.array(value)
        if self.mtab is not None:
            out["materials"] = self.mtab.copy()
        if self.bonds is not None:
            for name, arr in self.bonds._asdict().items():
                out[f"bonds.{name}"] = np.array(arr, copy=True)
            out["dt_critical_bonds"] = np.array(self.dt_critical_bonds)
        out["use_f_ext"] = np.array(self.use_f_ext)
        if self.attached is not None:
            out["attached.spheres"], out["attached.walls"] = (a.copy() for a in self.attached)
        out["walls.pivot"] = self.walls.pivot.copy()
        out["walls.ref_centre"], out["walls.ref_e1"], out["walls.ref_e2"] = (a.copy() for a in self.walls._ref)
        out["panel_force"] = self.panel_force.copy()
        out["panel_moment"] = self.panel_moment.copy()
        out["original_index"] = self.original_index.copy()
        scalars = {"time": self.time, "step": self.step_count, "dt": self.dt, "skin": self.skin,
                   "density": self.density, "dt_critical": self.dt_critical, "n_rebuilds": self.n_rebuilds,
                   "need_rebuild": self._need_rebuild, "spheres_per_thread": self.spheres_per_thread,
                   "sort_every": self.sort_every}
        for name, value in scalars.items():
            out[name] = np.array(value)
        out["gravity"] = self.gravity.copy()
        out["periodic"] = (np.array([-1.0, 0.0, 1.0]) if self.periodic is None
                           else np.array([self.periodic.axis, self.periodic.lo, self.periodic.length], float))
        return out

    @classmethod
    def from_arrays(cls, arrays, walls: Sequence[Wall] = ()) -> "Simulation":
        """Rebuild a Simulation from ``to_arrays`` output (or a loaded .npz). ``walls`` must
        be the same wall groups (same panel count and order) to re-attach their motions;
        the stored panel poses replace the geometry given in ``walls``; their friction must
        match the stored one (to change a wall's friction, edit ``arrays["panels.mu"]``)."""
        # copies: the caller's arrays (e.g. a cached specimen shared by several runs) must
        # not be advanced by this simulation
        a = {k: np.array(arrays[k], copy=True) for k in arrays}
        if int(a["version"]) != _STATE_VERSION:
            raise InvalidParameter("version", int(a["version"]), f"{_STATE_VERSION}")
        self = cls.__new__(cls)
        a.setdefault("params.mu_roll", np.array(0.0))                    # states saved before rolling resistance
        self.params = ContactParams(**{f: a[f"params.{f}"].item() for f in ContactParams._fields})
        n_sph = a["spheres.x"].shape[0]
        a.setdefault("spheres.mat", np.zeros(n_sph, np.int32))          # states saved before materials
        a.setdefault("spheres.f_ext", np.zeros((n_sph, 3)))
        a.setdefault("panels.mat", np.zeros(a["panels.centre"].shape[0], np.int32))
        self.spheres = Spheres(**{f: np.ascontiguousarray(a[f"spheres.{f}"]) for f in Spheres._fields})
        self.mtab = a["materials"].copy() if "materials" in a else None
        if self.mtab is not None and self.mtab.shape[-1] < N_PARAM_FIELDS:   # saved before rolling resistance
            self.mtab = np.concatenate([self.mtab, np.zeros(self.mtab.shape[:2] + (1,))], axis=-1)
        self.bonds = (Bonds(**{f: np.ascontiguousarray(a[f"bonds.{f}"]) for f in Bonds._fields})
                      if "bonds.i" in a else None)
        self.dt_critical_bonds = float(a["dt_critical_bonds"]) if "dt_critical_bonds" in a else math.inf
        self.use_f_ext = bool(a["use_f_ext"]) if "use_f_ext" in a else False
        self.attached = ((a["attached.spheres"].astype(np.int64), a["attached.walls"].astype(np.int64))
                         if "attached.spheres" in a else None)
        self.clumps = Clumps(**{f: np.ascontiguousarray(a[f"clumps.{f}"]) for f in Clumps._fields})
        n = self.spheres.x.shape[0]
        self._pair_bufs = [Pairs(**{f: np.ascontiguousarray(a[f"pairs.{f}"]) for f in Pairs._fields}),
                           _empty_pairs(n, 0)]
        self._fit_history()
        self._wall_bufs = [WallPairs(**{f: np.ascontiguousarray(a[f"wall_pairs.{f}"]) for f in WallPairs._fields}),
                           _empty_wall_pairs(n, 0)]
        self._cur = 0
        self._wcur = 0
        self._rows = np.empty((n, 16), np.int64)
        self.walls = WallSet(walls)
        if self.walls.n_panels != a["panels.centre"].shape[0]:
            raise InvalidParameter("walls", f"{self.walls.n_panels} panels",
                                   f"the {a['panels.centre'].shape[0]} panels of the checkpoint")
        if not np.array_equal(self.walls.panels.mu, a["panels.mu"]):
            # the stored friction would silently win over the one the caller asked for
            raise InvalidParameter("walls", f"panel friction {self.walls.panels.mu.tolist()}",
                                   f"the checkpoint's {a['panels.mu'].tolist()} (edit arrays['panels.mu'] to change it)")
        for f in self.walls.panels._fields:
            getattr(self.walls.panels, f)[...] = a[f"panels.{f}"]
        self.walls.pivot[...] = a["walls.pivot"]
        self.walls._ref = (a["walls.ref_centre"].copy(), a["walls.ref_e1"].copy(), a["walls.ref_e2"].copy())
        self.panel_force = a["panel_force"].copy()
        self.panel_moment = a["panel_moment"].copy()
        self.original_index = a["original_index"].copy()
        self.time = float(a["time"])
        self.step_count = int(a["step"])
        self.dt = float(a["dt"])
        self.skin = float(a["skin"])
        self.density = float(a["density"])
        self.dt_critical = float(a["dt_critical"])
        self.n_rebuilds = int(a["n_rebuilds"])
        self._need_rebuild = bool(a["need_rebuild"])
        self.spheres_per_thread = int(a["spheres_per_thread"])
        self.sort_every = int(a["sort_every"])
        self.gravity = a["gravity"].astype(float).copy()
        per = a["periodic"]
        self.periodic = None if per[0] < 0 else Periodic(int(per[0]), float(per[1]), float(per[2]))
        return self


# --------------------------------------------------------------------------------------
# construction helpers
# --------------------------------------------------------------------------------------

def _gather_ranges(starts: np.ndarray, ends: np.ndarray, order: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Concatenate the index ranges [starts[b], ends[b]) for b in ``order``: (new_to_old,
    where each body starts in the new order)."""
    length = (ends - starts)[order]
    new_start = np.zeros(len(order), np.int64)
    np.cumsum(length[:-1], out=new_start[1:])
    within = np.arange(int(length.sum()), dtype=np.int64) - np.repeat(new_start, length)
    return (np.repeat(starts[order], length) + within).astype(np.int64), new_start


def _body_ranges(labels: np.ndarray) -> list[tuple[int, int]]:
    """[start, end) sphere ranges of bodies: each free sphere alone, each clump's run."""
    n = labels.shape[0]
    ranges = []
    i = 0
    seen = set()
    while i < n:
        lab = labels[i]
        if lab < 0:
            ranges.append((i, i + 1))
            i += 1
            continue
        if lab in seen:
            raise InvalidParameter("clump", int(lab), "contiguous spheres per clump label")
        seen.add(lab)
        j = i
        while j < n and labels[j] == lab:
            j += 1
        ranges.append((i, j))
        i = j
    return ranges


def _check_periodic(periodic: Periodic, r_max: float, skin: float) -> None:
    if periodic.axis not in (0, 1, 2):
        raise InvalidParameter("periodic.axis", periodic.axis, "0, 1 or 2")
    need = 3.0 * (2.0 * r_max + skin)
    if not periodic.length >= need:
        raise InvalidParameter("periodic.length", periodic.length, f">= {need:.4g} m",
                               "three cells of 2 r_max + skin")


def _check_panels_periodic(walls: WallSet, axis: int) -> None:
    """A panel may not end inside the periodic direction: coordinates along it are only
    defined modulo the period, so any in-plane extent with a component along the axis
    must be unbounded."""
    pan = walls.panels
    for p in range(walls.n_panels):
        for e, half in ((pan.e1[p], pan.half[p, 0]), (pan.e2[p], pan.half[p, 1])):
            if abs(e[axis]) > 1e-12 and np.isfinite(half):
                raise InvalidParameter(f"panel {p} half extent", float(half),
                                       "np.inf along the periodic axis (use unbounded_width / periodic_axis)")


def _build_bodies(pos, radii, labels, vel, density) -> tuple[Spheres, Clumps]:
    n = pos.shape[0]
    bodies = _body_ranges(labels)
    sph_mass = density * 4.0 / 3.0 * math.pi * radii ** 3
    inv_m = 1.0 / sph_mass
    inv_i = 1.0 / (0.4 * sph_mass * radii ** 2)
    clump_of = -np.ones(n, np.int64)
    body_id = np.arange(n, dtype=np.int64)
    x = pos.copy()
    v = vel.copy()
    offsets = np.zeros((n, 3))
    cl_x, cl_v, cl_q, cl_im, cl_ii = [], [], [], [], []
    clump_ranges = [(a, b) for a, b in bodies if labels[a] >= 0]
    for c, (a, b) in enumerate(clump_ranges):
        props = clump_properties(pos[a:b], radii[a:b], density)
        moments, axes = principal_frame(props.inertia)
        q = matrix_to_quaternion(axes)
        b_off = (pos[a:b] - props.centre) @ axes          # body-frame offsets
        offsets[a:b] = b_off
        # place members exactly where the kernel will (x = X + R b)
        for m in range(a, b):
            x[m] = props.centre + kernels.quat_rotate(q[0], q[1], q[2], q[3], *b_off[m - a])
        vc = vel[a:b].mean(axis=0)
        v[a:b] = vc
        cl_x.append(props.centre)
        cl_v.append(vc)
        cl_q.append(q)
        cl_im.append(1.0 / props.mass)
        cl_ii.append(1.0 / moments)
        clump_of[a:b] = c
        body_id[a:b] = a
        inv_m[a:b] = 1.0 / props.mass
        inv_i[a:b] = 0.0
    nc = len(clump_ranges)
    spheres = Spheres(x=np.ascontiguousarray(x), v=np.ascontiguousarray(v), w=np.zeros((n, 3)),
                      r=radii.copy(), inv_m=inv_m, inv_i=inv_i, clump=clump_of, body_id=body_id,
                      f=np.zeros((n, 3)), t=np.zeros((n, 3)), x_ref=x.copy(), mat=np.zeros(n, np.int32),
                      f_ext=np.zeros((n, 3)))
    clumps = Clumps(x=np.array(cl_x, float).reshape(nc, 3), v=np.array(cl_v, float).reshape(nc, 3),
                    am=np.zeros((nc, 3)), w=np.zeros((nc, 3)), q=np.array(cl_q, float).reshape(nc, 4),
                    inv_m=np.array(cl_im, float).reshape(nc), inv_i=np.array(cl_ii, float).reshape(nc, 3),
                    members=np.array(clump_ranges, np.int64).reshape(nc, 2), offset=offsets)
    return spheres, clumps


def _empty_pairs(n: int, cap: int, width: int = 3) -> Pairs:
    return Pairs(start=np.zeros(n + 1, np.int64), nbr=np.zeros(cap, np.int64),
                 tstart=np.zeros(n + 1, np.int64), tpair=np.zeros(cap, np.int64),
                 tpos=np.zeros(cap, np.int64), ut=np.zeros((cap, width)), active=np.zeros(cap, np.uint8),
                 pf=np.zeros((cap, 8)))


def _empty_wall_pairs(n: int, cap: int) -> WallPairs:
    return WallPairs(start=np.zeros(n + 1, np.int64), panel=np.zeros(cap, np.int64),
                     ut=np.zeros((cap, 3)), active=np.zeros(cap, np.uint8), out=np.zeros((cap, 6)))


_NO_ATTACHED = (np.zeros(0, np.int64), np.zeros(0, np.int64))


def _index_bonds(bnd: Bonds, n: int) -> Bonds:
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


def _bond_critical_step(bnd: Bonds, r: np.ndarray, density: float) -> float:
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
