"""``calibrate gravel`` at reduced size: a 0.3 x 0.6 m biaxial specimen of coarse capsules
(about 220 grains) and a 0.3 x 0.15 m interface box (about 100 grains).

References: the biaxial test's stress boundary holds sigma_3 = 35 kPa (its definition;
S-OET's representative stress); a mobilised peak is never below the critical state;
Coulomb on a flat face bounds the global interface angle by the local one,
tan(global) = T / N <= mu (every grain-face contact obeys |t_i| <= mu n_i); the face
carries the applied normal load sigma_n L plus the weights (statics, within 1 %);
``choose`` interpolates linearly where two tests bracket the target; ``choose_both``
minimises the sum of the squared misfits to the peak and critical-state targets (its
minimum by hand below).
"""

import math

import numpy as np
import pytest

from dem2d.gravel import Gravel
from studies import get
from studies.gravel.calibrate import choose, choose_both


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("gravel")
    cmd = get("gravel").commands[0]
    plan = cmd.resolve(sets=["frictions_deg=45", "seeds=1", "interface_frictions_deg=25",
                             "grain_friction_deg=45", "biaxial.width=0.35", "biaxial.height=0.7",
                             "biaxial.max_strain=0.06", "shear.length_m=0.3", "shear.height_m=0.15",
                             "shear.displacement_m=0.006", "gravel.width_min_m=0.015", "gravel.width_max_m=0.024"])
    res, _ = cmd.run(plan, cmd.run_options(out=str(out), docs=str(out / "docs")))
    return res, out


def test_biaxial_holds_sigma_3_and_peak_above_critical(result):
    res, _ = result
    t = res["biaxial"]["tests"][0]
    s3 = np.array(t["curve"]["sigma_3"][5:])
    assert np.mean(s3) == pytest.approx(35e3, rel=0.02)
    assert t["phi_peak_deg"] >= t["phi_cs_deg"]
    assert 0.0 < t["porosity"] < 0.5


def test_interface_angle_bounded_by_local_friction_and_load_carried(result):
    res, _ = result
    t = res["interface"]["tests"][0]
    assert t["global_angle_deg"] <= 25.0 + 0.05          # Coulomb bound on a flat face
    assert t["normal_N_m"] == pytest.approx(t["applied_normal_N_m"], rel=0.01)


def test_report_names_paper_and_our_local_values(result):
    _, out = result
    text = (out / "docs" / "gravel_calibration.md").read_text()
    assert "| grain-grain friction | 45 deg |" in text and "| fill-block (interface) friction | 25 deg |" in text
    assert (out / "docs" / "gravel_calibration" / "biaxial.png").is_file()


def test_choose_interpolates_between_bracketing_tests():
    assert choose([45, 60, 75], [33.8, 36.3, 37.9], 37.7)["value_deg"] == round(60 + 15 * 1.4 / 1.6, 1)
    far = choose([25, 45], [21.0, 31.0], 37.7)
    assert far["reached"] is False and far["value_deg"] == 45 and math.isclose(far["closest_global_deg"], 31.0)


def test_choose_both_minimises_the_two_misfits():
    """Peaks 36, 37, 38 and critical states 32, 32, 30 at 40, 50, 60 deg, targets 37.7 / 32:
    on [50, 60] with t = x - 50 the misfit is (0.1 t - 0.7)^2 + (0.2 t)^2, least at
    t = 0.14 / 0.10 = 1.4 (on [40, 50] the least is 0.49 at 50, above 0.392 at 51.4)."""
    c = choose_both([40, 50, 60], [36.0, 37.0, 38.0], [32.0, 32.0, 30.0], 37.7, 32.0)
    assert c["value_deg"] == pytest.approx(51.4)
    assert c["phi_peak_deg"] == pytest.approx(37.14) and c["phi_cs_deg"] == pytest.approx(31.72)
    assert c["reached"] is False            # 0.56 deg from the peak target
