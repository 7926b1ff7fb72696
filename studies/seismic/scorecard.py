"""Sizkow & El Shamy's statements scored against the validation report
(``docs/validation/seismic.json``, with the material checks of
``seismic_material.json``): the soil's stated properties, the trends the paper states
at every frequency and across the frequencies, and its passive-mobilisation statement
(Fig. 4); the rows of the report's scorecard (``studies.scorecard``)."""

from __future__ import annotations

from ..scorecard import Row, number_verdict, trend_verdict

TUNED_PHI = "partly by construction: the rolling resistance mu_r 0.25 was calibrated to this angle"


def scorecard_rows(rep: dict, ref: dict, material: dict | None) -> list[Row]:
    significant = ref["targets"]["significant_ratio"]
    return _material_rows(ref, material) + _trend_rows(rep) + _across_rows(rep) + [
        _full_passive_row(rep, ref), _residual_passive_row(rep, significant), _similar_at_4_to_6_row(rep, significant)
    ] + [Row(statement, where, paper, "", "", "not reproduced", note=note) for statement, where, paper, note in UNMEASURED]


#: statements the runs draw but do not measure: (statement, where, the paper, why)
UNMEASURED = (
    ("the failure wedges resemble Coulomb-like planar failure surfaces", "Fig. 7, text (5 Hz)",
     "planar wedges", "the maximum shear strain is drawn at the paper's times (seismic/5Hz_shear_strain.png), "
                      "no plane is fitted to it"),
    ("failure wedges form in front of and behind the sheet pile and grow as the shaking goes on", "Conclusions",
     "wedges on both sides, growing", "drawn at 1.5, 2, 3.5 and 9 s (the same figure), not measured"),
)


def _run(rep: dict) -> dict:
    """The frequencies that ran (prototype Hz as written -> record)."""
    return {f: r for f, r in rep["frequencies"].items() if r != "not run"}


def _material_rows(ref: dict, mat: dict | None) -> list[Row]:
    soil, tol = ref["soil"], ref["targets"]
    phi, vs, f0, n = (soil[k]["value"] for k in ("friction_angle_deg", "shear_wave_speed_m_per_s",
                                                  "fundamental_frequency_Hz", "porosity"))
    tri = next((t for t in (mat or {}).get("triaxial", []) if t.get("rolling_resistance") == 0.25
                and t["confining_kPa"] == 70.0), None)
    col = (mat or {}).get("column_retained")
    ours_phi = None if tri is None else tri["phi_peak_deg"]
    ours_vs = None if col is None else col["Vs_from_f0_m_per_s"]
    ours_f0 = None if col is None else col["f0_Hz_prototype"]
    ours_n = (mat or {}).get("deposit_porosity")
    return [
        Row("friction angle of the sand", "soil properties", f"{phi:g} deg",
            "" if ours_phi is None else f"{ours_phi:.1f} deg (triaxial, 70 kPa)", f"+-{tol['phi_abs_tol_deg']:g} deg",
            number_verdict(ours_phi, phi, tol["phi_abs_tol_deg"]), TUNED_PHI),
        Row("shear-wave speed of the deposit", "soil properties", f"{vs:g} m/s",
            "" if ours_vs is None else f"{ours_vs:.0f} m/s (4 H f0, 9 m free-field column)", f"+-{100 * tol['shear_wave_speed_rel_tol']:g} %",
            number_verdict(ours_vs, vs, tol["shear_wave_speed_rel_tol"] * vs)),
        Row("fundamental frequency of the deposit", "soil properties (Table 1)", f"{f0:g} Hz",
            "" if ours_f0 is None else f"{ours_f0:.2f} Hz (the 9 m retained free-field column)",
            f"+-{100 * tol['frequency_rel_tol']:g} %",
            number_verdict(ours_f0, f0, tol["frequency_rel_tol"] * f0)),
        Row("porosity of the deposit", "soil properties", f"{n:g}", "" if ours_n is None else f"{ours_n:.3f}",
            f"+-{tol['porosity_abs_tol']:g}", number_verdict(ours_n, n, tol["porosity_abs_tol"])),
    ]


def _trend_rows(rep: dict) -> list[Row]:
    """Each single-frequency trend: held at every frequency run?"""
    freqs = _run(rep)
    names = list(next(iter(freqs.values()))["trends"]) if freqs else []
    rows = []
    for name in names:
        held = {f: r["trends"][name]["held"] for f, r in freqs.items() if name in r.get("trends", {})}
        known = {f: h for f, h in held.items() if h is not None}
        ours = ", ".join(f"{f} Hz {'held' if h else 'NOT held'}" for f, h in known.items())
        rows.append(Row(name, "text, every frequency", "at every frequency", ours, "every frequency",
                        trend_verdict(None if not known else all(known.values()))))
    return rows


