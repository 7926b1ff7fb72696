"""Plane polygons for wall sections: area, centroid and clipping by a half-plane.

Coordinates in m: x from the toe (front edge of the base) toward the backfill, y up
from the underside of the base at the toe. Polygons are lists of (x, y) vertices in
either orientation; clipping assumes a convex polygon (every section here is convex
or a union of convex parts).
"""

from __future__ import annotations

import math

Point = tuple[float, float]


def area_centroid(poly: list[Point]) -> tuple[float, float, float]:
    """Area [m2] and centroid (x, y) [m] of a simple polygon (shoelace formula).
    A degenerate polygon returns area 0 and the mean of its vertices."""
    a = cx = cy = 0.0
    n = len(poly)
    for i in range(n):
        x0, y0 = poly[i]
        x1, y1 = poly[(i + 1) % n]
        cross = x0 * y1 - x1 * y0
        a += cross
        cx += (x0 + x1) * cross
        cy += (y0 + y1) * cross
    a *= 0.5
    if abs(a) < 1e-14:
        xs = [p[0] for p in poly] or [0.0]
        ys = [p[1] for p in poly] or [0.0]
        return 0.0, math.fsum(xs) / len(xs), math.fsum(ys) / len(ys)
    return abs(a), cx / (6 * a), cy / (6 * a)


def clip_above(poly: list[Point], point: Point, slope: float) -> list[Point]:
    """The part of a convex polygon on or above the line through ``point`` with
    dy/dx = ``slope`` (Sutherland-Hodgman against one half-plane)."""
    px, py = point

    def side(p: Point) -> float:
        return p[1] - (py + slope * (p[0] - px))

    out: list[Point] = []
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        sa, sb = side(a), side(b)
        if sa >= 0:
            out.append(a)
        if (sa >= 0) != (sb >= 0):
            t = sa / (sa - sb)
            out.append((a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])))
    return out
