"""``wallsim validate wall``: does the calibrated backfill have the phi a designer asks
for, and what does the default wall give? Writes docs/validation/wall.{md,json}.

1. For phi 28, 34 and 40 deg: the micro parameters the phi card gives, then the
   triaxial test of that recipe at the card's size with another seed than the card's
   (seed 2): the achieved peak phi against the request, within 1.5 deg.
2. ``compare wall`` on the worked example (docs/examples/cantilever.toml) at the default
   size: its table, CPU time and the change the DEM's thrust makes to the checks.

Each triaxial keeps its calibration card (``<root>/nadukuru/calibration``) and is read
from there when it exists for the same size and seed, so an interrupted validation
goes on where it stopped."""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import reproducibility
from analytic.schema import check_fields, seed_param

from ..runfolder import git_revision, package_versions
from .calibrate import CardCase, _reusable, point_recipe
from .card import load_card, match_phi

#: the angles the issue asks the calibrated backfill to reach, and how closely
TARGETS_DEG = (28.0, 34.0, 40.0)
TOLERANCE_DEG = 1.5
EXAMPLE = Path("docs/examples/cantilever.toml")


@dataclass(frozen=True)
class CheckCase:
    """The validation's one setting: the seed of the check triaxials (not the card's)."""

    seed: int = seed_param(2, meaning="seed of the check triaxials (2: not the card's seed 1)")

    def __post_init__(self):
        check_fields(self)


def validate_wall(*, root: Path, out_dir: Path, seed: int = 2, example: Path = EXAMPLE, progress=None,
                  log=print) -> dict:
    """Run the phi checks and the example, write the report; returns its JSON record."""
    card = load_card()
    size = card["points"][0]["particles"]
    checks = [_phi_check(phi, card, size, seed, root, progress, log) for phi in TARGETS_DEG]
    example_result = _example_run(example, root, progress, log)
    rep = report_json(card, checks, example_result, seed)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "wall.json").write_text(json.dumps(rep, indent=2) + "\n")
    (out_dir / "wall.md").write_text(report_markdown(rep))
    return rep


def _phi_check(phi: float, card: dict, size: int, seed: int, root: Path, progress, log) -> dict:
    from ..triaxial.lab import TriaxialCase, calibrate_triaxial, card_path

    m = match_phi(phi, card)
    rec = point_recipe(size, m.particle_friction, m.rolling_friction)
    case = CardCase(particles=size, seed=seed)
    found = _reusable(card_path(root, rec, seed), case)
    if found is None:
        log(f"wall: triaxial for phi {phi:g} (friction {m.particle_friction:g}, rolling {m.rolling_friction:g}), "
            f"{size} spheres, seed {seed}")
        found, _ = calibrate_triaxial(TriaxialCase(specimen=rec, setup=case.setup, seed=seed), case.setup,
                                      particles=size, root=root, progress=progress)
    achieved = found["phi_peak_deg"]
    return {"phi_requested_deg": phi, "particle_friction": m.particle_friction,
            "rolling_friction": m.rolling_friction, "bracket": [list(b) for b in m.bracket],
            "phi_achieved_deg": achieved, "difference_deg": achieved - phi,
            "within_tolerance": abs(achieved - phi) <= TOLERANCE_DEG, "porosity": found["porosity"],
            "particles": found["particles"], "seed": seed, "wall_time_s": found["wall_time_s"]}


def _example_run(example: Path, root: Path, progress, log) -> dict:
    from .case import WallStudyCase
    from .compare import compare_wall

    log(f"wall: compare wall {example} at the default size")
    cpu = time.process_time()
    result, _ = compare_wall(WallStudyCase(design_file=str(example)), root=root, record=False, progress=progress)
    # this process's CPU over the run (every thread): the run folder's clocks start with the command
    return result | {"cpu_time_s": time.process_time() - cpu}


def report_json(card: dict, checks: list[dict], example: dict, seed: int) -> dict:
    keep = ("design_file", "wall_type", "mode", "wall_disp_over_H", "particles", "seed", "specimen_cached", "wall", "backfill", "dem",
            "theory", "design", "assumptions", "provenance", "run_folder", "wall_time_s", "cpu_time_s", "timings")
    return {"source": "issue: the calibrated backfill within 1.5 deg of the requested phi at 28, 34 and 40 deg",
            "card": {"points": card["points"], "path": card["path"], "recipe": card["recipe"]},
            "tolerance_deg": TOLERANCE_DEG, "phi_checks": checks,
            "phi_checks_within": sum(c["within_tolerance"] for c in checks),
            "example": {k: example[k] for k in keep if k in example},
            "git": git_revision(), "versions": package_versions(), "reproducibility": reproducibility.describe(),
            "check_seed": seed}