def _across_rows(rep: dict) -> list[Row]:
    return [Row(name, "text, across the frequencies", name, t["numbers"], "as stated", trend_verdict(t["held"]))
            for name, t in rep.get("trends_across_frequencies", {}).items()]


def _full_passive_row(rep: dict, ref: dict) -> Row:
    """Fig. 4: the full passive strength mobilised down to 1.5 m below the dredge line at
    4, 5 and 6 Hz, not at 1 and 3 Hz. Full: the largest K at 1.5 m reaches the Coulomb
    K_P of phi 31 deg with delta = 2 phi / 3 (the highest of the paper's K_P, 6.68)."""
    kp = ref["mononobe_okabe"]["delta_2phi_over_3"]["K_P"]
    got = {int(f): r["passive_K_max_at_1_5m"] for f, r in _run(rep).items()}
    full = {f: k >= kp for f, k in got.items()}
    holds = None if not got else all(full[f] == (f in (4, 5, 6)) for f in full)
    ours = ", ".join(f"{f} Hz K {k:.1f}" for f, k in sorted(got.items()))
    return Row("full passive strength down to 1.5 m below the dredge line at 4-6 Hz only", "Fig. 4, text",
               "reached at 4, 5, 6 Hz; not at 1, 3 Hz", ours, f"K max >= K_P {kp:g}", trend_verdict(holds),
               note=_reached_note(full) if holds is False else "")


def _reached_note(full: dict) -> str:
    """Where ours departs from 'at 4-6 Hz only', from the verdicts per frequency."""
    reached = [f for f, ok in sorted(full.items()) if ok]
    if not reached:
        return "ours reaches K_P at no frequency"
    return "ours reaches K_P at " + ", ".join(f"{f}" for f in reached) + " Hz"


def _front_thrust_ratios(rep: dict, over: str) -> dict | None:
    """The front face's residual thrust (its last reading) over ``over`` (static: the
    reading when the base started to move; max: the largest), per frequency run; None
    when a run did not record the front thrust at the end."""
    runs = _run(rep)
    if not runs or any("thrust_front_residual_kN_per_m" not in r["extra"] for r in runs.values()):
        return None
    return {f: r["extra"]["thrust_front_residual_kN_per_m"] / r["extra"][f"thrust_front_{over}_kN_per_m"]
            for f, r in runs.items()}


def _similar_at_4_to_6_row(rep: dict, significant: float) -> Row:
    """Fig. 3, text: at 4-6 Hz the maximum dynamic and residual passive pressures are
    similar; read on the front face's thrust: residual / maximum at least 1 / significant
    at each of 4, 5 and 6 Hz."""
    name, where = "at 4-6 Hz the maximum and residual passive pressures similar", "Fig. 3, text"
    paper = "4-6 Hz: maximum dynamic and residual earth pressures similar"
    ratio = _front_thrust_ratios(rep, "max")
    ratio = None if ratio is None else {f: v for f, v in ratio.items() if f in ("4", "5", "6")}
    if not ratio:
        return Row(name, where, paper, "", "", "not reproduced", note="4, 5 and 6 Hz not run with the front thrust")
    return Row(name, where, paper, ", ".join(f"{f} Hz x{v:.2f}" for f, v in ratio.items()),
               f"front thrust residual / max >= 1/{significant:g} at 4, 5, 6 Hz",
               trend_verdict(len(ratio) == 3 and all(v >= 1.0 / significant for v in ratio.values())))


def _residual_passive_row(rep: dict, significant: float) -> Row:
    """The conclusions: the residual passive pressure considerably above the initial
    static one; read as the front face's thrust at the end over the one when the base
    started to move, at least ``significant`` at every frequency (reference.json
    targets: the paper gives no number)."""
    name, where = "residual passive pressure considerably above the static one", "Conclusions"
    paper = "residual considerably higher than static"
    ratio = _front_thrust_ratios(rep, "static")
    if ratio is None:
        return Row(name, where, paper, "", "", "not reproduced", note="these runs did not record the front thrust "
                   "at the end")
    return Row(name, where, paper, ", ".join(f"{f} Hz x{v:.2f}" for f, v in ratio.items()),
               f"front thrust residual / static >= {significant:g} at every frequency",
               trend_verdict(all(v >= significant for v in ratio.values())))
