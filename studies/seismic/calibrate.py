"""Material checks of the seismic deposit at the case's contact parameters (measured,
never tuned per case; reference section 3):

* ``shear_wave``: the low-strain shear-wave speed Vs and the fundamental frequency f0 of
  a free-field column (the paper's Table 1: Vs = 210 m/s, f0 = 5.8 Hz prototype for the
  9 m retained column). The settled column is given a small horizontal velocity pulse
  at its base (one raised-cosine cycle of duration ``pulse`` [s], peak velocity
  ``peak_velocity`` [m/s], a shear strain ~ v / Vs of order 1e-5); the spectrum of the
  top slice's velocity after the pulse gives f0, and Vs_f0 = 4 H f0 (the uniform-column
  relation the paper's f0 follows; a depth-averaged Vs). Velocities scale 1 between
  model and prototype; f0 is divided by N.
* ``triaxial``: a cubical triaxial test (six frictionless platens, gravity off, the
  servo of ``studies.triaxial``) on the deposit's grains at the case's Hertz-Mindlin law
  and friction, then sheared at a constant axial strain rate: peak and end
  (critical-state estimate) phi = asin((s1 - s3) / (s1 + s3)); the paper: ~31 deg at
  35-140 kPa and porosity 0.40. The specimen is a cube cut from a deposit rained as the
  model's own (``specimen.rain_deposit``: same grains, friction, N g), so it has the
  deposit's porosity and fabric; the grains the platens would cut are removed and the
  platens brought to the confining stress. (Compacting a random cloud between servo
  platens, the former way, jammed a dense shell along the five moving platens while the
  floor read almost nothing: 300k steps left porosity 0.44-0.47 whatever the compaction
  friction, not the deposit's 0.40. Its phi of 16-18 deg at friction 0.5 was nonetheless
  close to the deposit's own: 17.9 deg on the cut cube; the strength comes from the
  rolling resistance, see ``SeismicCase.rolling_resistance``.)
"""

from __future__ import annotations

import math

import numpy as np

import dem3d
from dem3d import AccelerationTable, Simulation, settle, shaking
from dem3d.measure import slice_averages

from . import specimen as M
from .case import SeismicCase


