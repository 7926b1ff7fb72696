"""The section of a dry-stone wall cut into courses and blocks (pure geometry, no
physics): bed joints dipping inward at alpha, head joints perpendicular to them, the
section polygon and the level of each bed joint."""

from __future__ import annotations

import math

import numpy as np


def _clip(poly: np.ndarray, normal: np.ndarray, offset: float) -> np.ndarray:
    """The part of convex ``poly`` (k,2) where normal . p <= offset (Sutherland-Hodgman)."""
    out = []
    k = len(poly)
    for i in range(k):
        p, q = poly[i], poly[(i + 1) % k]
        fp, fq = normal @ p - offset, normal @ q - offset
        if fp <= 0:
            out.append(p)
        if fp * fq < 0:
            out.append(p + (q - p) * (fp / (fp - fq)))
    return np.array(out) if len(out) >= 3 else np.zeros((0, 2))


def area_centroid(poly: np.ndarray) -> tuple[float, np.ndarray]:
    x, y = poly[:, 0], poly[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cross = x * y1 - x1 * y
    a = cross.sum() / 2
    c = np.array([((x + x1) * cross).sum(), ((y + y1) * cross).sum()]) / (6 * a)
    return a, c


def section_polygon(section) -> np.ndarray:
    """The wall section (4,2), counter-clockwise: outer toe, heel, inner crest, outer crest.
    The base is the bed plane through the toe dipping inward at alpha (reference 5.3)."""
    h, b = section.height_m, section.base_width_m
    t1 = math.tan(math.radians(section.batter_outer_deg))
    t2 = math.tan(math.radians(section.batter_inner_deg))
    ta = math.tan(math.radians(section.joint_slope_deg))
    x_heel = b / (1 - ta * t2)
    return np.array([[0.0, 0.0], [x_heel, -x_heel * ta], [b - h * t2, h], [h * t1, h]])


def bed_axes(alpha_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors along the bed joints (inward, dipping by alpha) and normal to them."""
    a = math.radians(alpha_deg)
    return np.array([math.cos(a), -math.sin(a)]), np.array([math.sin(a), math.cos(a)])


def bed_joint_level(section, course: int, block_height: float) -> float:
    """Height above the toe [m] where the bed joint under ``course`` meets the outer face."""
    e_u, e_v = bed_axes(section.joint_slope_deg)
    t1 = math.tan(math.radians(section.batter_outer_deg))
    # outer face point (y t1, y) with e_v . p = course * block_height
    return course * block_height / (t1 * e_v[0] + e_v[1])


def course_pieces(section, block_length: float = 0.30, block_height: float = 0.125,
                  stagger: float = 0.5) -> list[tuple[int, np.ndarray]]:
    """The section cut into blocks: ``[(course, polygon (k,2) ccw), ...]``, courses from
    the base. Bed joints at v = k t (v normal to the beds), head joints every
    ``block_length`` along the bed, shifted by ``stagger`` of a block on odd courses; a
    cut closer than 0.4 block to a face is dropped (the face block is longer instead of
    a sliver), so face blocks are trimmed to the batter."""
    poly = section_polygon(section)
    e_u, e_v = bed_axes(section.joint_slope_deg)
    v_top = float((poly @ e_v).max())
    pieces = []
    k = 0
    while k * block_height < v_top - 1e-9:
        band = _clip(_clip(poly, -e_v, -k * block_height), e_v, (k + 1) * block_height)
        k_course = k
        k += 1
        if len(band) < 3:
            continue
        v_mid = (k_course + 0.5) * block_height
        mid = _clip(_clip(band, -e_v, -(v_mid - 1e-6)), e_v, v_mid + 1e-6)
        ref = mid if len(mid) >= 3 else band
        u_lo, u_hi = float((ref @ e_u).min()), float((ref @ e_u).max())
        shift = (stagger * block_length) if k_course % 2 else 0.0
        j0 = math.floor((u_lo - shift) / block_length)
        cuts = [shift + j * block_length for j in range(j0, j0 + int((u_hi - u_lo) / block_length) + 3)]
        cuts = [c for c in cuts if u_lo + 0.4 * block_length < c < u_hi - 0.4 * block_length]
        edges = [u_lo - 1.0] + cuts + [u_hi + 1.0]
        for a, b in zip(edges[:-1], edges[1:]):
            piece = _clip(_clip(band, -e_u, -a), e_u, b)
            if len(piece) >= 3 and area_centroid(piece)[0] > 0.02 * block_length * block_height:
                pieces.append((k_course, piece))
    return pieces
