"""The loose cloud every rained specimen starts from (the wall backfills of ``specimen``,
the triaxial cube of ``elements.triaxial``, the heap, the seismic deposit and its
free-field columns): bodies placed at random in a
box tall enough for a low solid fraction, since random sequential addition jams near a
solid fraction of 0.25-0.38; a taller, looser box is tried when a narrow one jams."""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

import dem3d
from analytic.errors import InvalidParameter


def loose_cloud(rng: np.random.Generator, lo, hi_at: Callable[[float], np.ndarray], fractions: Sequence[float],
                n_bodies: int, d_min: float, d_max: float, *, density: float, clump_fraction: float = 0.0,
                clump_overlap: float = 1.0, what: tuple[str, object] = ("particles", None)
                ) -> tuple[dem3d.Specimen, float]:
    """(specimen, solid fraction): ``n_bodies`` bodies of diameters in [d_min, d_max] [m]
    (``dem3d.random_specimen``: its clumps, density [kg/m^3]) placed at random in the box
    [lo, hi_at(f)] [m] for the first solid fraction f of ``fractions`` at which they fit.
    These are the only draws from ``rng``; a try that jams leaves the generator where it
    stopped and the next draws on from there. Raises InvalidParameter naming ``what``
    (the parameter and its value) when even the last fraction jams."""
    for fraction in fractions:
        try:
            return dem3d.random_specimen(rng, lo, hi_at(fraction), n_bodies, d_min, d_max,
                                         clump_fraction=clump_fraction, clump_overlap=clump_overlap,
                                         density=density), fraction
        except InvalidParameter:
            continue
    raise InvalidParameter(what[0], what[1], "a count whose grains fit the generation box",
                           f"random placement jammed even at a solid fraction of {fractions[-1]:.3g}")
