"""A column of spheres on a shaken base: shear-wave speed from a pulse's travel time and
the fundamental frequency of a base sine sweep, f0 = Vs / (4 H) (a uniform fixed-free
shear column; Kramer 1996, eq. 7.46)."""

import math

import numpy as np
import pytest

from dem3d import AccelerationTable, Simulation, Wall, history, linear, plane, shaking

from conftest import single_specimen, sphere_mass

R = 0.01
RHO = 2650.0
KN = 1e5
KS = 4e4
N = 40
G = 9.81


def column(motion, zeta_s):
    """N spheres stacked on a floor that moves with ``motion``, rotations locked (a
    stack of grains shears through its contacts' tangential springs, ks), linear law,
    settled under gravity first (the floor at rest until t0 = 0.15 s)."""
    m = sphere_mass(R, RHO)
    spec = single_specimen([(0.0, 0.0, R + 2 * R * k) for k in range(N)], R, RHO)
    law = linear(KN, KS, 1.0, zeta_n=0.3, zeta_s=zeta_s)
    sim = Simulation(spec, law, dt=0.05 * math.sqrt(m / KN), sort_by_cell=False,
                     walls=[Wall("base", plane((0, 0, 0), (0, 0, 1), mu=1.0), motion)])
    sim.lock(rotation=True)
    return sim


T0 = 0.15


def pulse_speed():
    """Shear-wave speed [m/s] from the arrival of a half-sine base velocity pulse (length
    20 grains) at spheres 5 and 25: 20 spacings over the delay of the velocity peaks."""
    m = sphere_mass(R, RHO)
    c = 2 * R * math.sqrt(KS / m)                      # expected long-wave speed
    t_h = 10 * 2 * R / c
    v0 = 1e-4

    def vel(t):
        s = t - T0
        return (v0 * math.sin(math.pi * s / t_h) if 0 < s < t_h else 0.0, 0.0, 0.0)

    def disp(t):
        s = min(max(t - T0, 0.0), t_h)
        return (v0 * t_h / math.pi * (1 - math.cos(math.pi * s / t_h)), 0.0, 0.0)

    sim = column(history(disp, vel), 0.0)
    times, v5, v25 = [], [], []
    steps = int((T0 + 45 * 2 * R / c) / sim.dt)
    for _ in range(steps):
        sim.step(1)
        if sim.time > T0:
            times.append(sim.time - 0.5 * sim.dt)        # leapfrog velocities are at t - dt/2
            v5.append(sim.spheres.v[5, 0])
            v25.append(sim.spheres.v[25, 0])
    zc = sim.spheres.x[:, 2]
    t = np.array(times)
    delay = _peak_time(t, np.array(v25)) - _peak_time(t, np.array(v5))
    return (zc[25] - zc[5]) / delay, c


def _peak_time(t, y):
    """Time of the maximum of y, refined by a parabola through the three samples."""
    k = int(np.argmax(y))
    a, b, c = y[k - 1], y[k], y[k + 1]
    return t[k] + 0.5 * (a - c) / (a - 2 * b + c) * (t[1] - t[0])


def sweep_peak():
    """Frequency [Hz] of the largest top/base velocity ratio under a base acceleration
    sweep 5 -> 25 Hz (linear, 0.005 g, 1.5 s, zeta_s = 0.03)."""
    f_a, f_b, dur = 5.0, 25.0, 1.5
    t = np.linspace(0.0, T0 + dur, int((T0 + dur) * 4000) + 1)
    s = np.clip(t - T0, 0.0, None)
    phase = 2 * math.pi * (f_a * s + 0.5 * (f_b - f_a) * s * s / dur)
    acc = np.where(t > T0, 0.005 * G * np.sin(phase), 0.0)
    tab = AccelerationTable(t, acc)
    sim = column(shaking(tab), 0.03)
    top, base, times = [], [], []
    every = 10
    for _ in range(int((T0 + dur) / (sim.dt * every))):
        sim.step(every)
        if sim.time > T0:
            times.append(sim.time)
            top.append(sim.spheres.v[N - 1, 0])
            base.append(tab.velocity(sim.time - 0.5 * sim.dt)[0])
    dt = times[1] - times[0]
    spec_top = np.abs(np.fft.rfft(top))
    spec_base = np.abs(np.fft.rfft(base))
    f = np.fft.rfftfreq(len(top), dt)
    band = (f > f_a + 1) & (f < f_b - 1)
    ratio = spec_top[band] / spec_base[band]
    return float(f[band][np.argmax(ratio)])


def test_column_resonates_at_vs_over_4h():
    """Vs from the pulse (expected D sqrt(ks/m), the long-wave speed of the stack, less
    its dispersion: group velocity c cos(pi D / lambda) = 0.988 c at lambda = 20 D, the
    half-sine's broader spectrum a little more; obtained 0.971 c) and the sweep's peak
    within 10 % of Vs / (4 H), H = N D the column height (obtained 12.00 Hz vs 11.52 Hz;
    the discrete stack's own f1 = sqrt(ks/m) sin(pi / (4N + 2)) / pi = 11.72 Hz)."""
    vs, c_long = pulse_speed()
    assert vs == pytest.approx(c_long, rel=0.05)
    height = 2 * R * N
    f0 = vs / (4 * height)
    f_peak = sweep_peak()
    assert f_peak == pytest.approx(f0, rel=0.10)
    print(f"Vs = {vs:.4f} m/s (long-wave {c_long:.4f}); f0 = Vs/4H = {f0:.3f} Hz; sweep peak {f_peak:.3f} Hz")
