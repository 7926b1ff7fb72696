"""The biaxial study's own figures: the shear band in the specimen (Khosravi et al.
Fig. 3, where the paper reads beta ~ 55 deg from the major principal plane)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..elements.biaxial import BiaxialCase, band_cell, band_window, strain_field


def plot_shear_band(test, case: BiaxialCase, band_deg: float, path: Path) -> Path | None:
    """The incremental maximum shear strain of the post-peak part of ``test``
    (``band_window``, on the band's own cells, ``band_cell``) with the band read from it
    (``shear_band_angle``: ``band_deg`` from the horizontal) drawn as ``band_line`` finds
    it. None when the test has too few marks or no band."""
    from viz.figures import plot_cell_map
    window = band_window(test.position_marks)
    if window is None or not np.isfinite(band_deg):
        return None
    cell = band_cell(case)
    centres, gamma = strain_field(*window, cell)
    centre, angle = band_line(centres, gamma, band_deg, cell)
    return plot_cell_map(centres, gamma, path, cell=cell, label="incremental max shear strain [-]",
                         lines=[(centre, angle, f"band {band_deg:.0f} deg from the horizontal")],
                         title=f"biaxial, mu {case.friction:g}, {case.confining / 1e3:g} kPa:\nstrain after the "
                               "peak (paper: a band at 55 deg)")


def band_line(centres: np.ndarray, gamma: np.ndarray, band_deg: float, cell: float) -> tuple[tuple, float]:
    """Where to draw a band of ``band_deg`` from the horizontal on a strain map (cell
    centres (k,2) [m], strain (k,)): through the strain-weighted centre of the cells
    above the median, at whichever inclination (band_deg or 180 - band_deg) collects the
    most excess strain within one ``cell`` of the line. Returns ((x, y), angle [deg])."""
    w = np.clip(gamma - np.median(gamma), 0.0, None)
    centre = (centres * w[:, None]).sum(axis=0) / w.sum() if w.sum() > 0 else centres.mean(axis=0)

    def along(angle: float) -> float:
        t = np.radians(angle)
        return float(w[np.abs((centres - centre) @ np.array([-np.sin(t), np.cos(t)])) < cell].sum())

    return (float(centre[0]), float(centre[1])), max((band_deg, 180.0 - band_deg), key=along)
