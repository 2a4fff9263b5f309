# SPDX-License-Identifier: Apache-2.0
"""cocotb bench for ``halfpoint_line`` (see :mod:`halfpoint.sim.unitbench`).

A command is a tuple of per-axis deltas; each recorded move is the tuple of
signed per-axis steps it made, read from step[] and dir[].
"""

from __future__ import annotations

from .unitbench import UnitBench
from ..spec.line import LineInputs, LineUnitModel


class LineBench(UnitBench):
    FIELDS = ("s_ready", "busy", "move", "step", "dir", "done", "reject", "err_code")

    def __init__(self, dut, axes: int, width: int, seed: int = 1, check: bool = True):
        super().__init__(dut, LineUnitModel(axes, width), seed, check)
        self.axes, self.width = axes, width
        self.mask = (1 << width) - 1

    def _pack(self, deltas) -> int:
        word = 0
        for k, d in enumerate(deltas):
            word |= (d & self.mask) << (k * self.width)
        return word

    def command_inputs(self, cmd):
        return LineInputs(s_valid=1, s_delta=tuple(cmd))

    def idle_inputs(self, **kw):
        half = 1 << (self.width - 1)
        junk = tuple(self.rng.randrange(-half, half) for _ in range(self.axes))
        return LineInputs(s_valid=0, s_delta=junk, **kw)

    def drive(self, i: LineInputs) -> None:
        self.drive_control(i)
        d = self.dut
        d.s_delta.value = self._pack(i.s_delta)

    def move_record(self, got):
        return tuple(
            ((1 if (got["dir"] >> k) & 1 else -1) if (got["step"] >> k) & 1 else 0)
            for k in range(self.axes)
        )
