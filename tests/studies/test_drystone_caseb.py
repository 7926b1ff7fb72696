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


def test_recording_holds_the_grains_blocks_and_failure_velocities(tmp_path):
    """The case-B recording (issue 24: blocks, grains, force chains, block velocities at
    failure), on the too-narrow wall: every grain and block of the result is in the last
    frame, every block has a finite velocity there, the fill height series ends at the
    DEM's critical height, and the wall moved at failure: the crest is farther out in the
    failure frame than in any frame before. That holds for any trajectory: a stage that
    ends standing has its crest short of the runaway limit (2 % of h), and failure takes
    the crest past it or keeps the blocks above 0.1 J/m (S-OET's criterion) for ten
    readings of 0.1 s. (How fast a block moves at the last instant does not: 0.13 mm/s
    on one CPU, 38 mm/s on another, before the portable mode.)"""
    import numpy as np

    from viz import paths as P
    from viz import readback
    cmd = get("drystone").commands[0]
    case = cmd.resolve(flags={"wall": "C2S"}, sets=NARROW)
    res, _ = cmd.run(case, cmd.run_options(out=str(tmp_path)))
    rrd = res["recording"]
    assert {"/" + P.BLOCKS, "/" + P.GRAINS, "/" + P.FORCE_CHAINS, "/" + P.BLOCK_VELOCITY} <= readback.entity_paths(rrd)
    _, grains = readback.read_column(rrd, "/" + P.GRAINS, "LineStrips2D:strips")
    _, blocks = readback.read_column(rrd, "/" + P.BLOCKS, "LineStrips2D:strips")
    assert len(grains[-1]) == res["particles"]["grains"] and len(blocks[-1]) == res["particles"]["blocks"]
    _, vel = readback.read_column(rrd, "/" + P.BLOCK_VELOCITY, "Arrows2D:vectors")
    assert len(vel) == 1 and len(vel[0]) == res["particles"]["blocks"]
    assert np.isfinite(np.asarray(vel[0], float)).all()
    _, height = readback.read_scalars(rrd, "/metrics/backfill_height_m")
    assert height[-1] == pytest.approx(res["critical_height_m"])
    _, crest = readback.read_scalars(rrd, "/metrics/crest_displacement_mm")
    assert crest[-1] > max(crest[:-2], default=-np.inf)     # the failure frame comes twice: stage, velocities


