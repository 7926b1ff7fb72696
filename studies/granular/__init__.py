"""Granular blocks shared by the studies of a wall and its backfill (3D, dem3d).

* ``cloud``     the loose cloud every rained specimen starts from (the heap's and the
                seismic deposit's too)
* ``recipe``    the sphere-and-clump backfill (``SpecimenRecipe``: grains, contacts,
                raining; Nadukuru & Michalowski's mixture by default), its contact law
                and time step
* ``wall``      the segmented wall, its box and its movement (``WallSetup``,
                ``Movement``), the grain scale, a case's checks and run length
* ``specimen``  the backfill rained behind the wall and settled, kept by content key
* ``movement``  the wall moved away from the fill, with its load history
* ``load``      the wall load of a frame, K by Nadukuru & Michalowski's eq. 6

The Nadukuru study runs its paper's case on them; a study of another wall uses the same
pipeline with its own case (anything with ``specimen``, ``wall``, ``movement``, ``seed``).
"""

from .recipe import CLUMP_VOLUME_FACTOR, MOST_PARTICLE_STEPS, SpecimenRecipe, contact_law, frictional_law, time_step

__all__ = ["CLUMP_VOLUME_FACTOR", "MOST_PARTICLE_STEPS", "SpecimenRecipe", "contact_law", "frictional_law",
           "time_step"]
