"""Property tests required by issue 29, and block-wall joint checks against the
dry-stone reference's closed forms (drystone-walls.md 5.4)."""

import copy
import dataclasses
import math
import tomllib
from importlib import resources

import numpy as np
import pytest

from analytic.design import (Backfill, CantileverWall, DesignCase, Factors, Foundation, Loads, Method, Seismic,
                             Water, factors_of_safety, load_factors, verify)
from analytic.design.blocks import BlockWall, critical_water_height
from analytic.design.checks import base_pressure
from analytic.design.sizing import solve

F = load_factors()


def wall_case(heel=3.0, beta=0.0, q=10.0, **method) -> DesignCase:
    return DesignCase(CantileverWall(6.0, 0.4, 0.6, 1.0, heel, 0.6, 24.0, back_batter=0.1), Backfill(19, 32, 0, beta),
                      Foundation(18, 30, 0, embedment=0.8), Loads(q), method=Method(**method))


def unit_factors() -> Factors:
    """The package's table with every partial factor set to 1 (Q_fav stays 0)."""
    data = tomllib.loads(resources.files("analytic.design").joinpath("factors/ec7.toml").read_text())
    data = copy.deepcopy(data)
    for group in ("actions", "materials", "resistances"):
        for s in data[group].values():
            for k in s:
                s[k] = 0.0 if k == "Q_fav" else 1.0
    return Factors.from_dict(data)


@pytest.mark.parametrize("beta", [0.0, 15.0])
@pytest.mark.parametrize("fmt", ["DA1", "DA2", "DA3"])
def test_unit_factors_give_reciprocal_factors_of_safety(fmt, beta):
    """Every factor 1: utilisation = 1 / FS for sliding, overturning and bearing."""
    case = wall_case(beta=beta, passive=True)
    fs = factors_of_safety(verify(case, F, "fs"))
    res = verify(case, unit_factors(), fmt)
    for name in ("sliding", "overturning", "bearing"):
        assert res.worst[name][1].utilisation == pytest.approx(1 / fs[name], rel=1e-12), name


@pytest.mark.parametrize("fmt", ["DA1", "DA2", "DA3", "fs"])
@pytest.mark.parametrize("single_source", [False, True])
def test_longer_heel_never_raises_sliding_utilisation(fmt, single_source):
    """Level fill: each extra 0.2 m of heel adds fill weight and leaves the thrust."""
    u = [verify(wall_case(heel=h, single_source=single_source), F, fmt).worst["sliding"][1].utilisation
         for h in np.arange(0.5, 5.01, 0.2)]
    assert all(b <= a + 1e-12 for a, b in zip(u, u[1:])), u


@pytest.mark.parametrize("e_over_B", [0.0, 0.05, -0.1, 1 / 6, 0.25, -0.3, 0.45])
def test_base_pressure_integrates_to_V_and_e(e_over_B):
    B, V = 3.0, 400.0
    x, q = base_pressure(V, e_over_B * B, B, n=20001)
    assert np.trapezoid(q, x) == pytest.approx(V, rel=1e-6)
    x_R = np.trapezoid(q * x, x) / V
    assert B / 2 - x_R == pytest.approx(e_over_B * B, abs=1e-5)
    assert q.min() >= 0


def test_fs_format_passes_at_the_required_factors():
    """'fs': utilisation = FS_required / FS (1.5 sliding, 2.0 overturning, 3.0 bearing)."""
    res = verify(wall_case(), F, "fs")
    fs = factors_of_safety(res)
    for k, req in (("sliding", 1.5), ("overturning", 2.0), ("bearing", 3.0)):
        assert res.worst[k][1].utilisation == pytest.approx(req / fs[k], rel=1e-12)


@pytest.mark.parametrize("fmt", ["DA1", "DA2", "fs"])
def test_solve_heel_gives_unit_utilisation(fmt):
    case = solve(wall_case(heel=1.0), F, fmt, "heel")
    assert verify(case, F, fmt).governing[2] == pytest.approx(1.0, abs=1e-3)
    shorter = case.replace_wall(case.wall.with_dimension("heel", case.wall.heel - 0.01))
    assert verify(shorter, F, fmt).governing[2] > 1.0


def test_seismic_at_zero_acceleration_is_the_static_check():
    """alpha = 0: the seismic format equals a static check with unit action and
    resistance factors and the EN 1998-5 3.1(3) material factors (phi 1.25)."""
    case = dataclasses.replace(wall_case(q=0.0), seismic=Seismic(alpha=0.0))   # a [seismic] table, alpha 0
    seis = verify(case, F, "seismic").worst
    data = tomllib.loads(resources.files("analytic.design").joinpath("factors/ec7.toml").read_text())
    data["combinations"]["FS"]["materials"] = "SEISMIC"
    data["formats"]["static"] = ["FS"]
    static = verify(case, Factors.from_dict(data), "static").worst
    for k in ("sliding", "overturning", "bearing"):
        assert seis[k][1].utilisation == pytest.approx(static[k][1].utilisation, rel=1e-12)
        assert seis[k][1].utilisation > 1 / factors_of_safety(verify(case, F, "fs"))[k]


