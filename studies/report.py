"""Formatting of results for people (rich tables) and programs (JSON-ready dicts).

Pure: builds renderables and dicts; the CLI prints them.
"""

from __future__ import annotations

from rich import box
from rich.console import Group
from rich.table import Table
from rich.text import Text

from analytic.inputs import Soil, Wall
from analytic.summary import MethodRow

SIGN_CONVENTION = ("sigma_h: normal stress on the wall face, compression positive; "
                   "tau: shear on the face, positive down the face (active); "
                   "K = 2P/(gamma H^2) along each method's own thrust direction, Kh its horizontal part; "
                   "h/H: height of the resultant above the base")


def _design_inputs(ground, line_loads, strip_loads) -> dict:
    """The c-phi / water / layer / load inputs in engineering units (empty when unused)."""
    out = {}
    if ground is not None:
        out["layers"] = [{"thickness_m": x.thickness, "phi_deg": x.phi_deg, "gamma_kN_per_m3": x.unit_weight / 1e3,
                          "c_kPa": x.cohesion / 1e3, "gamma_sat_kN_per_m3": x.gamma_sat / 1e3}
                         for x in ground.layers]
        out["water_depth_m"] = ground.water_depth
        out["water_depth_front_m"] = ground.water_depth_front
    if line_loads:
        out["line_loads"] = [{"Q_kN_per_m": ld.Q / 1e3, "x_m": ld.x} for ld in line_loads]
    if strip_loads:
        out["strip_loads"] = [{"q_kPa": ld.q / 1e3, "x1_m": ld.x1, "x2_m": ld.x2} for ld in strip_loads]
    return out


def theory_json(soil: Soil, wall: Wall, rows: list[MethodRow], passive: bool, *, ground=None,
                line_loads=(), strip_loads=()) -> dict:
    return {
        "inputs": {"phi_deg": soil.phi_deg, "gamma_kN_per_m3": soil.unit_weight / 1e3,
                   "H_m": wall.height, "delta_deg": wall.delta_deg, "omega_deg": wall.omega_deg,
                   "beta_deg": wall.beta_deg, "q_kPa": wall.surcharge / 1e3, "passive": passive,
                   **_design_inputs(ground, line_loads, strip_loads)},
        "sign_convention": SIGN_CONVENTION,
        "methods": [r.profile.as_dict() if r.profile is not None
                    else {"name": r.name, "K": None, "Kh": None, "thrust_kN_per_m": None,
                          "resultant_height_over_H": None, "source": "", "not_applicable": r.reason}
                    for r in rows],
    }


def _design_title(ground, line_loads, strip_loads) -> str:
    """Title suffix for a c-phi, wet, layered or loaded backfill."""
    bits = []
    if ground is not None:
        if len(ground.layers) > 1:
            bits.append(f"{len(ground.layers)} layers")
        elif ground.layers[0].cohesion:
            bits.append(f"c = {ground.layers[0].cohesion / 1e3:g} kPa")
        if ground.water_depth is not None:
            bits.append(f"water at {ground.water_depth:g} m")
        if ground.water_depth_front is not None:
            bits.append(f"front water at {ground.water_depth_front:g} m")
    bits += [f"line load {ld.Q / 1e3:g} kN/m at {ld.x:g} m" for ld in line_loads]
    bits += [f"strip load {ld.q / 1e3:g} kPa over {ld.x1:g}-{ld.x2:g} m" for ld in strip_loads]
    return "".join(", " + b for b in bits)


