"""Closed-form and arching theories of earth pressure on retaining walls.

Every method takes the frozen ``Soil`` and ``Wall`` records and returns a ``Profile``.
Bad input raises ``InvalidParameter`` (a ``ValueError``) naming the parameter and the
range where the method has a real solution.
"""

from .errors import InvalidParameter
from .inputs import Soil, Wall
from .profile import Profile
from .classical import coulomb, jaky, janssen, rankine, trial_wedge

__all__ = ["InvalidParameter", "Soil", "Wall", "Profile", "rankine", "coulomb", "jaky",
           "janssen", "trial_wedge"]
