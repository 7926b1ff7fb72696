"""The hydrostatic load on the wetted faces, step by step.

``face_loads`` is the arithmetic (compiled: on a case-A wall the numpy version took
~230 us a step against pymunk's ~90 us for the step itself); ``BodyBatch`` reads the
blocks' positions and writes their forces through ``pymunk.batch`` in one call each
(attribute by attribute it was ~140 us a step for 15 wet blocks)."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pymunk.batch as pb
from numba import njit

from analytic.constants import GAMMA_WATER


@njit(cache=True)
def face_loads(pos, ang, a, b, n0, slot, water_height, normal, force_b, torque_b):
    """Hydrostatic pressure gamma_w (h_w - y) on every wetted face, integrated along the
    face and put at its centre of pressure, summed per block.

    pos (q,2) [m], ang (q,) [rad]: the wet blocks; a, b (m,2): each face's end points in
    its block's frame [m]; n0 (m,2): the face's normal as built; slot (m,): each face's
    block among the q; water_height h_w [m]; normal: push along the face's normal as it
    is now (True) or as built (False), into the block.
    Writes forces (q,2) [N/m] into ``force_b`` and torques about the block centroids
    (q,) [N m/m] into ``torque_b`` (given, so a step allocates nothing). Each
    face is clipped at the water line (pressure linear along it, zero at the surface);
    a trapezoid's centre of pressure lies (p_a + 2 p_b) / (3 (p_a + p_b)) of the way
    from a to b. The operations are numpy's of the earlier version, in its order, so
    the bits are the same."""
    force_b[:] = 0.0
    torque_b[:] = 0.0
    for k in range(slot.shape[0]):
        q = slot[k]
        c = math.cos(ang[q])
        s = math.sin(ang[q])
        ax = pos[q, 0] + (c * a[k, 0] - s * a[k, 1])
        ay = pos[q, 1] + (s * a[k, 0] + c * a[k, 1])
        bx = pos[q, 0] + (c * b[k, 0] - s * b[k, 1])
        by = pos[q, 1] + (s * b[k, 0] + c * b[k, 1])
        dx = bx - ax
        dy = by - ay
        if normal:
            length = np.hypot(dx, dy)
            nx = -dy / length
            ny = dx / length
        else:     # as numpy's rot(n0) * 0 + n0: the same signed zeros
            nx = (c * n0[k, 0] - s * n0[k, 1]) * 0.0 + n0[k, 0]
            ny = (s * n0[k, 0] + c * n0[k, 1]) * 0.0 + n0[k, 1]
        pa = GAMMA_WATER * (water_height - ay)
        pb = GAMMA_WATER * (water_height - by)
        t = 0.0
        if (pa < 0) != (pb < 0):
            t = pa / (pa - pb if pa != pb else 1.0)
        if pa < 0 and pb > 0:
            ax = ax + t * dx
            ay = ay + t * dy
        if pb < 0 and pa > 0:
            bx = ax + t * dx
            by = ay + t * dy
        pa = max(pa, 0.0)
        pb = max(pb, 0.0)
        dx = bx - ax
        dy = by - ay
        force = np.hypot(dx, dy) * (pa + pb) / 2
        s_cp = (pa + 2 * pb) / (3 * (pa + pb)) if force > 0 else 0.0
        fx = force * nx
        fy = force * ny
        rx = ax + s_cp * dx - pos[q, 0]
        ry = ay + s_cp * dy - pos[q, 1]
        force_b[q, 0] += fx
        force_b[q, 1] += fy
        torque_b[q] += rx * fy - ry * fx


_READ = pb.BodyFields.BODY_ID | pb.BodyFields.POSITION | pb.BodyFields.ANGLE
_WRITE = pb.BodyFields.FORCE | pb.BodyFields.TORQUE


class BodyBatch:
    """Positions and angles of some bodies read, and forces and torques written, in one
    ``pymunk.batch`` call each. pymunk's rows (every body of the space, in its own order,
    which changes when bodies are added) are matched to ``bodies`` by id at each read."""

    def __init__(self, space: pymunk.Space, bodies: list):
        self.space = space
        self._want = np.array([bd.id for bd in bodies], dtype=np.uintp)
        self._read = pb.Buffer()
        self._write = pb.Buffer()
        self._ids = None
        self._rows = None
        self._out = None

    def read(self) -> tuple[np.ndarray, np.ndarray]:
        """(positions (q,2) [m], angles (q,) [rad]) of the bodies, in their order."""
        self._read.clear()
        pb.get_space_bodies(self.space, _READ, self._read)
        ids = np.frombuffer(self._read.int_buf(), dtype=np.uintp)
        if self._ids is None or not np.array_equal(ids, self._ids):
            self._match(ids)
        f = np.frombuffer(self._read.float_buf(), dtype=np.float64).reshape(-1, 3)[self._rows]
        return f[:, :2], f[:, 2]

    def write(self, force: np.ndarray, torque: np.ndarray) -> None:
        """Set the bodies' force (q,2) [N/m] and torque (q,) [N m/m]; every other body of
        the space gets zero, which pymunk has left there after its last step."""
        self._out[:] = 0.0
        self._out[self._rows, :2] = force
        self._out[self._rows, 2] = torque
        pb.set_space_bodies(self.space, _WRITE, self._write)

    def _match(self, ids: np.ndarray) -> None:
        row = {int(i): r for r, i in enumerate(ids)}
        self._ids = ids.copy()
        self._rows = np.array([row[int(i)] for i in self._want], dtype=np.int64)
        self._out = np.zeros((len(ids), 3))
        self._write.set_float_buf(self._out)
