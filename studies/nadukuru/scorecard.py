"""Nadukuru & Michalowski's statements scored against a validation report
(``docs/validation/nadukuru.json``): the rows of the report's scorecard
(``studies.scorecard``). The statements, their place in the paper, values and
tolerances are in reference.json (``statements``); here only how ours is read."""

from __future__ import annotations

import math
from functools import lru_cache

from analytic.classical import coulomb_coefficient
from analytic.slices import mode_case, solve

from ..config import with_current_names
from ..measures import profile_nonlinearity
from ..scorecard import Row, number_verdict, trend_verdict

WALLS = ("rough", "smooth")


def scorecard_rows(rep: dict, ref: dict, supporting: dict | None = None) -> list[Row]:
    """Every statement of ``ref['statements']`` scored on the report ``rep``;
    ``supporting``: the report's supporting JSON files by name (a statement of kind
    ``spread`` reads its runs there)."""
    rep = with_current_names(rep) | {"_supporting": with_current_names(supporting or {})}
    return [_ROWS[s["kind"]](s, rep, ref) for s in ref["statements"]]


def _table_value(s: dict, rep: dict, ref: dict) -> Row:
    """A value of Tables 1-2: K or h/H of one wall and mode."""
    wall, mode, key = s["wall"], s["mode"], s["key"]
    row = rep["walls"].get(wall, {}).get("modes", {}).get(mode)
    ours = None if row is None else row[key]
    paper = ref[wall][mode][key]
    tol = ref["targets"]["K_abs_tol" if key == "K" else "resultant_height_over_H_abs_tol"]
    return Row(s["statement"], s["where"], f"{paper:g}", "" if ours is None else f"{ours:.3f}", f"+-{tol:g}",
               number_verdict(ours, paper, tol), s.get("agreement", "independent"), s.get("note", ""))


def _specimen_value(s: dict, rep: dict, ref: dict) -> Row:
    """An at-rest figure of the specimen, on each wall (the worse of the two decides)."""
    key, paper, tol = s["key"], s["paper"], s["tolerance"]
    values = {w: rep["walls"][w]["specimen"][key] for w in WALLS if w in rep["walls"]}
    worst = max(values.values(), key=lambda v: abs(v - paper)) if values else None
    ours = ", ".join(f"{w} {v:.3f}" for w, v in values.items())
    return Row(s["statement"], s["where"], f"{paper:g}", ours, f"+-{tol:g}", number_verdict(worst, paper, tol),
               s.get("agreement", "independent"), s.get("note", ""))


def _triaxial(s: dict, rep: dict, ref: dict) -> Row:
    tri = rep.get("triaxial")
    ours = None if tri is None else tri["phi_peak_deg"]
    paper, tol = s["paper"], s["tolerance"]
    return Row(s["statement"], s["where"], f"{paper:g} deg", "" if ours is None else f"{ours:.1f} deg",
               f"+-{tol:g} deg", number_verdict(ours, paper, tol), s.get("agreement", "independent"),
               s.get("note", ""))


def _ordering(s: dict, rep: dict, ref: dict) -> Row:
    """A stated order of one quantity over modes, on the walls named: ``order`` lists
    the modes from lowest to highest (``lowest`` / ``highest``: only that end counts)."""
    holds, shown = [], []
    for wall in s["walls"]:
        modes = rep["walls"].get(wall, {}).get("modes", {})
        vals = {m: modes[m][s["key"]] for m in s["modes"] if m in modes}
        if len(vals) < len(s["modes"]):
            holds.append(None)
            continue
        shown.append(f"{wall}: " + ", ".join(f"{m} {v:.3f}" for m, v in vals.items()))
        if s["order"] == "lowest":
            holds.append(min(vals, key=vals.get) == s["modes"][0])
        elif s["order"] == "highest":
            holds.append(max(vals, key=vals.get) == s["modes"][0])
        else:
            holds.append(all(vals[a] < vals[b] for a, b in zip(s["modes"], s["modes"][1:])))
    verdict = trend_verdict(None if None in holds or not holds else all(holds))
    return Row(s["statement"], s["where"], s["paper"], "; ".join(shown), s.get("tolerance", "the order"), verdict,
               s.get("agreement", "independent"), s.get("note", ""))