def theory_text(soil: Soil, wall: Wall, rows: list[MethodRow], passive: bool, *, ground=None,
                line_loads=(), strip_loads=()):
    title = (f"{'Passive' if passive else 'Active / at-rest'} earth pressure: phi = {soil.phi_deg:g} deg, "
             f"delta = {wall.delta_deg:g} deg, H = {wall.height:g} m, gamma = {soil.unit_weight / 1e3:g} kN/m3"
             + (f", beta = {wall.beta_deg:g} deg" if wall.beta_deg else "")
             + (f", omega = {wall.omega_deg:g} deg" if wall.omega_deg else "")
             + (f", q = {wall.surcharge / 1e3:g} kPa" if wall.surcharge else "")
             + _design_title(ground, line_loads, strip_loads))
    split = any(r.profile is not None and ("parts" in r.profile.extra or r.profile.extra.get("thrust_q"))
                for r in rows)
    cols = ("method", "K", "Kh", "thrust\nkN/m", "h/H") + (
        ("Ph\nsoil", "Ph\nq", "Ph\nw") if split else ()) + ("status",)
    cells, sources = [], Text()
    for r in rows:
        p = r.profile
        if p is None:
            cells.append((r.name, "n/a", "", "", "", *(("", "", "") if split else ()), "not applicable"))
            sources.append(f"{r.name}: n/a: {r.reason}\n", style="dim")
            continue
        status = "verified" if p.status == "verified" else "[yellow]reconstruction[/yellow]"
        cells.append((p.method, f"{p.K:.4f}", f"{p.Kh:.4f}", f"{p.thrust / 1e3:.2f}",
                      f"{p.height_over_H:.3f}", *(_split_cells(p) if split else ()), status))
        sources.append(f"{p.method}: {p.source}" + (f" [{p.notes}]" if p.notes else "") + "\n",
                       style="dim")
    # numbers are never cut: a number column is as wide as its widest cell and header
    # line; only the words of the method and status columns wrap in a narrow terminal
    t = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, collapse_padding=True, pad_edge=False)
    for k, col in enumerate(cols):
        if col in ("method", "status"):
            t.add_column(col, justify="left", overflow="fold")
        else:
            width = max([len(line) for line in col.split("\n")] + [len(c[k]) for c in cells])
            t.add_column(col, justify="right", no_wrap=True, min_width=width, max_width=width)
    for c in cells:
        t.add_row(*c)
    foot = Text(SIGN_CONVENTION, style="dim")
    if split:
        foot.append("\nPh soil / Ph q / Ph w: horizontal thrust [kN/m] of the soil, of the surcharges "
                    "(uniform q, line and strip loads) and of the water; K stays the soil coefficient", style="dim")
    if any(r.profile is not None and r.profile.status != "verified" for r in rows):
        foot.append("\nreconstruction = the original paper's profile equation could not be read; "
                    "see analytic/arching.py for what is and is not verified.", style="dim")
    return Group(t, sources, foot)


def _split_cells(p) -> tuple[str, str, str]:
    """Horizontal soil, surcharge and water thrusts [kN/m] of one row."""
    parts = p.extra.get("parts")
    if parts:
        return tuple(f"{parts[k]['horizontal_kN_per_m']:.2f}" for k in ("soil", "surcharge", "water"))
    q = p.extra.get("thrust_q", 0.0) * (p.thrust_h / p.thrust if p.thrust else 0.0)
    if not p.extra.get("thrust_q"):
        return "", "", ""
    return f"{(p.thrust_h - q) / 1e3:.2f}", f"{q / 1e3:.2f}", "0.00"


def dsm_json(mode_code: str, result, preset) -> dict:
    p = result.profile
    return {
        "mode": mode_code,
        "K": p.K,
        "resultant_height_over_H": p.height_over_H,
        "theta_r_deg": result.theta_r_deg,
        "surface": p.extra.get("surface", ""),
        "paper": {"K": preset.paper_K, "resultant_height_over_H": preset.paper_height,
                  "source": "Nadukuru & Michalowski (2012) Table 3 (DSM)"},
        "fang_ishibashi": {"K": preset.fang_ishibashi_K, "resultant_height_over_H": preset.fang_ishibashi_height,
                           "source": "Fang & Ishibashi (1986) as quoted in Nadukuru & Michalowski (2012) Table 3"},
        "phi_deg": preset.phi_deg if "phi_deg" not in p.extra else p.extra["phi_deg"],
        "solve_time_ms": result.solve_time_s * 1e3,
        "status": p.status,
    }


def dsm_text(mode_code: str, result, preset, case):
    p = result.profile
    t = Table(title=f"Differential slice method, {preset.title} ({mode_code}): phi = {case.phi_deg:g} deg, "
                    f"delta = {case.delta_deg:g} deg", title_justify="left")
    for col in ("", "K", "h/H"):
        t.add_column(col, justify="left" if not col else "right", no_wrap=True)
    t.add_row("wallsim DSM", f"{p.K:.4f}", f"{p.height_over_H:.3f}")
    t.add_row("paper's DSM (Table 3)", f"{preset.paper_K:.3f}", f"{preset.paper_height:.3f}")
    t.add_row("Fang & Ishibashi (1986)", f"{preset.fang_ishibashi_K:.2f}", f"{preset.fang_ishibashi_height:.2f}")
    notes = Text(f"k_l and phi*: {preset.equation}\nslip surface: {case.surface.label}\n"
                 f"solve time {result.solve_time_s * 1e3:.1f} ms; K = 2P/(gamma H^2) with P the resultant "
                 f"at delta to the wall normal; h/H from the normal stress.", style="dim")
    if p.status != "verified":
        notes.append("\nThe paper's curved surface is not given: this curve is wallsim's choice "
                     "(maximum wall reaction over a family of curved surfaces), so the figures differ "
                     "from Table 3; see analytic/slices.py.", style="yellow")
    return Group(t, notes)


