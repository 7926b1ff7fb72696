"""Is the seismic wall's first-second collapse static? The coarse static state (cached by
``wallsim compare seismic`` under runs/), 1 s (prototype) with the base at rest: "fixed"
(lateral boundaries held, no local damping) or "freefield" (the dynamic stage at amplitude
1e-9 g). Measured at b819ab0 ("fixed"): wall top 0.07 -> 0.57 m in 0.9 s, 72 s CPU.

    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/seismic_static_check.py fixed
"""
import sys, time, dataclasses, numpy as np
from pathlib import Path
from studies.seismic.case import SeismicCase
from studies.seismic.run import prepare, coupled, shake
from studies.seismic.measures import wall_reading
from studies.seismic import specimen as M
from dem3d import Simulation
mode = sys.argv[1] if len(sys.argv) > 1 else "fixed"
case = dataclasses.replace(SeismicCase(), amplitude_g=1e-9)
p = prepare(case, Path("runs/seismic/cache"))
x0 = np.array(p.info["x_wall_before_excavation"])
rows = p.model.wall_row
x0r = np.bincount(rows, weights=x0[:, 0]) / np.bincount(rows)
c0 = time.process_time()
if mode == "freefield":
    sh = shake(case, p, fraction=1.0 / 9.0)
    tops = [-(r.x[-1] - x0r[-1]) * 50 for r in sh.readings]
    print("free-field: top displacement [m proto] every 0.1 s:", [round(t, 3) for t in tops[::5]])
else:
    sim = Simulation.from_arrays(p.main, walls=M.boundary_walls(case))
    sim.set_params(M.contact_law(case, local_damping=0.0), allow_unsafe_dt=True)
    out = []
    for k in range(10):
        sim.evaluate_forces()
        r = wall_reading(sim, case, p.model)
        out.append(round(-(r.x[-1] - x0r[-1]) * 50, 3))
        sim.step(int(0.002 / sim.dt))
    print("fixed lateral boundaries, no local damping: top [m proto] every 0.1 s:", out)
print("cpu", time.process_time() - c0)
