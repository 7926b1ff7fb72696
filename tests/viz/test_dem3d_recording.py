"""A small dem3d run recorded through viz/ and read back from the .rrd (issue 7):
entity paths, number of frames, and logged values equal to the engine's."""

import numpy as np

import dem3d
from viz import paths as P
from viz import readback
from viz.recorder import Recorder, panel_normal_stress


def _small_run():
    rng = np.random.default_rng(3)
    spec = dem3d.random_specimen(rng, (0.0, 0.0, 0.0), (0.6, 0.3, 0.9), 150, 0.04, 0.06, clump_fraction=0.3)
    walls = [dem3d.Wall("wall", dem3d.segmented_wall((0.0, 0.15, 0.0), (1, 0, 0), (0, 0, 1), 0.3, 0.9, 3, 0.3,
                                                     unbounded_width=True)),
             dem3d.Wall("box", dem3d.box((0.0, 0.0, 0.0), (0.6, 0.3, 1.0), 0.5, periodic_axis=1, omit=("x-",)))]
    sim = dem3d.Simulation(spec, dem3d.linear(1e6, 4e5, 0.5, zeta_n=0.3), dt=2e-5, walls=walls,
                           periodic=dem3d.Periodic(1, 0.0, 0.3))
    return list(dem3d.run(sim, 24_000, every=4_000))     # 0.48 s: the grains land and touch


def test_dem3d_run_round_trip(tmp_path):
    frames = _small_run()
    path = tmp_path / "small.rrd"
    with Recorder(path, dim=3, every=2) as rec:
        for f in frames:
            sigma = panel_normal_stress(f)
            rec.log_frame(f, metrics={"panel_stress_kPa": sigma / 1e3, "kinetic_energy_J":
                                      0.5 * float(np.sum(np.sum(f.velocities**2, axis=1)))})
    assert len(frames) == 7                       # initial + 24000/4000
    paths = readback.entity_paths(path)
    for entity in (P.PARTICLES, P.WALL, P.FORCE_CHAINS, P.METRIC_PANEL_STRESS, P.METRIC_KE):
        assert "/" + entity in paths, entity
    t, pos = readback.read_positions(path, "/" + P.PARTICLES)
    assert list(t) == [f.step for f in frames[::2]]             # every 2nd frame logged
    assert np.allclose(pos[-1], frames[-1].positions.astype(np.float32))
    t, s = readback.read_scalars(path, "/" + P.METRIC_PANEL_STRESS)
    assert len(t) == len(frames)
    # the logged panel stresses are the engine's, in kPa
    assert np.allclose(s[-1], panel_normal_stress(frames[-1]) / 1e3)