def report_markdown(rep: dict) -> str:
    """The report, from ``report_json``'s record only."""
    checks, ex = rep["phi_checks"], rep["example"]
    card_seed = rep["card"]["points"][0]["seed"]
    size = rep["card"]["points"][0]["particles"]
    lines = [
        "# Validation: the designer's wall in DEM (`compare wall`)", "",
        f"Generated by `wallsim validate wall` (git {rep['git']}).", "",
        "## The backfill reaches the requested phi", "",
        f"The phi card (`studies/wall/phi_card.json`, made by `wallsim calibrate wall`: cubical triaxial tests of "
        f"{size} spheres at 200 kPa, seed {card_seed}) maps the grain friction and rolling resistance to the peak "
        f"phi along its path ({rep['card']['path']}). For each requested angle the card's micro parameters were "
        f"tested again at the same size with seed {rep['check_seed']}: "
        f"**{rep['phi_checks_within']} of {len(checks)}** within {rep['tolerance_deg']:g} deg.", "",
        "| requested phi | grain friction | rolling | achieved peak phi | difference | within 1.5 deg |",
        "|---|---|---|---|---|---|"]
    for c in checks:
        lines.append(f"| {c['phi_requested_deg']:g} | {c['particle_friction']:g} | {c['rolling_friction']:g} | "
                     f"{c['phi_achieved_deg']:.2f} | {c['difference_deg']:+.2f} | "
                     f"{'yes' if c['within_tolerance'] else 'no'} |")
    lines += ["", "The card's points:", "", "| grain friction | rolling | peak phi | end phi | porosity |",
              "|---|---|---|---|---|"]
    for p in rep["card"]["points"]:
        lines.append(f"| {p['particle_friction']:g} | {p['rolling_friction']:g} | {p['phi_peak_deg']:.2f} | "
                     f"{p['phi_end_deg']:.2f} | {p['porosity']:.3f} |")
    if ex:
        lines += ["", *_example_lines(ex)]
    return "\n".join(lines) + "\n"


def _stages(ex: dict) -> str:
    t = ex.get("timings", {})
    if "specimen_s" not in t:
        return ""
    return (f" ({t['specimen_s']:.0f} s raining and settling the fill" + (", read from its cache" if ex.get(
        "specimen_cached") else "") + f", {t['movement_s']:.0f} s moving the wall)")


def _example_lines(ex: dict) -> list[str]:
    d, des = ex["dem"], ex["design"]
    m = des["thrust_overturning_moment_kNm_per_m"]
    cpu = ex.get("cpu_time_s")
    lines = [f"## The worked example: `wallsim compare wall {ex['design_file']}`", "",
             f"{ex['wall_type']} wall, back {ex['wall']['height_m']:g} m, surcharge {ex['wall']['surcharge_kPa']:g} "
             f"kPa, phi {ex['backfill']['phi_requested_deg']:g} deg; movement {ex['mode']} to Delta/H "
             f"{ex['wall_disp_over_H']:g}; {ex['particles']} spheres, seed {ex['seed']}; "
             f"{ex['wall_time_s']:.0f} s wall" + (f", {cpu:.0f} s CPU" if cpu is not None else "")
             + _stages(ex) + ".", "",
             "| | thrust kN/m | K | h/H |", "|---|---|---|---|",
             f"| wallsim DEM (active) | {d['thrust_kN_per_m']:.1f} | {d['K']:.3f} | {d['resultant_height_over_H']:.3f} |"]
    for t in (t for t in ex["theory"] if t["K"] is not None):
        lines.append(f"| {t['name']} | {t['thrust_kN_per_m']:.1f} | {t['K']:.3f} | {t['resultant_height_over_H']:.3f} |")
    lines += ["", f"Design checks ({des['format']}), utilisation classical -> with the DEM's thrust:", "",
              "| check | classical | DEM-informed |", "|---|---|---|"]
    for name, c in des["checks"].items():
        lines.append(f"| {name} | {c['classical']['utilisation']:.3f} | {c['dem']['utilisation']:.3f} |")
    lines += ["", f"Overturning moment of the thrust about the toe: {m['classical']:.1f} -> {m['dem']:.1f} kNm/m "
                  f"({100 * m['change']:+.0f} %).", "", "Assumptions: " + "; ".join(ex["assumptions"]) + "."]
    return lines

