"""dem3d: a numba soft-sphere / clump DEM engine with moving segmented walls.

Pure computation: nothing in this package writes files, prints or logs (studies/ and
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

Modules: params (laws, time step, materials per pair), state (SoA records), clumps
(mass properties), walls (panels, motions, displacement/acceleration histories for base
shaking), kernels (all numba code), engine (Simulation: external forces, parallel bonds,
spheres attached to walls), run (Frame, run), prep (generation, settling), measure
(porosity, stresses, energies, chains, slice averages, section forces of bonded
structures, strain fields, settlement), cantilever (bond calibration of a bonded strip
and its Euler-Bernoulli check), freefield (absorbing free-field lateral boundaries).

Dynamics (materials, bonds, shaking, free field), e.g. a bonded sheet and a shaken base::

    from dem3d import sine_ramp, shaking
    from dem3d.cantilever import calibrate_strip
    sim = Simulation(spec, soil, dt=dt, materials=[soil, wall_law], sphere_material=ids,
                     walls=[Wall("base", plane((0, 0, 0), (0, 0, 1), mu=0.6),
                                 shaking(sine_ramp(0.1 * 50 * 9.81, 250.0, 0.06, 0.08, 0.02)))])
    bonds = calibrate_strip(40e9, 5e-3)
    sim.make_bonds(1e-5, kn=bonds.kn, ks=bonds.ks, spheres=wall_ids)
    sim.attach_to_wall(base_layer_ids, "base")          # a rough base moving with it
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
