"""dem3d: a numba soft-sphere / clump DEM engine with moving segmented walls.

Pure computation: nothing in this package writes files, prints or logs (workflows/ and
cli.py do). Typical use (a 0.5 m periodic slab, a 6-panel wall at x = 0 that turns about
its base, the backfill on +x)::

    import numpy as np
    from dem3d import (Periodic, Simulation, Wall, box, frame, linear, random_specimen,
                       rotation, run, segmented_wall, settle, with_local_damping)

    lo, hi = (0.0, 0.0, 0.0), (3.3, 0.5, 6.0)
    spec = random_specimen(np.random.default_rng(1), lo, hi, 20_000, 0.046, 0.0736,
                           clump_fraction=0.3, clump_overlap=1.0)
    law = linear(8.3e6, 3.32e6, 0.65, zeta_n=0.3, zeta_s=0.3)
    wall = segmented_wall((0.0, 0.25, 0.0), normal=(1, 0, 0), up=(0, 0, 1), width=0.5,
                          height=3.1, n_segments=6, mu=0.35, unbounded_width=True)
    sim = Simulation(spec, law, dt=2e-5, periodic=Periodic(1, 0.0, 0.5),
                     walls=[Wall("box", box(lo, (3.3, 0.5, 8.0), periodic_axis=1, omit=("x-",))),
                            Wall("wall", wall)])
    settle(sim, ratio=1e-3)                       # rain and settle under gravity
    np.savez("rest.npz", **sim.to_arrays())       # (a workflow does the I/O)
    moving = [sim.walls.walls[0],
              Wall("wall", wall, rotation((0, 0.25, 0), (0, 1, 0), -1e-3))]   # away from the fill
    sim = Simulation.from_arrays(dict(np.load("rest.npz")), walls=moving)
    for f in run(sim, 20_000, every=1000):
        f.panel_force, f.panel_moment            # (6 + box panels, 3) [N], [N m]

Modules: params (laws, time step), state (SoA records), clumps (mass properties),
walls (panels, motions), kernels (all numba code), engine (Simulation), run (Frame,
run), prep (generation, settling), measure (porosity, stresses, energies, chains).
"""

from .engine import Periodic, Simulation
from .errors import BlowUp
from .params import (ABSOLUTE, DT_SAFETY, HERTZ_MINDLIN, LINEAR, RATIO, ContactParams, check_time_step,
                     critical_time_step, hertz_mindlin, linear, material_table, mix, pair_params,
                     restitution_to_damping_ratio, with_local_damping)
from .prep import SettleResult, random_specimen, settle
from .run import Frame, contacts, frame, run
from .state import Bonds, Specimen
from .walls import (FIXED, AccelerationTable, Motion, Panel, Ramp, Wall, box, history, plane, rectangle, rotation,
                    segmented_wall, shaking, sine_envelope, sine_ramp, translation)

__all__ = [
    "Simulation", "Periodic", "BlowUp", "Specimen", "Frame", "frame", "run", "contacts",
    "ContactParams", "linear", "hertz_mindlin", "with_local_damping", "restitution_to_damping_ratio",
    "critical_time_step", "check_time_step", "DT_SAFETY", "LINEAR", "HERTZ_MINDLIN", "RATIO", "ABSOLUTE",
    "Wall", "Panel", "Motion", "FIXED", "Ramp", "plane", "rectangle", "box", "segmented_wall",
    "translation", "rotation", "random_specimen", "settle", "SettleResult",
    "mix", "material_table", "pair_params", "Bonds", "AccelerationTable", "history", "shaking", "sine_envelope",
    "sine_ramp",
]
