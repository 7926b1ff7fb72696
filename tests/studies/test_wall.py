"""The designer's wall in DEM (``studies.wall``): the file read as `wallsim design` reads
it, what the DEM refuses, the phi card, the design checks rerun with a measured thrust,
and the Nadukuru case reproduced through the same pipeline."""

import dataclasses
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import cli
import studies
from analytic.design import MeasuredThrust, load_factors, verify
from analytic.design.actions import thrust_for
from analytic.design.config import case_from_dict
from analytic.errors import InvalidParameter
from studies.granular.recipe import SpecimenRecipe
from studies.nadukuru.case import NadukuruCase
from studies.wall.card import PATH, collate, load_card, match_phi
from studies.wall.case import WallStudyCase, grain_density
from tests.conftest import portable_only

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "docs" / "examples" / "cantilever.toml"
PINS = json.loads((ROOT / "tests" / "data" / "pinned_studies.json").read_text())


def _wall_file(tmp_path, text: str, name: str = "wall.toml") -> str:
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def _nadukuru_wall(tmp_path, phi: float) -> str:
    """A cantilever whose back is Nadukuru & Michalowski's rough 3.1 m wall: delta with
    tan(delta) = 0.35, level fill of 2650 kg/m3 grains at porosity 0.36, no surcharge."""
    gamma = 2650 * 9.81 * 0.64 / 1e3
    return _wall_file(tmp_path, f"""
[wall]
type = "cantilever"
height = 3.1
stem_top = 0.3
stem_base = 0.3
toe = 0.6
heel = 1.5
base_thickness = 0.4
unit_weight = 24
[backfill]
gamma = {gamma!r}
phi = {phi!r}
[foundation]
gamma = 18
phi = 30
[method]
earth_pressure = "coulomb"
wall_friction = {math.degrees(math.atan(0.35))!r}
""")


# ------------------------------------------------------------------ the design rerun
def _example():
    return case_from_dict(tomllib.loads(EXAMPLE.read_text()))


@pytest.mark.parametrize("fmt", ["DA1", "DA2", "DA3", "EQU", "fs"])
def test_a_measured_thrust_equal_to_the_classical_one_changes_no_check(fmt):
    """The rerun is the design check itself: the classical characteristic thrust given
    back as a measurement (same Ph, Pv, acting at its own resultant) gives every
    utilisation of `wallsim design` to 1e-12."""
    case, factors = _example(), load_factors()
    unit = {k: 1.0 for k in factors.format("DA1")[0].materials}
    t = thrust_for(case, unit)
    height = sum(p.Ph * p.y for p in t.parts) / t.Ph
    informed = dataclasses.replace(case, measured_thrust=MeasuredThrust(t.Ph, t.Pv, height, "classical"))
    a, b = verify(case, factors, fmt), verify(informed, factors, fmt)
    for name, (_, c) in a.worst.items():
        assert b.worst[name][1].utilisation == pytest.approx(c.utilisation, abs=1e-12), name


def test_a_measured_thrust_acts_where_it_was_measured():
    """Statics: the characteristic soil and surcharge parts sum to the measured Ph and Pv
    and their moment about the base underside is Ph x the measured height; in a DA1
    combination they are the measured thrust times the combination's factor on the
    classical thrust (phi_d = atan(tan 32 / 1.25) in DA1-2)."""
    case, factors = _example(), load_factors()
    unit = {k: 1.0 for k in factors.format("DA1")[0].materials}
    measured = MeasuredThrust(150.0, 20.0, 0.55 * 6.0, "test")
    informed = dataclasses.replace(case, measured_thrust=measured)
    t = thrust_for(informed, unit)
    loads = [p for p in t.parts if p.kind in ("soil", "surcharge")]
    assert sum(p.Ph for p in loads) == pytest.approx(150.0, rel=1e-12)
    assert sum(p.Pv for p in loads) == pytest.approx(20.0, rel=1e-12)
    assert sum(p.Ph * p.y for p in loads) == pytest.approx(150.0 * 3.3, rel=1e-12)
    combo2 = factors.format("DA1")[1].materials
    ratio = thrust_for(case, combo2).Ph / thrust_for(case, unit).Ph
    assert sum(p.Ph for p in thrust_for(informed, combo2).parts) == pytest.approx(150.0 * ratio, rel=1e-12)


# ------------------------------------------------------------------ the phi card
def _card(points):
    return {"points": [{"particle_friction": f, "rolling_friction": r, "phi_peak_deg": p} for f, r, p in points]}


