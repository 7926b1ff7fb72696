"""``Profile``: the one result record that every theory and every DEM run returns.

Sign convention (stated once, used everywhere, printed by the CLI):

* ``sigma_h`` is the normal stress the backfill exerts on the back face, compression
  positive, in Pa. For a vertical wall it is the horizontal stress.
* ``tau`` is the shear stress on the face, positive when the backfill drags the wall
  *down* the face (the active case: the wedge settles relative to the wall).
* ``z`` is depth below the top of the wall, in m, 0 <= z <= H.
* ``height`` is the height of the resultant's line of action above the base, in m,
  taken from the normal-stress distribution: h = H - int(sigma_h z dz) / int(sigma_h dz).
* ``thrust`` is the resultant force per metre of wall along the method's own direction
  (Coulomb: at delta to the face normal; Rankine: parallel to the backfill surface), N/m.
  ``K = 2 thrust / (gamma H^2)`` and ``Kh`` is its horizontal component.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import trapezoid


@dataclass(frozen=True)
class Profile:
    """Wall load distribution and its resultant.

    method:     short name ("rankine", "coulomb", "dsm", "dem", ...)
    z:          (n,) depth below the wall top [m]
    sigma_h:    (n,) normal stress on the face [Pa], compression positive
    tau:        (n,) shear stress on the face [Pa], positive down the face on the wall
    thrust:     resultant per metre of wall along the method's direction [N/m]
    thrust_h:   horizontal component of the resultant [N/m]
    height:     height of the resultant above the base [m]
    K:          2 thrust / (gamma H^2) (the method's own coefficient); for the linear
                methods (Rankine, Coulomb, Jaky, EC7, log-spiral) with a surcharge, still the
                soil coefficient, the surcharge's thrust being ``extra['thrust_q']``
    Kh:         horizontal part of K
    H:          wall height [m]
    omega_deg:  back-face inclination from vertical [deg]; stresses act per unit face
                length, and a face element spans dz / cos(omega)
    source:     equation and paper the values follow
    status:     "verified" (checked against published numbers) or "reconstruction"
    notes:      anything a user must know before trusting the numbers
    """

    method: str
    z: np.ndarray
    sigma_h: np.ndarray
    tau: np.ndarray
    thrust: float
    thrust_h: float
    height: float
    K: float
    Kh: float
    H: float
    omega_deg: float = 0.0
    source: str = ""
    status: str = "verified"
    notes: str = ""
    extra: dict = field(default_factory=dict)

    @property
    def height_over_H(self) -> float:
        return self.height / self.H

    def normal_force(self) -> float:
        """Normal force on the face, int sigma_h ds = int sigma_h dz / cos(omega) [N/m]
        (trapezoid rule on the stored points)."""
        return float(trapezoid(self.sigma_h, self.z)) / math.cos(math.radians(self.omega_deg))

    def shear_force(self) -> float:
        """Shear force on the face, int tau ds [N/m], positive down the face."""
        return float(trapezoid(self.tau, self.z)) / math.cos(math.radians(self.omega_deg))

    def centroid_height(self) -> float:
        """Height above the base of the resultant of the stored sigma_h points [m]."""
        n = float(trapezoid(self.sigma_h, self.z))
        return float(self.H - trapezoid(self.sigma_h * self.z, self.z) / n)

    def as_dict(self) -> dict:
        return {
            "name": self.method,
            "K": self.K,
            "Kh": self.Kh,
            "thrust_kN_per_m": self.thrust / 1e3,
            "thrust_h_kN_per_m": self.thrust_h / 1e3,
            "resultant_height_over_H": self.height_over_H,
            "source": self.source,
            "status": self.status,
            **({"thrust_q_kN_per_m": self.extra["thrust_q"] / 1e3} if self.extra.get("thrust_q") else {}),
            **({"parts": self.extra["parts"]} if "parts" in self.extra else {}),
            **({"notes": self.notes} if self.notes else {}),
        }


def depth_grid(H: float, n: int = 201) -> np.ndarray:
    """Depths 0..H [m] with ``n`` points, for tabulating closed-form profiles."""
    return np.linspace(0.0, H, n)
