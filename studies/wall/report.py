"""What a person reads after ``wallsim compare wall``: the DEM's load beside the theories,
the design checks classical and with the DEM's thrust, the change in overturning, and
the assumptions. Built from the result dict only (the JSON says the same)."""

from __future__ import annotations

from rich.console import Group
from rich.table import Table
from rich.text import Text

from ..granular.wall import MODE_TITLES


def wall_text(res: dict):
    d, w, b = res["dem"], res["wall"], res["backfill"]
    passive = res.get("direction") == "passive"
    mode = MODE_TITLES[res["mode"]] + (" into the fill (passive)" if passive else "")
    load = Table(title=f"{res['wall_type']} wall ({res['design_file']}): {mode} to Delta/H "
                       f"{res['wall_disp_over_H']:g}, {res['particles']} spheres, seed {res['seed']}, "
                       f"{res['wall_time_s']:.0f} s", title_justify="left")
    for col in ("", "thrust kN/m", "K", "h/H", "note"):
        load.add_column(col, justify="left" if col in ("", "note") else "right")
    load.add_row("wallsim DEM (active)", f"{d['thrust_kN_per_m']:.1f}", f"{d['K']:.3f}",
                 f"{d['resultant_height_over_H']:.3f}",
                 f"wall friction mobilised {round(d['wall_friction_mobilised_deg'], 1) + 0.0:.1f} deg; porosity {d['porosity']:.3f}")
    load.add_row("wallsim DEM (at rest)", "", f"{d['K_at_rest']:.3f}", f"{d['resultant_height_over_H_at_rest']:.3f}",
                 "before the wall moved")
    for t in res["theory"]:
        if t["K"] is None:
            load.add_row(t["name"], "", "", "", t["notes"])
            continue
        load.add_row(t["name"], f"{t['thrust_kN_per_m']:.1f}", f"{t['K']:.3f}", f"{t['resultant_height_over_H']:.3f}",
                     f"delta {t['delta_deg']:.1f} deg")
    des = res["design"]
    if des is None:
        return Group(load, Text(
            "design checks: not rerun: no check of a wall takes the load of a movement into the fill\n"
            f"wall: back {w['back']}, {w['height_m']:.3f} m, delta {w['delta_deg']:.2f} deg, surcharge "
            f"{w['surcharge_kPa']:g} kPa, backfill {w['backfill_length_m']:g} m long\n"
            "assumptions: " + "; ".join(res["assumptions"]), style="dim"))
    checks = Table(title=f"design checks, format {des['format']}: utilisation classical -> with the DEM's thrust",
                   title_justify="left")
    for col in ("check", "classical", "DEM-informed", "change"):
        checks.add_column(col, justify="left" if col == "check" else "right")
    for name, c in des["checks"].items():
        u0, u1 = c["classical"]["utilisation"], c["dem"]["utilisation"]
        checks.add_row(name, f"{u0:.3f}", f"{u1:.3f}", f"{u1 - u0:+.3f}")
    m = des["thrust_overturning_moment_kNm_per_m"]
    th = des["thrust"]
    g0, g1 = des["classical_governing"], des["dem_governing"]
    foot = Text(
        f"overturning moment of the thrust about the toe: {m['classical']:.1f} kNm/m classical (Ph "
        f"{th['classical']['Ph_kN_per_m']:.1f} kN/m at {th['classical']['height_m']:.2f} m) -> {m['dem']:.1f} kNm/m "
        f"with the DEM (Ph {th['dem']['Ph_kN_per_m']:.1f} kN/m at {th['dem']['height_m']:.2f} m): "
        f"{100 * m['change']:+.0f} %\n"
        f"governing: {g0['check']} {g0['utilisation']:.3f} classical, {g1['check']} {g1['utilisation']:.3f} with "
        f"the DEM ({'passes' if g1['passes'] else 'FAILS'})\n"
        f"wall: back {w['back']}, {w['height_m']:.3f} m, delta {w['delta_deg']:.2f} deg (friction {w['friction']:g}), "
        f"surcharge {w['surcharge_kPa']:g} kPa. Backfill: phi {b['phi_requested_deg']:g} deg -> grain friction "
        f"{b['phi_card']['particle_friction']:g}, rolling {b['phi_card']['rolling_friction']:g} (phi card); unit "
        f"weight {b['unit_weight_dem_kN_m3']:.2f} kN/m3 in the DEM (file {b['unit_weight_requested_kN_m3']:g})\n"
        "K = thrust / (0.5 gamma H^2 + q H), the DEM's with its own gamma; h/H: resultant above the base. "
        "Stresses per segment in segments.csv (kPa, compression +).\n"
        f"design rerun: {des['convention']}\n"
        "assumptions: " + "; ".join(res["assumptions"]), style="dim")
    return Group(load, checks, foot)