def shear_wave(case: SeismicCase, column: dict, height: float, *, peak_velocity: float = 2e-3,
               pulse: float = 2e-4, listen: float = 0.03, every: int = 4) -> dict:
    """Vs [m/s] and f0 [Hz, prototype] of a free-field column (module docstring).
    ``column``: the column's arrays (``Simulation.to_arrays``) of soil ``height`` [m]."""
    from .run import _column_walls
    sim = Simulation.from_arrays(column, walls=_column_walls(case))
    law = M.contact_law(case, local_damping=0.7)
    sim.set_params(law, allow_unsafe_dt=True)
    n = sim.n_spheres
    settle(sim, ratio=1e-4, energy=M.settle_energy(case, n, 1e-7), max_steps=20_000, check_every=500)
    t0 = sim.time
    amp = math.pi * peak_velocity / pulse                   # a = A sin(2 pi t / T): v peak = A T / pi
    cycle = AccelerationTable.sampled(lambda t: amp * math.sin(2.0 * math.pi * t / pulse), pulse, 64)
    table = AccelerationTable(np.concatenate([[0.0, t0 * (1.0 - 1e-9)], cycle.times + t0]),
                              np.concatenate([np.zeros((2, 3)), cycle.accel]))
    sim = Simulation.from_arrays(sim.to_arrays(), walls=_column_walls(case, shaking(table)))
    sim.set_params(M.contact_law(case, local_damping=0.0), allow_unsafe_dt=True)
    edges = M.lateral_edges(case, height)
    area = _column_area(sim, case)
    steps = int(round(listen / sim.dt))
    times, vel = [], []
    for _ in range(steps // every):
        sim.step(every)
        times.append(sim.time - t0)
        vel.append(slice_averages(sim, edges, area).velocity[:, 0])
    times, vel = np.array(times), np.array(vel)
    return _wave_figures(case, times, vel, height, pulse, peak_velocity) | {
        "column_spheres": n, "dt_s": float(sim.dt), "steps": steps}


def _column_area(sim: Simulation, case: SeismicCase) -> float:
    """Plan area of a column [m^2]: its periodic length along x times the slab width."""
    return float(sim.periodic.length) * case.width


def _wave_figures(case, times, vel, height, pulse, peak_velocity) -> dict:
    """f0 from the top slice's spectrum after the pulse (the base at rest again), and
    Vs_f0 = 4 H f0. (The pulse's arrival times at the slices were tried as a second
    estimate and dropped: at the coarse resolution the slices' residual velocities are
    of the pulse's size and the picked peaks gave no usable slope.)"""
    top = vel[:, -2]                                      # the top full slice
    after = times > 2.0 * pulse                           # the base at rest again
    t_after = times[after]
    sig = top[after] - np.polyval(np.polyfit(t_after, top[after], 1), t_after)   # creep removed
    pad = 8 * len(sig)                                    # zero padding: the peak between bins
    spec = np.abs(np.fft.rfft(sig * np.hanning(len(sig)), n=pad))
    freq = np.fft.rfftfreq(pad, d=float(times[1] - times[0]))
    ok = freq > 2.0 / max(float(t_after[-1] - t_after[0]), 1e-12)        # two cycles in the record
    f0_model = float(freq[ok][np.argmax(spec[ok])]) if ok.any() else math.nan
    return {"f0_Hz_prototype": f0_model / case.scale_N, "Vs_from_f0_m_per_s": 4.0 * height * f0_model,
            "pulse_s": pulse, "peak_velocity_m_per_s": peak_velocity,
            "frequency_resolution_Hz_prototype": 1.0 / float(t_after[-1] - t_after[0]) / case.scale_N}


def hertz_stiffness(case: SeismicCase, stress: float) -> float:
    """Normal tangent stiffness dF/d(delta) [N/m] of a Hertz contact between two mean
    grains carrying F = stress d^2 (about one contact per d^2 of a section): 1.5 F / delta,
    F = 4/3 E* sqrt(R*) delta^1.5 (the servo's platen stiffness)."""
    law = M.contact_law(case)
    d = case.d_mean
    force = stress * d * d
    delta = (force / (4.0 / 3.0 * law.e_star * math.sqrt(0.25 * d))) ** (2.0 / 3.0)
    return 1.5 * force / delta


def deposit_cube(case: SeismicCase, particles: int, seed: int) -> tuple[np.ndarray, np.ndarray, float]:
    """(positions, radii, side): about ``particles`` grains of a cube of ``side`` [m] cut
    from a deposit rained as the model's (``specimen.rain_deposit``, periodic along y),
    without the grains a platen on the cube's faces would cut (the deposit's porosity
    and fabric; the paper's deposit: porosity 0.40)."""
    side = (1.04 * particles * M.mean_grain_volume(case) / (1.0 - case.porosity)) ** (1.0 / 3.0)
    side *= 1.0 + 1.5 * case.d_mean / side            # the cut loses about a radius per face
    dep = M.rain_deposit(case, np.random.default_rng(seed), (0.0, 0.0), (side, side), side, 1)
    x, r = dep.positions.copy(), dep.radii
    x[:, 1] = np.mod(x[:, 1], side)
    # grains pressed against the deposit's walls and base overlap them slightly: kept
    slack = 0.1 * r[:, None]
    inside = np.all((x - r[:, None] >= -slack) & (x + r[:, None] <= side + slack), axis=1)
    return x[inside], r[inside], side


def triaxial(case: SeismicCase, *, confining: float = 70e3, particles: int = 2000, strain_rate: float = 1.0,
             max_strain: float = 0.12, seed: int = 1, chunk: int = 20) -> dict:
    """Peak and end phi [deg] of the deposit's grains at the case's contact law (module
    docstring). ``strain_rate`` [1/s]: 1/s keeps the inertial number
    I = rate d sqrt(rho / p) near 1e-3 at 70 kPa with the coarse grains (quasi-static)."""
    from ..elements.triaxial import ALL_BUT_FLOOR, ServoCell, ServoVelocity, TriaxialResult, platen_walls
    x, r, side0 = deposit_cube(case, particles, seed)
    spec = dem3d.Specimen(x, r, -np.ones(len(r), np.int64), case.grain_density)
    porosity_cut = 1.0 - float(np.sum(4.0 / 3.0 * np.pi * r ** 3)) / side0 ** 3
    servo = [ServoVelocity() for _ in range(6)]
    law = M.contact_law(case, local_damping=0.7)
    dt = M.time_step(case, law, bonds=False)
    sim = dem3d.Simulation(spec, law, dt=dt, walls=platen_walls(side0, servo), gravity=(0.0, 0.0, 0.0),
                           direct_sums=case.direct_sums)
    cell = ServoCell(sim, servo, hertz_stiffness(case, confining), case.d_mean, dt)
    target = np.full(6, confining)
    for it in range(100_000 // chunk):
        sig = cell.servo_step(target, ALL_BUT_FLOOR, 0.2, chunk)
        # the ratio bound is looser than studies.triaxial's 5e-3: rattlers hold it up here
        if it % 25 == 0 and np.all(np.abs(sig / confining - 1) < 0.05) and \
                dem3d.measure.unbalanced_force_ratio(sim) < 2e-2:
            break
    compaction = sim.step_count
    dims0 = cell.box()
    porosity0 = 1.0 - float(np.sum(sim.sphere_masses())) / case.grain_density / float(np.prod(dims0))
    inner = inner_porosity(sim, case.d_mean)
    sim.set_params(M.contact_law(case, local_damping=0.0))
    n_steps = int(max_strain / strain_rate / dt)
    eps_a, eps_v, s1, s3 = _shear(cell, servo, target, dims0, strain_rate * dims0[2], n_steps, chunk)
    res = TriaxialResult(np.array(eps_a), np.array(eps_v), np.array(s1), np.array(s3), porosity0, sim.n_spheres,
                         float(dims0[0]))
    inertial = strain_rate * case.d_mean * math.sqrt(case.grain_density / confining)
    return {"phi_peak_deg": res.phi_peak_deg, "strain_at_peak": res.strain_at_peak, "phi_end_deg": res.phi_end_deg,
            "porosity": porosity0, "inner_porosity": inner, "porosity_as_cut": porosity_cut, "confining_kPa": confining / 1e3,
            "spheres": sim.n_spheres, "friction": case.friction, "strain_rate_per_s": strain_rate,
            "inertial_number": inertial, "dt_s": dt, "compaction_steps": compaction, "shear_steps": n_steps,
            "curve": {"axial_strain": res.axial_strain[::25].tolist(),
                      "volumetric_strain": res.volumetric_strain[::25].tolist(),
                      "sigma_1_kPa": (res.sigma_1[::25] / 1e3).tolist(),
                      "sigma_3_kPa": (res.sigma_3[::25] / 1e3).tolist()}}


def inner_porosity(sim, margin: float) -> float:
    """Porosity of the box ``margin`` [m] inside the platens, the grains counted by their
    centres (the platens' wall effect left out, as the deposit's porosity leaves out
    the surface layer)."""
    lo = sim.walls.panels.centre[[0, 2, 4], [0, 1, 2]] + margin
    hi = sim.walls.panels.centre[[1, 3, 5], [0, 1, 2]] - margin
    x, r = sim.spheres.x, sim.spheres.r
    inside = np.all((x >= lo) & (x <= hi), axis=1)
    return 1.0 - float(np.sum(4.0 / 3.0 * np.pi * r[inside] ** 3)) / float(np.prod(hi - lo))


def _shear(cell, servo, target, dims0, v_axial: float, n_steps: int, chunk: int):
    """The top platen down at ``v_axial`` [m/s] for ``n_steps``, the lateral platens on
    the servo at the confining stress: per chunk axial and volumetric strain
    (compression +), sigma_1, sigma_3 [Pa]."""
    from ..elements.triaxial import LATERAL
    servo[5].value = tuple(v_axial * cell.normal[5])
    eps_a, eps_v, s1, s3 = [], [], [], []
    done = 0
    while done < n_steps:
        k = min(chunk, n_steps - done)
        sig = cell.servo_step(target, LATERAL, 4.0 * v_axial, k)
        done += k
        dims = cell.box()
        eps_a.append(1.0 - dims[2] / dims0[2])
        eps_v.append(1.0 - float(np.prod(dims)) / float(np.prod(dims0)))
        s1.append(0.5 * (sig[4] + sig[5]))
        s3.append(float(np.mean(sig[:4])))
    return eps_a, eps_v, s1, s3
