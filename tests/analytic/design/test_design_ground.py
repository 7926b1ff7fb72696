"""Design checks with a cohesive fill, a water table behind the wall and EN 1997-1
Annex C earth pressure, each against a hand calculation written out here."""

import math

import pytest

from analytic.design import (Backfill, CantileverWall, DesignCase, FillLayer, Foundation, GravityWall, Method, Water,
                             factors_of_safety, load_factors, verify)
from analytic.design.actions import wall_forces

F = load_factors()
r = math.radians
T30 = math.tan(r(30))
NQ30 = math.exp(math.pi * T30) * math.tan(r(60)) ** 2      # EN 1997-1 D.4, phi 30: 18.401
NG30 = 2 * (NQ30 - 1) * T30                                 # 20.093


def strip_q_ult(q: float, gamma: float, B_eff: float, V: float, H: float) -> float:
    """EN 1997-1 D.4, strip, c' = 0, phi 30, load inclined along B (m = 2):
    q' Nq (1 - H/V)^2 + 0.5 gamma' B' Ngamma (1 - H/V)^3 [kPa]."""
    return q * NQ30 * (1 - H / V) ** 2 + 0.5 * gamma * B_eff * NG30 * (1 - H / V) ** 3


def test_cantilever_cohesive_fill_DA2_by_hand():
    """Issue 29's cantilever (H 6, stem 0.5, toe 1.2, heel 3.0, base 0.7, 24 kN/m3;
    foundation 18 / 30 deg, delta_b = 0.6667 phi, D 0.7) with a fill 18 kN/m3, phi' 32,
    c' = 5 kPa, level, Rankine-Bell on the virtual back, DA2 (A1 + M1 + R2):
    Ka = tan^2(45 - 16) = 0.30726; sigma'_a = Ka gamma z - 2 c' sqrt(Ka);
    tension crack z0 = 2 c' / (gamma sqrt Ka) = 10 / (18 x 0.55431) = 1.00225 m, not
    counted; Pa = 0.5 Ka gamma (H - z0)^2 = 0.5 x 0.30726 x 18 x 4.99775^2 = 69.071 kN/m,
    horizontal, at (H - z0)/3 = 1.66592 m. Weights as in the dry case: V_k = 428.76 kN/m,
    M_W = 1193.616 kN m/m about the toe.
    Sliding: 1.35 Pa / (V_k tan(20.001) / 1.1) = 93.246 / 141.877 = 0.6572.
    Overturning: 1.35 Pa 1.66592 / M_W = 155.340 / 1193.616 = 0.13014.
    Bearing: the worse of the weights x 1.35 and x 1.0, R_d = q_ult B' / 1.4."""
    Ka = math.tan(r(29)) ** 2
    z0 = 2 * 5 / (18 * math.sqrt(Ka))
    Pa = 0.5 * Ka * 18 * (6 - z0) ** 2
    y = (6 - z0) / 3
    assert (z0, Pa) == pytest.approx((1.00225, 69.071), abs=5e-4)
    V_k, M_W = 428.76, 78.96 * 2.35 + 63.6 * 1.45 + 286.2 * 3.2
    H_d = 1.35 * Pa
    R_s = V_k * math.tan(r(0.6667 * 30)) / 1.1

    def bearing_u(gw):
        V = gw * V_k
        e = 2.35 - (gw * M_W - H_d * y) / V
        Bp = 4.7 - 2 * abs(e)
        return V / (strip_q_ult(18 * 0.7, 18, Bp, V, H_d) * Bp / 1.4)

    case = DesignCase(CantileverWall(6.0, 0.5, 0.5, 1.2, 3.0, 0.7, 24.0), Backfill(18, 32, 5),
                      Foundation(18, 30, 0, base_friction_ratio=0.6667, embedment=0.7))
    chk = {k: c for k, (_, c) in verify(case, F, "DA2").worst.items()}
    assert chk["sliding"].utilisation == pytest.approx(H_d / R_s, rel=1e-9)
    assert chk["sliding"].utilisation == pytest.approx(0.6572, abs=1e-4)
    assert chk["overturning"].utilisation == pytest.approx(H_d * y / M_W, rel=1e-9)
    assert chk["overturning"].utilisation == pytest.approx(0.13014, abs=1e-5)
    assert chk["bearing"].utilisation == pytest.approx(max(bearing_u(1.35), bearing_u(1.0)), rel=1e-9)