def _close(s: dict, rep: dict, ref: dict) -> Row:
    """Two modes' values within ``tolerance`` of each other on one wall."""
    modes = rep["walls"].get(s["wall"], {}).get("modes", {})
    a, b = (modes.get(m, {}).get(s["key"]) for m in s["modes"])
    holds = None if a is None or b is None else abs(a - b) <= s["tolerance"]
    ours = "" if holds is None else f"{s['modes'][0]} {a:.3f}, {s['modes'][1]} {b:.3f}"
    return Row(s["statement"], s["where"], s["paper"], ours, f"within {s['tolerance']:g}", trend_verdict(holds),
               s.get("agreement", "independent"), s.get("note", ""))


def _steady(s: dict, rep: dict, ref: dict) -> Row:
    """Delta/H by which the load is steady, against the paper's value (a factor of
    ``tolerance`` either way: the paper says 'approximately' of a curve read by eye), or
    'not yet at 0.008' (``paper`` None: ours must not be steady before 0.008)."""
    wall = s["wall"]
    modes = rep["walls"].get(wall, {}).get("modes", {})
    got = {m: modes[m]["wall_disp_over_H_steady"] for m in s["modes"] if m in modes}
    if len(got) < len(s["modes"]):
        return Row(s["statement"], s["where"], s["paper_text"], "", "", "not reproduced",
                   s.get("agreement", "independent"), s.get("note", ""))
    ours = ", ".join(f"{m} {v:.4f}" for m, v in got.items())
    if s.get("paper") is None:
        holds = all(v >= s["limit"] for v in got.values())
        tol = f"not steady before {s['limit']:g}"
    else:
        f = s["tolerance"]
        holds = all(s["paper"] / f <= v <= s["paper"] * f for v in got.values())
        tol = f"{s['paper'] / f:.4g}-{s['paper'] * f:.4g}"
    return Row(s["statement"], s["where"], s["paper_text"], ours, tol, trend_verdict(holds),
               s.get("agreement", "independent"), s.get("note", ""))


def _steady_before(s: dict, rep: dict, ref: dict) -> Row:
    """On one wall, the first modes of ``modes`` reach their steady load before the last."""
    modes = rep["walls"].get(s["wall"], {}).get("modes", {})
    got = {m: modes[m]["wall_disp_over_H_steady"] for m in s["modes"] if m in modes}
    if len(got) < len(s["modes"]):
        return _not_run(s, rep, ref)
    *first, last = s["modes"]
    holds = all(got[m] < got[last] for m in first)
    return Row(s["statement"], s["where"], s["paper_text"], ", ".join(f"{m} {v:.4f}" for m, v in got.items()),
               "the order", trend_verdict(holds), s.get("agreement", "independent"), s.get("note", ""))


def _rough_below_smooth(s: dict, rep: dict, ref: dict) -> Row:
    """For each mode of ``modes``, the rough wall's K below the smooth wall's."""
    r, sm = (rep["walls"].get(w, {}).get("modes", {}) for w in WALLS)
    pairs = {m: (r[m]["K"], sm[m]["K"]) for m in s["modes"] if m in r and m in sm}
    if len(pairs) < len(s["modes"]):
        return _not_run(s, rep, ref)
    holds = all(a < b for a, b in pairs.values())
    ours = "; ".join(f"{m} {a:.3f} < {b:.3f}" if a < b else f"{m} {a:.3f} >= {b:.3f}" for m, (a, b) in pairs.items())
    return Row(s["statement"], s["where"], s["paper_text"], ours, "the order", trend_verdict(holds),
               s.get("agreement", "independent"), s.get("note", ""))


def _spread(s: dict, rep: dict, ref: dict) -> Row:
    """A quantity that should not depend on a setting: its values over runs of a
    supporting file (``file``, ``runs``) spread by at most ``tolerance``."""
    data = rep["_supporting"].get(s["file"])
    if data is None:
        return _not_run(s, rep, ref)
    runs = data["runs"]
    vals = [runs[name][s["key"]] if name in runs else data["baseline"][s["mode"]][s["key"]] for name in s["runs"]]
    spread = max(vals) - min(vals)
    ours = " -> ".join(f"{v:.3f}" for v in vals) + f" (spread {spread:.3f})"
    return Row(s["statement"], s["where"], s["paper_text"], ours, f"spread <= {s['tolerance']:g}",
               trend_verdict(spread <= s["tolerance"] + 1e-12), s.get("agreement", "independent"),
               s.get("note", ""))


