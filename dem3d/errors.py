"""The engine's own error: a simulation that stopped being physical."""

from __future__ import annotations


class BlowUp(RuntimeError):
    """The state became non-finite or a sphere moved more than half the smallest radius
    in one step (kinetic energy growing without bound). ``str(err)`` is one line naming
    the step, the time, what was seen and the usual cure."""

    def __init__(self, step: int, time: float, what: str):
        self.step = step
        self.time = time
        self.what = what
        super().__init__(f"simulation blew up at step {step} (t = {time:.6g} s): {what}; "
                         "reduce dt or check stiffness, damping and initial overlaps")
