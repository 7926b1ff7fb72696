"""Pressure cells: the force the grains exert on every wall panel, from contact impulses.

An impulse solver has no contact forces, only impulses: the force a panel carries over
a step is the accumulated contact impulse of that step divided by dt (pymunk's
``Arbiter.total_impulse``, normal plus friction, on ``arbiter.bodies[0]``). Summing
these impulses over a window of steps and dividing by the window's duration gives the
*time-averaged* force over the window, which is what a pressure cell reads:

    F_panel = (1 / T) sum_steps J_panel,          T = n_steps dt     [N per m of wall]

A ``post_solve`` callback (one per panel collision type, so no look-up) adds the
impulse. It costs about 7 us per wall contact per step, so
the callbacks are only switched on while a window is open.
"""

from __future__ import annotations

import numpy as np
import pymunk

from .walls import PanelWall


class PanelProbe:
    """Accumulates the force on every panel of some walls over measurement windows.

    Forces are *on the panel, by the grains* (so a panel holding back grains at +normal
    sees a force along -normal); units N per metre of wall.
    """

    def __init__(self, space: pymunk.Space, walls: list[PanelWall]):
        self.space = space
        self.walls = list(walls)
        self.n = sum(len(w) for w in self.walls)
        self._jx = [0.0] * self.n
        self._jy = [0.0] * self.n
        self._contacts = [0] * self.n
        self.steps = 0
        self.time = 0.0
        self.active = False
        self._slices = {}
        k = 0
        for w in self.walls:
            self._slices[w.name] = slice(k, k + len(w))
            k += len(w)

    # ------------------------------------------------------------------ callbacks
    def _callback(self, i: int):
        jx, jy, nc = self._jx, self._jy, self._contacts

        def post_solve(arbiter: pymunk.Arbiter, space, data) -> None:
            # with on_collision(panel_type, None) the panel is bodies[0] and
            # total_impulse is the impulse applied to it (normal + friction)
            j = arbiter.total_impulse
            jx[i] += j.x
            jy[i] += j.y
            nc[i] += 1
        return post_solve

    def start(self) -> None:
        """Open a window: zero the sums and switch the callbacks on."""
        self.reset()
        if not self.active:
            k = 0
            for w in self.walls:
                for t in w.types:
                    self.space.on_collision(t, None, post_solve=self._callback(k))
                    k += 1
            self.active = True

    def stop(self) -> None:
        """Close the window and switch the callbacks off (the sums stay readable)."""
        if self.active:
            for w in self.walls:
                for t in w.types:
                    self.space.on_collision(t, None, post_solve=pymunk.empty_callback)
            self.active = False

    def reset(self) -> None:
        for i in range(self.n):
            self._jx[i] = 0.0
            self._jy[i] = 0.0
            self._contacts[i] = 0
        self.steps = 0
        self.time = 0.0

    def record_step(self, dt: float) -> None:
        """Count one step of length dt [s] into the open window (call after space.step)."""
        if self.active:
            self.steps += 1
            self.time += dt

    # ------------------------------------------------------------------ results
    def force(self, name: str | None = None) -> np.ndarray:
        """(p,2) time-averaged force on each panel over the window [N/m] (all walls
        in order, or one wall by name)."""
        if self.time <= 0.0:
            f = np.zeros((self.n, 2))
        else:
            f = np.column_stack([self._jx, self._jy]) / self.time
        return f if name is None else f[self._slices[name]]

    def contacts_per_step(self, name: str | None = None) -> np.ndarray:
        """(p,) mean number of grain contacts per panel per step over the window."""
        c = np.asarray(self._contacts, float) / max(self.steps, 1)
        return c if name is None else c[self._slices[name]]

    def wall(self, name: str) -> PanelWall:
        for w in self.walls:
            if w.name == name:
                return w
        raise KeyError(name)
