"""Where a case-B step goes (issue 24): one reduced fill (1.2 m wall, 1.0 m container, three
stages, about 1,360 grains, nothing held), then 400 steps of the same state at 10, 20,
40 and 80 sweeps, and the Python of one reading (kinetic energy and block positions).
Prints steps and body-steps per CPU second.

    PYTHONPATH=. python benchmarks/drystone_caseb_cost.py
"""
import time, copy
from analytic.drystone import WallSection
from studies.drystone.backfill import BackfilledWall, FillPlan
from dem2d.blocks import BlockSolver, Masonry
from dem2d.gravel import Gravel
sec=WallSection(1.2, 0.6, 8.53, 0.0, 8.53)
g=Gravel(friction_deg=72.8, interface_friction_deg=60, placement_friction_deg=45)
bw=BackfilledWall.build(sec, Masonry(friction_deg=25, block_length_m=0.33, block_height_m=0.12, first_course_fixed=False), g, FillPlan(container_m=1.0, formwork_m=0.0), solver=BlockSolver(dt=5e-4, iterations=40), seed=1)
t0=time.process_time()
for _ in range(3): r=bw.stage()
print("grains", len(bw.bodies), "fill cpu", time.process_time()-t0, "H", r["backfill_height_m"])
sp=bw.wall.space
for it in (10,20,40,80):
    sp.iterations=it
    t=time.process_time()
    for _ in range(400): sp.step(5e-4)
    dt=time.process_time()-t
    print(it, "sweeps:", round(400/dt,1), "steps/CPU-s", round(400*len(bw.bodies)/dt), "body-steps/CPU-s", "arbiters", len(sp.arbiters) if hasattr(sp,'arbiters') else '')
t=time.process_time()
for _ in range(20): bw.kinetic_energy(); bw.wall.positions()
print("one reading's Python (KE + positions):", (time.process_time()-t)/20, "s")
