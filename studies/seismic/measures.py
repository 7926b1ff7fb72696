"""What the seismic study measures on the sheet pile and the ground, model units in,
prototype units out (``case.prototype_factors``). Signs: wall displacement and rotation
positive toward the excavation (-x); face pressure compression positive; bending moment
per width positive when the retained face is in tension (the static cantilever's sign).

* ``wall_reading``: per row of wall balls (along z): mean displacement, the normal
  pressure of the soil on each face (front: the excavated side, back: the retained side)
  from the soil-ball contact forces' x components over the row's face area D x width,
  the thrust on each face (per width), and the bending moment at the joints between
  rows (``dem3d.measure.section_forces``, bond forces and moments).
* ``rotation_fit``: least-squares line through the rows' displacements: rotation and the
  pivot's height (where the line crosses zero) over the wall length.
* ``settlement``: ``dem3d.measure.settlement_profile`` of the retained ground against
  distance from the wall's back face.
* ``mononobe_okabe_overlay``: M-O active (retained side, surface to toe) and passive
  (dredge line to toe) profiles with phi and the DEM's unit weight, prototype units.
* ``row_moments``: the bending moment at each row of wall balls (for colouring the wall).
* ``shear_strain_map``: the maximum shear strain in the x-z plane between two sets of
  sphere positions (``dem3d.measure.strain_field``, one cell across the periodic slab).
* ``period_mean``: a running mean over one period of the base motion (the paper's
  "average" K of Fig. 4).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from analytic.inputs import Soil, Wall as WallInput
from analytic.constants import G
from analytic.seismic import mononobe_okabe
from analytic.classical import coulomb
from dem3d.measure import max_shear_strain, section_forces, settlement_profile, strain_field

from .case import SeismicCase


class WallReading(NamedTuple):
    """One reading of the wall (model units, SI).

    z:              (rows,) row heights above the base [m]
    x:              (rows,) mean x of each row's balls [m]
    sigma_front:    (rows,) soil pressure on the front face [Pa]
    sigma_back:     (rows,) soil pressure on the back face [Pa]
    thrust_front:   front-face thrust per width [N/m]
    thrust_back:    back-face thrust per width [N/m]
    cut_z:          (rows - 1,) joint heights [m]
    moment:         (rows - 1,) bending moment per width at the joints [N m/m]
    """

    z: np.ndarray
    x: np.ndarray
    sigma_front: np.ndarray
    sigma_back: np.ndarray
    thrust_front: float
    thrust_back: float
    cut_z: np.ndarray
    moment: np.ndarray


def soil_forces_on(sim, members: np.ndarray) -> np.ndarray:
    """(len(members), 3) sum of the contact forces of every other sphere on each of
    ``members`` (specimen indices) from the last force evaluation [N]; pairs inside the
    group and bonds are left out."""
    n = sim.n_spheres
    engine = np.empty(n, np.int64)
    engine[sim.original_index] = np.arange(n)
    rows = engine[np.asarray(members, np.int64)]
    mine = np.zeros(n, bool)
    mine[rows] = True
    prs = sim.pairs
    total = int(prs.start[-1])
    k = np.nonzero(prs.active[:total])[0]
    i = np.searchsorted(prs.start, k, side="right") - 1
    j = prs.nbr[k]
    f_j = prs.pf[sim.pair_rows()[k], 0:3]                      # force on j; -f_j on i
    out = np.zeros((n, 3))
    a = mine[i] & ~mine[j]
    b = mine[j] & ~mine[i]
    np.add.at(out, i[a], -f_j[a])
    np.add.at(out, j[b], f_j[b])
    return out[rows]


def wall_reading(sim, case: SeismicCase, model) -> WallReading:
    """The wall's displacement, face pressures, thrusts and moments now (module docstring)."""
    n = sim.n_spheres
    engine = np.empty(n, np.int64)
    engine[sim.original_index] = np.arange(n)
    rows = int(model.wall_row.max()) + 1
    x = sim.spheres.x[engine[model.wall]]
    f = soil_forces_on(sim, model.wall)
    d = case.wall_ball
    area = d * case.width
    count = np.bincount(model.wall_row, minlength=rows)
    z = np.bincount(model.wall_row, weights=x[:, 2], minlength=rows) / count
    xm = np.bincount(model.wall_row, weights=x[:, 0], minlength=rows) / count
    front = model.wall_sheet == 0
    sig_f = np.bincount(model.wall_row[front], weights=f[front, 0], minlength=rows) / area
    sig_b = -np.bincount(model.wall_row[~front], weights=f[~front, 0], minlength=rows) / area
    cuts = case.toe + d * np.arange(1, rows)
    sec = section_forces(sim, cuts, axis=2, spheres=model.wall)
    # section_forces: the moment of the part below the cut ON the part above; the retained
    # soil pushes the part above toward -x at a lever +z, a moment -h F about y, which the
    # section balances with +h F: the static cantilever's moment is positive about +y
    moment = sec.moment[:, 1] / case.width
    return WallReading(z, xm, sig_f, sig_b, float(sig_f.sum() * d), float(sig_b.sum() * d), cuts, moment)


