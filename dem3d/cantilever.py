"""A cantilever of bonded spheres: parallel-bond parameters for a target flexural
stiffness, and the check of the bonded beam against Euler-Bernoulli theory.

Strip model (``strip_specimen``): ``layers`` sheets of equal balls of radius
R = thickness / (2 layers), square-packed: ball centres at x_l = (2 l + 1 - layers) R
across the thickness and z = 2 R k along the length (one ball wide in y). Each ball is
bonded to its neighbours along z (same sheet) and across x (same row).

Calibration (``calibrate_strip``): in cylindrical bending with curvature kappa, plane
sections stay plane (the bonds across the sheets see no relative motion), a bond between
neighbours along z at x_l is stretched by x_l kappa D and bent by kappa D over its length
D = 2 R, so the moment carried by a row (width D) is M = kn D kappa sum_l (A x_l^2 + I),
A = pi Rb^2, I = pi Rb^4 / 4 (Potyondy & Cundall 2004's bond area and inertia). Per unit
width EI_w = kn sum_l (A x_l^2 + I); setting EI_w = E t^3 / 12 gives
    kn = E t^3 / (12 sum_l (A x_l^2 + I)),   ks = kn / shear_ratio.
For two sheets and Rb = R: kn = 32 E / (15 pi R) ~ 0.679 E / R.
Limits: the square strip has a solid fraction pi/6 = 0.52 (a close-packed sheet 0.60), so
its mass per area is rho_ball pi t / 6; choose the ball density for the target mass.

Check (``cantilever_check``): row 0 clamped (both balls locked), a load F across the
strip at the tip row, PFC local damping to the static state: tip deflection vs
F L^3 / (3 EI) with L = (N - 1) D from the clamped row to the loaded row (the joints sit
midway between rows, so the discrete sum of joint rotations is the midpoint rule of the
continuum integral, error D^2 / (4 L^2)). Then the load is removed and the undamped free
vibration's period gives the first frequency vs 1.875^2 sqrt(EI / (m L^4)) / (2 pi),
m the mass per unit length of the moving rows.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from analytic.errors import InvalidParameter

from .engine import Simulation
from .run import frame
from .params import linear
from .state import Specimen


class BondParameters(NamedTuple):
    """Parallel-bond parameters of a bonded strip (module docstring).

    kn, ks:            normal / shear bond stiffness per area [N/m^3]
    radius_multiplier: bond radius / ball radius [-]
    ball_radius:       R [m]
    layers:            sheets across the thickness
    youngs:            target Young's modulus E [Pa]
    thickness:         target thickness t [m]
    ei_per_width:      E t^3 / 12 [N m^2 / m]
    """

    kn: float
    ks: float
    radius_multiplier: float
    ball_radius: float
    layers: int
    youngs: float
    thickness: float
    ei_per_width: float


def calibrate_strip(youngs: float, thickness: float, *, layers: int = 2, radius_multiplier: float = 1.0,
                    shear_ratio: float = 1.0) -> BondParameters:
    """Bond stiffnesses that give a strip of ``layers`` sheets the bending stiffness of a
    solid plate E t^3 / 12 per unit width (module docstring)."""
    if not (youngs > 0 and thickness > 0 and layers >= 1 and radius_multiplier > 0 and shear_ratio > 0):
        raise InvalidParameter("calibration", (youngs, thickness, layers), "E > 0 Pa, t > 0 m, layers >= 1")
    r = thickness / (2.0 * layers)
    rb = radius_multiplier * r
    area = math.pi * rb * rb
    inertia = 0.25 * math.pi * rb ** 4
    x = (2.0 * np.arange(layers) + 1.0 - layers) * r
    ei = youngs * thickness ** 3 / 12.0
    kn = ei / float(np.sum(area * x * x + inertia))
    return BondParameters(kn, kn / shear_ratio, radius_multiplier, r, int(layers), float(youngs), float(thickness), ei)


def strip_specimen(length: float, thickness: float, *, layers: int = 2, density: float = 4000.0):
    """Balls of a strip along z from z = 0 (module docstring): (Specimen, row (n,)). The
    row count N = round(length / D) + 1 makes the clamped-to-tip length (N - 1) D."""
    r = thickness / (2.0 * layers)
    rows = int(round(length / (2.0 * r))) + 1
    if rows < 3:
        raise InvalidParameter("length", length, f">= {4 * r:.4g} m (3 rows)")
    z = 2.0 * r * np.arange(rows)
    x = (2.0 * np.arange(layers) + 1.0 - layers) * r
    zz, xx = np.meshgrid(z, x, indexing="ij")
    pos = np.stack([xx.ravel(), np.zeros(xx.size), zz.ravel()], axis=1)
    row = np.repeat(np.arange(rows), layers)
    n = pos.shape[0]
    return Specimen(pos, np.full(n, r), -np.ones(n, np.int64), float(density)), row


class CantileverResult(NamedTuple):
    """Outcome of ``cantilever_check`` (SI units)."""

    bonds: BondParameters
    length: float                   # L, clamped row to loaded row [m]
    width: float                    # strip width (one ball) [m]
    load: float                     # tip load [N]
    tip_deflection: float           # static tip deflection [m]
    beam_deflection: float          # F L^3 / (3 EI) [m]
    tip_deflection_over_beam: float
    frequency: float                # first natural frequency of the bonded strip [Hz]
    beam_frequency: float           # 1.875^2 sqrt(EI / (m L^4)) / (2 pi) [Hz]
    frequency_over_beam: float
    n_spheres: int
    steps: int


def cantilever_check(youngs: float = 40e9, thickness: float = 5e-3, length: float = 0.135, *,
                     density: float = 4000.0, layers: int = 2, radius_multiplier: float = 1.0,
                     shear_ratio: float = 1.0, tip_deflection_ratio: float = 1e-3,
                     dt_fraction: float = 0.2, tolerance: float = 1e-4, progress=None,
                     on_frame=None) -> CantileverResult:
    """Build the bonded strip calibrated by ``calibrate_strip``, clamp row 0, load the
    tip row across the strip with F giving a beam deflection ``tip_deflection_ratio`` L
    (small: linear theory), relax with local damping 0.7 until the tip moves less than
    ``tolerance`` of its deflection per period, and measure the deflection; then remove
    the load, switch damping off and time the free vibration over 3 periods (zero
    crossings about the unloaded position, linearly interpolated).
    ``dt_fraction`` x the bonds' critical step is the time step; ``progress(stage, done,
    total)`` is called after every chunk of steps ("relax" counts chunks of at most 400,
    "vibrate" samples); ``on_frame(frame)`` with the strip relaxed under the load and
    every 20 samples of the vibration (about 10 a period)."""
    prm = calibrate_strip(youngs, thickness, layers=layers, radius_multiplier=radius_multiplier,
                          shear_ratio=shear_ratio)
    spec, row = strip_specimen(length, thickness, layers=layers, density=density)
    r = prm.ball_radius
    d = 2.0 * r
    rows = int(row.max()) + 1
    big_l = (rows - 1) * d
    ei = prm.ei_per_width * d                  # strip one ball (D) wide
    m_ball = density * 4.0 / 3.0 * math.pi * r ** 3
    m_per_length = layers * m_ball / d
    beam_frequency = 1.875 ** 2 * math.sqrt(ei / (m_per_length * big_l ** 4)) / (2.0 * math.pi)
    period = 1.0 / beam_frequency
    # the contact law only acts between unbonded touching balls (none here); its
    # stiffness is set to the bonds' axial one so the usual time-step check applies
    k_axial = prm.kn * math.pi * (radius_multiplier * r) ** 2
    law = linear(k_axial, k_axial, 0.5, local_damping=0.7)
    sim = Simulation(spec, law, dt=1e-12, gravity=(0.0, 0.0, 0.0), sort_by_cell=False, skin=0.2 * r)
    sim.make_bonds(0.01 * r, kn=prm.kn, ks=prm.ks, radius_multiplier=radius_multiplier)
    sim.dt = dt_fraction * min(sim.dt_critical_bonds, sim.dt_critical)
    clamp = np.nonzero(row == 0)[0]
    tip = np.nonzero(row == rows - 1)[0]
    sim.lock(clamp, translation=True, rotation=True)
    load = tip_deflection_ratio * big_l * 3.0 * ei / big_l ** 3
    f = np.zeros((spec.positions.shape[0], 3))
    f[tip, 0] = load / len(tip)
    sim.set_external_force(f)
    x0 = spec.positions[tip, 0].mean()
    per = max(1, int(round(period / sim.dt)))
    chunk = max(1, per // 4)
    steps = 0
    last = None
    for k in range(400):                       # relax (at most 100 periods)
        sim.step(chunk)
        steps += chunk
        if progress is not None:
            progress("relax", k + 1, 400)
        tip_x = _tip(sim, tip) - x0
        if last is not None and abs(tip_x - last) < tolerance * 0.25 * abs(tip_x):
            break
        last = tip_x
    deflection = _tip(sim, tip) - x0
    if on_frame is not None:
        on_frame(frame(sim))
    sim.clear_external_force()
    sim.set_params(law._replace(local_damping=0.0), allow_unsafe_dt=True)
    times, values = [], []
    sample = max(1, per // 200)
    n_samples = int(3.5 * per / sample) + 1
    for k in range(n_samples):
        sim.step(sample)
        steps += sample
        if progress is not None and (k % 20 == 19 or k == n_samples - 1):
            progress("vibrate", k + 1, n_samples)
        if on_frame is not None and k % 20 == 19:
            on_frame(frame(sim))
        times.append(sim.time)
        values.append(_tip(sim, tip) - x0)
    frequency = _frequency(np.array(times), np.array(values))
    beam = load * big_l ** 3 / (3.0 * ei)
    return CantileverResult(prm, big_l, d, load, deflection, beam, deflection / beam, frequency, beam_frequency,
                            frequency / beam_frequency, int(spec.positions.shape[0]), steps)


def _tip(sim: Simulation, tip: np.ndarray) -> float:
    """Mean x of the tip balls [m] (specimen indices -> engine rows)."""
    engine = np.empty(sim.n_spheres, np.int64)
    engine[sim.original_index] = np.arange(sim.n_spheres)
    return float(sim.spheres.x[engine[tip], 0].mean())


def _frequency(t: np.ndarray, y: np.ndarray) -> float:
    """Frequency [Hz] from the zero crossings of y(t) (linear interpolation): (crossings
    - 1) / 2 half periods between the first and the last."""
    s = np.sign(y)
    k = np.nonzero(s[1:] * s[:-1] < 0)[0]
    if len(k) < 3:
        return float("nan")
    tc = t[k] - y[k] * (t[k + 1] - t[k]) / (y[k + 1] - y[k])
    return 0.5 * (len(tc) - 1) / (tc[-1] - tc[0])