def nadukuru_text(res: dict):
    d, p = res["dem"], res["paper"]
    t = Table(title=f"Nadukuru & Michalowski: mode {res['mode']}, {res['wall']} wall, {res['particles']} spheres, "
                    f"seed {res['seed']}, {res['wall_time_s']:.0f} s", title_justify="left")
    for col in ("", "K", "h/H", "note"):
        t.add_column(col, justify="right" if col in ("K", "h/H") else "left")

    def f(x, fmt):
        return "" if x is None else format(x, fmt)

    t.add_row("wallsim DEM (active)", f(d["K"], ".3f"), f(d["resultant_height_over_H"], ".3f"),
              f"porosity {d['porosity']:.3f}; steady by Delta/H {d['wall_disp_over_H_steady']:.4f}")
    t.add_row("wallsim DEM (at rest)", f(d["K_at_rest"], ".3f"), f(d["resultant_height_over_H_at_rest"], ".3f"),
              f"wall load {d['thrust_at_rest_kN_per_0.5m']:.1f} kN per 0.5 m (paper ~15.4)")
    t.add_row("paper's DEM", f(p.get("K"), ".3f"), f(p.get("resultant_height_over_H"), ".3f"), p.get("source", ""))
    fi = p.get("fang_ishibashi")
    if fi:
        t.add_row("Fang & Ishibashi", f(fi["K"], ".2f"), f(fi["resultant_height_over_H"], ".2f"), "physical tests")
    for row in res["theory"]:
        t.add_row(row["name"], f(row["K"], ".3f"), f(row["resultant_height_over_H"], ".3f"), row["note"])
    foot = Text("K: eq. 6, normal load / (0.5 rho (1 - n) g H^2 w) with the measured n; theories give their "
                "normal (horizontal) coefficient; h/H: height of the resultant above the base.\n"
                f"phi for the theories: {res['phi_deg']:.1f} deg ({res['phi_source']})", style="dim")
    tm = res.get("timings")
    if tm and tm.get("rrd_MB") is not None:
        foot.append(f"\nrecording: {tm['recording_s']:.1f} s of {tm['movement_s']:.0f} s wall movement "
                    f"({100 * tm['recording_share_of_movement']:.1f} %), {tm['rrd_MB']:.1f} MB", style="dim")
    return Group(t, foot)


# ----------------------------------------------------------------------------- checks
def check(item: str, measured: str, ok: bool | None) -> dict:
    """One validation item: what is checked, the measured figure as text, and whether
    it holds (None: this run cannot judge it, e.g. a reused specimen has no fill time)."""
    return {"item": item, "measured": measured, "ok": ok}


def within(value: float, target: float, tol: float) -> bool:
    """|value - target| <= tol."""
    return abs(value - target) <= tol


def verdict(ok: bool | None) -> str:
    return "n/a" if ok is None else ("yes" if ok else "**no**")


def checks_markdown(checks: list[dict], title: str = "Validation targets") -> list[str]:
    """A Markdown section: one row per check with its measured figure and verdict."""
    rows = [f"| {c['item']} | {c['measured']} | {verdict(c['ok'])} |" for c in checks]
    return [f"## {title}", "", "| item | measured | holds |", "|---|---|---|", *rows]


# ----------------------------------------------------------------------------- theory rows
def theory_row(name: str, profile, note: str = "", *, height_over_H: float | None = None) -> dict:
    """One theory beside the DEM, in both studies' results: the *normal* load
    coefficient on the wall (Kh of a vertical wall, comparable with the DEM's normal
    force) and the resultant's height over H; ``profile`` None gives an empty row."""
    if profile is None:
        return {"name": name, "K": None, "resultant_height_over_H": None, "note": note}
    return {"name": name, "K": profile.Kh,
            "resultant_height_over_H": profile.height_over_H if height_over_H is None else height_over_H,
            "note": note}


def reduced_size_line(size: str, here: str, full: str, source: str) -> str:
    """The one line a reduced run prints: its size, what it read, and what the
    full-size validation read for the same case (``source`` names the report)."""
    return f"reduced size: {size}; here {here}; at full size {full} ({source})"
