"""Issue 38: a case-B wall interrupted between stages and resumed from its run folder
ends as the uninterrupted run, bit for bit; and the snapshot a straight run goes on
from after every stage changes nothing (the rebuilt space keeps every shape's id, so
Chipmunk matches each contact point and warm-starts it as before). Reduced size of the
pinned run (test_pinned.py's drystone_b: a 0.48 m wall on a 0.16 m base, ~5 s a run)."""

import json

import numpy as np
import pytest

from studies import get
from studies.drystone.run_b import CHECKPOINT, compare_backfill

NARROW = ["height_m=0.48", "base_width_m=0.16", "block_length_m=0.15", "block_height_m=0.06",
          "backfill.width_min_m=0.02", "backfill.width_max_m=0.032", "backfill.container_m=0.6",
          "backfill.formwork_m=0.4", "backfill.hold_depth_m=none"]
#: result keys that are times, paths or resources (they differ between any two runs)
NOT_PHYSICS = ("wall_time_s", "cpu_time_s", "speed", "run_folder", "recording", "resources", "scale_note")


def _physics(result: dict) -> dict:
    out = {k: v for k, v in json.loads(json.dumps(result)).items() if k not in NOT_PHYSICS}
    out["stages"] = [{k: v for k, v in r.items() if not k.startswith("cpu_")} for r in out["stages"]]
    return out


@pytest.fixture(scope="module")
def case():
    return get("drystone").commands[0].resolve(flags={"wall": "C2S"}, sets=NARROW)


@pytest.mark.slow
def test_a_resumed_wall_is_the_straight_one_bit_for_bit(case, tmp_path, monkeypatch):
    """Ctrl-C in the third stage (after the snapshots of the first two), then ``resume``
    with the run folder: the same stages, critical height, mode and mechanism level."""
    straight, _ = compare_backfill(case, root=tmp_path / "straight", record=False)
    assert len(straight["stages"]) >= 3

    from studies.drystone.backfill import BackfilledWall
    original, calls = BackfilledWall.stage, {"n": 0}

    def stage(self, on_reading=None):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt
        return original(self, on_reading)

    with monkeypatch.context() as m:
        m.setattr(BackfilledWall, "stage", stage)
        with pytest.raises(KeyboardInterrupt):
            compare_backfill(case, root=tmp_path / "cut", record=False)
    [folder] = (tmp_path / "cut" / "drystone").iterdir()
    assert (folder / CHECKPOINT).is_file()
    resumed, path = compare_backfill(case, root=tmp_path / "cut", record=False, resume=folder)
    assert path == folder and not (folder / CHECKPOINT).exists()
    assert _physics(resumed) == _physics(straight)


@pytest.mark.slow
def test_a_restored_fill_steps_as_the_original(case):
    """Two stages, a snapshot, and 2000 more steps of the original and of the restored
    copy: every grain and block in the same place, bit for bit (what keeps the pinned
    numbers of runs from before the snapshots)."""
    from studies.drystone.backfill import BackfilledWall
    from dem2d.blocks import BlockSolver, LoadingPlan
    from studies.drystone.case import masonry

    bf = case.backfill
    bw = BackfilledWall.build(case.section(), masonry(case), bf.gravel(), bf.plan(),
                              BlockSolver(dt=case.dt, iterations=bf.iterations), LoadingPlan(), seed=bf.seed)
    bw.stage()
    bw.stage()
    copy = BackfilledWall.restored(bw.snapshot())
    bw.wall.advance(2000 * case.dt)
    copy.wall.advance(2000 * case.dt)
    assert np.array_equal(bw.positions(), copy.positions())
    assert np.array_equal(bw.wall.positions(), copy.wall.positions())