def test_the_phi_card_inverts_along_its_path():
    """A card point gives its own micro parameters exactly; between two points they are
    linear in phi; outside the card, one line with its range."""
    card = _card([(0.1, 0.0, 20.0), (0.65, 0.0, 36.0), (0.65, 0.1, 40.0)])
    m = match_phi(36.0, card)
    assert (m.particle_friction, m.rolling_friction) == (0.65, 0.0)
    m = match_phi(28.0, card)
    assert m.particle_friction == pytest.approx(0.1 + 0.5 * 0.55, abs=1e-3) and m.rolling_friction == 0.0
    m = match_phi(38.0, card)
    assert (m.particle_friction, m.rolling_friction) == (0.65, 0.05)
    with pytest.raises(InvalidParameter, match=r"backfill.phi.*\[20.0, 40.0\] deg"):
        match_phi(45.0, card)


def test_collate_refuses_a_card_whose_phi_falls_along_the_path():
    def triaxial_card(f, r, phi):
        rec = dataclasses.asdict(dataclasses.replace(SpecimenRecipe(), particle_friction=f, rolling_friction=r))
        return {"recipe": rec, "phi_peak_deg": phi, "phi_end_deg": phi - 3, "strain_at_peak": 0.02,
                "porosity": 0.36, "particles": 8200, "seed": 1, "wall_time_s": 1.0, "test": "cubical triaxial",
                "confining_kPa": 200.0, "strain_rate_per_s": 0.04}
    good = collate([triaxial_card(*PATH[1], 24.0), triaxial_card(*PATH[0], 20.0)])
    assert [p["phi_peak_deg"] for p in good["points"]] == [20.0, 24.0]       # sorted along the path
    with pytest.raises(InvalidParameter, match="phi rising along the path"):
        collate([triaxial_card(*PATH[0], 20.0), triaxial_card(*PATH[1], 19.0)])


def test_the_shipped_card_spans_the_angles_a_designer_asks_for():
    """About 25-45 deg (the issue's grid), made at the Nadukuru triaxial's 8,200 spheres,
    phi rising along the path; the paper's own recipe (friction 0.65, no rolling) is a
    point of it."""
    card = load_card()
    phis = [p["phi_peak_deg"] for p in card["points"]]
    assert phis == sorted(phis) and phis[0] <= 25.0 and phis[-1] >= 42.0
    assert all(p["particles"] == 8200 for p in card["points"])
    assert any(p["particle_friction"] == 0.65 and p["rolling_friction"] == 0.0 for p in card["points"])


# ------------------------------------------------------------------ the case
def test_unit_weight_sets_the_grain_density():
    """rho = gamma / (g (1 - n)): the Nadukuru fill (2650 kg/m3 at n = 0.36) is 16.64 kN/m3."""
    assert grain_density(2650 * 9.81 * 0.64 / 1e3, 0.36) == 2650.0
    assert grain_density(18.0, 0.36) == round(18e3 / (9.81 * 0.64))


def test_the_nadukuru_wall_file_is_the_nadukuru_case(tmp_path):
    """At the Nadukuru geometry and the card's phi of the paper's recipe, the wall case is
    the Nadukuru case, record for record (the same pipeline, the same specimen cache key)."""
    phi = next(p["phi_peak_deg"] for p in load_card()["points"]
               if p["particle_friction"] == 0.65 and p["rolling_friction"] == 0.0)
    case = WallStudyCase(design_file=_nadukuru_wall(tmp_path, phi), particles=2000, seed=3)
    nad = NadukuruCase(specimen=SpecimenRecipe(particles=2000), seed=3)
    assert (case.specimen, case.wall, case.movement) == (nad.specimen, nad.wall, nad.movement)
    from studies.granular.specimen import specimen_key
    assert specimen_key(case) == specimen_key(nad)


@portable_only
def test_the_nadukuru_wall_file_gives_the_nadukuru_numbers(tmp_path):
    """`compare wall` on that file gives the pinned `compare nadukuru --mode T
    --particles 2000 --seed 3` K and resultant height bit for bit
    (tests/data/pinned_studies.json)."""
    phi = next(p["phi_peak_deg"] for p in load_card()["points"]
               if p["particle_friction"] == 0.65 and p["rolling_friction"] == 0.0)
    case = WallStudyCase(design_file=_nadukuru_wall(tmp_path, phi), particles=2000, seed=3)
    res = studies.get("wall").run(case, out=str(tmp_path / "runs"), no_rrd=True)
    pinned = PINS["nadukuru"]["values"]["dem"]
    assert res["dem"]["K"] == pinned["K"]
    assert res["dem"]["resultant_height_over_H"] == pinned["resultant_height_over_H"]
    assert res["dem"]["porosity"] == pinned["porosity"]


