"""Material checks of the seismic deposit at the case's contact parameters (measured, not
tuned): Vs and f0 of both free-field columns of the prepared static state (paper: Vs
210 m/s, f0 5.8 Hz for the 9 m column) and phi from Hertz-Mindlin cubical triaxials at
35-140 kPa (paper: ~31 deg at porosity 0.40), at the case's rolling resistance and
across mu_r (and friction alone) to show how phi moves with it. Uses the static state
cached by ``wallsim compare seismic`` under ``--runs`` (prepares it if absent). See
studies/seismic/calibrate.py.

    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/seismic_material.py --runs runs \\
        --out docs/validation/seismic_material.json
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

import numba

from studies.runfolder import package_versions
from studies.seismic.case import SeismicCase
from studies.seismic.calibrate import shear_wave, triaxial
from studies.seismic.run import prepare


def main() -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--resolution", default="coarse")
    ap.add_argument("--runs", default="runs", help="root of the run folders (the static state's cache)")
    ap.add_argument("--triaxials", default="35:0.4,70:0.4,140:0.4,70:0.3,70:0.2,70:0,70:0:1.0",
                    help="triaxials as confining [kPa]:rolling resistance mu_r[:friction] (default friction: the "
                         "case's); each on a cube cut from a deposit rained as the model's")
    ap.add_argument("--particles", type=int, default=2000)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    case = SeismicCase(resolution=args.resolution)
    out = {"resolution": args.resolution, "grain_scale": case.scale, "numba_threads": numba.get_num_threads(),
           "contact": {"shear_modulus_Pa": case.shear_modulus, "poisson": case.poisson, "friction": case.friction,
                       "rolling_resistance": case.rolling_resistance, "damping_ratio": case.damping_ratio},
           "paper": {"Vs_m_per_s": 210.0, "f0_Hz": 5.8, "phi_deg": 31.0, "porosity": 0.40}}
    c0 = time.process_time()
    prep = prepare(case, Path(args.runs) / "seismic" / "cache")
    out["prepare_cpu_s"] = time.process_time() - c0
    out["deposit_porosity"] = prep.info["porosity"]
    for name, arrays, height in (("front", prep.columns[0], case.front_height),
                                 ("retained", prep.columns[1], case.retained_height)):
        c0 = time.process_time()
        out[f"column_{name}"] = shear_wave(case, arrays, height) | {"height_m_prototype": height * case.scale_N,
                                                                     "cpu_s": time.process_time() - c0}
        print(name, {k: out[f"column_{name}"][k] for k in ("f0_Hz_prototype", "Vs_from_f0_m_per_s")},
              flush=True)
    out["triaxial"] = []
    for item in args.triaxials.split(","):
        kpa, mu_r, *mu = (float(v) for v in item.split(":"))
        probe = dataclasses.replace(case, rolling_resistance=mu_r, friction=mu[0] if mu else case.friction)
        c0 = time.process_time()
        tx = triaxial(probe, confining=kpa * 1e3, particles=args.particles) | {
            "rolling_resistance": mu_r, "cpu_s": time.process_time() - c0}
        out["triaxial"].append(tx)
        print(kpa, mu_r, {k: tx[k] for k in ("phi_peak_deg", "phi_end_deg", "inner_porosity", "cpu_s")}, flush=True)
        if args.out:                                  # what is done so far survives an interruption
            Path(args.out).write_text(json.dumps(out, indent=1) + "\n")
    out["versions"] = package_versions()
    text = json.dumps(out, indent=1)
    if args.out:
        Path(args.out).write_text(text + "\n")
    return out


if __name__ == "__main__":
    main()
