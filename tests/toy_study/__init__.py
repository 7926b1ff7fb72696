"""A toy study, to show that a new study is one package plus one registry line: the
Rankine active pressure behind a smooth vertical wall as a run with its folder, its CSV
and its result (``tests/test_toy_study.py`` registers it as ``studies.toy``). The
study record is ``STUDY``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from analytic.schema import check_fields, param
from studies.runner import closing_line, finish, open_run_folder
from studies.study import Command, Option, Study


@dataclass(frozen=True)
class ToyCase:
    """A smooth vertical wall retaining a dry cohesionless fill with a level surface."""

    H: float = param(3.0, unit="m", lo=0, hi=100, lo_open=True, meaning="retained height")
    phi_deg: float = param(30.0, unit="deg", lo=0, hi=60, lo_open=True, hi_open=True,
                           meaning="friction angle of the fill")
    gamma_kN_m3: float = param(18.0, unit="kN/m^3", lo=0, hi=100, lo_open=True, meaning="unit weight of the fill")
    points: int = param(11, lo=2, hi=10_000, meaning="depths at which the pressure is written")

    def __post_init__(self):
        check_fields(self)


def run_toy(case: ToyCase, root) -> tuple[dict, object]:
    """Rankine's active state: K = (1 - sin phi) / (1 + sin phi), sigma_h = K gamma z,
    thrust K gamma H^2 / 2 at H / 3 above the base."""
    folder = open_run_folder("toy", case, root, seed=None)
    K = (1 - math.sin(math.radians(case.phi_deg))) / (1 + math.sin(math.radians(case.phi_deg)))
    z = np.linspace(0.0, case.H, case.points)
    folder.write_csv("profile.csv", ["depth_m", "sigma_h_kPa"], zip(z, K * case.gamma_kN_m3 * z))
    result = {"case": "toy", "K": K, "thrust_kN_per_m": 0.5 * K * case.gamma_kN_m3 * case.H ** 2,
              "resultant_height_over_H": 1.0 / 3.0, "run_folder": str(folder.path)}
    finish(folder, result)
    return result, folder.path


def _compare(case: ToyCase, opts: SimpleNamespace) -> tuple[dict, str]:
    result, folder = run_toy(case, opts.out)
    return result, closing_line(result, folder)


COMPARE = Command(
    verb="compare", help="toy: Rankine's active pressure behind a smooth wall",
    description="The Rankine active pressure of a level dry fill on a smooth vertical wall.",
    default_case=ToyCase, run=_compare, text=lambda r: f"K {r['K']:.4f}, thrust {r['thrust_kN_per_m']:.2f} kN/m",
    seed_key=None,
    options=(Option("--phi", "friction angle [deg] (30)", key="phi_deg"),))

STUDY = Study(name="toy", title="A toy study (Rankine's active state)", commands=(COMPARE,))
