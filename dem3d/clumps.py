"""Mass, centre of mass and inertia of rigid clumps of (possibly overlapping) spheres.

The overlap is counted once: a clump's solid is the *union* of its spheres.

* Two spheres: exact. If the spheres intersect (|r1 - r2| < d < r1 + r2), the union is the
  disjoint union of sphere 1 cut at the radical plane and sphere 2 cut at the same plane,
  because the cap of one sphere beyond that plane lies inside the other. Each piece is a
  slab of a sphere, whose volume and moments are polynomial integrals of the
  cross-section A(z) = pi (R^2 - z^2).
* Any number of spheres: midpoint quadrature on a regular grid over the bounding box
  (deterministic; the error falls as the grid is refined, ~ h / R relative).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from analytic.errors import InvalidParameter


class MassProperties(NamedTuple):
    """mass [kg], centre (3,) [m], inertia (3, 3) about the centre, world axes [kg m^2]."""

    mass: float
    centre: np.ndarray
    inertia: np.ndarray


def sphere_slab_moments(radius: float, z1: float, z2: float) -> tuple[float, float, float, float]:
    """Moments of the part of a ball of ``radius`` centred at 0 with z in [z1, z2].

    Returns (V, Sz, Szz, Srr) = (int dV, int z dV, int z^2 dV, int (x^2 + y^2) dV), from
    A(z) = pi (R^2 - z^2): V = pi [R^2 z - z^3/3], Sz = pi [R^2 z^2/2 - z^4/4],
    Szz = pi [R^2 z^3/3 - z^5/5], Srr = pi/2 [R^4 z - 2 R^2 z^3/3 + z^5/5].
    """
    r2 = radius * radius
    z1 = max(-radius, min(radius, z1))
    z2 = max(-radius, min(radius, z2))

    def vol(z):
        return math.pi * (r2 * z - z ** 3 / 3.0)

    def first(z):
        return math.pi * (r2 * z * z / 2.0 - z ** 4 / 4.0)

    def second(z):
        return math.pi * (r2 * z ** 3 / 3.0 - z ** 5 / 5.0)

    def radial(z):
        return 0.5 * math.pi * (r2 * r2 * z - 2.0 * r2 * z ** 3 / 3.0 + z ** 5 / 5.0)

    return (vol(z2) - vol(z1), first(z2) - first(z1), second(z2) - second(z1), radial(z2) - radial(z1))


def two_sphere_properties(c1, r1: float, c2, r2: float, density: float) -> MassProperties:
    """Exact mass properties of the union of two balls (module docstring)."""
    c1 = np.asarray(c1, float)
    c2 = np.asarray(c2, float)
    axis = c2 - c1
    d = float(np.linalg.norm(axis))
    if d <= abs(r1 - r2):                     # one ball inside the other (or coincident)
        c, r = (c1, r1) if r1 >= r2 else (c2, r2)
        m = density * 4.0 / 3.0 * math.pi * r ** 3
        return MassProperties(m, c.copy(), np.eye(3) * 0.4 * m * r * r)
    e = axis / d
    if d >= r1 + r2:
        pieces = [(0.0, r1, -r1, r1), (d, r2, -r2, r2)]
    else:
        a = (d * d + r1 * r1 - r2 * r2) / (2.0 * d)      # radical plane, from centre 1
        pieces = [(0.0, r1, -r1, a), (d, r2, a - d, r2)]
    vol = s_z = s_zz = s_rr = 0.0
    for zc, r, z1, z2 in pieces:   # piece of a ball centred at zc on the axis, local z in [z1, z2]
        v, sz, szz, srr = sphere_slab_moments(r, z1, z2)
        vol += v
        s_z += sz + zc * v
        s_zz += szz + 2.0 * zc * sz + zc * zc * v
        s_rr += srr
    zbar = s_z / vol
    s_zz_c = s_zz - zbar * zbar * vol
    axial = density * s_rr                       # about the axis
    transverse = density * (0.5 * s_rr + s_zz_c)  # about any axis normal to it through the centre
    inertia = transverse * np.eye(3) + (axial - transverse) * np.outer(e, e)
    return MassProperties(density * vol, c1 + zbar * e, inertia)


def grid_properties(centres, radii, density: float, cells_per_radius: int = 40) -> MassProperties:
    """Mass properties of the union of balls by midpoint quadrature on a regular grid of
    spacing min(radii) / ``cells_per_radius`` over the bounding box (deterministic)."""
    centres = np.ascontiguousarray(centres, float).reshape(-1, 3)
    radii = np.ascontiguousarray(radii, float).reshape(-1)
    if cells_per_radius < 2:
        raise InvalidParameter("cells_per_radius", cells_per_radius, ">= 2")
    h = float(radii.min()) / cells_per_radius
    lo = (centres - radii[:, None]).min(axis=0)
    hi = (centres + radii[:, None]).max(axis=0)
    counts = np.ceil((hi - lo) / h).astype(np.int64)
    sums = _grid_sums(centres, radii, lo, h, counts)
    vol, sx, sy, sz, sxx, syy, szz, sxy, sxz, syz = sums * h ** 3
    c = np.array([sx, sy, sz]) / vol
    second = np.array([[sxx, sxy, sxz], [sxy, syy, syz], [sxz, syz, szz]]) - vol * np.outer(c, c)
    inertia = density * (np.trace(second) * np.eye(3) - second)
    return MassProperties(density * vol, c, inertia)


@njit(cache=True)
def _grid_sums(centres, radii, lo, h, counts):
    out = np.zeros(10)
    for a in range(counts[0]):
        x = lo[0] + (a + 0.5) * h
        for b in range(counts[1]):
            y = lo[1] + (b + 0.5) * h
            for c in range(counts[2]):
                z = lo[2] + (c + 0.5) * h
                inside = False
                for s in range(radii.shape[0]):
                    dx = x - centres[s, 0]
                    dy = y - centres[s, 1]
                    dz = z - centres[s, 2]
                    if dx * dx + dy * dy + dz * dz <= radii[s] * radii[s]:
                        inside = True
                        break
                if inside:
                    out[0] += 1.0
                    out[1] += x
                    out[2] += y
                    out[3] += z
                    out[4] += x * x
                    out[5] += y * y
                    out[6] += z * z
                    out[7] += x * y
                    out[8] += x * z
                    out[9] += y * z
    return out


def clump_properties(centres, radii, density: float) -> MassProperties:
    """Exact for one or two spheres, grid quadrature for more."""
    centres = np.asarray(centres, float).reshape(-1, 3)
    radii = np.asarray(radii, float).reshape(-1)
    if len(radii) == 1:
        m = density * 4.0 / 3.0 * math.pi * radii[0] ** 3
        return MassProperties(m, centres[0].copy(), np.eye(3) * 0.4 * m * radii[0] ** 2)
    if len(radii) == 2:
        return two_sphere_properties(centres[0], radii[0], centres[1], radii[1], density)
    return grid_properties(centres, radii, density)


def principal_frame(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (3,) and the rotation matrix whose columns are the principal axes
    (a proper rotation, det = +1)."""
    moments, axes = np.linalg.eigh(inertia)
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    return moments, axes


def matrix_to_quaternion(rot: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method)."""
    m = rot
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [(m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    return q / np.linalg.norm(q)
