"""The settled Khosravi box, shared by every run of the same specimen (the translation of
``compare`` and the backfilling record): its content key and the pluviation that
fills it, resumable from its own snapshots."""

from __future__ import annotations

from dem2d.sim import restore
from studies.khosravi.case import KhosraviCase
from studies.khosravi.run import KhosraviRun
from studies.runfolder import package_versions
from studies.store import Store, content_key, to_plain

#: the case fields that shape the settled specimen
SPECIMEN_FIELDS = ("H", "box_width", "box_height", "n_panels", "d50", "cu", "particles_scale", "gs",
                   "friction", "wall_friction", "floor_friction", "far_wall_friction", "seed",
                   "solver", "pluviation", "checkpoint_layers")


def specimen_key(case: KhosraviCase) -> str:
    """Hash of every case field that shapes the settled specimen (not the translation)."""
    d = {k: to_plain(getattr(case, k)) for k in SPECIMEN_FIELDS}
    d["pymunk"] = package_versions().get("pymunk")
    return content_key(d)


def settled_box(case: KhosraviCase, specimens: Store | None, key: str, bar) -> tuple[KhosraviRun, bool]:
    """The filled box: the stored specimen if ``specimens`` holds one under ``key``,
    else a pluviation that is then stored. Every ``case.checkpoint_layers`` layers the
    fill goes on from its own snapshot (kept as ``<key>.partial.pkl`` when there is a
    store), as a fill resumed from that file does: pymunk rebuilds its contact cache and
    spatial index in a fresh space, so only a run that goes through the same snapshot
    is the same run, bit for bit, with or without the interruption. Returns (run,
    whether a stored specimen was reused)."""
    stored = specimens.load_bytes(key, ".pkl") if specimens is not None else None
    if stored is not None:
        return KhosraviRun(case, sim=restore(stored)), True
    partial = specimens.load_bytes(key, ".partial.pkl") if specimens is not None else None
    task = bar.add_task("pluviation" + (" (resumed)" if partial is not None else ""), total=None, status="")
    while True:
        run = KhosraviRun(case, sim=restore(partial) if partial is not None else None)
        mark = None
        for s in run.fill():
            bar.update(task, description=f"pluviation layer {s.layer}/{s.n_layers}",
                       status=f"{s.n_grains} disks, surface {s.surface * 1e3:.0f} mm, unbalance {s.ratio:.3f}")
            if s.done and s.layer < s.n_layers and s.layer % case.checkpoint_layers == 0:
                mark = run.sim.snapshot()       # between layers: go on from it
                break
        if mark is None:
            break
        partial = mark
        if specimens is not None:
            specimens.save_bytes(key, ".partial.pkl", partial)
    blob = run.sim.snapshot()
    if specimens is not None:
        specimens.save_bytes(key, ".pkl", blob)
        specimens.discard(key, ".partial.pkl")
    # go on from the stored specimen, as a later run reusing it will: both then continue
    # bit for bit alike, and the space is rebuilt in creation order
    return KhosraviRun(case, sim=restore(blob)), False
