"""Physical constants, each defined once. The papers and EN 1997 work with g = 9.81 m/s^2
and gamma_w = 9.81 kN/m^3 (not 9.80665), and so do we."""

#: gravitational acceleration [m/s^2]
G = 9.81
#: unit weight of water [kN/m^3] (the design and limit-equilibrium units: kN, m)
GAMMA_W = 9.81
#: unit weight of water [N/m^3] (SI, as the engines and the ground model work): GAMMA_W x 1000
GAMMA_WATER = 9810.0