def gravity_case(fill: Backfill, method: str, **kw) -> DesignCase:
    """The trapezoid of test_design_published (H 4, crest 0.6, base 2.4, vertical back,
    24 kN/m3: W = 57.6 at x 2.1 + 86.4 at x 1.2 = 144 kN/m), delta 20 deg on the real
    back; foundation 18 / 30 deg, delta_b 20 deg, D 0.5 m."""
    return DesignCase(GravityWall(4.0, crest=0.6, base=2.4, back_batter=0.0, unit_weight=24), fill,
                      Foundation(18, 30, base_friction_angle=20, embedment=0.5),
                      method=Method(method, wall_friction=20), **kw)


def test_gravity_wall_water_table_factors_of_safety_by_hand():
    """The gravity wall with a water table 2 m above the base in a fill 18 / 20 (sat)
    kN/m3, phi' 30, Coulomb delta 20: Ka = 0.29731 (Das Table 6.4: 0.2973).
    sigma'_v: 18 z to 36 kPa at z = 2, then 36 + (20 - 9.81)(z - 2); its integral over
    4 m S = 36 + 72 + 20.38 = 128.38 kN/m, moment about the base (36 x 8/3 + 72 x 1 +
    20.38 x 2/3) -> y = 1.41445 m; Pa = Ka S = 38.169 kN/m, Ph = Pa cos 20 = 35.867,
    Pv = Pa sin 20 = 13.055 at x 2.4. Water: Uw = 0.5 x 9.81 x 2^2 = 19.62 kN/m at
    2/3 m; uplift 0 at the toe to 19.62 kPa at the heel: U = 23.544 kN/m at x 1.6.
    FS_o = (M_W + Pv 2.4) / (Ph y + Uw 2/3 + U 1.6) = 2.5223;
    FS_s = (144 + Pv - U) tan 20 / (Ph + Uw) = 0.87577;
    FS_b = q_ult B' / V with gamma' = 18 - 9.81 under the base (uplift there), q' = 9."""
    Ka = math.cos(r(30)) ** 2 / (math.cos(r(20)) * (1 + math.sqrt(math.sin(r(50)) * math.sin(r(30))
                                                                  / math.cos(r(20)))) ** 2)
    S = 0.5 * 18 * 2 ** 2 + 36 * 2 + 0.5 * (20 - 9.81) * 2 ** 2
    y = (36 * 8 / 3 + 72 * 1 + 0.5 * (20 - 9.81) * 4 * 2 / 3) / S
    Ph, Pv = Ka * S * math.cos(r(20)), Ka * S * math.sin(r(20))
    Uw, U = 0.5 * 9.81 * 4, 0.5 * 9.81 * 2 * 2.4
    M_W = 57.6 * 2.1 + 86.4 * 1.2
    V, H = 144 + Pv - U, Ph + Uw
    e = 1.2 - (M_W + Pv * 2.4 - U * 1.6 - Ph * y - Uw * 2 / 3) / V
    Bp = 2.4 - 2 * abs(e)
    case = gravity_case(Backfill(18, 30, gamma_sat=20), "coulomb", water=Water(behind=2.0))
    thrust = {f.name: f for f in wall_forces(case, F.combinations["FS"].materials)}
    assert thrust["earth thrust"].y == pytest.approx(y, rel=1e-9)
    assert (thrust["water thrust"].Fh, thrust["uplift"].Fv) == pytest.approx((Uw, -U), rel=1e-12)
    fs = factors_of_safety(verify(case, F, "fs"))
    assert fs["overturning"] == pytest.approx((M_W + Pv * 2.4) / (Ph * y + Uw * 2 / 3 + U * 1.6), rel=1e-9)
    assert fs["overturning"] == pytest.approx(2.5223, abs=1e-4)
    assert fs["sliding"] == pytest.approx(V * math.tan(r(20)) / H, rel=1e-9)
    assert fs["sliding"] == pytest.approx(0.87577, abs=1e-5)
    assert fs["bearing"] == pytest.approx(strip_q_ult(9, 18 - 9.81, Bp, V, H) * Bp / V, rel=1e-9)


