"""Nadukuru & Michalowski's wall modes at reduced size (issue 5): the relations that hold
at any specimen size, checked on one small specimen shared by the modes.

* active K after translation < at-rest K (the paper: 0.214 < 0.385; any active state
  lies below at rest);
* resultant heights ordered RB < T < RT (Tables 1-2 and Fang & Ishibashi 1986:
  0.309 < 0.391 < 0.550 rough);
* translation reaches a steady load before Delta/H = 0.005 (the paper: ~0.003).
Paper-scale figures are in docs/validation/nadukuru.md, not here.
"""

import dataclasses

import numpy as np
import pytest

from analytic.errors import InvalidParameter
from studies.granular import SpecimenRecipe
from studies.granular.load import wall_load
from studies.granular.movement import move_wall, run_modes
from studies.granular.specimen import load_or_prepare
from studies.granular.wall import Movement, WallSetup, grain_scale
from studies.nadukuru.case import NadukuruCase

SMALL = NadukuruCase(specimen=SpecimenRecipe(particles=2400), seed=7)


@pytest.fixture(scope="module")
def specimen(tmp_path_factory):
    spec, _ = load_or_prepare(SMALL, tmp_path_factory.mktemp("specimens"))
    return spec


@pytest.fixture(scope="module")
def modes(specimen):
    out = {}
    for mode in ("T", "RB", "RT"):
        case = dataclasses.replace(SMALL, movement=Movement(mode=mode))
        out[mode] = run_modes(case, specimen)
    return out


def test_specimen_fills_the_wall_and_balances(specimen):
    """The trimmed fill reaches the wall top (within one grain) and is dense."""
    d_max = specimen.grain_scale * SMALL.specimen.d_max
    assert abs(specimen.fill_height - SMALL.wall.height) < d_max
    assert 0.30 < specimen.porosity < 0.42


def test_every_grain_stays_behind_the_wall(specimen):
    """Mass conservation in the box: no grain rained over the wall top lands in front of
    it (before the guard panel, 4 of 2,882 spheres did at 3,000 particles), and none is
    behind the far wall or below the floor."""
    x = specimen.state["spheres.x"]
    assert specimen.stages["in_front_of_wall"] == 0
    assert np.all(x[:, 0] > 0.0) and np.all(x[:, 0] < SMALL.wall.backfill_length) and np.all(x[:, 2] > 0.0)


def test_translation_active_below_at_rest(specimen, modes):
    assert modes["T"]["K_active"] < specimen.K_at_rest


def test_resultant_heights_ordered_RB_T_RT(modes):
    h = [modes[m]["resultant_height_over_H_active"] for m in ("RB", "T", "RT")]
    assert h[0] < h[1] < h[2], h


def test_translation_steady_before_half_a_percent(modes):
    assert modes["T"]["wall_disp_over_H_steady"] < 0.005


def test_interrupted_movement_resumes_exactly(specimen):
    """A movement stopped after a checkpoint and resumed from it gives bitwise the same
    loads as one run straight through (dem3d restores state and contact history)."""
    case = dataclasses.replace(SMALL, movement=Movement(mode="T", wall_disp_over_H=0.001))
    straight = [s.K for s, _ in move_wall(case, specimen)]
    saved = {}
    gen = move_wall(case, specimen, checkpoint=lambda st: saved.__setitem__("state", st), checkpoint_every_s=0.0)
    first = [next(gen)[0].K for _ in range(5)]
    next(gen)              # resuming the generator checkpoints the state after the 5th sample
    gen.close()            # ... and then the run is "interrupted"
    resumed = [s.K for s, _ in move_wall(case, specimen, resume=saved["state"])]
    assert first == straight[:5]
    assert resumed == straight[5:]


def test_wall_load_line_of_action():
    """A uniform normal stress on a wall of 6 panels acts at H/2; a triangular one at H/3:
    the resultant height uses panel forces and panel moments (statics)."""
    from types import SimpleNamespace
    H, n = 3.0, 6
    h = H / n
    corners = np.array([[[0, 0, k * h], [0, 1, k * h], [0, 1, (k + 1) * h], [0, 0, (k + 1) * h]] for k in range(n)],
                       float)
    normal = np.tile([1.0, 0.0, 0.0], (n, 1))
    # triangular stress p(z) = (H - z): panel force and moment about each panel centre
    zc = (np.arange(n) + 0.5) * h
    Fn = (H - zc) * h                       # exact for a linear stress over the panel
    # moment of the push (-x) about each panel centre, along +y:
    # int -(p)(z - zc) dz with p = (H - zc) - (z - zc) -> +h^3/12
    Mn = h**3 / 12.0
    F = np.column_stack([-Fn, np.zeros(n), np.zeros(n)])
    M = np.column_stack([np.zeros(n), np.full(n, Mn), np.zeros(n)])
    frame = SimpleNamespace(panel_force=F, panel_moment=M, panel_normal=normal, panel_corners=corners,
                            panel_area=np.full(n, h))
    load = wall_load(frame, np.arange(n), H)
    assert abs(load.normal - 0.5 * H**2) < 1e-12
    assert abs(load.height - H / 3) < 1e-12


