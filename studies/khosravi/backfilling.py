"""Khosravi et al. Fig. 9, the wall during backfilling, from a free fill.

The study's fill (``case.HELD_LAYERS``) holds grains deeper than ``hold_depth`` below the
surface static while the next layers fall: about 3.8 times cheaper, and the settled
specimen is the same kind of deposit. But the wall cells beside held grains then see only
the free strip along the wall, so they are not read (NaN), and Fig. 9 would show the top
2 cm of each layer only. This stage fills the same box (same seed, grading, layers and
solver) with nothing held and reads the wall after every layer: every cell below the
surface is read. Its specimen is stored under its own key, so an interrupted fill resumes
from its last checkpoint and a second run reuses it.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np

from studies.progress import progress
from studies.runner import Stopwatch, finish, open_run_folder
from studies.runfolder import RunFolder
from studies.store import Store, content_key
from .case import KhosraviCase
from .specimen import settled_box, specimen_key


def free_fill_case(case: KhosraviCase) -> KhosraviCase:
    """``case`` with no grain held while the layers fall (``pluviation.hold_depth`` = 0)."""
    return dataclasses.replace(case, pluviation=dataclasses.replace(case.pluviation, hold_depth=0.0))


def unread_cells(layer_readings: list, panel_height: float) -> int:
    """Number of (layer, cell) readings that are NaN although the cell lies wholly below
    that layer's surface: zero for a free fill."""
    return sum(int(np.isnan(np.asarray(sig, float)[: int(surf / panel_height)]).sum())
               for _, surf, sig in layer_readings)


def write_backfilling(rf: RunFolder, layer_readings: list, panel_height: float, *, gamma: float, H: float,
                      n_grains: int) -> None:
    """backfilling.csv (one row per layer and cell, height above the base) and Fig. 9."""
    from .figures import plot_khosravi_backfilling

    rf.write_csv("backfilling.csv", ["layer", "surface_m", "panel", "panel_centre_height_m", "sigma_h_kPa"],
                 [[layer, surf, i, (i + 0.5) * panel_height, s / 1e3]
                  for layer, surf, sig in layer_readings for i, s in enumerate(sig)])
    if layer_readings:
        plot_khosravi_backfilling(layer_readings, rf.file("fig09_backfilling.png"), gamma=gamma, H=H,
                                  panel_height=panel_height,
                                  title=f"During backfilling, {n_grains} disks (Khosravi Fig. 9)")


def backfilling_name(case: KhosraviCase) -> str:
    """The free fill's run folder name: ``backfilling-<content key of the free-fill case>``,
    so fills of other cases (seeds run side by side on Dask) never share a folder."""
    return f"backfilling-{content_key(free_fill_case(case))}"


def run_backfilling(case: KhosraviCase, *, root: str | Path = "runs", quiet: bool = False,
                    specimen_cache: bool = True) -> tuple[dict, RunFolder]:
    """Fill ``case``'s box with nothing held, reading the wall after every layer; write
    backfilling.csv, fig09_backfilling.png and result.json in the run folder
    ``backfilling_name(case)``. Returns (result, run folder)."""
    free = free_fill_case(case)
    clock, c_start = Stopwatch(), time.process_time()
    rf = open_run_folder("khosravi", free, root, name=backfilling_name(case))
    specimens = Store(Path(root) / "khosravi" / "_specimens") if specimen_cache else None
    with progress(quiet) as bar, clock("pluviation_s"):
        run, reused = settled_box(free, specimens, specimen_key(free), bar)
    bf = run.backfill
    unread = unread_cells(bf.layer_readings, case.panel_height)
    write_backfilling(rf, bf.layer_readings, case.panel_height, gamma=bf.gamma, H=bf.H, n_grains=bf.n_grains)
    result = {"particles": bf.n_grains, "seed": case.seed, "H_m": bf.H, "gamma_N_per_m3": bf.gamma,
              "porosity": bf.porosity, "layers": len(bf.layer_readings), "hold_depth_m": 0.0,
              "replaces_hold_depth_m": case.pluviation.hold_depth,
              "layer_dt_s": case.pluviation.layer_dt, "run_dt_s": case.solver.dt, "sweeps": case.solver.iterations,
              "unread_cells_below_surface": unread, "specimen_reused": reused,
              "timings_s": {**clock.seconds, "cpu_total": time.process_time() - c_start}}
    finish(rf, result, main=False, n_grains=bf.n_grains, dt=case.solver.dt, iterations=case.solver.iterations,
           friction=case.friction, wall_friction=case.material.wall_friction, specimen_reused=reused,
           **result["timings_s"])
    return result, rf