def _parallel_fields(s: dict, rep: dict, ref: dict) -> Row:
    """On each wall, the displacement fields of the ``parallel`` modes more nearly
    parallel than that of the ``curved`` mode: their mean resultant length R
    (``studies.measures.displacement_parallelism``) above its R. Read on the report's
    own runs; while they have no fields, on every seed of the reduced-size check
    (supporting ``file``), and the row says so."""
    modes = [*s["parallel"], s["curved"]]
    own = {w: {m: r["displacement_field"] for m, r in rep["walls"].get(w, {}).get("modes", {}).items()
               if "displacement_field" in r and m in modes} for w in s["walls"]}
    if all(len(f) == len(modes) for f in own.values()):
        shown = [f"{w}: R " + ", ".join(f"{m} {f[m]['resultant_length']:.3f}" for m in modes)
                 + " (spread " + ", ".join(f"{f[m]['spread_deg']:.0f}" for m in modes) + " deg)"
                 for w, f in own.items()]
        return Row(s["statement"], s["where"], s["paper_text"], "; ".join(shown), s["tolerance"],
                   trend_verdict(all(_more_parallel(f, s) for f in own.values())),
                   s.get("agreement", "independent"), s.get("note", ""))
    data = rep["_supporting"].get(s["file"])
    if data is None:
        return _not_run(s, rep, ref)
    fields = [(w, f) for runs in data["runs"].values() for w, f in runs.items() if w in s["walls"]]
    held = sum(_more_parallel(f, s) for _, f in fields)
    spreads = "; ".join(f"{w} " + ", ".join(
        f"{m} {min(f[m]['spread_deg'] for ww, f in fields if ww == w):.0f}-"
        f"{max(f[m]['spread_deg'] for ww, f in fields if ww == w):.0f}" for m in modes) for w in s["walls"])
    ours = (f"reduced size ({min(data['particles']):,}-{max(data['particles']):,} spheres), seeds "
            f"{', '.join(data['runs'])}: spread of the directions {spreads} deg; the order holds in {held} of "
            f"{len(fields)} specimens (paper scale: not run)")
    return Row(s["statement"], s["where"], s["paper_text"], ours, s["tolerance"],
               trend_verdict(held == len(fields)), s.get("agreement", "independent"), s.get("note", ""))


def _more_parallel(fields: dict, s: dict) -> bool:
    """The ``parallel`` modes' R above the ``curved`` mode's (one wall, one specimen)."""
    return all(fields[m]["resultant_length"] > fields[s["curved"]]["resultant_length"] for m in s["parallel"])


def _peak_height(s: dict, rep: dict, ref: dict) -> Row:
    """Where a mode's wall stress peaks: the centre of the segment with the largest
    active stress (segments listed from the base up), as a fraction of H, on every run
    named of a supporting file; within one segment of the paper's height."""
    data = rep["_supporting"].get(s["file"])
    if data is None or any(name not in data["runs"] for name in s["runs"]):
        return _not_run(s, rep, ref)
    heights = []
    for name in s["runs"]:
        seg = data["runs"][name]["segment_stress_over_rho_g_1mn_H"]
        heights.append((max(range(len(seg)), key=seg.__getitem__) + 0.5) / len(seg))
    step = 1.0 / len(data["runs"][s["runs"][0]]["segment_stress_over_rho_g_1mn_H"])
    holds = all(abs(h - s["paper"]) <= step + 1e-12 for h in heights)
    ours = f"largest segment stress at {', '.join(f'{h:.2f}' for h in heights)} H ({len(heights)} runs)"
    return Row(s["statement"], s["where"], s["paper_text"], ours, s["tolerance"], trend_verdict(holds),
               s.get("agreement", "independent"), s.get("note", ""))


