# SPDX-License-Identifier: Apache-2.0
"""cocotb bench for ``halfpoint_arc`` (see :mod:`halfpoint.sim.unitbench`).

Used by the cocotb tests in ``tb/halfpoint_arc/`` and by the ``rtl`` engine
of the command line.  A command is (cw, xs, ys, xe, ye); each recorded move is
the point (x, y) it reached.
"""

from __future__ import annotations

from ..spec.arc import ArcInputs, ArcUnitModel
from .unitbench import UnitBench


class ArcBench(UnitBench):
    FIELDS = (
        "s_ready", "busy", "move", "step_x", "step_y", "dir_x", "dir_y",
        "x", "y", "f", "done", "reject", "err_code",
    )
    SIGNED = frozenset({"x", "y", "f"})

    def __init__(self, dut, width: int, seed: int = 1, check: bool = True):
        super().__init__(dut, ArcUnitModel(width), seed, check)
        self.width = width
        self.mask = (1 << width) - 1

    def command_inputs(self, cmd):
        cw, xs, ys, xe, ye = cmd
        return ArcInputs(s_valid=1, s_cw=cw, s_xs=xs, s_ys=ys, s_xe=xe, s_ye=ye)

    def idle_inputs(self, **kw):
        r = self.rng
        half = 1 << (self.width - 1)
        return ArcInputs(
            s_valid=0, s_cw=r.randint(0, 1),
            s_xs=r.randrange(-half, half), s_ys=r.randrange(-half, half),
            s_xe=r.randrange(-half, half), s_ye=r.randrange(-half, half), **kw,
        )

    def drive(self, i: ArcInputs) -> None:
        self.drive_control(i)
        d = self.dut
        d.s_cw.value = i.s_cw
        for name in ("s_xs", "s_ys", "s_xe", "s_ye"):
            getattr(d, name).value = getattr(i, name) & self.mask

    def move_record(self, got):
        return (got["x"], got["y"])

    @staticmethod
    def points(result) -> list[tuple[int, int]]:
        """Lattice points of an arc result: its start, then every move."""
        cw, xs, ys, xe, ye = result.cmd
        return [(xs, ys)] + list(result.moves)
