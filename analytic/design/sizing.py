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
from .formats import FormatResult, verify

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


def governing_utilisation(case: DesignCase, factors: Factors, fmt: str) -> tuple[float, FormatResult | None]:
    """The highest utilisation of the format (inf if the wall cannot be evaluated)."""
    try:
        res = verify(case, factors, fmt)
    except (InvalidParameter, ZeroDivisionError, ValueError):
        return math.inf, None
    return res.governing[2], res


def solve(case: DesignCase, factors: Factors, fmt: str, name: str, *, step: float = 0.05,
          tol: float = 1e-7, max_size: float = 50.0) -> tuple[DesignCase, FormatResult]:
    """The case with the smallest passing ``name`` and its result."""
    if name not in DIMENSIONS:
        raise InvalidParameter("solve", name, " | ".join(DIMENSIONS))

    def trial(d):
        c = case.replace_wall(case.wall.with_dimension(name, d))
        return governing_utilisation(c, factors, fmt)[0]

    case.wall.with_dimension(name, _lower_bound(case, name) + step)   # refuses a wrong dimension early
    lo = _lower_bound(case, name)
    hi = lo
    while trial(hi) > 1.0:
        lo, hi = hi, hi + step
        if hi > max_size:
            raise InvalidParameter("solve", name, f"a size below {max_size:g} m",
                                   "no size passes every check of this format")
    if hi == lo:
        c = case.replace_wall(case.wall.with_dimension(name, hi))
        return c, verify(c, factors, fmt)
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if trial(mid) > 1.0 else (lo, mid)
    c = case.replace_wall(case.wall.with_dimension(name, hi))
    return c, verify(c, factors, fmt)
