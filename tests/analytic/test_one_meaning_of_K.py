"""One meaning of K in every row of the theory table (issue 40): the soil coefficient
2 P(q = 0) / (gamma H^2), whatever the surcharge; the surcharge's thrust is reported
apart (extra['thrust_q']), so P(q) = P(0) + thrust_q. Before, `theory --q 10` gave
Coulomb K 0.2542 and Mononobe-Okabe K 0.3524 for the same 28.28 kN/m thrust (M-O and the
arching rows folded q into K)."""

from dataclasses import replace

import pytest

from analytic import Soil, Wall
from analytic.summary import theory_table


@pytest.mark.parametrize("kh", [0.0, 0.1])
def test_every_row_keeps_the_soil_coefficient_with_a_surcharge(kh):
    soil = Soil(34.0, 16.7e3)
    loaded = Wall(3.1, 24.7, 0.0, 0.0, 10e3)
    bare = replace(loaded, surcharge=0.0)
    with_q = {r.name: r.profile for r in theory_table(soil, loaded, kh=kh)}
    without = {r.name: r.profile for r in theory_table(soil, bare, kh=kh)}
    checked = 0
    for name, p in with_q.items():
        if p is None:
            continue
        p0 = without[name]
        assert p.K == pytest.approx(p0.K, rel=1e-12), name
        assert p.Kh == pytest.approx(p0.Kh, rel=1e-12), name
        assert p.thrust == pytest.approx(p0.thrust + p.extra["thrust_q"], rel=1e-9), name
        assert p.extra["thrust_q"] > 0, name
        checked += 1
    assert checked >= 9 + (kh > 0)          # the classical, seismic and arching rows


def test_mononobe_okabe_without_inertia_is_coulomb_with_the_surcharge():
    """kh = kv = 0: K_AE = K_A, so the M-O row equals the Coulomb row, K and thrust."""
    rows = {r.name: r.profile for r in theory_table(Soil(34.0, 16.7e3), Wall(3.1, 24.7, 0.0, 0.0, 10e3))}
    mo, co = rows["mononobe-okabe"], rows["coulomb"]
    assert mo.K == pytest.approx(co.K, rel=1e-9) and mo.thrust == pytest.approx(co.thrust, rel=1e-9)
    assert mo.extra["thrust_q"] == pytest.approx(co.extra["thrust_q"], rel=1e-9)
