"""`--set key=value`: bare names reach nested records when they are unique; a name that
two records share must be given with its record, and the error says which."""

import pytest

from analytic.errors import InvalidParameter
from studies.config import apply_sets
from studies.nadukuru.case import NadukuruCase


def test_bare_and_dotted_keys():
    case = apply_sets(NadukuruCase(), ["floor_friction=0.3", "movement.local_damping=0.7"])
    assert case.specimen.floor_friction == 0.3
    assert case.movement.local_damping == 0.7 and case.specimen.local_damping == 0.7


def test_shared_name_must_name_its_record():
    with pytest.raises(InvalidParameter) as err:
        apply_sets(NadukuruCase(), ["local_damping=0.5"])
    msg = str(err.value)
    assert "specimen.local_damping" in msg and "movement.local_damping" in msg and "\n" not in msg


def test_out_of_range_names_the_key():
    with pytest.raises(InvalidParameter, match=r"movement\.local_damping = '?1\.5'? .*\[0, 1\)"):
        apply_sets(NadukuruCase(), ["movement.local_damping=1.5"])
