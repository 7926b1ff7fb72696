"""Summary of one full-size case-B run (issue 24): the numbers of a ``wallsim compare
drystone --wall C2S|C3S|C4L`` run folder that the issue asks of the one-hour wall, written
as JSON: critical height and mode beside the measured ones, grains, steps, pymunk steps
and body-steps per CPU second, CPU and wall time, and where the CPU went (the build of
the wall and the four phases of every stage, ``studies.drystone.backfill._PhaseClock``), with each
stage's row. Nothing is computed here that the run folder does not hold, except sums
and ratios.

    PYTHONPATH=. python benchmarks/drystone_caseb_run.py RUN_FOLDER --out docs/validation/drystone_caseb_c2s.json
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

PHASES = ("drop", "place", "settle", "read")
STAGE_KEYS = ("backfill_height_m", "thrust_N_m", "thrust_height_m", "formwork_thrust_N_m", "grains", "held",
              "crest_displacement_m", "settled", "steps") + tuple(f"cpu_{k}_s" for k in PHASES) + \
    tuple(f"steps_{k}" for k in PHASES)


def summary(folder: Path) -> dict:
    r = json.loads((folder / "result.json").read_text())
    m = json.loads((folder / "manifest.json").read_text())
    sp = r["speed"]
    cpu = r["cpu_time_s"]
    by_phase = {"build": sp["cpu_build_s"], **sp["cpu_by_phase_s"]}
    return {
        "command": m.get("command"), "git": m.get("git"), "created": m.get("created"), "versions": m.get("versions"),
        "load_average_1min": m.get("load_average_1min"), "run_folder": str(folder),
        "wall": r["wall"], "seed": r["seed"], "critical_height_m": r["critical_height_m"], "mode": r["mode"],
        "mechanism_level_m": r["mechanism_level_m"], "measured_height_m": r["measured_height_m"],
        "measured_mode": r["measured_mode"], "error_percent": r["error_percent"],
        "paper_dem_heights_m": r["paper_dem_heights_m"], "limit_equilibrium": r["limit_equilibrium"],
        "coulomb_delta_deg": r["coulomb"]["delta_deg"], "coulomb_delta_source": r["coulomb"]["delta_source"],
        "local_values": r["local_values"], "particles": r["particles"], "dt_s": r["dt_s"],
        "iterations": r["iterations"], "stages": len(r["stages"]), "steps": sp["steps"],
        "steps_per_cpu_s": sp["steps_per_cpu_s"], "body_steps_per_cpu_s": sp["body_steps_per_cpu_s"],
        "wall_time_s": r["wall_time_s"], "cpu_time_s": cpu,
        "cpu_by_phase_s": by_phase, "cpu_share_by_phase": {k: v / cpu for k, v in by_phase.items()},
        "steps_by_phase": sp["steps_by_phase"],
        "stage_rows": [{k: s.get(k) for k in STAGE_KEYS} for s in r["stages"]],
        "assumptions": r["assumptions"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--note", default="", help="a sentence on the run (machine load, anything unusual)")
    a = ap.parse_args()
    out = summary(a.folder) | ({"note": a.note} if a.note else {})
    a.out.write_text(json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
