"""dem3d: a numba soft-sphere / clump DEM engine with moving segmented walls.

Pure computation: nothing in this package writes files, prints or logs (workflows/ and
cli.py do). Typical use::

    from dem3d import (Simulation, Periodic, Wall, linear, box, segmented_wall, rotation,
                       random_specimen, settle, run)
    spec = random_specimen(np.random.default_rng(1), lo, hi, 2000, 0.046, 0.0736,
                           clump_fraction=0.3)
    sim = Simulation(spec, linear(8.3e6, 3.32e6, 0.65, zeta_n=0.3), dt=2e-5,
                     walls=[Wall("box", box(lo, hi_box, periodic_axis=1)),
                            Wall("wall", segmented_wall(...), rotation(pivot, axis, 1e-3))],
                     periodic=Periodic(1, 0.0, 0.5))
    settle(sim, ratio=1e-3)
    for frame in run(sim, 10_000, every=500):
        frame.panel_force      # (p, 3) force BY the particles ON each panel [N]

Modules: params (laws, time step), state (SoA records), clumps (mass properties),
walls (panels, motions), kernels (all numba code), engine (Simulation), run (Frame,
run), prep (generation, settling), measure (porosity, stresses, energies, chains).
"""

from .engine import Periodic, Simulation
from .errors import BlowUp
from .params import (ABSOLUTE, DT_SAFETY, HERTZ_MINDLIN, LINEAR, RATIO, ContactParams, check_time_step,
                     critical_time_step, hertz_mindlin, linear, restitution_to_damping_ratio,
                     with_local_damping)
from .prep import SettleResult, random_specimen, settle
from .run import Frame, contacts, frame, run
from .state import Specimen
from .walls import FIXED, Motion, Panel, Ramp, Wall, box, plane, rectangle, rotation, segmented_wall, translation

__all__ = [
    "Simulation", "Periodic", "BlowUp", "Specimen", "Frame", "frame", "run", "contacts",
    "ContactParams", "linear", "hertz_mindlin", "with_local_damping", "restitution_to_damping_ratio",
    "critical_time_step", "check_time_step", "DT_SAFETY", "LINEAR", "HERTZ_MINDLIN", "RATIO", "ABSOLUTE",
    "Wall", "Panel", "Motion", "FIXED", "Ramp", "plane", "rectangle", "box", "segmented_wall",
    "translation", "rotation", "random_specimen", "settle", "SettleResult",
]
