"""Parsers and flags shared by the studies' commands. Each parser turns the text a user
typed into a value or raises ``InvalidParameter`` naming the flag and its valid range."""

from __future__ import annotations

import math

from analytic.errors import InvalidParameter
from analytic.inputs import require_number

from .study import Option


def number(name: str, lo=None, hi=None, *, lo_open=True, hi_open=True, unit=""):
    """A finite float in a range."""
    def parse(text: str) -> float:
        return require_number(name, text, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit)
    parse.__name__ = name
    return parse


def count(name: str):
    """A whole number >= 1."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = 0
        if value < 1:
            raise InvalidParameter(name, text, ">= 1")
        return value
    parse.__name__ = name
    return parse


def number_list(name: str, scale: float = 1.0):
    """'0.3,0.5,0.7' -> (0.3, 0.5, 0.7) (times ``scale``); numbers >= 0."""
    def parse(text: str) -> tuple[float, ...]:
        try:
            vals = tuple(float(x) * scale for x in text.split(",") if x.strip())
        except ValueError:
            raise InvalidParameter(name, text, "comma-separated numbers") from None
        if not vals or any(not math.isfinite(v) or v < 0 for v in vals):
            raise InvalidParameter(name, text, "comma-separated numbers >= 0")
        return vals
    parse.__name__ = name
    return parse


def kpa_to_pa(value: float) -> float:
    return value * 1e3


#: the recording flags of the 3D runs
RECORDING = (
    Option("--rrd", "recording path (default: recording.rrd in the run folder)", metavar="FILE"),
    Option("--no-rrd", "write no recording", switch=True),
    Option("--spawn", "also open the Rerun viewer", switch=True),
    Option("--every", "log the scene (particles, chains) every N x 500 steps (5)", parse=count("every"), default=5),
)
