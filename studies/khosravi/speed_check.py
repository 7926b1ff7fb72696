"""Does the wall speed set how soon the Khosravi backfill reaches its active state?

The paper's pressure has dropped by Dis/H 0.0002-0.0005 at 0.002 mm/s; ours at 4 mm/s
takes ~0.0014-0.0023 (khosravi.md). A slower wall gives the grains more time to follow:
if the speed were the cause, the movement to 90 % of the drop would shrink as the wall
slows. This reads the runs of one specimen at several wall speeds (their run folders'
``panels_vs_displacement.csv``) and measures, for each, the movement to 90 % of the
thrust's drop at common ends of the movement (``studies.measures.steady_displacement``:
the drop is to the mean of the last fifth of the readings, so runs are compared over the
same stretch of movement)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from ..measures import steady_displacement


def thrust_series(folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """Dis/H of each reading (the at-rest first) and the normal thrust on the wall over
    the panels below the surface, as the sum of their stresses [kPa] (the panels share
    one height, so the thrust in N/m is this times the panel height: ratios need no
    more)."""
    with open(folder / "panels_vs_displacement.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    dis = sorted({float(r["wall_disp_over_H"]) for r in rows})
    total = {d: 0.0 for d in dis}
    for r in rows:
        if float(r["depth_m"]) > 0.0:
            total[float(r["wall_disp_over_H"])] += float(r["sigma_h_kPa"])
    return np.array(dis), np.array([total[d] for d in dis])


def snapshot_series(folder: Path, case) -> tuple[np.ndarray, np.ndarray]:
    """``thrust_series`` of a run stopped before its end, from its last translation
    snapshot (``compare.CHECKPOINT``) restored with ``case`` (its KhosraviCase)."""
    import pickle

    from .compare import CHECKPOINT
    from .run import KhosraviRun
    run = KhosraviRun.restored(case, pickle.loads((folder / CHECKPOINT).read_bytes())["run"])
    z, H = run.panel_depths(), run.backfill.H
    records = [run.rest] + list(run.history)
    dis = np.array([0.0] + [r.dis / H for r in run.history])
    return dis, np.array([float(np.sum(r.sigma[z > 0])) / 1e3 for r in records])


def drop_by_end(dis: np.ndarray, thrust: np.ndarray, ends: tuple[float, ...]) -> dict:
    """At each end of ``ends`` the series reached (within one reading spacing: a reading
    is taken mid-window, so 4 mm/s reads at 0.0029 and 0.0031 around 0.003):
    the movement to 90 % of the drop over the readings up to that end, the thrust there
    (mean of the last fifth of those readings) over the at-rest one, and the readings."""
    at = {}
    for end in ends:
        keep = dis <= end * (1 + 1e-9)
        if dis[-1] < end - float(np.median(np.diff(dis))):
            continue                                # the run stopped before this end
        d, F = dis[keep], thrust[keep]
        at[f"{end:g}"] = {"wall_disp_over_H_90": steady_displacement(d, F, 0.9),
                          "thrust_end_over_at_rest": float(F[-max(1, len(F) // 5):].mean() / F[0]),
                          "readings": int(keep.sum())}
    return at


def speed_record(folder: Path, ends: tuple[float, ...]) -> dict:
    """One finished run: its wall speed, H, disks, CPU time, and ``drop_by_end``."""
    result = json.loads((folder / "result.json").read_text())
    res = result.get("result", result)
    manifest = json.loads((folder / "manifest.json").read_text())
    config = (folder / "config.toml").read_text()
    speed = next(float(line.split("=")[1]) for line in config.splitlines() if line.startswith("wall_speed"))
    dis, thrust = thrust_series(folder)
    return {"wall_speed_m_per_s": speed, "H_m": res.get("H_m"), "particles": res.get("particles"),
            "seed": res.get("seed"), "movement_end_over_H": float(dis[-1]), "by_end": drop_by_end(dis, thrust, ends),
            "cpu_time_s": manifest.get("cpu_time_s"), "wall_time_s": manifest.get("wall_time_s"),
            "git": manifest.get("git"), "run_folder": folder.name}


def wall_speed_check(folders: list[Path], ends: tuple[float, ...] = (0.005, 0.01), command: str = "",
                     stopped: list[dict] = ()) -> dict:
    """The supporting record ``khosravi_wall_speed.json``: each run of ``folders`` by
    ``speed_record``, and each of ``stopped`` (runs stopped before their end, read from
    their last snapshot: a record with ``dis`` and ``thrust`` lists, whose other keys are
    kept), slowest first."""
    runs = [speed_record(Path(f), ends) for f in folders]
    for s in stopped:
        dis, thrust = np.asarray(s["dis"], float), np.asarray(s["thrust"], float)
        runs.append({k: v for k, v in s.items() if k not in ("dis", "thrust")}
                    | {"movement_end_over_H": float(dis[-1]), "by_end": drop_by_end(dis, thrust, ends)})
    runs.sort(key=lambda r: r["wall_speed_m_per_s"])
    return {"what": "the movement to 90 % of the thrust's drop at several wall speeds, one specimen, measured to "
                    "common ends of the movement (studies.khosravi.speed_check)",
            "command": command, "ends_over_H": list(ends), "runs": runs}
