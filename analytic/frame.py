"""``Frame``: the one snapshot record both engines return (dem2d.make_frame,
dem3d.frame) and the recorder and figures read. It sits here, beside ``Profile``, because
it is a plain record that every layer may import; nothing in it computes.

SI units. In 2D (d = 2) forces are per metre of wall and a panel's "area" is its length;
in 3D (d = 3) panels are quadrilaterals."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Frame(NamedTuple):
    """One snapshot of a run.

    step:           steps taken
    time:           simulated time [s]
    positions:      (n, d) circle / sphere centres [m] (a clump has one row per member)
    radii:          (n,) [m]
    velocities:     (n, d) velocity of the owning body [m/s] (3D: at time - dt/2)
    body_id:        (n,) the owning body of each row (2D: creation index; 3D: the first
                    member's index for a clump member, the sphere's own otherwise)
    contact_a/b:    (m, d) centres of the two bodies of each grain-grain contact [m]
                    (3D: b periodic-unwrapped, so b - a is the short separation)
    contact_force:  (m,) normal force of each contact, compression positive [N; N/m in 2D]
    panel_corners:  (p, 2, 2) panel endpoints in 2D, (p, 4, 3) corners in 3D [m]
    panel_normal:   (p, d) unit normals from the wall into the grains
    panel_force:    (p, d) force BY the grains ON each panel [N; N/m in 2D]; pressing
                    grains give panel_force . panel_normal < 0
    panel_area:     (p,) [m^2; m in 2D]
    block_outlines: 2D only: list of (k, 2) polygons of polygon grains/blocks, or None
    panel_moment:   3D only: (p, 3) moment of panel_force about the panel centre [N m],
                    or None
    particle_force: (n, d) contact force on each row's sphere (3D) or body (2D) from the
                    last step, walls included [N; N/m in 2D], or None
    material:       (n,) material id of each row (3D: row of the engine's material
                    table), or None (one material)
    contact_shear:  (m,) magnitude of the tangential force of each contact [N; N/m], or None
    bond_a/b:       3D only: (k, 3) centres of the two spheres of each intact parallel
                    bond [m] (b periodic-unwrapped), or None (a run without bonds)
    bond_force:     (k,) normal force of each intact bond, compression positive [N]
    bond_shear:     (k,) magnitude of its shear force [N]
    """

    step: int
    time: float
    positions: np.ndarray
    radii: np.ndarray
    velocities: np.ndarray
    body_id: np.ndarray
    contact_a: np.ndarray
    contact_b: np.ndarray
    contact_force: np.ndarray
    panel_corners: np.ndarray
    panel_normal: np.ndarray
    panel_force: np.ndarray
    panel_area: np.ndarray
    block_outlines: list | None = None
    panel_moment: np.ndarray | None = None
    particle_force: np.ndarray | None = None
    material: np.ndarray | None = None
    contact_shear: np.ndarray | None = None
    bond_a: np.ndarray | None = None
    bond_b: np.ndarray | None = None
    bond_force: np.ndarray | None = None
    bond_shear: np.ndarray | None = None


def panel_normal_stress(frame) -> np.ndarray:
    """(p,) normal stress of the grains on each panel [Pa], compression positive: the
    grains push a panel along -normal, so sigma = -(F . n) / A (2D: F per metre over the
    panel length). The one definition for the recorder, the engines and the studies."""
    return -np.einsum("pd,pd->p", frame.panel_force, frame.panel_normal) / frame.panel_area
