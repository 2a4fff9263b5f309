# SPDX-License-Identifier: Apache-2.0
"""Independent STEP/DIR timing checker (pure Python).

Fed with the pin levels of one axis once per clock, it checks the hostmot2
timing rules directly, without reference to any model, and counts the steps
(position) the pins describe:

* STEP active for exactly max(steplen, 1) clocks;
* STEP inactive for at least stepspace clocks between steps;
* DIR never changes while STEP stays active (it may change on the clock
  STEP rises when dirsetup is 0, or falls when dirhold is 0);
* DIR changes at least dirhold clocks after STEP went inactive;
* STEP goes active at least dirsetup clocks after DIR changed.
"""

from __future__ import annotations

from ..spec.stepgen import StepCfg


class TimingViolation(AssertionError):
    pass


class StepDirChecker:
    def __init__(self, cfg: StepCfg, name: str = "axis"):
        self.cfg = cfg
        self.name = name
        self.cycle = 0
        self.position = 0
        self.steps = 0
        self.prev_step = 0
        self.prev_dir = None
        self.rise = None       # cycle of the latest STEP rise
        self.fall = None       # cycle of the latest STEP fall
        self.dir_change = None  # cycle of the latest DIR change

    def _fail(self, what: str) -> None:
        raise TimingViolation(f"{self.name}, cycle {self.cycle}: {what}")

    def sample(self, step_pin: int, dir_pin: int) -> None:
        c = self.cfg
        step = step_pin ^ c.step_inv
        d = dir_pin ^ c.dir_inv
        n = self.cycle
        if not step and self.prev_step:
            width = n - self.rise
            if width != max(c.steplen, 1):
                self._fail(f"steplen: STEP active {width} clocks, need {max(c.steplen, 1)}")
            self.fall = n
        if self.prev_dir is not None and d != self.prev_dir:
            if self.prev_step and step:
                self._fail("DIR changed while STEP was active")
            if self.fall is not None and n - self.fall < c.dirhold:
                self._fail(f"dirhold: DIR changed {n - self.fall} clocks after STEP fell, need {c.dirhold}")
            self.dir_change = n
        if step and not self.prev_step:
            if self.fall is not None and n - self.fall < c.stepspace:
                self._fail(f"stepspace: STEP inactive {n - self.fall} clocks, need {c.stepspace}")
            if self.dir_change is not None and n - self.dir_change < c.dirsetup:
                self._fail(f"dirsetup: STEP {n - self.dir_change} clocks after DIR changed, need {c.dirsetup}")
            self.rise = n
            self.steps += 1
            self.position += 1 if d else -1
        self.prev_step, self.prev_dir = step, d
        self.cycle += 1

    @property
    def idle(self) -> bool:
        return not self.prev_step