def rotation_fit(z: np.ndarray, u: np.ndarray, case: SeismicCase) -> tuple[float, float, float]:
    """(rotation [deg], pivot height above the toe over the wall length, top
    displacement of the line [m]) of u(z) = a + b z, u toward the excavation."""
    b, a = np.polyfit(z, u, 1)
    top = case.toe + case.wall_length
    pivot = (-a / b - case.toe) / case.wall_length if b != 0 else math.nan
    return math.degrees(math.atan(b)), float(pivot), float(a + b * top)


def settlement(x_ref: np.ndarray, x_cur: np.ndarray, radii: np.ndarray, case: SeismicCase, soil: np.ndarray):
    """(distance from the wall's back face [m], settlement [m]) of the retained ground
    in bins of two mean diameters, model units."""
    t = 2.0 * case.wall_ball
    edges = np.arange(t, t + case.behind + 1e-12, 2.0 * case.d_mean)
    centre, s = settlement_profile(x_ref[soil], x_cur[soil], radii[soil], edges)
    return centre - t, s


def unit_weight(case: SeismicCase, porosity: float) -> float:
    """Dry unit weight at 1 g [N/m^3] (prototype; the model's at N g is N times it)."""
    return case.grain_density * (1.0 - porosity) * G


def mononobe_okabe_overlay(case: SeismicCase, porosity: float, phi_deg: float = 31.0,
                           delta_deg: float = 0.0) -> dict:
    """Static Coulomb and M-O (kh = amplitude_g, kv = 0) active on the retained side
    over the wall (surface to toe) and passive in front (dredge line to toe), prototype
    units: {"active_static", "active_MO", "passive_static", "passive_MO"} -> Profile
    (z below each side's surface [m], sigma_h [Pa]). phi ~ 31 deg [F]; delta not found
    ([A] 0 by default)."""
    n = case.scale_N
    soil = Soil(phi_deg, unit_weight(case, porosity))
    h_active = case.wall_length * n
    h_passive = (case.wall_length - (case.retained_height - case.front_height)) * n
    act = WallInput(h_active, delta_deg=delta_deg)
    pas = WallInput(h_passive, delta_deg=delta_deg)
    return {"active_static": coulomb(soil, act), "active_MO": mononobe_okabe(soil, act, case.amplitude_g),
            "passive_static": coulomb(soil, pas, passive=True),
            "passive_MO": mononobe_okabe(soil, pas, case.amplitude_g, passive=True)}


def row_moments(reading: WallReading) -> np.ndarray:
    """(rows,) bending moment per width at each row's centre [N m/m]: the mean of the
    joints below and above it, the wall's free toe and top carrying none."""
    m = np.concatenate([[0.0], np.asarray(reading.moment, float), [0.0]])
    return 0.5 * (m[:-1] + m[1:])


