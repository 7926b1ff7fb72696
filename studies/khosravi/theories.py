"""The theories Khosravi et al. set beside their DEM (section 4, Figs. 10-13): Jaky at
rest; Rankine, Handy, Paik-Salgado and Khosravi active. Closed forms only (analytic/),
so the report and its scorecard can evaluate them without the engine."""

from __future__ import annotations

from analytic import Soil, Wall, jaky, rankine
from analytic.arching import handy, khosravi, paik_salgado


def theories(phi_deg: float, gamma: float, H: float) -> dict:
    """Jaky (at rest) and Rankine, Handy, Paik-Salgado, Khosravi (active) for a fully
    rough wall (delta = phi) and the DEM's phi [deg], unit weight [N/m^3] and H [m]."""
    soil = Soil(phi_deg, gamma)
    wall = Wall(H, delta_deg=phi_deg)
    return {"jaky": jaky(soil, Wall(H)), "rankine": rankine(soil, Wall(H)), "handy": handy(soil, wall),
            "paik-salgado": paik_salgado(soil, wall), "khosravi": khosravi(soil, wall)}