def _coulomb(s: dict, rep: dict, ref: dict) -> Row:
    """Table 2's classical Coulomb K (smooth vertical wall, level backfill) against our
    closed form (``analytic.classical.coulomb_coefficient``) at the paper's phi."""
    ours = coulomb_coefficient(math.radians(s["phi_deg"]), 0.0, 0.0, 0.0)
    return Row(s["statement"], s["where"], f"{s['paper']:g}", f"{ours:.4f}", f"+-{s['tolerance']:g}",
               number_verdict(ours, s["paper"], s["tolerance"]), s.get("agreement", "independent"), s.get("note", ""))


def _dsm(s: dict, rep: dict, ref: dict) -> Row:
    """A value of Table 3's differential slice method against ours
    (``analytic.slices``: the mode's phi, k_l, phi* and slip surface of the paper's
    Appendix, delta 24.7 deg)."""
    res = _dsm_result(s["mode"])
    ours = res.K if s["key"] == "K" else res.resultant_height_over_H
    tol = ref["targets"]["dsm_K_abs_tol" if s["key"] == "K" else "dsm_resultant_height_over_H_abs_tol"]
    return Row(s["statement"], s["where"], f"{s['paper']:g}", f"{ours:.3f}", f"+-{tol:g}",
               number_verdict(ours, s["paper"], tol), s.get("agreement", "independent"), s.get("note", ""))


@lru_cache(maxsize=None)
def _dsm_result(mode: str):
    """Our DSM solution of a mode of Table 3 (the same for every report: solved once)."""
    return solve(mode_case(mode))


def _physical_test(s: dict, rep: dict, ref: dict) -> Row:
    """Our rough-wall DEM against Fang & Ishibashi's physical test as Table 1 gives it
    (interpolated to phi 39 deg), at the table's tolerances; within the paper's scatter
    when ours lies between the paper's own DEM value and the test's (the spread the
    paper shows for that quantity)."""
    mode, key = s["mode"], s["key"]
    row = rep["walls"].get("rough", {}).get("modes", {}).get(mode)
    ours = None if row is None else row[key]
    test, dem = ref["rough"][mode][f"FI_{key}"], ref["rough"][mode][key]
    tol = ref["targets"]["K_abs_tol" if key == "K" else "resultant_height_over_H_abs_tol"]
    return Row(s["statement"], s["where"], f"{test:g} (the paper's DEM {dem:g})", "" if ours is None else f"{ours:.3f}",
               f"+-{tol:g}", number_verdict(ours, test, tol, scatter=(min(test, dem), max(test, dem))),
               s.get("agreement", "independent"), s.get("note", ""))


def _centroids(s: dict, rep: dict, ref: dict) -> Row:
    """The abstract's resultant heights, on each wall: each mode of ``near`` within
    ``tolerance`` of its value, and each mode of ``below`` under its bound."""
    shown, holds = [], []
    for wall in s["walls"]:
        modes = rep["walls"].get(wall, {}).get("modes", {})
        if any(m not in modes for m in [*s["near"], *s["below"]]):
            return _not_run(s, rep, ref)
        h = {m: modes[m]["resultant_height_over_H"] for m in [*s["near"], *s["below"]]}
        holds += [abs(h[m] - v) <= s["tolerance"] + 1e-12 for m, v in s["near"].items()]
        holds += [h[m] < v for m, v in s["below"].items()]
        shown.append(f"{wall}: " + ", ".join(f"{m} {v:.3f}" for m, v in h.items()))
    tol = f"+-{s['tolerance']:g} of " + ", ".join(f"{m} {v:g}" for m, v in s["near"].items()) + "; " + \
        ", ".join(f"{m} below {v:.3f}" for m, v in s["below"].items())
    return Row(s["statement"], s["where"], s["paper_text"], "; ".join(shown), tol, trend_verdict(all(holds)),
               s.get("agreement", "independent"), s.get("note", ""))


