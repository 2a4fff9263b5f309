# SPDX-License-Identifier: Apache-2.0
"""Golden model of the per-axis STEP/DIR generator (``rtl/halfpoint_stepgen.v``).

Timing settings, in clock ticks, with the LinuxCNC / Mesa hostmot2 meanings:

* ``steplen``   STEP is active for exactly max(steplen, 1) clocks per step;
* ``stepspace`` STEP is inactive for at least max(stepspace, 1) clocks between
  steps;
* ``dirsetup``  DIR changes at least this many clocks before STEP goes active;
* ``dirhold``   DIR changes at least this many clocks after STEP went inactive.

A step request is taken only when the generator says it is ready for that
direction; the requester (the motion core) holds its interpolators back until
then, so no step is ever dropped or merged.  ``step_inv`` / ``dir_inv`` invert
the pins.

States: LOW (STEP inactive; ``low_t`` counts the clocks it has been inactive,
saturating), SETUP (DIR has changed, waiting ``dirsetup`` clocks), HIGH (STEP
active).  A request in LOW:
  same direction: ready when low_t >= stepspace; STEP goes active next clock.
  new direction:  ready when low_t >= max(stepspace, dirhold); DIR changes next
                  clock, STEP goes active dirsetup clocks after that.
The two comparisons are registered (computed at each edge for the new low_t
with the settings of that clock), so a settings change acts on readiness one
clock later; pins and counts use the settings of the clock itself.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

S_LOW, S_SETUP, S_HIGH = range(3)


@dataclass
class StepCfg:
    steplen: int = 1
    stepspace: int = 1
    dirsetup: int = 1
    dirhold: int = 1
    step_inv: int = 0
    dir_inv: int = 0


@dataclass
class StepInputs:
    req: int = 0
    req_dir: int = 0     # 1 = positive
    rst: int = 0


@dataclass
class StepOutputs:
    step_pin: int
    dir_pin: int
    ready_pos: int
    ready_neg: int
    busy: int


@dataclass
class StepLookahead:
    direction: int           # the logical direction, 1 = positive
    next_ready_same: int     # ready for it at the next clock, if not taken now
    next_ready_reverse: int  # ready for the other direction at the next clock, same


class StepGenModel:
    def __init__(self, tw: int = 16):
        self.tw = tw
        self.tmax = (1 << tw) - 1
        self.reset()

    def reset(self) -> None:
        self.state = S_LOW
        self.cnt = 0
        self.low_t = self.tmax
        self.dir = 0
        self.sp_ok = 1          # low_t >= stepspace, registered (low_t = max)
        self.dh_ok = 1          # low_t >= dirhold, registered

    def _ready(self, cfg: StepCfg, d: int) -> int:
        if self.state != S_LOW:
            return 0
        if d == self.dir:
            return self.sp_ok
        return int(self.sp_ok and self.dh_ok)

    def outputs(self, cfg: StepCfg) -> StepOutputs:
        return StepOutputs(
            step_pin=int(self.state == S_HIGH) ^ cfg.step_inv,
            dir_pin=self.dir ^ cfg.dir_inv,
            ready_pos=self._ready(cfg, 1),
            ready_neg=self._ready(cfg, 0),
            busy=int(self.state != S_LOW),
        )

    def lookahead(self, cfg: StepCfg) -> StepLookahead:
        """Readiness a clock ahead (the RTL's ``direction``, ``next_ready_same``,
        ``next_ready_reverse``): ready for the present direction and for a
        reversal at the next clock if no request is taken at this edge (after a
        take the generator is busy, so neither).  The motion core registers its
        pop's readiness from these."""
        idle = copy.copy(self)
        idle.clock(cfg, StepInputs())
        return StepLookahead(direction=self.dir,
                             next_ready_same=idle._ready(cfg, self.dir),
                             next_ready_reverse=idle._ready(cfg, 1 - self.dir))

    def clock(self, cfg: StepCfg, i: StepInputs) -> None:
        if i.rst:
            self.reset()
            return
        self._advance(cfg, i)
        self.sp_ok = int(self.low_t >= cfg.stepspace)
        self.dh_ok = int(self.low_t >= cfg.dirhold)

    def _advance(self, cfg: StepCfg, i: StepInputs) -> None:
        if i.req and not self._ready(cfg, i.req_dir):
            # the RTL would ignore it: a lost step; the requester must wait
            raise AssertionError("step request while not ready")
        steplen = max(cfg.steplen, 1)
        if self.state == S_LOW:
            if i.req:
                if i.req_dir != self.dir:
                    self.dir = i.req_dir
                    if cfg.dirsetup > 0:
                        self.state, self.cnt = S_SETUP, cfg.dirsetup
                        return
                self.state, self.cnt = S_HIGH, steplen
            else:
                self.low_t = min(self.low_t + 1, self.tmax)
        elif self.state == S_SETUP:
            if self.cnt <= 1:
                self.state, self.cnt = S_HIGH, steplen
            else:
                self.cnt -= 1
        else:  # S_HIGH
            if self.cnt <= 1:
                self.state, self.low_t = S_LOW, 1
            else:
                self.cnt -= 1
