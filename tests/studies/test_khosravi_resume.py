"""Issue 38: a Khosravi run interrupted in its fill or in its translation, and run again
(the fill from the stored partial specimen, the translation with --resume), ends as the
uninterrupted run, bit for bit. A box smaller than the pinned run's (H 0.1 m, grains 8 x
the paper's: 298 disks, a snapshot after layer 3, 3 readings of the translation; ~3 s of
CPU a run on the 2-vCPU VM)."""

import json
from dataclasses import replace

import pytest

from studies.khosravi.case import KhosraviCase
from studies.khosravi.compare import CHECKPOINT, compare_khosravi
from studies.khosravi.run import KhosraviRun

#: a snapshot after layer 3 of 5 and after every reading of the translation
CASE = KhosraviCase(H=0.1, particles_scale=8, wall_disp_over_H_max=0.001, checkpoint_layers=3,
                    checkpoint_readings=1)
#: result keys that are times, paths or resources (they differ between any two runs)
NOT_PHYSICS = ("timings_s", "specimen", "specimen_reused", "run_folder", "resources", "scale_note")


def _physics(result: dict) -> dict:
    return {k: v for k, v in json.loads(json.dumps(result)).items() if k not in NOT_PHYSICS}


def _interrupt_at(monkeypatch, calls: int, stage: str) -> None:
    """Ctrl-C at the ``calls``-th wall reading of ``stage`` ("fill": the readings taken
    after each layer, 0.2 windows long; "translation": the full windows, the at-rest
    reading first)."""
    seen = {"n": 0}
    original = KhosraviRun.reading

    def reading(self, window=None):
        is_fill = window is not None
        if is_fill == (stage == "fill"):
            seen["n"] += 1
            if seen["n"] == calls:
                raise KeyboardInterrupt
        return original(self, window)

    monkeypatch.setattr(KhosraviRun, "reading", reading)


@pytest.fixture(scope="module")
def straight(tmp_path_factory):
    result, _ = compare_khosravi(CASE, root=tmp_path_factory.mktemp("straight"), quiet=True)
    return _physics(result)


@pytest.mark.slow
def test_a_fill_interrupted_after_its_snapshot_ends_as_the_straight_run(straight, tmp_path, monkeypatch):
    """Interrupted at the reading of layer 4 (after the snapshot taken at layer 3), the
    same command again goes on from the stored partial specimen: same numbers."""
    with monkeypatch.context() as m:
        _interrupt_at(m, 4, "fill")
        with pytest.raises(KeyboardInterrupt):
            compare_khosravi(CASE, root=tmp_path, quiet=True)
    assert list((tmp_path / "khosravi" / "_specimens").glob("*.partial.pkl"))
    again, _ = compare_khosravi(CASE, root=tmp_path, quiet=True)
    assert _physics(again) == straight


@pytest.mark.slow
def test_a_translation_resumed_from_its_run_folder_ends_as_the_straight_run(straight, tmp_path, monkeypatch):
    """Interrupted in the second reading of the translation (after the snapshot of the
    first; the at-rest reading is the first full window), ``resume`` with the run folder continues from checkpoints/translation.pkl:
    same readings, same figures, and the checkpoint is gone once the run has its result."""
    with monkeypatch.context() as m:
        _interrupt_at(m, 3, "translation")
        with pytest.raises(KeyboardInterrupt):
            compare_khosravi(CASE, root=tmp_path, quiet=True, name="interrupted")
    folder = tmp_path / "khosravi" / "interrupted"
    assert (folder / CHECKPOINT).is_file()
    resumed, rf = compare_khosravi(CASE, root=tmp_path, quiet=True, resume=folder)
    assert rf.path == folder
    assert _physics(resumed) == straight
    assert not (folder / CHECKPOINT).exists()


def test_snapshot_cadence_is_part_of_the_specimen_key():
    """Two fills that go through different snapshots are different specimens, so one
    never reuses the other's."""
    from studies.khosravi.specimen import specimen_key
    assert specimen_key(CASE) != specimen_key(replace(CASE, checkpoint_layers=2))
    assert specimen_key(CASE) == specimen_key(replace(CASE, checkpoint_readings=5))
