"""Holding settled grains static during pluviation (``Sim.hold`` / ``release_all``).

References: statics (the floor and walls carry the whole weight once the grains are
released and settle), rigid-body kinematics (a held grain does not move), and the
mass of a disk, rho pi r^2 per metre of wall.
"""

import dataclasses

import numpy as np

from dem2d.pluviation import Pluviation
from studies.khosravi.run import KhosraviRun
from dem2d.sim import restore

from .test_determinism import TINY, checkpoint_after_layer


def _weight_balance(run: KhosraviRun) -> float:
    r = run.reading(0.01)
    return -(r.floor_fy + r.wall_fy + r.far_fy) / run.backfill.weight


def test_held_grains_stay_put_and_carry_their_contacts_back():
    run = KhosraviRun(TINY)
    for _ in run.fill():
        pass
    sim = restore(run.sim.snapshot())
    run = KhosraviRun(TINY, sim=sim)
    st = sim.state()
    r = sim.grains.circle_radius
    low = np.flatnonzero(st.position[:, 1] < 0.5 * run.backfill.H)
    assert sim.hold(low) == len(low) > 50
    sim.run(200)
    held = sim.state()
    assert np.array_equal(held.position[low], st.position[low])  # static: not one bit moved
    assert sim.release_all() == len(low)
    # disks: mass = rho pi r^2 (per metre of wall), as before they were held
    assert np.allclose(sim.masses(), TINY.material.density * np.pi * r**2, rtol=1e-12)
    sim.run(int(0.05 / sim.dt))
    assert abs(_weight_balance(run) - 1.0) <= 1e-2
    moved = np.linalg.norm(sim.state().position[low] - st.position[low], axis=1)
    assert np.median(moved) < 0.02 * r.min()  # released with their impulses: no collapse


def test_fill_with_held_layers_balances_its_weight():
    case = dataclasses.replace(TINY, H=0.09, pluviation=dataclasses.replace(
        TINY.pluviation, hold_depth=0.015, layer_dt=4e-4, final_settle_time=1.0, final_balance=0.005))
    run = KhosraviRun(case)
    statuses = []
    held_counts = []
    for s in run.fill():
        if s.done:
            statuses.append(s)
            held_counts.append(int(run.sim.held().sum()))
    # settled by statics: floor + wall reactions over the last check window = weight (0.5 %)
    assert statuses[-1].settled and abs(statuses[-1].balance - 1.0) < 0.005
    assert max(held_counts) > 0 and held_counts[-1] == 0  # held while filling, all free at the end
    assert run.sim.dt == case.solver.dt                   # the last layer settled at the solver's dt
    assert abs(_weight_balance(run) - 1.0) <= 1e-2
    # the cells below the held grains are blanked in the backfilling readings
    assert any(np.isnan(sig).any() for _, _, sig in run.backfill.layer_readings)


def test_hold_settings_are_checked():
    import pytest

    from analytic.errors import InvalidParameter

    with pytest.raises(InvalidParameter, match="hold_depth"):
        Pluviation(hold_depth=-0.01)
    with pytest.raises(InvalidParameter, match="layer_dt"):
        Pluviation(layer_dt=0.0)
    with pytest.raises(InvalidParameter, match="final_balance"):
        Pluviation(final_balance=1.5)


def test_a_fill_resumed_mid_way_ends_at_the_solvers_dt():
    # a checkpoint taken while the layers run at layer_dt must not carry that dt into
    # the final settle and the readings after it
    case = dataclasses.replace(TINY, H=0.09, pluviation=dataclasses.replace(
        TINY.pluviation, hold_depth=0.015, layer_dt=4e-4))
    mid = restore(checkpoint_after_layer(case, 2))
    assert mid.dt == 4e-4  # the checkpoint was taken while the layers ran at layer_dt
    resumed = KhosraviRun(case, sim=mid)
    for _ in resumed.fill():
        pass
    assert resumed.sim.dt == case.solver.dt == 2e-4
