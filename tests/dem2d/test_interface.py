"""Constant-normal-load interface shear test (studies.elements.interface), reduced size
(0.30 x 0.15 m, ~96 grains, 0.02 m/s), against statics and Coulomb:

* the face carries the applied normal load: N = sigma_n L + weight of grains and lid
  within 1 % (frictionless box sides and lid carry no vertical load);
* on a flat rigid face every grain contact slides once the face moves, so the global
  interface angle equals the local one, tan(delta) = mu_fb (Coulomb), within 0.5 deg;
  with a frictionless face it is 0. (S-OET's 25 -> 37.7 deg comes from the bumpy face of
  their disk-clump blocks; a flat face cannot give it: see the module docstring.)
"""

import pytest

from analytic.errors import InvalidParameter
from dem2d.gravel import Gravel
from studies.elements.interface import InterfaceShear, ShearCase


def _case(phi_i):
    return ShearCase(gravel=Gravel(interface_friction_deg=phi_i), length_m=0.30, height_m=0.15,
                     speed_m_s=0.02, displacement_m=0.01, seed=1, place_s=0.5,
                     load_s=0.25)


@pytest.mark.parametrize("phi_i", [25.0, 0.0])
def test_flat_face_global_angle_is_the_local_one_and_carries_the_load(phi_i):
    box = InterfaceShear(_case(phi_i)).build()
    late = box.shear(readings=5)[-2:]        # past the first 4 mm: sliding established
    for r in late:
        assert r.normal == pytest.approx(box.applied_normal(), rel=0.01)
        assert r.angle_deg == pytest.approx(phi_i, abs=0.5)


def test_gap_wider_than_the_smallest_grain_is_refused():
    with pytest.raises(InvalidParameter, match="gap"):
        ShearCase(gap_m=0.02)
