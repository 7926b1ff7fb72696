"""viz/: a recording written and read back from the .rrd (rerun.chunk): entity paths,
frame count and logged values must be what was logged."""

from types import SimpleNamespace

import numpy as np
import pytest

from viz import paths as P
from viz import readback
from viz.recorder import Recorder, panel_normal_stress


def _frame(k, n=40, dim=3, rng=np.random.default_rng(1)):
    return SimpleNamespace(
        step=100 * k, time=0.01 * k, positions=rng.random((n, dim)), radii=np.full(n, 0.02),
        velocities=rng.random((n, dim)), contact_a=rng.random((30, dim)), contact_b=rng.random((30, dim)),
        contact_force=np.linspace(1.0, 30.0, 30),
        panel_corners=rng.random((6, 4, 3)) if dim == 3 else rng.random((6, 2, 2)),
        panel_normal=np.tile(np.eye(dim)[0], (6, 1)), panel_force=-np.outer(np.arange(1, 7), np.eye(dim)[0]),
        panel_area=np.full(6, 0.25))


def test_panel_stress_sign():
    """Particles push the panel along -normal: F = -(1..6) N on 0.25 m^2 -> +4..24 Pa compression."""
    assert np.allclose(panel_normal_stress(_frame(0)), np.arange(1, 7) / 0.25)


@pytest.mark.parametrize("dim", [2, 3])
def test_recording_round_trip(tmp_path, dim):
    path = tmp_path / "run.rrd"
    frames = [_frame(k, dim=dim) for k in range(7)]
    with Recorder(path, dim=dim, every=2) as rec:
        rec.log_case("# case\nphi = 30")
        for k, f in enumerate(frames):
            rec.log_frame(f, wall_disp_over_H=k * 5e-4, metrics={"K": 0.2 + 0.01 * k, "resultant_height_over_H": 0.4},
                          profile=(np.linspace(0.1, 0.9, 6), np.full(6, 0.1)))
    paths = readback.entity_paths(path)
    assert {"/" + P.PARTICLES, "/" + P.WALL, "/" + P.FORCE_CHAINS, "/" + P.PROFILE_DEM, "/" + P.METRIC_K,
            "/" + P.CASE} <= paths
    # scene every 2nd call: frames 0, 2, 4, 6
    t, pos = readback.read_positions(path, "/" + P.PARTICLES, "Points3D" if dim == 3 else "Points2D")
    assert list(t) == [0, 200, 400, 600]
    assert np.allclose(pos[1], frames[2].positions.astype(np.float32))
    # metrics kept for every call, on all three timelines
    t, K = readback.read_scalars(path, "/" + P.METRIC_K)
    assert list(t) == [100 * k for k in range(7)] and np.allclose(K, 0.2 + 0.01 * np.arange(7))
    td, _ = readback.read_scalars(path, "/" + P.METRIC_K, timeline=P.TIMELINE_DISP)
    assert list(td) == [round(k * 5e-4 * 1e6) for k in range(7)]


def test_disabled_recorder_writes_nothing(tmp_path):
    rec = Recorder(tmp_path / "none.rrd", enabled=False)
    rec.log_frame(_frame(0), metrics={"K": 1.0})
    rec.close()
    assert not (tmp_path / "none.rrd").exists()
