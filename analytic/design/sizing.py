"""Sizing: the smallest toe, heel or base width for which every check of a format
passes (``--solve toe|heel|base``).

A coarse scan upward from the smallest admissible value (steps of ``step`` m) finds the
first passing size, then bisection pins the size where the governing utilisation
crosses 1 (to ``tol`` m). 'base' scales toe and heel together for a cantilever, moves
the front face of a gravity wall and widens a block wall.
"""

from __future__ import annotations

import math

from ..errors import InvalidParameter
from .case import DesignCase
from .factors import Factors
from .formats import verify

DIMENSIONS = ("toe", "heel", "base")


def _lower_bound(case: DesignCase, name: str) -> float:
    w = case.wall
    if name == "base" and w.kind == "gravity":
        return w.crest + max(w.back_batter, 0.0) + 1e-6
    if name == "base" and w.kind == "blocks":
        return w.base - w.crest + 1e-6
    if name == "base":
        return 1e-6
    return 0.0


def governing_utilisation(case: DesignCase, factors: Factors, fmts) -> float:
    """The highest utilisation over the formats (inf if the wall cannot be evaluated)."""
    worst = 0.0
    for fmt in ([fmts] if isinstance(fmts, str) else fmts):
        try:
            worst = max(worst, verify(case, factors, fmt).governing[2])
        except (InvalidParameter, ZeroDivisionError, ValueError):
            return math.inf
    return worst


def solve(case: DesignCase, factors: Factors, fmts, name: str, *, step: float = 0.05,
          tol: float = 1e-7, max_size: float = 50.0) -> DesignCase:
    """The case with the smallest ``name`` [m] for which every check of every format in
    ``fmts`` (a name or a list) passes."""
    if name not in DIMENSIONS:
        raise InvalidParameter("solve", name, " | ".join(DIMENSIONS))

    def resized(d):
        return case.replace_wall(case.wall.with_dimension(name, d))

    lo = _lower_bound(case, name)
    resized(lo + step)                    # refuses a dimension this wall does not have
    hi = lo
    while governing_utilisation(resized(hi), factors, fmts) > 1.0:
        lo, hi = hi, hi + step
        if hi > max_size:
            raise InvalidParameter("solve", name, f"a size below {max_size:g} m",
                                   "no size passes every check of this format")
    while hi - lo > tol and hi > lo:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if governing_utilisation(resized(mid), factors, fmts) > 1.0 else (lo, mid)
    return resized(hi)
