"""Every closed-form and arching theory for one wall, from Python.

    python examples/theory_table.py

Nadukuru & Michalowski's wall (H 3.1 m, gamma 16.7 kN/m3, phi 34, delta 24.7 deg):
prints K (along each method's thrust), Kh and the resultant height for each method.
"""

from analytic import Soil, Wall
from analytic.summary import theory_table


def run():
    """The theory rows for the paper's translation case (unit weight in N/m^3)."""
    soil = Soil(34.0, 16.7e3)
    wall = Wall(3.1, 24.7)
    return theory_table(soil, wall)


if __name__ == "__main__":
    for row in run():
        p = row.profile
        if p is not None:
            print(f"{row.name:>16}: K {p.K:.3f}  Kh {p.Kh:.3f}  h/H {p.height_over_H:.3f}")
        else:
            print(f"{row.name:>16}: n/a ({row.reason})")
