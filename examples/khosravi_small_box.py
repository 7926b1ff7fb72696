"""Khosravi et al.'s box in 2D DEM at a tiny size, from Python: the fill, the at-rest
reading and a short translation, with a look at a case setting through ``case()``.

    python examples/khosravi_small_box.py

H = 0.1 m with grains 5x the paper's (756 disks), the wall moved to Dis/H = 0.001
(seconds). Coarse grains: the figures are not the paper's (the full-size report is
docs/validation/khosravi.md); this shows the API.
"""

from studies import get


def run(out="runs"):
    """The study's result dict for the tiny box."""
    khosravi = get("khosravi")
    case = khosravi.case(H=0.1, particles_scale=5, wall_disp_over_H_max=0.001)
    return khosravi.run(case, out=out)


if __name__ == "__main__":
    r = run()
    d = r["dem"]
    print(f"{r['particles']} disks, porosity {r['porosity']:.3f}, phi (biaxial) {d['phi_biaxial']:.1f} deg")
    print(f"at rest: K upper half {d['K_at_rest_upper_half']:.3f} vs Jaky {d['jaky_K0']:.3f}")
    print(f"active thrust at Dis/H {r['wall_disp_over_H_active']:.4f}: {d['active_thrust_over_rankine']:.3f} x Rankine")
