"""Structure-of-arrays records the kernels read and write.

Every array is C-contiguous; float arrays are float64, index arrays int64, flags uint8.
The NamedTuples are immutable records of *mutable* arrays: the kernels update arrays in
place, the engine never swaps an array out from under a record without building a new one.

Index conventions
-----------------
* Spheres are numbered 0..n-1. The spheres of one clump are stored contiguously; a free
  sphere is its own body.
* ``body_id[i]`` is ``i`` for a free sphere and the index of the clump's first sphere for
  a clump member, so body ids are sphere indices and never collide.
* Velocities are those of the leapfrog half step: after step k (time t_k), ``v`` holds
  v(t_k - dt/2) ... v(t_k + dt/2) as documented per field.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Spheres(NamedTuple):
    """Per-sphere state, n spheres.

    x:      (n, 3) centre positions [m] at time t
    v:      (n, 3) centre velocities [m/s] at t - dt/2 (leapfrog half step)
    w:      (n, 3) angular velocities [rad/s] at t - dt/2 (a clump member carries its clump's)
    r:      (n,)   radii [m]
    inv_m:  (n,)   1 / mass of the body the sphere belongs to [1/kg]; 0 = immovable
    inv_i:  (n,)   1 / moment of inertia of a free sphere [1/(kg m^2)]; 0 = rotation locked
                   (unused for clump members: their clump holds the inertia)
    clump:  (n,)   clump index, -1 for a free sphere
    body_id:(n,)   body index (see module docstring)
    f:      (n, 3) contact force on the sphere from the last force evaluation [N]
    t:      (n, 3) contact torque about the sphere centre from the last evaluation [N m]
    x_ref:  (n, 3) positions when the neighbour list was last built [m]
    mat:    (n,)   int32 material id (row of the material table; unused with one material)
    f_ext:  (n, 3) external force the caller sets between steps [N] (added to the contact
                   force of free spheres and clump members when ``Simulation.f_ext`` is on)
    """

    x: np.ndarray
    v: np.ndarray
    w: np.ndarray
    r: np.ndarray
    inv_m: np.ndarray
    inv_i: np.ndarray
    clump: np.ndarray
    body_id: np.ndarray
    f: np.ndarray
    t: np.ndarray
    x_ref: np.ndarray
    mat: np.ndarray
    f_ext: np.ndarray


class Clumps(NamedTuple):
    """Rigid clumps of overlapping spheres, nc clumps.

    x:      (nc, 3) centre of mass [m] at t
    v:      (nc, 3) centre-of-mass velocity [m/s] at t - dt/2
    am:     (nc, 3) angular momentum about the centre of mass, world frame [kg m^2/s] at t - dt/2
    w:      (nc, 3) angular velocity, world frame [rad/s] at t - dt/2
    q:      (nc, 4) orientation quaternion (w, x, y, z), body (principal) frame -> world
    inv_m:  (nc,)   1 / clump mass [1/kg] (0 = immovable)
    inv_i:  (nc, 3) 1 / principal moments of inertia [1/(kg m^2)] (all 0 = rotation locked)
    members:(nc, 2) members of clump c are spheres members[c, 0] .. members[c, 1]-1
    offset: (n, 3)  member centre in the body frame [m] (rows of free spheres unused)
    """

    x: np.ndarray
    v: np.ndarray
    am: np.ndarray
    w: np.ndarray
    q: np.ndarray
    inv_m: np.ndarray
    inv_i: np.ndarray
    members: np.ndarray
    offset: np.ndarray


class Pairs(NamedTuple):
    """Half Verlet list in CSR form (each pair once, listed under its *first* sphere i,
    the one whose cell comes first in the scan), with per-pair contact history.

    start:  (n+1,)    pairs listed under sphere i are k = start[i] .. start[i+1]-1
    nbr:    (cap,)    j of pair k
    tstart: (n+1,)    transpose: the pairs in which sphere j is the second sphere occupy
                      positions tstart[j] .. tstart[j+1]-1 of the transposed order
    tpair:  (cap,)    pair index k at each transposed position
    tpos:   (cap,)    transposed position of pair k (inverse of tpair)
    ut:     (cap, 3)  tangential spring displacement of i relative to j [m], by pair k
    active: (cap,)    1 if pair k touched at the last force evaluation
    pf:     (cap, 8)  by TRANSPOSED position (so pass 2 reads it sequentially), from the
                      last evaluation: force on j (3) [N], torque on j about its centre (3)
                      [N m], normal force (compression +) [N], unused; all zero for a pair
                      not in contact. With ``Simulation.direct_sums`` by pair k instead, and
                      only the force on j and the normal force (columns 0-2, 6)
    slab_start: (nslab+1,) spheres of slab s (cell layers along z at the build, a
                      pair's second sphere in its first sphere's slab or the next one) at
                      slab_sphere[slab_start[s]:slab_start[s+1]], in cell order
    slab_sphere: (n,)
    """

    start: np.ndarray
    nbr: np.ndarray
    tstart: np.ndarray
    tpair: np.ndarray
    tpos: np.ndarray
    ut: np.ndarray
    active: np.ndarray
    pf: np.ndarray
    slab_start: np.ndarray
    slab_sphere: np.ndarray


class WallPairs(NamedTuple):
    """Sphere-panel candidate contacts in CSR form by sphere, with contact history.

    start:  (n+1,)    candidates of sphere i are k = start[i] .. start[i+1]-1
    panel:  (cap,)    panel index of candidate k
    ut:     (cap, 3)  tangential spring displacement of the sphere relative to the panel [m]
    active: (cap,)    1 if touching at the last force evaluation
    out:    (cap, 6)  force on the sphere (3) [N], contact point (3) [m]
    """

    start: np.ndarray
    panel: np.ndarray
    ut: np.ndarray
    active: np.ndarray
    out: np.ndarray


class Panels(NamedTuple):
    """Planar rectangular wall panels, p panels (see dem3d.walls for builders).

    centre: (p, 3)  panel centre [m]
    e1, e2: (p, 3)  unit in-plane axes
    normal: (p, 3)  unit normal e1 x e2, pointing from the wall INTO the particles
    half:   (p, 2)  half extents along e1, e2 [m]; np.inf = unbounded
    mu:     (p,)    particle-panel friction coefficient
    shared: (p, 4)  1 where an edge (-e1, +e1, -e2, +e2) is shared with a coplanar
                    neighbour panel: no edge contact there, and the half-open rule
                    [-a, a) assigns a sphere to exactly one of the two panels
    vel:    (p, 3)  velocity of the panel centre [m/s]
    omega:  (p, 3)  angular velocity [rad/s]; a point q of the panel moves at
                    vel + omega x (q - centre)
    mat:    (p,)    int32 material id of the panel's wall (used with a material table)
    """

    centre: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    normal: np.ndarray
    half: np.ndarray
    mu: np.ndarray
    shared: np.ndarray
    vel: np.ndarray
    omega: np.ndarray
    mat: np.ndarray


class Bonds(NamedTuple):
    """Parallel bonds (Potyondy & Cundall 2004, PFC "pbond"), nb bonds, with an index by
    sphere. A bond is a short elastic cylinder of radius rb glued between spheres i and j
    at their contact point; it carries a force and a moment, updated incrementally.

    i, j:     (nb,)     the bonded spheres (engine order)
    kn, ks:   (nb,)     normal / shear stiffness per unit area [N/m^3]
    rb:       (nb,)     bond radius [m] (lambda min(r_i, r_j))
    sigma_c:  (nb,)     tensile strength [Pa] (inf: unbreakable)
    tau_c:    (nb,)     shear strength [Pa] (inf: unbreakable)
    state:    (nb,)     uint8: 0 broken, 1 intact, 2 made at this state (no increment yet)
    fn:       (nb,)     normal force, compression + [N]
    fs:       (nb, 3)   shear force on i [N]
    mt:       (nb,)     twisting moment on i about n (n from i to j) [N m]
    mb:       (nb, 3)   bending moment on i [N m]
    out:      (nb, 12)  from the last evaluation: force on i (3) [N], torque on i about its
                        centre (3) [N m], force on j (3), torque on j (3)
    start:    (n+1,)    bonds of sphere s: entries start[s] .. start[s+1]-1 of ``entry``
    entry:    (2 nb,)   2 b + side (side 0: s is bond b's i, 1: its j), increasing b
    """

    i: np.ndarray
    j: np.ndarray
    kn: np.ndarray
    ks: np.ndarray
    rb: np.ndarray
    sigma_c: np.ndarray
    tau_c: np.ndarray
    state: np.ndarray
    fn: np.ndarray
    fs: np.ndarray
    mt: np.ndarray
    mb: np.ndarray
    out: np.ndarray
    start: np.ndarray
    entry: np.ndarray


class Specimen(NamedTuple):
    """Particles to simulate (an input record; see dem3d.prep for generators).

    positions:  (n, 3) sphere centres [m]
    radii:      (n,)   sphere radii [m]
    clump:      (n,)   clump label per sphere, -1 for a free sphere; the spheres of one
                       clump must be contiguous (labels otherwise arbitrary)
    density:    grain density [kg/m^3]
    velocities: (n, 3) initial centre velocities [m/s] or None (at rest); a clump takes
                the mean of its members' velocities
    """

    positions: np.ndarray
    radii: np.ndarray
    clump: np.ndarray
    density: float
    velocities: np.ndarray | None = None


class Periodic(NamedTuple):
    """Periodic boundary along one axis (0, 1, 2 = x, y, z): coordinates in [lo, lo + length)."""

    axis: int
    lo: float
    length: float


class WallMotion(NamedTuple):
    """The walls over a run of steps, as ``kernels.advance`` moves them.

    wall_of_panel:   (p,) wall index of each panel
    moving:          (n_walls,) bool, the walls with a motion
    pivot, axis:     (n_walls, 3) each wall's pivot [m] and rotation axis (unit)
    ref_centre, ref_e1, ref_e2:  (p, 3) panel poses at the last neighbour-list build
    om_mid, v_mid:   (n_steps, n_walls[, 3]) angular [rad/s] and linear [m/s] velocity
                     at each step's mid time
    om_end, v_end:   the same at each step's end
    """

    wall_of_panel: np.ndarray
    moving: np.ndarray
    pivot: np.ndarray
    axis: np.ndarray
    ref_centre: np.ndarray
    ref_e1: np.ndarray
    ref_e2: np.ndarray
    om_mid: np.ndarray
    v_mid: np.ndarray
    om_end: np.ndarray
    v_end: np.ndarray


class PanelLoads(NamedTuple):
    """Where ``kernels.advance`` puts the load on every panel: the last step's force and
    moment (p, 3) [N, N m], and per step (n_steps, p, 3), or 0 rows to keep none."""

    force: np.ndarray
    moment: np.ndarray
    hist_force: np.ndarray
    hist_moment: np.ndarray


class Segments(NamedTuple):
    """Boundary segments whose velocity ``kernels.advance`` sets after every step from
    the contact force on them and a fixed free-field load (``dem3d.freefield``: the
    implicit dashpot balance of its module docstring), so a coupled model runs many
    steps per call. Segment s is wall ``wall[s]`` (a translation whose velocity is
    held over a step), its panels ``panel[panel_start[s]:panel_start[s + 1]]``.

    frame:      (ns, 3, 3) rows: the segment's normal and two tangents (world -> local)
    mass:       (ns,) segment mass M [kg]
    area:       (ns,) segment area A [m^2]
    impedance:  (ns, 3) rho C along (normal, tangent, tangent) [kg/(m^2 s)]
    traction:   (ns, 3) A t_ff, local frame [N] (the free-field stress on the segment)
    dashpot:    (ns, 3) A rho C v_ff, local frame [N] (the free-field velocity's pull)
    velocity:   (ns, 3) world frame, the current half step [m/s]; updated in place
    """

    wall: np.ndarray
    panel_start: np.ndarray
    panel: np.ndarray
    frame: np.ndarray
    mass: np.ndarray
    area: np.ndarray
    impedance: np.ndarray
    traction: np.ndarray
    dashpot: np.ndarray
    velocity: np.ndarray


#: no boundary segments (``kernels.advance`` takes a Segments always: an empty one is a
#: loop of no entries, not a second compiled variant)
NO_SEGMENTS = Segments(wall=np.zeros(0, np.int64), panel_start=np.zeros(1, np.int64), panel=np.zeros(0, np.int64),
                       frame=np.zeros((0, 3, 3)), mass=np.zeros(0), area=np.zeros(0), impedance=np.zeros((0, 3)),
                       traction=np.zeros((0, 3)), dashpot=np.zeros((0, 3)), velocity=np.zeros((0, 3)))
