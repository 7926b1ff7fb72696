"""Nadukuru & Michalowski's Fig. 1 statements scored against the heap report
(``docs/validation/heap.json``): the rows of its scorecard (``studies.scorecard``).
The paper's text gives the arching dip and the heap's recipe, no numbers of the
result (Fig. 1 itself is not in the text)."""

from __future__ import annotations

import math

from ..scorecard import Row, trend_verdict


def scorecard_rows(rep: dict, ref: dict) -> list[Row]:
    return _dip_rows(rep) + [_wedge_row(rep)]


def _wedge_row(rep: dict) -> Row:
    """Fig. 1(a): a wedge-shaped (prismatic) heap, its flanks meeting at a ridge. Ours is a
    wedge when its height H is that of the flanks' slope over half the base,
    (B / 2) tan(slope), to within two of the largest grains (a ridge rounded by a grain or
    two); each seed."""
    B, d_max = rep["case"]["base_length"], rep["case"]["d_max"]
    ridge = [0.5 * B * math.tan(math.radians(a)) for a in rep["slope_deg"]["per_seed"]]
    h = rep["heap_height_m"]["per_seed"]
    ours = ", ".join(f"{x:.2f} against {r:.2f} m" for x, r in zip(h, ridge))
    return Row("the heap is wedge-shaped (prismatic)", "section on arching, Fig. 1(a)",
               "a wedge: the flanks meet at a ridge", f"height {ours} (seeds: H against (B/2) tan slope)",
               f"within {2 * d_max:.3f} m (two of the largest grains) on every seed",
               trend_verdict(all(abs(x - r) <= 2 * d_max for x, r in zip(h, ridge))),
               note="ours is flat-topped (heap.md, 'Shape')")


def _dip_rows(rep: dict) -> list[Row]:
    after = rep["centre_over_peak_after"]["per_seed"]
    before = rep["centre_over_peak_before"]["per_seed"]
    per_seed = ", ".join(f"{a:.2f}" for a in after)
    deeper = [b - a for a, b in zip(after, before)]
    return [
        Row("after the subsidence the base stress has a distinct local minimum at the centre (a dip)",
            "section on arching, Fig. 1(c)", "centre below the peak", f"centre / peak {per_seed} (seeds)",
            "centre / peak < 1 on every seed", trend_verdict(all(a < 1.0 for a in after))),
        Row("the dip comes with the subsidence: load shed from the compliant centre to the stiffer parts",
            "section on arching, Fig. 1(c)", "centre / peak falls as the base deflects",
            "falls by " + ", ".join(f"{x:.2f}" for x in deeper), "lower after than before on every seed",
            trend_verdict(all(x > 0 for x in deeper)),
            note="before the deflection ours is already below 1 (0.85 mean): the paper states no dip there"),
    ]
