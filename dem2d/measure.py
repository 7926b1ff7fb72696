"""Measurements on a 2D assembly: energies, stability, panel stresses, readings, fabric.

All functions are pure (numpy in, numpy out). Forces are per metre of wall [N/m],
stresses [Pa]. Sign convention of ``analytic/profile.py``: normal stress on a wall is
compression positive; shear on a wall is positive when the grains drag the wall *down*
its face.
"""

from __future__ import annotations

import numpy as np

from analytic.constants import G


def kinetic_energy(velocity: np.ndarray, mass: np.ndarray, spin: np.ndarray | None = None,
                   moment: np.ndarray | None = None) -> float:
    """Total kinetic energy [J/m]: sum 1/2 m |v|^2 (+ 1/2 I w^2 if spins are given)."""
    e = 0.5 * float(np.sum(mass * np.einsum("nd,nd->n", velocity, velocity)))
    if spin is not None and moment is not None:
        e += 0.5 * float(np.sum(moment * spin * spin))
    return e


def weight_normalised_unbalance(v_before: np.ndarray, v_after: np.ndarray, dt: float,
                           mass: np.ndarray, g: float = G) -> float:
    """Unbalanced force over weight, sum |m dv/dt| / sum m g [-]. Not PFC's
    "unbalanced force ratio" (mean unbalanced over mean contact force, which is
    ``dem3d.measure.unbalanced_force_ratio``): that name means only that one here.

    dv/dt over one step is the net acceleration (gravity plus contact impulses / dt),
    so this is PFC's / Yade's "unbalanced force" normalised by the one body force every
    grain carries (with gravity the mean contact force scales with the weight).
    A static assembly gives ~0; free fall gives 1.
    """
    a = np.linalg.norm(v_after - v_before, axis=1) / dt
    return float(np.sum(mass * a) / (np.sum(mass) * g))


def panel_stresses(force: np.ndarray, normal: np.ndarray, corners: np.ndarray,
                   length: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(sigma_n, tau) on each panel [Pa] from the force BY the grains ON the panel.

    sigma_n = -(F . n) / L (compression positive: grains at +n push along -n);
    tau = (F . t_down) / L, t_down = the panel tangent pointing downward (positive when
    the grains drag the wall down its face, the active-case direction).
    """
    sig = -np.einsum("pd,pd->p", force, normal) / length
    t = corners[:, 1] - corners[:, 0]
    t = t / np.linalg.norm(t, axis=1)[:, None]
    t = np.where((t[:, 1] > 0)[:, None], -t, t)  # make it point down (or along -x if level)
    tau = np.einsum("pd,pd->p", force, t) / length
    return sig, tau


def readings(values: np.ndarray, group: int = 4, top: float | None = None,
             panel_bottoms: np.ndarray | None = None, panel_height: float | None = None):
    """Average panel values in groups of ``group`` panels from the bottom (Khosravi et
    al.'s pressure cells: 4 segments of 10 mm per reading point).

    values: (p,) per panel, panel 0 at the bottom. Only groups lying wholly below
    ``top`` [m] (the backfill surface) are returned when ``panel_bottoms`` (p,) [m]
    and ``panel_height`` [m] are given. Returns (first panel index of each group,
    group mean) arrays.
    """
    values = np.asarray(values, float)
    starts = np.arange(0, len(values) - group + 1, group)
    if top is not None and panel_bottoms is not None and panel_height is not None:
        starts = starts[panel_bottoms[starts + group - 1] + panel_height <= top + 1e-12]
    means = np.array([values[s:s + group].mean() for s in starts])
    return starts, means


def solid_fraction(positions: np.ndarray, radii: np.ndarray, x0: float, x1: float,
                   y0: float, y1: float) -> float:
    """Area fraction of solids in a rectangle, counting the disks whose centres are
    inside (good to about d/size of the window) [-]."""
    inside = ((positions[:, 0] >= x0) & (positions[:, 0] < x1)
              & (positions[:, 1] >= y0) & (positions[:, 1] < y1))
    return float(np.sum(np.pi * radii[inside] ** 2) / ((x1 - x0) * (y1 - y0)))


def coordination_number(contact_a: np.ndarray, contact_b: np.ndarray, n_bodies: int,
                        exclude_rattlers: bool = True) -> float:
    """Mean number of grain-grain contacts per grain (rattlers, grains with fewer than
    2 contacts, left out when asked) [-]."""
    z = np.bincount(np.concatenate([contact_a, contact_b]), minlength=n_bodies)
    if exclude_rattlers:
        z = z[z >= 2]
    return float(z.mean()) if len(z) else 0.0


def stress_in_bands(position: np.ndarray, contact_a: np.ndarray, contact_b: np.ndarray,
                    impulse_on_a: np.ndarray, dt: float, x0: float, x1: float,
                    y_edges: np.ndarray) -> np.ndarray:
    """Average stress tensor [Pa] in horizontal bands from grain-grain contacts
    (Love-Weber): sigma_ij = (1/A) sum_c f_i l_j, with f the force on b (by a) and
    l = x_b - x_a the branch vector. A repulsive contact has f along l, so this is
    compression positive.

    A contact counts in the band holding the midpoint of its branch vector; bands span
    x0..x1 and y_edges[k]..y_edges[k+1]. Returns (k,2,2).
    """
    f = -impulse_on_a / dt           # force on b
    l = position[contact_b] - position[contact_a]
    mid = 0.5 * (position[contact_a] + position[contact_b])
    out = np.zeros((len(y_edges) - 1, 2, 2))
    inx = (mid[:, 0] >= x0) & (mid[:, 0] < x1)
    band = np.searchsorted(y_edges, mid[:, 1], side="right") - 1
    ok = inx & (band >= 0) & (band < len(y_edges) - 1)
    fl = np.einsum("mi,mj->mij", f[ok], l[ok])
    np.add.at(out, band[ok], fl)
    area = (x1 - x0) * np.diff(y_edges)
    return out / area[:, None, None]