def _design_floor(s: dict, rep: dict, ref: dict) -> Row:
    """The paper's design advice, a lowest height for the resultant per kind of wall
    (``floors``: the mode it is drawn from -> the advised height): it agrees with ours
    when none of our resultants of those modes lies below its floor by more than
    ``tolerance`` (the paper's own resultants, T 0.39 / 0.40 and RT 0.55 / 0.54, meet
    it so). How far our resultants stand above the floors is shown: a designer taking
    the floor itself places the load that much too low."""
    shown, holds = [], []
    for wall in s["walls"]:
        modes = rep["walls"].get(wall, {}).get("modes", {})
        if any(m not in modes for m in s["floors"]):
            return _not_run(s, rep, ref)
        h = {m: modes[m]["resultant_height_over_H"] for m in s["floors"]}
        holds += [h[m] >= f - s["tolerance"] - 1e-12 for m, f in s["floors"].items()]
        shown.append(f"{wall}: " + ", ".join(f"{m} {v:.3f} ({v - s['floors'][m]:+.3f} H)" for m, v in h.items()))
    tol = ", ".join(f"{m} at least {f:g} - {s['tolerance']:g}" for m, f in s["floors"].items())
    return Row(s["statement"], s["where"], s["paper_text"], "; ".join(shown), tol, trend_verdict(all(holds)),
               s.get("agreement", "independent"), s.get("note", ""))


def _linearity(s: dict, rep: dict, ref: dict) -> Row:
    """The at-rest profile near linear and the active profiles of ``nonlinear`` modes
    distinctly not (``studies.measures.profile_nonlinearity``: rms residual of the best
    line over the mean stress, at most ``linear_below`` at rest, at least
    ``nonlinear_above`` active). Read on the report's own runs (``figure_data``: the
    first reading of the first mode is the at-rest state); while they have none, on
    the runs of a supporting ``file`` (reduced size), and the row says so."""
    tol = f"at rest <= {s['linear_below']:g}; active >= {s['nonlinear_above']:g}"
    walls = {w: rep["walls"][w]["modes"] for w in s["walls"] if w in rep["walls"]}
    source = ""
    if not walls or not all("first_segment_stress_over_gamma_H" in modes.get(m, {}).get("figure_data", {})
                            for modes in walls.values() for m in s["nonlinear"]):
        data = rep["_supporting"].get(s["file"])
        if data is None:
            return _not_run(s, rep, ref)
        walls = {f"{w} seed {seed}": entry["modes"] for seed, run in data["runs"].items()
                 for w, entry in run.items() if w in s["walls"]}
        source = f" (reduced size, {min(data['particles']):,}-{max(data['particles']):,} spheres; paper scale: not run)"
    note = s.get("note", "") + ("" if not source else
                                ". At reduced size a segment is about four grains tall (grains x2.28), so a "
                                "profile's own scatter enters the measure; a paper-scale validation keeps its "
                                "profiles (figure_data) and the row then reads those")
    shown, holds = [], []
    for name, modes in walls.items():
        rest = profile_nonlinearity(modes[s["nonlinear"][0]]["figure_data"]["first_segment_stress_over_gamma_H"])
        active = {m: profile_nonlinearity(modes[m]["figure_data"]["segment_stress_over_gamma_H"])
                  for m in s["nonlinear"]}
        holds.append(rest <= s["linear_below"] and all(v >= s["nonlinear_above"] for v in active.values()))
        shown.append(f"{name}: at rest {rest:.2f}, " + ", ".join(f"{m} {v:.2f}" for m, v in active.items()))
    return Row(s["statement"], s["where"], s["paper_text"], "; ".join(shown) + source, tol,
               trend_verdict(all(holds)), s.get("agreement", "independent"), note)


def _not_run(s: dict, rep: dict, ref: dict) -> Row:
    """A statement no run of the report tests."""
    tol = s.get("tolerance", "")
    return Row(s["statement"], s["where"], s["paper_text"], "", tol if isinstance(tol, str) else f"{tol:g}",
               "not reproduced", s.get("agreement", "independent"), s.get("note", ""))


_ROWS = {"table": _table_value, "specimen": _specimen_value, "triaxial": _triaxial, "order": _ordering,
         "close": _close, "steady": _steady, "steady_before": _steady_before, "rough_below_smooth": _rough_below_smooth,
         "spread": _spread, "parallel_fields": _parallel_fields, "peak_height": _peak_height,
         "coulomb": _coulomb, "dsm": _dsm, "physical_test": _physical_test, "centroids": _centroids,
         "design_floor": _design_floor, "linearity": _linearity, "not_run": _not_run}
