"""``compare drystone --wall C2S`` at reduced size: a 0.48 m wall with a 0.8 m base,
coarse gravel (20-32 mm), a 0.6 m container, filled in 0.1 m stages up to the formwork
(0.2 m above the crest).

References: Coulomb's active thrust is the least a fill can put on a wall (the wall
would have to move outward to bring it down to that); this wall does not move
(the limit equilibrium of the section, analytic.drystone, puts its critical height at
about 2 m or more for any interface angle the calibration gives), so the fill's thrust on
it is at least Coulomb's with the slope (beta 32 deg, phi 37.7 deg, delta the interface
angle) at the last stage; the case-B output names the paper's local frictions
(S-OET: 45, 25, 15.6 deg) beside ours, and the measured height of C2S (2.30 m, S-OET
Table 4) beside the DEM's.
"""

import json

import pytest

from studies import get

SETS = ["height_m=0.48", "base_width_m=0.8", "backfill.width_min_m=0.02", "backfill.width_max_m=0.032",
        "backfill.container_m=0.6", "backfill.formwork_m=0.2", "backfill.hold_depth_m=none"]


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("caseb")
    cmd = get("drystone").commands[0]
    case = cmd.resolve(flags={"wall": "C2S"}, sets=SETS)
    res, _ = cmd.run(case, cmd.run_options(out=str(out)))
    return res


def test_unmoving_wall_carries_at_least_the_active_thrust(result):
    last, coulomb = result["stages"][-1], result["coulomb"]["rows"][-1]
    assert result["critical_height_m"] is None
    assert result["limit_equilibrium"]["critical_height_m"] > 2 * last["backfill_height_m"]
    assert last["backfill_height_m"] == pytest.approx(0.6)   # the last whole layer below 0.48 + 0.2 m
    assert last["thrust_N_m"] >= coulomb["thrust_N_m"]
    assert abs(last["crest_displacement_m"]) < 0.005


def test_output_names_paper_and_our_values(result):
    assert result["local_values"]["paper"] == {"grain_friction_deg": 45.0, "interface_friction_deg": 25.0,
                                               "placement_friction_deg": 15.6}
    assert result["local_values"]["ours"]["grain_friction_deg"] == 50.0   # gravel_calibration.json
    assert result["measured_height_m"] == 2.30 and result["paper_dem_heights_m"] == [2.46, 2.38]
    folder = result["run_folder"]
    rows = json.loads(open(f"{folder}/result.json").read())["stages"]
    assert len(rows) == len(result["stages"])
    assert any("ASSUMED" in a for a in result["assumptions"])
    assert any("part of the innermost crest block" in a for a in result["assumptions"])   # S-OET 5.2


def test_bad_case_b_settings_name_their_key():
    """Bad input: one message naming the case key and its range (project rule), before any run."""
    from analytic.errors import InvalidParameter
    cmd = get("drystone").commands[0]
    with pytest.raises(InvalidParameter, match="backfill.slope_deg"):
        cmd.resolve(flags={"wall": "C2S"}, sets=["backfill.slope_deg=70"])
    with pytest.raises(InvalidParameter, match="backfill.formwork = .*crest | fixed"):
        cmd.resolve(flags={"wall": "C2S"}, sets=["backfill.formwork=wooden"])
    with pytest.raises(InvalidParameter, match="backfill.grain_shape = .*capsule | clump3 | hexagon"):
        cmd.resolve(flags={"wall": "C2S"}, sets=["backfill.grain_shape=star"])
    with pytest.raises(InvalidParameter, match="geometry"):
        cmd.resolve(flags={"wall": "C3S", "geometry": "disk-count"})


#: a wall too narrow for its fill: 0.48 m of 0.15 x 0.06 m blocks (8 courses) on a 0.16 m
#: base, the formwork column 0.4 m above the crest, so the fill can rise to 0.88 m
NARROW = ["height_m=0.48", "base_width_m=0.16", "block_length_m=0.15", "block_height_m=0.06",
          "backfill.width_min_m=0.02", "backfill.width_max_m=0.032", "backfill.container_m=0.6",
          "backfill.formwork_m=0.4", "backfill.hold_depth_m=none"]


def test_too_narrow_wall_fails_by_its_limit_equilibrium_height(tmp_path):
    """Reference: the rigid-block limit equilibrium of the section with Coulomb's thrust
    (analytic.drystone.backfill_limit_equilibrium: gamma_s 14.9, phi 37.7, beta 32, delta
    the calibrated global interface angle) puts the critical backfill height of this wall
    below the 0.88 m the fill can reach (about 0.6 m, toppling). Coulomb's active thrust is
    the least a fill can put on a wall, and the DEM fill's peak angle (36.7 deg,
    gravel_calibration.md) is below the 37.7 used there, so the DEM wall must fail no
    later than the stage that passes that height; it carries the first layer (a sixth of
    that height). Measured (hexagons, local 50 / 45 deg): 0.50 m, sliding of the upper
    courses, on seeds 1 and 2; limit equilibrium 0.61 m toppling (delta 30.4); 3.6 s CPU."""
    cmd = get("drystone").commands[0]
    case = cmd.resolve(flags={"wall": "C2S"}, sets=NARROW)
    res, _ = cmd.run(case, cmd.run_options(out=str(tmp_path)))
    le = res["limit_equilibrium"]["critical_height_m"]
    assert le < 0.48 + 0.4 - 0.1            # the fill can pass it by a whole layer
    assert res["critical_height_m"] is not None, [r["backfill_height_m"] for r in res["stages"]]
    assert case.backfill.layer_m < res["critical_height_m"] <= le + case.backfill.layer_m
    assert res["mode"] in ("sliding", "toppling")