def test_cantilever_water_table_weights_fill_at_gamma_sat():
    """Issue 29's cantilever, fill 18 / 20 (sat) kN/m3, phi 32, water 2.7 m above the
    base underside (2 m above the heel slab): fill over the heel 3.0 x (3.3 x 18 + 2 x 20)
    = 298.2 kN/m; Rankine on the virtual back: Ka (18 x 3.3^2 / 2 + 59.4 x 2.7 + (20 -
    9.81) x 2.7^2 / 2); water 0.5 x 9.81 x 2.7^2 = 35.758 kN/m; uplift 0.5 x 9.81 x 2.7 x
    4.7 = 62.245 kN/m at 2/3 of B from the toe."""
    Ka = (1 - math.sin(r(32))) / (1 + math.sin(r(32)))
    case = DesignCase(CantileverWall(6.0, 0.5, 0.5, 1.2, 3.0, 0.7, 24.0), Backfill(18, 32, gamma_sat=20),
                      Foundation(18, 30, 0, base_friction_ratio=0.6667, embedment=0.7), water=Water(behind=2.7))
    f = wall_forces(case, F.combinations["FS"].materials)
    fill = sum(x.Fv for x in f if x.name.startswith("fill over heel"))
    by = {x.name: x for x in f}
    assert fill == pytest.approx(3.0 * (3.3 * 18 + 2 * 20), rel=1e-12)
    assert by["earth thrust"].Fh == pytest.approx(Ka * (18 * 3.3 ** 2 / 2 + 59.4 * 2.7 + 10.19 * 2.7 ** 2 / 2),
                                                  rel=1e-12)
    assert by["water thrust"].Fh == pytest.approx(0.5 * 9.81 * 2.7 ** 2, rel=1e-12)
    assert (by["uplift"].Fv, by["uplift"].x) == pytest.approx((-0.5 * 9.81 * 2.7 * 4.7, 4.7 * 2 / 3), rel=1e-12)


def test_gravity_wall_annex_c_cohesion_DA2_by_hand():
    """The gravity wall, fill 18 kN/m3, phi' 30, c' 4 kPa, EN 1997-1 Annex C (active:
    phi -> -30, delta -> -20, beta = theta = 0), DA2:
    C.3: m_t = (acos 0 + 30)/2 = 60; C.4: m_w = (acos(sin 20 / sin 30) + 50)/2 = 48.4199;
    C.5: nu = 60 - 48.4199 = 11.5801 deg = 0.20211 rad;
    C.6: K_n = (1 - 0.5 sin 66.8398) / (1 + 0.5 sin 90) exp(-2 nu tan 30) = 0.28522;
    C.8: K_c = (K_n - 1) / tan(-30) = 1.23803; C.9: K_gamma = K_n.
    sigma'_n = K_n gamma z - K_c c': crack z0 = 4 K_c / (18 K_n) = 0.96457 m;
    N = 0.5 K_n 18 (4 - z0)^2 = 23.652 kN/m at (4 - z0)/3, shear N tan 20 = 8.6087 down
    the back at x 2.4; K along the thrust K_n / cos 20 = 0.30353.
    The thrust is unfavourable in sliding and overturning (x 1.35), the wall favourable:
    sliding 1.35 N / ((144 + 1.35 x 8.6087) tan 20 / 1.1) = 31.930 / 51.492 = 0.62010;
    overturning 1.35 N y / (144 x 1.56 + 1.35 x 8.6087 x 2.4) = 32.307 / 252.532 = 0.12793."""
    mw = 0.5 * (math.degrees(math.acos(math.sin(r(20)) / math.sin(r(30)))) + 50)
    nu = r(60 - mw)
    Kn = (1 - 0.5 * math.sin(r(2 * mw - 30))) / (1 + 0.5) * math.exp(-2 * nu * T30)
    Kc = (Kn - 1) / math.tan(r(-30))
    assert (mw, Kn, Kc) == pytest.approx((48.4199, 0.28522, 1.23803), abs=5e-5)
    z0 = 4 * Kc / (18 * Kn)
    N, y = 0.5 * Kn * 18 * (4 - z0) ** 2, (4 - z0) / 3
    Pv = N * math.tan(r(20))
    H_d = 1.35 * N
    res = verify(gravity_case(Backfill(18, 30, 4), "ec7-annex-c"), F, "DA2")
    chk = {k: c for k, (_, c) in res.worst.items()}
    assert res.combinations[0].K == pytest.approx(Kn / math.cos(r(20)), rel=1e-12)
    assert chk["sliding"].utilisation == pytest.approx(H_d / ((144 + 1.35 * Pv) * math.tan(r(20)) / 1.1), rel=1e-9)
    assert chk["sliding"].utilisation == pytest.approx(0.62010, abs=1e-5)
    M_stb = 144 * 1.56 + 1.35 * Pv * 2.4
    assert chk["overturning"].utilisation == pytest.approx(H_d * y / M_stb, rel=1e-9)
    assert chk["overturning"].utilisation == pytest.approx(0.12793, abs=1e-5)

    def bearing_u(gw):
        V = gw * 144 + 1.35 * Pv
        e = 1.2 - (gw * 144 * 1.56 + 1.35 * (Pv * 2.4 - N * y)) / V
        Bp = 2.4 - 2 * abs(e)
        return V / (strip_q_ult(9, 18, Bp, V, H_d) * Bp / 1.4)
    assert chk["bearing"].utilisation == pytest.approx(max(bearing_u(1.35), bearing_u(1.0)), rel=1e-9)