def test_validate_case_b_writes_both_seeds_keeps_case_a_and_reuses_runs(tmp_path):
    """``validate drystone --case B`` at the narrow wall's size (two seeds): drystone.json
    gains case B in the issue's keys with the measured C2S height (2.30 m, S-OET Table 4),
    each seed failing no later than the limit-equilibrium stage (as above); case A, already
    there, is kept; a second call reads the finished runs instead of running them, and
    with ``run_missing`` False a seed without a run is written as not run."""
    import shutil
    from pathlib import Path

    from studies.drystone.validate_b import validate_case_b
    docs = tmp_path / "docs"
    docs.mkdir()
    shutil.copyfile(Path(__file__).resolve().parents[2] / "docs/validation/drystone.json", docs / "drystone.json")
    case_a = json.loads((docs / "drystone.json").read_text())["walls"]
    cmd = get("drystone").commands[0]
    case = cmd.resolve(flags={"wall": "C2S"}, sets=NARROW)
    rep = validate_case_b(case, out_dir=docs, root=tmp_path / "runs", walls=["C2S"], seeds=(1, 2))
    saved = json.loads((docs / "drystone.json").read_text())
    assert saved["walls"] == case_a
    for seed in ("1", "2"):
        e = saved["case_b"]["walls"]["C2S"][seed]
        assert {"critical_height_m", "mode", "measured_height_m", "measured_mode", "wall_time_s"} <= set(e)
        assert e["measured_height_m"] == 2.30 and e["seed"] == int(seed)
        assert case.backfill.layer_m < e["critical_height_m"] <= e["limit_equilibrium"]["critical_height_m"] + \
            case.backfill.layer_m
        m = e["motion_at_failure"]                  # read from the run's recording
        assert 0 < m["blocks"] < e["particles"]["blocks"] and m["steps"][0] < m["steps"][1]   # above course 0
        assert m["crest_movement_mm"] > 0 and m["rms_residual_mm"] <= m["max_residual_mm"]
    text = (docs / "drystone.md").read_text()
    assert "## Case A" in text and "## Case B" in text and "| C2S | 2 |" in text
    assert "### How the wall moved in the failing stage" in text
    folders = sorted((tmp_path / "runs" / "drystone").iterdir())
    assert len(folders) == 2
    again = validate_case_b(case, out_dir=docs, root=tmp_path / "runs", walls=["C2S"], seeds=(1, 2))
    assert sorted((tmp_path / "runs" / "drystone").iterdir()) == folders
    assert again["case_b"]["walls"] == rep["case_b"]["walls"]
    # a seed whose run folder is not on this machine keeps the entry the report has
    before = json.loads((docs / "drystone.json").read_text())["case_b"]
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    for f in folders:
        if json.loads((f / "result.json").read_text())["seed"] == 2:
            shutil.move(str(f), elsewhere / f.name)
    kept = validate_case_b(case, out_dir=docs, root=tmp_path / "runs", walls=["C2S"], seeds=(1, 2),
                           run_missing=False)
    assert kept["case_b"]["walls"]["C2S"]["2"] == before["walls"]["C2S"]["2"]
    assert kept["case_b"]["assumptions"] == before["assumptions"]
    partial = validate_case_b(case, out_dir=docs, root=tmp_path / "runs", walls=["C2S"], seeds=(1, 3),
                              run_missing=False)
    assert sorted((tmp_path / "runs" / "drystone").iterdir()) == [f for f in folders if f.exists()]  # no seed 3
    assert partial["case_b"]["walls"]["C2S"]["3"] == "not run"
    assert "| C2S | 3 | | not run |" in (docs / "drystone.md").read_text()


def test_inner_face_forces_reads_the_innermost_block_of_each_course_below_the_surface():
    """Oetomo et al. Fig. 20 is read on the loaded (inner) face: per course the block
    reaching furthest inward, only where its centre lies below the fill surface. Two
    courses of two blocks (x inward) under a fill 0.2 m high: the inner blocks are 1
    (course 0) and 3 (course 1, centre 0.15 m); a third course (centre 0.25 m) is above
    the surface. Block 3 carries 2 N/m, 0.4 % of the median (below 1 % is "no force")."""
    from studies.drystone.run_b import inner_face_forces
    box = lambda x0, y0: [[x0, y0], [x0 + 0.3, y0], [x0 + 0.3, y0 + 0.1], [x0, y0 + 0.1]]
    forces = {"backfill_height_m": 0.2,
              "outlines_m": [box(0.0, 0.0), box(0.3, 0.0), box(0.0, 0.1), box(0.3, 0.1), box(0.3, 0.2)],
              "fill_force_N_m": [[0.0, 0.0], [1000.0, 10.0], [0.0, 0.0], [2.0, 0.0], [500.0, 0.0]]}
    f = inner_face_forces(forces, [0, 0, 1, 1, 2])
    assert f["blocks"] == 2 and f["median_N_m"] == pytest.approx(501.0)
    assert f["without_force"] == 1 and f["least_N_m"] == 2.0 and f["largest_N_m"] == 1000.0


def test_report_tags_each_walls_own_assumptions_with_the_wall():
    """The case-B report lists an assumption every wall shares once, as it is, and one
    that differs between walls (C2S's 0.60 m base, C3S's 0.76 m: reference 3.3's
    back-fit) led by the walls it belongs to, so no base width reads as every wall's."""
    from studies.drystone.validate_b import tagged_assumptions
    tagged = tagged_assumptions({"C2S": ["unit weight 20 kN/m3", "base width 0.6 m"],
                                 "C3S": ["unit weight 20 kN/m3", "base width 0.76 m"],
                                 "C4L": ["unit weight 20 kN/m3", "base width 0.6 m"]})
    assert tagged == ["unit weight 20 kN/m3", "C2S, C4L: base width 0.6 m", "C3S: base width 0.76 m"]
