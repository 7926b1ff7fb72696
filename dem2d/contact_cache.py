"""The accumulated contact impulses of a pymunk space, saved and given back to a rebuilt one.

Chipmunk warm-starts its solver: every step begins with the impulses each contact point
carried at the end of the last step (matched by the point's feature hash), and a settled
pile stays settled only because of them. A space rebuilt from its bodies and shapes has
no such cache, so the pile would sink and shake for tens of steps. ``touching_contacts``
reads, for every pair of shapes that touched in the last step, each point's hash and its
normal and tangential impulse (jnAcc, jtAcc); ``warm_start`` arms the rebuilt space so
that in its first step every pair found again gets them back on the points with the
same hash, and counts as a continuing contact (Chipmunk then applies them as it would
have). Both points of a two-point contact (polygon pairs) are restored, which the
one-point warm start of ``sim.restore`` does not do.

This reads and writes private fields of the cffi structs (``cpArbiter.a/b/count/stamp/
state``, ``cpContact.hash/jnAcc/jtAcc``), checked on pymunk 7.3.1. The scalars jnAcc and
jtAcc, and the hash, do not change when a rebuilt space orders a pair's shapes the other
way round.
"""

from __future__ import annotations

import numpy as np
import pymunk
from pymunk._chipmunk_cffi import ffi, lib

#: at most this many points a pymunk contact has
MAX_POINTS = 2
_HOOK = "wallsim-contact-cache"


def _address(cdata) -> int:
    return int(ffi.cast("uintptr_t", cdata))


def _shape_index(shapes: list) -> dict[int, int]:
    return {_address(s._shape): k for k, s in enumerate(shapes)}


def touching_contacts(space: pymunk.Space, shapes: list) -> dict:
    """Every pair of ``shapes`` that touched in the space's last step: shape indices a, b
    (m,) (into ``shapes``), points (m,), and per point (m, MAX_POINTS) its hash, jn and jt
    (accumulated normal and tangential impulse [N s/m]; zero where a pair has one point)."""
    index = _shape_index(shapes)
    stamp = lib.cpSpaceGetTimestamp(space._space)
    rows = []
    for arb in space._get_arbiters():
        if arb.count == 0 or arb.stamp != stamp:
            continue                      # cached from an earlier step, not touching now
        a, b = index.get(_address(arb.a)), index.get(_address(arb.b))
        if a is None or b is None:
            continue
        pts = [(int(arb.contacts[i].hash), float(arb.contacts[i].jnAcc), float(arb.contacts[i].jtAcc))
               for i in range(arb.count)]
        rows.append((a, b, pts))
    m = len(rows)
    out = {"a": np.zeros(m, np.int64), "b": np.zeros(m, np.int64), "points": np.zeros(m, np.int64),
           "hash": np.zeros((m, MAX_POINTS), np.uint64), "jn": np.zeros((m, MAX_POINTS)),
           "jt": np.zeros((m, MAX_POINTS))}
    for r, (a, b, pts) in enumerate(rows):
        out["a"][r], out["b"][r], out["points"][r] = a, b, len(pts)
        for i, (h, jn, jt) in enumerate(pts):
            out["hash"][r, i], out["jn"][r, i], out["jt"][r, i] = h, jn, jt
    return out


def warm_start(space: pymunk.Space, shapes: list, saved: dict, dt: float) -> None:
    """Arm ``space`` (rebuilt with ``shapes`` in the order ``saved`` indexes) so that its
    next step gives every saved pair its saved impulses (module docstring); ``dt``: the
    time step the impulses were accumulated over (Chipmunk scales cached impulses by
    dt / previous dt)."""
    if not len(saved["a"]):
        return
    index = _shape_index(shapes)
    pairs = {}
    for r, (a, b) in enumerate(zip(saved["a"].tolist(), saved["b"].tolist())):
        pairs[(a, b) if a < b else (b, a)] = r
    hashes, jn, jt, points = saved["hash"].tolist(), saved["jn"].tolist(), saved["jt"].tolist(), \
        saved["points"].tolist()
    continuing = lib.CP_ARBITER_STATE_NORMAL

    def pre_solve(arbiter: pymunk.Arbiter, space_, data) -> None:
        arb = arbiter._arbiter
        a, b = index.get(_address(arb.a)), index.get(_address(arb.b))
        if a is None or b is None:
            return
        r = pairs.get((a, b) if a < b else (b, a))
        if r is None:
            return
        for i in range(arb.count):
            con = arb.contacts[i]
            h = int(con.hash)
            for j in range(points[r]):
                if hashes[r][j] == h:
                    con.jnAcc, con.jtAcc = jn[r][j], jt[r][j]
        arb.state = continuing

    space.on_collision(None, None, pre_solve=pre_solve)
    lib.cpSpaceSetCurrentTimeStep(space._space, dt)

    def disarm(space_, key) -> None:
        space_.on_collision(None, None, pre_solve=pymunk.empty_callback)

    # post-step callbacks run at the end of step(): the handler acts in the first step only
    space.add_post_step_callback(disarm, _HOOK)