def test_annex_c_reduces_to_rankine_for_a_dry_level_fill():
    """EN 1997-1 Annex C with delta = beta = theta = 0 is Rankine's (1 - sin phi)/(1 +
    sin phi) (the Annex's own limit): on a cantilever's virtual back, every check of every
    format equals the 'rankine-virtual-back' result."""
    def case(method):
        return DesignCase(CantileverWall(6.0, 0.5, 0.5, 1.2, 3.0, 0.7, 24.0), Backfill(18, 32),
                          Foundation(18, 30, 0, base_friction_ratio=0.6667, embedment=0.7), method=Method(method))
    for fmt in ("DA1", "DA2", "DA3", "EQU", "fs"):
        a, b = verify(case("ec7-annex-c"), F, fmt), verify(case("rankine-virtual-back"), F, fmt)
        for k, (_, c) in b.worst.items():
            assert a.worst[k][1].utilisation == pytest.approx(c.utilisation, rel=1e-12), (fmt, k)


def test_block_wall_fill_with_water_table_base_joint_by_hand():
    """A rectangular block wall (h 3, b 1.2, no batter, level joints, joint friction 35,
    22 kN/m3: W = 79.2 kN/m) retaining a fill 18 / 20 (sat) kN/m3, phi 30, water 2 m
    above the base; Coulomb delta = 2/3 phi = 20 on the back (Ka = 0.29731).
    sigma'_v: 18 z to 18 kPa at z = 1 m, then 18 + 10.19 (z - 1): S = 9 + 36 + 20.38 =
    65.38 kN/m; Ph = Ka S cos 20, Pv = Ka S sin 20; water 0.5 x 9.81 x 2^2 = 19.62 kN/m;
    the joints drain (no uplift). Base joint, factors 1: FS sliding =
    (79.2 + 6.648) tan 35 / (18.266 + 19.62) = 1.58664."""
    from analytic.design.blocks import BlockWall
    Ka = math.cos(r(30)) ** 2 / (math.cos(r(20)) * (1 + math.sqrt(math.sin(r(50)) * math.sin(r(30))
                                                                  / math.cos(r(20)))) ** 2)
    S = 9 + 36 + 0.5 * 10.19 * 4
    Ph, Pv = Ka * S * math.cos(r(20)), Ka * S * math.sin(r(20))
    fs = (79.2 + Pv) * math.tan(r(35)) / (Ph + 19.62)
    case = DesignCase(BlockWall(3.0, 1.2, courses=10, joint_friction=35), Backfill(18, 30, gamma_sat=20),
                      water=Water(behind=2.0))
    base = verify(case, F, "fs").combinations[0].joints[0]["sliding"]
    assert base.R_d / base.E_d == pytest.approx(fs, rel=1e-9)
    assert fs == pytest.approx(1.58664, abs=1e-5)