def test_seismic_kh_kv_from_en1998_5():
    """k_h = alpha S / r = 0.25 x 1.2 / 2 = 0.15; a_vg/a_g = 0.9 > 0.6 -> k_v = 0.075."""
    from analytic.design import Seismic
    s = Seismic(alpha=0.25, S=1.2, r=2.0)
    assert s.kh == pytest.approx(0.15) and s.kv == pytest.approx(0.075)
    assert Seismic(alpha=0.25, S=1.2, r=2.0, vertical_ratio=0.45).kv == pytest.approx(0.33 * 0.15)
    case = DesignCase(wall_case().wall, Backfill(19, 32), Foundation(18, 30, embedment=0.8), seismic=s)
    res = verify(case, F, "seismic")
    assert {r.kv for r in res.combinations} == {0.075, -0.075}


def test_block_wall_sliding_water_height_matches_closed_form():
    """drystone-walls.md 5.4: with water, h_w,S = y_I + sqrt(2 W tan(alpha + phi_b) /
    (gamma_w (1 - tan lambda2 tan(alpha + phi_b)))) at the base joint (y_I < 0: the heel
    is lower). Section: h 3, b 1.2, lambda1 0, lambda2 5, alpha 5, phi_b 25, 22 kN/m3.
    W by hand: trapezoid above y = 0 of widths 1.2 and 1.2 - 3 tan 5, plus the triangle
    between y = 0 and the base plane with apex at the heel."""
    t2, ta = math.tan(math.radians(5)), math.tan(math.radians(5))
    b, h = 1.2, 3.0
    x_h = b / (1 - ta * t2)
    y_h = -x_h * ta
    area = (b + b - h * t2) / 2 * h + 0.5 * b * abs(y_h)
    W = 22 * area
    T = math.tan(math.radians(30))
    hw = y_h + math.sqrt(2 * W * T / (9.81 * (1 - t2 * T)))
    wall = BlockWall(h, b, 0.0, 5.0, courses=10, joint_slope=5.0, joint_friction=25.0, unit_weight=22)
    got, mech, z = critical_water_height(DesignCase(wall, None), F.combinations["FS"])
    assert (mech, z) == ("sliding", 0.0)
    assert got == pytest.approx(hw, abs=1e-5)


def test_block_wall_toppling_water_height_by_hand():
    """Rectangle h 2, b 0.6, no batter, alpha 0, phi_b 45 (sliding cannot govern): the
    whole wall topples about the toe when gamma_w h_w^3 / 6 = W b / 2, W = 22 x 2 x 0.6;
    the base joint governs (upper joints carry less water per unit of weight)."""
    W = 22 * 2 * 0.6
    hw = (6 * W * 0.3 / 9.81) ** (1 / 3)
    wall = BlockWall(2.0, 0.6, 0.0, 0.0, courses=8, joint_friction=45.0, unit_weight=22)
    got, mech, z = critical_water_height(DesignCase(wall, None), F.combinations["FS"])
    assert (mech, z) == ("overturning", 0.0)
    assert got == pytest.approx(hw, abs=1e-5)


def test_block_wall_checks_every_joint_with_backfill():
    wall = BlockWall(3.0, 1.5, 10.0, 0.0, courses=6, joint_slope=3.0, joint_friction=35.0, unit_weight=22)
    res = verify(DesignCase(wall, Backfill(18, 34), Foundation(19, 32, embedment=0.3)), F, "DA1")
    lead = res.combinations[0]
    assert len(lead.joints) == 6
    assert {"sliding", "overturning", "bearing", "eccentricity"} <= set(res.worst)
    assert res.worst["sliding"][1].utilisation == max(
        r["sliding"].utilisation for c in res.combinations for r in c.joints)


def test_solve_toe_and_base_and_all_formats():
    """--solve toe on a cantilever, base on a gravity wall, and heel against several
    formats at once: the governing utilisation over them all is 1 within 1e-3."""
    from analytic.design import GravityWall
    c = solve(wall_case(heel=2.0, q=0.0), F, "fs", "toe")
    assert verify(c, F, "fs").governing[2] == pytest.approx(1.0, abs=1e-3)
    g = DesignCase(GravityWall(4.0, crest=0.6, base=1.0), Backfill(18, 30), Foundation(18, 30, embedment=0.5),
                   method=Method("coulomb", wall_friction=20))
    g = solve(g, F, "DA1", "base")
    assert verify(g, F, "DA1").governing[2] == pytest.approx(1.0, abs=1e-3)
    both = solve(wall_case(heel=1.0), F, ["DA1", "DA2", "fs"], "heel")
    assert max(verify(both, F, f).governing[2] for f in ("DA1", "DA2", "fs")) == pytest.approx(1.0, abs=1e-3)