def test_reduced_size_keeps_the_geometry():
    s, w = grain_scale(SpecimenRecipe(particles=2400), SMALL.wall)
    assert w >= 0.5 and s > 1.5
    s30, w30 = grain_scale(SpecimenRecipe(), SMALL.wall)
    assert w30 == 0.5 and 0.95 < s30 < 1.1     # paper scale: the paper's grains fill the box


def test_bad_mode():
    with pytest.raises(InvalidParameter, match="mode"):
        Movement(mode="X")


def test_smooth_side_walls_hold_the_fill_and_carry_no_weight(tmp_path):
    """The paper's box "with smooth side walls" (side_friction=0) instead of the periodic
    width: every sphere stays between the side walls, and the panels' vertical reactions
    add up to the fill's weight (static equilibrium, sum F_z = m g, within 1 %), of which
    the frictionless side and far walls take none."""
    case = NadukuruCase(specimen=SpecimenRecipe(particles=1500), wall=WallSetup(side_friction=0.0), seed=3)
    spec, _ = load_or_prepare(case, tmp_path)
    st = spec.state
    x, r = st["spheres.x"], st["spheres.r"]
    assert np.all(x[:, 1] - r > -0.1 * r) and np.all(x[:, 1] + r < spec.width + 0.1 * r)
    _, first = np.unique(st["spheres.body_id"], return_index=True)
    weight = float(np.sum(1.0 / st["spheres.inv_m"][first])) * 9.81
    fz = st["panel_force"][:, 2]
    assert abs(-fz.sum() / weight - 1.0) < 0.01
    n_wall = case.wall.segments
    assert np.all(np.abs(fz[n_wall + 1:]) < 1e-9 * weight)     # far wall and the two side walls


def test_checkpoints_come_with_progress_as_well_as_time(specimen):
    """With the wall-time trigger out of reach (1 h), a checkpoint still comes each time
    another tenth of the movement is done: 9 in a run (none at the end, which writes
    the result instead), at 10 %, 20 %, ... of the steps. Before, a run interrupted in
    its first 300 s restarted its movement."""
    case = dataclasses.replace(SMALL, movement=Movement(mode="T", wall_disp_over_H=0.002))
    marks = []
    for sample, _ in move_wall(case, specimen, checkpoint=lambda st: marks.append(float(st["time"])),
                               checkpoint_every_s=3600.0):
        last = sample
    t0 = float(specimen.state["time"])
    fractions = [(t - t0) / (last.time - t0) for t in marks]
    assert len(marks) == 9
    # each mark lands on the first sample at or past its tenth (samples are 50 steps apart)
    for k, f in enumerate(fractions, start=1):
        assert k / 10 - 1e-9 <= f < k / 10 + 0.05


def test_a_translation_draws_and_measures_its_displacement_field(specimen, tmp_path):
    """The validation's translation with its field (``movement_run`` with ``fields``):
    displacements.png and force_chains.png in the run folder, and the measure of Fig. 3's
    text in result.json. The wall moves away from the fill (-x), so the active wedge
    follows it and drops: the mean displacement points to -x and down (inclination
    between 0 and 90 deg below the horizontal)."""
    from studies.nadukuru.validate import movement_run
    case = dataclasses.replace(SMALL, movement=Movement(mode="T", wall_disp_over_H=0.004))
    res, _, folder = movement_run(case, specimen, "rough-T", tmp_path, frame_every=10**9, fields="rough",
                                  log=lambda msg: None)
    field = res["displacement_field"]
    assert (folder / "displacements.png").stat().st_size > 0 and (folder / "force_chains.png").stat().st_size > 0
    assert field["moving_grains"] > 0
    assert 0.0 < field["inclination_deg"] < 90.0
    assert 0.0 < field["resultant_length"] <= 1.0