REFUSED = [
    ('[wall]\ntype = "blocks"\nheight = 2\nbase = 1\n', "wall.type"),
    ('[backfill]\ngamma = 18\nphi = 30\nc = 5\n', "backfill.c"),
    ('[water]\nbehind = 2\n', "water.behind"),
    ('[backfill]\ngamma = 18\nphi = 60\n', "backfill.phi"),
]


@pytest.mark.parametrize("change,key", REFUSED, ids=[k for _, k in REFUSED])
def test_what_the_dem_cannot_model_is_refused_in_one_line(tmp_path, capsys, change, key):
    """Exit 2 and one line naming the key, before any folder or grain is made."""
    import tomli_w
    data = tomllib.loads(EXAMPLE.read_text())
    for table, values in tomllib.loads(change).items():
        data[table] = values if table == "wall" else data.get(table, {}) | values
    path = _wall_file(tmp_path, tomli_w.dumps(data))
    out = tmp_path / "runs"
    assert cli.main(["compare", "wall", path, "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith(f"wallsim: error: {key} ") and "Traceback" not in "".join(err), err
    assert not (out / "wall").exists()


def test_without_a_wall_file_the_command_says_what_it_needs(tmp_path, capsys):
    assert cli.main(["compare", "wall", "--out", str(tmp_path), "--quiet"]) == 2
    assert "design_file" in capsys.readouterr().err


def test_a_sloping_fill_is_cut_to_its_plane(tmp_path):
    """beta = 15 deg: the settled fill's surface follows z = H + x tan(beta) (geometry of
    the file's slope) to within one grain across the box."""
    from studies.granular.specimen import prepare_specimen
    from studies.granular.wall import grain_scale

    data = tomllib.loads(EXAMPLE.read_text())
    data["backfill"] |= {"phi": 30.0, "beta": 15.0}
    data["loads"]["surcharge"] = 0.0
    import tomli_w
    case = WallStudyCase(design_file=_wall_file(tmp_path, tomli_w.dumps(data)), particles=1200)
    spec = prepare_specimen(case)
    x, r = spec.state["spheres.x"], spec.state["spheres.r"]
    scale, _ = grain_scale(case.specimen, case.wall)
    d_max = scale * case.specimen.d_max
    L, H = case.wall.backfill_length, case.wall.height
    assert H == pytest.approx(6.0 + 3.0 * math.tan(math.radians(15.0)))      # the virtual back through the heel
    for lo in np.linspace(0.1, 0.7, 4) * L:
        band = (x[:, 0] >= lo) & (x[:, 0] < lo + 0.2 * L)
        top = float(np.max(x[band, 2] + r[band]))
        plane = H + (lo + 0.1 * L) * math.tan(math.radians(15.0))
        assert abs(top - plane) < d_max, (lo, top, plane)


@pytest.mark.parametrize("extra", [[], ["--format", "fs", "--mode", "RB"]], ids=["DA1-T", "fs-RB"])
def test_compare_wall_on_the_worked_example_writes_a_complete_run_folder(tmp_path, capsys, extra):
    """The example at a reduced size: every file the module docstring lists, the
    classical checks of the table equal `wallsim design`'s, the DEM thrust's moment
    about the toe is Ph x its height (statics), and the text says the change."""
    out = tmp_path / "runs"
    assert cli.main(["compare", "wall", str(EXAMPLE), "--particles", "1200", "--out", str(out), "--quiet",
                     "--json", *extra]) == 0
    res = json.loads(capsys.readouterr().out)
    folder = Path(res["run_folder"])
    for name in ("config.toml", "wall.toml", "manifest.json", "result.json", "history.csv", "segments.csv",
                 "theory.csv", "design.csv", "fig_pressure.png", "fig_K.png", "fig_displacements.png",
                 "fig_force_chains.png", "recording.rrd"):
        assert (folder / name).is_file(), name
    fmt = extra[1] if extra else "DA1"
    classical = verify(_example(), load_factors(), fmt)
    for name, c in res["design"]["checks"].items():
        assert c["classical"]["utilisation"] == pytest.approx(classical.worst[name][1].utilisation, rel=1e-12)
    th = res["design"]["thrust"]["dem"]
    m = res["design"]["thrust_overturning_moment_kNm_per_m"]
    assert m["dem"] == pytest.approx(th["Ph_kN_per_m"] * th["height_m"], rel=1e-9)      # y0 = 0: the base underside
    assert th["Ph_kN_per_m"] == pytest.approx(res["dem"]["K"] * (0.5 * 18 * 36 + 10 * 6), rel=1e-12)
    assert res["backfill"]["phi_card"]["rolling_friction"] == 0.0 and res["wall"]["friction"] == 0.0


def test_a_surcharged_movement_resumes_exactly(tmp_path):
    """The surcharge is an external force on the top grains, kept in the engine state:
    a movement interrupted after a checkpoint and resumed gives bitwise the loads of one
    run straight through; and the load on the top layer is q L w (10 kPa of the file)."""
    from studies.granular.movement import move_wall
    from studies.granular.specimen import load_or_prepare
    from studies.granular.wall import Movement
    from studies.wall.surcharge import load_or_surcharge

    case = WallStudyCase(design_file=str(EXAMPLE), particles=1200,
                         movement=Movement(mode="T", wall_disp_over_H=0.001))
    spec, _ = load_or_prepare(case, tmp_path)
    spec, _ = load_or_surcharge(case, spec, 10e3, tmp_path)
    f_ext = spec.state["spheres.f_ext"]
    assert -f_ext[:, 2].sum() == pytest.approx(10e3 * case.wall.backfill_length * spec.width, rel=1e-12)
    straight = [s.K for s, _ in move_wall(case, spec)]
    saved = {}
    gen = move_wall(case, spec, checkpoint=lambda st: saved.__setitem__("state", st), checkpoint_every_s=0.0)
    first = [next(gen)[0].K for _ in range(3)]
    next(gen)
    gen.close()
    resumed = [s.K for s, _ in move_wall(case, spec, resume=saved["state"])]
    assert first + resumed == straight


def test_a_reduced_triaxial_of_the_card_recipe_has_the_requested_phi():
    """The card inverted for 34 deg, tested at 2,000 spheres (the card: 8,200) with
    another seed: peak phi within the 1.5 deg the designer's backfill must reach. At
    3,000 spheres the card's points came out 0.4-0.8 deg above 8,200's (friction 0.2,
    0.65, rolling 0.05-0.2; seed 1), inside that. This recipe at seed 2 (measured):
    34.10 deg at 2,000 spheres, 34.12 at 3,000 (1.6x the CPU), 33.23 at 1,500."""
    from studies.elements.triaxial import run_triaxial
    from studies.wall.calibrate import point_recipe

    m = match_phi(34.0, load_card())
    res = run_triaxial(point_recipe(2000, m.particle_friction, m.rolling_friction), seed=2, particles=2000)
    assert res.phi_peak_deg == pytest.approx(34.0, abs=1.5)


def test_a_passive_movement_mirrors_each_mode():
    """direction passive: the wall moves into the fill (+x) in translation, and each
    rotation turns the other way about the same pivot."""
    from studies.granular.movement import wall_motion
    from studies.granular.wall import Movement

    for mode in ("T", "RB", "RT", "mixed"):
        a, _ = wall_motion(Movement(mode=mode), 3.0)
        p, _ = wall_motion(Movement(mode=mode, direction="passive"), 3.0)
        if mode == "T":
            assert a.velocity(1.0)[0] < 0 < p.velocity(1.0)[0]
        else:
            assert np.allclose(np.asarray(a.axis), -np.asarray(p.axis)) and a.pivot == p.pivot


def test_a_passive_run_loads_the_wall_above_at_rest(tmp_path, capsys):
    """Into the fill, K rises above its at-rest value (theory: K0 < Kp), the passive
    theories stand beside it, and no design check is rerun (none takes that load)."""
    out = tmp_path / "runs"
    data = tomllib.loads(EXAMPLE.read_text())
    data["loads"]["surcharge"] = 0.0
    import tomli_w
    path = _wall_file(tmp_path, tomli_w.dumps(data))
    assert cli.main(["compare", "wall", path, "--particles", "3000", "--out", str(out), "--quiet", "--json",
                     "--no-rrd", "--set", "movement.direction=passive", "--set",
                     "movement.wall_disp_over_H=0.01"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["dem"]["K"] > 1.5 * res["dem"]["K_at_rest"]
    assert [t["method"] for t in res["theory"]] == ["rankine", "coulomb", "log-spiral"]
    assert res["design"] is None and not (Path(res["run_folder"]) / "design.csv").exists()
    assert res["wall"]["backfill_length_m"] == 18.0          # 3 H