def test_cantilever_layered_fill_factors_of_safety_by_hand():
    """Issue 29's cantilever with 2 m of fill 16 kN/m3, phi' 28 over fill 18 kN/m3, phi'
    32, c' 5 kPa down to the base; Rankine-Bell per layer on the virtual back (H 6):
    K1 = (1 - sin 28)/(1 + sin 28) = 0.36103, P1 = 0.5 K1 16 2^2 = 11.553 at 4 + 2/3 m;
    K2 = tan^2 29 = 0.30726; sigma' = K2 sigma'_v - 2 c' sqrt(K2): 4.2892 kPa under the
    interface (sigma'_v = 32), 26.412 kPa at the base (sigma'_v = 104): rectangle 17.157
    at 2 m + triangle 44.245 at 4/3 m; Ph = 72.955 kN/m at 2.01798 m.
    Weights: base 78.96 at 2.35, stem 63.6 at 1.45, fill 3 (2 x 16 + 3.3 x 18) = 274.2 at
    3.2: V = 416.76 kN/m, M_W = 1155.216 kN m/m.
    FS_o = M_W / (Ph y) = 7.8468; FS_s = V tan(20.001) / Ph = 2.0793."""
    K1 = (1 - math.sin(r(28))) / (1 + math.sin(r(28)))
    K2 = math.tan(r(29)) ** 2
    P1 = 0.5 * K1 * 16 * 4
    top, bot = K2 * 32 - 10 * math.sqrt(K2), K2 * 104 - 10 * math.sqrt(K2)
    Ph = P1 + top * 4 + 0.5 * (bot - top) * 4
    y = (P1 * (4 + 2 / 3) + top * 4 * 2 + 0.5 * (bot - top) * 4 * 4 / 3) / Ph
    assert (Ph, y) == pytest.approx((72.955, 2.01798), abs=5e-4)
    V, M_W = 78.96 + 63.6 + 274.2, 78.96 * 2.35 + 63.6 * 1.45 + 274.2 * 3.2
    case = DesignCase(CantileverWall(6.0, 0.5, 0.5, 1.2, 3.0, 0.7, 24.0),
                      Backfill(18, 32, 5, layers=(FillLayer(2.0, 16, 28),)),
                      Foundation(18, 30, 0, base_friction_ratio=0.6667, embedment=0.7))
    fs = factors_of_safety(verify(case, F, "fs"))
    assert fs["overturning"] == pytest.approx(M_W / (Ph * y), rel=1e-9)
    assert fs["overturning"] == pytest.approx(7.8468, abs=1e-4)
    assert fs["sliding"] == pytest.approx(V * math.tan(r(0.6667 * 30)) / Ph, rel=1e-9)
    assert fs["sliding"] == pytest.approx(2.0793, abs=1e-4)


def test_two_identical_layers_equal_one_soil():
    """A layer of the same soil as the one below changes nothing (with a water table
    crossing the interface and c' > 0): every DA1 utilisation equal to 1e-9."""
    def case(layers):
        return DesignCase(CantileverWall(6.0, 0.5, 0.5, 1.2, 3.0, 0.7, 24.0),
                          Backfill(18, 32, 5, gamma_sat=20, layers=layers),
                          Foundation(18, 30, 0, base_friction_ratio=0.6667, embedment=0.7), water=Water(behind=3.5))
    a = verify(case((FillLayer(3.0, 18, 32, 5, 20),)), F, "DA1")
    b = verify(case(()), F, "DA1")
    for k, (_, c) in b.worst.items():
        assert a.worst[k][1].utilisation == pytest.approx(c.utilisation, rel=1e-9), k