#: prototype times [s] of the paper's Fig. 7 (maximum shear strain, 0.1 g 5 Hz) [F]
STRAIN_TIMES = (1.5, 2.0, 3.5, 9.0)
#: strain cell side in x and z, in mean grain diameters [A]: the paper's sampling spheres
#: are not sized; 2 d holds ~20 grains a cell across the 5-grain periodic slab (a
#: least-squares affine fit needs >= 4, and fewer grains make the field noisier)
STRAIN_CELL_GRAINS = 2.0
#: fewest grains (by reference centre) in a cell for its fit [A]
STRAIN_MIN_GRAINS = 10


class ShearStrainMap(NamedTuple):
    """Maximum shear strain in the x-z plane, model units.

    x_edges, z_edges:  (nx + 1,), (nz + 1,) cell edges [m]
    grains:            (nx, nz) grains (by reference centre) in each cell
    max_shear_strain:         (nx, nz) maximum engineering shear strain [-] (nan: < STRAIN_MIN_GRAINS)
    """

    x_edges: np.ndarray
    z_edges: np.ndarray
    grains: np.ndarray
    max_shear_strain: np.ndarray


def strain_edges(case: SeismicCase, cell_grains: float = STRAIN_CELL_GRAINS) -> tuple[np.ndarray, np.ndarray]:
    """Cell edges along x (front boundary to back boundary) and z (base to the retained
    surface) [m], cells of about ``cell_grains`` mean diameters."""
    cell = cell_grains * case.d_mean
    x_lo, x_hi = -case.front, 2.0 * case.wall_ball + case.behind
    nx = max(1, int(round((x_hi - x_lo) / cell)))
    nz = max(1, int(round(case.retained_height / cell)))
    return np.linspace(x_lo, x_hi, nx + 1), np.linspace(0.0, case.retained_height, nz + 1)


def shear_strain_map(case: SeismicCase, x_ref: np.ndarray, x_cur: np.ndarray, soil: np.ndarray,
                     cell_grains: float = STRAIN_CELL_GRAINS) -> ShearStrainMap:
    """The soil's maximum shear strain from ``x_ref`` to ``x_cur`` (specimen order [m]):
    the best-fit displacement gradient per cell (``strain_field``; one cell spans the
    periodic slab, so the field is the slab's average, displacements unwrapped across
    it), then the in-plane Mohr circle's diameter sqrt((e_xx - e_zz)^2 + (2 e_xz)^2)
    (``max_shear_strain`` on axes x, z; simple shear gamma gives gamma)."""
    xe, ze = strain_edges(case, cell_grains)
    ye = np.array([-case.width, 2.0 * case.width])       # every grain, wrapped or not
    sf = strain_field(np.asarray(x_ref)[soil], np.asarray(x_cur)[soil], (xe, ye, ze),
                      min_count=STRAIN_MIN_GRAINS, period=(1, case.width))
    shape = (len(xe) - 1, len(ze) - 1)
    gamma = max_shear_strain(sf.strain, plane=(0, 2)).reshape(shape)
    return ShearStrainMap(xe, ze, sf.count.reshape(shape), gamma)


def period_mean(t: np.ndarray, values: np.ndarray, period: float) -> np.ndarray:
    """Centred running mean of ``values`` over one ``period`` of ``t`` (same units),
    shortened at the ends of the record."""
    v = np.asarray(values, float)
    t = np.asarray(t, float)
    if len(v) < 2 or not period > 0:
        return v.copy()
    dt = float(np.median(np.diff(t)))
    h = max(0, int(round(0.5 * period / dt)))
    c = np.concatenate([[0.0], np.cumsum(v)])
    i = np.arange(len(v))
    lo, hi = np.maximum(i - h, 0), np.minimum(i + h + 1, len(v))
    return (c[hi] - c[lo]) / (hi - lo)
