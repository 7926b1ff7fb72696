"""What moved when a wall failed: the rigid motion fitted to the blocks above each bed
joint, and the mechanism it reads as (sliding along a bed joint or toppling about a
course's toe)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


from .geometry import bed_axes, bed_joint_level


@dataclass(frozen=True)
class Mechanism:
    """How the wall moved between two states (``classify_mechanism``).

    mode:         "sliding" (the part above a bed joint translates) or "toppling"
                  (it rotates outward about a point of the outer face)
    course:       the lowest course of the moving part (its bed joint, or the course
                  whose outer toe is the pivot)
    level_m:      height of that bed joint at the outer face, above the toe [m]
    rotation_deg: rotation of the top courses, outward positive [deg]
    crest_displacement_m: outward displacement of the top courses [m]
    pivot:        instantaneous centre of the top courses' motion (x, y) [m] (None when
                  they translate)
    """

    mode: str
    course: int
    level_m: float
    rotation_deg: float
    crest_displacement_m: float
    pivot: tuple | None


@dataclass(frozen=True)
class RigidFit:
    """One planar rigid motion fitted to many blocks' displacements (``rigid_motion_fit``).

    rotation_deg: rotation, counter-clockwise positive (outward toppling in the wall's
                  frame, x inward from the outer toe) [deg]
    pivot:        the point the motion leaves in place (x, y) [m]; None without rotation
    rms_residual_m, max_residual_m: how far the blocks' displacements depart from the
                  one motion (root mean square, largest) [m]
    worst:        index of the block that departs most
    """

    rotation_deg: float
    pivot: tuple | None
    rms_residual_m: float
    max_residual_m: float
    worst: int


def rigid_motion_fit(x0: np.ndarray, x1: np.ndarray) -> RigidFit:
    """Least-squares rigid motion x1 ~ c + T + R(w)(x0 - c) of points (n, 2) [m], with
    c their centroid: linearised in w (small rotations), d = T + w k x (x0 - c), whose
    fixed point is the pivot. A whole part of the wall rotating as one body leaves
    residuals far below its movement; a single block's slip stands out as ``worst``.
    Unlike ``classify_mechanism``'s top-two-course mean, which a lone slipping crest
    block can pull anywhere, every block given weighs the same."""
    x0, d = np.asarray(x0, float), np.asarray(x1, float) - np.asarray(x0, float)
    r = x0 - x0.mean(axis=0)
    a = np.zeros((2 * len(x0), 3))
    a[0::2, 0], a[1::2, 1] = 1.0, 1.0
    a[0::2, 2], a[1::2, 2] = -r[:, 1], r[:, 0]
    (tx, ty, w), *_ = np.linalg.lstsq(a, d.reshape(-1), rcond=None)
    res = np.hypot(*(d.reshape(-1) - a @ np.array([tx, ty, w])).reshape(-1, 2).T)
    c = x0.mean(axis=0)
    pivot = (float(c[0] - ty / w), float(c[1] + tx / w)) if abs(w) > 1e-12 else None
    return RigidFit(math.degrees(w), pivot, float(np.sqrt((res ** 2).mean())), float(res.max()), int(res.argmax()))


def classify_mechanism(section, block_height: float, course: np.ndarray, dynamic: np.ndarray,
                       x0: np.ndarray, a0: np.ndarray, x1: np.ndarray, a1: np.ndarray) -> Mechanism:
    """Sliding or toppling, from block kinematics between states 0 and 1.

    The top two courses are fitted with one rigid motion (mean translation T of their
    centroid c, mean rotation w); its centre (pivot) is the point that motion leaves in
    place. The
    wall topples when that centre lies near the outer face within the wall's height and
    the rotation accounts for at least half the crest movement (w x lever >= |T| / 2);
    the pivot's bed joint is the level. Otherwise it slides, on the lowest bed joint
    above which every course has most of its blocks moving with the crest (|d - T| <
    |T| / 2).
    """
    d = x1 - x0
    w_all = a1 - a0
    top = course[dynamic].max()
    crest = dynamic & (course >= top - 1)
    T = d[crest].mean(axis=0)
    w = float(w_all[crest].mean())
    c = x0[crest].mean(axis=0)
    moved = float(np.hypot(*T))
    e_u, e_v = bed_axes(section.joint_slope_deg)
    t1 = math.tan(math.radians(section.batter_outer_deg))
    pivot = None
    if abs(w) > 1e-12:
        # the fixed point of the finite rigid motion x -> c + T + R(w) (x - c)
        R = np.array([[math.cos(w), -math.sin(w)], [math.sin(w), math.cos(w)]])
        pivot = np.linalg.solve(np.eye(2) - R, c + T - R @ c)
        lever = float(np.hypot(*(c - pivot)))
        x_face = pivot[1] * t1
        near_face = abs(pivot[0] - x_face) < 0.35 * section.base_width_m
        inside = -block_height <= pivot[1] <= section.height_m - block_height
        if near_face and inside and abs(w) * lever >= 0.5 * moved and w > 0:
            k = int(max(round(float(pivot @ e_v) / block_height), 0))
            k = max(k, int(course[dynamic].min()))
            return Mechanism("toppling", k, bed_joint_level(section, k, block_height), math.degrees(w), -T[0],
                             tuple(pivot))
    with_crest = np.hypot(*(d - T).T) < 0.5 * max(moved, 1e-12)
    k_slide = top
    for k in range(int(top), int(course[dynamic].min()) - 1, -1):
        sel = dynamic & (course == k)
        if sel.any() and with_crest[sel].mean() >= 0.5:
            k_slide = k
        else:
            break
    return Mechanism("sliding", k_slide, bed_joint_level(section, k_slide, block_height), math.degrees(w), -T[0],
                     None if pivot is None else tuple(pivot))
