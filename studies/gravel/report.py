"""Files of ``calibrate gravel``: CSV and figures in the run folder, and with ``--docs``
the report ``gravel_calibration.{md,json}`` with its figures in ``gravel_calibration/``."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

from studies.store import atomic_write, to_plain


def write_figures(folder, result: dict) -> list[str]:
    """biaxial.png (curves), biaxial_vs_friction.png, interface.png (angle against
    displacement), interface_vs_friction.png in the run folder; their names."""
    from viz.figures import plot_shear_test, plot_series

    names = []
    if "biaxial" in result:
        b = result["biaxial"]
        plot_shear_test({f"local {t['friction_deg']:g} deg, seed {t['seed']}":
                      (t["curve"]["eps_axial"], _smooth(t["curve"]["sigma_1"], t), _smooth(t["curve"]["sigma_3"], t),
                       t["curve"]["eps_vol"]) for t in b["tests"]}, folder.file("biaxial.png"),
                     title=f"Gravel biaxial, 35 kPa ({result.get('grain_shape', 'capsule')} AR 2.5, 10-16 mm); "
                     "stresses averaged over 1 % strain, as the peak is read")
        mus = [r["friction_deg"] for r in b["rows"]]
        t = result["targets"]
        plot_series(mus, {"peak (seed mean)": [r["phi_peak_deg"] for r in b["rows"]],
                          "critical state (seed mean)": [r["phi_cs_deg"] for r in b["rows"]],
                          f"target peak {t['phi_peak_deg']:g}": (mus, [t["phi_peak_deg"]] * len(mus)),
                          f"paper critical ~{t['phi_cs_deg']:g}": (mus, [t["phi_cs_deg"]] * len(mus))},
                    folder.file("biaxial_vs_friction.png"), xlabel="local grain friction [deg]",
                    ylabel="global friction angle [deg]", title="Biaxial at 35 kPa: global against local")
        names += ["biaxial.png", "biaxial_vs_friction.png"]
    if "interface" in result:
        i = result["interface"]
        plot_series(None, {f"local {t['interface_friction_deg']:g} deg, seed {t['seed']}":
                           ([r["displacement"] * 1e3 for r in t["readings"]], [r["angle_deg"] for r in t["readings"]])
                           for t in i["tests"]}, folder.file("interface.png"), xlabel="face displacement [mm]",
                    ylabel="atan(T / N) [deg]", title="Interface shear, 35 kPa, flat block face")
        mus = [r["interface_friction_deg"] for r in i["rows"]]
        plot_series(mus, {"global (DEM, seed mean)": [r["global_angle_deg"] for r in i["rows"]],
                          "global = local (Coulomb bound on a flat face)": (mus, mus),
                          f"target {result['targets']['interface_angle_deg']:g}":
                              (mus, [result["targets"]["interface_angle_deg"]] * len(mus))},
                    folder.file("interface_vs_friction.png"), xlabel="local fill-block friction [deg]",
                    ylabel="global interface angle [deg]", title="Interface shear: global against local")
        names += ["interface.png", "interface_vs_friction.png"]
    return names


def _smooth(y, test: dict, strain: float = 0.01):
    """Running mean of ``y`` over ``strain`` of axial strain (the window the peak is read on)."""
    import numpy as np
    eps = np.asarray(test["curve"]["eps_axial"])
    k = max(1, int(round(strain / max(float(np.median(np.diff(eps))), 1e-12))))
    return np.convolve(np.asarray(y, float), np.ones(k) / k, mode="same") if len(y) > k else np.asarray(y, float)


def write_tables(folder, result: dict) -> None:
    """biaxial.csv and interface.csv (one row per test) in the run folder."""
    if "biaxial" in result:
        keys = ["friction_deg", "seed", "phi_peak_deg", "eps_peak", "phi_cs_deg", "dilatancy_deg",
                "dilatancy_peak_deg", "porosity", "inner_porosity", "n_grains", "steps", "cpu_time_s"]
        folder.write_csv("biaxial.csv", keys, [[t[k] for k in keys] for t in result["biaxial"]["tests"]])
    if "interface" in result:
        keys = ["interface_friction_deg", "grain_friction_deg", "global_angle_deg", "normal_N_m",
                "applied_normal_N_m", "n_grains", "steps", "cpu_time_s"]
        folder.write_csv("interface.csv", keys, [[t[k] for k in keys] for t in result["interface"]["tests"]])


def _f(x, fmt=".1f") -> str:
    return "n/a" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, fmt)


#: how the report names each grain shape of ``dem2d.gravel``
SHAPE_WORDS = {"capsule": "rigid capsules", "clump3": "rigid three-circle clumps", "hexagon": "rigid rounded hexagons"}


def markdown(result: dict) -> str:
    """The report: paper's local values and ours, both series, settings."""
    p, t = result["paper_local"], result["targets"]
    grains = SHAPE_WORDS[result.get("grain_shape", "capsule")]
    b, i = result.get("biaxial"), result.get("interface")
    def ours(part, key):
        if not part:
            return "not run"
        c = part.get("choice", {})
        if "phi_cs_deg" in c:       # the biaxial choice on both targets
            return (f"{_f(part[key])} deg (there peak {c['phi_peak_deg']:.1f}, critical state {c['phi_cs_deg']:.1f} "
                    f"deg; the peak alone would give {_f(part['peak_only']['value_deg'])} deg)")
        return f"{_f(part[key])} deg" + ("" if c.get("reached", True) else
                                          f" (target not reached: closest global {c['closest_global_deg']:.1f} deg)")
    lines = ["# Case-B gravel: local frictions calibrated against the global targets", "",
             f"`{result['command']}` (git {result['git']}). S-OET tuned local values for PFC2D's soft clumps; "
             f"{grains} need their own, calibrated as S-OET did against the global targets "
             "(Colas's triaxial at 35 kPa; S-OET's interface test).", "",
             f"| value | paper's local (PFC2D) | ours ({grains}, pymunk) | global target |", "|---|---|---|---|",
             f"| grain-grain friction | {p['grain_friction_deg']:g} deg | "
             f"{ours(b, 'grain_friction_deg')} | peak {t['phi_peak_deg']:g} and critical state "
             f"{t['phi_cs_deg']:g} deg at 35 kPa |",
             f"| fill-block (interface) friction | {p['interface_friction_deg']:g} deg | "
             f"{ours(i, 'interface_friction_deg')} | {t['interface_angle_deg']:g} deg |", ""]
    if b:
        lines += ["## Biaxial at 35 kPa", "", f"At our grain friction (nearest to both targets, "
                  f"{b['choice'].get('rule', 'peak alone')}): peak {_f(b.get('phi_peak_at_chosen_deg'))} deg "
                  f"(target {t['phi_peak_deg']:g}), critical state {_f(b['phi_cs_at_chosen_deg'])} deg "
                  f"(about {t['phi_cs_deg']:g}, Colas's angle of repose).", "",
                  "| local friction | seeds | peak (sd) | critical state (sd) | dilatancy at the peak "
                  "| dilatancy, last third | porosity (specimen / inner) |",
                  "|---|---|---|---|---|---|---|"]
        lines += [f"| {r['friction_deg']:g} | {','.join(map(str, r['seeds']))} | {r['phi_peak_deg']:.1f} "
                  f"({r['phi_peak_sd_deg']:.1f}) | {r['phi_cs_deg']:.1f} ({r['phi_cs_sd_deg']:.1f}) | "
                  f"{_f(r.get('dilatancy_peak_deg'))} | {r['dilatancy_deg']:.1f} | "
                  f"{r['porosity']:.3f} / {r['inner_porosity']:.3f} |" for r in b["rows"]]
        lines += ["", "![curves](gravel_calibration/biaxial.png)", "",
                  "![global vs local](gravel_calibration/biaxial_vs_friction.png)", ""]
    if i:
        lines += ["## Interface shear (flat block face)", "",
                  f"Grains at local {i['grain_friction_deg']:.1f} deg.", "",
                  "| local fill-block friction | seeds | global angle, mean (sd) | per seed | N / applied | grains |",
                  "|---|---|---|---|---|---|"]
        for r in i["rows"]:
            ts = [x for x in i["tests"] if x["interface_friction_deg"] == r["interface_friction_deg"]]
            lines.append(f"| {r['interface_friction_deg']:g} | {','.join(map(str, r['seeds']))} | "
                         f"{r['global_angle_deg']:.2f} ({r['global_angle_sd_deg']:.2f}) | "
                         f"{', '.join(format(x['global_angle_deg'], '.2f') for x in ts)} | "
                         f"{min(x['normal_N_m'] / x['applied_normal_N_m'] for x in ts):.4f} | {ts[0]['n_grains']} |")
        lines += ["", "![readings](gravel_calibration/interface.png)", "",
                  "![global vs local](gravel_calibration/interface_vs_friction.png)", ""]
    return "\n".join(lines + result.get("discussion", []) + [""])


