"""A translating wall in 3D DEM beside the paper and the theories, from Python.

    python examples/nadukuru_translation.py

Nadukuru & Michalowski's 3.1 m wall with a reduced specimen (2,000 spheres and
clumps, grains scaled up to fill the same box), rained, settled and translated to
Delta/H = 0.008 (about half a minute on 2 cores). The run folder (CSV, figures,
config.toml, manifest.json) goes under ``runs/``.
"""

from studies import get


def run(out="runs"):
    """The study's result dict for the reduced translation case (seed 3)."""
    nadukuru = get("nadukuru")
    case = nadukuru.case(mode="T", particles=2000, seed=3)
    return nadukuru.run(case, out=out, no_rrd=True)


if __name__ == "__main__":
    r = run()
    dem, paper = r["dem"], r["paper"]
    print(f"{r['particles']} spheres, porosity {dem['porosity']:.3f}")
    print(f"DEM   K {dem['K']:.3f}  h/H {dem['resultant_height_over_H']:.3f}")
    print(f"paper K {paper['K']:.3f}  h/H {paper['resultant_height_over_H']:.3f}  ({paper['source']})")
    for t in r["theory"]:
        if t["K"] is not None:
            print(f"{t['name']:>15} K {t['K']:.3f}  h/H {t['resultant_height_over_H']:.3f}")
    print(f"run folder: {r['run_folder']}")