def test_polygon_gravity_wall_equals_its_trapezoid():
    """The same section as a polygon (either orientation) gives the same checks as the
    trapezoid on the virtual back; and Coulomb with delta = beta on that vertical back
    is Rankine's sloping-fill thrust (Mueller-Breslau with omega 0, delta = beta)."""
    from analytic.design import GravityWall
    trap = GravityWall(4.0, crest=0.6, base=2.4, back_batter=0.4)
    poly = GravityWall(0.0, polygon=((0, 0), (2.4, 0), (2.0, 4.0), (1.4, 4.0)))
    rev = GravityWall(0.0, polygon=((1.4, 4.0), (2.0, 4.0), (2.4, 0), (0, 0)))
    fill, fnd = Backfill(18, 30, 0, 10), Foundation(18, 30, embedment=0.5)
    ref = verify(DesignCase(trap, fill, fnd), F, "DA1").worst
    for w in (poly, rev):
        for m in (Method(), Method("coulomb", wall_friction=10.0)):
            got = verify(DesignCase(w, fill, fnd, method=m), F, "DA1").worst
            for k in ("sliding", "overturning", "bearing"):
                assert got[k][1].utilisation == pytest.approx(ref[k][1].utilisation, rel=1e-9), (w, m, k)


# drystone-walls.md 2.3: the case-A sections back-fitted with the reference's
# limit-equilibrium reconstruction (gamma_m 20, vertical inner face, alpha 0 except V5S
# 8.53 deg) and its predicted critical water heights: sliding / toppling [m] and mode.
CASE_A = [  # name, h, b, lambda1, alpha, phi_b, h_w sliding, h_w toppling, mode
    ("V1L", 2.0, 0.78, 15.0, 0.0, 36.0, 1.74, 1.81, "sliding"),
    ("V2L", 1.95, 0.70, 0.0, 0.0, 36.0, 2.01, 1.78, "overturning"),
    ("V3L", 4.0, 1.49, 15.0, 0.0, 36.0, 3.37, 3.51, "sliding"),
    ("V4L", 2.0, 0.78, 7.5, 0.0, 36.0, 1.96, 1.90, "overturning"),
    ("V5S", 4.25, 1.67, 15.0, 8.53, 28.5, 3.62, 3.87, "sliding"),
]


@pytest.mark.parametrize("name,h,b,l1,alpha,phi_b,hw_s,hw_t,mode", CASE_A, ids=[c[0] for c in CASE_A])
def test_block_walls_against_the_drystone_reference(name, h, b, l1, alpha, phi_b, hw_s, hw_t, mode):
    """With the reference's stair slope m = 2 x 0.125 / 0.30 = 0.83 (its DEM blocks),
    bed-joint sliding (its mechanism S, 5.4) and toppling over lines stepping through head
    joints (its mechanism T, 5.5) give its critical water heights to 0.5 % and its
    governing mechanism for all five walls. 0.5 % is what the table's rounding of b to
    0.01 m allows: dW/W up to 0.6 %, h_w ~ W^(1/2) (sliding) or ~ b^(2/3) (toppling).
    V2L's sliding height, 2.01 m, is above its 1.95 m crest: the wall must stand in
    sliding with water to the crest. The design default (m = 0, bed joints only) is a
    narrower set of mechanisms, so its toppling height can only be higher."""
    wall = BlockWall(h, b, l1, 0.0, courses=10, joint_slope=alpha, joint_friction=phi_b, unit_weight=20,
                     stair_slope=0.83)
    case, fs = DesignCase(wall, None), F.combinations["FS"]
    got_s = critical_water_height(case, fs, mechanisms=("sliding",))[0]
    if hw_s > h:
        assert got_s == math.inf
    else:
        assert got_s == pytest.approx(hw_s, rel=5e-3)
    assert critical_water_height(case, fs, mechanisms=("overturning",))[0] == pytest.approx(hw_t, rel=5e-3)
    assert critical_water_height(case, fs)[1] == mode
    bed_only = DesignCase(dataclasses.replace(wall, stair_slope=0.0), None)
    assert critical_water_height(bed_only, fs, mechanisms=("overturning",))[0] >= hw_t * (1 - 5e-3)
