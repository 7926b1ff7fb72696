"""Khosravi et al.'s box at reduced size (grains 5x coarser, same geometry): statics,
the wall test, solver sensitivity, checkpoints and determinism.

References: statics (reactions = weight), the paper (pressure falls as the wall moves
away; studies/khosravi/reference.json), the issue's 5 % solver-sensitivity target.
"""

from __future__ import annotations

import importlib.util
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from dem2d.measure import readings
from studies.khosravi.run import KhosraviRun
from studies.measures import k_upper_half, normal_thrust
from dem2d.sim import restore

REF = json.loads(Path(importlib.util.find_spec("studies.khosravi").submodule_search_locations[0], "reference.json").read_text())
TARGETS = REF["targets"]


def _run_from(settled, **changes) -> KhosraviRun:
    sim = restore(settled.blob)
    case = replace(settled.case, **changes)
    if "solver" in changes:
        sim.set_solver(case.solver)
    return KhosraviRun(case, sim=sim)


def test_settled_column_reactions_equal_its_weight(settled_box):
    # reference: statics. Floor + retaining wall + far wall vertical reactions = weight
    # (time average over 0.05 s; the tolerance 1e-2)
    run = _run_from(settled_box, window=0.05)
    r = run.reading()
    total = -(r.floor_fy + r.wall_fy + r.far_fy) / run.backfill.weight
    assert abs(total - 1.0) <= TARGETS["weight_balance_abs_tol"]
    # the rough wall carries part of the weight, the smooth far wall none
    assert -r.wall_fy > 0
    assert abs(r.far_fy) < 1e-3 * run.backfill.weight  # only where grains touch its end cap


def test_backfill_fills_the_box_to_H(settled_box):
    bf = settled_box.backfill
    assert bf.H == pytest.approx(0.3, abs=0.02)
    assert 0.1 < bf.porosity < 0.3      # 2D disk packings: 0.1-0.25; paper 0.21
    assert bf.n_grains == settled_box.n_grains


#: at 5x coarser grains the wall must move ~5x further (in Dis/H) than at full size to
#: reach the active state, because rigid grains need a displacement of a fraction of a
#: grain to rearrange (docs/dem2d.md); 5 mm/s keeps the inertial number ~5e-4
ACTIVE = dict(wall_disp_over_H_max=0.01, wall_speed=5e-3)


@pytest.fixture(scope="module")
def translated(settled_box):
    """The wall test from one specimen with the chosen solver and with twice the
    iterations at half the time step: (run, at-rest reading, thrust history) each."""
    base = settled_box.case.solver
    out = {}
    for key, solver in (("base", base), ("fine", replace(base, iterations=2 * base.iterations, dt=base.dt / 2))):
        run = _run_from(settled_box, solver=solver, **ACTIVE)
        rest = run.at_rest()
        z = run.panel_depths()
        thrust = [normal_thrust(r.sigma, z, run.case.panel_height) for r in run.translate()]
        out[key] = (run, rest, np.array(thrust))
    return out


def test_pressure_falls_when_the_wall_moves_away(translated):
    # reference: Khosravi et al. section 4.2 -- the lateral pressure drops as the wall
    # translates away from the backfill
    run, rest, thrust = translated["base"]
    z = run.panel_depths()
    f_rest = normal_thrust(rest.sigma, z, run.case.panel_height)
    assert run.history[-1].dis / run.backfill.H >= ACTIVE["wall_disp_over_H_max"]
    assert np.mean(thrust[-3:]) < 0.85 * f_rest
    # and below at rest at every reading point
    _, m_rest, _ = run.readings_of(rest)
    m_act = np.mean([run.readings_of(r)[1] for r in run.history[-3:]], axis=0)
    assert np.all(m_act < m_rest)
    # the wall moved by exactly speed x time
    assert -run.sim.walls["wall"].displacement()[0] == pytest.approx(
        run.case.wall_speed * (run.sim.time - rest.time - 0.5 * run.case.window), rel=1e-6)


def test_active_thrust_does_not_depend_on_iterations_and_dt(translated):
    # the solver check at the active state (the limit state, friction fully
    # mobilised): twice the iterations and half dt change the wall's normal thrust
    # (mean of the last 5 windows) by less than 5 %
    f0 = np.mean(translated["base"][2][-5:])
    f1 = np.mean(translated["fine"][2][-5:])
    assert abs(f1 - f0) / f0 < TARGETS["solver_sensitivity_rel_tol"]


def test_readings_run_at_their_own_sweeps_after_the_fill(settled_box):
    # reference: the case definition (KhosraviCase.reading_iterations). The fill's
    # solver until at_rest(), the readings' sweeps from there on; the time step kept
    run = _run_from(settled_box, reading_iterations=2 * settled_box.case.solver.iterations)
    assert run.sim.space.iterations == settled_box.case.solver.iterations
    run.at_rest()
    assert run.sim.space.iterations == 2 * settled_box.case.solver.iterations
    assert run.sim.dt == settled_box.case.solver.dt


def _rest_readings(settled, solver):
    run = _run_from(settled, solver=solver, window=0.04)
    run.sim.run(int(round(0.02 / solver.dt)))
    r = run.reading()
    z = run.panel_depths()
    _, means = readings(np.where(z > 0, r.sigma, np.nan), 4)
    return (means[np.isfinite(means)],
            k_upper_half(r.sigma, z, run.case.panel_height, run.backfill.gamma, run.backfill.H))


def test_at_rest_pressures_do_not_depend_on_iterations(settled_box):
    # the solver check, iterations part: twice the iterations on the same
    # settled packing (both branches restored from one snapshot) changes the 4-panel
    # readings and the upper-half K by less than 5 %
    base = settled_box.case.solver
    m1, k1 = _rest_readings(settled_box, base)
    m2, k2 = _rest_readings(settled_box, replace(base, iterations=2 * base.iterations))
    tol = TARGETS["solver_sensitivity_rel_tol"]
    assert np.max(np.abs(m2 - m1) / m1) < tol
    assert abs(k2 - k1) / k1 < tol


@pytest.mark.xfail(strict=True, reason="known limit (docs/dem2d.md): the at-rest force network of rigid "
                                       "grains is statically indeterminate and pymunk settles on a "
                                       "dt-dependent one (K upper half +15 % and wall friction reversing "
                                       "sign from dt 2e-4 to 1e-4 s)")
def test_at_rest_pressures_do_not_depend_on_dt(settled_box):
    # the solver check, dt part, at rest: halve dt (and double the iterations)
    base = settled_box.case.solver
    m1, k1 = _rest_readings(settled_box, base)
    m2, k2 = _rest_readings(settled_box, replace(base, iterations=2 * base.iterations, dt=base.dt / 2))
    tol = TARGETS["solver_sensitivity_rel_tol"]
    assert np.max(np.abs(m2 - m1) / m1) < tol and abs(k2 - k1) / k1 < tol


def test_snapshot_restores_the_contact_forces(settled_box):
    # a restored specimen carries the same wall load as the running one (warm-started
    # impulses), and two restores of the same bytes continue identically
    a, b = restore(settled_box.blob), restore(settled_box.blob)
    for s in (a, b):
        s.run(100)
    assert np.array_equal(a.state().position, b.state().position)
    run = _run_from(settled_box, window=0.02)
    r = run.reading()
    assert -(r.floor_fy + r.wall_fy + r.far_fy) / run.backfill.weight == pytest.approx(1.0, abs=0.01)
    st = run.sim.state()
    assert np.abs(st.velocity).max() < 0.01  # no collapse after the restart
