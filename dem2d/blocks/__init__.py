"""Dry-stone walls of rigid polygon blocks on pymunk, loaded by water to failure.

Oetomo et al. (S-OET, docs/reference/drystone-walls.md 2.1) model Villemus's walls
as courses of 0.30 x 0.125 m blocks with staggered joints, bed joints dipping toward
the fill by alpha, head joints perpendicular to them, the first course fixed, and raise
hydrostatic water on the inner face by 1 % of h per increment until the wall's kinetic
energy stays above 1e-3 J/m for 10 readings. Here the blocks are rigid pymunk polygons
(impulse contact solver: no contact stiffness, so displacements before failure are
numerical, not physical).

Coordinates: x inward from the outer toe (the fill is at +x), y up, per metre of wall.
The section is ``analytic.drystone.WallSection``; its base is the bed plane through the
outer toe dipping inward at alpha (reference 5.3), water height ``h_w`` is measured from
the toe level.

* ``geometry``   the section cut into courses and blocks (``course_pieces``; no physics)
* ``model``      the pymunk space (``BlockWall``): blocks, foundation, pair friction, water load
* ``water``      the water load's arithmetic, compiled (``face_loads``), and its batch read/write
* ``mechanism``  sliding along a bed joint or toppling about a course's toe (``classify_mechanism``)
* ``loading``    water increments, settling, failure test, mechanism (``load_to_failure``)

The tilt calibration (a block on a block) and the gravel backfill placement are
protocols over these, in the studies that run them.

Pure engine: no files, no printing. Units SI; angles in degrees at the interface.
"""

from .geometry import bed_joint_level, course_pieces, section_polygon
from .loading import LoadingPlan, LoadingResult, load_to_failure, window_energy
from .mechanism import Mechanism, RigidFit, classify_mechanism, rigid_motion_fit
from .model import BLOCK_TYPE, FOUNDATION_TYPE, BlockSolver, BlockWall, Masonry, new_block_space, pair_friction

__all__ = ["BLOCK_TYPE", "FOUNDATION_TYPE", "BlockSolver", "BlockWall", "LoadingPlan", "LoadingResult", "Masonry",
           "Mechanism", "RigidFit", "bed_joint_level", "classify_mechanism", "course_pieces", "load_to_failure",
           "new_block_space", "pair_friction", "rigid_motion_fit", "section_polygon", "window_energy"]
