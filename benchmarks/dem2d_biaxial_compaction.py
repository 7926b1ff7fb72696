"""Biaxial compaction only (studies/elements/biaxial.py defaults, 4 kPa), then what the packing is
made of: disks outside the piston box, overlap area and mean overlap, interior solid
fraction, coordination. Written to find out why the full-size specimen reports a solid
fraction of ~0.91 (results: docs/validation/biaxial_compaction_check.json).

    python benchmarks/dem2d_biaxial_compaction.py SCALE     # SCALE = particles_scale (1 = full size)
"""

import json
import sys
import time

import numpy as np
from scipy.spatial import cKDTree

from studies.elements.biaxial import BiaxialCase, BiaxialTest
from dem2d.measure import solid_fraction


def lens_area(r1, r2, d):
    """Area shared by two overlapping disks of radii r1, r2 at centre distance d [m^2]."""
    a1 = r1**2 * np.arccos(np.clip((d**2 + r1**2 - r2**2) / (2 * d * r1), -1, 1))
    a2 = r2**2 * np.arccos(np.clip((d**2 + r2**2 - r1**2) / (2 * d * r2), -1, 1))
    tri = 0.5 * np.sqrt(np.clip((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2), 0, None))
    return a1 + a2 - tri


def main(scale: float) -> dict:
    test = BiaxialTest(BiaxialCase(particles_scale=scale, friction=0.3))
    t0 = time.perf_counter()
    last = None
    for last in test.prepare():
        pass
    w, h = test.width(), test.height()
    x = np.array([tuple(b.position) for b in test.sim.grains.bodies])
    r = np.asarray(test.sim.grains.circle_radius)
    pairs = cKDTree(x).query_pairs(2 * r.max(), output_type="ndarray")
    d = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1)
    r1, r2 = r[pairs[:, 0]], r[pairs[:, 1]]
    touch = r1 + r2 - d > 0
    r1, r2, d = r1[touch], r2[touch], d[touch]
    solid = float(np.sum(np.pi * r**2))
    return {"scale": scale, "n": len(r), "width": w, "height": h,
            "solid_fraction_reported": last.solid_fraction, "sigma1": last.sigma_1, "sigma3": last.sigma_3,
            "outside_box": int(np.sum((x[:, 0] < 0) | (x[:, 0] > w) | (x[:, 1] < 0) | (x[:, 1] > h))),
            "overlap_area_share": float(lens_area(r1, r2, d).sum() / solid),
            "mean_overlap_over_rmin": float(np.mean((r1 + r2 - d) / np.minimum(r1, r2))),
            "interior_fraction_centres": solid_fraction(x, r, 0.2 * w, 0.8 * w, 0.2 * h, 0.8 * h),
            # geometric: overlapping pairs per disk, rattlers included
            "coordination": 2 * int(touch.sum()) / len(r), "wall_s": time.perf_counter() - t0}


if __name__ == "__main__":
    print(json.dumps(main(float(sys.argv[1])), indent=1))