def slim(result: dict) -> dict:
    """The calibration's record without the biaxial curves (the run folder keeps them)."""
    out = json.loads(json.dumps(to_plain(result)))
    for t in out.get("biaxial", {}).get("tests", []):
        t.pop("curve", None)
    return out


def write_local_values(result_json: Path, out: Path) -> Path:
    """``out`` (docs/validation/gravel_local_values.json): a ``calibrate gravel`` run
    restricted to the case-B runs' local values (its run folder's result.json, with the
    mode it ran in), slimmed as the calibration's record; the dry-stone scorecard's
    backfill rows read it."""
    atomic_write(out, (json.dumps(slim(json.loads(Path(result_json).read_text())), indent=2) + "\n").encode())
    return out


def write_docs(docs: Path, result: dict, folder) -> None:
    """gravel_calibration.md / .json (curves left out) and the figures beside them; the
    hand-written ``gravel_calibration_discussion.md`` of ``docs`` is appended."""
    fig_dir = docs / "gravel_calibration"
    fig_dir.mkdir(parents=True, exist_ok=True)
    for name in result.get("figures", []):
        shutil.copy(folder.file(name), fig_dir / name)
    atomic_write(docs / "gravel_calibration.json", (json.dumps(slim(result), indent=2) + "\n").encode())
    text = markdown(result)
    discussion = docs / "gravel_calibration_discussion.md"
    if discussion.is_file():    # written by hand; the command copies it in
        text += "\n" + discussion.read_text()
    atomic_write(docs / "gravel_calibration.md", text.encode())
