"""Bulk read-out of a space into numpy arrays, and the ``Frame`` record the viz draws.

This module and ``blocks.water`` are the two that use ``pymunk.batch`` (marked "highly
experimental" by pymunk, so it is wrapped in these two places). Rows come back in pymunk's internal order (which
includes kinematic and static bodies and changes when bodies are added); they are
mapped to creation order through the body ids (``Grains.id_map``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pymunk
import pymunk.batch as pb

from analytic.frame import Frame

from .build import Grains


# the snapshot record both engines return: analytic/frame.py


class BodyState(NamedTuple):
    """Dynamic-body arrays in creation order: position (n,2) [m], angle (n,) [rad],
    velocity (n,2) [m/s], angular velocity (n,) [rad/s]."""

    position: np.ndarray
    angle: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray


_BODY_FIELDS = (pb.BodyFields.BODY_ID | pb.BodyFields.POSITION | pb.BodyFields.ANGLE
                | pb.BodyFields.VELOCITY | pb.BodyFields.ANGULAR_VELOCITY)


def body_state(space: pymunk.Space, grains: Grains) -> BodyState:
    """Positions, angles, velocities and spins of every grain (creation order)."""
    buf = pb.Buffer()
    pb.get_space_bodies(space, _BODY_FIELDS, buf)
    ids = np.frombuffer(buf.int_buf(), dtype=np.uintp)
    f = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 6)
    ids_sorted, rows = grains.id_map()
    pos_in_sorted = np.searchsorted(ids_sorted, ids)
    pos_in_sorted = np.minimum(pos_in_sorted, len(ids_sorted) - 1)
    mine = ids_sorted[pos_in_sorted] == ids
    idx = rows[pos_in_sorted[mine]]
    n = len(grains)
    out = np.empty((n, 6))
    out[idx] = f[mine]
    return BodyState(out[:, 0:2], out[:, 2], out[:, 3:5], out[:, 5])


def circle_positions(state: BodyState, grains: Grains) -> np.ndarray:
    """(c,2) world centres of every circle shape [m]."""
    b = grains.circle_body
    off = grains.circle_offset
    if not np.any(off):
        return state.position[b].copy()
    c, s = np.cos(state.angle[b]), np.sin(state.angle[b])
    return state.position[b] + np.column_stack([c * off[:, 0] - s * off[:, 1], s * off[:, 0] + c * off[:, 1]])


class Contacts(NamedTuple):
    """Touching grain-grain pairs after the last step: body indices a, b (m,), the
    normal (m,2) from a to b, the impulse on a over the step (m,2) [N s/m] and the
    contact point (m,2) [m]."""

    a: np.ndarray
    b: np.ndarray
    normal: np.ndarray
    impulse: np.ndarray
    point: np.ndarray


_ARB_FIELDS = (pb.ArbiterFields.BODY_A_ID | pb.ArbiterFields.BODY_B_ID | pb.ArbiterFields.CONTACT_COUNT
               | pb.ArbiterFields.TOTAL_IMPULSE | pb.ArbiterFields.NORMAL | pb.ArbiterFields.POINT_A_1)


def raw_arbiters(space: pymunk.Space) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Every cached arbiter: body-a ids, body-b ids, contact counts (0 = separated) and
    the impulse on body a over the last step (m,2) [N s/m]."""
    AF = pb.ArbiterFields
    buf = pb.Buffer()
    pb.get_space_arbiters(space, AF.BODY_A_ID | AF.BODY_B_ID | AF.CONTACT_COUNT | AF.TOTAL_IMPULSE, buf)
    ii = np.frombuffer(buf.int_buf(), dtype=np.uintp).reshape(-1, 3)
    ff = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 2)
    return ii[:, 0].copy(), ii[:, 1].copy(), ii[:, 2].copy(), ff.copy()


def grain_contacts(space: pymunk.Space, grains: Grains) -> Contacts:
    """Every touching grain-grain contact (pairs with a wall are left out)."""
    buf = pb.Buffer()
    pb.get_space_arbiters(space, _ARB_FIELDS, buf)
    ii = np.frombuffer(buf.int_buf(), dtype=np.uintp).reshape(-1, 3)
    ff = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 6)
    ids_sorted, rows = grains.id_map()
    live = ii[:, 2] > 0
    ii, ff = ii[live], ff[live]

    def lookup(ids):
        k = np.minimum(np.searchsorted(ids_sorted, ids), len(ids_sorted) - 1)
        ok = ids_sorted[k] == ids
        return np.where(ok, rows[k], -1)

    a, b = lookup(ii[:, 0]), lookup(ii[:, 1])
    both = (a >= 0) & (b >= 0)
    return Contacts(a[both], b[both], ff[both, 2:4], ff[both, 0:2], ff[both, 4:6])


def contact_force_on_bodies(space: pymunk.Space, grains: Grains, dt: float) -> np.ndarray:
    """(n,2) sum of the contact forces on each grain over the last step, walls and blocks
    included (impulse / dt) [N/m], in creation order."""
    a, b, count, impulse = raw_arbiters(space)
    ids_sorted, rows = grains.id_map()
    out = np.zeros((len(grains), 2))
    live = count > 0
    for ids, sign in ((a, 1.0), (b, -1.0)):
        k = np.minimum(np.searchsorted(ids_sorted, ids), len(ids_sorted) - 1)
        mine = live & (ids_sorted[k] == ids)
        np.add.at(out, rows[k[mine]], sign * impulse[mine])
    return out / dt


def make_frame(space: pymunk.Space, grains: Grains, step: int, time: float, dt: float,
               walls: list, panel_force: np.ndarray | None = None,
               with_contacts: bool = True) -> Frame:
    """Assemble a ``Frame``. ``walls``: PanelWalls drawn and measured, in the order of
    ``panel_force`` ((p,2) N/m, e.g. ``PanelProbe.force()``; zeros if None)."""
    st = body_state(space, grains)
    pos = circle_positions(st, grains)
    vel = st.velocity[grains.circle_body]
    body_force = None
    if with_contacts and len(grains):
        c = grain_contacts(space, grains)
        along = np.einsum("md,md->m", c.impulse, c.normal)
        fn = np.abs(along) / dt
        ft = np.linalg.norm(c.impulse - along[:, None] * c.normal, axis=1) / dt
        ca, cb = st.position[c.a], st.position[c.b]
        body_force = contact_force_on_bodies(space, grains, dt)
    else:
        ca = cb = np.zeros((0, 2))
        fn = ft = np.zeros(0)
    corners = np.concatenate([w.corners() for w in walls]) if walls else np.zeros((0, 2, 2))
    normals = np.concatenate([w.normals() for w in walls]) if walls else np.zeros((0, 2))
    areas = np.concatenate([w.lengths() for w in walls]) if walls else np.zeros(0)
    if panel_force is None:
        panel_force = np.zeros((len(areas), 2))
    outlines = None
    if grains.polys:
        outlines = []
        for k, verts in grains.polys:
            ang = st.angle[k]
            R = np.array([[np.cos(ang), -np.sin(ang)], [np.sin(ang), np.cos(ang)]])
            outlines.append(verts @ R.T + st.position[k])
    return Frame(int(step), float(time), pos, grains.circle_radius.copy(), vel,
                 grains.circle_body.copy(), ca, cb, fn, corners, normals,
                 np.asarray(panel_force, float), areas, outlines, contact_shear=ft,
                 particle_force=body_force[grains.circle_body] if body_force is not None else None)
