"""dem2d: 2D discrete elements on pymunk (rigid grains, impulse contact solver).

Pure engine: no files, no printing, no rerun. Units SI; forces per metre of wall.

Layout (docs/dem2d.md has the why):

* ``grading``     Grading(d50, cu): grain sizes by mass, sampled by number
* ``params``      Solver (dt, iterations, slop, overlap time, broad phase, threads), Material
* ``build``       new_space, friction_split (pymunk multiplies frictions), Grains,
                  add_disks / add_clumps / add_polygons
* ``walls``       PanelWall = N kinematic panels (pressure cells); drivers Fixed,
                  Translate, RotateAbout, Schedule
* ``probes``      PanelProbe: time-averaged force on every panel from contact impulses
* ``frames``      Frame (the viz contract), body_state, grain_contacts (pymunk.batch)
* ``measure``     energies, unbalanced force, panel stresses, 4-panel readings, fabric
* ``sim``         Sim (space + grains + walls + clock), snapshot / restore
* ``pluviation``  layered pluviation
* ``blocks``      dry-stone walls of rigid polygon blocks (courses, staggered joints,
                  counter-slope), pair friction, hydrostatic water, loading to failure,
                  sliding / toppling classifier
* ``gravel``      elongated capsule grains (dry-stone case B backfill), placement at a
                  lowered friction, porosity, box reactions

The element tests (biaxial, interface shear) run on this engine from
``studies/elements/``; the dry-stone and tilt protocols from their studies.
"""

from .blocks import BlockSolver, BlockWall, LoadingPlan, LoadingResult, Masonry, Mechanism, load_to_failure
from .build import Grains, add_clumps, add_disks, add_polygons, friction_split, new_space
from .frames import Frame, body_state, grain_contacts, make_frame
from .grading import Grading
from .params import Material, Solver
from .pluviation import Pluviation, pluviate
from .probes import PanelProbe
from .sim import Sim, restore
from .walls import Fixed, PanelWall, RotateAbout, Schedule, Translate, panel_wall

__all__ = ["BlockSolver", "BlockWall", "LoadingPlan",
           "LoadingResult", "Masonry", "Mechanism", "load_to_failure", "Grains", "add_clumps", "add_disks",
           "add_polygons", "friction_split", "new_space", "Frame", "body_state", "grain_contacts",
           "make_frame", "Grading", "Material", "Solver", "Pluviation", "pluviate", "PanelProbe",
           "Sim", "restore", "Fixed", "PanelWall", "RotateAbout",
           "Schedule", "Translate", "panel_wall"]
